"""The efficiency of a run over its operating range, computed before anything is drawn:
against the output torque (each load source, the measured points' model values), over
torque and input speed, and over torque and oil temperature at the operating point's oil
from the heat balance (``toothfem run``; the pictures: :func:`toothfem.report.files.
efficiency_charts`)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .case import Case
from .efficiency import evaluate
from .efficiency.mesh_table import LoadsMemo
from .efficiency.thermal import heat_balance
from .errors import CaseError

#: Output torques of the efficiency curves and maps, as fractions of the largest torque of
#: the case (its operating point or a measured point): from near no load to 10 % beyond it,
#: so every marked point sits inside the chart, not on its edge.
TORQUE_GRID = np.linspace(0.02, 1.1, 55)


#: Input speeds of the speed map, as fractions of the operating speed.
SPEED_GRID = np.linspace(0.1, 2.0, 60)


#: Oil temperatures of the temperature map [deg C]; widened in OIL_TEMPERATURE_STEP_C steps
#: to take in the operating point's oil temperature (within the lubricant's range).
OIL_TEMPERATURE_GRID_C = np.linspace(20.0, 100.0, 41)


OIL_TEMPERATURE_STEP_C = 2.0


def oil_temperature_grid(oil_C: float, lubricant) -> np.ndarray:
    """The oil temperatures [deg C] of the temperature map: OIL_TEMPERATURE_GRID_C, widened
    to take in ``oil_C`` with a margin of one tenth of the range, within the lubricant's
    pour point and largest temperature.

    Parameters
    ----------
    oil_C : float
        The operating point's oil temperature [deg C].
    lubricant : toothfem.case_running.Lubricant
        Its ``pour_point_C`` and ``max_temperature_C`` bound the grid.

    Returns
    -------
    numpy.ndarray
        Ascending [deg C].
    """
    lo, hi = float(OIL_TEMPERATURE_GRID_C[0]), float(OIL_TEMPERATURE_GRID_C[-1])
    if lo <= oil_C <= hi:
        return OIL_TEMPERATURE_GRID_C
    margin = 0.1 * (max(hi, oil_C) - min(lo, oil_C))
    step = OIL_TEMPERATURE_STEP_C
    lo = max(min(lo, math.floor((oil_C - margin) / step) * step), lubricant.pour_point_C)
    hi = min(max(hi, math.ceil((oil_C + margin) / step) * step), lubricant.max_temperature_C)
    return np.linspace(lo, hi, int(round((hi - lo) / step)) + 1)


def operating_oil(case: Case, speed: float, torque: float, loads: str, memo=None) -> tuple:
    """The oil temperature [deg C] of the operating point and what it is: the heat
    balance's equilibrium with the run's loads (the report's heat balance), else the
    lubricant's reference temperature, said so.

    Parameters
    ----------
    case : toothfem.case.Case
    speed, torque : float
        Input speed [rpm] and output torque [N m].
    loads : {"analytic", "fem"}
        The loads of the run's heat balance.
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met.

    Returns
    -------
    (float, str)
        The temperature [deg C] and its words for a label.
    """

    try:
        oil = float(heat_balance(case, speed, torque, loads=loads,
                                 memo=LoadsMemo() if memo is None else memo).temperature_C[0])
    except CaseError as e:          # no balance below the oil's largest temperature
        ref = case.lubricant.reference_temperature_C
        return ref, (f"oil at {ref:g} deg C, the lubricant's reference (no heat balance: "
                     f"{str(e).split(':')[0]})")
    return oil, f"oil at {oil:.1f} deg C, the heat balance's equilibrium ({loads} loads)"



@dataclass(frozen=True, kw_only=True)
class EfficiencyMaps:
    """A run's efficiency over its operating range (module docstring). Speeds [rpm],
    torques [N m], temperatures [deg C], efficiencies [-]; grids are (speeds or
    temperatures, torques) as ``numpy.meshgrid`` makes them."""
    speed_rpm: float                 # the operating point
    torque_Nm: float
    sources: tuple                   # the load sources of the curves ("analytic", "fem")
    torque_grid_Nm: np.ndarray       # (T,) the curves' and maps' torques
    curve_speed_rpm: float           # the curves' speed: the measured points' where there
    curves: dict                     # {source: (T,)} at curve_speed_rpm
    operating_speed_curve: np.ndarray | None    # (T,) analytic at speed_rpm, if it differs
    operating_efficiency: float      # analytic, at the operating point
    measured_model: tuple            # the model's efficiency at each measured point
    speed_map: tuple                 # (torque (S, T), speed (S, T), efficiency (S, T))
    oil_C: float                     # the operating point's oil
    oil_words: str                   # what that temperature is
    temperature_map: tuple           # (torque (H, T), oil (H, T), efficiency (H, T))
    operating_oil_efficiency: float  # analytic, at the operating point and its oil


def efficiency_maps(case: Case, speed: float, torque: float, sources,
                    memo=None) -> EfficiencyMaps:
    """The efficiency of a case over its operating range (:class:`EfficiencyMaps`).

    Parameters
    ----------
    case : toothfem.case.Case
    speed, torque : float
        The operating point [rpm], [N m].
    sources : sequence of str
        The curves' load sources ("analytic", "fem"); the maps take the analytic loads,
        the heat balance the FE's where given.
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met (each table computed once for it).

    Returns
    -------
    EfficiencyMaps
    """
    sources = tuple(sources)
    t_max = max([torque] + [m.output_torque_Nm for m in case.measured])
    speed_curve = case.measured[0].input_speed_rpm if case.measured else speed
    t_grid = TORQUE_GRID * t_max
    memo = LoadsMemo() if memo is None else memo
    curves = {s: evaluate(case, speed_curve, t_grid, loads=s, memo=memo).efficiency
              for s in sources}
    at_speed = evaluate(case, speed, t_grid, memo=memo).efficiency if speed_curve != speed \
        else None
    measured = tuple(float(evaluate(case, m.input_speed_rpm, m.output_torque_Nm,
                                    memo=memo).efficiency[0]) for m in case.measured)
    tt, nn = np.meshgrid(t_grid, SPEED_GRID * speed)
    eta = evaluate(case, nn, tt, memo=memo).efficiency.reshape(nn.shape)
    oil_op, oil_words = operating_oil(case, speed, torque,
                                      "fem" if "fem" in sources else "analytic", memo)
    tt2, th = np.meshgrid(t_grid, oil_temperature_grid(oil_op, case.lubricant))
    eta_t = evaluate(case, speed, tt2, th, memo=memo).efficiency.reshape(th.shape)
    return EfficiencyMaps(
        speed_rpm=float(speed), torque_Nm=float(torque), sources=sources, torque_grid_Nm=t_grid,
        curve_speed_rpm=float(speed_curve), curves=curves, operating_speed_curve=at_speed,
        operating_efficiency=float(evaluate(case, speed, torque, memo=memo).efficiency[0]),
        measured_model=measured, speed_map=(tt, nn, eta), oil_C=oil_op, oil_words=oil_words,
        temperature_map=(tt2, th, eta_t),
        operating_oil_efficiency=float(evaluate(case, speed, torque, oil_op,
                                                memo=memo).efficiency[0]))
