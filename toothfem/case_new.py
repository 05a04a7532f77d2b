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
layout's assumptions) is each one's :class:`toothfem.case_template.NewCaseTemplate`, its
layout's ``case_template`` (toothfem/layouts/): nothing here branches on the drive.

Computing and writing are apart: :func:`new_case` returns the text and the loaded case
(every value checked by the normal loader, its refusal restated with the option that set
the value); :func:`toothfem.output.write_new_file` writes the text atomically and never over an
existing file unless told to. Units: the key numbers' (mm, N m, rpm); SI inside the sizing.
"""
from __future__ import annotations

import json
import numbers
import textwrap
from dataclasses import dataclass
from typing import cast

from . import __version__
from .case import Case, parse_case, parse_case_text
from .case_sections import Material
from .case_template import (FLOAT_KEY_NUMBERS, OPTIONS, Entry, NewCaseTemplate, field_range,
                            key_numbers_text, put, restated, round_to, size_step)
from .errors import CaseError, ToothfemError, check_range
from .case_consistency import INTERFERING_WARN, interference_estimate
from .derived import derived
from .fem.drives import DEFAULT_POSITIONS, drive_for
from .layouts import LAYOUTS, layout_named
from .units import MPA_PER_PA

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
#: The column at which the files' line comments start (as the shipped cases).
COMMENT_COLUMN, LINE_WIDTH = 28, 99


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


def templates() -> dict[str, NewCaseTemplate]:
    """The layouts ``toothfem new`` writes: every layout with a ``case_template``.

    Returns
    -------
    dict
        Layout name -> its :class:`NewCaseTemplate`, in the order of
        :data:`toothfem.layouts.LAYOUTS`.
    """
    return {layout.name: layout.case_template for layout in LAYOUTS
            if isinstance(layout.case_template, NewCaseTemplate)}


def _check_key(option: str, value, cls, name: str, why: str = ""):
    """A key number against the range of the case field it fills; one line naming the
    option otherwise."""
    r = field_range(cls, name)
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


def _load(sections: dict, template: NewCaseTemplate, given: dict) -> Case:
    """The case of a mapping of entries, through the normal loader (refusals restated)."""
    try:
        return parse_case(_mapping(sections))
    except ToothfemError as exc:
        raise restated(exc, template, given) from None


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
    step = min(size_step(radius_mm), FACE_WIDTH_STEP_MM)

    listed = key_numbers_text(given)

    def ph_at(width):
        put(sections, section, "face_width_mm", width, "assumption", "")
        return _peak_ph_MPa(_load(sections, template, given), torque, listed)

    b = floor
    for _ in range(FACE_WIDTH_ITERATIONS):
        b = max(b * (ph_at(b) / target) ** 2, floor)
    b = round_to(b, step, "up")
    ph = ph_at(b)
    for _ in range(FACE_WIDTH_MAX_STEPS):
        if ph <= target * (1 + 1e-9):
            break
        b = round_to(b + step, step)
        ph = ph_at(b)
    design = (f"a peak Hertz pressure of {target:.4g} MPa at the torque (the allowable "
              f"{allowable:g} MPa / {CONTACT_SAFETY:g}; the analytic split gives {ph:.4g} "
              "MPa here)")
    why = (f"sized for {design}" if b > round_to(floor, step, "up") else
           f"{FACE_WIDTH_MIN_PER_RADIUS:g} x the {radius_name} (the thinnest shipped disc): "
           f"wider than the torque needs for {design}")
    put(sections, section, "face_width_mm", b, "assumption", why)
    return b, ph, why


def _shared_sections(s: dict, template: NewCaseTemplate, given: dict) -> None:
    """Material, operating point, lubricant, friction and tolerances (the layout's
    lubrication, friction coefficients and stage tolerances from its template)."""
    put(s, "material", "youngs_modulus_GPa", 208.0, "assumption",
        "through-hardened bearing steel (100Cr6), as the shipped cases")
    put(s, "material", "poisson_ratio", 0.3, "assumption", "bearing steel")
    op = "operating"
    put(s, op, "output_torque_Nm", given["torque_Nm"], "key", "--torque-Nm")
    put(s, op, "input_speed_rpm", given["input_speed_rpm"], "key", "--input-speed-rpm")
    put(s, op, "rated_torque_Nm", given["torque_Nm"], "assumption",
        "the torque the face width is sized for; a catalogue's rated torque replaces it")
    lub = "lubricant"
    lubrication, why = template.lubrication
    put(s, lub, "lubrication", lubrication, "assumption", why)
    for key, value, why in (
            ("dynamic_viscosity_Pa_s", 0.058, "ISO VG 68 mineral (base) oil at 40 C"),
            ("kinematic_viscosity_mm2_s", 68.0, "ISO VG 68 at 40 C"),
            ("density_kg_m3", 860.0, "mineral oil"),
            ("pressure_viscosity_1_per_GPa", 20.0, "mineral oil"),
            ("reference_temperature_C", 40.0, "ISO 3448's reference"),
            ("vogel_B_C", 900.0, "VG 68 mineral oil: 68 mm2/s at 40 C, 8.7 at 100 C"),
            ("roughness_Ra_um", 0.4, "ground surfaces")):
        put(s, lub, key, value, "assumption", why)
    fr = "friction"
    put(s, fr, "bearing_coefficient", 0.0015, "assumption",
        "rolling bearings (the shipped cycloid cases)")
    for key, value, why in template.friction:
        put(s, fr, key, value, "assumption", why)
    tol = "tolerances"
    put(s, tol, "distribution", "normal", "assumption",
        "3 sigma at each limit (a capable process, Cpk = 1)")
    for key, value, why in template.tolerances(s):
        put(s, tol, key, value, "assumption", why)
    put(s, tol, "eccentricity_mm", 0.002, "assumption", "+- limit, ground eccentric")


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
    layout = layout_named(drive)
    template: NewCaseTemplate = layout.case_template
    _check_key_numbers(drive, template, given)
    given = {k: (float(v) if k in FLOAT_KEY_NUMBERS else int(v)) for k, v in given.items()
             if v is not None}
    if name is not None and (not isinstance(name, str) or not name.strip()):
        raise CaseError(f"--name = {name!r} must be a non-empty string")
    s: dict = {}
    put(s, "case", "name", name or "new", "follows", "")     # named once the ratio is known
    put(s, "case", "drive", drive, "key", "the drive type")
    put(s, "case", "source", "toothfem new: key numbers given, the rest derived or assumed",
        "follows", "")
    body = template(given)
    s.update(body.sections)
    _shared_sections(s, template, given)
    _, ph, _ = _face_width(s, layout.stage_section, body.radius_mm, template.radius_name,
                           template, given)
    ratio = _load(s, template, given).ratio()
    if name is None:
        put(s, "case", "name", f"new {drive} drive ({template.name_size(given, s)}), ratio "
            f"{abs(ratio):.6g}, {given['torque_Nm']:g} N m", "follows", "")
    text = _render(s, drive, layout.label, given, ratio, body.notes)
    try:
        case = parse_case_text(text)      # the file as written, through the normal loader
    except ToothfemError as exc:
        raise restated(exc, template, given) from None
    shown = derived(case)                 # what `check` prints: the operating point too
    est = interference_estimate(case, shown)
    if est is not None and est["share"] > INTERFERING_WARN:
        # play for the built discs: an equidistant modification of the per-flank clearance
        # the estimate needs (to first order it is that clearance)
        mod = round_to(est["clearance_needed_um"] / 1000.0, 0.0005, "up")
        put(s, layout.stage_section, "equidistant_modification_mm", mod, "assumption",
            f"the smallest (0.5 um steps) that keeps {100 * INTERFERING_WARN:g} % of the "
            "reducers built within [tolerances] from interfering, by check's estimate "
            "(toothfem size chooses it on the built reducers)")
        text = _render(s, drive, layout.label, given, ratio, body.notes)
        case = parse_case_text(text)
        shown = derived(case)
    if "operating_efficiency_analytic" not in shown:
        raise CaseError(f"{'; '.join(shown['warnings'])} (the key numbers "
                        f"{key_numbers_text(given)} leave no valid value for it)")
    assumptions = tuple((f"{sec}.{e.key}", e.value, e.note) for sec, entries in s.items()
                        for e in entries if e.kind in _LISTED_KINDS and sec != "case")
    return NewCase(drive=drive, text=text, case=case,
                   key_numbers={OPTIONS[k]: v for k, v in given.items()},
                   assumptions=assumptions, ratio=ratio, peak_ph_MPa=ph,
                   efficiency=shown["operating_efficiency_analytic"],
                   warnings=tuple(shown["warnings"]))


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
