"""The catalog of physical effects the measured-data loop may add to the efficiency model.

An :class:`Effect` is a piece of physics with named parameters in physical units (bounds,
starting values), the case fields it sets (``apply(case, values) -> case`` through
``dataclasses.replace``), the drives it acts on and the equation and source it comes from.
It is never a curve fitted to the residual: its shape over speed, torque and oil temperature
comes from the model, only its physical parameter is fitted.

Most effects act through the case: the efficiency model evaluates the field they set. Two
act through a loss term beside the model (written in :func:`Effect.route`):

* ``load_sharing_clearance``: the analytic load split ignores the clearance of a modified
  cycloid profile; the effect tabulates the change of the pin-contact and crank-bearing
  losses over a grid of clearances with the contact model (rigid bodies on equal contact
  springs, :func:`clearance_tables`), once per data set.
* ``thermal`` (:mod:`.thermal_effect`): the oil in the contacts warmer than the sump
  sensor by a thermal resistance times the losses (with the time constant of the case's
  heat capacity when the data carry time).

Physics the model has by default (churning in an oil bath, mixed lubrication with a
boundary coefficient of 0.1, the seals) is not added again: its effect fits a correction
of its parameter (the churning law's factor, the boundary coefficient; ``drag_torque`` is
drag beyond the seals' own, e.g. bearing preload).

The catalog (:func:`catalog`), by name:

========================= ================================ ============== =================
effect                    parameter (case field)           drives         source
========================= ================================ ============== =================
drag_torque               friction.drag_torque_Nmm         all            ISO/TR 14179-2
churning                  lubricant.churning_scale         all (oil bath) Lu & Xu Eq. 42
viscosity_temperature     lubricant.vogel_B_C              all (oil T)    Vogel 1921
mixed_lubrication         friction.boundary_coefficient    all (EHL law)  Johnson et al. 1972
bearing_friction          friction.bearing_coefficient     all            Palmgren; SKF
output_mechanism_friction friction.output_pin_coefficient  sine           Lu & Xu Eqs. 37-39
load_sharing_clearance    cycloid.equidistant_modif..._mm  cycloid, rv    contact model
pin_sliding               friction.pin_groove_coefficient  cycloid, rv    Malhotra 1983
thermal                   (thermal resistance, K/W)        all (oil T)    lumped heat balance
========================= ================================ ============== =================

The sine pair has no route for ``pin_sliding`` (no pins in its mesh; its output pins are
``output_mechanism_friction``) nor for ``load_sharing_clearance`` (the case has no field for
a sine tooth modification, and the pair's analytic split takes every tooth within a fixed
5 um of contact): both are cycloid/RV only. The cycloid and RV models have no pins-in-holes
output mechanism (the disc drives the carrier through its crank bearings, which
``bearing_friction`` covers), so ``output_mechanism_friction`` is sine only.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ...errors import ToothfemError
from ...fem import cycloid_fe as cf
from ...fem.drives import drive_for
from ..bearing_friction import bearing_losses
from ..drive_losses import bearing_component, disc_contact_losses
from ..lubricant import viscosity_factor
from ..mesh_table import table_from_records
from .effect_base import (Effect, Parameter, Points, Prediction, crank_speed_factor,  # noqa: F401
                          declared_if_changed, need_cycloid, predict, prepare, read, setter,
                          true_points, with_effects)
from .loss_effects import bearing_preload, viscosity_grade, viscous_drag, windage
from .rig_effects import input_torque_offset, oil_temp_offset, output_torque_offset, warm_up
from .thermal_effect import thermal
from ...units import rpm_to_rad_s


# ---------------------------------------------------------------------------------------
# The effects


def drag_torque() -> Effect:
    """Load-independent drag torque on the input shaft beyond the model's own seals.

    P_drag = T_drag omega_in: ISO/TR 14179-2:2001 counts seal losses as a load-independent
    torque on the shaft (the model has the seals of ISO/TR 14179-1 at their diameters); a
    preloaded bearing pair or a tighter seal adds a load-independent moment of the same
    kind (SKF, 'The SKF model for calculating the frictional moment', 2018: M_drag,
    M_seal).

    Returns
    -------
    Effect
        Parameter drag_torque_Nmm [N mm] (friction.drag_torque_Nmm).
    """
    return Effect(
        name="drag_torque",
        summary="load-independent drag on the input shaft (seals, bearing preload)",
        equation="P = T_drag * omega_in",
        citation="ISO/TR 14179-2:2001 (seal and no-load losses); SKF frictional moment "
                 "model (2018), M_seal",
        parameters=(Parameter("drag_torque_Nmm", "N mm", 0.0, 1e6, (5.0, 50.0, 500.0), 50.0,
                              "drag torque on the input shaft"),),
        case_fields=("friction.drag_torque_Nmm",),
        set_fields=setter("friction", "drag_torque_Nmm"),
        declared_by=declared_if_changed("friction", "drag_torque_Nmm",
                                         "friction.drag_torque_Nmm"),
        linear_in=lambda case: "drag",
        direct_test="no-load runs (output uncoupled) at several speeds: a drag torque that does "
                    "not change with speed; run both directions: a drag changes sign with the "
                    "direction, a meter's offset does not")


def _needs_bath_churning(case, points):
    lub = case.lubricant
    if lub.lubrication != "oil_bath":
        return (f"lubricant.lubrication = {lub.lubrication!r}: no oil bath to churn (the "
                "bearings' drag is Palmgren's)")
    if lub.churning == "none":
        return "lubricant.churning = 'none': the case has no churning law to correct"
    return None


def churning() -> Effect:
    """A correction of the churning the model has by default in an oil bath.

    The no-load loss of each gear stage in the bath (Lu & Xu 2024, Eq. 42):
    P0 = k 1e-7 a0 (n/60)^(4/3) (nu/n)^0.1 (nu + 90) kW, a0 the stage's centre distance
    [mm] (the eccentricity of a K-H-V stage), n its pinion's speed [rpm], nu the kinematic
    viscosity at the oil temperature [mm^2/s]; the factor k is fitted (1 = the law as
    the model takes it by default, efficiency/no_load.py).

    Returns
    -------
    Effect
        Parameter churning_scale [-] (lubricant.churning_scale).
    """
    return Effect(
        name="churning",
        summary="speed- and viscosity-dependent no-load loss (oil agitation, splash)",
        equation="P0 = k * 1e-7 a0 (n/60)^(4/3) (nu/n)^0.1 (nu + 90) kW",
        citation="Lu & Xu, Heliyon 10 (2024) e26300, Eq. 42; ISO/TR 14179-1:2001 (no-load "
                 "loss)",
        parameters=(Parameter("churning_scale", "-", 0.0, 100.0, (1.0, 0.3, 3.0), 1.0,
                              "factor k on the Lu & Xu law"),),
        case_fields=("lubricant.churning_scale",),
        set_fields=setter("lubricant", "churning_scale"),
        declared_by=declared_if_changed("lubricant", "churning_scale",
                                        "lubricant.churning_scale"),
        not_applicable=_needs_bath_churning,
        linear_in=lambda case: "churning",
        direct_test="no-load runs (output uncoupled) at several speeds and oil temperatures: a "
                    "loss that follows n^(4/3) and the viscosity; or the run repeated with "
                    "the oil level lowered")


#: Oil temperatures must span at least this range [K] for the Vogel B to show.
MIN_OIL_TEMP_SPAN_C = 5.0


def _needs_temps(case, points):
    t = points.oil_temp_C
    if t is None:
        return "the data has no oil_temp_C column (Vogel's law acts through T - T_ref)"
    if np.ptp(t) < MIN_OIL_TEMP_SPAN_C:
        return (f"the oil temperatures span {np.ptp(t):.1f} K < {MIN_OIL_TEMP_SPAN_C:g} K: "
                "no leverage on the viscosity-temperature law")
    return None


def viscosity_temperature() -> Effect:
    """The oil's own viscosity-temperature law instead of the library default.

    Vogel (1921): eta(T) = A exp(B / (T + C)) (T in deg C), so eta(T)/eta(T_ref) =
    exp(B/(T + C) - B/(T_ref + C)); the fitted B [deg C] sets how fast the viscosity falls
    with temperature (C kept at the case's value; B and C together are not identifiable
    from efficiency data over a few tens of kelvin). Acts on the EHL friction (eta0 in the
    Xu regression and the film ratio) and on the churning law (nu).

    Returns
    -------
    Effect
        Parameter vogel_B_C [deg C] (lubricant.vogel_B_C).
    """
    return Effect(
        name="viscosity_temperature",
        summary="oil viscosity versus temperature (Vogel B), acting on EHL friction and "
                "churning",
        equation="eta(T)/eta(T_ref) = exp(B/(T + C) - B/(T_ref + C))",
        citation="H. Vogel, Physikalische Zeitschrift 22 (1921) 645-646",
        parameters=(Parameter("vogel_B_C", "deg C", 100.0, 5000.0,
                              (1000.0, 600.0, 1500.0, 2500.0), 500.0, "Vogel B"),),
        case_fields=("lubricant.vogel_B_C",),
        set_fields=setter("lubricant", "vogel_B_C"),
        declared_by=declared_if_changed("lubricant", "vogel_B_C", "lubricant.vogel_B_C"),
        not_applicable=_needs_temps,
        direct_test="the oil's viscosity measured at two temperatures (ISO 3104)")


def _needs_ehl(case, points):
    if case.friction.mesh_law != "ehl_xu2007":
        return (f"friction.mesh_law = {case.friction.mesh_law!r} has no film ratio (the "
                "blending acts on the EHL law)")
    return None


#: Smallest boundary coefficient the fit tries: 0 is the model's switch to the EHL law
#: alone, not a frictionless asperity, so the fitted range stops short of it.
MIN_BOUNDARY = 1e-3


def mixed_lubrication() -> Effect:
    """A correction of the boundary friction the model has by default in mixed lubrication.

    mu = (1 - f) mu_EHL + f mu_b, f the asperities' share of the load (Johnson, Greenwood &
    Poon 1972 with plastically flattened Gaussian asperities, efficiency/mixed_film.py);
    the model's mu_b is 0.1 (lubricated steel, Bowden & Tabor 1950) and the fit corrects it
    (additives, coatings, running-in change it). Since the film ratio grows with speed and
    viscosity, its loss is largest at low speed and high temperature.

    Returns
    -------
    Effect
        Parameter boundary_coefficient [-] (friction.boundary_coefficient).
    """
    return Effect(
        name="mixed_lubrication",
        summary="boundary (asperity) friction of the load the film cannot carry",
        equation="mu = (1 - f) mu_EHL + f mu_b, f = min(1, (H/p_m) erfc(lambda_f/sqrt 2)/2)",
        citation="Johnson, Greenwood & Poon, Wear 19 (1972) 91-108; Bowden & Tabor (1950); "
                 "Castro & Seabra, Proc. IMechE J 221 (2007) 399-411",
        parameters=(Parameter("boundary_coefficient", "-", MIN_BOUNDARY, 0.3,
                              (0.1, 0.03, 0.2), 0.05, "boundary friction coefficient mu_b"),),
        case_fields=("friction.boundary_coefficient",),
        set_fields=setter("friction", "boundary_coefficient"),
        declared_by=declared_if_changed("friction", "boundary_coefficient",
                                         "friction.boundary_coefficient"),
        not_applicable=_needs_ehl,
        direct_test="the contact's friction on a twin-disc machine at the reducer's film "
                    "ratios (its boundary friction at low speed and hot oil)")


def bearing_friction() -> Effect:
    """Load-dependent friction of the bearings.

    Sine reducer: M = mu_b F r_p on the eccentric bearing, F from the planet's equilibrium
    (sine paper Eq. 32). Cycloid and RV reducers: the load term of every bearing's Palmgren
    moment, M1 = mu_b P d_m/2 (efficiency/bearing_friction.py), beside its viscous M0. P = M
    omega_rel. The fitted mu_b replaces the library's default; a case that declares its own
    bearing coefficient is not refitted.

    Returns
    -------
    Effect
        Parameter bearing_coefficient [-] (friction.bearing_coefficient).
    """
    return Effect(
        name="bearing_friction",
        summary="load-dependent friction of the eccentric/crank bearings",
        equation="P = mu_b F r omega_rel (sine, Eq. 32); mu_b P d_m/2 omega_rel per bearing",
        citation="A. Palmgren, Ball and Roller Bearing Engineering (1959); SKF General "
                 "Catalogue, M = 0.5 mu P d; Lu & Xu 2024 Eq. 32",
        parameters=(Parameter("bearing_coefficient", "-", 0.0, 0.1,
                              (0.0015, 0.0005, 0.005, 0.015), 0.002,
                              "bearing friction coefficient mu_b"),),
        case_fields=("friction.bearing_coefficient",),
        set_fields=setter("friction", "bearing_coefficient"),
        declared_by=declared_if_changed("friction", "bearing_coefficient",
                                         "friction.bearing_coefficient"),
        linear_in=lambda case: bearing_component(drive_for(case)),
        direct_test="the bearings' friction torque under a known radial load on a bearing "
                    "test rig")


def _needs_output_mechanism(case, points):
    if case.output_mechanism is None:
        return "needs the [output_mechanism] section"
    return None


def output_mechanism_friction() -> Effect:
    """Sliding of the output pins in the planet's holes (pins-in-holes W mechanism).

    Sine paper Eqs. 37-39: P = f_k sum(Q) v_k with sum(Q) = 4 T2/(pi R_w) and v_k = 2 a0
    omega_rel; the fitted f_k replaces the library default.

    Returns
    -------
    Effect
        Parameter output_pin_coefficient [-] (friction.output_pin_coefficient).
    """
    return Effect(
        name="output_mechanism_friction",
        summary="pins sliding in the holes of the pins-in-holes output mechanism",
        equation="P = f_k (4 T2 / (pi R_w)) (2 a0 omega_rel)",
        citation="Lu & Xu, Heliyon 10 (2024) e26300, Eqs. 37-39",
        parameters=(Parameter("output_pin_coefficient", "-", 0.0, 0.3, (0.05, 0.02, 0.1),
                              0.03, "pin-hole friction coefficient f_k"),),
        acts_on="output_mechanism",
        case_fields=("friction.output_pin_coefficient",),
        set_fields=setter("friction", "output_pin_coefficient"),
        declared_by=declared_if_changed("friction", "output_pin_coefficient",
                                         "friction.output_pin_coefficient"),
        not_applicable=_needs_output_mechanism,
        linear_in=lambda case: "output_mechanism",
        direct_test="the output mechanism turned with the planet's mesh removed: the "
                    "pins' sliding torque under load")


def _needs_conventional(case, points):
    why = need_cycloid(case, points)
    if why:
        return why
    if case.cycloid.pin_structure != "conventional":
        return (f"cycloid.pin_structure = {case.cycloid.pin_structure!r}: the pins are one "
                "piece with the housing, no groove to slide in")
    return None


def pin_sliding() -> Effect:
    """Conventional pins that slide in their housing grooves instead of rolling freely.

    A pin free to turn takes the sliding at whichever interface resists less: the loss per
    contact is min(mu_disc, mu_g) F v_s (efficiency/drive_losses.py); mu_g = 0 is ideal rolling.
    The pins' sliding in the grooves is the loss mechanism of the roller/pin analyses of
    Malhotra & Parameswaran (1983) and Gorla et al. (2008).

    Returns
    -------
    Effect
        Parameter pin_groove_coefficient [-] (friction.pin_groove_coefficient).
    """
    return Effect(
        name="pin_sliding",
        summary="conventional pins sliding in their grooves (Coulomb mu_g) instead of rolling",
        equation="P = sum min(mu_disc, mu_g) F |v_s|",
        citation="Malhotra & Parameswaran, Mech. Mach. Theory 18 (1983) 491-499; Gorla et "
                 "al., J. Mech. Des. 130 (2008)",
        parameters=(Parameter("pin_groove_coefficient", "-", 0.0, 0.3, (0.02, 0.005, 0.08),
                              0.02, "groove friction coefficient mu_g"),),
        acts_on="pins",
        case_fields=("friction.pin_groove_coefficient",),
        set_fields=setter("friction", "pin_groove_coefficient"),
        declared_by=declared_if_changed("friction", "pin_groove_coefficient",
                                         "friction.pin_groove_coefficient"),
        not_applicable=_needs_conventional,
        direct_test="the pins inspected after a run: sliding tracks in the grooves, or "
                    "marked pins that have not turned")


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


def contact_compliance(drive) -> float:
    """Compliance of one pin contact for the equal-springs contact model.

    The mean diagonal of the disc's FE influence matrix (plus the integral housing's, which
    the cycle solver adds) at the candidate pins of one position, plus for conventional pins
    the pin's own FE compliance averaged over contact angles within 45 deg. One disc
    factorisation (seconds). The Hertz local correction at the actual half-width (about 10 %
    at these loads) and the coupling between contacts (off-diagonal terms about 10 % of the
    diagonal) are left out: that is the equal-springs limit.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        A cycloid or RV drive.

    Returns
    -------
    float
        Compliance [m per N/m of face width].
    """
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
    points, in the limit of rigid bodies on equal contact springs.

    Per clearance the cycle solver finds the contact set and forces at every position
    (complementarity with the torque balance: fem/cycloid_fe.CycleSolver with
    ``equal_springs``) at a few disc torques spanning the data; the friction of each contact
    is the model's (same law, lubricant and oil temperature as the case), and the ratio
    sum(mu F v_s)(c) / sum(mu F v_s)(0) scales the model's pin-contact loss (the mean
    bearing force likewise scales the crank-bearing loss). At c = 0 the equal-springs split
    is the analytic F proportional to the moment arm, so the ratio starts at exactly 1.

    Parameters
    ----------
    case : toothfem.case.Case
        A cycloid or RV case.
    points : Points
        The M operating points.
    compliance : float, optional
        Contact spring [m per N/m]; default :func:`contact_compliance`, from the FE.
    grid_mm : sequence of float
        The K clearances [mm].

    Returns
    -------
    ClearanceTables
        Pin-contact and crank-bearing loss ratios (K, M) [-].
    """
    cyc = case.cycloid
    drive = drive_for(case)
    if compliance is None:
        compliance = contact_compliance(drive)
    t_disc = drive.member_torque(points.torque_Nm, peak=False)
    lo, hi = float(np.min(t_disc)), float(np.max(t_disc))
    torques = np.geomspace(lo, hi, CLEARANCE_TORQUES) if hi > lo * 1.01 else np.array([hi])
    crank = np.abs(rpm_to_rad_s(points.speed_rpm) * crank_speed_factor(case))
    lubricant = case.to_si().lubricant
    visc = viscosity_factor(lubricant, points.oil_temp_C) * np.ones(len(points))
    eta0 = lubricant.dynamic_viscosity_Pa_s * visc
    pin_rows: list[np.ndarray] = []
    bearing_rows: list[np.ndarray] = []
    contacts: list[float] = []
    for c_mm in grid_mm:
        d = drive_for(dataclasses.replace(case, cycloid=dataclasses.replace(
            cyc, equidistant_modification_mm=float(c_mm))))
        state = d.meshing(d.positions(CLEARANCE_POSITIONS))
        solver = d.cycle_solver(CLEARANCE_POSITIONS, cache=False,
                                solver_options={"equal_springs": compliance})
        records = [solver.solve(float(t)) for t in torques]
        table = table_from_records(state, records, "equal_springs")
        loss, f_bearing = disc_contact_losses(case, table, t_disc, crank, eta0)
        pin_rows.append(loss)
        bearing_rows.append(f_bearing)
        contacts.append(float(np.mean(records[-1].contacts_per_position)))
    pins, bearing = np.array(pin_rows), np.array(bearing_rows)

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
    # the crank bearings' load term scales with their load; their viscous M0 does not
    bearings = ev.losses_W.get("crank_bearings", 0.0) - _viscous(case, points, "crank_bearings")
    return (rp - 1.0) * pins + (rb - 1.0) * bearings


def _viscous(case, points, component):
    """A bearing group's viscous (load-independent) loss at the points [W]."""
    si = case.to_si()
    w_in = rpm_to_rad_s(points.speed_rpm)
    factor = viscosity_factor(si.lubricant, points.oil_temp_C) * np.ones_like(w_in)
    return bearing_losses(si, drive_for(si), {}, w_in, factor).get(component, 0.0)


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
    the limit of rigid bodies on equal contact springs (see :func:`clearance_tables`),
    tabulated over :data:`CLEARANCE_GRID_MM` once per data set. The full FE cycle mode
    (about 25-50 s per geometry here) is the reference it is checked against in the slow
    tests.

    Parameters
    ----------
    compliance : float, optional
        Contact spring [m per N/m]; default from the FE.

    Returns
    -------
    Effect
        Parameter equidistant_modification_mm [mm] (cycloid.equidistant_modification_mm),
        a loss term beside the model.
    """
    return Effect(
        name="load_sharing_clearance",
        summary="disc-pin clearance (equidistant modification) changing the load split, "
                "through the contact model",
        equation="g_i = g0_i(Delta r_z) + k F_i - beta l_i >= 0, F_i >= 0, F_i g_i = 0, "
                 "sum F_i l_i = T",
        citation="Wang et al. (the pin-housing paper, docs/references.md), modifications "
                 "Delta r_z, Delta R_z; toothfem fem/cycloid_fe.CycleSolver (complementarity)",
        parameters=(Parameter("equidistant_modification_mm", "mm", 0.0, 0.05,
                              (0.003, 0.001, 0.01, 0.03), 0.003,
                              "clearance: equidistant modification Delta r_z"),),
        acts_on="pins",
        case_fields=("cycloid.equidistant_modification_mm",),
        set_fields=setter("cycloid", "equidistant_modification_mm"),
        declared_by=_declared_modification,
        not_applicable=need_cycloid,
        loss_route=lambda case: True,
        extra_loss=_clearance_loss,
        prepare=lambda case, points: clearance_tables(case, points, compliance),
        direct_test="the disc's profile on a gear measuring machine, or pressure-sensitive "
                    "film at the pins under load (the pins in contact)")


# ---------------------------------------------------------------------------------------
# The catalog

NAMES = ("drag_torque", "churning", "viscosity_temperature", "mixed_lubrication",
         "bearing_friction", "output_mechanism_friction", "load_sharing_clearance",
         "pin_sliding", "thermal", "viscosity_grade", "windage", "viscous_drag",
         "bearing_preload",
         "input_torque_offset", "output_torque_offset", "oil_temp_offset", "warm_up")


def catalog(*, clearance_compliance=None) -> tuple:
    """Every effect of the catalog (the order of :data:`NAMES`).

    Parameters
    ----------
    clearance_compliance : float, optional
        Fixes the contact springs of ``load_sharing_clearance`` [m per N/m] instead of
        taking them from the FE (one disc factorisation per design).

    Returns
    -------
    tuple of Effect
        The effects, in the order of :data:`NAMES`.
    """
    return (drag_torque(), churning(), viscosity_temperature(), mixed_lubrication(),
            bearing_friction(), output_mechanism_friction(),
            load_sharing_clearance(clearance_compliance), pin_sliding(), thermal(),
            viscosity_grade(), windage(), viscous_drag(), bearing_preload(),
            input_torque_offset(),
            output_torque_offset(), oil_temp_offset(), warm_up())


def by_name(name, effects=None) -> Effect:
    """The catalog effect called ``name``.

    Parameters
    ----------
    name : str
        One of :data:`NAMES`.
    effects : iterable of Effect, optional
        Where to look; default :func:`catalog`.

    Returns
    -------
    Effect
        The effect.

    Raises
    ------
    ToothfemError
        If no effect has that name.
    """
    for e in effects or catalog():
        if e.name == name:
            return e
    raise ToothfemError(f"effect {name!r} is not in the catalog; known: {list(NAMES)}")
