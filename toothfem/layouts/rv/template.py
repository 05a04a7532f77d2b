"""What ``toothfem new`` asks of an RV reducer and the sections it writes: its train, the
disc, the crank and pillar holes between the centre bore and the root circle, and the
first stage whose centre distance puts the cranks there."""
from __future__ import annotations

from ...case_sections import RVTrain, SpurStage
from ...case_template import (OPERATING_HELP, OPERATING_RANGES, LayoutSections,
                              NewCaseTemplate, put, round_to)
from ...cycloid_template import (DISC_COUNT, DISC_HELP, DISC_RANGES, ECCENTRICITY_RANGE, GREASE,
                                 HOLE_PER_HALF_SPACING, HOLE_PER_ROOM, PIN_GROOVE_FRICTION,
                                 centre_bore, check_lobes, cycloid_stage, disc_keys, disc_lobes,
                                 disc_name, hole_radius, pin_tolerances)


RV_BORE_PER_ROOT = 0.13


#: An RV drive's crankshafts (one planet each) and carrier pillars, and a pillar hole's
#: radius per crank hole's. ASSUMPTION: the shipped RV cases (two of each, 8 mm pillars
#: beside 10 mm crank holes).
CRANK_COUNT = 2


PILLAR_COUNT = 2


PILLAR_PER_CRANK = 0.8


#: ISO 54:1996 modules, series I [mm]: an RV first stage takes the one nearest the module
#: that puts the crankshafts midway between the bore and the root circle.
ISO54_MODULES_MM = (0.05, 0.06, 0.08, 0.1, 0.12, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.8,
                    1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0,
                    20.0, 25.0, 32.0, 40.0, 50.0)


#: First-stage pressure angle [deg]: ISO 53's standard basic rack.
PRESSURE_ANGLE_DEG = 20.0


def rv_keys(given: dict) -> dict:
    """An RV reducer's: its disc stage's, its train's and its first stage's.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    dict
        Case key -> key number.
    """
    return disc_keys(given) | {
        "rv.pin_count": "pins", "rv.disc_teeth": "lobes", "rv.sun_teeth": "sun_teeth",
        "rv.planet_teeth": "planet_teeth", "first_stage.sun_teeth": "sun_teeth",
        "first_stage.planet_teeth": "planet_teeth"}


def rv_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of an RV reducer: its train, the disc, the crank and pillar holes
    between the centre bore (the input shaft only) and the root circle, the first stage
    whose centre distance puts the cranks there.

    Parameters
    ----------
    template : NewCaseTemplate
        The layout's template.
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    toothfem.case_template.LayoutSections
    """
    zb, z1, z2 = given["pins"], given["sun_teeth"], given["planet_teeth"]
    za, lobes_kind = disc_lobes(template, given, train=lambda za: RVTrain(
        sun_teeth=z1, planet_teeth=z2, disc_teeth=za, pin_count=zb))
    s: dict = {}
    put(s, "rv", "sun_teeth", z1, "key", "--sun-teeth (z1)")
    put(s, "rv", "planet_teeth", z2, "key", "--planet-teeth (z2)")
    put(s, "rv", "disc_teeth", za, *lobes_kind)
    put(s, "rv", "pin_count", zb, "key", "--pins")
    put(s, "rv", "disc_count", DISC_COUNT, "assumption",
        "two discs 180 deg apart balance their eccentric forces")
    put(s, "rv", "mesh_efficiency",
        RVTrain.__dataclass_fields__["mesh_efficiency"].default, "assumption",
        "the RV paper's value for every gear pair (read by --method rv_split_power only)")
    root, step = cycloid_stage(s, given, za, lobes_kind)
    h = "cycloid.disc_holes"
    bore, _, _ = centre_bore(RV_BORE_PER_ROOT, root, step)
    put(s, h, "centre_bore_radius_mm", bore, "assumption",
        f"{RV_BORE_PER_ROOT:g} of the root radius {root:.4g} mm: the input shaft "
        "passes (the RV-40E-like case: 0.13)")
    wanted = 2 * 0.5 * (bore + root) / (z1 + z2)
    module = min(ISO54_MODULES_MM, key=lambda m: abs(m - wanted))
    circle = float(f"{module * (z1 + z2) / 2:.10g}")
    holes = CRANK_COUNT + PILLAR_COUNT
    crank, room = hole_radius(circle, bore, root, holes)
    fine = step if step <= 0.5 else 0.5
    crank = round_to(crank, fine)
    put(s, h, "crank_hole_count", CRANK_COUNT, "assumption",
        "two crankshafts, one planet each (the shipped RV cases)")
    put(s, h, "crank_hole_circle_radius_mm", circle, "follows",
        f"the first stage's centre distance m (z1 + z2) / 2 at m = {module:g} mm")
    put(s, h, "crank_hole_radius_mm", crank, "assumption",
        f"{HOLE_PER_ROOM:g} of the {room:.4g} mm room between the bore and the root "
        f"circle (at most {HOLE_PER_HALF_SPACING:g} of the half spacing): the needle "
        "bearing on the crank's journal")
    put(s, h, "pillar_hole_count", PILLAR_COUNT, "assumption",
        "two carrier pillars between the cranks (the shipped RV cases)")
    put(s, h, "pillar_hole_circle_radius_mm", circle, "assumption",
        "on the cranks' circle, halfway between them")
    put(s, h, "pillar_hole_radius_mm", round_to(PILLAR_PER_CRANK * crank, fine),
        "assumption", f"{PILLAR_PER_CRANK:g} of the crank hole's (the shipped RV cases)")
    fs = "first_stage"
    put(s, fs, "sun_teeth", z1, "key", "--sun-teeth")
    put(s, fs, "planet_teeth", z2, "key", "--planet-teeth")
    put(s, fs, "planet_count", CRANK_COUNT, "follows", "one planet per crankshaft")
    put(s, fs, "module_mm", module, "assumption",
        f"the ISO 54 module nearest {wanted:.3g} mm, which puts the cranks midway "
        "between the bore and the root circle")
    put(s, fs, "pressure_angle_deg", PRESSURE_ANGLE_DEG, "assumption",
        "ISO 53 standard basic rack")
    return LayoutSections(s, given["pin_circle_radius_mm"], (
        "first_stage.face_width_mm: the model's 10 modules",
        "bearings.eccentric_type: needle rollers in the crank holes (the model's "
        "default, RV reducers' crank bearings)"))


def rv_tolerances(s: dict) -> tuple:
    """An RV reducer's: its cycloid stage's and its crank holes' position.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.

    Returns
    -------
    tuple of (str, float, str)
        Key, value [mm] and reason.
    """
    return pin_tolerances(s) + (("crank_hole_position_mm", 0.005,
                                 "true-position zone of the crank holes"),)


#: An RV reducer: the disc's key numbers and the first stage's tooth numbers.
RV_TEMPLATE = NewCaseTemplate(
    required=("pins", "pin_circle_radius_mm", "eccentricity_mm", "sun_teeth",
              "planet_teeth", "torque_Nm", "input_speed_rpm"),
    optional=("lobes",),
    key_ranges=DISC_RANGES | {"sun_teeth": (SpurStage, "sun_teeth"),
                              "planet_teeth": (SpurStage, "planet_teeth")}
    | OPERATING_RANGES | ECCENTRICITY_RANGE,
    key_help=DISC_HELP | {"sun_teeth": "the first stage's sun teeth",
                          "planet_teeth": "the first stage's planet teeth"}
    | OPERATING_HELP,
    check=check_lobes, direct_keys=rv_keys, build=rv_sections,
    radius_name="pin-circle radius", lubrication=GREASE,
    friction=(PIN_GROOVE_FRICTION,), tolerances=rv_tolerances, name_size=disc_name)
