"""The loop's ``thermal`` effect: the oil where the losses are made runs warmer than the
sump sensor that the data's ``oil_temp_C`` column reads.

A lumped thermal resistance R [K/W] between the loss sites and the sensor (the housing's
lumped heat balance, efficiency/thermal.py, seen from the sensor; the case field
``thermal.sensor_resistance_K_W``, read by this effect only): the oil at a point is
T = T_sensor + dT with

    dT = R P(T_sensor + dT) (1 - exp(-t / (R C)))

P the model's losses at that temperature, C the case's heat capacity (``[thermal]``, or the
default of efficiency/thermal.py) and t the operating time when the data carry a
``time_h`` column (the warm-up of a rig run: the efficiency drifts while the sensor does
not); without time, the steady state (the factor is 1). R is the fitted parameter; the time
constant is then tau = R C. The loss beside the model is P(T_sensor + dT) - P(T_sensor),
each component's temperature response tabulated once per data set and model case on a grid
of dT (:class:`ThermalTables`, with the analytic load split) and interpolated; the fixed
point is found on that grid.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...errors import MeasuredDataError
from ...fem.drives import drive_for
from ..evaluation import evaluate
from ..lubricant import temperature_range
from ..thermal import housing
from .effect_base import Effect, Parameter, Points, declared_if_changed, setter
from ...units import S_PER_H

#: Points of the dT grid from 0 to the oil's upper limit, spaced geometrically from
#: GRID_FIRST_K (the losses are smooth in T and nearly exponential through the viscosity:
#: interpolated in their logarithm; each point costs a model evaluation per model case).
GRID_POINTS = 8
GRID_FIRST_K = 0.5
#: Model cases whose tables are kept per data set.
TABLES_KEPT = 16
#: The case field of the fitted resistance (read by this effect only).
FIELD = "thermal.sensor_resistance_K_W"


def _model_key(case):
    """The sections a model evaluation depends on (hashable frozen records)."""
    return (case.lubricant, case.friction, case.material, case.cycloid, case.sine,
            case.first_stage, case.output_mechanism, case.seals, case.bearings, case.thermal)


@dataclass(eq=False)
class ThermalTables:
    """Each loss component at the points over a grid of temperature rises, per model case
    (filled on first use)."""
    points: Points
    rise_K: np.ndarray               # (G,)
    tables: dict = field(default_factory=dict)

    def components(self, case) -> dict:
        """Each loss component of ``case`` at T_sensor + rise (filled on first use).

        Parameters
        ----------
        case : toothfem.case.Case
            The model case.

        Returns
        -------
        dict of str to numpy.ndarray
            {component: (M, G) losses [W]}.
        """
        key = _model_key(case)
        hit = self.tables.get(key)
        if hit is None:
            pts = self.points
            if pts.oil_temp_C is None:
                raise MeasuredDataError("the thermal effect needs the data's oil_temp_C column "
                                        "(the sensor the warmer oil is measured against)")
            cols = [evaluate(case, pts.speed_rpm, pts.torque_Nm, pts.oil_temp_C + dt).losses_W
                    for dt in self.rise_K]
            hit = {k: np.stack([c[k] for c in cols], axis=1) for k in cols[0]}
            if len(self.tables) >= TABLES_KEPT:
                self.tables.pop(next(iter(self.tables)))
            self.tables[key] = hit
        return hit


def thermal_tables(case, points) -> ThermalTables:
    """The grid of temperature rises for these points: 0 up to the oil's upper limit above
    the warmest sensor reading.

    Parameters
    ----------
    case : toothfem.case.Case
        The case whose oil limit bounds the grid.
    points : Points
        The operating points (with oil temperatures [deg C]).

    Returns
    -------
    ThermalTables
        The grid [K]; the tables are filled on first use.
    """
    hi = temperature_range(case.to_si().lubricant)[1]
    top = max(hi - float(np.max(points.oil_temp_C)), 0.0)
    if top <= 0.0:                   # the sensor already reads the oil's limit: no room
        return ThermalTables(points=points, rise_K=np.zeros(1))
    grid = np.geomspace(min(GRID_FIRST_K, top / 2), top, GRID_POINTS - 1)
    return ThermalTables(points=points, rise_K=np.concatenate([[0.0], grid]))


def _row_interp(x, grid, values):
    """Per-row interpolation of positive (M, G) ``values`` at (M,) ``x`` on ``grid`` (G,),
    linear in their logarithm (a loss that follows the viscosity is nearly exponential in
    the temperature)."""
    idx = np.clip(np.searchsorted(grid, x) - 1, 0, grid.size - 2)
    x0, x1 = grid[idx], grid[idx + 1]
    w = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
    rows = np.arange(values.shape[0])
    v0, v1 = values[rows, idx], values[rows, idx + 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        logged = v0 * (v1 / v0) ** w
    return np.where((v0 > 0) & (v1 > 0), logged, (1 - w) * v0 + w * v1)


def rise(total, grid, resistance, factor):
    """The fixed point dT = R phi P(dT) per point on the tabulated losses: the first crossing
    of R phi P(dT) - dT on the grid, interpolated (the grid's end if there is none: the
    oil's limit).

    Parameters
    ----------
    total : numpy.ndarray, shape (M, G)
        Total loss P [W] at each rise of ``grid``.
    grid : numpy.ndarray, shape (G,)
        Temperature rises [K], from 0.
    resistance : float
        Thermal resistance R [K/W].
    factor : numpy.ndarray, shape (M,)
        phi, the share of the steady rise reached (1 - exp(-t/(R C))) [-].

    Returns
    -------
    numpy.ndarray, shape (M,)
        dT [K].
    """
    gap = resistance * factor[:, None] * total - grid[None, :]
    below = gap <= 0
    k = np.argmax(below, axis=1)               # the first crossing of each row
    out = np.full(total.shape[0], grid[-1])
    out[below.any(axis=1) & (k == 0)] = 0.0
    rows = np.nonzero(below.any(axis=1) & (k > 0))[0]       # one array operation a row set
    k = k[rows]
    g0, g1 = gap[rows, k - 1], gap[rows, k]
    out[rows] = grid[k - 1] + (grid[k] - grid[k - 1]) * g0 / (g0 - g1)
    return out


def _extra_loss(case, points, ev, values, tables: ThermalTables):
    if tables.rise_K.size < 2:
        return np.zeros(len(points))
    comps = tables.components(case)
    base = {k: v[:, 0] for k, v in comps.items()}
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = {k: np.where(base[k] > 0, ev.losses_W[k] / np.where(base[k] > 0, base[k], 1.0),
                             1.0) for k in comps}
    total = sum(scale[k][:, None] * comps[k] for k in comps)
    r = float(values[0])
    factor = np.ones(len(points))
    if points.time_h is not None and r > 0:
        c = housing(case.to_si(), drive_for(case)).heat_capacity_J_K
        with np.errstate(over="ignore"):    # R C -> 0: warm at once, exp(-inf) = 0
            factor = 1.0 - np.exp(-points.time_h * S_PER_H / (r * c))
    dt = rise(total, tables.rise_K, r, factor)
    return _row_interp(dt, tables.rise_K, total) - total[:, 0]


def _needs_sensor(case, points):
    if points.oil_temp_C is None:
        return ("the data has no oil_temp_C column (a sensor the warmer oil is measured "
                "against; without one, `toothfem efficiency --thermal` gives the balance)")
    return None


def thermal() -> Effect:
    """The oil in the contacts warmer than the sensor by R times the losses (module
    docstring), with the time constant R C when the data carry time.

    Returns
    -------
    Effect
        Parameter thermal_resistance_K_W [K/W] (thermal.sensor_resistance_K_W), a loss term
        beside the model.
    """
    section, name = FIELD.split(".")
    return Effect(
        name="thermal",
        summary="oil warmer than the sump sensor by a thermal resistance x the losses "
                "(time constant R C with time)",
        equation="dT = R P(T_s + dT) (1 - exp(-t/(R C))), T = T_s + dT",
        citation="lumped heat balance, ISO/TR 14179-1:2001; toothfem efficiency/thermal.py",
        parameters=(Parameter("thermal_resistance_K_W", "K/W", 0.0, 20.0, (0.5, 2.0, 8.0),
                              1.0, "thermal resistance between the losses and the sensor"),),
        not_applicable=_needs_sensor,
        loss_route=lambda case: True, extra_loss=_extra_loss, prepare=thermal_tables,
        case_fields=(FIELD,), set_fields=setter(*FIELD.split(".")),
        declared_by=declared_if_changed(section, name, FIELD),
        direct_test="a thermocouple in the oil near the discs or the teeth beside the sump "
                    "sensor, logged along the run")
