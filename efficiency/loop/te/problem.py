"""The TE/hysteresis loop's side of the fitting engine (:mod:`..engine`; docs/te_rig.md,
"The loop"): the recordings' figures as the engine's rows (:class:`Observations`), the
loop's effects (:class:`TeEffect`), its model evaluation (:class:`TeModel`), the rules it
fits and selects by (:data:`TE_RULES`) and its report record (:class:`TeLoop`).

The rows are weighted by their uncertainty (weight 1/sigma, so a weighted residual is in
sigma); an effect is added only where BIC falls by :attr:`Settings.delta_bic` and the
held-out error by :attr:`Settings.min_cv_gain`, the thresholds the efficiency loop uses.
The held-out error is k-fold over the observations' groups (torque levels: a fold holds out
whole torques).

The model is a callable: ``model(options) -> (N,) predictions`` on the observations' rows,
``options`` the effects' model options merged (:attr:`TeEffect.options`).
"""
from __future__ import annotations

import contextlib
from collections.abc import Callable
import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from ....bars import bar
from ....errors import ToothfemError
from .. import engine as en
from ..engine import Parameter, parameter  # noqa: F401  (the TE effects' parameters)
from ..settings import DEFAULT_SETTINGS

#: The TE loop's rules (:class:`..engine.Rules`), the reason beside each.
TE_RULES = en.Rules(
    fd_step=1e-2,            # the system model is smooth in a play or an error of
                             # micrometres at this step, and its contact solve settles to
                             # less than finer steps would read
    fit_tol=1e-4,            # the parameters' standard errors are percents; each function
                             # evaluation is a system solve
    starts="restart",        # from the first start; the others only while the best ends at
                             # a bound (each start a run of system solves)
    folds="label",           # the torque levels' groups take the shuffle's labels
    scoring="alone",         # each evaluation is a system solve: a candidate fits its own
                             # parameters with the effects added held; only the one added
                             # is refitted jointly
    rank="bic",              # the lowest BIC among those that pass (kept as the TE loop
                             # chose, so its results stay as they were)
    tie_bic=0.0,             # an exact tie only: the first in the candidates' order
    aliases="unbounded",     # any candidate not at a bound at most Settings.alias_bic above
                             # the added one: a candidate that does not pass may still
                             # explain the rows as well
    # Two fits whose rows differ by less than this [sigma, the weighted distance D between
    # their predictions] are aliases whatever their BIC: the noise makes BIC's difference
    # D^2 +- 2 D (for rows y = p_a + noise, |y - p_b|^2 - |y - p_a|^2 = D^2 + 2 <p_a - p_b,
    # noise>), so below D = 6 the other candidate can win by noise alone at more than three
    # standard deviations' chance (0.13 %), and the model's own error (its sampling of the
    # period) is not in the rows' sigma: a BIC margin there is no evidence. (RV-40E's
    # eccentric under crank 2, disc 1 with its phase turned mirrors crank 1, disc 1's at
    # D = 4.5 on the shipped recordings, and won there by BIC 8.9.)
    alias_separation=6.0,
    exclude_aliases=True,    # an added effect's aliases are not added after it: the rows
                             # cannot tell them apart
    prune_fraction=None,     # no backward step (its refits are system solves)
    pairs=False,             # a pair's fit is a run of system solves for each of about
                             # 60 pairs: minutes a step (issue 39's budget); a bounded
                             # candidate is reported with what it would need instead
)
#: Residual [sigma] of every row where the model does not settle: far worse than any fit.
FAILED_SIGMA = 30.0
#: Options equal to this many significant decimals (SI: 1e-15 m) are one model evaluation:
#: the fits of one step start from the same values and revisit them.
OPTION_DECIMALS = 15
#: Model evaluations kept (each an (N,) array of a few hundred rows).
EVALUATIONS_KEPT = 4096
#: Seconds between a step's progress lines off a terminal (a step takes minutes).
PROGRESS_EVERY_S = 30.0


@dataclass(frozen=True, kw_only=True)
class Observations:
    """What the recordings say, one row per observed figure: ``values`` in each row's unit,
    ``sigma`` one reading's standard uncertainty (same unit), ``group`` the fold group of the
    held-out error (the torque level), ``labels`` what each row is (its unit in the label),
    ``kinds`` the row's quantity (e.g. ``twist_arcmin``, ``order_39_arcsec``). The engine's
    :class:`~..engine.Observations`, weighted by 1/sigma."""
    values: np.ndarray
    sigma: np.ndarray
    group: np.ndarray
    labels: tuple
    kinds: tuple

    def __post_init__(self):
        n = len(self.values)
        if not (len(self.sigma) == len(self.group) == len(self.labels) == len(self.kinds) == n):
            raise ValueError("observations: values, sigma, group, labels and kinds differ "
                             "in length")
        if not np.all(np.asarray(self.sigma) > 0):
            raise ValueError("observations: every sigma must be > 0")

    @property
    def weight(self) -> np.ndarray:
        """(N,) 1 / sigma: a weighted residual is in sigma."""
        return 1.0 / np.asarray(self.sigma, float)


class OptionsOf(Protocol):
    """An effect's model options at its parameters' values (a lambda binding the effect's
    index as a default argument fits)."""

    def __call__(self, values: tuple[float, ...], /) -> dict:
        """The model's options.

        Parameters
        ----------
        values : tuple of float
            One per parameter, in the parameters' units.

        Returns
        -------
        dict
            Flat option keys (:mod:`.effects`) -> value in SI.
        """


@dataclass(frozen=True, kw_only=True)
class TeEffect:
    """An effect of the TE/hysteresis loop (the engine's :class:`~..engine.Effect`): its
    parameters (bounds, starts, typical value) and ``options(values) -> dict`` of the
    model's options it sets; what it means, its source and the measurement that tells it
    apart from the others (``direct_test``)."""
    name: str
    parameters: tuple
    options: OptionsOf                 # tuple of values -> dict
    summary: str
    citation: str
    direct_test: str
    costly: str = ""                   # why its model evaluations cost most ("": they don't)

    def model_options(self, values) -> dict:
        """The model's options at ``values``.

        Parameters
        ----------
        values : sequence of float
            One per parameter, in the parameters' units.

        Returns
        -------
        dict
        """
        return dict(self.options(tuple(float(v) for v in values)))


class TeModel:
    """The loop's model evaluation (the engine's :class:`~..engine.Model`): the effects'
    options merged, one evaluation per distinct set of options, and a wall of
    :data:`FAILED_SIGMA` on every row where the model does not settle (the fit steered away
    from it, each such evaluation kept in :attr:`failures`).

    Parameters
    ----------
    observations : Observations
    model : callable
        ``model(options: dict) -> (N,) array`` on the observations' rows; ``{}`` is the
        case as declared.
    catalog : dict of str to TeEffect
    """

    def __init__(self, observations: Observations, model, catalog: dict):
        self.obs = observations
        self.model = model
        self.catalog = catalog
        self.evaluations = 0
        self.failures: list[str] = []     # the model's failures, one line each
        self._cache: dict = {}
        # called after each evaluation with the effects fitted, the last one the candidate
        self.on_evaluation: Callable[[str], None] | None = None
        self.replayed = 0                 # evaluations read back from a journal
        self._log: list = []              # the evaluations since take_log

    def options(self, names, values) -> dict:
        """The model's options of the effects ``names`` at ``values``.

        Parameters
        ----------
        names : sequence of str
        values : array_like
            Their parameters' values, one effect after the other.

        Returns
        -------
        dict
        """
        options: dict = {}
        i = 0
        for n in names:
            k = len(self.catalog[n].parameters)
            options.update(self.catalog[n].model_options(values[i:i + k]))
            i += k
        return options

    def predict(self, names, values) -> np.ndarray:
        """The model's prediction with the effects ``names`` at ``values``.

        Parameters
        ----------
        names : tuple of str
        values : numpy.ndarray
            Their parameters' values, one effect after the other.

        Returns
        -------
        numpy.ndarray, (N,)
        """
        options = self.options(names, values)
        key = _key(options)
        if key in self._cache:
            return self._cache[key]
        failed = len(self.failures)
        out = self._evaluate(options)
        self._keep(key, out)
        self._log.append([[[list(k), float(v)] for k, v in options.items()],
                          [float(x) for x in out],
                          self.failures[-1] if len(self.failures) > failed else ""])
        if self.on_evaluation is not None:
            self.on_evaluation(", ".join(names) or "the case as declared")
        return out

    def _keep(self, key, out) -> None:
        if len(self._cache) >= EVALUATIONS_KEPT:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = out

    def take_log(self) -> list:
        """The evaluations since the last call, each ``[options, rows, failure]`` in plain
        JSON (the options as [key as a list, value] pairs): what a journal keeps for
        :meth:`replay`.

        Returns
        -------
        list
        """
        log, self._log = self._log, []
        return log

    def replay(self, log) -> None:
        """Take evaluations a journal kept (:meth:`take_log`'s entries) as done: the same
        options give those rows without a model evaluation, so a resumed loop goes through
        its finished steps again in moments, to the same numbers.

        Parameters
        ----------
        log : iterable of [list of [list, float], list of float, str]

        Raises
        ------
        ValueError
            For an entry of another number of rows than the observations'.
        """
        for options, rows, failure in log:
            out = np.asarray(rows, float)
            if out.shape != self.obs.values.shape:
                raise ValueError(f"a journaled evaluation holds {out.size} rows; the "
                                 f"recordings give {self.obs.values.size}")
            self._keep(_key({tuple(k): v for k, v in options}), out)
            if failure:
                self.failures.append(str(failure))
            self.replayed += 1

    def _evaluate(self, options: dict) -> np.ndarray:
        """One model evaluation, checked (the wall of FAILED_SIGMA where it fails)."""
        self.evaluations += 1
        try:
            out = np.asarray(self.model(options), float)
        except ToothfemError as exc:
            # the model does not settle there (a contact's active set cycling at a corner
            # of the parameters): a wall of FAILED_SIGMA on every row steers the fit away
            self.failures.append(f"{exc} (at {options})")
            return self.obs.values - FAILED_SIGMA * np.asarray(self.obs.sigma, float)
        if out.shape != self.obs.values.shape or not np.all(np.isfinite(out)):
            raise ValueError(f"the model returned {out.shape} values (finite: "
                             f"{bool(np.all(np.isfinite(out)))}) for {len(self.obs.values)} "
                             "observations")
        return out


def _key(options: dict) -> tuple:
    """One evaluation's key: its options, each to OPTION_DECIMALS."""
    return tuple(sorted((k, round(float(v), OPTION_DECIMALS)) for k, v in options.items()))


@dataclass(frozen=True, kw_only=True)
class TeStep:
    """One selection step: the candidates scored, the one added (or None) and why, its alias
    group and the candidates that would help only at a bound."""
    index: int
    scored: tuple                      # (name, bic, cv_wrmse, values, at_bound any)
    added: str | None
    reason: str
    aliased: tuple = ()
    bounded: tuple = ()


@dataclass(frozen=True, kw_only=True)
class TeLoop:
    """The outcome: the fits before and after, the steps, the effects added with their alias
    groups and direct tests, and why the loop stopped."""
    baseline: en.Fit
    final: en.Fit
    steps: tuple
    added: tuple                       # names
    alias_groups: dict                 # added name -> tuple of aliased names
    stop_reason: str
    observations: Observations
    catalog: dict = field(default_factory=dict)      # name -> TeEffect
    failures: tuple = ()               # where the model did not settle, one line each
    evaluations: int = 0
    replayed: int = 0                  # evaluations read back from an earlier run's journal

    def failure_note(self) -> str:
        """One line on the evaluations where the model did not settle (the fit was
        steered away from them), or "" where there were none.

        Returns
        -------
        str
        """
        if not self.failures:
            return ""
        return (f"the model did not settle at {len(self.failures)} of {self.evaluations} "
                f"evaluations (each read as {FAILED_SIGMA:g} sigma on every row, the fit "
                f"steered away; "
                f"the first: {self.failures[0]})")

    def group_values(self, name: str) -> dict:
        """An added effect's alias group with each member's fitted values (the added one's
        final values, each alias's from the step that added it).

        Parameters
        ----------
        name : str
            An added effect.

        Returns
        -------
        dict of str to tuple of float
        """
        out = {name: tuple(self.final.values[name])}
        for step in self.steps:
            if step.added == name:
                out.update({c[0]: tuple(c[3]) for c in step.scored if c[0] in step.aliased})
        return out

    def to_dict(self) -> dict:
        """The loop as plain JSON types.

        Returns
        -------
        dict
        """
        def fit(f: en.Fit):
            return {"effects": list(f.effects),
                    "values": {k: list(v) for k, v in f.values.items()},
                    "stderr": {k: [None if not np.isfinite(s) else s for s in v]
                               for k, v in f.stderr.items()},
                    "at_bound": {k: list(v) for k, v in f.at_bound.items()},
                    "weighted_rmse_sigma": f.wrmse, "held_out_weighted_rmse_sigma": f.cv_wrmse,
                    "bic": f.bic}

        return {"baseline": fit(self.baseline), "final": fit(self.final),
                "added": [{"name": n, "parameters": {
                    p.name: {"value": v, "unit": p.unit, "bounds": [p.lo, p.hi]}
                    for p, v in zip(self.catalog[n].parameters, self.final.values[n])},
                    "summary": self.catalog[n].summary, "citation": self.catalog[n].citation,
                    "alias_group": [{"name": a, "values": list(v),
                                     "direct_test": self.catalog[a].direct_test}
                                    for a, v in self.group_values(n).items()]}
                    for n in self.added],
                "steps": [{"index": s.index, "added": s.added, "reason": s.reason,
                           "aliased": list(s.aliased), "bounded": list(s.bounded),
                           "candidates": [{"name": c[0], "bic": c[1],
                                           "held_out_weighted_rmse_sigma": c[2],
                                           "values": list(c[3]), "at_bound": c[4]}
                                          for c in s.scored]} for s in self.steps],
                "stop_reason": self.stop_reason,
                "model_failures": list(self.failures),
                "held_out_error_cut": self.baseline.cv_wrmse / max(self.final.cv_wrmse, 1e-300),
                "rows": len(self.observations.values)}


class _Bar(en.Listener):
    """A bar over each step's candidates, the model evaluations so far beside it."""

    def __init__(self, model: TeModel, enabled: bool, on_step=None):
        self.model, self.enabled, self.on_step = model, enabled, on_step

    def stepped(self, step: en.Step) -> None:
        """Hand each finished step to ``on_step`` (its record: what was added, every
        candidate's fit), as it finishes."""
        if self.on_step is None:
            self.model.take_log()
            return
        self.on_step(step.index, {
            "added": step.added, "removed": list(step.removed),
            "model_evaluations": self.model.evaluations,
            "effects": list(step.after.effects),
            "values": {k: [float(x) for x in v] for k, v in step.after.values.items()},
            "held_out_weighted_rmse_sigma": step.after.cv_wrmse,
            "candidates": [{"name": sc.name, "delta_bic": sc.delta_bic,
                            "cv_gain": sc.cv_gain, "failure": sc.failure}
                           for sc in step.scores],
            # what a resumed run replays (TeModel.replay): this step's new evaluations
            "evaluations": self.model.take_log()})

    @contextlib.contextmanager
    def scoring(self, step, names):
        with bar(total=len(names), desc=f"TE loop step {step}", unit="candidate",
                 enabled=self.enabled, every_s=PROGRESS_EVERY_S) as shown:
            def evaluated(fitting):
                shown.set_postfix_str(f"{self.model.evaluations} model evaluations; "
                                      f"fitting {fitting}")

            def tick(score):
                shown.update(1)
                shown.set_postfix_str(f"{self.model.evaluations} model evaluations")
            self.model.on_evaluation = evaluated
            try:
                yield tick
            finally:
                self.model.on_evaluation = None


def _gains(f: en.Fit, ref: en.Fit) -> tuple:
    """(BIC fall, relative held-out cut) of a fit against the step's."""
    cv = 1 - f.cv_wrmse / ref.cv_wrmse if ref.cv_wrmse > 0 else 0.0
    return ref.bic - f.bic, cv


class TeProblem:
    """Observations, a model and a catalog: the engine with the TE loop's rules, and the
    loop (:meth:`run`).

    Parameters
    ----------
    observations : Observations
    model : callable
        ``model(options: dict) -> (N,) array`` on the observations' rows; ``{}`` is the
        case as declared.
    catalog : sequence of TeEffect
    settings : Settings
    """

    def __init__(self, observations: Observations, model, catalog, settings=DEFAULT_SETTINGS):
        self.obs = observations
        self.catalog = {e.name: e for e in catalog}
        self.settings = settings
        self.model = TeModel(observations, model, self.catalog)
        self.engine = en.Engine(observations, self.catalog.values(), self.model, rules=TE_RULES,
                                settings=settings)

    def fit(self, names, start: dict | None = None, free=None) -> en.Fit:
        """Fit the effects ``names`` to every row (:meth:`..engine.Engine.fit`).

        Parameters
        ----------
        names : sequence of str
        start : dict, optional
            name -> values to start from; the others start at their parameters' ``starts``.
        free : collection of str, optional
            The effects whose parameters vary (default all); the others stay at ``start``.

        Returns
        -------
        Fit
        """
        return self.engine.fit(names, start, free=free)

    def separation(self, a: en.Fit, b: en.Fit) -> float:
        """The weighted distance between two fits' rows [sigma] (``TE_RULES.alias_separation``).

        Parameters
        ----------
        a, b : Fit

        Returns
        -------
        float
        """
        return self.engine.separation(a, b)

    def run(self, candidates=None, progress: bool = False, on_step=None,
            replay=()) -> TeLoop:
        """Forward selection by the TE loop's rules (:func:`..engine.select`).

        Parameters
        ----------
        candidates : sequence of str, optional
            Names from the catalog (default all).
        progress : bool
            A bar over each step's candidates, the model evaluations so far beside it.
        on_step : callable, optional
            ``on_step(index, record)`` as each step finishes (a long run keeps it on disk);
            the record's ``evaluations`` are the step's new model evaluations.
        replay : iterable, optional
            Model evaluations of an earlier run's finished steps (their records'
            ``evaluations``, :meth:`TeModel.replay`): the run goes through those steps
            again without evaluating the model, then on.

        Returns
        -------
        TeLoop
        """
        s = self.settings
        self.model.replay(replay)
        listener = _Bar(self.model, progress, on_step)
        sel = en.select(self.engine, list(candidates or self.catalog), listener=listener)
        steps = tuple(self._step(st) for st in sel.steps)
        if sel.stop == en.NOTHING_PASSES:
            stop = steps[-1].reason
        elif sel.stop in (en.NO_CANDIDATES, en.ALL_TRIED) \
                and len(sel.final.effects) < s.max_effects:
            stop = "every candidate tried"
            with listener.scoring(len(steps) + 1, ()):      # the empty step, shown
                pass
        elif sel.stop == en.TOO_FEW_ROWS:
            stop = "too few rows left for another parameter"
        else:
            stop = f"{s.max_effects} effects: the most the loop adds"
        return TeLoop(baseline=sel.baseline, final=sel.final, steps=steps,
                      added=sel.final.effects,
                      alias_groups={st.added: st.aliased for st in sel.steps if st.added},
                      stop_reason=stop, observations=self.obs, catalog=self.catalog,
                      failures=tuple(self.model.failures), evaluations=self.model.evaluations,
                      replayed=self.model.replayed)

    def _values(self, name: str, fit: en.Fit) -> str:
        """An effect's fitted parameters, each with its unit, a bound said."""
        out = []
        for p, v, at in zip(self.catalog[name].parameters, fit.values[name],
                            fit.at_bound[name]):
            out.append(f"{p.name} = {v:.4g}" + (" (its bound)" if at else ""))
        return ", ".join(out)

    def _step(self, step: en.Step) -> TeStep:
        """The report's record of a step, its candidates by BIC."""
        s = self.settings
        order = en.ranked(step.scores, "bic")
        table = tuple((c.name, c.bic, c.cv_wrmse, c.fit.values[c.name] if c.fit else (),
                       c.at_bound) for c in order)
        bounded = tuple(c.name for c in order if c.bounded)
        if step.added is None:
            if bounded:
                best = next(c for c in order if c.bounded)
                assert best.fit is not None       # a bounded candidate was fitted
                _, gain_cv = _gains(best.fit, step.before)
                stop = ("every candidate that would help does so only at a bound of its "
                        f"parameter: the best, {best.name}, at "
                        f"{self._values(best.name, best.fit)}, would cut the held-out error "
                        f"by {100 * gain_cv:.3g} %; the data ask for more than it can "
                        "physically give")
            else:
                best = order[0]
                gain_bic, gain_cv = _gains(best.fit, step.before) if best.fit else (
                    -math.inf, 0.0)
                at = f", at {self._values(best.name, best.fit)}," if best.fit else ""
                stop = (f"the best candidate, {best.name}{at} lowers BIC by {gain_bic:.3g} "
                        f"(needs {s.delta_bic:g}) and the held-out error by "
                        f"{100 * gain_cv:.3g} % (needs {100 * s.min_cv_gain:g} %)")
            return TeStep(index=step.index, scored=table, added=None, reason=stop,
                          bounded=bounded)
        assert step.added_fit is not None
        gain_bic, gain_cv = _gains(step.added_fit, step.before)
        return TeStep(index=step.index, scored=table, added=step.added,
                      reason=f"BIC -{gain_bic:.3g}, held-out error -{100 * gain_cv:.3g} %",
                      aliased=step.aliased, bounded=bounded)
