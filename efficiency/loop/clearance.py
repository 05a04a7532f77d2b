"""The ``load_sharing_clearance`` effect: the analytic load split ignores the clearance of a
modified cycloid profile; the effect tabulates the change of the pin-contact and
crank-bearing losses over a grid of clearances with the contact model (rigid bodies on
equal contact springs, :func:`clearance_tables`), once per data set."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...fem import cycloid_fe as cf
from ...fem.drives import drive_for
from ..drive_losses import disc_contact_losses
from ..lubricant import viscosity_factor
from ..mesh_table import table_from_records
from .effect import Effect, Parameter, Points, crank_speed_factor, needs_cycloid, set_field


# ---------------------------------------------------------------------------------------
# Clearance through the contact model

#: Clearances [mm] at which the contact model is solved; the effect interpolates between.
CLEARANCE_GRID_MM = (0.0, 0.0005, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02,
                     0.03, 0.05)
#: Disc torques at which each clearance's load split is solved (fractions between the
#: data's smallest and largest, log-spaced); the table interpolates F/T between them.
CLEARANCE_TORQUES = 8
#: Meshing positions over one pin pitch (the efficiency model's default).
CLEARANCE_POSITIONS = 36


@lru_cache(maxsize=8)
def contact_compliance(drive) -> float:
    """Compliance of one pin contact [m per N/m of face width] for the equal-springs
    contact model: the mean diagonal of the disc's FE influence matrix (plus the integral
    housing's, which the cycle solver adds) at the candidate pins of one position, plus
    for conventional pins the pin's own FE compliance averaged over contact angles within
    45 deg. One disc factorisation (seconds). The Hertz local correction at the actual
    half-width (about 10 % at these loads) and the coupling between contacts (off-diagonal
    terms about 10 % of the diagonal) are left out: that is the equal-springs limit."""
    solver = drive.cycle_solver(1, cache=False)
    model = solver.model
    c = float(np.mean(np.diag(solver.influence(0))))
    if model.pin_structure == "conventional":
        pin = cf.PinModel(model.geometry.pin_radius_m, model.youngs_modulus,
                          model.poisson_ratio, solver.b_ref / 2, model.plane)
        near = np.abs(pin.angles) <= math.pi / 4
        c += float(np.mean(pin.table[near]))
    return c


@dataclass(frozen=True)
class ClearanceTables:
    """Per clearance (K,) and point (M,): the pin-contact and crank-bearing losses relative
    to zero clearance, from the equal-springs contact model."""
    clearance_mm: np.ndarray        # (K,)
    pin_ratio: np.ndarray           # (K, M)
    bearing_ratio: np.ndarray       # (K, M)
    compliance: float               # m per N/m
    contacts_mean: np.ndarray       # (K,) mean pins in contact at the largest torque


def clearance_tables(case, points: Points, compliance=None,
                     grid_mm=CLEARANCE_GRID_MM) -> ClearanceTables:
    """Loss ratios over a grid of clearances (equidistant modification Delta r_z) at the
    points, in the limit of rigid bodies on equal contact springs (``compliance`` m per
    N/m; default :func:`contact_compliance`, from the FE).

    Per clearance the cycle solver finds the contact set and forces at every position
    (complementarity with the torque balance: fem/cycloid_fe.CycleSolver with
    ``equal_springs``) at a few disc torques spanning the data; the friction of each contact
    is the model's (same law, lubricant and oil temperature as the case), and the ratio
    sum(mu F v_s)(c) / sum(mu F v_s)(0) scales the model's pin-contact loss (the mean
    bearing force likewise scales the crank-bearing loss). At c = 0 the equal-springs split
    is the analytic F proportional to the moment arm, so the ratio starts at exactly 1."""
    cyc = case.cycloid
    drive = drive_for(case)
    if compliance is None:
        compliance = contact_compliance(drive)
    t_disc = drive.member_torque(points.torque_Nm, peak=False)
    lo, hi = float(np.min(t_disc)), float(np.max(t_disc))
    torques = np.geomspace(lo, hi, CLEARANCE_TORQUES) if hi > lo * 1.01 else np.array([hi])
    crank = np.abs(points.speed_rpm * 2 * math.pi / 60 * crank_speed_factor(case))
    visc = viscosity_factor(case.lubricant, points.oil_temp_C) * np.ones(len(points))
    eta0 = case.lubricant.dynamic_viscosity_Pa_s * visc
    pins, bearing, contacts = [], [], []
    for c_mm in grid_mm:
        d = drive_for(dataclasses.replace(case, cycloid=dataclasses.replace(
            cyc, equidistant_modification_mm=float(c_mm))))
        state = d.meshing(d.positions(CLEARANCE_POSITIONS))
        solver = d.cycle_solver(CLEARANCE_POSITIONS, cache=False,
                                solver_options={"equal_springs": compliance})
        records = [solver.solve(float(t)) for t in torques]
        table = table_from_records(state, records, "equal_springs")
        loss, f_bearing = disc_contact_losses(case, table, t_disc, crank, eta0)
        pins.append(loss)
        bearing.append(f_bearing)
        contacts.append(float(np.mean(records[-1].contacts_per_position)))
    pins, bearing = np.array(pins), np.array(bearing)

    def ratio(a):
        with np.errstate(divide="ignore", invalid="ignore"):
            r = a / a[0]
        return np.where(a[0] > 0, r, 1.0)

    return ClearanceTables(np.asarray(grid_mm, float), ratio(pins), ratio(bearing),
                           float(compliance), np.array(contacts))


def _clearance_loss(case, points, ev, values, tables: ClearanceTables):
    from scipy.interpolate import PchipInterpolator

    c = float(values[0])
    x = tables.clearance_mm
    rp = PchipInterpolator(x, tables.pin_ratio, axis=0)(c)
    rb = PchipInterpolator(x, tables.bearing_ratio, axis=0)(c)
    pins = ev.losses_W.get("pin_contacts", 0.0)
    bearings = ev.losses_W.get("crank_bearings", 0.0)
    return (rp - 1.0) * pins + (rb - 1.0) * bearings


def _declared_modification(case):
    cyc = case.cycloid
    if cyc is None:
        return None
    for name in ("equidistant_modification_mm", "move_distance_modification_mm",
                 "rotation_modification_deg"):
        if getattr(cyc, name) != 0:
            return f"cycloid.{name} = {getattr(cyc, name)!r}"
    return None


def load_sharing_clearance(compliance=None) -> Effect:
    """Clearance between disc and pins changing which pins carry the torque.

    A positive equidistant modification Delta r_z opens a gap that grows away from the
    pins of largest moment arm; under load the contact set is what closes (complementarity:
    gap >= 0, F >= 0, F gap = 0, sum F l = T), so fewer pins carry more load at low torque
    and the set grows with torque. The friction loss changes with it (the loaded pins
    differ in sliding speed and pressure). The load split comes from the contact model in
    the limit of rigid bodies on equal contact springs (``compliance``, default from the
    FE; see :func:`clearance_tables`), tabulated over :data:`CLEARANCE_GRID_MM` once per
    data set. The full FE cycle mode (about 25-50 s per geometry here) is the reference it
    is checked against in the slow tests."""
    return Effect(
        name="load_sharing_clearance",
        summary="disc-pin clearance (equidistant modification) changing the load split, "
                "through the contact model",
        equation="g_i = g0_i(Delta r_z) + k F_i - beta l_i >= 0, F_i >= 0, F_i g_i = 0, "
                 "sum F_i l_i = T",
        citation="Wang et al. (the pin-housing paper, docs/references.md), modifications Delta r_z, Delta R_z;"
                 " toothfem fem/cycloid_fe.CycleSolver (complementarity)",
        parameters=(Parameter("equidistant_modification_mm", "mm", 0.0, 0.05,
                              (0.003, 0.001, 0.01, 0.03), 0.003,
                              "clearance: equidistant modification Delta r_z"),),
        drives=("cycloid", "rv"),
        case_fields=("cycloid.equidistant_modification_mm",),
        set_fields=set_field("cycloid", "equidistant_modification_mm"),
        declared_by=_declared_modification,
        not_applicable=needs_cycloid,
        loss_route=lambda case: True,
        extra_loss=_clearance_loss,
        prepare=lambda case, points: clearance_tables(case, points, compliance))
