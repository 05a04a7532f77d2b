"""Small rules more than one layout shares: a section a layout requires, the output pins
of a single-stage layout, the seals' temperature limit of a layout without a maker's, and
the rounding of the rows ``toothfem check`` prints."""
from __future__ import annotations

from typing import TypeVar

from ..errors import CaseError

_S = TypeVar("_S")

#: The case (oil) temperature limit of a layout without a maker's figure (K-H-V, the sine
#: pair) [C]: the upper end of nitrile lip seals' working range for oil or grease. No
#: K-H-V or sine maker's surface limit was found (Sumitomo's Fine Cyclo catalogue was
#: searched and not read in full); the seals taken for nitrile and their lips at the lumped
#: heat balance's one temperature (their own friction heating above it not counted) are
#: ASSUMPTIONS.
NITRILE_SEAL_LIMIT_C = 100.0
NITRILE_SEAL_SOURCE = ("nitrile lip seals' working range -40 to +100 C for oil or grease "
                       "(M. J. Neale, ed., The Tribology Handbook, Butterworth-Heinemann, "
                       "'Lip seals', the table of sealing-lip rubbers); ASSUMPTION: nitrile "
                       "seals, their lips at the heat balance's temperature "
                       "(thermal.case_temperature_limit_C sets it)")


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
