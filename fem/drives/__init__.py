"""Drives: one abstraction for both reducers (docs/architecture.md).

A :class:`Drive` is what every capability asks instead of branching on the drive type:
the positions of one meshing period, the meshing state, the member torque for an output
torque (the one torque rule), the train speeds, the FE model, the cycle solver (with the
disk cache) and the analytic split. :func:`drive_for` picks the implementation for a case:
:class:`CycloidDrive` (a cycloid disc on its pins: K-H-V cycloid drives and the second
stage of RV-type drives) or :class:`SineDrive` (the sine planet in its ring).

To add a drive: implement :class:`Drive` in a module of this package, give its layout a
record in :data:`toothfem.fem.drives.registry.RECORDS` and its class here in
:data:`DRIVES`, and provide every part of ``registry.PARTS`` in the module that owns it
(docs/architecture.md, "Adding a drive"; tests/test_registry.py checks each).
"""
from __future__ import annotations

from .base import DEFAULT_POSITIONS, MAX_POSITIONS, Drive
from .cycloid import CycloidDrive
from .sine import SineDrive
from ...si import si_of
from .registry import layout_name

__all__ = ["DEFAULT_POSITIONS", "MAX_POSITIONS", "Drive", "CycloidDrive", "SineDrive", "DRIVES", "drive_for"]

#: The case's ``drive`` name -> the implementation that analyses its meshing stage (an RV
#: drive's contact stage is its cycloid disc).
DRIVES: dict[str, type[CycloidDrive] | type[SineDrive]] = {
    "cycloid": CycloidDrive, "rv": CycloidDrive, "sine": SineDrive}


def drive_for(case) -> Drive:
    """The :class:`Drive` of a case.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
        Anything with ``to_si()``; the drive keeps the SI record.

    Returns
    -------
    Drive
        ``CycloidDrive`` or ``SineDrive``.

    Raises
    ------
    CaseError
        When the case has no meshing stage to analyse (an RV case without its [cycloid]
        disc) or lacks the [material] the contact needs.
    """
    si = si_of(case)
    return DRIVES[layout_name(si)].from_case(si)
