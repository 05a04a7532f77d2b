"""A built cycloid stage in the cycle mode: the shifts of the candidates' initial gaps [m]
that a stage's deviations (pin offsets and radii, the crank's eccentricity error, the disc's
offset and profile) cause, to first order, at any pitch of the pairing period
(docs/tolerance.md, "The idea: a deviation shifts gaps, not compliance").
"""
from __future__ import annotations

import math

import numpy as np

from ...geometry.vectors import rotate
from .model import _Position


def deviation_gaps(model, q: _Position, deviation, pitch: int = 0) -> np.ndarray:
    """Change of the initial gaps of one position's candidates for a built disc stage.

    To first order in the deviations: each pin's move against the disc projected on the
    disc's outward normal n opens its gap (:func:`pin_moves`); a larger pin or added
    profile material closes it (on the flank of the contact's moment arm: < 0 carries a
    positive torque, column 0).

    Parameters
    ----------
    model : CycloidFEModel
    q : _Position
        The candidates of one crank angle (disc frame).
    deviation : toothfem.fem.deviations.CycloidDeviation
    pitch : int
        Pin pitches on from ``q``.

    Returns
    -------
    numpy.ndarray, shape (C,)
        Gap change [m] (> 0 opens).
    """
    za = model.geometry.lobe_count
    d, dr = pin_moves(model, q, deviation, pitch)
    # lobe l spans psi in [2 pi l/Za, 2 pi (l+1)/Za): root to root, both flanks
    lobes = (np.floor(np.mod(q.psi, 2 * math.pi) * za / (2 * math.pi)).astype(int)
             + int(pitch)) % za
    return np.sum(q.normal * d, axis=0) - dr - deviation.profile[lobes, (q.arm > 0).astype(int)]


def pin_moves(model, q: _Position, deviation, pitch: int = 0):
    """Moves of the candidate pins against the disc for a built stage.

    At crank angle phi + m 2 pi/Zb the stage is the one at phi turned by 2 pi m/Zb: pin
    j + m and lobe l + m take the places of pin j and lobe l (docs/tolerance.md). A pin's
    offset is turned back by 2 pi m/Zb and into the disc frame (by phi/Za); the disc's
    own move (the crank's eccentricity error along the crank, its profile off its bore)
    counts against every pin.

    Parameters
    ----------
    model : CycloidFEModel
    q : _Position
        The candidates of one crank angle.
    deviation : toothfem.fem.deviations.CycloidDeviation
    pitch : int
        m, the pin pitches on.

    Returns
    -------
    move : numpy.ndarray, shape (2, C)
        Each candidate pin centre's move against the disc [m], disc frame of pitch 0.
    radius : numpy.ndarray, shape (C,)
        Each candidate pin's radius change [m].
    """
    g = model.geometry
    zb, za = g.pin_count, g.lobe_count
    m = int(pitch)
    pins = (q.pins + m) % zb
    to_disc = q.phi / za                     # housing -> disc frame at crank angle phi
    d = rotate(rotate(deviation.pin_offset[:, pins], -2 * math.pi * m / zb), to_disc)
    crank = np.array([math.cos(q.phi), math.sin(q.phi)])
    disc = rotate(deviation.eccentricity * crank, to_disc) \
        + rotate(np.asarray(deviation.member_offset, float), -2 * math.pi * m / za)
    return d - disc[:, None], deviation.pin_radius[pins]
