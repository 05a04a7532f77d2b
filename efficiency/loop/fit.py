"""Fitting catalog effects to measured efficiencies: bounded least squares, k-fold held-out error.

:class:`Problem` holds the measured efficiencies, the case and the catalog. Its
:meth:`~Problem.make_fit` fits a set of effects to all points by bounded least squares
(``scipy.optimize.least_squares``, trust-region reflective, parameters scaled by their typical
value, from the best of several starting values) and scores the fit by BIC, AIC and a fast
held-out error; :meth:`~Problem.held_out` gives the k-fold held-out errors by full refits.

Weights: the residual r = eta_measured - eta_model at every point is weighted by 1/sigma
where the data give an uncertainty (the rig's torque sensors), else unweighted; the weights
are relative (mean square 1), so the weighted RMS is in efficiency units.

Effects whose loss is proportional to their parameter (drag, bearing and output-pin friction,
churning) are evaluated once at a reference value and scaled (effects.predict's cache), so
fitting them costs almost no model evaluations.

The held-out error of a candidate during selection (:meth:`~Problem.linear_cv`) is one
bounded Gauss-Newton step from its all-data fit for each fold: exact for a loss linear in the
parameter, which drag, churning, bearing and output-pin friction are, and close for the
others. The held-out errors reported before and after the loop (:meth:`~Problem.held_out`)
are from full refits on each fold's training points.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..evaluation import Efficiency
from . import effects as fx
from .settings import Settings

# The least-squares fit and its scores.
FD_STEP = 1e-3          # relative finite-difference step of the Jacobian, on parameters
                        # scaled by their typical value (the model is smooth there; the
                        # clearance tables are PCHIP-interpolated)
EXACT_TOL = 1e-12       # tolerances of a fit that should meet its points exactly (a
                        # candidate's closing value on fewer points than parameters can
                        # tell apart: its residual goes to 0, where 1e-6 stops short)
FIT_TOL = 1e-6          # tolerances of the fit (cost, step, gradient): the parameters'
                        # standard errors are percents, so a relative change of 1e-6 is
                        # converged; 1e-10 took 28 % more model evaluations for the same
                        # values to 4 digits (four scenarios of tests/test_loop*.py)
AT_BOUND_REL = 1e-4     # a value within this fraction of its parameter's typical value of
                        # a bound is at it
WRSS_FLOOR = 1e-300     # floor of the weighted residual sum of squares in BIC and AIC:
                        # keeps the logarithm finite for an exact fit (the smallest normal
                        # double is 2.2e-308)

# The held-out error.
MIN_FOLDS = 2           # one fold to hold out and one to train on
STEP_BOUND_EPS = 1e-15  # width added to the upper bound of a Gauss-Newton step:
                        # lsq_linear needs each lower bound strictly below its upper bound,
                        # which a parameter pinned where both meet is not

# The caches of Problem.predict.
CACHE_DECIMALS = 12     # parameter values equal to this many decimals are one prediction:
                        # the optimiser revisits a point up to rounding in its steps
PREDICTION_CACHE_SIZE = 4096   # predictions kept, each an (M,) array (1.6 kB at M = 200:
                               # at most 6.5 MB; 40 kB at Settings.max_points = 5000: at most
                               # 164 MB), more than one least-squares fit asks for
                               # (max_nfev = 60 steps, each with its finite-difference columns)
MODEL_CACHE_SIZE = 512  # model evaluations kept (effects.predict's cache, each a few (M,)
                        # loss arrays): bounds the memory while keeping the evaluations the
                        # fits of one selection step share


@dataclass(frozen=True, kw_only=True)
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
        """Unweighted RMS of the residual on all points [efficiency, a fraction]."""
        return float(np.sqrt(np.mean(self.residual ** 2)))


@dataclass(frozen=True, kw_only=True)
class HeldOut:
    """Errors on held-out points (k-fold refits), efficiency as a fraction."""
    rmse: float
    max_abs: float
    wrmse: float
    residual: np.ndarray           # (M,) held-out residual of each point
    folds: int


def fold_count(n: int, settings: Settings) -> int:
    """Folds of the k-fold held-out error on ``n`` points: :attr:`Settings.folds`, but no
    more than the points and no fewer than :data:`MIN_FOLDS`.

    Parameters
    ----------
    n : int
        Points.
    settings : Settings
        The loop's settings.

    Returns
    -------
    int
        Folds.
    """
    return max(MIN_FOLDS, min(settings.folds, n))


def at_bound(value, parameter) -> bool:
    """Whether a fitted value sits at a bound of its parameter.

    Parameters
    ----------
    value : float
        Fitted value, in the parameter's unit.
    parameter : effects.Parameter
        The parameter (bounds ``lo``, ``hi`` and ``typical`` value).

    Returns
    -------
    bool
        True within :data:`AT_BOUND_REL` x typical of either bound.
    """
    tol = AT_BOUND_REL * parameter.typical
    return value <= parameter.lo + tol or value >= parameter.hi - tol


class Problem:
    """Measured efficiencies, the case and the catalog: predictions, fits, held-out errors.

    Parameters
    ----------
    case : toothfem.Case
        The reducer case the effects are added to.
    data : measured.MeasuredData
        Measured points, M of them.
    effects : sequence of effects.Effect
        The catalog effects that may be fitted.
    settings : Settings
        Folds, fold seed and function evaluations per fit.
    loads : str
        Load sharing of the model, ``"analytic"`` or ``"fem"``.
    """

    def __init__(self, *, case, data, effects, settings: Settings, loads):
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
        # each applicable effect with the bounds of this case and data (Effect.bound_to)
        self.effects = {e.name: e.bound_to(case, self.points)
                        if e.applicable(case, self.points) is None else e for e in effects}
        self.prepared: dict[str, object] = {}   # effect name -> its prepared tables
        self.evaluations = 0
        # (names, values) -> efficiency
        self._cache: dict[tuple[tuple[str, ...], tuple[float, ...]], np.ndarray] = {}
        self._evals: dict[tuple, Efficiency] = {}   # model evaluations (effects.predict's cache)
        folds = fold_count(self.n, settings)
        perm = np.random.default_rng(settings.seed).permutation(self.n)
        self.fold = np.empty(self.n, int)
        self.fold[perm] = np.arange(self.n) % folds
        self.n_folds = folds

    # -- predictions
    def predict(self, names, values_flat) -> np.ndarray:
        """Efficiency at the measured points with the effects ``names`` set.

        Parameters
        ----------
        names : sequence of str
            Effect names, in the order of ``values_flat``.
        values_flat : array_like
            Their parameter values, one after the other, in the parameters' units.

        Returns
        -------
        numpy.ndarray
            (M,) efficiency, a fraction.
        """
        key = (tuple(names), tuple(np.round(values_flat, CACHE_DECIMALS)))
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
        if len(self._cache) > PREDICTION_CACHE_SIZE:
            self._cache.clear()
        if len(self._evals) > MODEL_CACHE_SIZE:
            self._evals.clear()
        self._cache[key] = eta
        return eta

    def params(self, names) -> list:
        """The parameters of the effects ``names``.

        Parameters
        ----------
        names : sequence of str
            Effect names.

        Returns
        -------
        list of effects.Parameter
            Their parameters, effect by effect, in order.
        """
        return [p for name in names for p in self.effects[name].parameters]

    # -- scores
    def criteria(self, wrss, k) -> tuple:
        """Information criteria of a fit on the M points.

        Parameters
        ----------
        wrss : float
            Weighted residual sum of squares.
        k : int
            Number of fitted parameters.

        Returns
        -------
        tuple of float
            (BIC, AIC) = n ln(WRSS/n) + (k ln n, 2k); lower is better, differences matter
            (Kass & Raftery 1995).
        """
        n = self.n
        misfit = n * math.log(max(wrss, WRSS_FLOOR) / n)
        return misfit + k * math.log(n), misfit + 2 * k

    # -- fit
    def fit(self, names, start=None, train=None, max_nfev=None, tol=FIT_TOL) -> tuple:
        """Bounded least squares of the effects ``names``.

        Parameters
        ----------
        names : tuple of str
            Effects to fit together.
        start : dict, optional
            {name: values} starting values; effects not in it start from the best of their
            parameters' ``starts``.
        train : numpy.ndarray of bool, optional
            (M,) points to fit on (default all).
        max_nfev : int, optional
            Function evaluations allowed (default :attr:`Settings.max_nfev`).
        tol : float
            Tolerances of the fit (cost, step, gradient; default :data:`FIT_TOL`).

        Returns
        -------
        tuple
            (values_flat, Jacobian in scaled units (M_train, k), weighted residual
            (M_train,), number of function evaluations).
        """
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
                            diff_step=FD_STEP, x_scale=1.0, ftol=tol, xtol=tol, gtol=tol,
                            max_nfev=max_nfev or self.settings.max_nfev)
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
        """Fit the effects ``names`` to all points and score the fit.

        Parameters
        ----------
        names : sequence of str
            Effects to fit together (empty: the case as it is).
        start : dict, optional
            {name: values} starting values (as :meth:`fit`).

        Returns
        -------
        Fit
            Values, standard errors, residual, BIC, AIC and the fast held-out error.
        """
        names = tuple(names)
        x, jac, r, nfev = self.fit(names, start)
        params = self.params(names)
        k = len(params)
        wrss = float(np.sum(r ** 2))
        pred = self.predict(names, x)
        values, stderr, bound, i = {}, {}, {}, 0
        se = self._stderr(jac, wrss, k, params)
        for name in names:
            m = len(self.effects[name].parameters)
            values[name] = tuple(float(v) for v in x[i:i + m])
            stderr[name] = tuple(float(s) for s in se[i:i + m])
            bound[name] = tuple(bool(at_bound(v, p)) for v, p in
                                zip(x[i:i + m], params[i:i + m]))
            i += m
        bic, aic = self.criteria(wrss, k)
        return Fit(effects=names, values=values, stderr=stderr, at_bound=bound,
                   prediction=pred, residual=self.eta - pred, n_params=k, wrss=wrss,
                   bic=bic, aic=aic,
                   cv_wrmse=self.linear_cv(x, jac, r, params), nfev=nfev)

    def _stderr(self, jac, wrss, k, params):
        """Standard errors s sqrt(diag (J^T J)^-1), s^2 = WRSS / (n - k); nan where undefined."""
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
        all-data fit (module docstring).

        Parameters
        ----------
        x : numpy.ndarray
            (k,) fitted values, in the parameters' units.
        jac : numpy.ndarray
            (M, k) Jacobian of the weighted residual in scaled units (from :meth:`fit`).
        r : numpy.ndarray
            (M,) weighted residual at ``x``.
        params : list of effects.Parameter
            The k parameters.

        Returns
        -------
        float
            Weighted RMS of the held-out residuals [efficiency].
        """
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
            sol = lsq_linear(jac[train], -r[train], bounds=(lo, hi + STEP_BOUND_EPS))
            out[test] = r[test] + jac[test] @ sol.x
        return float(np.sqrt(np.mean(out ** 2)))

    def held_out(self, fit: Fit) -> HeldOut:
        """k-fold held-out errors with full refits from the all-data values.

        Parameters
        ----------
        fit : Fit
            The all-data fit whose effects are refitted on each fold's training points.

        Returns
        -------
        HeldOut
            RMS, largest and weighted RMS held-out error, and each point's held-out residual.
        """
        if fit.n_params == 0:
            r = fit.residual
        else:
            r = np.empty(self.n)
            start = dict(fit.values)
            for f in range(self.n_folds):
                test = self.fold == f
                x, _, _, _ = self.fit(fit.effects, start, train=~test)
                r[test] = (self.eta - self.predict(fit.effects, x))[test]
        return HeldOut(rmse=float(np.sqrt(np.mean(r ** 2))), max_abs=float(np.max(np.abs(r))),
                       wrmse=float(np.sqrt(np.mean((self.w * r) ** 2))), residual=r,
                       folds=self.n_folds if fit.n_params else 0)
