"""What ``toothfem new`` asks of a K-H-V cycloid drive and the sections it writes: the disc
with its centre bore round the eccentric bearing and the output pins through its holes."""
from __future__ import annotations

from ...case_template import (OPERATING_HELP, OPERATING_RANGES, OUTPUT_PIN_COUNT,
                              OUTPUT_PIN_FRICTION, LayoutSections, NewCaseTemplate, put,
                              round_to, zero_clearance)
from ...cycloid_template import (DISC_HELP, DISC_RANGES, ECCENTRICITY_RANGE, GREASE,
                                 HOLE_PER_HALF_SPACING, HOLE_PER_ROOM, PIN_GROOVE_FRICTION,
                                 centre_bore, check_lobes, cycloid_stage, disc_keys, disc_lobes,
                                 disc_name, hole_radius, pin_tolerances)
from ...fem.datasheet.supports import ROLLER_DIAMETER_REL


#: Centre bore per root radius of the disc, rounded up. ASSUMPTION: K-H-V, the eccentric
#: roller bearing sits in it (the shipped K-H-V case: 14 mm of 45.8 mm, 0.31); RV, only the
#: input shaft passes (RV-40E-like 8 mm of 59.7 mm, 0.13).
KHV_BORE_PER_ROOT = 0.3


PIN_PER_ROLLER = 0.73


def khv_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of a K-H-V cycloid drive: the disc, its centre bore round the eccentric
    bearing and the output pins through its holes.

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
    za, lobes_kind = disc_lobes(template, given)
    s: dict = {}
    root, step = cycloid_stage(s, given, za, lobes_kind)
    e = given["eccentricity_mm"]
    h = "cycloid.disc_holes"
    bore, capped, largest = centre_bore(KHV_BORE_PER_ROOT, root, step)
    put(s, h, "centre_bore_radius_mm", bore, "assumption",
        f"{KHV_BORE_PER_ROOT:g} of the root radius {root:.4g} mm: the eccentric "
        "roller bearing's outer race (the shipped K-H-V case: 0.31)" + (
             f"; at most {largest:g} mm, the model's input bearings (ISO 15 series 0 on a "
             "shaft of the bore's diameter) end there" if capped else ""))
    circle = round_to(0.5 * (bore + root), step)
    hole, room = hole_radius(circle, bore, root, OUTPUT_PIN_COUNT)
    fine = 0.1 if step >= 0.5 else 0.01
    roller, hole = zero_clearance(round_to(hole - e, fine), e)
    pin = round_to(PIN_PER_ROLLER * roller, fine)
    om = "output_mechanism"
    put(s, om, "pin_count", OUTPUT_PIN_COUNT, "assumption",
        "eight output pins, as the shipped K-H-V and sine cases")
    put(s, om, "pin_hole_circle_radius_mm", circle, "assumption",
        "midway between the centre bore and the disc's root circle")
    put(s, om, "roller_radius_mm", roller, "assumption",
        f"the hole ({HOLE_PER_ROOM:g} of the {room:.4g} mm room, at most "
        f"{HOLE_PER_HALF_SPACING:g} of the half spacing) less the eccentricity; the "
        "sleeve touches the hole")
    put(s, om, "pin_radius_mm", pin, "assumption",
        f"{PIN_PER_ROLLER:g} of the roller's (the shipped K-H-V case: 4 in 5.5 mm)")
    put(s, om, "hole_radius_mm", hole, "assumption",
        "the roller's radius plus the eccentricity: zero nominal clearance, the K-H-V "
        "mechanism's kinematics (the model's default)")
    put(s, om, "eccentric_bearing_inner_radius_mm",
        round_to(bore * (1 - ROLLER_DIAMETER_REL), fine), "assumption",
        f"the bore less one roller of {ROLLER_DIAMETER_REL:g} of its radius (the "
        "system model's assumed rollers, fem/datasheet/supports.py)")
    return LayoutSections(s, given["pin_circle_radius_mm"])


#: A K-H-V cycloid drive: the disc's key numbers; output pins through its holes.
KHV_TEMPLATE = NewCaseTemplate(
    required=("pins", "pin_circle_radius_mm", "eccentricity_mm", "torque_Nm",
              "input_speed_rpm"),
    optional=("lobes",),
    key_ranges=DISC_RANGES | OPERATING_RANGES | ECCENTRICITY_RANGE,
    key_help=DISC_HELP | OPERATING_HELP,
    check=check_lobes, direct_keys=disc_keys, build=khv_sections,
    radius_name="pin-circle radius", lubrication=GREASE,
    friction=(OUTPUT_PIN_FRICTION, PIN_GROOVE_FRICTION), tolerances=pin_tolerances,
    name_size=disc_name)
