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
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar
from collections.abc import Mapping

from . import si
from .case_checks import STATED_RATIO_MAX, check_type, expected_type
from .errors import CaseError, GeometryError, check_range, decode_text, short_repr
from .geometry.disc import disc_polygon
from .geometry import train
from .fem.drives.registry import provide, record_of, stage_sections

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

# the sections, re-exported: ``from toothfem.case import Material`` and the like
from .case_sections import (Bearings, CycloidStage, DiscHoles, DutyPoint, Friction, Lubricant,
                            Material, MeasuredPoint, Operating, OutputMechanism, RVTrain, Seals,
                            SineStage, SpurStage, Supports, Thermal, check_ambient,
                            check_duty_cycle)
from .case_design import Design, Tolerances, check_tolerances
from .units import M_PER_MM


@dataclass(frozen=True)
class Case:
    name: str
    drive: str                      # "cycloid" | "sine" | "rv"
    source: str = ""
    stated_ratio: float | None = None
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

    def __post_init__(self):
        record = record_of(self)        # refuses a drive no layout names
        for sec in record.required_sections[self.drive]:
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
        record_of(self).part("case_checks")(self)

    def khv_output(self):
        """The output pins that pass through a K-H-V cycloid drive's discs, or None (a 2K-V
        drive, or no cycloid).

        Returns
        -------
        toothfem.case_sections.OutputMechanism or None
        """
        if self.cycloid is None or "output_mechanism" not in record_of(self).components:
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
        return record_of(self).part("ratio")(self)

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


def _need(section: _S | None, name: str, case: Case) -> _S:
    """A section the layout requires (``DriveRecord.required_sections``), or the CaseError
    that names it."""
    if section is None:
        raise CaseError(f"[{name}] section is required for drive = {case.drive!r}")
    return section


@provide("ratio", "cycloid")
def _khv_ratio(case: Case) -> float:
    """A K-H-V cycloid drive: the disc's lobes on the pins."""
    cyc = _need(case.cycloid, "cycloid", case)
    return train.khv_ratio(cyc.lobe_count, cyc.pin_count)


@provide("ratio", "rv")
def _rv_ratio(case: Case) -> float:
    """A 2K-V drive: from [rv], or from [first_stage] and [cycloid]."""
    if case.rv is not None:
        z = case.rv
        return train.rv_ratio(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count)
    fs = _need(case.first_stage, "first_stage", case)
    cyc = _need(case.cycloid, "cycloid", case)
    return train.rv_ratio(fs.sun_teeth, fs.planet_teeth, cyc.lobe_count, cyc.pin_count)


@provide("ratio", "sine")
def _sine_ratio(case: Case) -> float:
    """The sine pair: one tooth difference, the planet's teeth on the ring's."""
    st = _need(case.sine, "sine", case)
    return train.khv_ratio(st.planet_teeth, st.ring_teeth)


def _needs_output_pins(case: Case) -> None:
    """A single-stage layout carries its torque out through pins in the member's holes."""
    if case.output_mechanism is None:
        raise CaseError(f"drive = {case.drive!r} without a [first_stage] needs "
                        "[output_mechanism] (pins in holes: the output path of a K-H-V "
                        "stage)")


@provide("case_checks", "cycloid")
def _check_khv(case: Case) -> None:
    """K-H-V: the output pins, and the disc on its eccentric bearing in the centre bore
    with the output pins' holes beside it."""
    _needs_output_pins(case)
    _check_khv_disc(case)


provide("case_checks", "sine")(_needs_output_pins)


@provide("case_checks", "rv")
def _check_rv(case: Case) -> None:
    """2K-V: a cycloid stage behind its spur first stage, on cranks in crank holes."""
    if case.cycloid is None:
        return                          # the [rv] train alone (the RV paper's method)
    if case.first_stage is None:
        raise CaseError("[first_stage] section is required with a [cycloid] section for "
                        f"drive = {case.drive!r} (the sun-planet mesh)")
    h = case.cycloid.disc_holes
    if h.crank_hole_count < 1:     # (their radii: DiscHoles checks them with a count)
        raise CaseError(f"cycloid.disc_holes.crank_hole_count = {h.crank_hole_count} "
                        "is outside the valid range [1, 12]: a two-stage (RV-type) "
                        "drive carries its discs on crankshafts in crank holes "
                        "(crank_hole_count, crank_hole_radius_mm and "
                        "crank_hole_circle_radius_mm > 0)")


def _check_khv_disc(case: Case) -> None:
    """A K-H-V disc sits on its eccentric bearing in the centre bore, and the output
    pins' holes fit in the disc beside it."""
    cyc = _need(case.cycloid, "cycloid", case)
    om = _need(case.output_mechanism, "output_mechanism", case)
    if cyc.disc_holes.centre_bore_radius_mm <= 0:
        raise CaseError("cycloid.disc_holes.centre_bore_radius_mm = "
                        f"{cyc.disc_holes.centre_bore_radius_mm!r} must be > 0 for a K-H-V "
                        "drive: the disc sits on its eccentric bearing in the centre bore")
    holes = cyc.holes_si(om)
    gap = holes.output_hole_radius_m - om.contact_radius_mm * M_PER_MM \
        - cyc.eccentricity_mm * M_PER_MM
    if gap < 0:
        raise CaseError(f"output_mechanism.hole_radius_mm = {om.hole_radius_mm!r} is "
                        "outside the valid range: at least the pin's (or roller's) radius "
                        f"plus the eccentricity, {om.contact_radius_mm + cyc.eccentricity_mm:g}"
                        " mm (else the disc cannot orbit on its output pins)")
    try:
        disc_polygon(cyc.geometry(), holes, points_per_lobe=16)
    except GeometryError as exc:
        raise CaseError(f"{exc} (the output pins' holes: output_mechanism.pin_count, "
                        "pin_hole_circle_radius_mm, hole_radius_mm; the bore: "
                        "cycloid.disc_holes.centre_bore_radius_mm)") from None


_SECTIONS = {
    "material": Material, "cycloid": CycloidStage, "first_stage": SpurStage,
    "sine": SineStage, "rv": RVTrain, "operating": Operating, "lubricant": Lubricant,
    "friction": Friction, "output_mechanism": OutputMechanism, "supports": Supports,
    "seals": Seals, "bearings": Bearings, "thermal": Thermal, "tolerances": Tolerances,
    "design": Design,
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
        for i, v in enumerate(value if isinstance(value, list) else [value]):
            name = f"published.{key}" + (f"[{i}]" if isinstance(value, list) else "")
            check_type(name, v, "number")
            check_range(name, v, error=CaseError)
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
                  "rated_output_speed_rpm", "rig_input_speed_rpm", "rig_output_torque_max_Nm")
#: How alike a key must be to a read name to count as its misspelling (difflib's ratio:
#: "max_forse_N" to "max_force_N" is 0.91; "efficiency_range" to "efficiency" 0.77).
PUBLISHED_TYPO_RATIO = 0.85


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

