"""A reducer layout: everything the analyses ask that differs between a K-H-V cycloid drive,
an RV (2K-V) reducer and a sine reducer (docs/architecture.md, "Adding a layout").

Each layout is one package of :mod:`toothfem.layouts` that builds one :class:`Layout`
from the cores' pieces (the drive of its meshing stage and the output path of its system
model, its loss flow, envelope and bearing set, case checks and ``toothfem new``
template, the rows ``check`` prints, its drawing and CAD parts) and exports it as
``LAYOUT``; :data:`toothfem.layouts.LAYOUTS` lists them, one line each. A case's layout
travels with its SI record (``CaseSI.layout``) and with its drive (``Drive.layout``), so
the cores take it as an argument and never import a layout (tests/test_layering.py).
"""
from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .efficiency.drive_losses import LossModel
    from .fem.drives.base import Drive
    from .si import CaseSI


@dataclass(frozen=True, eq=False, kw_only=True)
class Layout:
    """One reducer layout (module docstring). Compared and hashed by identity: each is a
    module-level constant, pickled as a reference to it.

    Attributes
    ----------
    name : str
        The layout: "cycloid" (K-H-V), "rv" (2K-V) or "sine".
    label : str
        What it is, for a reader ("an RV (2K-V) reducer: ...").
    module : str
        The package that defines it (``__name__``): where an unpickled copy is looked up.
    stage_section : str
        The case section of its meshing stage ("cycloid" or "sine"): where its tolerance
        and design keys and its mesh efficiency are named.
    tolerance_keys : tuple of str
        The ``[tolerances]`` keys of that stage (the other stages' must stay zero).
    design_keys : mapping
        The stage-section keys ``toothfem design`` varies -> (the SI geometry field each
        sets, the factor from the key's unit to SI); empty: no search for this layout.
    required_sections : mapping
        The case's ``drive`` value(s) that name this layout -> the sections each requires.
    selected_by : mapping
        A ``drive`` value this layout shares with another -> the section whose presence
        selects this one (a ``cycloid`` case with a ``[first_stage]`` is the RV layout).
    components : frozenset of str
        The parts an effect of the measured-data loops may act on ("pins",
        "output_mechanism", "main_bearings" ...; ``Effect.acts_on``).
    case_temperature_limit_C : float or None
        The case surface's temperature limit when the case states none, with
        ``case_temperature_source``; None: no default (toothfem.limits.case_temperature).
    drive : callable
        ``drive(si, layout) -> Drive``: the drive of its meshing stage with its output path.
    ratio : callable
        ``ratio(case) -> float``, the signed train ratio from the tooth numbers.
    case_checks : callable
        ``case_checks(case) -> None``: the layout's cross-section rules, a CaseError naming
        the key otherwise.
    case_template : object
        A :class:`toothfem.case_template.NewCaseTemplate`: what ``toothfem new`` asks.
    derived_rows : callable
        ``derived_rows(case) -> dict``: its geometry and train figures ``check`` prints.
    loss_model : LossModel
        Every loss component of its power flow (:class:`toothfem.efficiency.drive_losses.
        LossModel`).
    envelope : callable
        ``envelope(si, drive) -> dict``: the seals', bearings' and housing's sizes the case
        leaves out.
    bearing_set : callable
        ``bearing_set(si, drive) -> tuple of Bearing``: every bearing of the layout, its
        group names matching the system model's (``efficiency.bearings.SYSTEM_GROUPS``).
    eccentric_loads : callable
        ``(si, drive, table, resultant (P, 2), member_torque) -> ((P, 2) load on one
        eccentric bearing, (P, S) its magnitude over the relative turn)``.
    main_row_force : callable
        ``(si, drive, table, member_torque (M,)) -> (M, P, 2)``: the force one member puts
        on the main bearings.
    drawing : callable
        ``drawing(drive, case_name) -> matplotlib Figure``: the pair with its dimensions.
    cad_parts : callable
        ``cad_parts(si, drive, points_per_tooth) -> PartDrawing``: the DXF, SVG and STEP
        bodies.
    """
    name: str
    label: str
    module: str
    stage_section: str
    tolerance_keys: tuple[str, ...]
    design_keys: Mapping[str, tuple[str, float]] = field(default_factory=dict)
    required_sections: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    selected_by: Mapping[str, str] = field(default_factory=dict)
    components: frozenset[str] = frozenset()
    case_temperature_limit_C: float | None = None
    case_temperature_source: str = ""
    drive: Callable[[CaseSI, Layout], Drive]
    ratio: Callable[[Any], float]
    case_checks: Callable[[Any], None]
    case_template: Any
    derived_rows: Callable[[Any], dict]
    loss_model: LossModel
    envelope: Callable[[CaseSI, Drive], dict]
    bearing_set: Callable[[CaseSI, Drive], tuple]
    eccentric_loads: Callable[..., tuple]
    main_row_force: Callable[..., Any]
    drawing: Callable[[Drive, str], Any]
    cad_parts: Callable[[CaseSI, Drive, int], Any]

    def make_drive(self, si: CaseSI) -> Drive:
        """The drive of a case of this layout.

        Parameters
        ----------
        si : toothfem.si.CaseSI

        Returns
        -------
        toothfem.fem.drives.base.Drive
        """
        return self.drive(si, self)

    def __reduce__(self):
        """Pickled as its name in its package (a Dask worker gets the same object)."""
        return (layout_in, (self.module,))

    def __repr__(self) -> str:
        return f"Layout({self.name!r})"


def layout_in(module: str) -> Layout:
    """The ``LAYOUT`` a layout package defines (what an unpickled layout is).

    Parameters
    ----------
    module : str
        The package, e.g. "toothfem.layouts.rv".

    Returns
    -------
    Layout
    """
    return importlib.import_module(module).LAYOUT
