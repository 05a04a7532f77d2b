"""What ``toothfem new`` asks of a one-tooth-difference sine reducer and the sections it
writes: the pair, sized by one of its sizes, and its output pins."""
from __future__ import annotations

from ...case_sections import SineStage
from ...case_template import (OPERATING_HELP, OPERATING_RANGES, OPTIONS, OUTPUT_PIN_COUNT,
                              OUTPUT_PIN_FRICTION, LayoutSections, NewCaseTemplate,
                              entry_value, field_range, put, round_to)
from ...errors import CaseError, GeometryError, check_range
from ...geometry import sine
from ...units import M_PER_MM, MM_PER_M, UM_PER_M


#: A sine pair's size: exactly one of these (with the tooth numbers, each fixes the other
#: two). What each layout takes is its :class:`NewCaseTemplate` (the templates below); what
#: each layout is, in the file's header and the command's help, its record's ``label``.
SINE_SIZE = ("module_mm", "eccentricity_mm", "ring_pitch_radius_mm")


#: Sine tooth height per its largest valid value (no interference, a monotone contact
#: path; m/2 at one tooth difference). ASSUMPTION: the sine paper's prototype (0.4 mm of
#: 0.45 mm); raised to the load-carrying bound where that is higher.
TOOTH_HEIGHT_PER_MAX = 0.9


#: Sine output mechanism per planet pitch radius r1 (pin circle R_w, pin radius r_x, the
#: eccentric bearing's inner radius r_p). ASSUMPTION: the sine paper's prototype, Table 4
#: (26.2, 6 and 10 mm at r1 = 35.55 mm).
SINE_OUTPUT_PER_R1 = {"pin_hole_circle_radius_mm": 26.2 / 35.55,
                      "pin_radius_mm": 6.0 / 35.55,
                      "eccentric_bearing_inner_radius_mm": 10.0 / 35.55}


def check_sine(given: dict) -> None:
    """A sine pair's size given once (:data:`SINE_SIZE`), its ring's teeth above the
    planet's.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).
    """
    sizes = [k for k in SINE_SIZE if given.get(k) is not None]
    if len(sizes) != 1:
        one_of = ", ".join(OPTIONS[k] for k in SINE_SIZE)
        raise CaseError(f"a sine drive's size is one of {one_of} (exactly one: each fixes "
                        "the others with the tooth numbers); given: "
                        f"{', '.join(OPTIONS[k] for k in sizes) or 'none'}")
    z1 = given["teeth"]
    if given.get("ring_teeth") is not None:
        check_range("--ring-teeth", given["ring_teeth"], z1 + 1, None, error=CaseError,
                    why="an internal mesh: the ring has more teeth than the planet "
                        "(--teeth)")


def sine_keys(given: dict) -> dict:
    """A sine pair's: its tooth numbers, and its module where that gives the size.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    dict
        Case key -> key number.
    """
    keys = {"sine.planet_teeth": "teeth", "sine.ring_teeth": "ring_teeth"}
    size = next(k for k in SINE_SIZE if given.get(k) is not None)
    if size == "module_mm":
        keys["sine.module_mm"] = "module_mm"
    return keys


def sine_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of a one-tooth-difference sine reducer: the pair, sized by the one of
    :data:`SINE_SIZE` given, and its output pins.

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
    z1 = given["teeth"]
    z2 = given.get("ring_teeth") or z1 + 1
    dz = z2 - z1
    size = next(k for k in SINE_SIZE if given.get(k) is not None)
    per_module = {"module_mm": 1.0, "eccentricity_mm": dz / 2, "ring_pitch_radius_mm": z2 / 2}
    lo, hi = (v * per_module[size] for v in (field_range(SineStage, "module_mm")["lo"],
                                             field_range(SineStage, "module_mm")["hi"]))
    check_range(OPTIONS[size], given[size], lo, hi, error=CaseError,
                why="the module's range, 0.05-100 mm (ISO 54), times "
                    f"{per_module[size]:g} at these tooth numbers")
    m = float(f"{given[size] / per_module[size]:.10g}")
    s: dict = {}
    put(s, "sine", "planet_teeth", z1, "key", "--teeth (z1)")
    put(s, "sine", "ring_teeth", z2,
        *(("key", "--ring-teeth (z2)") if given.get("ring_teeth") else
          ("follows", "z1 + 1: one tooth difference")))
    put(s, "sine", "module_mm", m, *(("key", "--module-mm") if size == "module_mm" else
                                       ("follows", f"from {OPTIONS[size]} = {given[size]:g}")))
    top = sine.tooth_height_limits(z1, z2, m * M_PER_MM).max * MM_PER_M
    step = 0.01 if top >= 0.2 else 0.001
    a = round_to(TOOTH_HEIGHT_PER_MAX * top, step, "down")
    why = (f"{TOOTH_HEIGHT_PER_MAX:g} of the largest valid {top:.4g} mm (the sine paper's "
           "prototype: 0.4 of 0.45 mm)")
    try:
        sine.check_load_carrying(sine.SineGearPair(z1, z2, m * M_PER_MM, a * M_PER_MM, 1e-3))
    except GeometryError:
        low = sine.min_tooth_height_m(z1, z2, m * M_PER_MM) * MM_PER_M
        a = min(round_to(low, step, "up"), top)
        why = (f"the load-carrying bound {low:.4g} mm (a drive flank within "
               f"{sine.LOAD_CARRYING_GAP_M * UM_PER_M:g} um at every crank angle), rounded up; "
               f"the largest valid is {top:.4g} mm")
    put(s, "sine", "tooth_height_mm", a, "assumption", why)
    put(s, "sine", "face_width_mm", None, "assumption", "")
    put(s, "sine", "centre_distance_mm", float(f"{m * dz / 2:.10g}"), "follows",
        "the eccentricity a0 = m (z2 - z1) / 2")
    r1 = m * z1 / 2
    fine = 0.1 if r1 >= 10 else 0.01
    om = "output_mechanism"
    put(s, om, "pin_count", OUTPUT_PIN_COUNT, "assumption",
        "eight output pins, as the shipped sine and K-H-V cases")
    for key, share in SINE_OUTPUT_PER_R1.items():
        put(s, om, key, round_to(share * r1, fine), "assumption",
            f"{share:.3g} of the planet's pitch radius {r1:.4g} mm (the sine paper's "
            "prototype, Table 4)")
    return LayoutSections(s, m * z2 / 2, ("output_mechanism.plain_bearing_friction_torque_"
                                          "Nmm: 0 (the model's default; the sine paper "
                                          "gives none)",))


def sine_tolerances(s: dict) -> tuple:
    """A sine pair's: its tooth profile's.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.

    Returns
    -------
    tuple of (str, float, str)
        Key, value [mm] and reason.
    """
    return (("tooth_profile_mm", 0.003,
             "+- limit of each flank, ground teeth (as the shipped sine case)"),)


def sine_name(given: dict, s: dict) -> str:
    """A sine pair's size in the case's default name.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).
    s : dict
        Section -> its entries so far.

    Returns
    -------
    str
    """
    return f"{given['teeth']} teeth, module {entry_value(s, 'sine', 'module_mm'):g} mm"


#: A one-tooth-difference sine reducer: the tooth numbers and one size; output pins.
SINE_TEMPLATE = NewCaseTemplate(
    required=("teeth", "torque_Nm", "input_speed_rpm"),
    optional=("ring_teeth", "module_mm", "eccentricity_mm", "ring_pitch_radius_mm"),
    sizes=SINE_SIZE,
    key_ranges={"teeth": (SineStage, "planet_teeth"), "ring_teeth": (SineStage, "ring_teeth"),
                "module_mm": (SineStage, "module_mm")} | OPERATING_RANGES,
    key_help={"teeth": "the planet's teeth z1",
              "ring_teeth": "the ring's teeth (default z1 + 1)",
              "module_mm": "the module [mm]",
              "eccentricity_mm": "the centre distance a0 (one way to give its size)",
              "ring_pitch_radius_mm": "the ring's pitch radius [mm]"} | OPERATING_HELP,
    check=check_sine, direct_keys=sine_keys, build=sine_sections,
    radius_name="ring's pitch radius",
    lubrication=("oil_bath", "a horizontal reducer half in oil (the sine paper's rig)"),
    friction=(OUTPUT_PIN_FRICTION,), tolerances=sine_tolerances, name_size=sine_name)
