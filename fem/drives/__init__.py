"""Drives: one abstraction for both meshing stages (docs/architecture.md).

A :class:`Drive` is what every capability asks instead of branching on the drive type:
the positions of one meshing period, the meshing state, the member torque for an output
torque (the one torque rule), the train speeds, the FE model, the cycle solver (with the
disk cache), the analytic split and the system model of the whole reducer.
:class:`CycloidDrive` is a cycloid disc on its pins (K-H-V cycloid drives and the second
stage of RV-type drives), :class:`SineDrive` the sine planet in its ring. A case's layout
(:mod:`toothfem.layouts`, carried by its SI record) builds its drive: :func:`drive_for`.
"""
from __future__ import annotations

from .base import DEFAULT_POSITIONS, MAX_POSITIONS, Drive
from .cycloid import CycloidDrive
from .sine import SineDrive
from ...si import si_of

__all__ = ["DEFAULT_POSITIONS", "MAX_POSITIONS", "Drive", "CycloidDrive", "SineDrive", "drive_for"]


def drive_for(case) -> Drive:
    """The :class:`Drive` of a case, built by its layout (``CaseSI.layout``).

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
    return si.layout.make_drive(si)
