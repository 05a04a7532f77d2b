"""Bounded least squares of a set of effects, scored: BIC, AIC, standard errors, the
at-bound rule, the k-fold held-out error; the rows' distance between two fits.

:class:`Engine` holds a loop's observations, its effects and its model. Its
:meth:`~Engine.fit` fits a set of effects (``scipy.optimize.least_squares``, trust-region
reflective, each parameter scaled by its typical value, some of them optionally held) and
scores the fit; the held-out error of a fit is one bounded Gauss-Newton step from it for
each fold, on the fold's training rows (no model evaluation: the fit's Jacobian), exact for
a model linear in the parameters and close for the others. :meth:`~Engine.held_out` gives
the k-fold held-out errors by full refits.

The weighted residual of a row is weight x (observed - model); BIC = N ln(WRSS / N) + k ln N
and AIC = N ln(WRSS / N) + 2k (Kass & Raftery 1995: lower is better, differences matter).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..settings import Settings
from .records import (AT_BOUND_REL, STEP_BOUND_EPS, WRSS_FLOOR, Effect, Fit, HeldOut, Model,
                      Observations, Rules, assign_folds, at_bound)


@dataclass(frozen=True)
class Solution:
    """A least-squares solution before it is scored."""
    values: np.ndarray             # (k,) every parameter's value, in its unit
    jac: np.ndarray                # (M, k) Jacobian of the weighted residual in scaled units
                                   # (value / typical); 0 in the columns held
    residual: np.ndarray           # (M,) weighted residual at ``values`` (the rows fitted)
    nfev: int


class Engine:
    """A loop's observations, effects and model: fits, scores and held-out errors.

    Parameters
    ----------
    observations : Observations
        The N rows, their weights and fold groups.
    effects : sequence of Effect
        The effects that may be fitted (their parameters' bounds as this loop fits them).
    model : Model
        The loop's model evaluation.
    rules : Rules
        The loop's finite-difference step, tolerances, starts and folds.
    settings : Settings
        Folds, fold seed and function evaluations per fit (and the selection's
        thresholds).
    """

    def __init__(self, observations: Observations, effects, model: Model, *, rules: Rules,
                 settings: Settings):
        self.observations = observations
        self.y = np.asarray(observations.values, float)
        self.w = np.asarray(observations.weight, float)
        self.n = self.y.size
        self.effects: dict[str, Effect] = {e.name: e for e in effects}
        self.model = model
        self.rules = rules
        self.settings = settings
        self.fold, self.n_folds = assign_folds(observations.group, settings.folds,
                                               settings.seed, rules.folds)

    def params(self, names) -> list:
        """The parameters of the effects ``names``, effect by effect, in order.

        Parameters
        ----------
        names : sequence of str

        Returns
        -------
        list of Parameter
        """
        return [p for name in names for p in self.effects[name].parameters]

    def predict(self, names, values) -> np.ndarray:
        """The model with the effects ``names`` at ``values`` (:meth:`Model.predict`).

        Parameters
        ----------
        names : sequence of str
        values : array_like
            Their parameters' values, one effect after the other.

        Returns
        -------
        numpy.ndarray
            (N,)
        """
        return self.model.predict(tuple(names), np.asarray(values, float))

    def criteria(self, wrss: float, k: int) -> tuple:
        """(BIC, AIC) of a fit with ``k`` parameters and weighted residual sum of squares
        ``wrss`` on the N rows (module docstring).

        Parameters
        ----------
        wrss : float
        k : int

        Returns
        -------
        tuple of float
        """
        n = self.n
        misfit = n * math.log(max(wrss, WRSS_FLOOR) / n)
        return misfit + k * math.log(n), misfit + 2 * k

    # -- least squares
    def solve(self, names, start=None, *, free=None, train=None, tol=None,
              max_nfev=None) -> Solution:
        """Bounded least squares of the effects ``names``.

        Parameters
        ----------
        names : sequence of str
            Effects to fit together.
        start : dict, optional
            {name: values} to start from (a previous fit's); the others start from their
            parameters' ``starts`` (:attr:`Rules.starts`).
        free : collection of str, optional
            The effects whose parameters vary (default all); the others stay at ``start``.
        train : numpy.ndarray of bool, optional
            (N,) rows to fit on (default all).
        tol : float, optional
            Tolerances of the fit (default :attr:`Rules.fit_tol`).
        max_nfev : int, optional
            Function evaluations per run (default :attr:`Settings.max_nfev`).

        Returns
        -------
        Solution
        """
        from scipy.optimize import least_squares

        names = tuple(names)
        params = self.params(names)
        if not params:
            r = self.w * (self.y - self.predict((), np.zeros(0)))
            return Solution(np.zeros(0), np.zeros((self.n, 0)), r, 0)
        start = start or {}
        free = set(names if free is None else free)
        tol = tol or self.rules.fit_tol
        max_nfev = max_nfev or self.settings.max_nfev
        typ = np.array([p.typical for p in params])
        lo = np.array([p.lo for p in params]) / typ
        hi = np.array([p.hi for p in params]) / typ
        sizes = [len(self.effects[n].parameters) for n in names]
        moving = np.concatenate([np.full(k, n in free) for n, k in zip(names, sizes)])
        mask = np.ones(self.n, bool) if train is None else train
        x0 = np.concatenate([np.asarray(start[n], float) if n in start else
                             np.array([p.starts[0] for p in self.effects[n].parameters],
                                      float) for n in names])

        held = x0 / typ             # scaled; the parameters held stay at theirs

        def values_of(x):
            z = held.copy()
            z[moving] = x
            return z * typ

        def fun(x):
            return (self.w * (self.y - self.predict(names, values_of(x))))[mask]

        if self.rules.starts == "screen":
            x0 = self._screened(names, start, x0, moving, typ, fun)
        lo_f, hi_f = lo[moving], hi[moving]
        starts = [(x0 / typ)[moving]]
        if self.rules.starts == "restart":
            for j, p in enumerate(p for p, m in zip(params, moving) if m):
                for s in p.starts[1:]:       # each parameter's other starts, the rest kept
                    x = starts[0].copy()
                    x[j] = s / typ[moving][j]
                    starts.append(x)
        best, nfev = None, 0
        for x in starts:        # the other starts only while the best ends at a bound
            if best is not None and not (np.any(best.x <= lo_f + AT_BOUND_REL)
                                         or np.any(best.x >= hi_f - AT_BOUND_REL)):
                break
            res = least_squares(fun, np.clip(x, lo_f, hi_f), bounds=(lo_f, hi_f),
                                method="trf", diff_step=self.rules.fd_step, x_scale=1.0,
                                ftol=tol, xtol=tol, gtol=tol, max_nfev=max_nfev)
            nfev += res.nfev
            if best is None or res.cost < best.cost:
                best = res
        if best is None:        # starts holds the first start at least
            raise RuntimeError(f"fit of {names}: no least-squares run")
        jac = np.zeros((len(best.fun), len(params)))
        jac[:, moving] = best.jac
        return Solution(values_of(best.x), jac, best.fun, nfev)

    def _screened(self, names, start, x0, moving, typ, fun) -> np.ndarray:
        """Starting values: the given ones, else each new effect's parameters, one after
        the other, at the best of their ``starts`` by the cost there."""
        x0 = x0.copy()
        k = 0
        for name in names:
            params = self.effects[name].parameters
            if name not in start:
                for j, p in enumerate(params):
                    if not moving[k + j]:
                        continue
                    best, best_cost = x0[k + j], None
                    for s in p.starts:
                        trial = x0.copy()
                        trial[k + j] = s
                        cost = float(np.sum(fun((trial / typ)[moving]) ** 2))
                        if best_cost is None or cost < best_cost:
                            best, best_cost = s, cost
                    x0[k + j] = best
            k += len(params)
        return x0

    # -- scores
    def fit(self, names, start=None, *, free=None) -> Fit:
        """Fit the effects ``names`` to every row and score the fit.

        Parameters
        ----------
        names : sequence of str
            Effects to fit together (empty: the model as it is).
        start : dict, optional
            {name: values} to start from (as :meth:`solve`).
        free : collection of str, optional
            The effects whose parameters vary (default all); BIC counts every parameter.

        Returns
        -------
        Fit
            Values, standard errors, the at-bound flags, residual, BIC, AIC and the held-out
            error.
        """
        names = tuple(names)
        sol = self.solve(names, start, free=free)
        params = self.params(names)
        k = len(params)
        wrss = float(np.sum(sol.residual ** 2))
        pred = self.predict(names, sol.values)
        se = self._stderr(sol.jac, wrss, params)
        values, stderr, bound, i = {}, {}, {}, 0
        for name in names:
            m = len(self.effects[name].parameters)
            values[name] = tuple(float(v) for v in sol.values[i:i + m])
            stderr[name] = tuple(float(s) for s in se[i:i + m])
            bound[name] = tuple(bool(at_bound(v, p)) for v, p in
                                zip(sol.values[i:i + m], params[i:i + m]))
            i += m
        bic, aic = self.criteria(wrss, k)
        cv = self._linear_cv(sol, params)
        return Fit(effects=names, values=values, stderr=stderr, at_bound=bound,
                   prediction=pred, residual=self.y - pred, n_params=k, wrss=wrss, bic=bic,
                   aic=aic, cv_wrmse=float(np.sqrt(np.mean(cv ** 2))), cv_residual=cv,
                   nfev=sol.nfev)

    def _stderr(self, jac, wrss, params) -> np.ndarray:
        """Standard errors s sqrt(diag (J^T J)^-1), s^2 = WRSS / (N - k), in the parameters'
        units; nan where not defined (no residual degree of freedom, a singular J^T J: a
        parameter held or without effect on the rows)."""
        k = len(params)
        if k == 0:
            return np.zeros(0)
        dof = self.n - k
        if dof <= 0:
            return np.full(k, np.nan)
        typ = np.array([p.typical for p in params])
        try:
            cov = np.linalg.inv(jac.T @ jac) * (wrss / dof)
        except np.linalg.LinAlgError:
            return np.full(k, np.nan)
        d = np.diag(cov)
        return np.where(d >= 0, np.sqrt(np.abs(d)), np.nan) * typ

    def _linear_cv(self, sol: Solution, params) -> np.ndarray:
        """(N,) each row's weighted residual with its fold held out: one bounded
        Gauss-Newton step from the all-rows fit on the training rows (the rows' residuals
        move by J d)."""
        from scipy.optimize import lsq_linear

        r, jac = sol.residual, sol.jac
        if not params:
            return r.copy()
        typ = np.array([p.typical for p in params])
        u = sol.values / typ
        lo = np.minimum(np.array([p.lo for p in params]) / typ - u, 0.0)
        hi = np.maximum(np.array([p.hi for p in params]) / typ - u, 0.0)
        out = np.empty(self.n)
        for f in range(self.n_folds):
            test = self.fold == f
            train = ~test
            # the training rows' optimum, linearised: min |r_t + J_t d| within the bounds
            step = lsq_linear(jac[train], -r[train], bounds=(lo, hi + STEP_BOUND_EPS)).x \
                if train.any() else np.zeros(len(params))
            out[test] = r[test] + jac[test] @ step
        return out

    def held_out(self, fit: Fit) -> HeldOut:
        """k-fold held-out errors with full refits from the all-rows values.

        Parameters
        ----------
        fit : Fit
            The all-rows fit whose effects are refitted on each fold's training rows.

        Returns
        -------
        HeldOut
            RMS, largest and weighted RMS held-out error, and each row's held-out residual.
        """
        if fit.n_params == 0:
            r = fit.residual
        else:
            r = np.empty(self.n)
            start = dict(fit.values)
            for f in range(self.n_folds):
                test = self.fold == f
                sol = self.solve(fit.effects, start, train=~test)
                r[test] = (self.y - self.predict(fit.effects, sol.values))[test]
        return HeldOut(rmse=float(np.sqrt(np.mean(r ** 2))), max_abs=float(np.max(np.abs(r))),
                       wrmse=float(np.sqrt(np.mean((self.w * r) ** 2))), residual=r,
                       folds=self.n_folds if fit.n_params else 0)

    def separation(self, a: Fit, b: Fit) -> float:
        """The weighted distance between two fits' rows: how far apart the data could tell
        them (:attr:`Rules.alias_separation`).

        Parameters
        ----------
        a, b : Fit

        Returns
        -------
        float
        """
        return float(np.linalg.norm((a.prediction - b.prediction) * self.w))
