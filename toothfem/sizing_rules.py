"""The rules of ``toothfem size`` (docs/sizing.md): each dimension of a 2K-V reducer from a
named rule or standard, in the case's units (mm, N m, MPa). :mod:`toothfem.sizing` searches
with them on the system model."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .units import M_PER_MM, MM_PER_M

@dataclass(frozen=True)
class Choice:
    """One sized case key: its ``value``, the ``rule`` that chose it and its ``source``."""
    key: str
    value: float
    rule: str
    source: str


#: Steps of the sized dimensions [mm]: holes and pillars to half a millimetre, the disc
#: width to a millimetre (ground discs come in whole millimetres).
HOLE_STEP_MM, WIDTH_STEP_MM = 0.5, 1.0
#: Crankshafts tried, fewest first (each with its planet and a pillar between each pair):
#: the catalogue's RV units run two or three.
CRANK_COUNTS = (2, 3)
#: ASSUMPTION: the widest disc, as a share of the pin circle's radius (RV discs: 0.1-0.25;
#: a wider disc tilts on its crank bearings and loads its edges, which the plane model
#: does not see).
WIDTH_MAX_PER_RADIUS = 0.25
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
    disc's root circle.

    Parameters
    ----------
    circle_mm, bore_mm, root_mm : float
        The crank circle's, the centre bore's and the root circle's radii [mm].

    Returns
    -------
    float
        [mm].
    """
    return min(circle_mm - bore_mm, root_mm - circle_mm)


def largest_crank_hole_mm(circle_mm, bore_mm, root_mm, cranks, pillar_hole_mm) -> float:
    """The largest crank hole that leaves the web :data:`WEB_PER_ROOM` of the room to the
    root circle and the bore, and to the neighbouring pillar hole (cranks and pillars
    alternate on the one circle), rounded down to :data:`HOLE_STEP_MM`.

    Parameters
    ----------
    circle_mm, bore_mm, root_mm : float
        The crank circle's, the centre bore's and the root circle's radii [mm].
    cranks : int
        Cranks on the circle (as many pillars between them).
    pillar_hole_mm : float
        The pillar hole's radius [mm].

    Returns
    -------
    float
        The crank hole's radius [mm].
    """
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
    takes the shaft.

    Parameters
    ----------
    shaft_mm : float
        The crankshaft's diameter [mm].

    Returns
    -------
    tuple of float
        (bore, outside diameter, width) [mm].
    """
    from .efficiency.bearing_set import standard_size
    bore, outer, width = standard_size(shaft_mm * M_PER_MM, "supports.crankshaft_diameter_mm")
    return bore * MM_PER_M, outer * MM_PER_M, width * MM_PER_M


def axial_stack_mm(discs: int, width_mm: float, support_width_mm: float,
                   spur_width_mm: float) -> float:
    """The reducer's axial length: the discs side by side, a support bearing and a carrier
    wall (:data:`SHOULDER_MM`) each side, and the first stage's gears outside the end plate.

    Parameters
    ----------
    discs : int
    width_mm, support_width_mm, spur_width_mm : float
        The disc's, the support bearing's and the first stage's widths [mm].

    Returns
    -------
    float
        [mm].
    """
    return discs * width_mm + 2 * (support_width_mm + SHOULDER_MM) + spur_width_mm


def round_to_step(x: float, step: float, how: str) -> float:
    """``x`` rounded up or down to a multiple of ``step``.

    Parameters
    ----------
    x, step : float
    how : {"up", "down"}

    Returns
    -------
    float
    """
    f = {"up": math.ceil, "down": math.floor}[how]
    return float(f(x / step - 1e-9 if how == "up" else x / step + 1e-9) * step)




def sizing_choices(d, case, targets, circle, room, bore, root, pillars, spur_w, pillar_dia,
             built, module_rule) -> list:
    """Every sized key of design ``d`` with its rule, in the words of the case file's
    comments (``sized: <rule>``) and sizing.json.

    Parameters
    ----------
    d : toothfem.sizing._Design
    case : toothfem.case.Case
    targets : toothfem.sizing.Targets
    circle, room, bore, root : float
        The crank circle's radius, its room, the bore's and the root's radii [mm].
    pillars : int
    spur_w : float
        The first stage's face width [mm].
    pillar_dia : float
        The pillar the momentary torque needs [mm].
    built : dict or None
        The as-built ensemble of the final design (:func:`toothfem.sizing.as_built`).
    module_rule : str
        The module's rule, in words.

    Returns
    -------
    list of Choice
    """
    e, discs = case.cycloid.eccentricity_mm, case.cycloid.disc_count
    shaft = d.shaft(e)
    bore_s, outer_s, width_s = support_bearing_mm(shaft)
    out = [
        Choice("cycloid.disc_holes.crank_hole_count", d.cranks,
               f"the fewest crankshafts of {CRANK_COUNTS} that reach every target",
               "the catalogue's RV units run two or three"),
        Choice("first_stage.planet_count", d.cranks, "one planet on each crankshaft",
               "the 2K-V train"),
        Choice("cycloid.disc_holes.pillar_hole_count", d.cranks,
               "one carrier pillar between each pair of cranks", "the RV layout"),
        Choice("first_stage.module_mm", d.module, module_rule, "ISO 54:1996 series I"),
        Choice("cycloid.disc_holes.crank_hole_circle_radius_mm", d.circle,
               f"the first stage's centre distance m (z1 + z2) / 2 = {circle:.4g} mm (each "
               "planet sits on its crank)", "the 2K-V train's kinematics"),
        Choice("cycloid.disc_holes.crank_hole_radius_mm", d.crank_hole,
               f"the smallest hole (0.5 mm steps, at most {1 - WEB_PER_ROOM:g} of the "
               f"{room:.4g} mm room) whose needle set gives the unit L10 of "
               f"{targets.rated_life_h:g} h at the rated point with the disc width",
               "ISO 281:2007 (needle rollers: a quarter of the hole's radius, 1.2 diameters "
               "apart)"),
        Choice("cycloid.face_width_mm", d.width,
               f"the narrowest disc (from 0.1 of the pin circle, 1 mm steps) with the life "
               f"above and the reducer's P_h at {targets.rated_torque_Nm:g} N m within "
               f"material.allowable_contact_stress_MPa", "ISO 281:2007; Hertz line contact"),
        Choice("cycloid.disc_holes.pillar_hole_circle_radius_mm", d.circle,
               "on the crank circle, halfway between the cranks", "the RV layout"),
        Choice("cycloid.disc_holes.pillar_hole_radius_mm", d.pillar_hole,
               f"a pillar of at least {pillar_dia:.3g} mm (yield at the momentary "
               f"{targets.momentary_torque_Nm:g} N m, half of it through the pillars) plus "
               "the eccentricity and a 0.5 mm gap, grown to the rigidity target where short",
               "Roark's Formulas, Table 8.1 case 1e (fixed-guided beam)"),
        Choice("supports.crankshaft_diameter_mm", shaft,
               f"the journal (the hole less two needles) less twice the eccentricity; its "
               f"support bearings ISO 15 series 0, {bore_s:g} x {outer_s:g} x {width_s:g} mm",
               "ISO 15:2017"),
        Choice("supports.crankshaft_span_mm", d.span(discs, e),
               f"{discs} discs, a {SHOULDER_MM:g} mm carrier wall each side, half a support "
               f"bearing's {width_s:g} mm each side", "the RV layout (ASSUMPTION: the walls)"),
    ]
    if built is not None:
        out.append(Choice(
            "cycloid.equidistant_modification_mm", round(d.equidistant, 6),
            f"the smallest (0.5 um steps) that leaves at most {INTERFERING_MAX:.0%} of "
            f"{built['rings']} reducers built within [tolerances] interfering and their "
            "median backlash at least 0", "the tolerance ensemble (docs/tolerance.md)"))
    return out
