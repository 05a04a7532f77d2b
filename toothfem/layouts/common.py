"""Small rules more than one layout shares: a section a layout requires, the output pins
of a single-stage layout, and the rounding of the rows ``toothfem check`` prints."""
from __future__ import annotations

from typing import TypeVar

from ..errors import CaseError

_S = TypeVar("_S")


def need(section: _S | None, name: str, case) -> _S:
    """A section the layout requires (``Layout.required_sections``), or the CaseError that
    names it.

    Parameters
    ----------
    section : object or None
        The case's section.
    name : str
        Its name in the case file.
    case : toothfem.case.Case

    Returns
    -------
    object
        ``section``.
    """
    if section is None:
        raise CaseError(f"[{name}] section is required for drive = {case.drive!r}")
    return section


def needs_output_pins(case) -> None:
    """A single-stage layout carries its torque out through pins in the member's holes.

    Parameters
    ----------
    case : toothfem.case.Case

    Raises
    ------
    CaseError
        Without an [output_mechanism].
    """
    if case.output_mechanism is None:
        raise CaseError(f"drive = {case.drive!r} without a [first_stage] needs "
                        "[output_mechanism] (pins in holes: the output path of a K-H-V "
                        "stage)")


def rounded(x, digits: int = 10) -> float:
    """``x`` to ``digits`` significant digits (the rows ``check`` prints).

    Parameters
    ----------
    x : float
    digits : int

    Returns
    -------
    float
    """
    return float(f"{x:.{digits}g}")
