"""One registration record per reducer layout: everything a consumer asks of a drive.

A layout is what the analyses tell apart: a K-H-V cycloid drive (one eccentric, the discs
turn the output through pins in holes), an RV (2K-V) drive (a spur first stage turns
cranks that carry the discs) and a one-tooth-difference sine drive. Each has one
:class:`DriveRecord` here, which holds

- what the drive package itself knows (the case section of its meshing stage, the keys of
  that stage's tolerances and of the modifications ``toothfem design`` varies, the label a
  reader sees), and
- a *part* per capability of the layers above, which the owning module provides once with
  :func:`provide` (the loss model in ``efficiency.drive_losses``, the envelope in
  ``efficiency.envelope``, the drawing in ``toothfem.report.plots`` ...).

Consumers ask the drive (``drive.part("loss_model")``) or the case
(``record_of(case).part("derived_rows")``); nothing outside this package branches on the
layout; each consumer imports the module that provides its part, so the part is there
when asked. ``tests/test_registry.py`` checks that every record has every part of
:data:`PARTS` (docs/architecture.md, "Adding a drive").
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ...errors import CaseError
from ...units import DEG, M_PER_MM

#: Every part a layout provides, the module that provides it and what it is.
PARTS: dict[str, str] = {
    "loss_model": "toothfem.efficiency.drive_losses: (si, drive, points) -> DriveLosses, "
                  "every loss component of the layout's power flow",
    "envelope": "toothfem.efficiency.envelope: (si, drive) -> dict, the seals', bearings' "
                "and housing's sizes the case leaves out",
    "bearing_set": "toothfem.efficiency.bearing_set: (si, drive) -> list of BearingGroup, "
                   "every bearing of the layout",
    "eccentric_loads": "toothfem.efficiency.bearings: (si, drive, table, resultant (P, 2), "
                       "member_torque) -> ((P, 2) load on one eccentric bearing, (P, S) its "
                       "magnitude over the relative turn): how the member's torque leaves it",
    "main_row_force": "toothfem.efficiency.bearings: (si, drive, table, member_torque (M,)) "
                      "-> (M, P, 2) force one member puts on the main bearings",
    "ratio": "toothfem.case: (case) -> float, the signed train ratio from the tooth numbers "
             "of the sections the layout requires",
    "case_checks": "toothfem.case: (case) -> None, the layout's cross-section rules (its "
                   "output path, holes and bore), a CaseError naming the key otherwise",
    "case_template": "toothfem.case_new: a NewCaseTemplate, what `toothfem new` asks of the "
                     "layout (its key numbers, their checks and the case text's sections)",
    "derived_rows": "toothfem.derived: (case) -> dict, the layout's geometry and train "
                    "figures that `toothfem check` prints",
    "drawing": "toothfem.report.plots: (drive, case_name) -> matplotlib Figure, the pair "
               "drawn with its dimensions",
    "cad_parts": "toothfem.cad_parts: (si, drive, points_per_tooth) -> PartDrawing, the "
                 "bodies of the DXF, SVG and STEP",
}


@dataclass
class DriveRecord:
    """A layout's registration (module docstring).

    Attributes
    ----------
    name : str
        The layout: "cycloid" (K-H-V), "rv" (2K-V) or "sine".
    label : str
        What the layout is, for a reader ("an RV (2K-V) reducer: ...").
    stage_section : str
        The case section of its meshing stage ("cycloid" or "sine"): where its tolerance
        and design keys and its mesh efficiency are named.
    tolerance_keys : tuple of str
        The ``[tolerances]`` keys of that stage (the other stages' must stay zero).
    design_keys : dict
        The stage-section keys ``toothfem design`` varies -> (the SI geometry field each
        sets, the factor from the key's unit to SI); empty: no search for this layout.
    required_sections : dict
        The case's ``drive`` value(s) that name this layout -> the sections each requires.
    selected_by : dict
        A ``drive`` value this layout shares with another -> the section whose presence
        selects this one (a ``cycloid`` case with a ``[first_stage]`` is the RV layout).
    components : frozenset of str
        The parts the layout has that an effect may act on ("pins", "output_mechanism",
        "main_bearings" ...): a loop effect names the one it needs (``Effect.acts_on``).
    case_temperature_limit_C : float or None
        The case surface's temperature limit when the case states none, with
        ``case_temperature_source``; None: no default (toothfem.limits.case_temperature).
    parts : dict
        Part name (:data:`PARTS`) -> the callable its owning module provided.
    """
    name: str
    label: str
    stage_section: str
    tolerance_keys: tuple[str, ...]
    design_keys: Mapping[str, tuple[str, float]] = field(default_factory=dict)
    required_sections: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    selected_by: Mapping[str, str] = field(default_factory=dict)
    components: frozenset[str] = frozenset()
    case_temperature_limit_C: float | None = None
    case_temperature_source: str = ""
    parts: dict[str, Callable[..., Any]] = field(default_factory=dict)

    def part(self, name: str) -> Callable[..., Any]:
        """The part ``name`` of this layout.

        Parameters
        ----------
        name : str
            A key of :data:`PARTS`.

        Returns
        -------
        callable
            What the owning module provided.

        Raises
        ------
        KeyError
            Naming the part, the layout and the module that should provide it.
        """
        try:
            return self.parts[name]
        except KeyError:
            where = PARTS.get(name, "no module: not a part of PARTS").split(":")[0]
            raise KeyError(f"layout {self.name!r} has no part {name!r} (provided by "
                           f"{where}; import toothfem first)") from None


#: The disc's profile modifications the design search varies (toothfem/design.py).
_CYCLOID_DESIGN = {"equidistant_modification_mm": ("equidistant_m", M_PER_MM),
                   "move_distance_modification_mm": ("move_distance_m", M_PER_MM),
                   "rotation_modification_deg": ("rotation_rad", DEG)}
_CYCLOID_TOLERANCES = ("pin_position_mm", "pin_diameter_lower_mm", "pin_diameter_upper_mm",
                       "pin_circle_radius_mm", "disc_profile_mm", "crank_hole_position_mm")

#: The layouts, by name.
RECORDS: dict[str, DriveRecord] = {
    "cycloid": DriveRecord(
        name="cycloid", stage_section="cycloid", tolerance_keys=_CYCLOID_TOLERANCES,
        design_keys=_CYCLOID_DESIGN,
        required_sections={"cycloid": ("cycloid", "material")},
        components=frozenset({"pins", "eccentric_bearing", "output_mechanism",
                              "main_bearings"}),
        label="a K-H-V cycloid drive with output pins through the discs"),
    "rv": DriveRecord(
        name="rv", stage_section="cycloid", tolerance_keys=_CYCLOID_TOLERANCES,
        design_keys=_CYCLOID_DESIGN,
        required_sections={"rv": ("rv",), "cycloid": ("cycloid", "material")},
        selected_by={"cycloid": "first_stage"},
        components=frozenset({"pins", "first_stage", "crank_bearings", "main_bearings"}),
        label="an RV (2K-V) reducer: a spur first stage, crankshafts, cycloid discs",
        # Nabtesco's RV-E series catalogue (operating conditions: the reducer's surface at
        # most 60 C); an ASSUMPTION for a reducer of another maker
        case_temperature_limit_C=60.0,
        case_temperature_source="Nabtesco RV-E catalogue: the reducer's surface at most "
                                "60 C; ASSUMPTION for this case (thermal."
                                "case_temperature_limit_C sets it)"),
    "sine": DriveRecord(
        name="sine", stage_section="sine", tolerance_keys=("tooth_profile_mm",),
        required_sections={"sine": ("sine", "material")},
        components=frozenset({"teeth", "eccentric_bearing", "output_mechanism"}),
        label="a one-tooth-difference sine-profile reducer with output pins"),
}


def provide(part: str, *layouts: str) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Register the decorated callable as ``part`` of each named layout.

    Parameters
    ----------
    part : str
        A key of :data:`PARTS`.
    *layouts : str
        Keys of :data:`RECORDS`.

    Returns
    -------
    callable
        The decorator; it returns the callable unchanged.

    Raises
    ------
    ValueError
        For a part not in :data:`PARTS`, an unknown layout or a part provided twice.
    """
    if part not in PARTS:
        raise ValueError(f"part {part!r} is not one of {sorted(PARTS)}")
    unknown = [n for n in layouts if n not in RECORDS]
    if unknown or not layouts:
        raise ValueError(f"layouts {unknown or list(layouts)} are not among {sorted(RECORDS)}")

    def register(fn: Callable[..., Any]) -> Callable[..., Any]:
        for n in layouts:
            if part in RECORDS[n].parts and RECORDS[n].parts[part] is not fn:
                raise ValueError(f"part {part!r} of layout {n!r} is provided twice")
            RECORDS[n].parts[part] = fn
        return fn
    return register


def case_drives() -> tuple[str, ...]:
    """The values a case's ``drive`` may take (every record's, each once).

    Returns
    -------
    tuple of str
    """
    return tuple(sorted({n for r in RECORDS.values() for n in r.required_sections}))


def layout_name(case) -> str:
    """The layout of a case, from its ``drive`` and sections: of the records its ``drive``
    names, one whose selecting section (``DriveRecord.selected_by``) the case has, else the
    one without such a section (a ``cycloid`` case with a ``[first_stage]`` is the RV
    layout, without one the K-H-V layout).

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
        Its ``drive`` and sections are read.

    Returns
    -------
    str
        A key of :data:`RECORDS`.

    Raises
    ------
    CaseError
        For a ``drive`` that no layout names.
    """
    drive = getattr(case, "drive", None)
    named = [r for r in RECORDS.values() if drive in r.required_sections]
    if not isinstance(drive, str) or not named:
        raise CaseError(f"case.drive = {drive!r} is not one of {list(case_drives())}")
    chosen = [r for r in named if drive in r.selected_by
              and getattr(case, r.selected_by[drive], None) is not None]
    return (chosen or [r for r in named if drive not in r.selected_by])[0].name


def record_of(case) -> DriveRecord:
    """The :class:`DriveRecord` of a case (:func:`layout_name`).

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI

    Returns
    -------
    DriveRecord
    """
    return RECORDS[layout_name(case)]


def stage_sections() -> tuple[str, ...]:
    """The case sections that hold a meshing stage, each once.

    Returns
    -------
    tuple of str
        E.g. ("cycloid", "sine").
    """
    return tuple(dict.fromkeys(r.stage_section for r in RECORDS.values()))
