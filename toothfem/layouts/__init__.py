"""The reducer layouts, each one package that builds its :class:`toothfem.layout.Layout`
(docs/architecture.md, "Adding a layout"): a new layout is its folder and one line in
:data:`LAYOUTS`. Nothing here is registered by importing a module: the list is the
registry."""
from __future__ import annotations

from ..errors import CaseError
from ..layout import Layout
from . import khv, rv, sine

#: Every layout, in the order ``toothfem new`` lists them.
LAYOUTS: tuple[Layout, ...] = (
    khv.LAYOUT,
    rv.LAYOUT,
    sine.LAYOUT,
)


def layout_named(name: str) -> Layout:
    """The layout of a name ("cycloid", "rv", "sine").

    Parameters
    ----------
    name : str

    Returns
    -------
    Layout

    Raises
    ------
    CaseError
        For a name no layout has, naming the valid ones.
    """
    for layout in LAYOUTS:
        if layout.name == name:
            return layout
    raise CaseError(f"layout {name!r} is not one of {[x.name for x in LAYOUTS]}")


def case_drives() -> tuple[str, ...]:
    """The values a case's ``drive`` may take (every layout's, each once).

    Returns
    -------
    tuple of str
    """
    return tuple(sorted({n for x in LAYOUTS for n in x.required_sections}))


def layout_of(case) -> Layout:
    """The layout of a case, from its ``drive`` and sections: of the layouts its ``drive``
    names, one whose selecting section (``Layout.selected_by``) the case has, else the one
    without such a section (a ``cycloid`` case with a ``[first_stage]`` is the RV layout,
    without one the K-H-V layout).

    Parameters
    ----------
    case : toothfem.case.Case
        Its ``drive`` and sections are read.

    Returns
    -------
    Layout

    Raises
    ------
    CaseError
        For a ``drive`` that no layout names.
    """
    drive = getattr(case, "drive", None)
    named = [x for x in LAYOUTS if drive in x.required_sections]
    if not isinstance(drive, str) or not named:
        raise CaseError(f"case.drive = {drive!r} is not one of {list(case_drives())}")
    chosen = [x for x in named if drive in x.selected_by
              and getattr(case, x.selected_by[drive], None) is not None]
    return (chosen or [x for x in named if drive not in x.selected_by])[0]


def stage_sections() -> tuple[str, ...]:
    """The case sections that hold a meshing stage, each once.

    Returns
    -------
    tuple of str
        E.g. ("cycloid", "sine").
    """
    return tuple(dict.fromkeys(x.stage_section for x in LAYOUTS))
