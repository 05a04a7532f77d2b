"""Effects fitted to TE and hysteresis recordings by the measured-data loop's rules
(docs/te_rig.md, "The loop"): bounded least squares on the observations weighted by their
uncertainty, an effect added only where BIC falls by :attr:`Settings.delta_bic` and the
held-out error by :attr:`Settings.min_cv_gain`; candidates within :attr:`Settings.alias_bic`
of the added one, or whose fitted rows lie within :data:`ALIAS_SEPARATION` of its, are its
alias group (each with the measurement that tells it apart); an
effect that helps only at a bound of its parameter is not added.

The model is a callable: ``model(options) -> (N,) predictions`` on the observations' rows,
``options`` the effects' model options merged (:attr:`TeEffect.options`). The held-out error
is k-fold over the observations' groups (torque levels: a fold holds out whole torques), each
fold one bounded Gauss-Newton step from the all-data fit on its training rows (no model
evaluation: the Jacobian of the fit), as the efficiency loop's selection does.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from ....bars import bar
from ....errors import ToothfemError
from ..effect_base import Parameter
from ..fit import at_bound, fold_count
from ..settings import DEFAULT_SETTINGS

#: Relative finite-difference step of the Jacobian on parameters scaled by their typical
#: value (the system model is smooth in a play or an error of micrometres at this step).
FD_STEP = 1e-2
#: Tolerances of a fit (cost, step, gradient): the parameters' standard errors are percents.
FIT_TOL = 1e-4
#: Floor of the weighted residual sum of squares in BIC (an exact fit stays finite).
WRSS_FLOOR = 1e-300
#: Residual [sigma] of every row where the model does not settle: far worse than any fit.
FAILED_SIGMA = 30.0
#: Options equal to this many significant decimals (SI: 1e-15 m) are one model evaluation:
#: the fits of one step start from the same values and revisit them.
CACHE_DECIMALS = 15
#: Two candidates' fits whose rows differ by less than this [sigma, the weighted distance
#: D between their predictions] are aliases whatever their BIC: the noise makes BIC's
#: difference D^2 +- 2 D (for rows y = p_a + noise, |y - p_b|^2 - |y - p_a|^2 = D^2 +
#: 2 <p_a - p_b, noise>), so below D = 6 the other candidate can win by noise alone at
#: more than three standard deviations' chance (0.13 %), and the model's own error (its
#: sampling of the period) is not in the rows' sigma: a BIC margin there is no evidence.
#: (RV-40E's eccentric under crank 2, disc 1 with its phase turned mirrors crank 1, disc
#: 1's at D = 4.5 on the shipped recordings, and won there by BIC 8.9.)
ALIAS_SEPARATION = 6.0
#: Model evaluations kept (each an (N,) array of a few hundred rows).
CACHE_SIZE = 4096


@dataclass(frozen=True, kw_only=True)
class Observations:
    """What the recordings say, one row per observed figure: ``values`` in each row's unit,
    ``sigma`` one reading's standard uncertainty (same unit), ``group`` the fold group of the
    held-out error (the torque level), ``labels`` what each row is (its unit in the label),
    ``kinds`` the row's quantity (e.g. ``twist_arcmin``, ``order_39_arcsec``)."""
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
    """An effect of the TE/hysteresis loop: its parameters (bounds, starts, typical value)
    and ``options(values) -> dict`` of the model's options it sets; what it means, its source
    and the measurement that tells it apart from the others (``direct_test``)."""
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


@dataclass(frozen=True, kw_only=True)
class TeFit:
    """A set of effects fitted to every observation."""
    effects: tuple                     # names, in the order added
    values: dict                       # name -> tuple of values
    stderr: dict                       # name -> tuple of standard errors (nan: not defined)
    at_bound: dict                     # name -> tuple of bool
    prediction: np.ndarray             # (N,)
    residual: np.ndarray               # (N,) measured - model, in the rows' units
    wrss: float
    bic: float
    cv_wrmse: float                    # held-out RMS of the weighted residual [sigma]
    cv_residual: np.ndarray            # (N,) held-out residual of each row, weighted
    nfev: int = 0

    @property
    def wrmse(self) -> float:
        """RMS of the weighted residual on every row [sigma]."""
        return float(math.sqrt(self.wrss / max(len(self.residual), 1)))


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
    baseline: TeFit
    final: TeFit
    steps: tuple
    added: tuple                       # names
    alias_groups: dict                 # added name -> tuple of aliased names
    stop_reason: str
    observations: Observations
    catalog: dict = field(default_factory=dict)      # name -> TeEffect
    failures: tuple = ()               # where the model did not settle, one line each
    evaluations: int = 0

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
        def fit(f: TeFit):
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


class TeProblem:
    """Observations, a model and a catalog: fits and held-out errors.

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
        self.model = model
        self.catalog = {e.name: e for e in catalog}
        self.settings = settings
        self.weight = 1.0 / np.asarray(observations.sigma, float)
        groups = np.unique(observations.group)
        k = fold_count(len(groups), settings)
        rng = np.random.default_rng(settings.seed)
        self.fold_of_group = dict(zip(groups, rng.permutation(len(groups)) % k))
        self.folds = np.array([self.fold_of_group[g] for g in observations.group])
        self.k = k
        self.evaluations = 0
        self.failures: list = []        # the model's failures, one line each
        self._cache: dict = {}

    def predict(self, names, values) -> np.ndarray:
        """The model's prediction with the effects ``names`` at ``values``.

        Parameters
        ----------
        names : sequence of str
        values : sequence of sequence of float

        Returns
        -------
        numpy.ndarray, (N,)
        """
        options: dict = {}
        for n, v in zip(names, values):
            options.update(self.catalog[n].model_options(v))
        key = tuple(sorted((k, round(float(v), CACHE_DECIMALS)) for k, v in options.items()))
        if key in self._cache:
            return self._cache[key]
        out = self._evaluate(options)
        if len(self._cache) >= CACHE_SIZE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = out
        return out

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

    def fit(self, names, start: dict | None = None, free=None) -> TeFit:
        """Fit the effects ``names`` to every row (bounded least squares, each parameter
        scaled by its typical value, from each start the parameters list).

        Parameters
        ----------
        names : sequence of str
        start : dict, optional
            name -> values to start from (a previous fit's); the others start at their
            parameters' ``starts``.
        free : collection of str, optional
            The effects whose parameters vary (default all); the others stay at ``start``
            (a candidate scored against the effects already fitted: one fit of its own
            parameters, the joint refit kept for the one added). BIC counts every
            parameter.

        Returns
        -------
        TeFit
        """
        from scipy.optimize import least_squares

        names = tuple(names)
        params = [p for n in names for p in self.catalog[n].parameters]
        y, w = self.obs.values, self.weight
        if not params:
            pred = self.predict((), ())
            return self._scored(names, {}, pred, np.zeros((len(y), 0)), (), 0)
        start = start or {}
        free = set(names if free is None else free)
        typical = np.array([p.typical for p in params])
        lo = np.array([p.lo for p in params]) / typical
        hi = np.array([p.hi for p in params]) / typical
        sizes = [len(self.catalog[n].parameters) for n in names]
        moving = np.concatenate([np.full(k, n in free) for n, k in zip(names, sizes)])
        full = np.concatenate([np.asarray(start[n], float) if n in start else
                               np.array([p.starts[0] for p in self.catalog[n].parameters])
                               for n in names]) / typical

        def split(x):
            z = full.copy()
            z[moving] = x
            vals, i = [], 0
            for k in sizes:
                vals.append(tuple(z[i:i + k] * typical[i:i + k]))
                i += k
            return vals

        def residual(x):
            return (y - self.predict(names, split(x))) * w

        lo_f, hi_f = lo[moving], hi[moving]
        starts = [full[moving]]
        for j, p in enumerate(np.array(params, dtype=object)[moving]):
            for s0 in p.starts[1:]:              # each parameter's other starts, the rest kept
                x = starts[0].copy()
                x[j] = s0 / typical[moving][j]
                starts.append(x)
        best, nfev = None, 0
        for x0 in starts:       # the other starts only while the best ends at a bound
            if best is not None and not _at_any_bound(best.x, lo_f, hi_f):
                break
            r = least_squares(residual, np.clip(x0, lo_f, hi_f), bounds=(lo_f, hi_f),
                              method="trf", diff_step=FD_STEP, ftol=FIT_TOL, xtol=FIT_TOL,
                              gtol=FIT_TOL, max_nfev=self.settings.max_nfev)
            nfev += r.nfev
            if best is None or r.cost < best.cost:
                best = r
        if best is None:        # starts holds the start point at least
            raise RuntimeError(f"fit of {names}: no least-squares start was run")
        values = dict(zip(names, split(best.x)))
        pred = y - best.fun / w
        jac = np.zeros((len(y), len(params)))
        jac[:, moving] = best.jac * (1.0 / typical[moving])   # d(weighted residual)/d(value)
        return self._scored(names, values, pred, jac, params, nfev)

    def _scored(self, names, values, pred, jac, params, nfev) -> TeFit:
        """The fit's BIC, standard errors, bounds and held-out error."""
        y, w = self.obs.values, self.weight
        r = y - pred
        wr = r * w
        n, k = len(y), len(params)
        wrss = float(wr @ wr)
        bic = n * math.log(max(wrss, WRSS_FLOOR) / n) + k * math.log(n)
        stderr, bound = {}, {}
        cov = None
        if k:
            jtj = jac.T @ jac
            s2 = wrss / max(n - k, 1)
            try:
                cov = np.linalg.inv(jtj) * s2
            except np.linalg.LinAlgError:
                cov = None
        i = 0
        for name in names:
            ps = self.catalog[name].parameters
            vals = values[name]
            stderr[name] = tuple(float(math.sqrt(cov[i + j, i + j])) if cov is not None and
                                 cov[i + j, i + j] >= 0 else float("nan")
                                 for j in range(len(ps)))
            bound[name] = tuple(at_bound(v, p) for v, p in zip(vals, ps))
            i += len(ps)
        cv = self._held_out(wr, jac, params, values, names)
        return TeFit(effects=names, values=values, stderr=stderr, at_bound=bound,
                     prediction=pred, residual=r, wrss=wrss, bic=bic,
                     cv_wrmse=float(np.sqrt(np.mean(cv ** 2))), cv_residual=cv, nfev=nfev)

    def separation(self, a: TeFit, b: TeFit) -> float:
        """The weighted distance between two fits' rows [sigma]: how far apart the data
        could tell them (ALIAS_SEPARATION).

        Parameters
        ----------
        a, b : TeFit

        Returns
        -------
        float
        """
        return float(np.linalg.norm((a.prediction - b.prediction) * self.weight))

    def _held_out(self, wr, jac, params, values, names) -> np.ndarray:
        """Each row's weighted residual when its fold is held out: one bounded
        Gauss-Newton step from the all-data fit on the training rows (the rows' residuals
        change by -J delta)."""
        from scipy.optimize import lsq_linear

        if not params:
            return wr.copy()
        x = np.array([v for n in names for v in values[n]])
        lo = np.array([p.lo for p in params]) - x
        hi = np.array([p.hi for p in params]) - x + 1e-15
        out = np.empty_like(wr)
        for f in range(self.k):
            held = self.folds == f
            train = ~held
            # the training rows' optimum, linearised: min |r_t + J_t d| within the bounds;
            # the held-out rows' residuals move with it by J_h d
            step = lsq_linear(jac[train], -wr[train], bounds=(lo, hi)).x if train.any() \
                else np.zeros(len(x))
            out[held] = wr[held] + jac[held] @ step
        return out

    def run(self, candidates=None, progress: bool = False) -> TeLoop:
        """Forward selection by the loop's rules.

        Parameters
        ----------
        candidates : sequence of str, optional
            Names from the catalog (default all).
        progress : bool
            A bar over each step's candidates, the model evaluations so far beside it.

        Returns
        -------
        TeLoop
        """
        s = self.settings
        pool = list(candidates or self.catalog)
        base = self.fit(())
        current = base
        steps: list[TeStep] = []
        groups: dict[str, tuple[str, ...]] = {}
        stop = "no candidate left"
        excluded: set = set()
        while len(current.effects) < s.max_effects:
            scored = []
            todo = [n for n in pool if n not in current.effects and n not in excluded]
            with bar(total=len(todo), desc=f"TE loop step {len(steps) + 1}",
                     unit="candidate", enabled=progress) as shown:
                for name in todo:
                    f = self.fit(current.effects + (name,), start=current.values,
                                 free=(name,))
                    scored.append((name, f))
                    shown.update(1)
                    shown.set_postfix_str(f"{self.evaluations} model evaluations")
            if not scored:
                stop = "every candidate tried"
                break
            scored.sort(key=lambda nf: nf[1].bic)      # ties keep the catalog's order
            table = tuple((n, f.bic, f.cv_wrmse, f.values[n], any(f.at_bound[n]))
                          for n, f in scored)

            def gains(f, ref=current):      # against this step's fit
                cv = 1 - f.cv_wrmse / ref.cv_wrmse if ref.cv_wrmse > 0 else 0.0
                return ref.bic - f.bic, cv

            helps = [(n, f) for n, f in scored
                     if gains(f)[0] >= s.delta_bic and gains(f)[1] >= s.min_cv_gain]
            bounded = tuple(n for n, f in helps if any(f.at_bound[n]))
            usable = [(n, f) for n, f in helps if not any(f.at_bound[n])]
            if not usable:
                if bounded:
                    stop = ("every candidate that would help does so only at a bound of its "
                            "parameter: the data ask for more than it can physically give")
                else:
                    name, best = scored[0]
                    gain_bic, gain_cv = gains(best)
                    stop = (f"the best candidate, {name}, lowers BIC by {gain_bic:.3g} (needs "
                            f"{s.delta_bic:g}) and the held-out error by "
                            f"{100 * gain_cv:.3g} % (needs {100 * s.min_cv_gain:g} %)")
                steps.append(TeStep(index=len(steps) + 1, scored=table, added=None,
                                    reason=stop, bounded=bounded))
                break
            name, best = usable[0]
            if current.effects:     # the one added: every parameter refitted together
                joint = self.fit(best.effects, start=best.values)
                if joint.bic <= best.bic:
                    best = joint
            gain_bic, gain_cv = gains(best)
            aliased = tuple(n for n, f in scored if n != name and not any(f.at_bound[n])
                            and (f.bic - best.bic < s.alias_bic
                                 or self.separation(f, best) < ALIAS_SEPARATION))
            groups[name] = aliased
            steps.append(TeStep(index=len(steps) + 1, scored=table, added=name,
                                reason=f"BIC -{gain_bic:.3g}, held-out error "
                                       f"-{100 * gain_cv:.3g} %",
                                aliased=aliased, bounded=bounded))
            excluded.update(aliased)             # its aliases are not added after it
            current = best
        else:
            stop = f"{s.max_effects} effects: the most the loop adds"
        return TeLoop(baseline=base, final=current, steps=tuple(steps),
                      added=current.effects, alias_groups=groups, stop_reason=stop,
                      observations=self.obs, catalog=self.catalog,
                      failures=tuple(self.failures), evaluations=self.evaluations)


def _at_any_bound(x, lo, hi) -> bool:
    """Whether a scaled parameter vector touches a bound (within 1e-4 of its scale, 1)."""
    return bool(np.any(x <= lo + 1e-4) or np.any(x >= hi - 1e-4))


def parameter(name: str, unit: str, lo: float, hi: float, typical: float, starts=None,
              doc: str = "") -> Parameter:
    """A fitted parameter of a TE effect (the efficiency loop's record).

    Parameters
    ----------
    name, unit : str
    lo, hi : float
        Physical bounds, in ``unit``.
    typical : float
        The fit's scale.
    starts : sequence of float, optional
        Starting values (default the typical value).
    doc : str

    Returns
    -------
    Parameter
    """
    return Parameter(name=name, unit=unit, lo=lo, hi=hi, typical=typical,
                     starts=tuple(starts or (typical,)), doc=doc)
