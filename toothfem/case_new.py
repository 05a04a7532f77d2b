"""A new case file from a drive type and its key numbers (``toothfem new``, issue 25 item 6).

The key numbers are what an engineer knows first about a reducer: the pins and lobes (a
cycloid disc), the teeth (a sine pair, an RV first stage), the size (pin-circle radius,
module), the eccentricity, the output torque and the input speed. Every other value of
the case is derived from them by a stated rule, or chosen, and marked in the file with
``# ASSUMPTION: <reason>``; sections the case model sizes by its own documented rules
(``[seals]``, ``[bearings]``, ``[thermal]``, ``[supports]``: docs/case_schema.md) are left
to those rules and named in the file's header.

The rules, each a named constant below with its reason: the pin radius a share of the
pin pitch (kept clear of undercut), the face width from the torque (the seeds' analytic
split at that torque gives a peak Hertz pressure of the material's contact fatigue limit
over a safety, no thinner than a tenth of the radius), the disc's holes in the room
between its centre bore and its root circle, an RV first stage's module the ISO 54 module
that puts the crankshafts midway in that room, a sine pair's tooth height a share of its
largest valid one (:func:`toothfem.geometry.sine.tooth_height_limits`), the output
mechanism in proportion to the disc or the planet as in the shipped cases.

What differs between the layouts (the key numbers, their checks, the sections and the
layout's assumptions) is each one's :class:`NewCaseTemplate`, registered as its record's
part ``case_template`` (fem/drives/registry.py): nothing here branches on the drive.

Computing and writing are apart: :func:`new_case` returns the text and the loaded case
(every value checked by the normal loader, its refusal restated with the option that set
the value); :func:`toothfem.output.write_new_file` writes the text atomically and never over an
existing file unless told to. Units: the key numbers' (mm, N m, rpm); SI inside the sizing.
"""
from __future__ import annotations

import dataclasses
import json
import math
import numbers
import re
import textwrap
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import cast

from . import __version__
from .case import Case, parse_case, parse_case_text
from .case_checks import PIN_RADIUS_MM
from .case_sections import CycloidStage, Material, Operating, RVTrain, SineStage, SpurStage
from .errors import CaseError, GeometryError, ToothfemError, check_range
from .fem.datasheet.supports import ROLLER_DIAMETER_REL
from .derived import derived
from .efficiency.bearing_set import ISO15_SERIES_0
from .fem.drives import DEFAULT_POSITIONS, drive_for
from .fem.drives.registry import RECORDS, provide
from .geometry import sine
from .geometry.cycloid import CycloidGeometry, min_convex_curvature_radius
from .units import M_PER_MM, MM_PER_M, MPA_PER_PA, UM_PER_M

# -- the key numbers ------------------------------------------------------------------------
#: Keyword of :func:`new_case` -> the command-line option that gives it (messages name it).
OPTIONS = {
    "pins": "--pins", "lobes": "--lobes", "pin_circle_radius_mm": "--pin-circle-radius-mm",
    "eccentricity_mm": "--eccentricity-mm", "sun_teeth": "--sun-teeth",
    "planet_teeth": "--planet-teeth", "teeth": "--teeth", "ring_teeth": "--ring-teeth",
    "module_mm": "--module-mm", "ring_pitch_radius_mm": "--ring-pitch-radius-mm",
    "torque_Nm": "--torque-Nm", "input_speed_rpm": "--input-speed-rpm",
}
#: A sine pair's size: exactly one of these (with the tooth numbers, each fixes the other
#: two). What each layout takes is its :class:`NewCaseTemplate` (the templates below); what
#: each layout is, in the file's header and the command's help, its record's ``label``.
SINE_SIZE = ("module_mm", "eccentricity_mm", "ring_pitch_radius_mm")
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
#: Safety of the peak Hertz pressure against the material's contact fatigue limit
#: (``material.allowable_contact_stress_MPa``, ISO 281's 1500 MPa): ASSUMPTION, the upper
#: end of the minimum pitting safeties S_H,min of gear rating practice (1.0-1.3, ISO 6336-2
#: / DIN 3990 application guidance).
CONTACT_SAFETY = 1.3
#: Thinnest face width per radius (pin circle; a sine ring's pitch radius). ASSUMPTION: the
#: thinnest shipped disc (the pin-housing paper's 10 mm at Rz = 100 mm); thinner, the disc
#: bends out of its plane, which the plane-strain model does not see.
FACE_WIDTH_MIN_PER_RADIUS = 0.1
#: Refinements of the face width by Hertz's p ~ 1/sqrt(b) (the split shifts a little with
#: the width); then it is rounded up and widened by steps until the pressure holds.
FACE_WIDTH_ITERATIONS, FACE_WIDTH_MAX_STEPS = 3, 20
#: Coarsest step of a face width [mm] (the layout's step of a smaller reducer below it).
FACE_WIDTH_STEP_MM = 0.5
#: Largest contact force of the analytic split, times the largest moment arm, per member
#: torque: a force a million times what the torque needs at the full arm is no share of
#: the load but a contact without moment arm (on the line of centres) loaded alone.
FORCE_ARM_MAX_PER_TORQUE = 1e6
#: Discs of a cycloid stage. ASSUMPTION: two discs 180 deg apart balance each other's
#: eccentric force (every shipped cycloid case).
DISC_COUNT = 2
#: Centre bore per root radius of the disc, rounded up. ASSUMPTION: K-H-V, the eccentric
#: roller bearing sits in it (the shipped K-H-V case: 14 mm of 45.8 mm, 0.31); RV, only the
#: input shaft passes (RV-40E-like 8 mm of 59.7 mm, 0.13).
KHV_BORE_PER_ROOT, RV_BORE_PER_ROOT = 0.3, 0.13
#: A hole's radius per the radial room of its circle (the smaller distance to the bore and
#: to the root circle), capped at a share of half the spacing of the holes on that circle.
#: ASSUMPTION: the shipped K-H-V case (6.7 mm holes in a 15.8 mm room, 0.42; 0.58 of the
#: half spacing) and the RV-40E-like crank holes (10 mm in 23.7 mm at m = 1.5: 0.42).
HOLE_PER_ROOM, HOLE_PER_HALF_SPACING = 0.42, 0.6
#: K-H-V output pins. ASSUMPTION: eight, as the shipped K-H-V and sine cases; the pin's
#: radius 0.73 of its roller's (the shipped K-H-V case: 4 mm pins in 5.5 mm rollers).
OUTPUT_PIN_COUNT, PIN_PER_ROLLER = 8, 0.73
#: Step [mm] by which a roller's radius may move so that the zero-clearance hole round it
#: is written in a few digits (``_zero_clearance``): a hundredth, below any fit's tolerance.
ROLLER_NUDGE_MM = 0.01
#: An RV drive's crankshafts (one planet each) and carrier pillars, and a pillar hole's
#: radius per crank hole's. ASSUMPTION: the shipped RV cases (two of each, 8 mm pillars
#: beside 10 mm crank holes).
CRANK_COUNT, PILLAR_COUNT, PILLAR_PER_CRANK = 2, 2, 0.8
#: ISO 54:1996 modules, series I [mm]: an RV first stage takes the one nearest the module
#: that puts the crankshafts midway between the bore and the root circle.
ISO54_MODULES_MM = (0.05, 0.06, 0.08, 0.1, 0.12, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.8,
                    1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0,
                    20.0, 25.0, 32.0, 40.0, 50.0)
#: First-stage pressure angle [deg]: ISO 53's standard basic rack.
PRESSURE_ANGLE_DEG = 20.0
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
#: ISO 286-1 standard tolerance grade IT5 [um] by diameter range (upper limits [mm]): the
#: h5 pins' lower diameter deviation (the shipped cases: h5, -5 um on 3-6 mm).
IT5_UM = ((3.0, 4.0), (6.0, 5.0), (10.0, 6.0), (18.0, 8.0), (30.0, 9.0), (50.0, 11.0),
          (80.0, 13.0), (120.0, 15.0), (180.0, 18.0), (250.0, 20.0), (315.0, 23.0),
          (400.0, 25.0))
#: The column at which the files' line comments start (as the shipped cases).
COMMENT_COLUMN, LINE_WIDTH = 28, 99


@dataclass(frozen=True)
class Entry:
    """One key of the new file: its ``value``, and the ``note`` after it; ``kind`` says
    what the value is: "key" (a key number, note the option), "follows" (fixed by the key
    numbers, note the reason) or "assumption" (a rule or a choice, note its reason)."""
    key: str
    value: object
    kind: str
    note: str


@dataclass(frozen=True, kw_only=True)
class NewCase:
    """A new case: its ``text`` (TOML with every value's reason), the ``case`` that text
    loads to, the ``key_numbers`` given (option -> value), every ``assumptions`` entry
    as (dotted key, value, reason), and the sizing's figures: the speed ``ratio``
    (signed), the analytic ``peak_ph_MPa`` at the torque, the operating point's analytic
    ``efficiency`` and the ``warnings`` of ``toothfem check``."""
    drive: str
    text: str
    case: Case
    key_numbers: dict
    assumptions: tuple
    ratio: float
    peak_ph_MPa: float
    efficiency: float
    warnings: tuple


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
    ``case_template`` (fem/drives/registry.py); :func:`new_case` reads nothing else that
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


def templates() -> dict[str, NewCaseTemplate]:
    """The layouts ``toothfem new`` writes: every record with a ``case_template``.

    Returns
    -------
    dict
        Layout name -> its :class:`NewCaseTemplate`, in the order of ``RECORDS``.
    """
    return {name: t for name, record in RECORDS.items()
            if isinstance(t := record.parts.get("case_template"), NewCaseTemplate)}


# -- rounding ------------------------------------------------------------------------------
def _step(size_mm: float) -> float:
    """The step [mm] a layout of this size is rounded to: 1 mm from 100 mm, 0.5 from 50,
    0.1 from 10, 0.05 from 5, else 0.01 (a hundredth of the size or finer)."""
    for step in (1.0, 0.5, 0.1, 0.05):
        if step <= size_mm / 100:
            return step
    return 0.01


def _round(x: float, step: float, how: str = "nearest") -> float:
    """``x`` to a multiple of ``step`` ("nearest", "down", "up"), its float noise cut
    (3.0000000000000004 / 0.1 is not rounded down to 30 steps)."""
    q = x / step
    n = {"nearest": round(q), "down": math.floor(q + _NOISE),
         "up": math.ceil(q - _NOISE)}[how]
    return float(f"{n * step:.10g}")


#: Steps of float noise ignored by ``_round``.
_NOISE = 1e-9


# -- the key numbers' checks -----------------------------------------------------------------
def _field_range(cls, name: str) -> dict:
    """The valid range of a case field, from its metadata (lo, hi, lo_open, hi_open)."""
    md = {f.name: f for f in dataclasses.fields(cls)}[name].metadata
    return {k: md.get(k) for k in ("lo", "hi", "lo_open", "hi_open")} | {
        "integer": bool(md.get("integer"))}


def _check_key(option: str, value, cls, name: str, why: str = ""):
    """A key number against the range of the case field it fills; one line naming the
    option otherwise."""
    r = _field_range(cls, name)
    integer = r.pop("integer")
    if integer and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
        raise CaseError(f"{option} = {value!r} must be an integer")
    check_range(option, value, error=CaseError, why=why, **r)


def _check_key_numbers(drive: str, template: NewCaseTemplate, given: dict) -> None:
    """Every key number the drive needs, none it does not take, each in its field's range
    (the case model's), then the layout's own checks (tooth numbers against each other
    where no field holds the rule)."""
    required, optional = template.required, template.optional
    for kw in required:
        if given.get(kw) is None:
            raise CaseError(f"{OPTIONS[kw]} is required for a {drive} drive "
                            f"(key numbers: {', '.join(OPTIONS[k] for k in required)})")
    for kw, v in given.items():
        if v is not None and kw not in required + optional:
            takes = sorted(d for d, t in templates().items() if kw in t.required + t.optional)
            raise CaseError(f"{OPTIONS[kw]} = {v!r} does not apply to a {drive} drive "
                            f"(it is a key number of: {', '.join(takes)})")
    for kw, (cls, name) in template.key_ranges.items():
        if given.get(kw) is not None:
            _check_key(OPTIONS[kw], given[kw], cls, name)
    template.check(given)


def _check_lobes(given: dict) -> None:
    """A cycloid disc's lobes, where given: one fewer than the pins."""
    if given.get("lobes") is not None:
        zb = given["pins"]
        check_range("--lobes", given["lobes"], zb - 1, zb - 1, error=CaseError,
                    why="a cycloid disc has one lobe fewer than its pins (--pins - 1)")


def _check_sine(given: dict) -> None:
    """A sine pair's size given once (:data:`SINE_SIZE`), its ring's teeth above the
    planet's."""
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


def _disc_keys(given: dict) -> dict:
    """A cycloid stage's keys its key numbers set (K-H-V and RV)."""
    return {"cycloid.pin_count": "pins", "cycloid.lobe_count": "lobes",
            "cycloid.pin_circle_radius_mm": "pin_circle_radius_mm",
            "cycloid.eccentricity_mm": "eccentricity_mm"}


def _rv_keys(given: dict) -> dict:
    """An RV reducer's: its disc stage's, its train's and its first stage's."""
    return _disc_keys(given) | {
        "rv.pin_count": "pins", "rv.disc_teeth": "lobes", "rv.sun_teeth": "sun_teeth",
        "rv.planet_teeth": "planet_teeth", "first_stage.sun_teeth": "sun_teeth",
        "first_stage.planet_teeth": "planet_teeth"}


def _sine_keys(given: dict) -> dict:
    """A sine pair's: its tooth numbers, and its module where that gives the size."""
    keys = {"sine.planet_teeth": "teeth", "sine.ring_teeth": "ring_teeth"}
    size = next(k for k in SINE_SIZE if given.get(k) is not None)
    if size == "module_mm":
        keys["sine.module_mm"] = "module_mm"
    return keys


def _restated(exc: ToothfemError, template: NewCaseTemplate, given: dict) -> CaseError:
    """The loader's one-line refusal in the options' names: a key a key number sets is
    named as its option; a derived key keeps its name, followed by the key numbers it
    comes from."""
    msg = str(exc)
    m = _KEY_AT_START.match(msg)
    direct = _direct_keys(template, given)
    if m and m.group(1) in direct:
        return CaseError(direct[m.group(1)] + msg[len(m.group(1)):])
    return CaseError(f"{msg} (a value derived from the key numbers {_numbers(given)}: they "
                     "leave no valid value for it)")


def _numbers(given: dict) -> str:
    """The key numbers given, as a message lists them."""
    return ", ".join(f"{OPTIONS[k]} = {v:g}" if isinstance(v, float) else f"{OPTIONS[k]} = {v}"
                     for k, v in given.items() if v is not None)


def _load(sections: dict, template: NewCaseTemplate, given: dict) -> Case:
    """The case of a mapping of entries, through the normal loader (refusals restated)."""
    try:
        return parse_case(_mapping(sections))
    except ToothfemError as exc:
        raise _restated(exc, template, given) from None


def _mapping(sections: dict) -> dict:
    """Sections of entries -> the mapping the loader reads (nested tables by dotted name)."""
    out: dict = {}
    for name, entries in sections.items():
        table = out
        for part in name.split("."):
            table = table.setdefault(part, {})
        for e in entries:
            if e.value is not None:
                table[e.key] = e.value
    return out


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
    r = _round(min(PIN_RADIUS_PER_PITCH * pitch, PIN_RADIUS_PER_UNDERCUT * rho), step, "down")
    why = (f"{PIN_RADIUS_PER_PITCH:g} of the pin pitch {pitch:.4g} mm (the shipped cases: "
           "0.29-0.30)")
    if PIN_RADIUS_PER_UNDERCUT * rho < PIN_RADIUS_PER_PITCH * pitch:
        why = (f"{PIN_RADIUS_PER_UNDERCUT:g} of the undercut bound {rho:.4g} mm (the "
               f"smallest convex curvature radius; {PIN_RADIUS_PER_PITCH:g} of the pitch "
               "would undercut the profile)")
    return r, why


def _zero_clearance(roller_mm: float, e_mm: float) -> tuple:
    """A roller radius near ``roller_mm`` and the hole of zero clearance round it on an
    eccentric orbit, roller + eccentricity [mm], both written in a few digits: the case
    model checks the clearance as a sum in metres, where rounding noise can make it
    negative; the roller moves by ROLLER_NUDGE_MM steps until it does not (else the hole
    is raised by its last float digit)."""
    for k in (0, -1, 1, -2, 2, -3, 3):
        roller = _round(roller_mm + k * ROLLER_NUDGE_MM, ROLLER_NUDGE_MM)
        hole = float(f"{roller + e_mm:.10g}")
        if hole * M_PER_MM - roller * M_PER_MM - e_mm * M_PER_MM >= 0:
            return roller, hole
    roller = _round(roller_mm, ROLLER_NUDGE_MM)
    hole = float(f"{roller + e_mm:.10g}")
    while hole * M_PER_MM - roller * M_PER_MM - e_mm * M_PER_MM < 0:
        hole = math.nextafter(hole, math.inf)
    return roller, hole


def _hole_radius(circle_mm: float, inner_mm: float, outer_mm: float, holes_on_circle: int):
    """A hole's radius [mm] on a circle between two radii (module constants)."""
    room = min(circle_mm - inner_mm, outer_mm - circle_mm)
    spacing = circle_mm * math.sin(math.pi / holes_on_circle)
    return min(HOLE_PER_ROOM * room, HOLE_PER_HALF_SPACING * spacing), room


def _peak_ph_MPa(case: Case, torque_Nm: float, listed: str) -> float:
    """The largest Hertz pressure [MPa] of the seeds' analytic split over one meshing
    period at an output torque (the drive's peak member torque); refused where the split
    loads a contact without a moment arm (``listed``: the key numbers, for the message)."""
    drive = drive_for(case)
    state = drive.meshing(drive.positions(DEFAULT_POSITIONS))
    member = drive.member_torque(torque_Nm)
    split = drive.analytic_split(state, member)
    arm = float(abs(split.moment_arm).max())
    if not float(split.force.max()) * arm <= FORCE_ARM_MAX_PER_TORQUE * member:
        raise CaseError(f"the key numbers {listed} give a pair whose seeds' analytic split "
                        f"loads a {drive.contact_name} contact on the line of centres (no "
                        "moment arm) at some crank angle, where no face width carries the "
                        "torque (the efficiency there is 0): choose other tooth numbers or "
                        "another size")
    return float(split.ph.max()) * MPA_PER_PA


def _face_width(sections: dict, section: str, radius_mm: float, radius_name: str,
                template: NewCaseTemplate, given: dict) -> tuple:
    """The face width [mm] from the torque (module docstring), its entry placed in
    ``sections[section]``; returns (width, peak P_h [MPa] there, reason)."""
    allowable = cast(float, Material.__dataclass_fields__[
        "allowable_contact_stress_MPa"].default)
    target = allowable / CONTACT_SAFETY
    torque = given["torque_Nm"]
    floor = FACE_WIDTH_MIN_PER_RADIUS * radius_mm
    step = min(_step(radius_mm), FACE_WIDTH_STEP_MM)

    listed = _numbers(given)

    def ph_at(width):
        _put(sections, section, "face_width_mm", width, "assumption", "")
        return _peak_ph_MPa(_load(sections, template, given), torque, listed)

    b = floor
    for _ in range(FACE_WIDTH_ITERATIONS):
        b = max(b * (ph_at(b) / target) ** 2, floor)
    b = _round(b, step, "up")
    ph = ph_at(b)
    for _ in range(FACE_WIDTH_MAX_STEPS):
        if ph <= target * (1 + 1e-9):
            break
        b = _round(b + step, step)
        ph = ph_at(b)
    design = (f"a peak Hertz pressure of {target:.4g} MPa at the torque (the allowable "
              f"{allowable:g} MPa / {CONTACT_SAFETY:g}; the analytic split gives {ph:.4g} "
              "MPa here)")
    why = (f"sized for {design}" if b > _round(floor, step, "up") else
           f"{FACE_WIDTH_MIN_PER_RADIUS:g} x the {radius_name} (the thinnest shipped disc): "
           f"wider than the torque needs for {design}")
    _put(sections, section, "face_width_mm", b, "assumption", why)
    return b, ph, why


def _put(sections: dict, section: str, key: str, value, kind: str, note: str) -> None:
    """Set (or replace) one entry of a section, keeping the order of first setting."""
    entries = sections.setdefault(section, [])
    new = Entry(key, value, kind, note)
    for i, e in enumerate(entries):
        if e.key == key:
            entries[i] = new
            return
    entries.append(new)


def _disc_lobes(template: NewCaseTemplate, given: dict, train=None) -> tuple:
    """The disc's lobes and their entry's kind and note, once the case model's own checks
    pass (K1 < 1 and the tooth numbers; ``train(lobes)`` builds the layout's other section
    that holds them), its refusal restated in the options' names."""
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
        raise _restated(exc, template, given) from None
    return za, lobes_kind


def _cycloid_stage(s: dict, given: dict, za: int, lobes_kind: tuple) -> tuple:
    """The ``[cycloid]`` section (K-H-V and RV alike); returns the disc's root radius [mm]
    and the step [mm] its layout is rounded to."""
    zb, rz, e = given["pins"], given["pin_circle_radius_mm"], given["eccentricity_mm"]
    c = "cycloid"
    _put(s, c, "pin_count", zb, "key", "--pins")
    _put(s, c, "lobe_count", za, *lobes_kind)
    _put(s, c, "pin_circle_radius_mm", rz, "key", "--pin-circle-radius-mm (Rz)")
    _put(s, c, "eccentricity_mm", e, "key", f"--eccentricity-mm (K1 = e Zb / Rz = "
         f"{e * zb / rz:.3g})")
    r_pin, why = _pin_radius(zb, rz, e)
    _put(s, c, "pin_radius_mm", r_pin, "assumption", why)
    _put(s, c, "face_width_mm", None, "assumption", "")      # placed here, sized below
    _put(s, c, "disc_count", DISC_COUNT, "assumption",
         "two discs 180 deg apart balance their eccentric forces (every shipped case)")
    _put(s, c, "pin_structure", "conventional", "assumption",
         "pins in grooves of the housing, the common build")
    return rz - e - r_pin, _step(rz)


def _centre_bore(per_root: float, root: float, step: float) -> tuple:
    """The disc's centre bore radius [mm], ``per_root`` of the root radius rounded up and
    at most the largest shaft of the model's input bearings; returns (bore, whether that
    cap applied, the cap)."""
    bore = _round(per_root * root, step, "up")
    largest = max(ISO15_SERIES_0) / 2          # the input bearings' shaft: the bore's diameter
    return min(bore, largest), bore > largest, largest


def _khv_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of a K-H-V cycloid drive: the disc, its centre bore round the eccentric
    bearing and the output pins through its holes."""
    za, lobes_kind = _disc_lobes(template, given)
    s: dict = {}
    root, step = _cycloid_stage(s, given, za, lobes_kind)
    e = given["eccentricity_mm"]
    h = "cycloid.disc_holes"
    bore, capped, largest = _centre_bore(KHV_BORE_PER_ROOT, root, step)
    _put(s, h, "centre_bore_radius_mm", bore, "assumption",
         f"{KHV_BORE_PER_ROOT:g} of the root radius {root:.4g} mm: the eccentric "
         "roller bearing's outer race (the shipped K-H-V case: 0.31)" + (
             f"; at most {largest:g} mm, the model's input bearings (ISO 15 series 0 on a "
             "shaft of the bore's diameter) end there" if capped else ""))
    circle = _round(0.5 * (bore + root), step)
    hole, room = _hole_radius(circle, bore, root, OUTPUT_PIN_COUNT)
    fine = 0.1 if step >= 0.5 else 0.01
    roller, hole = _zero_clearance(_round(hole - e, fine), e)
    pin = _round(PIN_PER_ROLLER * roller, fine)
    om = "output_mechanism"
    _put(s, om, "pin_count", OUTPUT_PIN_COUNT, "assumption",
         "eight output pins, as the shipped K-H-V and sine cases")
    _put(s, om, "pin_hole_circle_radius_mm", circle, "assumption",
         "midway between the centre bore and the disc's root circle")
    _put(s, om, "roller_radius_mm", roller, "assumption",
         f"the hole ({HOLE_PER_ROOM:g} of the {room:.4g} mm room, at most "
         f"{HOLE_PER_HALF_SPACING:g} of the half spacing) less the eccentricity; the "
         "sleeve touches the hole")
    _put(s, om, "pin_radius_mm", pin, "assumption",
         f"{PIN_PER_ROLLER:g} of the roller's (the shipped K-H-V case: 4 in 5.5 mm)")
    _put(s, om, "hole_radius_mm", hole, "assumption",
         "the roller's radius plus the eccentricity: zero nominal clearance, the K-H-V "
         "mechanism's kinematics (the model's default)")
    _put(s, om, "eccentric_bearing_inner_radius_mm",
         _round(bore * (1 - ROLLER_DIAMETER_REL), fine), "assumption",
         f"the bore less one roller of {ROLLER_DIAMETER_REL:g} of its radius (the "
         "system model's assumed rollers, fem/datasheet/supports.py)")
    return LayoutSections(s, given["pin_circle_radius_mm"])


def _rv_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of an RV reducer: its train, the disc, the crank and pillar holes
    between the centre bore (the input shaft only) and the root circle, the first stage
    whose centre distance puts the cranks there."""
    zb, z1, z2 = given["pins"], given["sun_teeth"], given["planet_teeth"]
    za, lobes_kind = _disc_lobes(template, given, train=lambda za: RVTrain(
        sun_teeth=z1, planet_teeth=z2, disc_teeth=za, pin_count=zb))
    s: dict = {}
    _put(s, "rv", "sun_teeth", z1, "key", "--sun-teeth (z1)")
    _put(s, "rv", "planet_teeth", z2, "key", "--planet-teeth (z2)")
    _put(s, "rv", "disc_teeth", za, *lobes_kind)
    _put(s, "rv", "pin_count", zb, "key", "--pins")
    _put(s, "rv", "disc_count", DISC_COUNT, "assumption",
         "two discs 180 deg apart balance their eccentric forces")
    _put(s, "rv", "mesh_efficiency",
         RVTrain.__dataclass_fields__["mesh_efficiency"].default, "assumption",
         "the RV paper's value for every gear pair (read by --method rv_split_power only)")
    root, step = _cycloid_stage(s, given, za, lobes_kind)
    h = "cycloid.disc_holes"
    bore, _, _ = _centre_bore(RV_BORE_PER_ROOT, root, step)
    _put(s, h, "centre_bore_radius_mm", bore, "assumption",
         f"{RV_BORE_PER_ROOT:g} of the root radius {root:.4g} mm: the input shaft "
         "passes (the RV-40E-like case: 0.13)")
    wanted = 2 * 0.5 * (bore + root) / (z1 + z2)
    module = min(ISO54_MODULES_MM, key=lambda m: abs(m - wanted))
    circle = float(f"{module * (z1 + z2) / 2:.10g}")
    holes = CRANK_COUNT + PILLAR_COUNT
    crank, room = _hole_radius(circle, bore, root, holes)
    fine = step if step <= 0.5 else 0.5
    crank = _round(crank, fine)
    _put(s, h, "crank_hole_count", CRANK_COUNT, "assumption",
         "two crankshafts, one planet each (the shipped RV cases)")
    _put(s, h, "crank_hole_circle_radius_mm", circle, "follows",
         f"the first stage's centre distance m (z1 + z2) / 2 at m = {module:g} mm")
    _put(s, h, "crank_hole_radius_mm", crank, "assumption",
         f"{HOLE_PER_ROOM:g} of the {room:.4g} mm room between the bore and the root "
         f"circle (at most {HOLE_PER_HALF_SPACING:g} of the half spacing): the needle "
         "bearing on the crank's journal")
    _put(s, h, "pillar_hole_count", PILLAR_COUNT, "assumption",
         "two carrier pillars between the cranks (the shipped RV cases)")
    _put(s, h, "pillar_hole_circle_radius_mm", circle, "assumption",
         "on the cranks' circle, halfway between them")
    _put(s, h, "pillar_hole_radius_mm", _round(PILLAR_PER_CRANK * crank, fine),
         "assumption", f"{PILLAR_PER_CRANK:g} of the crank hole's (the shipped RV cases)")
    fs = "first_stage"
    _put(s, fs, "sun_teeth", z1, "key", "--sun-teeth")
    _put(s, fs, "planet_teeth", z2, "key", "--planet-teeth")
    _put(s, fs, "planet_count", CRANK_COUNT, "follows", "one planet per crankshaft")
    _put(s, fs, "module_mm", module, "assumption",
         f"the ISO 54 module nearest {wanted:.3g} mm, which puts the cranks midway "
         "between the bore and the root circle")
    _put(s, fs, "pressure_angle_deg", PRESSURE_ANGLE_DEG, "assumption",
         "ISO 53 standard basic rack")
    return LayoutSections(s, given["pin_circle_radius_mm"], (
        "first_stage.face_width_mm: the model's 10 modules",
        "bearings.eccentric_type: needle rollers in the crank holes (the model's "
        "default, RV reducers' crank bearings)"))


def _sine_sections(template: NewCaseTemplate, given: dict) -> LayoutSections:
    """The sections of a one-tooth-difference sine reducer: the pair, sized by the one of
    :data:`SINE_SIZE` given, and its output pins."""
    z1 = given["teeth"]
    z2 = given.get("ring_teeth") or z1 + 1
    dz = z2 - z1
    size = next(k for k in SINE_SIZE if given.get(k) is not None)
    per_module = {"module_mm": 1.0, "eccentricity_mm": dz / 2, "ring_pitch_radius_mm": z2 / 2}
    lo, hi = (v * per_module[size] for v in (_field_range(SineStage, "module_mm")["lo"],
                                             _field_range(SineStage, "module_mm")["hi"]))
    check_range(OPTIONS[size], given[size], lo, hi, error=CaseError,
                why="the module's range, 0.05-100 mm (ISO 54), times "
                    f"{per_module[size]:g} at these tooth numbers")
    m = float(f"{given[size] / per_module[size]:.10g}")
    s: dict = {}
    _put(s, "sine", "planet_teeth", z1, "key", "--teeth (z1)")
    _put(s, "sine", "ring_teeth", z2,
         *(("key", "--ring-teeth (z2)") if given.get("ring_teeth") else
           ("follows", "z1 + 1: one tooth difference")))
    _put(s, "sine", "module_mm", m, *(("key", "--module-mm") if size == "module_mm" else
                                       ("follows", f"from {OPTIONS[size]} = {given[size]:g}")))
    top = sine.tooth_height_limits(z1, z2, m * M_PER_MM).max * MM_PER_M
    step = 0.01 if top >= 0.2 else 0.001
    a = _round(TOOTH_HEIGHT_PER_MAX * top, step, "down")
    why = (f"{TOOTH_HEIGHT_PER_MAX:g} of the largest valid {top:.4g} mm (the sine paper's "
           "prototype: 0.4 of 0.45 mm)")
    try:
        sine.check_load_carrying(sine.SineGearPair(z1, z2, m * M_PER_MM, a * M_PER_MM, 1e-3))
    except GeometryError:
        low = sine.min_tooth_height_m(z1, z2, m * M_PER_MM) * MM_PER_M
        a = min(_round(low, step, "up"), top)
        why = (f"the load-carrying bound {low:.4g} mm (a drive flank within "
               f"{sine.LOAD_CARRYING_GAP_M * UM_PER_M:g} um at every crank angle), rounded up; "
               f"the largest valid is {top:.4g} mm")
    _put(s, "sine", "tooth_height_mm", a, "assumption", why)
    _put(s, "sine", "face_width_mm", None, "assumption", "")
    _put(s, "sine", "centre_distance_mm", float(f"{m * dz / 2:.10g}"), "follows",
         "the eccentricity a0 = m (z2 - z1) / 2")
    r1 = m * z1 / 2
    fine = 0.1 if r1 >= 10 else 0.01
    om = "output_mechanism"
    _put(s, om, "pin_count", OUTPUT_PIN_COUNT, "assumption",
         "eight output pins, as the shipped sine and K-H-V cases")
    for key, share in SINE_OUTPUT_PER_R1.items():
        _put(s, om, key, _round(share * r1, fine), "assumption",
             f"{share:.3g} of the planet's pitch radius {r1:.4g} mm (the sine paper's "
             "prototype, Table 4)")
    return LayoutSections(s, m * z2 / 2, ("output_mechanism.plain_bearing_friction_torque_"
                                          "Nmm: 0 (the model's default; the sine paper "
                                          "gives none)",))


def _shared_sections(s: dict, template: NewCaseTemplate, given: dict) -> None:
    """Material, operating point, lubricant, friction and tolerances (the layout's
    lubrication, friction coefficients and stage tolerances from its template)."""
    _put(s, "material", "youngs_modulus_GPa", 208.0, "assumption",
         "through-hardened bearing steel (100Cr6), as the shipped cases")
    _put(s, "material", "poisson_ratio", 0.3, "assumption", "bearing steel")
    op = "operating"
    _put(s, op, "output_torque_Nm", given["torque_Nm"], "key", "--torque-Nm")
    _put(s, op, "input_speed_rpm", given["input_speed_rpm"], "key", "--input-speed-rpm")
    _put(s, op, "rated_torque_Nm", given["torque_Nm"], "assumption",
         "the torque the face width is sized for; a catalogue's rated torque replaces it")
    lub = "lubricant"
    lubrication, why = template.lubrication
    _put(s, lub, "lubrication", lubrication, "assumption", why)
    for key, value, why in (
            ("dynamic_viscosity_Pa_s", 0.058, "ISO VG 68 mineral (base) oil at 40 C"),
            ("kinematic_viscosity_mm2_s", 68.0, "ISO VG 68 at 40 C"),
            ("density_kg_m3", 860.0, "mineral oil"),
            ("pressure_viscosity_1_per_GPa", 20.0, "mineral oil"),
            ("reference_temperature_C", 40.0, "ISO 3448's reference"),
            ("vogel_B_C", 900.0, "VG 68 mineral oil: 68 mm2/s at 40 C, 8.7 at 100 C"),
            ("roughness_Ra_um", 0.4, "ground surfaces")):
        _put(s, lub, key, value, "assumption", why)
    fr = "friction"
    _put(s, fr, "bearing_coefficient", 0.0015, "assumption",
         "rolling bearings (the shipped cycloid cases)")
    for key, value, why in template.friction:
        _put(s, fr, key, value, "assumption", why)
    tol = "tolerances"
    _put(s, tol, "distribution", "normal", "assumption",
         "3 sigma at each limit (a capable process, Cpk = 1)")
    for key, value, why in template.tolerances(s):
        _put(s, tol, key, value, "assumption", why)
    _put(s, tol, "eccentricity_mm", 0.002, "assumption", "+- limit, ground eccentric")


def _pin_tolerances(s: dict) -> tuple:
    """A cycloid stage's tolerances: the pins' (ISO 286 h5 on their diameter), the pin
    circle's and the disc profile's."""
    pin_diameter_mm = 2 * _value(s, "cycloid", "pin_radius_mm")
    it5 = _it5_um(pin_diameter_mm)
    return (("pin_position_mm", 0.005, "true-position zone of each pin, jig-ground bores"),
            ("pin_diameter_lower_mm", -it5 * 1e-3,
             f"ISO 286 h5 on a {pin_diameter_mm:g} mm pin: 0 / -{it5:g} um"),
            ("pin_diameter_upper_mm", 0.0, "ISO 286 h5: the upper deviation is 0"),
            ("pin_circle_radius_mm", 0.003, "+- limit, ground parts"),
            ("disc_profile_mm", 0.003, "+- limit of each flank, profile grinding"))


def _rv_tolerances(s: dict) -> tuple:
    """An RV reducer's: its cycloid stage's and its crank holes' position."""
    return _pin_tolerances(s) + (("crank_hole_position_mm", 0.005,
                                  "true-position zone of the crank holes"),)


def _sine_tolerances(s: dict) -> tuple:
    """A sine pair's: its tooth profile's."""
    return (("tooth_profile_mm", 0.003,
             "+- limit of each flank, ground teeth (as the shipped sine case)"),)


def _disc_name(given: dict, s: dict) -> str:
    """A cycloid stage's size in the case's default name."""
    return f"{given['pins']} pins on a {given['pin_circle_radius_mm']:g} mm radius"


def _sine_name(given: dict, s: dict) -> str:
    """A sine pair's size in the case's default name."""
    return f"{given['teeth']} teeth, module {_value(s, 'sine', 'module_mm'):g} mm"


# -- the layouts' templates ------------------------------------------------------------------
#: Key number -> (case section class, field) its range is checked against.
_Ranges = dict[str, tuple[type, str]]
_OPERATING_RANGES: _Ranges = {"torque_Nm": (Operating, "output_torque_Nm"),
                              "input_speed_rpm": (Operating, "input_speed_rpm")}
_OPERATING_HELP = {"torque_Nm": "output torque [N m]: the operating point and the rated "
                                "torque the size is for",
                   "input_speed_rpm": "input speed [rpm]"}
_DISC_RANGES: _Ranges = {"pins": (CycloidStage, "pin_count"),
                         "lobes": (CycloidStage, "lobe_count"),
                         "pin_circle_radius_mm": (CycloidStage, "pin_circle_radius_mm")}
#: Checked after the operating point's (the order of the refusals before the templates).
_ECCENTRICITY_RANGE: _Ranges = {"eccentricity_mm": (CycloidStage, "eccentricity_mm")}
_DISC_HELP = {"pins": "pins Zb in the housing",
              "lobes": "lobes Za of a disc (default pins - 1)",
              "pin_circle_radius_mm": "pin circle radius Rz [mm]",
              "eccentricity_mm": "the crank's eccentricity [mm]"}
_GREASE = ("grease", "robot-joint cycloid and RV units are grease-filled (Nabtesco RV-E "
                     "catalogue)")
_OUTPUT_PIN_FRICTION = ("output_pin_coefficient", 0.05,
                        "lubricated steel pins in holes (the shipped K-H-V case)")
_PIN_GROOVE_FRICTION = ("pin_groove_coefficient", 0.05, "conventional pins sliding in "
                        "lubricated grooves (the shipped cycloid cases)")

#: A K-H-V cycloid drive: the disc's key numbers; output pins through its holes.
KHV_TEMPLATE = NewCaseTemplate(
    required=("pins", "pin_circle_radius_mm", "eccentricity_mm", "torque_Nm",
              "input_speed_rpm"),
    optional=("lobes",),
    key_ranges=_DISC_RANGES | _OPERATING_RANGES | _ECCENTRICITY_RANGE,
    key_help=_DISC_HELP | _OPERATING_HELP,
    check=_check_lobes, direct_keys=_disc_keys, build=_khv_sections,
    radius_name="pin-circle radius", lubrication=_GREASE,
    friction=(_OUTPUT_PIN_FRICTION, _PIN_GROOVE_FRICTION), tolerances=_pin_tolerances,
    name_size=_disc_name)
#: An RV reducer: the disc's key numbers and the first stage's tooth numbers.
RV_TEMPLATE = NewCaseTemplate(
    required=("pins", "pin_circle_radius_mm", "eccentricity_mm", "sun_teeth",
              "planet_teeth", "torque_Nm", "input_speed_rpm"),
    optional=("lobes",),
    key_ranges=_DISC_RANGES | {"sun_teeth": (SpurStage, "sun_teeth"),
                               "planet_teeth": (SpurStage, "planet_teeth")}
    | _OPERATING_RANGES | _ECCENTRICITY_RANGE,
    key_help=_DISC_HELP | {"sun_teeth": "the first stage's sun teeth",
                           "planet_teeth": "the first stage's planet teeth"}
    | _OPERATING_HELP,
    check=_check_lobes, direct_keys=_rv_keys, build=_rv_sections,
    radius_name="pin-circle radius", lubrication=_GREASE,
    friction=(_PIN_GROOVE_FRICTION,), tolerances=_rv_tolerances, name_size=_disc_name)
#: A one-tooth-difference sine reducer: the tooth numbers and one size; output pins.
SINE_TEMPLATE = NewCaseTemplate(
    required=("teeth", "torque_Nm", "input_speed_rpm"),
    optional=("ring_teeth", "module_mm", "eccentricity_mm", "ring_pitch_radius_mm"),
    sizes=SINE_SIZE,
    key_ranges={"teeth": (SineStage, "planet_teeth"), "ring_teeth": (SineStage, "ring_teeth"),
                "module_mm": (SineStage, "module_mm")} | _OPERATING_RANGES,
    key_help={"teeth": "the planet's teeth z1",
              "ring_teeth": "the ring's teeth (default z1 + 1)",
              "module_mm": "the module [mm]",
              "eccentricity_mm": "the centre distance a0 (one way to give its size)",
              "ring_pitch_radius_mm": "the ring's pitch radius [mm]"} | _OPERATING_HELP,
    check=_check_sine, direct_keys=_sine_keys, build=_sine_sections,
    radius_name="ring's pitch radius",
    lubrication=("oil_bath", "a horizontal reducer half in oil (the sine paper's rig)"),
    friction=(_OUTPUT_PIN_FRICTION,), tolerances=_sine_tolerances, name_size=_sine_name)
provide("case_template", "cycloid")(KHV_TEMPLATE)
provide("case_template", "rv")(RV_TEMPLATE)
provide("case_template", "sine")(SINE_TEMPLATE)


def new_case(drive: str, *, torque_Nm: float | None = None,
             input_speed_rpm: float | None = None, pins: int | None = None,
             lobes: int | None = None, pin_circle_radius_mm: float | None = None,
             eccentricity_mm: float | None = None, sun_teeth: int | None = None,
             planet_teeth: int | None = None, teeth: int | None = None,
             ring_teeth: int | None = None, module_mm: float | None = None,
             ring_pitch_radius_mm: float | None = None, name: str | None = None) -> NewCase:
    """A case from a drive type and its key numbers, every other value derived or assumed.

    Parameters
    ----------
    drive : {"cycloid", "rv", "sine"}
        The case's drive, a layout with a :class:`NewCaseTemplate` (:func:`templates`): a
        K-H-V cycloid drive with output pins through its discs, an RV (2K-V) reducer, a
        one-tooth-difference sine reducer with output pins.
    torque_Nm : float
        Output torque of the operating point, also the rated torque the size is for [N m].
    input_speed_rpm : float
        Input speed [rpm].
    pins, lobes : int, optional
        Cycloid and RV: the pins Zb, and the disc's lobes Za (default Zb - 1).
    pin_circle_radius_mm, eccentricity_mm : float, optional
        Cycloid and RV: the pin circle's radius Rz and the eccentricity [mm]. A sine
        reducer's ``eccentricity_mm`` is its centre distance a0 (one way to give its size).
    sun_teeth, planet_teeth : int, optional
        RV: the first stage's tooth numbers.
    teeth, ring_teeth : int, optional
        Sine: the planet's teeth z1 and the ring's (default z1 + 1).
    module_mm, ring_pitch_radius_mm : float, optional
        Sine: its size as the module or the ring's pitch radius [mm] (exactly one of these
        and ``eccentricity_mm``).
    name : str, optional
        The case's name (default: the drive and its key numbers).

    Returns
    -------
    NewCase
        The text, the case it loads to (the normal loader's checks passed), the key numbers
        and every assumption.

    Raises
    ------
    CaseError
        One line naming the option (``--pins`` ...) of a missing, inapplicable or bad key
        number, its value and the valid range; or a derived value the key numbers leave no
        room for, with those key numbers.
    """
    given = {"pins": pins, "lobes": lobes, "pin_circle_radius_mm": pin_circle_radius_mm,
             "eccentricity_mm": eccentricity_mm, "sun_teeth": sun_teeth,
             "planet_teeth": planet_teeth, "teeth": teeth, "ring_teeth": ring_teeth,
             "module_mm": module_mm, "ring_pitch_radius_mm": ring_pitch_radius_mm,
             "torque_Nm": torque_Nm, "input_speed_rpm": input_speed_rpm}
    valid = templates()
    if drive not in valid:
        raise CaseError(f"drive = {drive!r} is not one of {sorted(valid)}")
    template = cast(NewCaseTemplate, RECORDS[drive].part("case_template"))
    _check_key_numbers(drive, template, given)
    given = {k: (float(v) if k in FLOAT_KEY_NUMBERS else int(v)) for k, v in given.items()
             if v is not None}
    if name is not None and (not isinstance(name, str) or not name.strip()):
        raise CaseError(f"--name = {name!r} must be a non-empty string")
    s: dict = {}
    _put(s, "case", "name", name or "new", "follows", "")     # named once the ratio is known
    _put(s, "case", "drive", drive, "key", "the drive type")
    _put(s, "case", "source", "toothfem new: key numbers given, the rest derived or assumed",
         "follows", "")
    body = template(given)
    s.update(body.sections)
    _shared_sections(s, template, given)
    record = RECORDS[drive]
    _, ph, _ = _face_width(s, record.stage_section, body.radius_mm, template.radius_name,
                           template, given)
    ratio = _load(s, template, given).ratio()
    if name is None:
        _put(s, "case", "name", f"new {drive} drive ({template.name_size(given, s)}), ratio "
             f"{abs(ratio):.6g}, {given['torque_Nm']:g} N m", "follows", "")
    text = _render(s, drive, record.label, given, ratio, body.notes)
    try:
        case = parse_case_text(text)      # the file as written, through the normal loader
    except ToothfemError as exc:
        raise _restated(exc, template, given) from None
    shown = derived(case)                 # what `check` prints: the operating point too
    if "operating_efficiency_analytic" not in shown:
        raise CaseError(f"{'; '.join(shown['warnings'])} (the key numbers "
                        f"{_numbers(given)} leave no valid value for it)")
    assumptions = tuple((f"{sec}.{e.key}", e.value, e.note) for sec, entries in s.items()
                        for e in entries if e.kind in _LISTED_KINDS and sec != "case")
    return NewCase(drive=drive, text=text, case=case,
                   key_numbers={OPTIONS[k]: v for k, v in given.items()},
                   assumptions=assumptions, ratio=ratio, peak_ph_MPa=ph,
                   efficiency=shown["operating_efficiency_analytic"],
                   warnings=tuple(shown["warnings"]))


def _value(s: dict, section: str, key: str):
    """The value of one entry of the sections."""
    return next(e.value for e in s[section] if e.key == key)


# -- the text ------------------------------------------------------------------------------------
def _toml_value(v) -> str:
    """A value as TOML writes it (floats always with a point)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        s = f"{v:.10g}"
        s = s if float(s) == v else repr(v)         # a value set to its last digit stays
        return s if any(c in s for c in ".eni") else s + ".0"
    return json.dumps(v, ensure_ascii=False)


#: What an entry's comment starts with, by its kind ("follows": its reason alone).
_COMMENT_PREFIX = {"key": "key number: ", "assumption": "ASSUMPTION: "}
#: The kinds of entry a NewCase lists among its ``assumptions``.
_LISTED_KINDS = frozenset({"assumption"})


def _comment(e: Entry) -> str:
    return _COMMENT_PREFIX.get(e.kind, "") + e.note


def _line(assign: str, comment: str) -> list:
    """``assign`` with its comment from COMMENT_COLUMN, wrapped on comment lines below."""
    if not comment:
        return [assign]
    col = max(COMMENT_COLUMN, len(assign) + 1)
    room = max(LINE_WIDTH - col - 2, 30)
    chunks = textwrap.wrap(comment, room, break_on_hyphens=False) or [""]
    lines = [f"{assign:<{col}}# {chunks[0]}"]
    lines += [f"{'':<{col}}#   {c}" for c in chunks[1:]]
    return lines


def _render(s: dict, drive: str, label: str, given: dict, ratio: float, notes) -> str:
    """The TOML text of the sections, with the header (``label``: what the drive is)."""
    numbers = " ".join(f"{OPTIONS[k]} {v:g}" if isinstance(v, float) else f"{OPTIONS[k]} {v}"
                       for k, v in given.items())
    head = [f"Written by `toothfem new` (toothfem {__version__}): {label}.",
            f"Key numbers: toothfem new {drive} {numbers}. Speed ratio {ratio:.6g} "
            "(n_input / n_output, signed).",
            "Every other value is derived from them by a stated rule or chosen, and marked "
            "ASSUMPTION with its reason: replace it once the hardware is known.",
            "Not written, so the case model's own rules apply (each an ASSUMPTION with its "
            "source in docs/case_schema.md): [seals], [bearings], [thermal] and "
            "[supports] (sized from the geometry), the housing's outer radius (5 pin radii "
            "beyond the pin circle), the duty cycle (the operating point alone)"
            + "".join(f"; {n}" for n in notes) + "."]
    out = []
    for para in head:
        out += ["# " + line for line in textwrap.wrap(para, LINE_WIDTH - 2,
                                                      break_on_hyphens=False,
                                                      break_long_words=False)]
    for section, entries in s.items():
        out.append("")
        out.append(f"[{section}]")
        for e in entries:
            if e.value is None:
                continue
            out += _line(f"{e.key} = {_toml_value(e.value)}", _comment(e))
    return "\n".join(out) + "\n"


# -- writing -------------------------------------------------------------------------------------
