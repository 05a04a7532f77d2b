"""What ``toothfem new`` asks of a layout and the rules every layout's template shares
(docs/architecture.md, "Adding a layout"): the key numbers and their options, the
:class:`NewCaseTemplate` each layout package fills (``Layout.case_template``), the entries
of a case text with their kind and reason, and the sizing rules of a cycloid stage that the
K-H-V and RV templates both take (the pin radius, the holes in the disc, the tolerances).

:mod:`toothfem.case_new` turns a template and its key numbers into a case file; this module
computes nothing that needs the case loader, so the layouts' templates sit below it.
Units: the key numbers' (mm, N m, rpm).
"""
from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from .case_checks import PIN_RADIUS_MM
from .case_sections import CycloidStage, Operating
from .efficiency.bearing_set import ISO15_SERIES_0
from .errors import CaseError, ToothfemError, check_range
from .geometry.cycloid import CycloidGeometry, min_convex_curvature_radius
from .units import M_PER_MM, MM_PER_M

# -- the key numbers ------------------------------------------------------------------------
#: Keyword of :func:`new_case` -> the command-line option that gives it (messages name it).
OPTIONS = {
    "pins": "--pins", "lobes": "--lobes", "pin_circle_radius_mm": "--pin-circle-radius-mm",
    "eccentricity_mm": "--eccentricity-mm", "sun_teeth": "--sun-teeth",
    "planet_teeth": "--planet-teeth", "teeth": "--teeth", "ring_teeth": "--ring-teeth",
    "module_mm": "--module-mm", "ring_pitch_radius_mm": "--ring-pitch-radius-mm",
    "torque_Nm": "--torque-Nm", "input_speed_rpm": "--input-speed-rpm",
}


#: The key numbers that are lengths, torques or speeds (floats in the file); the rest count.
FLOAT_KEY_NUMBERS = ("pin_circle_radius_mm", "eccentricity_mm", "module_mm",
                     "ring_pitch_radius_mm", "torque_Nm", "input_speed_rpm")


# -- the rules and their reasons --------------------------------------------------------------
#: Pin radius per pin pitch 2 pi Rz / Zb. ASSUMPTION: the shipped conventional-pin cases
#: (RV-40E-like 3.0 mm on a 10.05 mm pitch, 0.30; the K-H-V robot joint 3.0 on 10.5, 0.29).
PIN_RADIUS_PER_PITCH = 0.3


#: Largest pin radius per the undercut bound (the smallest convex curvature radius of the
#: theoretical profile): a fifth of margin keeps the working profile's sharpest convex
#: point from a cusp where K1 is high.
PIN_RADIUS_PER_UNDERCUT = 0.8


#: Discs of a cycloid stage. ASSUMPTION: two discs 180 deg apart balance each other's
#: eccentric force (every shipped cycloid case).
DISC_COUNT = 2


#: A hole's radius per the radial room of its circle (the smaller distance to the bore and
#: to the root circle), capped at a share of half the spacing of the holes on that circle.
#: ASSUMPTION: the shipped K-H-V case (6.7 mm holes in a 15.8 mm room, 0.42; 0.58 of the
#: half spacing) and the RV-40E-like crank holes (10 mm in 23.7 mm at m = 1.5: 0.42).
HOLE_PER_ROOM = 0.42


HOLE_PER_HALF_SPACING = 0.6


#: K-H-V output pins. ASSUMPTION: eight, as the shipped K-H-V and sine cases; the pin's
#: radius 0.73 of its roller's (the shipped K-H-V case: 4 mm pins in 5.5 mm rollers).
OUTPUT_PIN_COUNT = 8


#: Step [mm] by which a roller's radius may move so that the zero-clearance hole round it
#: is written in a few digits (``zero_clearance``): a hundredth, below any fit's tolerance.
ROLLER_NUDGE_MM = 0.01


#: ISO 286-1 standard tolerance grade IT5 [um] by diameter range (upper limits [mm]): the
#: h5 pins' lower diameter deviation (the shipped cases: h5, -5 um on 3-6 mm).
IT5_UM = ((3.0, 4.0), (6.0, 5.0), (10.0, 6.0), (18.0, 8.0), (30.0, 9.0), (50.0, 11.0),
          (80.0, 13.0), (120.0, 15.0), (180.0, 18.0), (250.0, 20.0), (315.0, 23.0),
          (400.0, 25.0))


@dataclass(frozen=True)
class Entry:
    """One key of the new file: its ``value``, and the ``note`` after it; ``kind`` says
    what the value is: "key" (a key number, note the option), "follows" (fixed by the key
    numbers, note the reason) or "assumption" (a rule or a choice, note its reason)."""
    key: str
    value: object
    kind: str
    note: str


@dataclass(frozen=True)
class LayoutSections:
    """What a layout's builder writes: its own ``sections`` (section -> list of
    :class:`Entry`, in the file's order), the ``radius_mm`` its face width is scaled by
    (the pin circle, a sine ring's pitch radius) and the ``notes`` on what the header's
    "Not written" adds for it."""
    sections: dict
    radius_mm: float
    notes: tuple[str, ...] = ()


@dataclass(frozen=True, kw_only=True)
class NewCaseTemplate:
    """What ``toothfem new`` asks of one layout, registered as its record's part
    ``Layout.case_template`` (toothfem/layout.py); :func:`new_case` reads nothing else that
    differs between the layouts.

    Attributes
    ----------
    required, optional : tuple of str
        The key numbers (keywords of :func:`new_case`, keys of :data:`OPTIONS`) the layout
        needs and may take.
    sizes : tuple of str
        Optional key numbers of which exactly one gives the size (the command's help
        names them), empty where the required ones fix it.
    key_ranges : mapping
        Key number -> (case section class, field) whose range it is checked against, in
        the order the checks run.
    key_help : mapping
        Key number -> what it is in this layout (the command's help).
    check : callable
        ``check(given)``: the layout's own checks of the key numbers (``None`` where not
        given), after the ranges; a one-line CaseError naming the option otherwise.
    direct_keys : callable
        ``direct_keys(given) -> {case key: key number}``: the layout's keys a key number
        sets directly (a refusal of one is restated with the option; the operating point's
        keys are common to all).
    build : callable
        ``build(template, given) -> LayoutSections``: the layout's own sections (call the
        template: ``template(given)``).
    radius_name : str
        The radius the thinnest face width is scaled by, as the reason names it.
    lubrication : (str, str)
        ``lubricant.lubrication``'s value and its reason.
    friction : tuple of (str, float, str)
        The layout's ``[friction]`` coefficients beside the bearings': key, value, reason.
    tolerances : callable
        ``tolerances(sections) -> tuple of (key, value, reason)``: the ``[tolerances]`` of
        its meshing stage, from the sections written so far.
    name_size : callable
        ``name_size(given, sections) -> str``: the size in the default case name.
    """
    required: tuple[str, ...]
    optional: tuple[str, ...]
    sizes: tuple[str, ...] = ()
    key_ranges: Mapping[str, tuple[type, str]]
    key_help: Mapping[str, str]
    check: Callable[[dict], None]
    direct_keys: Callable[[dict], dict]
    build: Callable[[NewCaseTemplate, dict], LayoutSections]
    radius_name: str
    lubrication: tuple[str, str]
    friction: tuple[tuple[str, float, str], ...]
    tolerances: Callable[[dict], tuple]
    name_size: Callable[[dict, dict], str]

    def __post_init__(self):
        takes = self.required + self.optional
        odd = [k for k in takes if k not in OPTIONS or k not in self.key_help]
        odd += [k for k in (*self.sizes, *self.key_ranges) if k not in takes]
        if odd:
            raise ValueError(f"key numbers {odd} lack an option or a help text, or are not "
                             "among the template's key numbers")

    def __call__(self, given: dict) -> LayoutSections:
        """The layout's own sections from its key numbers (``build``).

        Parameters
        ----------
        given : dict
            Key number -> value (checked, without the ones not given).

        Returns
        -------
        LayoutSections
        """
        return self.build(self, given)


# -- rounding ------------------------------------------------------------------------------
def size_step(size_mm: float) -> float:
    """The step [mm] a layout of this size is rounded to: 1 mm from 100 mm, 0.5 from 50,
    0.1 from 10, 0.05 from 5, else 0.01 (a hundredth of the size or finer).

    Parameters
    ----------
    size_mm : float
        The layout's size [mm].

    Returns
    -------
    float
        [mm].
    """
    for step in (1.0, 0.5, 0.1, 0.05):
        if step <= size_mm / 100:
            return step
    return 0.01


def round_to(x: float, step: float, how: str = "nearest") -> float:
    """``x`` to a multiple of ``step`` ("nearest", "down", "up"), its float noise cut
    (3.0000000000000004 / 0.1 is not rounded down to 30 steps).

    Parameters
    ----------
    x : float
    step : float
    how : {"nearest", "down", "up"}

    Returns
    -------
    float
    """
    q = x / step
    n = {"nearest": round(q), "down": math.floor(q + ROUND_NOISE),
         "up": math.ceil(q - ROUND_NOISE)}[how]
    return float(f"{n * step:.10g}")


#: Steps of float noise ignored by ``round_to``.
ROUND_NOISE = 1e-9


# -- the key numbers' checks -----------------------------------------------------------------
def field_range(cls, name: str) -> dict:
    """The valid range of a case field, from its metadata (lo, hi, lo_open, hi_open).

    Parameters
    ----------
    name : str
        Its field.

    Returns
    -------
    dict
        lo, hi, lo_open, hi_open and integer.
    """
    md = {f.name: f for f in dataclasses.fields(cls)}[name].metadata
    return {k: md.get(k) for k in ("lo", "hi", "lo_open", "hi_open")} | {
        "integer": bool(md.get("integer"))}


# -- loading, with the refusal restated in the options' names --------------------------------
_KEY_AT_START = re.compile(r"^([a-z_]+(?:\.[a-z_]+)*(?:\[\d+\])?) = ")


#: The operating point's keys each key number sets directly (every layout's).
_OPERATING_KEYS = {"operating.output_torque_Nm": "torque_Nm",
                   "operating.rated_torque_Nm": "torque_Nm",
                   "operating.input_speed_rpm": "input_speed_rpm"}


def _direct_keys(template: NewCaseTemplate, given: dict) -> dict:
    """The case keys each key number sets directly -> its option."""
    keys = _OPERATING_KEYS | template.direct_keys(given)
    return {k: OPTIONS[v] for k, v in keys.items()}


def restated(exc: ToothfemError, template: NewCaseTemplate, given: dict) -> CaseError:
    """The loader's one-line refusal in the options' names: a key a key number sets is
    named as its option; a derived key keeps its name, followed by the key numbers it
    comes from.

    Parameters
    ----------
    exc : toothfem.errors.ToothfemError
        The loader's refusal.
    template : NewCaseTemplate
        The layout's template.
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    CaseError
    """
    msg = str(exc)
    m = _KEY_AT_START.match(msg)
    direct = _direct_keys(template, given)
    if m and m.group(1) in direct:
        return CaseError(direct[m.group(1)] + msg[len(m.group(1)):])
    return CaseError(f"{msg} (a value derived from the key numbers {key_numbers_text(given)}: they "
                     "leave no valid value for it)")


def key_numbers_text(given: dict) -> str:
    """The key numbers given, as a message lists them.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    str
    """
    return ", ".join(f"{OPTIONS[k]} = {v:g}" if isinstance(v, float) else f"{OPTIONS[k]} = {v}"
                     for k, v in given.items() if v is not None)


# -- the rules ---------------------------------------------------------------------------------
def _it5_um(diameter_mm: float) -> float:
    """ISO 286 IT5 [um] of a diameter [mm] (the largest tabulated step above 400 mm)."""
    return next((it for top, it in IT5_UM if diameter_mm <= top), IT5_UM[-1][1])


def _pin_radius(pins: int, rz_mm: float, e_mm: float) -> tuple:
    """The pin radius [mm] by PIN_RADIUS_PER_PITCH, below the undercut bound, and its
    reason."""
    pitch = 2 * math.pi * rz_mm / pins
    step = 0.1 if pitch >= 2.0 else 0.01
    free = CycloidGeometry(pin_count=pins, pin_circle_radius_m=rz_mm * M_PER_MM,
                           eccentricity_m=e_mm * M_PER_MM, pin_radius_m=1e-9)
    rho = min_convex_curvature_radius(free.nominal()) * MM_PER_M
    r = round_to(min(PIN_RADIUS_PER_PITCH * pitch, PIN_RADIUS_PER_UNDERCUT * rho), step, "down")
    why = (f"{PIN_RADIUS_PER_PITCH:g} of the pin pitch {pitch:.4g} mm (the shipped cases: "
           "0.29-0.30)")
    if PIN_RADIUS_PER_UNDERCUT * rho < PIN_RADIUS_PER_PITCH * pitch:
        why = (f"{PIN_RADIUS_PER_UNDERCUT:g} of the undercut bound {rho:.4g} mm (the "
               f"smallest convex curvature radius; {PIN_RADIUS_PER_PITCH:g} of the pitch "
               "would undercut the profile)")
    return r, why


def zero_clearance(roller_mm: float, e_mm: float) -> tuple:
    """A roller radius near ``roller_mm`` and the hole of zero clearance round it on an
    eccentric orbit, roller + eccentricity [mm], both written in a few digits: the case
    model checks the clearance as a sum in metres, where rounding noise can make it
    negative; the roller moves by ROLLER_NUDGE_MM steps until it does not (else the hole
    is raised by its last float digit).

    Parameters
    ----------
    roller_mm : float
        The roller's radius [mm].
    e_mm : float
        The eccentricity [mm].

    Returns
    -------
    (float, float)
        The roller's radius and the hole's [mm].
    """
    for k in (0, -1, 1, -2, 2, -3, 3):
        roller = round_to(roller_mm + k * ROLLER_NUDGE_MM, ROLLER_NUDGE_MM)
        hole = float(f"{roller + e_mm:.10g}")
        if hole * M_PER_MM - roller * M_PER_MM - e_mm * M_PER_MM >= 0:
            return roller, hole
    roller = round_to(roller_mm, ROLLER_NUDGE_MM)
    hole = float(f"{roller + e_mm:.10g}")
    while hole * M_PER_MM - roller * M_PER_MM - e_mm * M_PER_MM < 0:
        hole = math.nextafter(hole, math.inf)
    return roller, hole


def hole_radius(circle_mm: float, inner_mm: float, outer_mm: float, holes_on_circle: int):
    """A hole's radius [mm] on a circle between two radii (module constants).

    Parameters
    ----------
    circle_mm : float
        The holes' circle radius [mm].
    inner_mm : float
        The bore's radius [mm].
    outer_mm : float
        The root circle's radius [mm].
    holes_on_circle : int

    Returns
    -------
    (float, float)
        The hole's radius and the radial room [mm].
    """
    room = min(circle_mm - inner_mm, outer_mm - circle_mm)
    spacing = circle_mm * math.sin(math.pi / holes_on_circle)
    return min(HOLE_PER_ROOM * room, HOLE_PER_HALF_SPACING * spacing), room


def put(sections: dict, section: str, key: str, value, kind: str, note: str) -> None:
    """Set (or replace) one entry of a section, keeping the order of first setting.

    Parameters
    ----------
    sections : dict
        Section -> its entries so far.
    section : str
    key : str
    value : object
        None: placed here, set later.
    kind : {"key", "follows", "assumption"}
    note : str
        Its reason.
    """
    entries = sections.setdefault(section, [])
    new = Entry(key, value, kind, note)
    for i, e in enumerate(entries):
        if e.key == key:
            entries[i] = new
            return
    entries.append(new)


def disc_lobes(template: NewCaseTemplate, given: dict, train=None) -> tuple:
    """The disc's lobes and their entry's kind and note, once the case model's own checks
    pass (K1 < 1 and the tooth numbers; ``train(lobes)`` builds the layout's other section
    that holds them), its refusal restated in the options' names.

    Parameters
    ----------
    template : NewCaseTemplate
        The layout's template.
    given : dict
        Key number -> value (checked; those not given left out).
    train : callable, optional
        ``train(lobes)`` builds the layout's other section that holds them.

    Returns
    -------
    (int, tuple)
        The lobes and their entry's (kind, note).
    """
    zb, rz, e = given["pins"], given["pin_circle_radius_mm"], given["eccentricity_mm"]
    za = given.get("lobes")
    lobes_kind = ("key", "--lobes") if za is not None else (
        "follows", "pins - 1: a one-tooth-difference disc")
    za = zb - 1 if za is None else za
    try:       # K1 < 1 and the tooth numbers, by the case model's own checks
        CycloidStage(pin_count=zb, lobe_count=za, pin_circle_radius_mm=rz,
                     eccentricity_mm=e, pin_radius_mm=PIN_RADIUS_MM[0], face_width_mm=1.0)
        if train is not None:
            train(za)
    except ToothfemError as exc:
        raise restated(exc, template, given) from None
    return za, lobes_kind


def cycloid_stage(s: dict, given: dict, za: int, lobes_kind: tuple) -> tuple:
    """The ``[cycloid]`` section (K-H-V and RV alike); returns the disc's root radius [mm]
    and the step [mm] its layout is rounded to.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.
    given : dict
        Key number -> value (checked; those not given left out).
    za : int
        The disc's lobes.
    lobes_kind : tuple
        Their entry's (kind, note).

    Returns
    -------
    (float, float)
        The disc's root radius and the layout's step [mm].
    """
    zb, rz, e = given["pins"], given["pin_circle_radius_mm"], given["eccentricity_mm"]
    c = "cycloid"
    put(s, c, "pin_count", zb, "key", "--pins")
    put(s, c, "lobe_count", za, *lobes_kind)
    put(s, c, "pin_circle_radius_mm", rz, "key", "--pin-circle-radius-mm (Rz)")
    put(s, c, "eccentricity_mm", e, "key", f"--eccentricity-mm (K1 = e Zb / Rz = "
        f"{e * zb / rz:.3g})")
    r_pin, why = _pin_radius(zb, rz, e)
    put(s, c, "pin_radius_mm", r_pin, "assumption", why)
    put(s, c, "face_width_mm", None, "assumption", "")      # placed here, sized below
    put(s, c, "disc_count", DISC_COUNT, "assumption",
        "two discs 180 deg apart balance their eccentric forces (every shipped case)")
    put(s, c, "pin_structure", "conventional", "assumption",
        "pins in grooves of the housing, the common build")
    return rz - e - r_pin, size_step(rz)


def centre_bore(per_root: float, root: float, step: float) -> tuple:
    """The disc's centre bore radius [mm], ``per_root`` of the root radius rounded up and
    at most the largest shaft of the model's input bearings; returns (bore, whether that
    cap applied, the cap).

    Parameters
    ----------
    per_root : float
        The bore per root radius.
    root : float
        The root radius [mm].
    step : float
        The layout's step [mm].

    Returns
    -------
    (float, bool, float)
        The bore [mm], whether the cap applied, the cap [mm].
    """
    bore = round_to(per_root * root, step, "up")
    largest = max(ISO15_SERIES_0) / 2          # the input bearings' shaft: the bore's diameter
    return min(bore, largest), bore > largest, largest


def check_lobes(given: dict) -> None:
    """A cycloid disc's lobes, where given: one fewer than the pins.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).
    """
    if given.get("lobes") is not None:
        zb = given["pins"]
        check_range("--lobes", given["lobes"], zb - 1, zb - 1, error=CaseError,
                    why="a cycloid disc has one lobe fewer than its pins (--pins - 1)")


def disc_keys(given: dict) -> dict:
    """A cycloid stage's keys its key numbers set (K-H-V and RV).

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    dict
        Case key -> key number.
    """
    return {"cycloid.pin_count": "pins", "cycloid.lobe_count": "lobes",
            "cycloid.pin_circle_radius_mm": "pin_circle_radius_mm",
            "cycloid.eccentricity_mm": "eccentricity_mm"}


def pin_tolerances(s: dict) -> tuple:
    """A cycloid stage's tolerances: the pins' (ISO 286 h5 on their diameter), the pin
    circle's and the disc profile's.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.

    Returns
    -------
    tuple of (str, float, str)
        Key, value [mm] and reason.
    """
    pin_diameter_mm = 2 * entry_value(s, "cycloid", "pin_radius_mm")
    it5 = _it5_um(pin_diameter_mm)
    return (("pin_position_mm", 0.005, "true-position zone of each pin, jig-ground bores"),
            ("pin_diameter_lower_mm", -it5 * 1e-3,
             f"ISO 286 h5 on a {pin_diameter_mm:g} mm pin: 0 / -{it5:g} um"),
            ("pin_diameter_upper_mm", 0.0, "ISO 286 h5: the upper deviation is 0"),
            ("pin_circle_radius_mm", 0.003, "+- limit, ground parts"),
            ("disc_profile_mm", 0.003, "+- limit of each flank, profile grinding"))


def disc_name(given: dict, s: dict) -> str:
    """A cycloid stage's size in the case's default name.

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
    return f"{given['pins']} pins on a {given['pin_circle_radius_mm']:g} mm radius"


def entry_value(s: dict, section: str, key: str):
    """The value of one entry of the sections.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.
    section : str
    key : str

    Returns
    -------
    object
        The entry's value.
    """
    return next(e.value for e in s[section] if e.key == key)


# -- the layouts' templates ------------------------------------------------------------------
#: Key number -> (case section class, field) its range is checked against.
Ranges = dict[str, tuple[type, str]]


OPERATING_RANGES: Ranges = {"torque_Nm": (Operating, "output_torque_Nm"),
                            "input_speed_rpm": (Operating, "input_speed_rpm")}


OPERATING_HELP = {"torque_Nm": "output torque [N m]: the operating point and the rated "
                                "torque the size is for",
                  "input_speed_rpm": "input speed [rpm]"}


DISC_RANGES: Ranges = {"pins": (CycloidStage, "pin_count"),
                       "lobes": (CycloidStage, "lobe_count"),
                       "pin_circle_radius_mm": (CycloidStage, "pin_circle_radius_mm")}


#: Checked after the operating point's (the order of the refusals before the templates).
ECCENTRICITY_RANGE: Ranges = {"eccentricity_mm": (CycloidStage, "eccentricity_mm")}


DISC_HELP = {"pins": "pins Zb in the housing",
             "lobes": "lobes Za of a disc (default pins - 1)",
             "pin_circle_radius_mm": "pin circle radius Rz [mm]",
             "eccentricity_mm": "the crank's eccentricity [mm]"}


GREASE = ("grease", "robot-joint cycloid and RV units are grease-filled (Nabtesco RV-E "
                     "catalogue)")


OUTPUT_PIN_FRICTION = ("output_pin_coefficient", 0.05,
                       "lubricated steel pins in holes (the shipped K-H-V case)")


PIN_GROOVE_FRICTION = ("pin_groove_coefficient", 0.05, "conventional pins sliding in "
                       "lubricated grooves (the shipped cycloid cases)")

