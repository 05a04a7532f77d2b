"""A built stage's crank eccentricity errors in the system model
(:class:`toothfem.fem.drives.assembly.CycloidSystem`).

The errors (``deviation.crank_eccentricity_m`` and ``crank_phase_rad``, one per crank or
per crank and disc, :class:`toothfem.fem.deviations.CycloidDeviation`) enter where the
eccentric does: crank k's eccentric at disc j stands at E_j + de_k u(phi_j + theta_k), so
the bearing between it and the disc's seat is deformed by de_k u(phi_j + theta_k) with
every body at rest (``Element.offset``). Unequal cranks force each disc to a compromise
pose through the crank bearings' play and stiffness; the cranks turn against the carrier,
so the pose goes round at that order. An error of one eccentric alone turns the output:
the TE ripples at that order. A crank's error on both its eccentrics pushes discs at 180
deg opposite ways: their turns cancel in the TE's first harmonic and the split between the
discs ripples instead. Equal errors on every crank (one phase) move each disc by
de u(phi_j + theta) with no bearing deformed: the deviation's ``eccentricity`` (the pins'
gaps shifted) on a 2K-V drive; a K-H-V drive's output pins see the disc's move too (their
holes' clearance closes by de), which ``eccentricity`` leaves out. The error's lever in
the crank's rotation (psi x (E + dE) instead of psi x E) is second order and left out, as
``eccentricity`` does.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import CaseError


def with_crank_errors(system, elements, phi: float, deviation, pitch: int = 0) -> list:
    """``elements`` with a built stage's crank eccentricity errors as the crank bearings'
    forced deformations: crank k's eccentric at disc j off its place by
    de_kj u(phi_j + theta_kj) (the module's docstring; errors (cranks,) or (cranks,
    discs)); the elements themselves where the deviation has none.

    ``pitch`` m: the state m meshing periods on, solved in pitch 0's frame (the stage
    turned back by m periods): the errors' directions are pitch 0's, and the cranks stand
    where pitch 0's did, each moved on by the carrier's turn against that frame,
    (turn ratio - 1) m period; that must be a whole number of crank spacings (the crank at
    place k is then crank k - that number).

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    elements : list of toothfem.fem.system.solve.Element
        At crank angle phi.
    phi : float
        [rad].
    deviation : object or None
        The drive's record of :mod:`toothfem.fem.deviations`.
    pitch : int

    Returns
    -------
    list of toothfem.fem.system.solve.Element

    Raises
    ------
    CaseError
        For errors of another shape, or a pitch that does not bring the cranks back onto
        the cranks' places.
    """
    de = np.asarray(getattr(deviation, "crank_eccentricity_m", ()), float)
    if de.size == 0 or not np.any(de):
        return elements
    cranks = system.cranks
    theta = np.asarray(getattr(deviation, "crank_phase_rad", ()), float)
    theta = np.zeros(de.shape) if theta.size == 0 else theta
    shape = (cranks, system.discs)
    try:
        de = np.broadcast_to(de.reshape(de.shape + (1,) * (2 - de.ndim)), shape)
        theta = np.broadcast_to(theta.reshape(theta.shape + (1,) * (2 - theta.ndim)), shape)
    except ValueError:
        raise CaseError(f"crank_eccentricity_m {np.shape(deviation.crank_eccentricity_m)}"
                        f" and crank_phase_rad {np.shape(deviation.crank_phase_rad)}: "
                        f"one value per crank ({cranks}) or per crank and "
                        f"{system.drive.member_name} {shape}") from None
    turn = (system.mesh.turn_ratio - 1.0) * int(pitch) * system.drive.period_rad
    moved = turn * cranks / (2 * math.pi)
    if cranks > 1 and abs(moved - round(moved)) > 1e-9:
        raise CaseError(f"pitch {int(pitch)}: the carrier turns {math.degrees(turn):.6g} "
                        "deg against pitch 0's frame, not a whole number of crank "
                        "spacings; solve crank errors at the positions' own pitch")
    moved = int(round(moved)) if cranks > 1 else 0
    offsets = {}
    for k in range(cranks):
        c = (k - moved) % cranks           # the crank standing at place k
        for s in system.slots:
            a = phi + s.phase_rad + theta[c, s.index]
            offsets[system.bearing_names[k][s.index]] = de[c, s.index] * np.array(
                [math.cos(a), math.sin(a)])
    return [replace(e, offset=offsets[e.name]) if e.name in offsets else e
            for e in elements]
