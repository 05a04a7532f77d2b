"""Effects the data cannot tell apart, and the measurement that would.

When the selection finds several effects that explain the data equally well (BIC within
:attr:`Settings.alias_bic`), :func:`alias_group` reports them together: each member with
its fitted values and what they would mean physically, and the operating points where the
members' fitted models differ most against the noise, allowing each member to refit its
parameters to the new readings (:func:`separating_points`). Those are the points to
measure next: each is given with every member's predicted efficiency, the noise there and
how many repeated readings leave the wrong member a misfit of three standard deviations.
Where no operating point inside the reducer's range separates them (an exact
alias: a drag torque on the input and a zero offset of the input torque meter are the same
number to efficiency data), the group says so and lists each member's ``direct_test``, a
measurement away from the operating points that shows it.

The operating range searched (:func:`search_grid`): input speed from half the data's
lowest to 1.25 x its highest; output torque from a third of the data's lowest to the
larger of its highest and the case's rated torque; oil temperature, where the data have
it, 15 K either side of the data's, inside the oil's law and 0-100 C (a rig's oil
conditioning); time, where the data have it, from 0 to twice the data's longest.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from . import effects as fx
from .measured import sensor_sigma

#: Values per axis of the operating grid searched (4 axes: 5^4 = 625 points, a few model
#: evaluations of that size per member).
GRID_PER_AXIS = 5
#: Points proposed per group, and their least spacing on the grid's unit cube (so they do
#: not all sit in one corner).
PROPOSED_POINTS = 4
MIN_SPACING = 0.3
#: A difference of this many standard deviations tells two members apart (3 sigma: a
#: false call about 1 in 370 for one comparison).
SEPARATION_SIGMAS = 3.0
#: Most repeated readings proposed at one point; a point that needs more does not separate
#: the group in practice.
MAX_REPEATS = 25
#: Relative step of a member's parameter for its sensitivity (of its typical value or its
#: value, the larger; the model is smooth there).
SENSITIVITY_STEP = 1e-3
#: An axis along which the separation changes by less than this share of its largest value
#: does not matter to it (the proposed points leave it free).
AXIS_MATTERS = 0.01
#: Widening of the data's ranges for the search (module docstring).
SPEED_RANGE = (0.5, 1.25)
TORQUE_LOW = 1 / 3
OIL_MARGIN_K = 15.0
OIL_RIG_RANGE_C = (0.0, 100.0)
TIME_FACTOR = 2.0


@dataclass(frozen=True, kw_only=True)
class Member:
    """One effect of an alias group with its fitted values."""
    name: str
    values: dict                   # parameter name -> {"value", "unit"}
    meaning: str                   # what the fitted values would mean physically
    direct_test: str               # a measurement that shows it whatever the points


@dataclass(frozen=True, kw_only=True)
class ProposedPoint:
    """An operating point where the members' fitted models differ most against the noise."""
    input_speed_rpm: float
    output_torque_Nm: float
    oil_temp_C: float | None
    time_h: float | None
    efficiency: dict               # member name -> predicted efficiency [-]
    sigma: float                   # noise of one reading there [efficiency]
    separation: float              # misfit [sigmas] one reading leaves the wrong one of the
                                   # closest two members after it refits
    repeats: int                   # readings for a SEPARATION_SIGMAS misfit
    free: tuple = ()               # columns whose value does not change the separation


@dataclass(frozen=True, kw_only=True)
class AliasGroup:
    """Effects the data cannot tell apart at one selection step, and how to tell them apart."""
    step: int
    members: tuple                 # Member, the one added first
    points: tuple                  # ProposedPoint, best first
    separable: bool                # some point inside the range separates them
    note: str
    exact_pairs: tuple = ()        # (name, name) pairs no point separates

    def to_dict(self) -> dict:
        """The group as the report's JSON writes it (``alias_groups``).

        Returns
        -------
        dict
            Plain JSON types: the members, the proposed points, whether some point
            separates them, the pairs no point separates and the note.
        """
        return {"step": self.step, "separable": self.separable, "note": self.note,
                "exact_aliases": [list(p) for p in self.exact_pairs],
                "members": [{"name": m.name, "values": m.values, "meaning": m.meaning,
                             "direct_test": m.direct_test} for m in self.members],
                "proposed_points": [{
                    "input_speed_rpm": p.input_speed_rpm, "output_torque_Nm": p.output_torque_Nm,
                    "oil_temp_C": p.oil_temp_C, "time_h": p.time_h,
                    "efficiency": p.efficiency, "sigma": p.sigma,
                    "separation_sigmas": p.separation, "repeats": p.repeats,
                    "any_value_of": list(p.free)}
                    for p in self.points]}


def search_grid(case, points: fx.Points, n=GRID_PER_AXIS) -> fx.Points:
    """The operating points searched for a separating measurement (module docstring).

    Parameters
    ----------
    case : toothfem.case.Case
        Its rated torque and oil's temperature range widen or bound the search.
    points : Points
        The data's operating points.
    n : int
        Values per axis.

    Returns
    -------
    Points
        The grid, n^k points (k = 2, 3 or 4 axes: the data's oil temperature and time
        columns add theirs).
    """
    from ..lubricant import temperature_range

    s = np.asarray(points.speed_rpm, float)
    t = np.asarray(points.torque_Nm, float)
    rated = case.operating.rated_torque_Nm or 0.0
    axes = [np.linspace(SPEED_RANGE[0] * s.min(), SPEED_RANGE[1] * s.max(), n),
            np.linspace(TORQUE_LOW * t.min(), max(t.max(), rated), n)]
    if points.oil_temp_C is not None:
        lo, hi = temperature_range(case.to_si().lubricant)
        temp = np.asarray(points.oil_temp_C, float)
        axes.append(np.linspace(max(lo, OIL_RIG_RANGE_C[0], temp.min() - OIL_MARGIN_K),
                                min(hi, OIL_RIG_RANGE_C[1], temp.max() + OIL_MARGIN_K), n))
    if points.time_h is not None:
        axes.append(np.linspace(0.0, TIME_FACTOR * float(np.max(points.time_h)), n))
    grid = np.array(list(itertools.product(*axes))).T
    k = 2
    oil = time = None
    if points.oil_temp_C is not None:
        oil, k = grid[k], k + 1
    if points.time_h is not None:
        time = grid[k]
    return fx.Points(speed_rpm=grid[0], torque_Nm=grid[1], oil_temp_C=oil, time_h=time)


def _noise(prob, grid: fx.Points, eta: np.ndarray, scatter: float) -> np.ndarray:
    """(G,) standard deviation of one efficiency reading at the grid's points: the rig's
    torque sensors where the data name them, else the data's scatter about the fit."""
    sensors = prob.data.provenance.get("sensors") if prob.data.provenance else None
    if sensors:
        t_in = grid.torque_Nm / (abs(prob.case.ratio()) * eta)
        sigma = sensor_sigma(eta, t_in, grid.torque_Nm, sensors)
        if sigma is not None:
            return np.asarray(sigma, float)
    return np.full(len(grid), scatter)


def separating_points(prob, fits: dict) -> tuple:
    """The operating points where the members, each refitted to the data plus the new
    readings, still differ most against the noise.

    Each member's fitted model is evaluated over :func:`search_grid`. Where two members
    differ by d and n readings of noise sigma are added there, both refit their parameters
    (covariances C_a, C_b from their fits on the data, sensitivities g_a, g_b at the
    point): the truth is one member at parameters the data know only to C, and the other
    mimics it as far as its own C lets it. The misfit left is chi^2 = n d^2 / (sigma^2 +
    n q) with q = g_a^T C_a g_a + g_b^T C_b g_b (Sherman-Morrison: the rank-one update of a
    least-squares fit); the readings separate the pair when chi^2 >= SEPARATION_SIGMAS^2,
    with n >= 9 sigma^2 / (d^2 - 9 q) readings, and never where d^2 <= 9 q (the refits
    absorb the difference). The effects added before the group are held at their values.

    Parameters
    ----------
    prob : problem.Problem
        The data, case and (bounded) effects.
    fits : dict of str to engine.Fit
        Member name -> its fit (the effects before it plus the member, all data).

    Returns
    -------
    tuple
        (tuple of ProposedPoint, best first; the largest separation with MAX_REPEATS
        readings of the pairs some point separates [sigmas]; the pairs of names no point
        separates).
    """
    grid = search_grid(prob.case, prob.points)
    eta, q = {}, {}
    for name, f in fits.items():
        eta[name], q[name] = _member_at(prob, grid, name, f)
    names = list(eta)
    scatter = min(math.sqrt(f.wrss / max(prob.n - f.n_params, 1)) for f in fits.values())
    sigma = _noise(prob, grid, eta[names[0]], scatter)
    pairs = {}
    for a, b in itertools.combinations(names, 2):
        d2 = (eta[a] - eta[b]) ** 2
        qq = q[a] + q[b]
        pairs[(a, b)] = (np.sqrt(d2 / (sigma ** 2 + qq)),                    # one reading
                         np.sqrt(MAX_REPEATS * d2 / (sigma ** 2 + MAX_REPEATS * qq)),
                         _readings(d2, qq, sigma))
    # pairs no point separates are exact aliases (each needs its direct test); the points
    # are chosen for the others, by the separation the most readings give
    exact = tuple(pr for pr, v in pairs.items() if not float(v[1].max()) >= SEPARATION_SIGMAS)
    rest = [v for pr, v in pairs.items() if pr not in exact] or list(pairs.values())
    gap = np.min([v[1] for v in rest], axis=0)
    one = np.min([v[0] for v in rest], axis=0)
    need = np.max([v[2] for v in rest], axis=0)
    # positions on the unit cube of the searched ranges, along the axes the separation
    # changes with (the grid is a product of GRID_PER_AXIS values per axis): the proposed
    # points spread out where it matters
    cols = {k: c for k, c in (("input_speed_rpm", grid.speed_rpm),
                              ("output_torque_Nm", grid.torque_Nm),
                              ("oil_temp_C", grid.oil_temp_C), ("time_h", grid.time_h))
            if c is not None}
    cube = gap.reshape((GRID_PER_AXIS,) * len(cols))
    free = tuple(k for a, k in enumerate(cols)
                 if float(np.max(np.ptp(cube, axis=a))) <= AXIS_MATTERS * float(gap.max()))
    unit = np.stack([(c - c.min()) / (np.ptp(c) or 1.0) for k, c in cols.items()
                     if k not in free] or [np.zeros_like(gap)], axis=1)
    chosen: list[int] = []
    for j in np.lexsort((-gap, need)):          # fewest readings first, then widest apart
        if len(chosen) == PROPOSED_POINTS:
            break
        if all(np.linalg.norm(unit[j] - unit[k]) >= MIN_SPACING for k in chosen):
            chosen.append(int(j))
    out = tuple(ProposedPoint(
        input_speed_rpm=float(grid.speed_rpm[j]), output_torque_Nm=float(grid.torque_Nm[j]),
        oil_temp_C=None if grid.oil_temp_C is None else float(grid.oil_temp_C[j]),
        time_h=None if grid.time_h is None else float(grid.time_h[j]),
        efficiency={n: float(eta[n][j]) for n in names}, sigma=float(sigma[j]),
        separation=float(one[j]), repeats=int(need[j]), free=free) for j in chosen)
    return out, float(gap.max()), exact


def _member_at(prob, grid, name, fit):
    """(efficiency (G,), q = g^T C g (G,)) of a member's fitted model over the grid: g its
    efficiency's sensitivity to its own parameters, C their (diagonal) covariance from the
    fit's standard errors."""
    assignment = {prob.effects[n]: fit.values[n] for n in fit.effects}
    eff = prob.effects[name]
    base = fx.predict(prob.case, grid, assignment, loads=prob.loads, memo=prob.memo).efficiency
    q = np.zeros_like(base)
    values = list(fit.values[name])
    for j, (p, se) in enumerate(zip(eff.parameters, fit.stderr[name])):
        if not math.isfinite(se) or se <= 0:
            continue
        h = SENSITIVITY_STEP * max(abs(values[j]), p.typical)
        moved = values[j] + h if values[j] + h <= p.hi else values[j] - h
        trial = dict(assignment)
        trial[eff] = tuple(moved if k == j else v for k, v in enumerate(values))
        g = (fx.predict(prob.case, grid, trial, loads=prob.loads,
                        memo=prob.memo).efficiency - base) / (
            moved - values[j])
        q += (g * se) ** 2
    return base, q


def _readings(d2, q, sigma):
    """Readings n at each point for a SEPARATION_SIGMAS misfit after the refit, n = 9
    sigma^2 / (d^2 - 9 q); MAX_REPEATS + 1 where more, or none, would do."""
    s2 = SEPARATION_SIGMAS ** 2
    room = d2 - s2 * q
    with np.errstate(divide="ignore", invalid="ignore"):
        n = np.where(room > 0, np.ceil(s2 * sigma ** 2 / room), np.inf)
    return np.clip(n, 1, MAX_REPEATS + 1).astype(int)


def _member(eff, values) -> Member:
    """A member's values and what they would mean."""
    vals = {p.name: {"value": float(v), "unit": p.unit} for p, v in zip(eff.parameters, values)}
    return Member(name=eff.name, values=vals, meaning=eff.summary, direct_test=eff.direct_test)


def alias_group(prob, step: int, fits: dict) -> AliasGroup:
    """An alias group of one selection step: the members, their fitted values and meaning,
    and the measurement that would separate them (module docstring).

    Parameters
    ----------
    prob : problem.Problem
        The data, case and effects.
    step : int
        The selection step (1-based).
    fits : dict of str to engine.Fit
        Member name -> its fit, the added effect first.

    Returns
    -------
    AliasGroup
    """
    members = tuple(_member(prob.effects[n], f.values[n]) for n, f in fits.items())
    points, best, exact = separating_points(prob, fits)
    separable = best >= SEPARATION_SIGMAS
    parts = []
    if separable:
        p = points[0]
        parts.append(
            f"the data cannot tell {', '.join(fits)} apart; measure at the proposed points "
            f"(best: {p.input_speed_rpm:.0f} rpm, {p.output_torque_Nm:.4g} N m"
            + ("" if p.oil_temp_C is None or "oil_temp_C" in p.free
               else f", {p.oil_temp_C:.0f} C")
            + ("" if p.time_h is None or "time_h" in p.free else f", {p.time_h:.3g} h")
            + (f"; any {' and '.join(p.free)}" if p.free else "")
            + f": one reading there tells the closest two members apart by "
              f"{p.separation:.2g} sigma after they refit, {p.repeats} reading(s) by 3 "
              "sigma)")
    if exact:
        alike = sorted({n for pr in exact for n in pr}, key=list(fits).index)
        every = len(exact) == len(fits) * (len(fits) - 1) // 2
        parts.append(
            "no operating point in the range searched separates "
            + (f"any two of {', '.join(fits)}" if every else
               "; ".join(f"{a} from {b}" for a, b in exact))
            + (f" (at best {best:.2g} sigma with {MAX_REPEATS} readings, after the "
               "refit)" if not separable else "")
            + ": measure " + ("one of them" if len(alike) == 2 else "them")
            + " directly (" + "; ".join(f"{m.name}: {m.direct_test}" for m in members
                                        if m.name in alike and m.direct_test) + ")")
    return AliasGroup(step=step, members=members, points=points if separable else (),
                      separable=bool(separable), note=". ".join(parts),
                      exact_pairs=tuple(exact))
