"""Effects of the rig rather than of the reducer: what its sensors read is not what the
reducer did.

An efficiency rig reads the input torque T1, the output torque T2 and the oil temperature;
its efficiency column is T2 / (|i| T1). Each effect here changes the reading, not the
reducer's losses, so it sets no case field (``final_case`` leaves the case as it was) and
says in ``direct_test`` how a measurement away from the operating points would show it:

* ``input_torque_offset``: a zero offset d1 of the input torque meter, T1_read = T1 + d1;
* ``output_torque_offset``: a zero offset d2 of the output torque meter, T2_read = T2 + d2
  (the reducer ran at T2_read - d2);
* ``oil_temp_offset``: the oil temperature sensor reads dT above the oil (a Pt100's
  tolerance, or a sensor placed on the housing wall or the return line instead of the
  sump), so the reducer ran at T_read - dT;
* ``warm_up``: the oil warms along the run, T = T_read + dT_inf (1 - exp(-t / tau)), while
  the logged temperature does not follow (a sensor that logs its first value, a column
  filled in by hand); the rise dT_inf and the time constant tau are bounded by the
  housing's heat balance (:mod:`toothfem.efficiency.thermal`).

The zero offsets and the drag torque on the input are one and the same to efficiency data
(a drag T_d on the input is T1 + T_d, an offset is T1 + d1): no operating point tells them
apart, which the loop reports with each one's ``direct_test``.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ...fem.drives import drive_for
from ..evaluation import evaluate
from ..lubricant import temperature_range
from ..thermal import housing, shed_per_kelvin
from .effect_base import Effect, Parameter
from ...units import S_PER_H

#: Largest zero offset the fit may take, as a share of the smallest torque the meter read
#: (for the input meter, the smallest lossless input torque T2/|i|, below its true
#: reading): a strain-gauge torque transducer's zero drifts by a few 0.01 % of its range
#: per 10 K (class 0.05-0.2, DIN 51309 / EURAMET cg-14), a meter not zeroed before the run
#: by more; an offset of half the smallest reading would halve that reading, which any
#: plausibility check of the rig sees. The bound only keeps the fit physical.
OFFSET_SHARE = 0.5
#: Largest temperature sensor offset [K]: a Pt100 of class B is within 0.3 + 0.005 |T| K
#: (IEC 60751:2022), about 0.8 K at 100 C; a sensor on the housing wall or in the return
#: line instead of the sump reads up to about 10-15 K off in a reducer at its thermal
#: equilibrium (ISO/TR 14179-1 takes the housing surface 0-10 K below the oil).
TEMP_OFFSET_MAX_K = 15.0
#: The warm-up's rise is at most this many times the housing's steady rise R P_max at the
#: data's largest loss: the heat balance's convection and radiation coefficients and the
#: heat the rig's shafts and couplings conduct away are known to about a factor of two.
WARM_RISE_MARGIN = 2.0
#: Its time constant lies within this factor of the heat balance's C / (h A) either way
#: (the housing's capacity is an estimate: half the envelope's steel; a rig's shafts,
#: couplings and base plate add to it).
WARM_TAU_FACTOR = 4.0


def _offset_bounds(smallest):
    """((lo, hi, typical),) of a zero offset for a meter whose smallest reading is given."""
    hi = OFFSET_SHARE * float(smallest)
    return ((-hi, hi, hi / 20),)


def _input_bounds(case, points):
    return _offset_bounds(np.min(points.torque_Nm) / abs(case.ratio()))


def _output_bounds(case, points):
    return _offset_bounds(np.min(points.torque_Nm))


def input_torque_offset() -> Effect:
    """Zero offset of the input torque meter: T1_read = T1 + d1.

    Returns
    -------
    Effect
        Parameter input_offset_Nm [N m]; no case field (the rig's, not the reducer's).
    """
    return Effect(
        name="input_torque_offset",
        summary="zero offset of the input torque meter (the rig's reading, not the reducer)",
        equation="T1_read = T1 + d1; eta_read = T2 / (|i| (T1 + d1))",
        citation="zero signal of a torque transducer: DIN 51309:2005, EURAMET cg-14 (2011)",
        parameters=(Parameter("input_offset_Nm", "N m", -1e6, 1e6, (0.0,), 1.0,
                              "input torque meter zero offset d1"),),
        case_fields=(), set_fields=lambda case, values: case,
        declared_by=lambda case: None,
        reading=lambda t1, t2, v: (t1 + v[0], t2), bounds_for=_input_bounds,
        direct_test="read the input torque meter with its shaft uncoupled (no torque) before "
                    "and after the run: the reading is the offset; or run both directions "
                    "of rotation: a drag changes sign with the direction, an offset does not")


def _output_true(case, points, values):
    return dataclasses.replace(points, torque_Nm=np.asarray(points.torque_Nm) - values[0])


def output_torque_offset() -> Effect:
    """Zero offset of the output torque meter: T2_read = T2 + d2, the reducer ran at
    T2_read - d2.

    Returns
    -------
    Effect
        Parameter output_offset_Nm [N m]; no case field (the rig's, not the reducer's).
    """
    return Effect(
        name="output_torque_offset",
        summary="zero offset of the output torque meter (the reducer ran at T2_read - d2)",
        equation="T2_read = T2 + d2; eta_read = (T2 + d2) / (|i| T1)",
        citation="zero signal of a torque transducer: DIN 51309:2005, EURAMET cg-14 (2011)",
        parameters=(Parameter("output_offset_Nm", "N m", -1e6, 1e6, (0.0,), 1.0,
                              "output torque meter zero offset d2"),),
        case_fields=(), set_fields=lambda case, values: case,
        declared_by=lambda case: None, true_points=_output_true,
        reading=lambda t1, t2, v: (t1, t2 + v[0]), bounds_for=_output_bounds,
        direct_test="read the output torque meter with the brake released and the shaft "
                    "uncoupled (no torque): the reading is the offset")


def _needs_oil_column(case, points):
    if points.oil_temp_C is None:
        return "the data has no oil_temp_C column (no sensor to be offset)"
    return None


def _oil_limits(case):
    """(lowest, highest) oil temperature of the case's viscosity law [deg C]."""
    return temperature_range(case.to_si().lubricant)


def _temp_offset_bounds(case, points):
    lo_c, hi_c = _oil_limits(case)
    t = np.asarray(points.oil_temp_C, float)
    # T = T_read - dT inside the law's range: dT < min(T_read) - lo_c, dT > max(T_read) - hi_c
    return ((max(-TEMP_OFFSET_MAX_K, float(np.max(t)) - hi_c),
             min(TEMP_OFFSET_MAX_K, float(np.min(t)) - lo_c), 1.0),)


def _oil_true(case, points, values):
    return dataclasses.replace(points, oil_temp_C=np.asarray(points.oil_temp_C) - values[0])


def oil_temp_offset() -> Effect:
    """The oil temperature sensor reads dT above the oil: the reducer ran at T_read - dT.

    Returns
    -------
    Effect
        Parameter sensor_offset_K [K]; no case field (the rig's, not the reducer's).
    """
    return Effect(
        name="oil_temp_offset",
        summary="oil temperature sensor reading above (or below) the oil in the sump",
        equation="T = T_read - dT",
        citation="IEC 60751:2022 (Pt100 tolerance classes); ISO/TR 14179-1:2001 (housing "
                 "surface below the oil)",
        parameters=(Parameter("sensor_offset_K", "K", -TEMP_OFFSET_MAX_K, TEMP_OFFSET_MAX_K,
                              (0.0, -5.0, 5.0), 1.0, "temperature sensor offset dT"),),
        case_fields=(), set_fields=lambda case, values: case,
        declared_by=lambda case: None, not_applicable=_needs_oil_column,
        true_points=_oil_true, bounds_for=_temp_offset_bounds,
        direct_test="a calibrated thermometer in the sump beside the sensor at two "
                    "temperatures (a cold start and the warm equilibrium)")


def _needs_time(case, points):
    if points.time_h is None:
        return "the data has no time_h column (a warm-up is a drift along the time)"
    if float(np.ptp(points.time_h)) <= 0:
        return "time_h is one value: no warm-up to see"
    return None


def heat_balance_scales(case, points) -> tuple:
    """The housing's steady rise at the data's largest loss, R P_max [K], and its time
    constant C / (h A) [h] at the data's oil temperature (:mod:`toothfem.efficiency.thermal`).

    Parameters
    ----------
    case : toothfem.case.Case
        The case (its housing and losses).
    points : Points
        The operating points (oil at the column's or the reference temperature).

    Returns
    -------
    tuple of float
        (rise [K], time constant [h]).
    """
    oil = points.oil_or_reference(case)
    ev = evaluate(case, points.speed_rpm, points.torque_Nm, oil)
    loss = float(np.max(sum(ev.losses_W.values())))
    h = housing(case.to_si(), drive_for(case))
    per_kelvin = float(np.mean(shed_per_kelvin(h, oil)))
    return loss / per_kelvin, h.heat_capacity_J_K / per_kelvin / S_PER_H


def _warm_bounds(case, points):
    rise, tau = heat_balance_scales(case, points)
    room = _oil_limits(case)[1] - float(np.max(points.oil_or_reference(case)))
    top = min(WARM_RISE_MARGIN * rise, room)
    return ((0.0, top, max(top / 10, 0.1), (top / 4, top / 2)),
            (tau / WARM_TAU_FACTOR, tau * WARM_TAU_FACTOR, tau, (tau, tau / 2, 2 * tau)))


def _warm_true(case, points, values):
    rise, tau = values
    oil = points.oil_or_reference(case)
    t = np.asarray(points.time_h, float)
    return dataclasses.replace(points, oil_temp_C=oil + rise * (1.0 - np.exp(-t / tau)))


def warm_up() -> Effect:
    """The oil warming along the run while the logged temperature does not follow.

    T(t) = T_read + dT_inf (1 - exp(-t/tau)): a first-order approach from the start
    temperature (the logged one) to the warm equilibrium, t the data's ``time_h``. The rise
    is bounded by the housing's heat balance, :data:`WARM_RISE_MARGIN` x R P_max, and tau
    by a factor :data:`WARM_TAU_FACTOR` either way of its C / (h A).

    Returns
    -------
    Effect
        Parameters warm_rise_K [K] and time_constant_h [h]; no case field (the rig's log).
    """
    return Effect(
        name="warm_up",
        summary="oil warming along the run (first-order, bounded by the heat balance) that "
                "the logged oil temperature does not show",
        equation="T = T_read + dT_inf (1 - exp(-t / tau))",
        citation="lumped heat balance, ISO/TR 14179-1:2001; toothfem efficiency/thermal.py",
        parameters=(Parameter("warm_rise_K", "K", 0.0, 200.0, (5.0, 15.0, 30.0), 5.0,
                              "rise of the oil once warm, dT_inf"),
                    Parameter("time_constant_h", "h", 1e-3, 1e3, (1.0, 3.0), 1.0,
                              "time constant of the warm-up, tau")),
        case_fields=(), set_fields=lambda case, values: case,
        declared_by=lambda case: None, not_applicable=_needs_time,
        true_points=_warm_true, bounds_for=_warm_bounds,
        direct_test="a thermometer in the sump logged along the run (or the run repeated "
                    "after the reducer has reached its equilibrium temperature)")
