"""What ``toothfem new`` asks of a layout and the rules every layout's template shares
(docs/architecture.md, "Adding a layout"): the key numbers and their options, the
:class:`NewCaseTemplate` each layout package fills (``Layout.case_template``), the entries
of a case text with their kind and reason, rounding, the loader's refusals restated in the
options' names, and the operating point's and output pins' rules. The sizing rules of a
cycloid stage that the K-H-V and RV templates both take (the pin radius, the holes in the
disc, the tolerances): :mod:`toothfem.cycloid_template`.

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

from .case_running import Operating
from .errors import CaseError, ToothfemError
from .units import M_PER_MM

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
#: K-H-V output pins. ASSUMPTION: eight, as the shipped K-H-V and sine cases; the pin's
#: radius 0.73 of its roller's (the shipped K-H-V case: 4 mm pins in 5.5 mm rollers).
OUTPUT_PIN_COUNT = 8


#: Step [mm] by which a roller's radius may move so that the zero-clearance hole round it
#: is written in a few digits (``zero_clearance``): a hundredth, below any fit's tolerance.
ROLLER_NUDGE_MM = 0.01


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


OUTPUT_PIN_FRICTION = ("output_pin_coefficient", 0.05,
                       "lubricated steel pins in holes (the shipped K-H-V case)")
