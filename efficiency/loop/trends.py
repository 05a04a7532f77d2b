"""Residual analysis: does the residual follow a covariate, and which effect's signature?

:func:`residual_trends`: for every covariate in the data (input speed, output torque, oil
temperature, time, run, any further numeric column) the fraction R^2 of the residual's
variance that a smooth function of that covariate explains (a Legendre polynomial of degree
:attr:`Settings.degree` in the covariate, or one mean per level when it has few values), with
the F-test p-value against a constant. The residual *follows* a covariate when p is below
:attr:`Settings.alpha_trend` / number of covariates (Bonferroni) and R^2 >=
:attr:`Settings.r2_trend`.

:func:`signatures`: for every candidate effect the weighted correlation of the residual with
its signature, the change of the efficiency a step of one typical value in its parameter
makes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import ToothfemError
from .engine import Fit
from .problem import Problem
from .settings import DEFAULT_SETTINGS

#: Fewest residual degrees of freedom of a trend's F-test: with fewer the residual variance
#: is too poorly known for the test to say anything; the trend is reported as nan.
MIN_TREND_DOF = 3


@dataclass(frozen=True, kw_only=True)
class Trend:
    """How strongly the residual follows one covariate."""
    covariate: str
    kind: str                      # "numeric" (polynomial) or "levels" (one mean per value)
    r2: float                      # share of the residual variance explained
    p_value: float
    amplitude: float               # range of the fitted trend over the data [efficiency]
    follows: bool


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


def residual_trends(residual, covariates: dict, weights=None, settings=DEFAULT_SETTINGS) -> tuple:
    """How strongly the residual follows each covariate (module docstring).

    Parameters
    ----------
    residual : array_like
        (M,) residual, measured - model efficiency.
    covariates : dict
        name -> (M,) array (numbers, or labels for a run).
    weights : array_like, optional
        (M,) relative weights (1/sigma); default unweighted.
    settings : Settings
        Trend level, share, number of levels and polynomial degree.

    Returns
    -------
    tuple of Trend
        One per covariate that varies: R^2, F-test p-value, range of the fitted trend
        [efficiency] and whether the residual follows it.
    """
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
        if dof < MIN_TREND_DOF:
            out.append(Trend(covariate=name, kind=kind, r2=float("nan"),
                             p_value=float("nan"), amplitude=float("nan"), follows=False))
            continue
        a = np.column_stack([np.ones(n), b]) * w[:, None]
        coef, *_ = np.linalg.lstsq(a, w * r, rcond=None)
        fitted = np.column_stack([np.ones(n), b]) @ coef
        rss1 = float(np.sum((w * (r - fitted)) ** 2))
        mean_w = np.sum(w ** 2 * r) / np.sum(w ** 2)
        rss0 = float(np.sum((w * (r - mean_w)) ** 2))
        if rss0 <= 0:
            out.append(Trend(covariate=name, kind=kind, r2=0.0, p_value=1.0, amplitude=0.0,
                             follows=False))
            continue
        r2 = max(0.0, 1.0 - rss1 / rss0)
        fstat = ((rss0 - rss1) / q) / (rss1 / dof) if rss1 > 0 else np.inf
        p = float(f_dist.sf(fstat, q, dof))
        out.append(Trend(covariate=name, kind=kind, r2=float(r2), p_value=p,
                         amplitude=float(np.ptp(fitted)),
                         follows=bool(p < alpha and r2 >= settings.r2_trend)))
    return tuple(out)


def most_followed(trends) -> Trend | None:
    """The covariate the residual follows most: the largest R^2 among those it follows,
    else among all (None when no covariate varies).

    Parameters
    ----------
    trends : sequence of Trend
        From :func:`residual_trends`.

    Returns
    -------
    Trend or None
    """
    usable = [t for t in trends if math.isfinite(t.r2)]
    if not usable:
        return None
    return max(usable, key=lambda t: (t.follows, t.r2))


def signatures(problem: Problem, fit: Fit, names) -> dict:
    """Correlation of the residual with each candidate's signature.

    The signature of an effect is the change of the efficiency from a step of one typical
    value in its parameter(s), on top of the effects of ``fit``; the correlation is weighted
    by the problem's weights.

    Parameters
    ----------
    problem : Problem
        The measured data, case and catalog.
    fit : Fit
        The fit whose residual is correlated (the baseline in the loop).
    names : iterable of str
        Candidate effects.

    Returns
    -------
    dict
        name -> correlation in [-1, 1]; effects whose prediction fails are left out.
    """
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
