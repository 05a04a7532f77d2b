"""The face width in `toothfem contact`: the cycle mode's load sharing with the disc's face
cut into slices (``[cycloid] face_slices`` > 1; fem/cycloid_fe/slices.py,
docs/face_width.md), and its summary figures. The writing: :mod:`toothfem.report.face_width`.
"""
from __future__ import annotations

from typing import Any

from .errors import CaseError
from .fem.cycloid_fe.slices import FaceSpec, SlicedSharing, solve_sliced


def face_of(drive) -> FaceSpec:
    """The drive's face-width slicing: its stage's ``face`` (a cycloid stage's
    ``[cycloid]`` keys); one slice for a stage without one (the sine pair).

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    FaceSpec
    """
    pairs = getattr(getattr(drive, "stage", None), "face", ())
    return FaceSpec(**dict(pairs))


def sliced_contact(drive, solver, torque: float, mode: str,
                   progress: Any = None) -> SlicedSharing | None:
    """The sliced load sharing of the cycle mode where the case has more than one slice.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    solver : toothfem.fem.cycloid_fe.CycleSolver
        The planar cycle solver (its tables per unit length).
    torque : float
        The member's torque [N m].
    mode : {"cycle", "detailed"}
        The contact analysis' mode.
    progress : callable, optional
        Wraps the iterable of positions.

    Returns
    -------
    SlicedSharing or None
        None for one slice.

    Raises
    ------
    CaseError
        For slices with the detailed mode (planar: one slice).
    """
    face = face_of(drive)
    if face.slices == 1:
        return None
    if mode != "cycle":
        raise CaseError(f"cycloid.face_slices = {face.slices} is outside the valid range for "
                        "--mode detailed: 1 (the detailed mode is planar; the slices run in "
                        "the cycle mode)")
    return solve_sliced(solver, face, torque, progress=progress)
