"""Close the loop with measured data: residuals, effect selection, report.

``run_loop(case, data)`` compares the model with measured efficiencies, and adds physical
effects from the catalog (efficiency/effects.py) one at a time while they help:

1. Residual r = eta_measured - eta_model at every point, weighted by 1/sigma where the data
   give an uncertainty (the rig's torque sensors), else unweighted.
2. Residual analysis (:func:`residual_trends`): for every covariate in the data (input speed,
   output torque, oil temperature, time, run, any further numeric column) the fraction R^2
   of the residual's variance that a smooth function of that covariate explains (a cubic
   in the covariate, or one mean per level when it has few values), with the F-test
   p-value; and for every candidate effect the correlation of the residual with its
   signature, the change of the efficiency a small step of its parameter makes
   (:func:`signatures`).
3. Selection, forward: every applicable candidate not declared by the case is fitted
   together with the effects already added (bounded least squares,
   ``scipy.optimize.least_squares``, several starting values), scored by its k-fold held-out
   error and by BIC; the candidate with the lowest held-out error among those that lower
   BIC by at least :attr:`Settings.delta_bic` and the held-out error by at least
   :attr:`Settings.min_cv_gain` is added; then any earlier effect whose removal now costs
   less than half that BIC threshold is dropped again (a backward step: an effect taken on
   the way can be made redundant by a later one); repeat. Candidates within
   :attr:`Settings.alias_bic` of the added one are named as aliases: the data cannot tell
   them apart. When none passes, the loop stops and says which came closest and by how much
   it fell short.
4. After the last effect, a residual that still follows a covariate (p below
   ``alpha_trend`` / number of covariates and R^2 >= ``r2_trend``) is reported as
   unexplained, with that covariate.

Effects whose loss is proportional to their parameter (drag, bearing and output-pin friction,
churning) are evaluated once at a reference value and scaled (effects.predict's cache), so
fitting them costs almost no model evaluations.

During selection the held-out error of a candidate is computed by one bounded Gauss-Newton
step from its all-data fit for each fold (exact for a loss linear in the parameter, which
drag, churning, bearing and output-pin friction are, and close for the others); the held-out
errors reported before and after are from full refits on each fold's training points.

With fewer than :attr:`Settings.min_points` points there is no held-out error to select on:
the loop then reports the baseline error and, for each candidate, the parameter value that
would bring the model onto the data (:attr:`LoopReport.closing`) with whether that value is
inside the effect's physical bounds: what such data can and cannot support.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...errors import ToothfemError
from . import effects as fx


@dataclass(frozen=True)
class Settings:
    """Thresholds of the selection and of the residual analysis (why each, in the doc)."""
    folds: int = 5                 # k of the k-fold held-out error
    delta_bic: float = 10.0        # BIC decrease an effect must bring ('very strong',
                                   # Kass & Raftery 1995)
    min_cv_gain: float = 0.02      # and at least this relative cut of the held-out error
    max_effects: int = 4           # never more effects than this
    min_points: int = 8            # below: no selection (no held-out error to speak of)
    alpha_trend: float = 1e-3      # family-wise level of 'the residual follows x'
    r2_trend: float = 0.05         # and at least this share of the residual variance
    max_levels: int = 6            # a covariate with at most this many values: one mean each
    degree: int = 3                # polynomial degree of a covariate's smooth trend
    alias_bic: float = 2.0         # candidates within this BIC of the chosen one: aliased
    seed: int = 0                  # fold assignment
    max_nfev: int = 60             # function evaluations per least-squares fit


# ---------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True)
class Fit:
    """A fitted set of effects on all points."""
    effects: tuple                 # effect names, in the order added
    values: dict                   # name -> tuple of parameter values
    stderr: dict                   # name -> tuple of standard errors (nan if not defined)
    at_bound: dict                 # name -> tuple of bool
    prediction: np.ndarray         # (M,) efficiency
    residual: np.ndarray           # (M,) measured - predicted
    n_params: int
    wrss: float                    # weighted residual sum of squares
    bic: float
    aic: float
    cv_wrmse: float                # held-out weighted RMS (selection's estimate)
    nfev: int = 0

    @property
    def rmse(self) -> float:
        return float(np.sqrt(np.mean(self.residual ** 2)))


@dataclass(frozen=True)
class HeldOut:
    """Errors on held-out points (k-fold refits), efficiency as a fraction."""
    rmse: float
    max_abs: float
    wrmse: float
    residual: np.ndarray           # (M,) held-out residual of each point
    folds: int


@dataclass(frozen=True)
class Trend:
    """How strongly the residual follows one covariate."""
    covariate: str
    kind: str                      # "numeric" (polynomial) or "levels" (one mean per value)
    r2: float                      # share of the residual variance explained
    p_value: float
    amplitude: float               # range of the fitted trend over the data [efficiency]
    follows: bool


@dataclass(frozen=True)
class Candidate:
    """One candidate's score at one selection step."""
    name: str
    values: tuple
    stderr: tuple
    rmse: float
    cv_wrmse: float
    delta_bic: float
    passed: bool
    note: str = ""


@dataclass(frozen=True)
class Step:
    index: int
    added: str | None
    candidates: tuple              # Candidate, best first
    reason: str
    aliased: tuple = ()            # names as good as the added one (BIC within alias_bic)
    removed: tuple = ()            # names dropped again after this addition


@dataclass(frozen=True)
class EffectFit:
    """An effect the loop added, with its fitted parameters."""
    name: str
    parameters: dict               # name -> {"value", "stderr", "unit", "at_bound", "bounds"}
    case_fields: tuple
    citation: str
    equation: str


@dataclass(frozen=True)
class Closing:
    """Small data: the parameter value that brings the model onto the data."""
    name: str
    values: tuple
    rmse: float
    at_bound: bool
    note: str


@dataclass(frozen=True)
class LoopReport:
    case_name: str
    data_source: str
    n_points: int
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

    def to_dict(self) -> dict:
        """The JSON of the report (report.json)."""
        def held(h: HeldOut, fit: Fit):
            return {"rmse": h.rmse, "max_abs_error": h.max_abs, "weighted_rmse": h.wrmse,
                    "folds": h.folds, "fit_rmse": fit.rmse, "bic": fit.bic,
                    "mean_residual": float(np.mean(fit.residual))}

        def trend(t: Trend):
            return {"covariate": t.covariate, "kind": t.kind, "r2": t.r2,
                    "p_value": t.p_value, "amplitude": t.amplitude, "follows": t.follows}

        return _jsonable({
            "case": self.case_name, "data": self.data_source, "n_points": self.n_points,
            "weighted": self.weighted, "selection": self.selection,
            "baseline": held(self.baseline, self.baseline_fit),
            "final": held(self.final, self.final_fit),
            "effects": [{"name": e.name, "parameters": e.parameters,
                         "case_fields": list(e.case_fields), "citation": e.citation,
                         "equation": e.equation} for e in self.effects],
            "unexplained": list(self.unexplained),
            "stop_reason": self.stop_reason,
            "steps": [{"index": s.index, "added": s.added, "reason": s.reason,
                       "aliased": list(s.aliased), "removed": list(s.removed),
                       "candidates": [{"name": c.name, "values": list(c.values),
                                       "stderr": list(c.stderr), "rmse": c.rmse,
                                       "cv_weighted_rmse": c.cv_wrmse,
                                       "delta_bic": c.delta_bic, "passed": c.passed,
                                       "note": c.note} for c in s.candidates]}
                      for s in self.steps],
            "trends_before": [trend(t) for t in self.trends_before],
            "trends_after": [trend(t) for t in self.trends_after],
            "signatures": self.signatures, "skipped": self.skipped,
            "closing": [{"name": c.name, "values": list(c.values), "rmse": c.rmse,
                         "at_bound": c.at_bound, "note": c.note} for c in self.closing],
            "rejected_rows": [str(r) for r in self.rejected_rows],
            "provenance": self.provenance,
            "elapsed_s": self.elapsed_s, "model_evaluations": self.evaluations,
        })


def _jsonable(x):
    """Plain JSON types; NaN and infinities as None (strict JSON has no NaN)."""
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_jsonable(v) for v in x.tolist()]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x


# ---------------------------------------------------------------------------------------
# The fitting problem

#: Relative finite-difference step of the Jacobian, on parameters scaled by their typical
#: value (the model is smooth there; the clearance tables are PCHIP-interpolated).
FD_STEP = 1e-3
#: Tolerances of the least-squares fit (cost, step, gradient).
FIT_TOL = 1e-10


class _Problem:
    """Measured efficiencies, the case and the catalog: predictions, fits, held-out errors."""

    def __init__(self, case, data, effects, settings, loads):
        self.case = case
        self.data = data
        self.settings = settings
        self.loads = loads
        self.points = fx.Points.of(data)
        self.eta = np.asarray(data.efficiency, float)
        self.n = self.eta.size
        if data.sigma is not None and np.all(np.isfinite(data.sigma)) and np.all(data.sigma > 0):
            w = 1.0 / np.asarray(data.sigma, float)
            self.w = w / np.sqrt(np.mean(w ** 2))       # relative weights, mean square 1
            self.weighted = True
        else:
            self.w = np.ones(self.n)
            self.weighted = False
        self.effects = {e.name: e for e in effects}
        self.prepared = {}
        self.evaluations = 0
        self._cache = {}            # (names, values) -> efficiency
        self._evals = {}            # model evaluations (effects.predict's cache)
        folds = max(2, min(settings.folds, self.n))
        perm = np.random.default_rng(settings.seed).permutation(self.n)
        self.fold = np.empty(self.n, int)
        self.fold[perm] = np.arange(self.n) % folds
        self.n_folds = folds

    # -- predictions
    def predict(self, names, values_flat) -> np.ndarray:
        key = (tuple(names), tuple(np.round(values_flat, 12)))
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        assignment, k = {}, 0
        for name in names:
            eff = self.effects[name]
            m = len(eff.parameters)
            assignment[eff] = tuple(values_flat[k:k + m])
            k += m
            if eff.route(self.case) == "loss" and eff.prepare is not None \
                    and name not in self.prepared:
                self.prepared[name] = eff.prepare(self.case, self.points)
        before = len(self._evals)
        eta = fx.predict(self.case, self.points, assignment, self.prepared,
                         loads=self.loads, cache=self._evals).efficiency
        self.evaluations += len(self._evals) - before
        if len(self._cache) > 4096:
            self._cache.clear()
        if len(self._evals) > 512:
            self._evals.clear()
        self._cache[key] = eta
        return eta

    def params(self, names):
        return [p for name in names for p in self.effects[name].parameters]

    # -- scores
    def bic(self, wrss, k):
        n = self.n
        return n * math.log(max(wrss, 1e-300) / n) + k * math.log(n)

    def aic(self, wrss, k):
        return self.n * math.log(max(wrss, 1e-300) / self.n) + 2 * k

    # -- fit
    def fit(self, names, start=None, train=None, max_nfev=None) -> tuple:
        """Bounded least squares of the effects ``names`` (start: {name: values}); returns
        (values_flat, jacobian in scaled units, weighted residual, nfev)."""
        from scipy.optimize import least_squares

        params = self.params(names)
        if not params:
            r = self.w * (self.eta - self.predict((), np.zeros(0)))
            return np.zeros(0), np.zeros((self.n, 0)), r, 0
        typ = np.array([p.typical for p in params])
        lo = np.array([p.lo for p in params]) / typ
        hi = np.array([p.hi for p in params]) / typ
        mask = np.ones(self.n, bool) if train is None else train
        start = start or {}

        def fun(u):
            return (self.w * (self.eta - self.predict(names, u * typ)))[mask]

        x0 = self._start(names, start, fun, typ)
        res = least_squares(fun, np.clip(x0 / typ, lo, hi), bounds=(lo, hi), method="trf",
                            diff_step=FD_STEP, x_scale=1.0, ftol=FIT_TOL, xtol=FIT_TOL,
                            gtol=FIT_TOL, max_nfev=max_nfev or self.settings.max_nfev)
        return res.x * typ, res.jac, res.fun, res.nfev

    def _start(self, names, start, fun, typ):
        """Starting values: given ones, else the best of each new effect's ``starts``."""
        x0 = []
        for name in names:
            eff = self.effects[name]
            if name in start:
                x0.extend(start[name])
            else:
                x0.extend(p.starts[0] for p in eff.parameters)
        x0 = np.array(x0, float)
        k = 0
        for name in names:
            eff = self.effects[name]
            m = len(eff.parameters)
            if name not in start:
                for j, p in enumerate(eff.parameters):
                    best, best_cost = x0[k + j], None
                    for s in p.starts:
                        trial = x0.copy()
                        trial[k + j] = s
                        cost = float(np.sum(fun(trial / typ) ** 2))
                        if best_cost is None or cost < best_cost:
                            best, best_cost = s, cost
                    x0[k + j] = best
            k += m
        return x0

    def make_fit(self, names, start=None) -> Fit:
        names = tuple(names)
        x, jac, r, nfev = self.fit(names, start)
        params = self.params(names)
        k = len(params)
        wrss = float(np.sum(r ** 2))
        pred = self.predict(names, x)
        values, stderr, at_bound, i = {}, {}, {}, 0
        se = self._stderr(jac, wrss, k, params)
        for name in names:
            m = len(self.effects[name].parameters)
            values[name] = tuple(float(v) for v in x[i:i + m])
            stderr[name] = tuple(float(s) for s in se[i:i + m])
            at_bound[name] = tuple(bool(_at_bound(v, p)) for v, p in
                                   zip(x[i:i + m], params[i:i + m]))
            i += m
        cv = self.linear_cv(x, jac, r, params)
        return Fit(names, values, stderr, at_bound, pred, self.eta - pred, k, wrss,
                   self.bic(wrss, k), self.aic(wrss, k), cv, nfev)

    def _stderr(self, jac, wrss, k, params):
        if k == 0:
            return np.zeros(0)
        dof = self.n - k
        if dof <= 0:
            return np.full(k, np.nan)
        typ = np.array([p.typical for p in params])
        jtj = jac.T @ jac
        try:
            cov = np.linalg.inv(jtj) * (wrss / dof)
        except np.linalg.LinAlgError:
            return np.full(k, np.nan)
        d = np.diag(cov)
        return np.where(d >= 0, np.sqrt(np.abs(d)), np.nan) * typ

    def linear_cv(self, x, jac, r, params) -> float:
        """Held-out weighted RMS by one bounded Gauss-Newton step per fold from the
        all-data fit (module docstring)."""
        from scipy.optimize import lsq_linear

        if not params:
            return float(np.sqrt(np.mean(r ** 2)))
        typ = np.array([p.typical for p in params])
        u = x / typ
        lo = np.array([p.lo for p in params]) / typ - u
        hi = np.array([p.hi for p in params]) / typ - u
        lo, hi = np.minimum(lo, 0.0), np.maximum(hi, 0.0)
        out = np.empty(self.n)
        for f in range(self.n_folds):
            test = self.fold == f
            train = ~test
            # fun = w (eta - pred); fun(u + d) ~ r + J d; minimise over the training points
            sol = lsq_linear(jac[train], -r[train], bounds=(lo, hi + 1e-15))
            out[test] = r[test] + jac[test] @ sol.x
        return float(np.sqrt(np.mean(out ** 2)))

    def held_out(self, fit: Fit) -> HeldOut:
        """k-fold held-out errors with full refits from the all-data values."""
        if fit.n_params == 0:
            r = fit.residual
        else:
            r = np.empty(self.n)
            start = dict(fit.values)
            for f in range(self.n_folds):
                test = self.fold == f
                x, _, _, _ = self.fit(fit.effects, start, train=~test)
                r[test] = (self.eta - self.predict(fit.effects, x))[test]
        return HeldOut(float(np.sqrt(np.mean(r ** 2))), float(np.max(np.abs(r))),
                       float(np.sqrt(np.mean((self.w * r) ** 2))), r,
                       self.n_folds if fit.n_params else 0)


#: A fitted value within this fraction of its parameter's typical value of a bound is at it.
AT_BOUND_REL = 1e-4


def _at_bound(v, p):
    tol = AT_BOUND_REL * p.typical
    return v <= p.lo + tol or v >= p.hi - tol


# ---------------------------------------------------------------------------------------
# Residual analysis


def _basis(x, settings):
    """(kind, (M, q) design without intercept) of a covariate, or None if constant."""
    x = np.asarray(x)
    if x.dtype == object or x.dtype.kind in "US":
        levels = np.unique(x.astype(str))
        kind = "levels"
        xs = x.astype(str)
    else:
        x = x.astype(float)
        levels = np.unique(x)
        kind = "levels" if levels.size <= settings.max_levels else "numeric"
        xs = x
    if levels.size < 2:
        return None
    if kind == "levels":
        return kind, np.stack([(xs == lv).astype(float) for lv in levels[1:]], axis=1)
    z = (x - x.min()) / np.ptp(x) * 2 - 1
    deg = min(settings.degree, levels.size - 1)
    return kind, np.polynomial.legendre.legvander(z, deg)[:, 1:]


def residual_trends(residual, covariates: dict, weights=None, settings=Settings()) -> tuple:
    """For each covariate: the share R^2 of the (weighted) residual variance a smooth
    function of it explains, the F-test p-value against a constant, the range of the
    fitted trend, and whether the residual follows it (p < alpha_trend / number of
    covariates and R^2 >= r2_trend). ``covariates``: name -> (M,) array."""
    from scipy.stats import f as f_dist

    r = np.asarray(residual, float)
    n = r.size
    w = np.ones(n) if weights is None else np.asarray(weights, float)
    out = []
    usable = {k: v for k, v in covariates.items() if _basis(v, settings) is not None}
    alpha = settings.alpha_trend / max(len(usable), 1)
    for name, x in usable.items():
        kind, b = _basis(x, settings)
        q = b.shape[1]
        dof = n - q - 1
        if dof < 3:
            out.append(Trend(name, kind, float("nan"), float("nan"), float("nan"), False))
            continue
        a = np.column_stack([np.ones(n), b]) * w[:, None]
        coef, *_ = np.linalg.lstsq(a, w * r, rcond=None)
        fitted = np.column_stack([np.ones(n), b]) @ coef
        rss1 = float(np.sum((w * (r - fitted)) ** 2))
        mean_w = np.sum(w ** 2 * r) / np.sum(w ** 2)
        rss0 = float(np.sum((w * (r - mean_w)) ** 2))
        if rss0 <= 0:
            out.append(Trend(name, kind, 0.0, 1.0, 0.0, False))
            continue
        r2 = max(0.0, 1.0 - rss1 / rss0)
        fstat = ((rss0 - rss1) / q) / (rss1 / dof) if rss1 > 0 else np.inf
        p = float(f_dist.sf(fstat, q, dof))
        amp = float(np.ptp(fitted))
        follows = bool(p < alpha and r2 >= settings.r2_trend)
        out.append(Trend(name, kind, float(r2), p, amp, follows))
    return tuple(out)


def signatures(problem: _Problem, fit: Fit, names) -> dict:
    """Correlation of the residual with each candidate's signature: the change of the
    efficiency from a step of one typical value in its parameter(s) (weighted)."""
    out = {}
    base = fit.prediction
    cur = dict(fit.values)
    for name in names:
        eff = problem.effects[name]
        step = tuple(min(p.hi, max(p.lo, p.starts[0] + p.typical)) for p in eff.parameters)
        names2 = fit.effects + (name,)
        flat = np.concatenate([np.asarray(cur[n], float) for n in fit.effects]
                              + [np.asarray(step, float)]) if fit.effects else np.asarray(step)
        try:
            s = problem.predict(names2, flat) - base
        except ToothfemError:
            continue
        w = problem.w
        a, b = w * (fit.residual - np.average(fit.residual, weights=w ** 2)), \
            w * (s - np.average(s, weights=w ** 2))
        den = math.sqrt(float(np.sum(a ** 2) * np.sum(b ** 2)))
        out[name] = float(np.sum(a * b) / den) if den > 0 else 0.0
    return out


# ---------------------------------------------------------------------------------------
# The loop


def candidates_of(case, points, effects):
    """(candidate names, {name: why skipped}) for a case and its data."""
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


def run_loop(case, data, effects=None, *, settings=Settings(), loads="analytic",
             progress=None) -> LoopReport:
    """The measured-data loop on ``case`` and ``data`` (a MeasuredData); module docstring.
    ``effects``: the catalog to draw from (default :func:`effects.catalog`);
    ``progress``: optional callable(str) told of each step."""
    t0 = time.perf_counter()
    effects = tuple(effects or fx.catalog())
    say = progress or (lambda msg: None)
    prob = _Problem(case, data, effects, settings, loads)
    cands, skipped = candidates_of(case, prob.points, effects)
    covs = data.covariates()
    base = prob.make_fit(())
    baseline = prob.held_out(base)
    trends_before = residual_trends(base.residual, covs, prob.w, settings)
    sig = signatures(prob, base, cands)
    say(f"baseline: RMSE {100 * base.rmse:.3f} points on {prob.n} points")
    if prob.n < settings.min_points:
        closing = _closing(prob, cands)
        stop = (f"{prob.n} point(s): fewer than {settings.min_points}, so no held-out error "
                "can be formed and no effect is selected; 'closing' lists the parameter "
                "each candidate would need to meet the data")
        return LoopReport(case.name, data.source, prob.n, prob.weighted, baseline, baseline,
                          base, base, (), (), trends_before, trends_before, sig, skipped, (),
                          stop, closing, False, tuple(data.rejected), dict(data.provenance),
                          covs, prob.eta, data.sigma, time.perf_counter() - t0,
                          prob.evaluations)
    current = base
    steps = []
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
        scored = []
        for name in pool:
            try:
                f = prob.make_fit(current.effects + (name,), dict(current.values))
            except ToothfemError as exc:
                scored.append((None, Candidate(name, (), (), float("nan"), float("inf"),
                                               float("inf"), False, f"failed: {exc}")))
                continue
            dbic = f.bic - current.bic
            gain = 1 - f.cv_wrmse / current.cv_wrmse if current.cv_wrmse > 0 else 0.0
            ok = dbic <= -settings.delta_bic and gain >= settings.min_cv_gain
            note = ""
            if any(f.at_bound[name]):
                note = "parameter at its bound"
            scored.append((f, Candidate(name, f.values[name], f.stderr[name], f.rmse,
                                        f.cv_wrmse, dbic, ok, note)))
        scored.sort(key=lambda fc: (not fc[1].passed, fc[1].cv_wrmse))
        best_fit, best = scored[0]
        cand_records = tuple(c for _, c in scored)
        if not best.passed:
            closest = min((c for _, c in scored), key=lambda c: c.cv_wrmse)
            stop = (f"nothing helps: the best candidate, {closest.name}, changes the held-out "
                    f"error by {100 * (closest.cv_wrmse / current.cv_wrmse - 1):+.1f} % and BIC "
                    f"by {closest.delta_bic:+.1f} (needs <= -{settings.min_cv_gain:.0%} and "
                    f"<= -{settings.delta_bic:g})")
            steps.append(Step(len(steps) + 1, None, cand_records, stop))
            break
        aliased = tuple(c.name for _, c in scored[1:]
                        if c.passed and abs(c.delta_bic - best.delta_bic) < settings.alias_bic)
        reason = (f"added {best.name}: held-out weighted RMS {current.cv_wrmse:.4g} -> "
                  f"{best.cv_wrmse:.4g}, BIC {best.delta_bic:+.1f}")
        if aliased:
            reason += f"; the data cannot tell it from {', '.join(aliased)}"
        current, removed = _prune(prob, best_fit, best.name, settings)
        if removed:
            reason += "; then removed " + ", ".join(removed) + " (no longer needed)"
        steps.append(Step(len(steps) + 1, best.name, cand_records, reason, aliased,
                          tuple(removed)))
        say(reason)
        if len(steps) >= 2 * len(cands):
            stop = "the selection keeps exchanging effects: stopped"
            break
    final = prob.held_out(current)
    covs_after = residual_trends(current.residual, covs, prob.w, settings)
    unexplained = tuple(t.covariate for t in covs_after if t.follows)
    effect_fits = tuple(_effect_fit(prob.effects[n], current) for n in current.effects)
    return LoopReport(case.name, data.source, prob.n, prob.weighted, baseline, final, base,
                      current, effect_fits, tuple(steps), trends_before, covs_after, sig,
                      skipped, unexplained, stop, (), True, tuple(data.rejected),
                      dict(data.provenance), covs, prob.eta, data.sigma,
                      time.perf_counter() - t0, prob.evaluations)


def _prune(prob: _Problem, fit: Fit, keep: str, settings: Settings):
    """Backward step: drop, one at a time, an effect (other than ``keep``, the one just
    added) whose removal costs less than half the entry threshold of BIC; an effect added
    early can be made redundant by later ones. Returns (fit, removed names)."""
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
        if cost >= settings.delta_bic / 2:
            break
        removed.append(name)
        fit = f
    return fit, removed


def _effect_fit(eff, fit: Fit) -> EffectFit:
    params = {}
    for p, v, s, b in zip(eff.parameters, fit.values[eff.name], fit.stderr[eff.name],
                          fit.at_bound[eff.name]):
        params[p.name] = {"value": v, "stderr": s, "unit": p.unit, "at_bound": b,
                          "bounds": [p.lo, p.hi]}
    return EffectFit(eff.name, params, eff.case_fields, eff.citation, eff.equation)


def _closing(prob: _Problem, cands) -> tuple:
    """Small data: each candidate alone, fitted to all points (no held-out check)."""
    out = []
    for name in cands:
        try:
            x, _, r, _ = prob.fit((name,))
        except ToothfemError as exc:
            out.append(Closing(name, (), float("nan"), False, f"failed: {exc}"))
            continue
        params = prob.effects[name].parameters
        pred = prob.predict((name,), x)
        rmse = float(np.sqrt(np.mean((prob.eta - pred) ** 2)))
        bound = any(_at_bound(v, p) for v, p in zip(x, params))
        note = ("at its bound: this effect alone cannot reach the data" if bound and rmse > 1e-4
                else "meets the data" if rmse <= 1e-4 else "closest value")
        out.append(Closing(name, tuple(float(v) for v in x), rmse, bound, note))
    return tuple(out)


def final_case(case, report: LoopReport, effects=None):
    """The case with every effect the loop added set to its fitted values."""
    cat = {e.name: e for e in (effects or fx.catalog())}
    assignment = {cat[e.name]: tuple(p["value"] for p in e.parameters.values())
                  for e in report.effects}
    return fx.with_effects(case, assignment)


# ---------------------------------------------------------------------------------------
# Plots and Markdown (matplotlib imported only here)


def plot_residuals(report: LoopReport, stage="before"):
    """Figure: residual [efficiency points] against every covariate, ``stage`` 'before'
    (the baseline) or 'after' (the final model); held-out residuals after, since those are
    the ones that measure the model. Returns the matplotlib Figure (not shown)."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if stage == "before":
        r, trends, title = report.baseline_fit.residual, report.trends_before, "baseline"
    else:
        r = report.final.residual if report.selection else report.final_fit.residual
        trends, title = report.trends_after, "after the loop (held-out)"
    covs = report.covariates
    k = max(len(covs), 1)
    cols = min(k, 3)
    rows = math.ceil(k / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.2 * rows), squeeze=False)
    tr = {t.covariate: t for t in trends}
    for ax, (name, x) in zip(axes.flat, covs.items()):
        x = np.asarray(x)
        if x.dtype == object:
            levels = sorted(set(x.astype(str)))
            xi = np.array([levels.index(v) for v in x.astype(str)], float)
            ax.set_xticks(range(len(levels)), levels, rotation=45, fontsize=7)
            ax.plot(xi, 100 * r, ".", ms=4, alpha=0.7)
        else:
            ax.plot(x.astype(float), 100 * r, ".", ms=4, alpha=0.7)
        ax.axhline(0.0, color="k", lw=0.6)
        t = tr.get(name)
        label = name if t is None else (f"{name}: R² {t.r2:.2f}, p {t.p_value:.1g}"
                                        + (" FOLLOWS" if t.follows else ""))
        ax.set_title(label, fontsize=8)
        ax.set_xlabel(name, fontsize=8)
        ax.set_ylabel("residual [points]", fontsize=8)
    for ax in list(axes.flat)[len(covs):]:
        ax.set_visible(False)
    fig.suptitle(f"{report.case_name}: residual {title}; R² and p of the fitted model's "
                 "residual", fontsize=9)
    fig.tight_layout()
    return fig


def markdown(report: LoopReport, images=("residuals_before.png", "residuals_after.png")) -> str:
    """report.md text."""
    pct = lambda x: f"{100 * x:.3f}"   # noqa: E731
    b, f = report.baseline, report.final
    out = [f"# Measured-data loop: {report.case_name}", "",
           f"Data: `{report.data_source}`, {report.n_points} points"
           + (f" ({len(report.rejected_rows)} rows refused)" if report.rejected_rows else "")
           + ("; weighted by the sensors' uncertainty" if report.weighted else "; unweighted"),
           ""]
    if report.provenance:
        src = report.provenance.get("source")
        if src:
            out += [f"Provenance: {src}", ""]
    out += ["## Error before and after", "",
            "| | baseline | final |", "|---|---|---|",
            f"| held-out RMSE [points] | {pct(b.rmse)} | {pct(f.rmse)} |",
            f"| held-out max abs error [points] | {pct(b.max_abs)} | {pct(f.max_abs)} |",
            f"| fit RMSE [points] | {pct(report.baseline_fit.rmse)} | "
            f"{pct(report.final_fit.rmse)} |",
            f"| mean residual [points] | {pct(np.mean(report.baseline_fit.residual))} | "
            f"{pct(np.mean(report.final_fit.residual))} |", ""]
    if not report.selection:
        out += ["Held-out errors need data to hold out: with so few points the 'final' "
                "column equals the baseline.", ""]
    out += ["## Effects added", ""]
    if report.effects:
        out += ["| effect | parameter | value | std. error | unit | note |",
                "|---|---|---|---|---|---|"]
        for e in report.effects:
            for pname, p in e.parameters.items():
                out.append(f"| {e.name} | {pname} | {p['value']:.5g} | {p['stderr']:.2g} | "
                           f"{p['unit']} | {'at bound' if p['at_bound'] else ''} |")
        out += [""] + [f"- {e.name}: {e.equation} ({e.citation}); sets "
                       f"{', '.join(e.case_fields)}" for e in report.effects] + [""]
    else:
        out += ["None.", ""]
    out += [f"Stop: {report.stop_reason}", ""]
    if report.steps:
        out += ["## Selection steps", ""]
        for s in report.steps:
            out += [f"Step {s.index}: {s.reason}", "",
                    "| candidate | values | std. error | fit RMSE [points] | held-out weighted RMS "
                    "| ΔBIC | passes |", "|---|---|---|---|---|---|---|"]
            for c in s.candidates:
                out.append(f"| {c.name} | {', '.join(f'{v:.4g}' for v in c.values)} | "
                           f"{', '.join(f'{v:.2g}' for v in c.stderr)} | {pct(c.rmse)} | "
                           f"{c.cv_wrmse:.4g} | {c.delta_bic:+.1f} | "
                           f"{'yes' if c.passed else 'no'}"
                           f"{' (' + c.note + ')' if c.note else ''} |")
            out.append("")
    if not report.selection:
        r = report.baseline_fit.residual
        sig = report.sigma
        out += ["## Each point against its measurement uncertainty", "",
                "| point | speed [rpm] | torque [N m] | measured [%] | model [%] | residual "
                "[points] | sensor sigma [points] |", "|---|---|---|---|---|---|---|"]
        covs = report.covariates
        for i in range(report.n_points):
            s_i = "–" if sig is None else f"{100 * sig[i]:.2f}"
            out.append(f"| {i + 1} | {covs['input_speed_rpm'][i]:g} | "
                       f"{covs['output_torque_Nm'][i]:g} | {100 * report.measured[i]:.2f} | "
                       f"{100 * report.baseline_fit.prediction[i]:.2f} | {100 * r[i]:+.2f} | "
                       f"{s_i} |")
        out.append("")
    if report.closing:
        out += ["## What each candidate would need (too few points to select)", "",
                "| effect | value(s) | RMSE after [points] | note |", "|---|---|---|---|"]
        for c in report.closing:
            out.append(f"| {c.name} | {', '.join(f'{v:.4g}' for v in c.values)} | "
                       f"{pct(c.rmse)} | {c.note} |")
        out.append("")
    trends = [t for t in report.trends_before if math.isfinite(t.r2)]
    out += ["## Residual against the covariates", ""]
    if trends:
        out += ["| covariate | R² before | p before | R² after | p after | follows after |",
                "|---|---|---|---|---|---|"]
    else:
        out += ["Too few points (or no covariate that varies) for a trend test.", ""]
    after = {t.covariate: t for t in report.trends_after}
    for t in trends:
        a = after.get(t.covariate)
        out.append(f"| {t.covariate} | {t.r2:.3f} | {t.p_value:.2g} | "
                   f"{a.r2 if a else float('nan'):.3f} | {a.p_value if a else float('nan'):.2g} | "
                   f"{'yes' if a and a.follows else 'no'} |")
    out += ["", f"Unexplained: {', '.join(report.unexplained) or 'nothing'}"
            + (" (the final residual still follows these covariates; no catalog effect "
               "accounts for it)" if report.unexplained else ""), ""]
    if report.signatures and report.n_points >= 3:
        out += ["## Residual against each candidate's signature (baseline)", "",
                "| effect | correlation |", "|---|---|"]
        out += [f"| {k} | {v:+.3f} |" for k, v in report.signatures.items()] + [""]
    if report.skipped:
        out += ["## Not candidates", ""] + [f"- {k}: {v}" for k, v in report.skipped.items()]
        out.append("")
    if report.rejected_rows:
        out += ["## Refused rows", ""] + [f"- {r}" for r in report.rejected_rows] + [""]
    out += [f"![residuals before]({images[0]})", "", f"![residuals after]({images[1]})", "",
            f"Loop time {report.elapsed_s:.1f} s, {report.evaluations} model evaluations.", ""]
    return "\n".join(out)
