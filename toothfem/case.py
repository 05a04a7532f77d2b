"""Case model: a reducer described in TOML (units in key names) as frozen dataclasses.

``load_case(path)`` opens a file; ``parse_case(mapping)`` validates a mapping, so tests can
pass dicts. Every section is a frozen dataclass whose fields carry their valid range in
``metadata``; ``__post_init__`` checks them, so a record built in code is validated the same
way as one read from a file. A bad value raises :class:`CaseError` with one line naming the
key, the value and the valid range.

Units: the case keeps the units of its keys (mm, N·m, rpm, GPa ...); the ``*_si`` helpers
and the geometry constructors convert to SI.
"""
from __future__ import annotations

import contextlib
import dataclasses
import difflib
import math
import re
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar
from collections.abc import Mapping

from . import si
from .case_checks import STATED_RATIO_MAX, check_type, expected_type
from .errors import CaseError, check_range, decode_text, short_repr
from .layout import Layout
from .layouts import case_drives, layout_of, stage_sections

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

# the sections, re-exported: ``from toothfem.case import Material`` and the like
from .case_running import (Bearings, DutyPoint, Friction, Lubricant, MeasuredPoint, Operating,
                           Seals, Thermal, check_ambient, check_duty_cycle)
from .case_sections import (CycloidStage, DiscHoles, Material, OutputMechanism, RVTrain,
                            SineStage, SpurStage, Supports, _f)
from .case_design import Design, Envelope, Tolerances, check_tolerances
from .case_wear import Wear


@dataclass(frozen=True)
class Case:
    # the [case] table's keys, their schema as the sections' (toothfem.case_schema); parse_case
    # checks them
    name: str = _f(doc="the reducer, as the reports title it")
    drive: str = _f(choices=case_drives(), doc="the meshing stage; with the sections it "
                                               "selects the layout (toothfem.layouts)")
    source: str = _f(default="", doc="where the case's values come from",
                     source="empty: none stated")
    stated_ratio: float | None = _f(-STATED_RATIO_MAX, STATED_RATIO_MAX, default=None,
                                    doc="the ratio as the source states it (signed or its "
                                        "magnitude), checked against the tooth numbers",
                                    unset="not checked",
                                    source="none: nothing to check against")
    material: Material | None = None
    cycloid: CycloidStage | None = None
    first_stage: SpurStage | None = None
    sine: SineStage | None = None
    rv: RVTrain | None = None
    operating: Operating = field(default_factory=Operating)
    lubricant: Lubricant = field(default_factory=Lubricant)
    friction: Friction = field(default_factory=Friction)
    output_mechanism: OutputMechanism | None = None
    supports: Supports | None = None
    measured: tuple[MeasuredPoint, ...] = ()
    published: Mapping[str, Any] = field(default_factory=dict)
    seals: Seals = field(default_factory=Seals)
    bearings: Bearings = field(default_factory=Bearings)
    thermal: Thermal = field(default_factory=Thermal)
    duty_cycle: tuple[DutyPoint, ...] = ()
    tolerances: Tolerances = field(default_factory=Tolerances)
    design: Design | None = None
    envelope: Envelope | None = None
    wear: Wear = field(default_factory=Wear)

    def __post_init__(self):
        layout = self.layout            # refuses a drive no layout names
        for sec in layout.required_sections[self.drive]:
            if getattr(self, sec) is None:
                raise CaseError(f"[{sec}] section is required for drive = {self.drive!r}")
        if self.rv is not None:           # the [rv] tooth numbers bind the stages
            z = self.rv
            for sec, pairs in (("first_stage", (("sun_teeth", z.sun_teeth),
                                                ("planet_teeth", z.planet_teeth))),
                               ("cycloid", (("lobe_count", z.disc_teeth),
                                            ("pin_count", z.pin_count)))):
                st = getattr(self, sec)
                for key, want in pairs if st is not None else ():
                    if getattr(st, key) != want:
                        raise CaseError(f"{sec}.{key} = {getattr(st, key)} disagrees with the "
                                        f"[rv] tooth numbers ({want})")
        check_duty_cycle(self.duty_cycle)
        check_tolerances(self.tolerances, next(
            (sec for sec in stage_sections() if getattr(self, sec) is not None), None))
        check_ambient(self.thermal, self.lubricant)
        self._check_analysable()
        if self.stated_ratio is not None:
            computed = self.ratio()
            if not math.isclose(abs(computed), abs(self.stated_ratio), rel_tol=1e-9):
                raise CaseError(f"case.stated_ratio = {self.stated_ratio!r} disagrees with the "
                                f"ratio {computed:g} computed from the tooth numbers")

    def _check_analysable(self):
        """Cross-section rules that the analyses need (issue 14, item 2: nothing ``check``
        accepts may fail later for want of a section): a load, a material for every profile
        pair, the output path of each drive type."""
        op = self.operating
        if op.output_torque_Nm is None and op.input_torque_Nm is None \
                and op.input_power_kW is None:
            raise CaseError("[operating] needs output_torque_Nm, input_torque_Nm or "
                            "input_power_kW (the load every analysis starts from)")
        if self.cycloid is not None and self.material is None:
            raise CaseError("[material] section is required with a [cycloid] section (the "
                            "contact model of the disc)")
        self.layout.case_checks(self)

    @property
    def layout(self) -> Layout:
        """The case's layout (:func:`toothfem.layouts.layout_of`): what every analysis asks
        of it.

        Returns
        -------
        toothfem.layout.Layout
        """
        return layout_of(self)

    def khv_output(self):
        """The output pins that pass through a K-H-V cycloid drive's discs, or None (a 2K-V
        drive, or no cycloid).

        Returns
        -------
        toothfem.case_sections.OutputMechanism or None
        """
        if self.cycloid is None or "output_mechanism" not in self.layout.components:
            return None
        return self.output_mechanism

    def ratio(self) -> float:
        """Input/output speed ratio computed from the tooth numbers (signed; see
        :mod:`toothfem.geometry.train` for the sign convention).

        Returns
        -------
        float
            i = omega_input / omega_output [-].
        """
        return self.layout.ratio(self)

    def to_si(self) -> si.CaseSI:
        """The case in SI records (:mod:`toothfem.si`): what fem/ and efficiency/ read.
        Computed once per case (cached on the frozen record).

        Returns
        -------
        toothfem.si.CaseSI
            The SI record.
        """
        cached = self.__dict__.get("_si")
        if cached is None:
            cached = si.from_case(self)
            object.__setattr__(self, "_si", cached)
        return cached


_S = TypeVar("_S")


_SECTIONS = {
    "material": Material, "cycloid": CycloidStage, "first_stage": SpurStage,
    "sine": SineStage, "rv": RVTrain, "operating": Operating, "lubricant": Lubricant,
    "friction": Friction, "output_mechanism": OutputMechanism, "supports": Supports,
    "seals": Seals, "bearings": Bearings, "thermal": Thermal, "tolerances": Tolerances,
    "design": Design, "envelope": Envelope, "wear": Wear,
}
_NESTED = {CycloidStage: {"disc_holes": DiscHoles}}


def _section(cls, mapping: Mapping[str, Any], name: str):
    if not isinstance(mapping, Mapping):
        raise CaseError(f"[{name}] must be a table, got {type(mapping).__name__}")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, value in mapping.items():
        if key not in fields:
            raise CaseError(f"{name}.{key} is not a known key; known: {sorted(fields)}")
        sub = _NESTED.get(cls, {}).get(key)
        if sub is not None:
            value = _section(sub, value, f"{name}.{key}")
        else:
            check_type(f"{name}.{key}", value, expected_type(fields[key]))
            if fields[key].type in ("float", "float | None") and isinstance(value, int):
                # beyond any float (OverflowError): the section refuses it by range
                with contextlib.suppress(OverflowError):
                    value = float(value)
        kwargs[key] = value
    missing = [f.name for f in fields.values()
               if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
               and f.name not in kwargs]
    if missing:
        raise CaseError(f"{name}.{missing[0]} is required")
    try:
        return cls(**kwargs)
    except CaseError as exc:       # name the table as the file does, e.g. measured[0]
        msg = str(exc)
        if name != cls._section and msg.startswith(cls._section + "."):
            msg = name + msg[len(cls._section):]
        raise CaseError(msg) from None


def parse_case(mapping: Mapping[str, Any]) -> Case:
    """Validate a case mapping (as read from TOML) into a :class:`Case`.

    Parameters
    ----------
    mapping : Mapping
        Tables by section name (``case``, ``cycloid``, ``operating`` ...), keys with their
        units in the name.

    Returns
    -------
    Case
        Validated; a bad value raises :class:`CaseError` naming the key, its value and the
        valid range.

    Raises
    ------
    CaseError
        A missing or unknown section or key, a section of the wrong kind, or a value of the
        wrong type or outside its range (one line naming the key, its value and the valid
        range).
    """
    mapping = dict(mapping)
    head = mapping.pop("case", None)
    if not isinstance(head, Mapping):
        raise CaseError("[case] table with name and drive is required")
    head = dict(head)
    for key in head:
        if key not in ("name", "drive", "source", "stated_ratio"):
            raise CaseError(f"case.{key} is not a known key; known: "
                            "['drive', 'name', 'source', 'stated_ratio']")
    for key in ("name", "drive"):
        if key not in head:
            raise CaseError(f"case.{key} is required")
    kwargs: dict[str, Any] = dict(head)
    for key in ("name", "drive", "source"):
        if key in kwargs:
            check_type(f"case.{key}", kwargs[key], "string")
    if "stated_ratio" in kwargs:
        check_type("case.stated_ratio", kwargs["stated_ratio"], "number")
        check_range("case.stated_ratio", kwargs["stated_ratio"], -STATED_RATIO_MAX,
                    STATED_RATIO_MAX, error=CaseError, why="a reducer ratio, signed")
    measured = mapping.pop("measured", [])
    published = mapping.pop("published", {})
    duty = mapping.pop("duty_cycle", [])
    for key, value in mapping.items():
        cls = _SECTIONS.get(key)
        if cls is None:
            raise CaseError(f"[{key}] is not a known section; known: "
                            f"{sorted(_SECTIONS) + ['case', 'duty_cycle', 'measured', 'published']}")
        kwargs[key] = _section(cls, value, key)
    if not isinstance(measured, list):
        raise CaseError("[[measured]] must be an array of tables")
    kwargs["measured"] = tuple(_section(MeasuredPoint, m, f"measured[{i}]")
                               for i, m in enumerate(measured))
    if not isinstance(duty, list):
        raise CaseError("[[duty_cycle]] must be an array of tables")
    kwargs["duty_cycle"] = tuple(_section(DutyPoint, d, f"duty_cycle[{i}]")
                                 for i, d in enumerate(duty))
    if not isinstance(published, Mapping):
        raise CaseError("[published] must be a table")
    for key, value in published.items():      # figures quoted for comparison
        _check_published_key(key)
        if isinstance(value, str):
            continue
        # a figure, or a range of figures (e.g. the maker's efficiency band [lo, hi])
        lo, hi, lo_open, why = published_range(key)
        for i, v in enumerate(value if isinstance(value, list) else [value]):
            name = f"published.{key}" + (f"[{i}]" if isinstance(value, list) else "")
            check_type(name, v, "number")
            check_range(name, v, lo, hi, lo_open=lo_open, error=CaseError, why=why)
        if isinstance(value, list) and len(value) == 2 and value[0] > value[1]:
            raise CaseError(f"published.{key} = {value!r} is a range with its least above "
                            "its greatest; valid: [least, greatest]")
    kwargs["published"] = dict(published)
    return Case(**kwargs)


#: The ``[published]`` names toothfem reads: shown beside our figures
#: (toothfem.report.summary.PUBLISHED_NAMES, and ``loss_share_<component>``), the maker's
#: rated life (toothfem.durability.MAKER_KEYS) and the paper's rig point on the efficiency
#: chart. Other keys are kept as notes; a key within a typo of one of these is refused (a
#: misspelled figure would silently not be compared).
PUBLISHED_READ = ("pins_in_contact", "teeth_in_contact", "max_contact_stress_MPa",
                  "max_ph_MPa", "max_force_N", "efficiency", "efficiency_computed",
                  "loss_L1_W", "loss_L2_W", "rated_life_h", "rated_torque_Nm",
                  "rated_output_speed_rpm", "rig_input_speed_rpm", "rig_output_torque_max_Nm",
                  "torsional_rigidity_Nm_per_arcmin", "lost_motion_arcmin",
                  "lost_motion_torque_Nm", "backlash_arcmin", "allowable_moment_Nm",
                  "momentary_torque_Nm", "start_stop_torque_Nm", "mass_kg")
#: How alike a key must be to a read name to count as its misspelling (difflib's ratio:
#: "max_forse_N" to "max_force_N" is 0.91; "efficiency_range" to "efficiency" 0.77).
PUBLISHED_TYPO_RATIO = 0.85


#: The range of a ``[published]`` figure by its name: (name test, lo, hi, lo open, why).
#: The first that matches applies; a name none matches is a note (any finite number).
PUBLISHED_RANGES = (
    (lambda k: "efficiency" in k or k.startswith("loss_share_"), 0.0, 1.0, False,
     "a fraction (0.88 for 88 %)"),
    (lambda k: k in ("pins_in_contact", "teeth_in_contact"), 0.0, 1e4, False,
     "a count of pins or teeth"),
    (lambda k: k.endswith("_Nm_per_arcmin"), 0.0, 1e7, True,
     "a torsional rigidity [N m/arcmin] of a reducer"),
    (lambda k: k.endswith("_arcmin"), 0.0, 600.0, False, "an angle [arcmin] (600: 10 deg)"),
    (lambda k: k.endswith("_kg"), 0.0, 1e6, True, "a mass [kg]"),
    (lambda k: k.endswith("_Nm"), 0.0, 1e7, True, "a torque [N m] of a reducer"),
    (lambda k: k.endswith("_rpm"), 0.0, 1e6, True, "a speed [rpm]"),
    (lambda k: k.endswith("_h"), 0.0, 1e7, True, "a life [h] (1e7 h: 1100 years)"),
    (lambda k: k.endswith("_MPa"), 0.0, 1e5, True, "a stress [MPa]"),
    (lambda k: k.endswith("_N"), 0.0, 1e9, True, "a force [N]"),
    (lambda k: k.endswith("_W"), 0.0, 1e9, False, "a power [W]"),
)


def published_range(key: str) -> tuple:
    """The valid range of the ``[published]`` figure ``key``.

    Parameters
    ----------
    key : str
        Its name (the unit suffix tells its kind).

    Returns
    -------
    tuple
        ``(lo, hi, lo_open, why)``; ``(None, None, False, "")`` for a note (any finite
        number).
    """
    for test, lo, hi, lo_open, why in PUBLISHED_RANGES:
        if test(key):
            return lo, hi, lo_open, why
    return None, None, False, ""


def _check_published_key(key: str) -> None:
    if key in PUBLISHED_READ or key.startswith("loss_share_"):
        return
    near = difflib.get_close_matches(key, PUBLISHED_READ, n=1, cutoff=PUBLISHED_TYPO_RATIO)
    if near:
        raise CaseError(f"published.{key} is not a figure toothfem reads; did you mean "
                        f"{near[0]!r}? (read: {', '.join(PUBLISHED_READ)}, loss_share_*; "
                        "other keys are kept as notes)")


def as_case(case, name: str = "case") -> Case:
    """A case given as a :class:`Case` or as the path of a case file.

    Parameters
    ----------
    case : Case or str or os.PathLike
        The case, or its TOML file (loaded and validated).
    name : str
        The argument, as a message names it.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        For anything else, naming the argument; as :func:`load_case` for a bad file.
    """
    if isinstance(case, Case):
        return case
    if isinstance(case, (str, os.PathLike)):
        return load_case(case)
    raise CaseError(f"{name} = {short_repr(case)} is not a case; valid: a toothfem.Case "
                    "or the path of a case file")


def load_case(path) -> Case:
    """Open a TOML case file and validate it.

    Parameters
    ----------
    path : str or Path
        The case file.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        The file's name, then the key, its value and the valid range.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise CaseError(f"{path}: no such case file") from None
    except IsADirectoryError:
        raise CaseError(f"{path}: is a folder, not a case file") from None
    except OSError as exc:
        raise CaseError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    try:
        return parse_case_text(decode_text(raw, path, CaseError))
    except CaseError as exc:
        raise CaseError(f"{path}: {exc}") from None


def parse_case_text(text: str) -> Case:
    """A case file's text, read as TOML and validated (:func:`parse_case`).

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        For text that is not TOML, then as :func:`parse_case`.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"not valid TOML: {exc}") from None
    return parse_case(data)


def case_to_dict(case: Case) -> dict:
    """Plain mapping of a case, the inverse of :func:`parse_case`.

    Parameters
    ----------
    case : Case

    Returns
    -------
    dict
        ``parse_case(case_to_dict(case)) == case``.
    """
    out: dict[str, Any] = {"case": {k: getattr(case, k) for k in ("name", "drive", "source")
                                    if getattr(case, k) is not None}}
    if case.stated_ratio is not None:
        out["case"]["stated_ratio"] = case.stated_ratio
    for key in _SECTIONS:
        sec = getattr(case, key)
        if sec is not None:
            out[key] = {k: v for k, v in dataclasses.asdict(sec).items() if v is not None}
    if case.measured:
        out["measured"] = [dataclasses.asdict(m) for m in case.measured]
    if case.duty_cycle:
        out["duty_cycle"] = [dataclasses.asdict(d) for d in case.duty_cycle]
    if case.published:
        out["published"] = dict(case.published)
    return out


def with_keys(text: str, section: str, values: dict, *, notes: dict | None = None,
              note: str = "toothfem design", create: bool = False) -> str:
    """Set keys in one table of a TOML text, comments and the rest left as they are.

    Parameters
    ----------
    text : str
        TOML.
    section : str
        The table's name (``[section]``).
    values : dict of str to float
        Each key's line replaced, or added under the header.
    notes : dict of str to str, optional
        Each key's comment (default ``note``).
    note : str
        The comment of a key without its own.
    create : bool
        Add the table at the end where ``text`` has none (else refused).

    Returns
    -------
    str

    Raises
    ------
    CaseError
        If ``text`` has no such table and ``create`` is False.
    """
    lines = text.splitlines()
    head = next((i for i, ln in enumerate(lines)
                 if re.match(rf"\s*\[{re.escape(section)}\]\s*(#.*)?$", ln)), None)
    if head is None:
        if not create:
            raise CaseError(f"the case file has no [{section}] table")
        lines += ["", f"[{section}]"]
        head = len(lines) - 1
    end = next((i for i in range(head + 1, len(lines))
                if re.match(r"\s*\[", lines[i])), len(lines))
    notes = notes or {}
    for key, value in values.items():
        shown = str(value) if isinstance(value, (int, str)) else f"{value:.6g}"
        line = f"{key} = {shown}   # {notes.get(key, note)}"
        hit = next((i for i in range(head + 1, end)
                    if re.match(rf"\s*{re.escape(key)}\s*=", lines[i])), None)
        if hit is None:
            lines.insert(head + 1, line)
            end += 1
        else:
            lines[hit] = line
    return "\n".join(lines) + "\n"
