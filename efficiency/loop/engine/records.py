"""The fitting engine's records: a fitted parameter, the Protocols a loop implements
(:class:`Observations`, :class:`Effect`, :class:`Model`), the :class:`Rules` each loop sets,
a :class:`Fit` and its :class:`HeldOut` errors, and the rules every loop shares (the
at-bound rule, the folds of the held-out error).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

#: A value within this fraction of its parameter's typical value of a bound is at it (in
#: the scaled units of a fit, value / typical: within this of the scaled bound).
AT_BOUND_REL = 1e-4
#: Floor of the weighted residual sum of squares in BIC and AIC: keeps the logarithm finite
#: for an exact fit (the smallest normal double is 2.2e-308).
WRSS_FLOOR = 1e-300
#: Fewest folds of the held-out error: one fold to hold out and one to train on.
MIN_FOLDS = 2
#: Width added to the upper bound of a held-out Gauss-Newton step: lsq_linear needs each
#: lower bound strictly below its upper bound, which a parameter pinned where both meet
#: is not.
STEP_BOUND_EPS = 1e-15
#: Tolerances of a fit that should meet its points exactly (a parameter's closing value on
#: fewer points than parameters can tell apart: its residual goes to 0, where the loops'
#: own tolerances stop short).
EXACT_TOL = 1e-12


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter: name (with unit), bounds and starting values (absolute)."""
    name: str
    unit: str
    lo: float
    hi: float
    starts: tuple            # starting values tried before the fit (absolute)
    typical: float           # scale of the fit (x_scale) and of a signature's step
    doc: str = ""


def parameter(name: str, unit: str, lo: float, hi: float, typical: float, starts=None,
              doc: str = "") -> Parameter:
    """A fitted parameter by keywords, its starts defaulting to its typical value.

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


class Observations(Protocol):
    """What a loop fits: N rows, each with its weight and its fold group."""

    @property
    def values(self) -> np.ndarray:
        """(N,) the observed values, in each row's unit."""

    @property
    def weight(self) -> np.ndarray:
        """(N,) each row's weight: the weighted residual is weight x (value - model)."""

    @property
    def group(self) -> np.ndarray:
        """(N,) each row's fold group: the held-out error holds out whole groups."""


class Effect(Protocol):
    """An effect a loop may add: its name and its bounded parameters."""

    @property
    def name(self) -> str:
        """The effect's name, unique in its catalog."""

    @property
    def parameters(self) -> Sequence[Parameter]:
        """Its fitted parameters, in the order of its values."""


class Model(Protocol):
    """A loop's model evaluation: the rows with a set of effects at their values."""

    def predict(self, names: tuple[str, ...], values: np.ndarray) -> np.ndarray:
        """The model on the rows with the effects ``names`` set.

        Parameters
        ----------
        names : tuple of str
            Effect names, in the order of ``values``.
        values : numpy.ndarray
            Their parameters' values, one effect after the other, in the parameters'
            units.

        Returns
        -------
        numpy.ndarray
            (N,) in the rows' units.
        """


@dataclass(frozen=True, kw_only=True)
class Rules:
    """How a loop fits and selects, where the two loops differ (each adapter sets every
    field, with its reason beside it; the thresholds both share are
    :class:`~toothfem.efficiency.loop.settings.Settings`').

    fd_step : relative finite-difference step of the Jacobian, on parameters scaled by their
        typical value.
    fit_tol : tolerances of a fit (cost, step, gradient).
    starts : "screen": each new effect's parameters start from the best of their
        ``starts`` by the cost there, one least-squares run; "restart": from the first
        start, and again from each other start while the best run ends at a bound.
    folds : "deal": the fold groups shuffled and dealt round the folds (group perm[i] takes
        fold i mod k); "label": group i takes fold perm[i] mod k. Both are balanced random
        folds of the same seed.
    scoring : "joint": a candidate is fitted with every parameter free; "alone": only its
        own parameters, the effects already added held, and the one added refitted jointly
        (kept where that lowers BIC or keeps it).
    rank : the passing candidate added: the lowest "held_out" error or the lowest "bic".
    tie_bic : passing candidates whose BIC changes lie within this of the best one's are a
        tie, won by the first in the candidates' order.
    aliases : the candidates named as the added one's aliases: "passing" ones whose BIC
        change lies within ``Settings.alias_bic`` of its, either side; or "unbounded" ones
        (no parameter at a bound, passing or not) at most ``Settings.alias_bic`` above its
        BIC. Either way also any not at a bound whose rows lie within
        ``alias_separation``.
    alias_separation : a candidate whose fitted rows lie within this weighted distance of
        the added one's [sigma of the weights] is its alias whatever its BIC (0: none is).
    exclude_aliases : whether an added effect's aliases leave the candidates.
    prune_fraction : after each addition, an earlier effect whose removal costs less than
        this fraction of ``Settings.delta_bic`` in BIC is removed again; None: never.
    pairs : whether a candidate that helps only at a parameter's bound is fitted together
        with each other candidate (:func:`.selection.pairs`), two effects added at once.
    """
    fd_step: float
    fit_tol: float
    starts: Literal["screen", "restart"]
    folds: Literal["deal", "label"]
    scoring: Literal["joint", "alone"]
    rank: Literal["held_out", "bic"]
    tie_bic: float
    aliases: Literal["passing", "unbounded"]
    alias_separation: float
    exclude_aliases: bool
    prune_fraction: float | None
    pairs: bool

    def __post_init__(self):
        for name, allowed in (("starts", ("screen", "restart")), ("folds", ("deal", "label")),
                              ("scoring", ("joint", "alone")), ("rank", ("held_out", "bic")),
                              ("aliases", ("passing", "unbounded"))):
            if getattr(self, name) not in allowed:
                raise ValueError(f"Rules.{name} = {getattr(self, name)!r}: one of {allowed}")
        if not (self.fd_step > 0 and self.fit_tol > 0):
            raise ValueError(f"Rules: fd_step = {self.fd_step} and fit_tol = {self.fit_tol} "
                             "must be > 0")


@dataclass(frozen=True, kw_only=True)
class Fit:
    """A set of effects fitted to every row, scored. Residuals are observed - model, in the
    rows' units; weighted ones times each row's weight."""
    effects: tuple                 # names, in the order added
    values: dict                   # name -> tuple of parameter values
    stderr: dict                   # name -> tuple of standard errors (nan: not defined)
    at_bound: dict                 # name -> tuple of bool
    prediction: np.ndarray         # (N,) the model
    residual: np.ndarray           # (N,) observed - model
    n_params: int
    wrss: float                    # weighted residual sum of squares
    bic: float
    aic: float
    cv_wrmse: float                # held-out weighted RMS (one Gauss-Newton step a fold)
    cv_residual: np.ndarray        # (N,) each row's weighted residual when held out
    nfev: int = 0

    @property
    def rmse(self) -> float:
        """RMS of the residual on every row, in the rows' unit."""
        return float(np.sqrt(np.mean(self.residual ** 2)))

    @property
    def wrmse(self) -> float:
        """RMS of the weighted residual on every row."""
        return float(np.sqrt(self.wrss / max(len(self.residual), 1)))


@dataclass(frozen=True, kw_only=True)
class HeldOut:
    """Errors on held-out rows (k-fold full refits), in the rows' unit."""
    rmse: float
    max_abs: float
    wrmse: float
    residual: np.ndarray           # (N,) held-out residual of each row
    folds: int


def at_bound(value, parameter) -> bool:
    """Whether a fitted value sits at a bound of its parameter (the at-bound rule: an
    effect that helps only there is not an explanation).

    Parameters
    ----------
    value : float
        Fitted value, in the parameter's unit.
    parameter : Parameter
        The parameter (bounds ``lo``, ``hi`` and ``typical`` value).

    Returns
    -------
    bool
        True within :data:`AT_BOUND_REL` x typical of either bound.
    """
    tol = AT_BOUND_REL * parameter.typical
    return value <= parameter.lo + tol or value >= parameter.hi - tol


def fold_count(groups: int, folds: int) -> int:
    """Folds of the k-fold held-out error over ``groups`` fold groups: ``folds``, but no
    more than the groups and no fewer than :data:`MIN_FOLDS`.

    Parameters
    ----------
    groups : int
        Fold groups (rows, or the groups the rows fall in).
    folds : int
        The folds asked for (:attr:`Settings.folds`).

    Returns
    -------
    int
    """
    return max(MIN_FOLDS, min(folds, groups))


def assign_folds(group, folds: int, seed: int, scheme: str) -> tuple:
    """Each row's fold: the rows' groups spread over the folds at random (:attr:`Rules.folds`).

    Parameters
    ----------
    group : array_like
        (N,) each row's fold group.
    folds : int
        The folds asked for.
    seed : int
        Seed of the shuffle.
    scheme : {"deal", "label"}
        How the shuffle becomes folds (:class:`Rules`).

    Returns
    -------
    tuple
        ((N,) fold of each row, number of folds).
    """
    groups, index = np.unique(np.asarray(group), return_inverse=True)
    k = fold_count(len(groups), folds)
    perm = np.random.default_rng(seed).permutation(len(groups))
    if scheme == "deal":
        of_group = np.empty(len(groups), int)
        of_group[perm] = np.arange(len(groups)) % k
    else:
        of_group = perm % k
    return of_group[np.asarray(index).reshape(-1)], k
