"""Effect selection: forward by BIC and held-out gain, backward by BIC; the loop itself.

:func:`run_loop` compares the model with measured efficiencies and adds effects of the
catalog one at a time while they help:

1. Baseline: the case as it is, its residual trends (:mod:`.trends`) and each candidate's
   signature.
2. Forward: every applicable candidate not declared by the case is fitted together with the
   effects already added (:meth:`.fit.Problem.make_fit`), scored by its k-fold held-out
   error and by BIC; the candidate with the lowest held-out error among those that lower BIC
   by at least :attr:`Settings.delta_bic` and the held-out error by at least
   :attr:`Settings.min_cv_gain` is added (of candidates within :data:`TIE_BIC` of each other,
   the one first in the catalog). A candidate that would pass only with a parameter at its
   physical bound is not added: the data ask for more than it can give. Candidates within
   :attr:`Settings.alias_bic` of the added one are named as aliases, an alias group with the
   measurement that would separate them (:mod:`.separation`). After each step the covariate
   the residual follows most is recorded.
3. Backward: any earlier effect whose removal now costs less than :data:`PRUNE_FRACTION` of
   the BIC threshold is dropped again (an effect taken on the way can be made redundant by a
   later one); repeat from 2. When no candidate passes, the loop stops and says which came
   closest and by how much it fell short.
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
from .binning import bin_rows
from .fit import EXACT_TOL, Fit, Problem, at_bound, fold_count
from .measured import MeasuredData, require_distinct
from .report import Candidate, Closing, EffectFit, LoopReport, Step
from .separation import AliasGroup, alias_group
from .settings import DEFAULT_SETTINGS, Settings
from .trends import most_followed, residual_trends, signatures

#: An effect leaves again when removing it costs less than this fraction of the BIC entry
#: threshold: below the threshold, so an effect just added does not leave at once.
PRUNE_FRACTION = 0.5
#: Selection steps allowed per candidate: each can be added once and removed once; more
#: steps than that means the selection keeps exchanging effects.
STEPS_PER_CANDIDATE = 2
#: Candidates whose BIC changes differ by less than this are a tie (a likelihood ratio
#: of 1.05: no preference; exact aliases differ by the fit's rounding, near aliases such
#: as the two torque meters' offsets by about 1e-3).
TIE_BIC = 0.1
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
        k = fold_count(len(points), settings)
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
    base = prob.make_fit(())
    baseline = prob.held_out(base)
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
    current, steps, stop = _select(prob, cands, base, settings, say, covs)
    final = prob.held_out(current)
    trends_after = residual_trends(current.residual, covs, prob.w, settings)
    return LoopReport(**common, final=final, final_fit=current,
                      effects=tuple(_effect_fit(prob.effects[n], current)
                                    for n in current.effects),
                      steps=steps, trends_after=trends_after,
                      unexplained=tuple(t.covariate for t in trends_after if t.follows),
                      stop_reason=stop, closing=(), selection=True,
                      alias_groups=tuple(s.group for s in steps if s.group is not None),
                      elapsed_s=time.perf_counter() - t0, evaluations=prob.evaluations)


def _group(prob: Problem, step: int, fits: dict) -> AliasGroup:
    """The alias group of a step (:func:`.separation.alias_group`); a search that fails
    (a member's model refused at a point of the search) is said in the group's note."""
    try:
        return alias_group(prob, step, fits)
    except ToothfemError as exc:
        return AliasGroup(step=step, members=(), points=(), separable=False,
                          note=f"the data cannot tell {', '.join(fits)} apart; the search "
                               f"for a separating measurement failed: {exc}")


def _select(prob: Problem, cands, base: Fit, settings: Settings, say, covs):
    """Forward-backward selection from ``base``: (final fit, steps, stop reason)."""
    current = base
    steps: list[Step] = []
    stop = ""
    while True:
        pool = [c for c in cands if c not in current.effects]
        if not cands:
            stop = ("no candidate: every effect of the catalog is declared in the case or "
                    "cannot act on this drive and data (see 'skipped')")
            break
        if not pool:
            stop = "every candidate effect has been added"
            break
        if len(current.effects) >= settings.max_effects:
            stop = f"the limit of {settings.max_effects} effects is reached"
            break
        if prob.n - current.n_params - 1 < settings.min_points:
            stop = "too few points left for another parameter"
            break
        scored = _score(prob, current, pool, settings)
        best_fit, best = scored[0]
        cand_records = tuple(c for _, c in scored)
        bounded = tuple(c.name for c in cand_records if c.bounded)
        if not best.passed:
            closest = min((c for _, c in scored), key=lambda c: c.cv_wrmse)
            stop = (f"nothing helps: the best candidate, {closest.name}, changes the held-out "
                    f"error {_change(closest.cv_wrmse, current.cv_wrmse)} and BIC "
                    f"by {closest.delta_bic:+.1f} (needs <= -{settings.min_cv_gain:.0%} and "
                    f"<= -{settings.delta_bic:g})")
            if bounded:
                stop += (f"; {', '.join(bounded)} would explain the data only at the bound of "
                         "its parameter: the data ask for more than it can physically give, "
                         "so it is not an explanation")
            steps.append(Step(index=len(steps) + 1, added=None, candidates=cand_records,
                              reason=stop, bounded=bounded,
                              trend=most_followed(residual_trends(current.residual, covs,
                                                                  prob.w, settings))))
            break
        aliased = tuple(c.name for _, c in scored[1:]
                        if c.passed and abs(c.delta_bic - best.delta_bic) < settings.alias_bic)
        reason = (f"added {best.name}: held-out weighted RMS {current.cv_wrmse:.4g} -> "
                  f"{best.cv_wrmse:.4g}, BIC {best.delta_bic:+.1f}")
        group = None
        if aliased:
            reason += f"; the data cannot tell it from {', '.join(aliased)}"
            fits = {best.name: best_fit}
            fits.update((c.name, f) for f, c in scored[1:] if c.name in aliased)
            group = _group(prob, len(steps) + 1, fits)
        if bounded:
            reason += (f"; not added, at the bound of its parameter: {', '.join(bounded)}")
        current, removed = _prune(prob, best_fit, best.name, settings)
        if removed:
            reason += "; then removed " + ", ".join(removed) + " (no longer needed)"
        trend = most_followed(residual_trends(current.residual, covs, prob.w, settings))
        steps.append(Step(index=len(steps) + 1, added=best.name, candidates=cand_records,
                          reason=reason, aliased=aliased, removed=tuple(removed),
                          bounded=bounded, group=group, trend=trend))
        say(reason)
        if len(steps) >= STEPS_PER_CANDIDATE * len(cands):
            stop = "the selection keeps exchanging effects: stopped"
            break
    return current, tuple(steps), stop


def _change(new: float, old: float) -> str:
    """'by -12.3 %': the relative change of a held-out error; from 0 (the model already
    meets every held-out point) there is no relative change to give."""
    if old > 0:
        return f"by {100 * (new / old - 1):+.1f} %"
    return f"from 0 to {new:.4g}"


def _score(prob: Problem, current: Fit, pool, settings: Settings) -> list:
    """[(fit or None, Candidate)] of each candidate of ``pool`` fitted with the effects of
    ``current``, those that pass first, then by held-out error."""
    scored: list[tuple[Fit | None, Candidate]] = []
    for name in pool:
        try:
            f = prob.make_fit(current.effects + (name,), dict(current.values))
        except ToothfemError as exc:
            scored.append((None, Candidate(name=name, values=(), stderr=(), rmse=float("nan"),
                                           cv_wrmse=float("inf"), delta_bic=float("inf"),
                                           passed=False, note=f"failed: {exc}")))
            continue
        dbic = f.bic - current.bic
        gain = 1 - f.cv_wrmse / current.cv_wrmse if current.cv_wrmse > 0 else 0.0
        helps = dbic <= -settings.delta_bic and gain >= settings.min_cv_gain
        # an effect that helps only with a parameter at its physical bound is not an
        # explanation: the data ask for more than it can give
        bounded = helps and any(f.at_bound[name])
        note = ""
        if any(f.at_bound[name]):
            eff = prob.effects[name]
            note = "at its bound: " + ", ".join(
                f"{p.name} = {v:.4g} {p.unit} (bounds {p.lo:.4g} to {p.hi:.4g})"
                for p, v, b in zip(eff.parameters, f.values[name], f.at_bound[name]) if b)
        scored.append((f, Candidate(name=name, values=f.values[name], stderr=f.stderr[name],
                                    rmse=f.rmse, cv_wrmse=f.cv_wrmse, delta_bic=dbic,
                                    passed=helps and not bounded, bounded=bounded,
                                    note=note)))
    scored.sort(key=lambda fc: (not fc[1].passed, fc[1].cv_wrmse))
    if scored and scored[0][1].passed:
        # exact aliases (a drag on the input and the input meter's offset) tie up to the
        # fit's rounding: the one first in the catalog, the reducer's before the rig's, is
        # added; the step names the others
        top = scored[0][1].delta_bic
        order = list(prob.effects)
        first = min((fc for fc in scored
                     if fc[1].passed and abs(fc[1].delta_bic - top) <= TIE_BIC),
                    key=lambda fc: order.index(fc[1].name))
        scored.remove(first)
        scored.insert(0, first)
    return scored


def _prune(prob: Problem, fit: Fit, keep: str, settings: Settings):
    """Backward step: drop, one at a time, an effect (other than ``keep``, the one just
    added) whose removal costs less than :data:`PRUNE_FRACTION` of the entry threshold of
    BIC; an effect added early can be made redundant by later ones. Returns (fit, removed
    names)."""
    removed = []
    while len(fit.effects) >= 2:
        trials = []
        for name in fit.effects:
            if name == keep:
                continue
            rest = tuple(n for n in fit.effects if n != name)
            f = prob.make_fit(rest, {n: fit.values[n] for n in rest})
            trials.append((f.bic - fit.bic, name, f))
        if not trials:
            break
        cost, name, f = min(trials, key=lambda t: t[0])
        if cost >= PRUNE_FRACTION * settings.delta_bic:
            break
        removed.append(name)
        fit = f
    return fit, removed


def _effect_fit(eff, fit: Fit) -> EffectFit:
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
            x, _, _, _ = prob.fit((name,), tol=EXACT_TOL)
        except ToothfemError as exc:
            out.append(Closing(name=name, values=(), rmse=float("nan"), at_bound=False,
                               note=f"failed: {exc}"))
            continue
        params = prob.effects[name].parameters
        pred = prob.predict((name,), x)
        rmse = float(np.sqrt(np.mean((prob.eta - pred) ** 2)))
        bound = any(at_bound(v, p) for v, p in zip(x, params))
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
