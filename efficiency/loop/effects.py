"""The catalog of physical effects the measured-data loop may add to the efficiency model.

An :class:`Effect` is a piece of physics with named parameters in physical units (bounds,
starting values), the case fields it sets (``apply(case, values) -> case`` through
``dataclasses.replace``), the drives it acts on and the equation and source it comes from.
It is never a curve fitted to the residual: its shape over speed, torque and oil temperature
comes from the model, only its physical parameter is fitted.

Most effects act through the case: the efficiency model evaluates the field they set. One
acts through a loss term beside the model (written in :func:`Effect.route`):

* ``load_sharing_clearance``: the analytic load split ignores the clearance of a modified
  cycloid profile; the effect tabulates the change of the pin-contact and crank-bearing
  losses over a grid of clearances with the contact model (rigid bodies on equal contact
  springs, :func:`clearance_tables`), once per data set.

The catalog (:func:`catalog`), by name:

========================= ================================ ============== =================
effect                    parameter (case field)           drives         source
========================= ================================ ============== =================
drag_torque               friction.drag_torque_Nmm         all            ISO/TR 14179-2
churning                  lubricant.churning_scale         all            Lu & Xu Eq. 42
viscosity_temperature     lubricant.vogel_B_C              all (oil T)    Vogel 1921
mixed_lubrication         friction.boundary_coefficient    all (EHL law)  Johnson et al. 1972
bearing_friction          friction.bearing_coefficient     all            Palmgren; SKF
output_mechanism_friction friction.output_pin_coefficient  sine           Lu & Xu Eqs. 37-39
load_sharing_clearance    cycloid.equidistant_modif..._mm  cycloid, rv    contact model
pin_sliding               friction.pin_groove_coefficient  cycloid, rv    Malhotra 1983
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

import numpy as np

from ...errors import ToothfemError
from ...fem.drives import drive_for
from ..drive_losses import bearing_component
from .clearance import clearance_tables, contact_compliance, load_sharing_clearance
from .effect import (Effect, Parameter, Points, crank_speed_factor, declared_if_changed,
                     needs_cycloid, predict, prepare, set_field, with_effects)

#: The catalog's public names; the records and the prediction machinery (:mod:`.effect`) and
#: the clearance effect's tables (:mod:`.clearance`) are re-exported here for the loop's
#: callers (``from toothfem.efficiency.loop import effects as fx``).
__all__ = ["NAMES", "Effect", "Parameter", "Points", "by_name", "catalog", "churning",
           "clearance_tables", "contact_compliance", "crank_speed_factor", "drag_torque",
           "load_sharing_clearance", "mixed_lubrication", "output_mechanism_friction",
           "pin_sliding", "predict", "prepare", "viscosity_temperature", "with_effects",
           "bearing_friction"]


# ---------------------------------------------------------------------------------------
# The effects


def drag_torque() -> Effect:
    """Load-independent drag torque on the input shaft (lip seals, bearing preload).

    P_drag = T_drag omega_in: ISO/TR 14179-2:2001 counts seal losses as a load-independent
    torque on the shaft (its seal-loss formula gives the torque from the shaft diameter);
    a preloaded bearing pair adds a load-independent moment of the same kind (SKF,
    'The SKF model for calculating the frictional moment', 2018: M_drag, M_seal)."""
    return Effect(
        name="drag_torque",
        summary="load-independent drag on the input shaft (seals, bearing preload)",
        equation="P = T_drag * omega_in",
        citation="ISO/TR 14179-2:2001 (seal and no-load losses); SKF frictional moment "
                 "model (2018), M_seal",
        parameters=(Parameter("drag_torque_Nmm", "N mm", 0.0, 1e6, (5.0, 50.0, 500.0), 50.0,
                              "drag torque on the input shaft"),),
        drives=("sine", "cycloid", "rv"),
        case_fields=("friction.drag_torque_Nmm",),
        set_fields=set_field("friction", "drag_torque_Nmm"),
        declared_by=declared_if_changed("friction", "drag_torque_Nmm",
                                         "friction.drag_torque_Nmm"),
        linear_in=lambda case: "drag")


def _set_churning(case, values):
    lub = dataclasses.replace(case.lubricant, churning="lu_xu_2024", churning_scale=values[0])
    return dataclasses.replace(case, lubricant=lub)


def churning() -> Effect:
    """Oil agitation, splashing and seal drag that grow with speed and viscosity.

    The sine paper's no-load loss (Lu & Xu 2024, Eq. 42, the form of ISO/TR 14179-1's
    no-load gear loss): P0 = k 1e-7 a0 (n/60)^(4/3) (nu/n)^0.1 (nu + 90) kW, a0 the centre
    distance (eccentricity) [mm], n the eccentric's speed [rpm], nu the kinematic viscosity
    at the oil temperature [mm^2/s]; the factor k is fitted (1 = the paper's law). On a
    cycloid or RV drive the model takes a0 = the eccentricity and n = the crank speed."""
    return Effect(
        name="churning",
        summary="speed- and viscosity-dependent no-load loss (oil agitation, splash)",
        equation="P0 = k * 1e-7 a0 (n/60)^(4/3) (nu/n)^0.1 (nu + 90) kW",
        citation="Lu & Xu, Heliyon 10 (2024) e26300, Eq. 42; ISO/TR 14179-1:2001 (no-load "
                 "loss)",
        parameters=(Parameter("churning_scale", "-", 0.0, 100.0, (1.0, 0.3, 3.0), 1.0,
                              "factor k on the Lu & Xu law"),),
        drives=("sine", "cycloid", "rv"),
        case_fields=("lubricant.churning", "lubricant.churning_scale"),
        set_fields=_set_churning,
        declared_by=lambda case: (f"lubricant.churning = {case.lubricant.churning!r}"
                                  if case.lubricant.churning != "none" else None),
        linear_in=lambda case: "churning")


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
    Xu regression and the film ratio) and on the churning law (nu)."""
    return Effect(
        name="viscosity_temperature",
        summary="oil viscosity versus temperature (Vogel B), acting on EHL friction and "
                "churning",
        equation="eta(T)/eta(T_ref) = exp(B/(T + C) - B/(T_ref + C))",
        citation="H. Vogel, Physikalische Zeitschrift 22 (1921) 645-646",
        parameters=(Parameter("vogel_B_C", "deg C", 100.0, 5000.0,
                              (1000.0, 600.0, 1500.0, 2500.0), 500.0, "Vogel B"),),
        drives=("sine", "cycloid", "rv"),
        case_fields=("lubricant.vogel_B_C",),
        set_fields=set_field("lubricant", "vogel_B_C"),
        declared_by=declared_if_changed("lubricant", "vogel_B_C", "lubricant.vogel_B_C"),
        not_applicable=_needs_temps)


def _needs_ehl(case, points):
    if case.friction.mesh_law != "ehl_xu2007":
        return (f"friction.mesh_law = {case.friction.mesh_law!r} has no film ratio (the "
                "blending acts on the EHL law)")
    return None


def mixed_lubrication() -> Effect:
    """Asperity friction as the film ratio falls below full film.

    mu = (1 - xi) mu_EHL + xi mu_b with xi = (1 - lambda/3)^2 for lambda = h_c/S < 3: the
    load shared by the asperities (Johnson, Greenwood & Poon 1972) carries the boundary
    friction mu_b; the shape of xi is the solid-fraction blending of the model
    (efficiency/contact_friction.py, in the manner of Castro & Seabra 2008). Since lambda grows with
    speed and viscosity, the extra loss is largest at low speed and high temperature."""
    return Effect(
        name="mixed_lubrication",
        summary="boundary (asperity) friction blended in as the film ratio falls below 3",
        equation="mu = (1 - xi) mu_EHL + xi mu_b, xi = (1 - lambda/3)^2",
        citation="Johnson, Greenwood & Poon, Wear 19 (1972) 91-108; Castro & Seabra (2008)",
        parameters=(Parameter("boundary_coefficient", "-", 0.0, 0.3, (0.05, 0.01, 0.15), 0.05,
                              "boundary friction coefficient mu_b"),),
        drives=("sine", "cycloid", "rv"),
        case_fields=("friction.boundary_coefficient",),
        set_fields=set_field("friction", "boundary_coefficient"),
        declared_by=declared_if_changed("friction", "boundary_coefficient",
                                         "friction.boundary_coefficient"),
        not_applicable=_needs_ehl)


def bearing_friction() -> Effect:
    """Load-dependent friction of the eccentric (sine) or crank (cycloid, RV) bearings.

    M = mu_b F r (the SKF simplified frictional moment M = 0.5 mu P d; Palmgren's
    load-dependent term), P = M omega_rel, with F the bearing force from the member's
    equilibrium (sine paper Eq. 32). The fitted mu_b replaces the library's default; a case
    that declares its own bearing coefficient is not refitted."""
    return Effect(
        name="bearing_friction",
        summary="load-dependent friction of the eccentric/crank bearings",
        equation="P = mu_b F r omega_rel",
        citation="A. Palmgren, Ball and Roller Bearing Engineering (1959); SKF General "
                 "Catalogue, M = 0.5 mu P d; Lu & Xu 2024 Eq. 32",
        parameters=(Parameter("bearing_coefficient", "-", 0.0, 0.1,
                              (0.0015, 0.0005, 0.005, 0.015), 0.002,
                              "bearing friction coefficient mu_b"),),
        drives=("sine", "cycloid", "rv"),
        case_fields=("friction.bearing_coefficient",),
        set_fields=set_field("friction", "bearing_coefficient"),
        declared_by=declared_if_changed("friction", "bearing_coefficient",
                                         "friction.bearing_coefficient"),
        linear_in=lambda case: bearing_component(drive_for(case)))


def _needs_output_mechanism(case, points):
    if case.output_mechanism is None:
        return "needs the [output_mechanism] section"
    return None


def output_mechanism_friction() -> Effect:
    """Sliding of the output pins in the planet's holes (pins-in-holes W mechanism).

    Sine paper Eqs. 37-39: P = f_k sum(Q) v_k with sum(Q) = 4 T2/(pi R_w) and v_k = 2 a0
    omega_rel; the fitted f_k replaces the library default."""
    return Effect(
        name="output_mechanism_friction",
        summary="pins sliding in the holes of the pins-in-holes output mechanism",
        equation="P = f_k (4 T2 / (pi R_w)) (2 a0 omega_rel)",
        citation="Lu & Xu, Heliyon 10 (2024) e26300, Eqs. 37-39",
        parameters=(Parameter("output_pin_coefficient", "-", 0.0, 0.3, (0.05, 0.02, 0.1),
                              0.03, "pin-hole friction coefficient f_k"),),
        drives=("sine",),
        case_fields=("friction.output_pin_coefficient",),
        set_fields=set_field("friction", "output_pin_coefficient"),
        declared_by=declared_if_changed("friction", "output_pin_coefficient",
                                         "friction.output_pin_coefficient"),
        not_applicable=_needs_output_mechanism,
        linear_in=lambda case: "output_mechanism")


def _needs_conventional(case, points):
    why = needs_cycloid(case, points)
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
    Malhotra & Parameswaran (1983) and Gorla et al. (2008)."""
    return Effect(
        name="pin_sliding",
        summary="conventional pins sliding in their grooves (Coulomb mu_g) instead of rolling",
        equation="P = sum min(mu_disc, mu_g) F |v_s|",
        citation="Malhotra & Parameswaran, Mech. Mach. Theory 18 (1983) 491-499; Gorla et "
                 "al., J. Mech. Des. 130 (2008)",
        parameters=(Parameter("pin_groove_coefficient", "-", 0.0, 0.3, (0.02, 0.005, 0.08),
                              0.02, "groove friction coefficient mu_g"),),
        drives=("cycloid", "rv"),
        case_fields=("friction.pin_groove_coefficient",),
        set_fields=set_field("friction", "pin_groove_coefficient"),
        declared_by=declared_if_changed("friction", "pin_groove_coefficient",
                                         "friction.pin_groove_coefficient"),
        not_applicable=_needs_conventional)


# ---------------------------------------------------------------------------------------
# The catalog

NAMES = ("drag_torque", "churning", "viscosity_temperature", "mixed_lubrication",
         "bearing_friction", "output_mechanism_friction", "load_sharing_clearance",
         "pin_sliding")


def catalog(*, clearance_compliance=None) -> tuple:
    """Every effect of the catalog (the order of :data:`NAMES`). ``clearance_compliance``
    [m per N/m] fixes the contact springs of ``load_sharing_clearance`` instead of taking
    them from the FE (one disc factorisation per design)."""
    return (drag_torque(), churning(), viscosity_temperature(), mixed_lubrication(),
            bearing_friction(), output_mechanism_friction(),
            load_sharing_clearance(clearance_compliance), pin_sliding())


def by_name(name, effects=None) -> Effect:
    """The catalog effect called ``name``."""
    for e in effects or catalog():
        if e.name == name:
            return e
    raise ToothfemError(f"effect {name!r} is not in the catalog; known: {list(NAMES)}")
