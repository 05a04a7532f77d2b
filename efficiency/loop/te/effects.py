"""The effects a TE/hysteresis loop fits (docs/te_rig.md, "The loop"): each a named set of
bounded parameters, what it means, its source and the measurement that tells it apart,
and the model options it sets (:class:`toothfem.efficiency.loop.te.model.Effects`).

Options are flat keys so effects combine by a dict update: ``("play",)``,
``("eccentric", k, j, "radial")`` and ``("eccentric", k, j, "tangential")``,
``("stiffness", part)``, ``("friction",)``,
``("equidistant",)``, ``("move_distance",)``, ``("pin_radius",)``, ``("pin_ring", key)``
(a key of ``Effects.pin_ring_m``); :func:`effects_of` turns them into an ``Effects``.
"""
from __future__ import annotations

import math
from typing import TypedDict

import numpy as np

from ....fem.drives.assembly import SCALABLE
from .problem import TeEffect, parameter
from .model import DEFAULT_TE_SAMPLES, Effects, ring_order, ring_samples
from ....units import ARCMIN, M_PER_MM, M_PER_UM

#: Crank-bearing play [um]: 0 to 50, a needle or cylindrical bearing of 20-50 mm bore from
#: group C2 to beyond C5 (ISO 5753-1:2009, radial internal clearance); typical 5 um.
PLAY_BOUNDS_UM = (0.0, 50.0)
#: An eccentric's centre off its drawn place [um], each component (radial: along the
#: eccentric's direction, the eccentricity error; tangential: across it, + in the sense of
#: the crank angle, the eccentric's phase error times the eccentricity): +-20, the order of
#: IT6 on a 30-50 mm eccentric's diameter (16 um, ISO 286-1) that its grinding holds, taken
#: as the position zone of its axis about the journals' (ISO 1101); typical 3 um.
ECCENTRIC_BOUNDS_UM = (-20.0, 20.0)
#: A stiffness factor on one part: within 3x either way of the model's (a bearing's
#: stiffness from its catalogue or a contact law is known to tens of percent, not a factor
#: of 3).
STIFFNESS_BOUNDS = (1 / 3, 3.0)
#: The parts whose stiffness a fit may scale (the system model's names, model.Effects).
STIFFNESS_PARTS = ("crank bearings", "support bearings", "mesh")
#: A factor on the path friction's coefficients: 0 (none) to 5 (boundary friction of dry
#: starts against the model's lubricated ones, mu about 0.1 against 0.02).
FRICTION_BOUNDS = (0.0, 5.0)
#: Every pin's radius change [um]: +-10, twice the IT5 limit of a 5-10 mm pin (6 um,
#: ISO 286-1) for a lot off its nominal.
PIN_RADIUS_BOUNDS_UM = (-10.0, 10.0)
#: The pin ring's errors by order round it (Effects.pin_ring_m): name -> (key, what it is).
#: Order 1 tangential (the cumulative pitch error) and order 2 radial (ovality) show at
#: the fitted orders (2 and the pin passing's second multiples, 2 Zb and 2 Za); the ring's
#: centre moved (order 1 radial with tangential) barely shows (5 um on RV-40E: every fitted
#: row within 0.17 arcsec, under 2 sigma of a width) and orders from 3 show at orders the
#: fit has no row for (docs/te_rig.md).
PIN_RING_EFFECTS = {
    "pin_ring_pitch_error": ("tangential_1", "the pins' cumulative pitch error round the "
                                             "ring (order 1 tangential: an indexing error)"),
    "pin_ring_ovality": ("radial_2", "the pin ring out of round (order 2 radial: the "
                                     "housing's pin grooves on an oval, or the housing "
                                     "bolted out of round)"),
}
#: The pin ring's flank tolerance class for the bounds: an amplitude a of a ring order
#: spans 2 a, at most the total cumulative pitch tolerance F_p of class 7, twice class 5's
#: (ISO 1328-1:2013: F_p = (0.3 m + 1.25 sqrt(d) + 7) sqrt(2)^(A - 5) um, m and d in mm; the
#: pin ring's d its pin circle's diameter, m = d / Zb), so a <= F_p(class 5).
PIN_RING_CLASS = 5
#: The disc's equidistant and move-distance modifications off the case's [um]: +-15, the span of the
#: RV makers' modifications (Blanche & Yang 1989: 5-30 um) about a drawn value.
CLEARANCE_SPAN_UM = 15.0


def catalog(model) -> list:
    """The effects for a case's model.

    Parameters
    ----------
    model : toothfem.efficiency.loop.te.model.RecordingModel

    Returns
    -------
    list of TeEffect
        Crank-bearing play, each eccentric's eccentricity error (crank k, disc j), a
        stiffness factor per part, the friction factor, every pin's radius change where
        the drive has pins, and the profile clearance (move-distance, equidistant) where
        the drive has those modifications.
    """
    system = model.system(0)
    cranks, discs = system.cranks, system.discs
    out = [TeEffect(
        name="crank_bearing_play",
        parameters=(parameter("crank_bearing_play_um", "um", *PLAY_BOUNDS_UM, 5.0,
                              starts=(5.0, 20.0)),),
        options=lambda v: {("play",): v[0] * M_PER_UM},
        summary="diametral play of the crank (eccentric) bearings: the disc floats in it "
                "near zero torque (lost motion, hysteresis width at the knee)",
        citation="ISO 5753-1:2009 radial internal clearance; the system model's roller "
                 "bearings with play (docs/stiffness.md)",
        direct_test="the crank bearing's radial play on a removed crank (dial gauge, ISO "
                    "5753-1 measuring load), or the lost motion at +-3 % with the cranks "
                    "locked against the discs")]
    for k in range(cranks):
        for j in range(discs):
            out.append(_eccentric_effect(k, j, cranks, system.mesh.eccentricity_m))
    for part in STIFFNESS_PARTS:
        if part not in SCALABLE:
            continue
        out.append(TeEffect(
            name=f"stiffness_{part.replace(' ', '_')}",
            parameters=(parameter("stiffness_factor", "-", *STIFFNESS_BOUNDS, 1.0,
                                  starts=(1.0, 0.6, 1.6)),),
            options=lambda v, part=part: {("stiffness", part): v[0]},
            summary=f"the {part}' stiffness off the model's by a factor: the loop's slope "
                    "(rigidity) and the TE's mean",
            citation="the system model's compliances in series (docs/stiffness.md)",
            direct_test=f"the {part}' deflection under a known load on a press, apart from "
                        "the reducer"))
    out.append(TeEffect(
        name="friction",
        parameters=(parameter("friction_factor", "-", *FRICTION_BOUNDS, 1.0,
                              starts=(1.0, 0.3, 3.0)),),
        options=lambda v: {("friction",): v[0]},
        summary="the path friction's coefficients off the case's by a factor: the "
                "hysteresis loop's width at every torque",
        citation="the path friction of the loop (toothfem.efficiency.no_load.path_friction, "
                 "docs/stiffness.md)",
        direct_test="the no-load starting torque at the output, both directions (the "
                    "friction alone, no elastic twist)"))
    layout = model.drive.layout
    if "pins" in layout.components:
        out.append(TeEffect(
            name="pin_radius_error",
            parameters=(parameter("pin_radius_change_um", "um", *PIN_RADIUS_BOUNDS_UM, 2.0,
                                  starts=(2.0, -2.0)),),
            options=lambda v: {("pin_radius",): v[0] * M_PER_UM},
            summary="every pin's radius off its drawing by one amount (a lot of pins): the "
                    "clearance to the disc, so the backlash, the lost motion and the "
                    "contacts that carry near zero torque",
            citation="ISO 286-1 (IT5 on a 5-10 mm pin: 6 um); the built stage's pin "
                     "radius change (fem/deviations.py)",
            direct_test="the pins' diameter with a micrometer (or the pin lot's gauge "
                        "certificate)"))
        out += _pin_ring_effects(model.drive.geometry)
    # the disc's profile modifications: those the layout's design search varies, read from
    # the stage's own SI geometry (DriveRecord.design_keys)
    keys = layout.design_keys
    if keys:
        out += _clearance_effects(getattr(model.si, layout.stage_section).geometry, keys)
    return out


def _eccentric_effect(k: int, j: int, cranks: int, eccentricity_m: float) -> TeEffect:
    """The centre of crank k's eccentric under disc j off its drawn place: radial (the
    eccentricity error) and tangential (its phase error), both fitted: the phase shows in
    the second harmonic of the crank's turn against the carrier and in the hysteresis width
    (docs/te_rig.md, "The loop")."""
    where = f"crank {k + 1}, disc {j + 1}" if cranks > 1 else f"disc {j + 1}"
    e_um = eccentricity_m / M_PER_UM
    return TeEffect(
        name=f"eccentric_error_{k + 1}_{j + 1}",
        parameters=(parameter("radial_error_um", "um", *ECCENTRIC_BOUNDS_UM, 3.0,
                              starts=(3.0, -3.0, 10.0),
                              doc="along the eccentric's direction: its eccentricity error"),
                    parameter("tangential_error_um", "um", *ECCENTRIC_BOUNDS_UM, 3.0,
                              starts=(0.0, 5.0, -5.0),
                              doc=f"across it, + in the sense of the crank angle: its phase error "
                                  f"times the eccentricity ({e_um:.0f} um; 1 um is "
                                  f"{1 / e_um / ARCMIN:.2f} arcmin)")),
        options=lambda v: {("eccentric", k, j, "radial"): v[0] * M_PER_UM,
                           ("eccentric", k, j, "tangential"): v[1] * M_PER_UM},
        summary=f"the centre of the eccentric under {where} off its drawing: radially (its "
                "eccentricity) and tangentially (its phase against the crank's other "
                "eccentrics): the disc is forced to a compromise pose, a TE ripple once per "
                "turn of the crank against the carrier, its second harmonic and the "
                "hysteresis width by the error's direction, and a ripple of the split "
                "between the discs",
        citation="ISO 286-1 (IT6 on the eccentric's diameter), ISO 1101 (position of its "
                 "axis); the system model's forced crank-bearing deformation "
                 "(docs/te_model.md)",
        direct_test=f"the eccentric under {where} on a roundness tester: its run-out about "
                    "the crank's journals (ISO 1101) gives the eccentricity, its angle "
                    "against the crank's other eccentrics the phase")


def cumulative_pitch_tolerance_um(diameter_mm: float, module_mm: float,
                                   flank_class: int) -> float:
    """ISO 1328-1:2013's total cumulative pitch tolerance F_p [um].

    Parameters
    ----------
    diameter_mm, module_mm : float
        The reference diameter and the normal module [mm].
    flank_class : int
        The flank tolerance class A (1-11).

    Returns
    -------
    float
        (0.3 m + 1.25 sqrt(d) + 7) sqrt(2)^(A - 5).
    """
    return (0.3 * module_mm + 1.25 * math.sqrt(diameter_mm) + 7.0) \
        * math.sqrt(2.0) ** (flank_class - 5)


def _pin_ring_effects(g) -> list:
    """The pin ring's order-1 pitch error and order-2 ovality (PIN_RING_EFFECTS): one
    amplitude each, its orientation round the ring left out (the spectra's amplitudes do
    not see it: 0.37 rad turned moves them by under 1 %, docs/te_rig.md). Costly: their
    TE runs over 4 (2 Zb + h) + 1 sampled pitches (model.ring_samples)."""
    d_mm = 2 * g.pin_circle_radius_m / M_PER_MM
    top = cumulative_pitch_tolerance_um(d_mm, d_mm / g.pin_count, PIN_RING_CLASS)
    out = []
    for name, (key, what) in PIN_RING_EFFECTS.items():
        kind, order = ring_order(key)
        out.append(TeEffect(
            name=name,
            parameters=(parameter(f"{kind}_amplitude_um", "um", 0.0, top, top / 4,
                                  starts=(top / 4, top / 2)),),
            options=lambda v, key=key: {("pin_ring", key): v[0] * M_PER_UM},
            summary=f"{what}: pin j at angle theta_j moved {kind}ly by a cos({order} "
                    "theta_j); the TE ripples at the fitted orders it reaches (2 and the "
                    "pin passing's second multiples) and its hysteresis width moves",
            citation=f"ISO 1328-1:2013 (the bound: F_p of class {PIN_RING_CLASS} on the "
                     f"pin circle, {top:.1f} um); the pins' centre offsets on the system "
                     "model's nominal tables (fem/deviations.py)",
            direct_test="the pins' centres on a coordinate measuring machine, the housing "
                        "bolted as in service: the order-1 tangential part of their "
                        "positions is the cumulative pitch error, the order-2 radial part "
                        "the ovality",
            costly=f"its TE runs over {ring_samples(g.pin_count, order)} sampled pitches "
                   f"of the output revolution, against {DEFAULT_TE_SAMPLES} for the others "
                   "(docs/te_rig.md)"))
    return out


def _clearance_effects(g, keys) -> list:
    """The disc's move-distance and equidistant modifications off the drawing's, for those
    of ``keys`` (the layout's design keys) the geometry ``g`` (SI) has."""
    out = []
    both = "equidistant_modification_mm" in keys
    m0 = float(g.move_distance_m) / M_PER_UM if "move_distance_modification_mm" in keys \
        else 0.0
    e0 = float(g.equidistant_m) / M_PER_UM if both else np.inf
    # one box in which every combination is a disc geometry/cycloid.py accepts (move <=
    # equidistant): the equidistant from e_low up, the move-distance up to e_low, where
    # e_low = max(e0 - span, m0) (the case's own m0 <= e0, so both boxes hold the case)
    e_low = max(e0 - CLEARANCE_SPAN_UM, m0)
    if "move_distance_modification_mm" in keys:
        top = min(m0 + CLEARANCE_SPAN_UM, e_low)
        out.append(TeEffect(
            name="move_distance_clearance",
            # at most the equidistant modification: beyond it the disc's tips and roots
            # would interfere with the pins (geometry/cycloid.py refuses it)
            parameters=(parameter("move_distance_modification_um", "um",
                                  m0 - CLEARANCE_SPAN_UM, top, max(abs(m0), 5.0),
                                  starts=(m0, m0 - 5.0)),),
            options=lambda v: {("move_distance",): v[0] * M_PER_UM},
            summary="the disc's move-distance (radial) modification off the drawing's: "
                    "the clearance at the lobes' tips and roots, the backlash",
            citation="the profile modification on the nominal FE tables (docs/te_model.md)",
            direct_test="the disc's profile on a gear measuring machine (the lobes' normal "
                        "deviation at tip and root)"))
    if both:
        out.append(TeEffect(
            name="profile_clearance",
            parameters=(parameter("equidistant_modification_um", "um",
                                  e_low, e0 + CLEARANCE_SPAN_UM,
                                  max(abs(e0), 5.0), starts=(e0, e0 + 5.0)),),
            options=lambda v: {("equidistant",): v[0] * M_PER_UM},
            summary="the disc's equidistant modification off the drawing's: the backlash "
                    "and the lost motion, the contacts that carry near zero torque",
            citation="the profile modification on the nominal FE tables (docs/te_model.md)",
            direct_test="the disc's profile on a gear measuring machine (the lobes' normal "
                        "deviation, ISO 1328-1 style)"))
    return out


class _EffectsKeywords(TypedDict, total=False):
    """The :class:`Effects` fields :func:`effects_of` sets (the others keep their
    defaults)."""
    crank_bearing_play_m: float
    crank_eccentricity_m: np.ndarray
    crank_phase_rad: np.ndarray
    stiffness_scale: dict[str, float]
    friction_scale: float
    equidistant_modification_m: float
    move_distance_modification_m: float
    pin_radius_m: float
    pin_ring_m: dict[str, float]


def effects_of(options: dict, cranks: int, discs: int) -> Effects:
    """The model's :class:`Effects` from the catalog's flat options.

    Parameters
    ----------
    options : dict
        Flat keys (module docstring) -> value in SI.
    cranks, discs : int
        The shape of the eccentric errors.

    Returns
    -------
    Effects
    """
    ecc = np.zeros((cranks, discs, 2))       # radial, tangential
    stiffness: dict[str, float] = {}
    ring: dict[str, float] = {}
    kw: _EffectsKeywords = {}
    for key, v in options.items():
        if key[0] == "play":
            kw["crank_bearing_play_m"] = float(v)
        elif key[0] == "eccentric":
            ecc[key[1], key[2], ("radial", "tangential").index(key[3])] = float(v)
        elif key[0] == "stiffness":
            stiffness[key[1]] = float(v)
        elif key[0] == "friction":
            kw["friction_scale"] = float(v)
        elif key[0] == "equidistant":
            kw["equidistant_modification_m"] = float(v)
        elif key[0] == "move_distance":
            kw["move_distance_modification_m"] = float(v)
        elif key[0] == "pin_radius":
            kw["pin_radius_m"] = float(v)
        elif key[0] == "pin_ring":
            ring[key[1]] = float(v)
        else:
            raise KeyError(f"not an option of the TE effects: {key!r}")
    if np.any(ecc):
        # the model takes each error as its size and its direction from the eccentric's
        kw["crank_eccentricity_m"] = np.hypot(ecc[..., 0], ecc[..., 1])
        kw["crank_phase_rad"] = np.arctan2(ecc[..., 1], ecc[..., 0])
    if stiffness:
        kw["stiffness_scale"] = stiffness
    if ring:
        kw["pin_ring_m"] = ring
    return Effects(**kw)
