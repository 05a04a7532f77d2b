"""What the measured-data loop found: the :class:`LoopReport` record and its JSON.

The records here hold data only; the loop (:mod:`.run`) builds them. Pictures and
the Markdown text of a report are the reporting layer's (``toothfem.report.loop``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .engine import Fit, HeldOut
from .separation import AliasGroup
from .trends import Trend


@dataclass(frozen=True, kw_only=True)
class Candidate:
    """One candidate's score at one selection step."""
    name: str
    values: tuple
    stderr: tuple
    rmse: float
    cv_wrmse: float
    delta_bic: float
    passed: bool
    bounded: bool = False          # would pass but for a parameter at its physical bound
    note: str = ""


@dataclass(frozen=True, kw_only=True)
class Step:
    """One step of the forward-backward selection."""
    index: int
    added: str | None
    candidates: tuple              # Candidate, best first
    reason: str
    aliased: tuple = ()            # names as good as the added one (BIC within alias_bic)
    removed: tuple = ()            # names dropped again after this addition
    bounded: tuple = ()            # names that would help only at a parameter's bound
    group: AliasGroup | None = None   # the alias group of this step and how to separate it
    trend: Trend | None = None     # the covariate the residual follows most after the step
    partner: str = ""              # added together with ``added`` (a pair)


@dataclass(frozen=True, kw_only=True)
class EffectFit:
    """An effect the loop added, with its fitted parameters."""
    name: str
    parameters: dict               # name -> {"value", "stderr", "unit", "at_bound", "bounds"}
    case_fields: tuple
    citation: str
    equation: str


@dataclass(frozen=True, kw_only=True)
class Closing:
    """Small data: the parameter value that brings the model onto the data."""
    name: str
    values: tuple
    rmse: float
    at_bound: bool
    note: str


@dataclass(frozen=True, kw_only=True)
class LoopReport:
    """The outcome of :func:`~toothfem.efficiency.loop.run_loop`: errors before and after,
    the effects added, the selection steps, the residual trends. Efficiencies and errors as
    fractions; arrays of shape (M,) over the measured points (the bins' means when the rows
    were binned: ``binning``)."""
    case_name: str
    data_source: str
    n_points: int                  # points fitted (M)
    n_rows: int                    # good rows of the data (more than M when binned)
    weighted: bool
    baseline: HeldOut
    final: HeldOut
    baseline_fit: Fit
    final_fit: Fit
    effects: tuple                 # EffectFit
    steps: tuple                   # Step
    trends_before: tuple           # Trend
    trends_after: tuple
    signatures: dict               # effect name -> correlation with the baseline residual
    skipped: dict                  # effect name -> why not a candidate
    unexplained: tuple             # covariate names the final residual still follows
    stop_reason: str
    closing: tuple = ()            # Closing (small data only)
    selection: bool = True
    rejected_rows: tuple = ()
    provenance: dict = field(default_factory=dict)
    covariates: dict = field(default_factory=dict)   # name -> (M,) for the plots
    measured: np.ndarray | None = None
    sigma: np.ndarray | None = None          # measurement uncertainty of each point
    elapsed_s: float = 0.0
    evaluations: int = 0
    notes: tuple = ()              # what was done to the data, one line each (dropped
                                   # columns, binning)
    binning: dict | None = None    # binning.Binning.to_dict(), None when not binned
    alias_groups: tuple = ()       # separation.AliasGroup of the steps that found one

    def unexplained_text(self) -> str:
        """What the final residual still holds, in words: the covariates it follows; or,
        where no trend test could be made, that nothing was analysed and the mean residual
        that remains (a residual no test looked at is never "nothing").

        Returns
        -------
        str
        """
        if self.unexplained:
            return (", ".join(self.unexplained) + " (the final residual still follows these "
                    "covariates; no catalog effect accounts for it)")
        if not any(math.isfinite(t.r2) for t in self.trends_after):
            mean = 100 * float(np.mean(self.final_fit.residual))
            return (f"not analysed: {self.n_points} point(s), too few for a trend test; the "
                    f"final residual, {mean:+.3g} points on average (measured - model), "
                    "remains unexplained")
        return "nothing (the final residual follows none of the covariates)"

    def to_dict(self) -> dict:
        """The JSON of the report (report.json).

        Returns
        -------
        dict
            Plain JSON types only (NaN and infinities as None): rows and points, baseline
            and final errors, effects, selection steps, trends, signatures, skipped
            candidates, closing values, refused rows, notes on the data and its binning,
            provenance, time and model evaluations.
        """
        def held(h: HeldOut, fit: Fit):
            return {"rmse": h.rmse, "max_abs_error": h.max_abs, "weighted_rmse": h.wrmse,
                    "folds": h.folds, "fit_rmse": fit.rmse, "bic": fit.bic,
                    "mean_residual": float(np.mean(fit.residual))}

        def trend(t: Trend | None):
            if t is None:
                return None
            return {"covariate": t.covariate, "kind": t.kind, "r2": t.r2,
                    "p_value": t.p_value, "amplitude": t.amplitude, "follows": t.follows}

        return jsonable({
            "case": self.case_name, "data": self.data_source, "n_rows": self.n_rows,
            "n_points": self.n_points, "notes": list(self.notes), "binning": self.binning,
            "weighted": self.weighted, "selection": self.selection,
            "baseline": held(self.baseline, self.baseline_fit),
            "final": held(self.final, self.final_fit),
            "effects": [{"name": e.name, "parameters": e.parameters,
                         "case_fields": list(e.case_fields), "citation": e.citation,
                         "equation": e.equation} for e in self.effects],
            "unexplained": list(self.unexplained),
            "unexplained_text": self.unexplained_text(),
            "stop_reason": self.stop_reason,
            "steps": [{"index": s.index, "added": s.added, "added_with": s.partner or None,
                       "reason": s.reason,
                       "aliased": list(s.aliased), "removed": list(s.removed),
                       "bounded": list(s.bounded), "residual_follows_most": trend(s.trend),
                       "candidates": [{"name": c.name, "values": list(c.values),
                                       "stderr": list(c.stderr), "rmse": c.rmse,
                                       "cv_weighted_rmse": c.cv_wrmse,
                                       "delta_bic": c.delta_bic, "passed": c.passed,
                                       "bounded": c.bounded, "note": c.note}
                                      for c in s.candidates]}
                      for s in self.steps],
            "alias_groups": [g.to_dict() for g in self.alias_groups],
            "trends_before": [trend(t) for t in self.trends_before],
            "trends_after": [trend(t) for t in self.trends_after],
            "signatures": self.signatures, "skipped": self.skipped,
            "closing": [{"name": c.name, "values": list(c.values), "rmse": c.rmse,
                         "at_bound": c.at_bound, "note": c.note} for c in self.closing],
            "rejected_rows": [str(r) for r in self.rejected_rows],
            "provenance": self.provenance,
            "elapsed_s": self.elapsed_s, "model_evaluations": self.evaluations,
        })


def jsonable(x):
    """Plain JSON types; NaN and infinities as None (strict JSON has no NaN).

    Parameters
    ----------
    x : object
        A dict, list, tuple, numpy array or scalar, nested.

    Returns
    -------
    object
        The same structure of dicts (string keys), lists, bools, ints, finite floats or
        None, and anything else as it was.
    """
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return [jsonable(v) for v in x.tolist()]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
