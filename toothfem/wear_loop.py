"""The wear effect for a rig's long-run data: a reducer's lost motion logged against its
running hours, fitted with the loops' engine (efficiency/loop/engine) to the wear model of
``toothfem wear`` (docs/wear.md, "Fitting the coefficient").

Every wear rate of the model is proportional to the wear coefficient K_b (Archard's law;
the regime, the run-in and the loads depend on the worn state alone), so the worn state
after t hours at K_b is the state after K_b t / K_ref hours at K_ref: one run of the wear
model at K_ref gives the lost motion at every (t, K_b) with K_b t <= K_ref T, by
interpolation in the product. The effects: ``wear`` (log10 K_b, the clearances growing
with the logged hours) and ``initial_lost_motion`` (the rig's reducer's lost motion new,
off the model's by its build: its tolerances).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .case import Case, as_case
from .efficiency.loop import engine as en
from .efficiency.loop.settings import Settings
from .errors import CaseError, check_range
from .wear import DEFAULT_POSITIONS, wear_analysis

#: The fitted log10 K_b's bounds: three decades about the default 1e-8 where the
#: published RV test lies (docs/wear.md; the mild wear of lubricated steel spans more, a
#: wider box costs the curve's run more rows).
LOG10_K_BOUNDS = (-10.5, -7.5)
#: The fitted parameter is log10(K_b / K_UNIT) (the engine scales a parameter by its typical
#: value: a positive one keeps its bounds in order).
K_UNIT = 1e-12
#: The curve's rows per decade of K_b t (geometric: the run-in is in the first decades).
ROWS_PER_DECADE = 4
#: The new reducer's lost motion off the model's [arcmin]: +-0.5, half the RV-40E's
#: catalogue figure (a build within its tolerances: docs/tolerance.md's ensembles span less).
OFFSET_BOUNDS_ARCMIN = (-0.5, 0.5)
#: How the wear fit runs (the engine's rules, each with its reason).
WEAR_RULES = en.Rules(
    fd_step=1e-3,            # the model is an interpolation, smooth at this step
    fit_tol=1e-10,           # each evaluation costs microseconds
    starts="restart",        # from the first start, the others while the best ends at a bound
    folds="label",           # each logged row its own group
    scoring="joint",         # two parameters: fitted together
    rank="bic",              # as the TE loop
    tie_bic=0.0,             # an exact tie only
    aliases="passing",       # as the efficiency loop
    alias_separation=0.0,    # none by distance
    exclude_aliases=False,
    prune_fraction=None,     # no selection here: one fit
    pairs=False)


@dataclass(frozen=True)
class WearEffect:
    """An effect of the wear fit (the engine's Effect): its name and bounded parameters,
    what it means and the measurement that tells it apart."""
    name: str
    parameters: tuple
    summary: str
    direct_test: str


EFFECTS = (
    WearEffect("wear", (en.parameter("log10_wear_coefficient_over_1e-12", "-",
                                     LOG10_K_BOUNDS[0] - math.log10(K_UNIT),
                                     LOG10_K_BOUNDS[1] - math.log10(K_UNIT), 3.0,
                                     starts=(3.0, 4.0, 2.0)),),
               "the clearances growing with the logged hours at Archard's K_b (pins, disc "
               "flanks, crank and support bearings): the lost motion's growth",
               "the pins' and races' worn depth at a teardown (profile and roundness), or the "
               "lost motion logged over the hours"),
    WearEffect("initial_lost_motion", (en.parameter("lost_motion_offset_arcmin", "arcmin",
                                                    *OFFSET_BOUNDS_ARCMIN, 0.05,
                                                    starts=(0.0,)),),
               "the reducer's lost motion new off the model's (its build within the "
               "tolerances): the log's level at 0 h",
               "the lost motion at +-3 % of the rated torque before the run"),
)


@dataclass(frozen=True)
class WearLog:
    """A rig's long-run log (the engine's Observations): the lost motion [arcmin] at the
    running hours, each row weighted by 1 / its standard deviation."""
    hours: np.ndarray
    values: np.ndarray
    weight: np.ndarray

    @property
    def group(self) -> np.ndarray:
        """Each row its own fold group."""
        return np.arange(self.values.size)


class WearCurve:
    """The wear model's lost motion at any (hours, K_b) with K_b hours inside its run: the
    run's lost motion against K_b t (module docstring), interpolated; the engine's Model
    on a log's hours.

    Parameters
    ----------
    kt : array_like
        K_b t of the run's rows [h], increasing from 0.
    lost_motion_arcmin : array_like
        The lost motion at each [arcmin].
    hours : array_like
        The log's hours (the rows :meth:`predict` gives).
    """

    def __init__(self, kt, lost_motion_arcmin, hours):
        self.kt = np.asarray(kt, float)
        self.lost = np.asarray(lost_motion_arcmin, float)
        self.hours = np.asarray(hours, float)

    @classmethod
    def of_case(cls, case: Case, hours, *, positions: int = DEFAULT_POSITIONS,
                rows_per_decade: int = ROWS_PER_DECADE) -> WearCurve:
        """One run of the wear model at the largest K_b of LOG10_K_BOUNDS over the log's
        hours, its rows geometric in K_b t from the least K_b at the least nonzero hours.

        Parameters
        ----------
        case : toothfem.case.Case
        hours : array_like
            The log's hours (one at least above 0).
        positions : int
            The run's positions (:func:`toothfem.wear.wear_analysis`).
        rows_per_decade : int
            The run's rows per decade of K_b t.

        Returns
        -------
        WearCurve
        """
        h = np.asarray(hours, float)
        k_ref = 10.0 ** LOG10_K_BOUNDS[1]
        top = float(np.max(h))
        low = float(np.min(h[h > 0])) * 10.0 ** (LOG10_K_BOUNDS[0] - LOG10_K_BOUNDS[1])
        n = max(2, int(math.ceil(rows_per_decade * math.log10(top / low))))
        times = np.concatenate([[0.0], np.geomspace(low, top, n + 1)])
        times[-1] = top
        run = wear_analysis(case, top, wear_coefficient=k_ref, positions=positions,
                            times=times)
        return cls([r["hours"] * k_ref for r in run.history],
                   [r["lost_motion_arcmin"] for r in run.history], h)

    def lost_motion(self, hours, k: float) -> np.ndarray:
        """The model's lost motion at the hours for K_b = k.

        Parameters
        ----------
        hours : array_like
            [h].
        k : float
            K_b [-].

        Returns
        -------
        numpy.ndarray
            [arcmin], the hours' shape.
        """
        return np.interp(np.asarray(hours, float) * k, self.kt, self.lost)

    def predict(self, names, values) -> np.ndarray:
        """The log's rows with the effects ``names`` at ``values`` (the engine's Model).

        Parameters
        ----------
        names : tuple of str
            Of EFFECTS.
        values : array_like
            Their parameters, in order.

        Returns
        -------
        numpy.ndarray
            The lost motion at the log's hours [arcmin].
        """
        k, offset = 0.0, 0.0
        for i, name in enumerate(names):
            if name == "wear":
                k = K_UNIT * 10.0 ** float(values[i])
            elif name == "initial_lost_motion":
                offset = float(values[i])
            else:
                raise KeyError(f"not a wear effect: {name!r}")
        return self.lost_motion(self.hours, k) + offset


@dataclass(frozen=True)
class WearFit:
    """The fitted wear coefficient with its standard error (from log10 K_b's), the new
    lost motion's offset, and the engine's fit."""
    wear_coefficient: float
    wear_coefficient_stderr: float
    lost_motion_offset_arcmin: float
    fit: en.Fit


def fit_wear(case, hours, lost_motion_arcmin, *, sigma_arcmin: float = 0.01,
             positions: int = DEFAULT_POSITIONS,
             rows_per_decade: int = ROWS_PER_DECADE) -> WearFit:
    """Fit K_b (and the new lost motion's offset) to a logged lost motion over hours, on
    the case's wear model (:meth:`WearCurve.of_case`).

    Parameters
    ----------
    case : toothfem.case.Case
    hours, lost_motion_arcmin : array_like
        The log: running hours [h] (>= 0, at least 3 rows, one above 0) and the lost motion
        at each [arcmin].
    sigma_arcmin : float
        The log's standard deviation [arcmin] (> 0).
    positions, rows_per_decade : int
        The wear curve's.

    Returns
    -------
    WearFit

    Raises
    ------
    CaseError
        For a log of other than matching, finite rows, negative hours or fewer than 3 rows.
    """
    h, y = _checked_log(hours, lost_motion_arcmin, sigma_arcmin)
    curve = WearCurve.of_case(as_case(case), h, positions=positions,
                              rows_per_decade=rows_per_decade)
    return fit_log(curve, h, y, sigma_arcmin=sigma_arcmin)


def _checked_log(hours, lost_motion_arcmin, sigma_arcmin):
    h = np.asarray(hours, float)
    y = np.asarray(lost_motion_arcmin, float)
    if h.shape != y.shape or h.ndim != 1 or h.size < 3:
        raise CaseError(f"hours and lost_motion_arcmin: {h.size} and {y.size} rows; valid: "
                        "as many of each, at least 3")
    if not (np.all(np.isfinite(h)) and np.all(np.isfinite(y)) and np.all(h >= 0)
            and np.any(h > 0)):
        raise CaseError("hours and lost_motion_arcmin: finite, hours >= 0 and one above 0")
    check_range("sigma_arcmin", sigma_arcmin, 0.0, None, lo_open=True, error=CaseError)
    return h, y


def fit_log(curve: WearCurve, hours, lost_motion_arcmin, *,
            sigma_arcmin: float = 0.01) -> WearFit:
    """Fit the ``wear`` and ``initial_lost_motion`` effects to a log on a wear curve, with
    the loops' engine.

    Parameters
    ----------
    curve : WearCurve
        Its ``hours`` the log's.
    hours, lost_motion_arcmin : array_like
        The log.
    sigma_arcmin : float
        Its standard deviation [arcmin].

    Returns
    -------
    WearFit
    """
    h, y = _checked_log(hours, lost_motion_arcmin, sigma_arcmin)
    log = WearLog(h, y, np.full(h.size, 1.0 / sigma_arcmin))
    engine = en.Engine(log, EFFECTS, curve, rules=WEAR_RULES, settings=Settings())
    fit = engine.fit(("wear", "initial_lost_motion"))
    lk, = fit.values["wear"]
    lk_se, = fit.stderr["wear"]
    k = K_UNIT * 10.0 ** lk
    return WearFit(wear_coefficient=k, wear_coefficient_stderr=k * math.log(10.0) * lk_se,
                   lost_motion_offset_arcmin=fit.values["initial_lost_motion"][0], fit=fit)
