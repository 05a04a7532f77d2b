"""The rules of ``toothfem size`` (docs/sizing.md): each dimension of a 2K-V reducer from a
named rule or standard, in the case's units (mm, N m, MPa). :mod:`toothfem.sizing` searches
with them on the system model."""
from __future__ import annotations

import math

from .units import M_PER_MM, MM_PER_M

#: Steps of the sized dimensions [mm]: holes and pillars to half a millimetre, the disc
#: width to a millimetre (ground discs come in whole millimetres).
HOLE_STEP_MM, WIDTH_STEP_MM = 0.5, 1.0
#: ASSUMPTION: the disc's web between a crank hole and the root circle, the centre bore
#: or a neighbouring hole is at least this share of the crank circle's radial room (a
#: quarter: the web carries the pins' resultant round the hole; RV discs of the catalogue
#: sizes show webs of a quarter to a third of the room).
WEB_PER_ROOM = 0.25
#: ASSUMPTION: the carrier's wall between a disc and a support bearing [mm], each side.
SHOULDER_MM = 2.0
#: The end plate's share of the cranks' support force: discs set symmetrically between
#: the two support bearings of each crank (fem/datasheet/supports.py).
PLATE_SHARE = 0.5
#: Rounds of the search on the system model (each solves the candidate once).
MAX_ROUNDS = 8
#: As-built targets: at most this share of the built reducers interferes (P5 of the
#: backlash >= 0), judged on this many rings at this many positions each.
INTERFERING_MAX, RINGS, RING_POSITIONS = 0.05, 40, 6
#: Step of the profile modification [mm]: half a micrometre.
MOD_STEP_MM = 0.0005


def iso54_module(wanted_mm: float) -> float:
    """The ISO 54:1996 series I module nearest ``wanted_mm``.

    Parameters
    ----------
    wanted_mm : float

    Returns
    -------
    float
        [mm].
    """
    from .layouts.rv.template import ISO54_MODULES_MM
    return min(ISO54_MODULES_MM, key=lambda m: abs(m - wanted_mm))


def crank_room_mm(circle_mm: float, bore_mm: float, root_mm: float) -> float:
    """The crank circle's radial room: the smaller distance to the centre bore and to the
    disc's root circle [mm]."""
    return min(circle_mm - bore_mm, root_mm - circle_mm)


def largest_crank_hole_mm(circle_mm, bore_mm, root_mm, cranks, pillar_hole_mm) -> float:
    """The largest crank hole [mm] that leaves the web :data:`WEB_PER_ROOM` of the room to
    the root circle and the bore, and to the neighbouring pillar hole (cranks and pillars
    alternate on the one circle), rounded down to :data:`HOLE_STEP_MM`."""
    room = crank_room_mm(circle_mm, bore_mm, root_mm)
    web = WEB_PER_ROOM * room
    between = 2 * circle_mm * math.sin(math.pi / (2 * cranks)) - pillar_hole_mm - web
    return round_to_step(min(room - web, between), HOLE_STEP_MM, "down")


def pillar_diameter_mm(momentary_torque_Nm, pillars, circle_mm, length_mm,
                       yield_strength_MPa) -> float:
    """The smallest pillar that carries the momentary torque without yielding [mm]: the
    end plate's share s T crosses the pillars (:data:`PLATE_SHARE`), each a fixed-guided
    beam whose end moment F L / 2 (Roark, Table 8.1 case 1e) bends it to
    32 M / (pi d^3) <= the yield strength (the catalogue's momentary torque: the torque
    no part may yield at).

    Parameters
    ----------
    momentary_torque_Nm : float
    pillars : int
    circle_mm, length_mm : float
        Their circle's radius and free length [mm].
    yield_strength_MPa : float

    Returns
    -------
    float
        d [mm].
    """
    force = PLATE_SHARE * momentary_torque_Nm / (pillars * circle_mm * M_PER_MM)
    moment = force * length_mm * M_PER_MM / 2
    d = (32 * moment / (math.pi * yield_strength_MPa * 1e6)) ** (1 / 3)
    return d * MM_PER_M


def support_bearing_mm(shaft_mm: float) -> tuple:
    """The support bearing of a crankshaft: the smallest ISO 15 diameter series 0 bore that
    takes the shaft, its outside diameter and width [mm]."""
    from .efficiency.bearing_set import standard_size
    bore, outer, width = standard_size(shaft_mm * M_PER_MM, "supports.crankshaft_diameter_mm")
    return bore * MM_PER_M, outer * MM_PER_M, width * MM_PER_M


def axial_stack_mm(discs: int, width_mm: float, support_width_mm: float,
                   spur_width_mm: float) -> float:
    """The reducer's axial length [mm]: the discs side by side, a support bearing and a
    carrier wall (:data:`SHOULDER_MM`) each side, and the first stage's gears outside the
    end plate."""
    return discs * width_mm + 2 * (support_width_mm + SHOULDER_MM) + spur_width_mm


def round_to_step(x: float, step: float, how: str) -> float:
    """``x`` rounded up or down (``how``) to a multiple of ``step``."""
    f = {"up": math.ceil, "down": math.floor}[how]
    return float(f(x / step - 1e-9 if how == "up" else x / step + 1e-9) * step)


