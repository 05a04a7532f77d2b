"""The measured-data loop (:func:`run_loop`): the efficiency loop's adapter of the fitting
engine (:mod:`.engine`), with the data checked and binned (:func:`loop_data`) and the
report records built (:mod:`.report`).

:func:`run_loop` compares the model with measured efficiencies and adds effects of the
catalog one at a time while they help:

1. Baseline: the case as it is, its residual trends (:mod:`.trends`) and each candidate's
   signature.
2. Selection (:func:`.engine.select` by the efficiency loop's :data:`.problem.EFFICIENCY_RULES`): every
   applicable candidate not declared by the case is fitted together with the effects
   already added, scored by its k-fold held-out error and by BIC; the candidate with the
   lowest held-out error among those that lower BIC by at least :attr:`Settings.delta_bic`
   and the held-out error by at least :attr:`Settings.min_cv_gain` is added (of candidates
   within ``EFFICIENCY_RULES.tie_bic`` of each other, the one first in the catalog). A candidate that
   would pass only with a parameter at its physical bound is not added: the data ask for
   more than it can give. Candidates within :attr:`Settings.alias_bic` of the added one are
   named as aliases, an alias group with the measurement that would separate them
   (:mod:`.separation`, the engine's separating-measurement hook). After each step the
   covariate the residual follows most is recorded.
3. Backward: any earlier effect whose removal now costs less than ``EFFICIENCY_RULES.prune_fraction``
   of the BIC threshold is dropped again (an effect taken on the way can be made redundant
   by a later one); repeat from 2. When no candidate passes, the loop stops and says which
   came closest and by how much it fell short.
4. After the last effect, a residual that still follows a covariate is reported as
   unexplained, with that covariate.

Before all this the data are checked and, when large, binned (:func:`loop_data`): more than
one row needs at least two distinct operating points, a selection at least one per fold;
more than :attr:`Settings.max_points` rows are binned onto at most that many operating
points (:mod:`.binning`), and the report's notes say so.

With fewer than :attr:`Settings.min_points` points there is no held-out error to select on:
the loop then reports the baseline error and, for each candidate, the parameter value that
would bring the model onto the data (:attr:`LoopReport.closing`) with whether that value is
inside the effect's physical bounds: what such data can and cannot support.
"""
from __future__ import annotations

import time

import numpy as np

from ...errors import MeasuredDataError, ToothfemError
from . import effects as fx
from . import engine as en
from .binning import bin_rows
from .measured import MeasuredData, require_distinct
from .problem import Problem
from .report import Candidate, Closing, EffectFit, LoopReport, Step
from .separation import AliasGroup, alias_group
from .settings import DEFAULT_SETTINGS, Settings
from .trends import most_followed, residual_trends, signatures

#: A candidate alone "meets the data" when its RMSE is below this [efficiency]: 0.01
#: points, far below a rig's uncertainty (the sine prototype's rig: 2 points).
CLOSING_RMSE = 1e-4


def candidates_of(case, points, effects):
    """The effects the loop may add to a case for its data, and why the others may not.

    Parameters
    ----------
    case : toothfem.Case
        The reducer case.
    points : effects.Points
        The measured operating points.
    effects : iterable of effects.Effect
        The catalog to draw from.

    Returns
    -------
    tuple
        (candidate names in catalog order, {name: why not a candidate}): an effect is
        skipped when it cannot act on the drive or data, or when the case declares it.
    """
    cands, skipped = [], {}
    for e in effects:
        why = e.applicable(case, points)
        if why:
            skipped[e.name] = why
            continue
        dec = e.declared(case)
        if dec:
            skipped[e.name] = f"declared in the case ({dec}): not re-added"
            continue
        cands.append(e.name)
    return cands, skipped


def loop_data(data: MeasuredData, settings: Settings = DEFAULT_SETTINGS) -> tuple:
    """The points the loop fits: ``data`` checked and, above :attr:`Settings.max_points`
    rows, binned (:func:`.binning.bin_rows`).

    Parameters
    ----------
    data : measured.MeasuredData
        Measured rows.
    settings : Settings
        Folds, fewest points of a selection, most points kept.

    Returns
    -------
    tuple
        (MeasuredData of the points, :class:`.binning.Binning` or None when not binned).

    Raises
    ------
    MeasuredDataError
        No rows; several rows of one operating point (identical points: the loop compares
        the model with the change of the efficiency between points); fewer distinct points
        than folds where a selection is made (a held-out fold would hold copies of the
        training points).
    """
    rows = len(data)
    if rows == 0:
        raise MeasuredDataError(f"{data.source or 'measured data'}: no measured points")
    if rows > 1:
        require_distinct(data, 2, "comparing the change of the efficiency between points")
    points, binning = bin_rows(data, settings.max_points)
    if len(points) >= settings.min_points:
        k = en.fold_count(len(points), settings.folds)
        require_distinct(points, k, f"the selection's {k}-fold held-out error (a distinct "
                                    "point per fold; fewer folds need fewer)", rows=rows)
    return points, binning


def run_loop(case, data, effects=None, *, settings=DEFAULT_SETTINGS, loads="analytic",
             progress=None) -> LoopReport:
    """The measured-data loop (module docstring).

    Parameters
    ----------
    case : toothfem.Case
        The reducer case, as declared.
    data : measured.MeasuredData
        Measured efficiencies, M rows (binned when more than :attr:`Settings.max_points`).
    effects : sequence of effects.Effect, optional
        The catalog to draw from (default :func:`effects.catalog`).
    settings : Settings
        Thresholds of the selection and of the residual analysis.
    loads : str
        Load sharing of the model, ``"analytic"`` or ``"fem"`` (FE cycle mode, slow).
    progress : callable, optional
        ``progress(str)`` is told of each step.

    Returns
    -------
    LoopReport
        Errors before and after, the effects added, the selection steps, the residual
        trends and what the final residual still follows; ``notes`` says what was done to
        the data (dropped columns, binning).

    Raises
    ------
    MeasuredDataError
        Data the loop cannot compare with (:func:`loop_data`), in one line.
    """
    t0 = time.perf_counter()
    effects = tuple(effects or fx.catalog())
    say = progress or (lambda msg: None)
    rows = len(data)
    data, binning = loop_data(data, settings)
    if binning is not None:
        say(binning.note())
    prob = Problem(case=case, data=data, effects=effects, settings=settings, loads=loads)
    cands, skipped = candidates_of(case, prob.points, effects)
    covs = data.covariates()
    base = prob.engine.fit(())
    baseline = prob.engine.held_out(base)
    trends_before = residual_trends(base.residual, covs, prob.w, settings)
    common = dict(case_name=case.name, data_source=data.source, n_points=prob.n,
                  weighted=prob.weighted, baseline=baseline, baseline_fit=base,
                  trends_before=trends_before, signatures=signatures(prob, base, cands),
                  skipped=skipped, rejected_rows=tuple(data.rejected),
                  provenance=dict(data.provenance), covariates=covs, measured=prob.eta,
                  sigma=data.sigma, n_rows=rows, notes=tuple(data.notes),
                  binning=None if binning is None else binning.to_dict())
    say(f"baseline: RMSE {100 * base.rmse:.3f} points on {prob.n} points")
    if prob.n < settings.min_points:
        stop = (f"{prob.n} point(s): fewer than {settings.min_points}, so no held-out error "
                "can be formed and no effect is selected; 'closing' lists the parameter "
                "each candidate would need to meet the data")
        return LoopReport(**common, final=baseline, final_fit=base, effects=(), steps=(),
                          trends_after=trends_before, unexplained=(), stop_reason=stop,
                          closing=_closing(prob, cands), selection=False,
                          elapsed_s=time.perf_counter() - t0, evaluations=prob.evaluations)
    told = _Steps(prob, covs, say)
    sel = en.select(prob.engine, cands, base=base, separate=lambda i, fits: _group(prob, i, fits),
                    listener=told)
    current, steps = sel.final, tuple(told.steps)
    final = prob.engine.held_out(current)
    trends_after = residual_trends(current.residual, covs, prob.w, settings)
    return LoopReport(**common, final=final, final_fit=current,
                      effects=tuple(_effect_fit(prob.effects[n], current)
                                    for n in current.effects),
                      steps=steps, trends_after=trends_after,
                      unexplained=tuple(t.covariate for t in trends_after if t.follows),
                      stop_reason=_stop_reason(sel, steps, settings), closing=(),
                      selection=True,
                      alias_groups=tuple(s.group for s in steps if s.group is not None),
                      elapsed_s=time.perf_counter() - t0, evaluations=prob.evaluations)


#: The selection's stop kinds in the loop's words (nothing passing: the last step's
#: reason, :meth:`_Steps.stepped`).
STOP_REASONS = {
    en.NO_CANDIDATES: ("no candidate: every effect of the catalog is declared in the case or "
                       "cannot act on this drive and data (see 'skipped')"),
    en.ALL_TRIED: "every candidate effect has been added",
    en.TOO_FEW_ROWS: "too few points left for another parameter",
    en.EXCHANGING: "the selection keeps exchanging effects: stopped",
}


def _stop_reason(sel: en.Selection, steps, settings: Settings) -> str:
    """Why the selection stopped, in the loop's words."""
    if sel.stop == en.NOTHING_PASSES:
        return steps[-1].reason
    if sel.stop == en.MAX_EFFECTS:
        return f"the limit of {settings.max_effects} effects is reached"
    return STOP_REASONS[sel.stop]


class _Steps(en.Listener):
    """The engine's steps as the report's :class:`~.report.Step` records, each added one
    told to ``say`` as it is taken."""

    def __init__(self, prob: Problem, covs, say):
        self.prob, self.covs, self.say = prob, covs, say
        self.steps: list[Step] = []

    def stepped(self, step: en.Step) -> None:
        prob, settings = self.prob, self.prob.settings
        current = step.before
        # the candidates by held-out error, those that pass first and the one added first
        order = en.ranked(step.scores, "held_out")
        if step.added is not None:
            order.sort(key=lambda c: c.name != step.added)
        cands = tuple(_candidate(prob, c) for c in order)
        bounded = tuple(c.name for c in cands
                        if c.bounded and c.name not in (step.added, step.partner))
        trend = most_followed(residual_trends(step.after.residual, self.covs, prob.w,
                                              settings))
        if step.added is None:
            closest = min(cands, key=lambda c: c.cv_wrmse)
            stop = (f"nothing helps: the best candidate, {closest.name}, changes the held-out "
                    f"error {_change(closest.cv_wrmse, current.cv_wrmse)} and BIC "
                    f"by {closest.delta_bic:+.1f} (needs <= -{settings.min_cv_gain:.0%} and "
                    f"<= -{settings.delta_bic:g})")
            if bounded:
                stop += (f"; {', '.join(bounded)} would explain the data only with a "
                         "parameter at its bound: the data ask for more than the effects can "
                         "physically give, so it is not an explanation")
                if step.pairs:
                    stop += f" (nor with any of the {len(step.pairs)} pairs tried)"
            self.steps.append(Step(index=step.index, added=None, candidates=cands,
                                   reason=stop, bounded=bounded, trend=trend))
            return
        if step.partner:
            fit = step.added_fit
            assert fit is not None          # a step that adds has its fit
            reason = (f"added {step.added} together with {step.partner} ({step.added} alone "
                      f"stops at a parameter's bound): held-out weighted RMS "
                      f"{current.cv_wrmse:.4g} -> {fit.cv_wrmse:.4g}, BIC "
                      f"{fit.bic - current.bic:+.1f}")
        else:
            best = cands[0]
            reason = (f"added {best.name}: held-out weighted RMS {current.cv_wrmse:.4g} -> "
                      f"{best.cv_wrmse:.4g}, BIC {best.delta_bic:+.1f}")
        if step.aliased:
            reason += f"; the data cannot tell it from {', '.join(step.aliased)}"
        if bounded:
            reason += (f"; not added, a parameter at its bound: {', '.join(bounded)}")
        if step.removed:
            reason += "; then removed " + ", ".join(step.removed) + " (no longer needed)"
        group = step.group
        assert group is None or isinstance(group, AliasGroup)      # _group's
        self.steps.append(Step(index=step.index, added=step.added, partner=step.partner,
                               candidates=cands,
                               reason=reason, aliased=step.aliased, removed=step.removed,
                               bounded=bounded, group=group, trend=trend))
        self.say(reason)


def _group(prob: Problem, step: int, fits: dict) -> AliasGroup:
    """The alias group of a step (:func:`.separation.alias_group`); a search that fails
    (a member's model refused at a point of the search) is said in the group's note."""
    try:
        return alias_group(prob, step, fits)
    except ToothfemError as exc:
        return AliasGroup(step=step, members=(), points=(), separable=False,
                          note=f"the data cannot tell {', '.join(fits)} apart; the search "
                               f"for a separating measurement failed: {exc}")


def _change(new: float, old: float) -> str:
    """'by -12.3 %': the relative change of a held-out error; from 0 (the model already
    meets every held-out point) there is no relative change to give."""
    if old > 0:
        return f"by {100 * (new / old - 1):+.1f} %"
    return f"from 0 to {new:.4g}"


def _candidate(prob: Problem, c: en.Score) -> Candidate:
    """The report's record of a candidate's score."""
    if c.fit is None:
        return Candidate(name=c.name, values=(), stderr=(), rmse=float("nan"),
                         cv_wrmse=float("inf"), delta_bic=float("inf"), passed=False,
                         note=f"failed: {c.failure}")
    f, note = c.fit, ""
    if c.at_bound:
        eff = prob.effects[c.name]
        note = "at its bound: " + ", ".join(
            f"{p.name} = {v:.4g} {p.unit} (bounds {p.lo:.4g} to {p.hi:.4g})"
            for p, v, b in zip(eff.parameters, f.values[c.name], f.at_bound[c.name]) if b)
    return Candidate(name=c.name, values=f.values[c.name], stderr=f.stderr[c.name],
                     rmse=f.rmse, cv_wrmse=f.cv_wrmse, delta_bic=c.delta_bic,
                     passed=c.passed, bounded=c.bounded, note=note)


def _effect_fit(eff, fit: en.Fit) -> EffectFit:
    """The record of an added effect: each parameter's value, error, unit and bounds."""
    params = {}
    for p, v, s, b in zip(eff.parameters, fit.values[eff.name], fit.stderr[eff.name],
                          fit.at_bound[eff.name]):
        params[p.name] = {"value": v, "stderr": s, "unit": p.unit, "at_bound": b,
                          "bounds": [p.lo, p.hi]}
    return EffectFit(name=eff.name, parameters=params, case_fields=eff.case_fields,
                     citation=eff.citation, equation=eff.equation)


def _closing(prob: Problem, cands) -> tuple:
    """Small data: each candidate alone, fitted to all points (no held-out check)."""
    out = []
    for name in cands:
        try:
            x = prob.engine.solve((name,), tol=en.EXACT_TOL).values
        except ToothfemError as exc:
            out.append(Closing(name=name, values=(), rmse=float("nan"), at_bound=False,
                               note=f"failed: {exc}"))
            continue
        params = prob.effects[name].parameters
        pred = prob.predict((name,), x)
        rmse = float(np.sqrt(np.mean((prob.eta - pred) ** 2)))
        bound = any(en.at_bound(v, p) for v, p in zip(x, params))
        if bound and rmse > CLOSING_RMSE:
            note = "at its bound: this effect alone cannot reach the data"
        elif rmse <= CLOSING_RMSE:
            note = "meets the data"
        else:
            note = "closest value"
        out.append(Closing(name=name, values=tuple(float(v) for v in x), rmse=rmse,
                           at_bound=bound, note=note))
    return tuple(out)


def final_case(case, report: LoopReport, effects=None):
    """The case with every effect the loop added set to its fitted values.

    Parameters
    ----------
    case : toothfem.Case
        The case the loop ran on.
    report : LoopReport
        Its report.
    effects : sequence of effects.Effect, optional
        The catalog the loop drew from (default :func:`effects.catalog`).

    Returns
    -------
    toothfem.Case
        A copy with the fitted effects' case fields set (the input is not changed).
    """
    cat = {e.name: e for e in (effects or fx.catalog())}
    assignment = {cat[e.name]: tuple(p["value"] for p in e.parameters.values())
                  for e in report.effects}
    return fx.with_effects(case, assignment)
