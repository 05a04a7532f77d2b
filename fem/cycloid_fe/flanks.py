"""The modified disc's two flanks for the detailed mode: the outline of a disc with a rotation
modification and the projection of a pin's contact zone on the flank it meets.

A rotation modification Delta delta turns each flank of every lobe: the disc is the
intersection (Delta delta > 0) or the union (< 0) of the working profile turned by
+Delta delta and by -Delta delta (:func:`toothfem.geometry.cycloid_distance.modified_distance`).
The flank that carries a torque of sign s is the profile turned by -s Delta delta. The
detailed mode meshes the disc turned by s Delta delta from its nominal pose: there the
loaded flank is the unmodified profile itself, the other flank the profile turned by
2 s Delta delta, and the holes are turned by s Delta delta; the pins stand where they
stand at the nominal pose. The linear rigid-rotation unknown of the contact solve is then
measured from that pose (docs/derivations.md 8), and the transmission error is it plus
s Delta delta.
"""
from __future__ import annotations

import math

import numpy as np

from ...geometry.cycloid import inward_normal, working_profile
from ...geometry.cycloid_distance import foot_point, polar_parameter
from ...geometry.vectors import rotate
from .model import _disc_rings


def frame_turn(geometry, side: int) -> float:
    """The detailed mode's disc pose: turned by side * Delta delta from the nominal.

    Parameters
    ----------
    geometry : toothfem.geometry.cycloid.CycloidGeometry
    side : {1, -1}
        The torque's sign.

    Returns
    -------
    float
        The turn [rad], counter-clockwise.
    """
    return side * geometry.rotation_rad


def flank_turn(geometry, side: int, arm) -> np.ndarray:
    """Turn of the profile each pin meets, in the detailed mode's frame [rad]: 0 for the
    flank that carries the torque of sign ``side`` (moment arm of sign -side), else
    2 side Delta delta.

    Parameters
    ----------
    geometry : toothfem.geometry.cycloid.CycloidGeometry
    side : {1, -1}
    arm : array_like, shape (C,)
        Moment arms (MeshingState sign).

    Returns
    -------
    numpy.ndarray, shape (C,)
    """
    arm = np.asarray(arm, float)
    return np.where(side * arm <= 0, 0.0, 2 * side * geometry.rotation_rad)


def project(gen, points, turn: float, psi0):
    """Foot points of ``points`` (2, N) on the working profile turned by ``turn``.

    Parameters
    ----------
    gen : toothfem.geometry.cycloid._Generating
    points : numpy.ndarray, shape (2, N)
        Points [m] in the frame of the turned profile.
    turn : float
        The profile's turn [rad].
    psi0 : array_like, shape (N,)
        Starting parameters [rad].

    Returns
    -------
    psi : numpy.ndarray, shape (N,)
        Parameters of the foot points on the unturned profile [rad].
    point : numpy.ndarray, shape (2, N)
        The foot points [m] (turned).
    normal : numpy.ndarray, shape (2, N)
        Outward unit normals there (turned).
    """
    psi, _ = foot_point(gen, rotate(points, -turn) if turn else points, psi0)
    point = working_profile(gen, psi)
    normal = -inward_normal(gen, psi)
    if turn:
        point, normal = rotate(point, turn), rotate(normal, turn)
    return psi, point, normal


def half_lobe_turns(geometry) -> tuple:
    """Which turned profile bounds the disc over each half-lobe (between two symmetry
    lines, a tip and a root) of a disc with a rotation modification.

    Parameters
    ----------
    geometry : toothfem.geometry.cycloid.CycloidGeometry
        With ``rotation_rad`` nonzero.

    Returns
    -------
    alpha : numpy.ndarray, shape (2 Za + 1,)
        The symmetry lines' polar angles in the disc's nominal frame [rad], from 0.
    turn : numpy.ndarray, shape (2 Za,)
        The turn of the profile that bounds each half-lobe there, +Delta delta or -Delta
        delta: a point of the +delta profile inside the -delta disc (intersection,
        Delta delta > 0) or outside it (union) says +delta.
    """
    delta = geometry.rotation_rad
    gen = geometry.generating()
    step = math.pi / geometry.lobe_count
    alpha = step * np.arange(2 * geometry.lobe_count + 1)
    mid = rotate(working_profile(gen, alpha[:-1] + 0.5 * step - delta), delta)
    d_other = foot_point(gen, rotate(mid, delta), alpha[:-1] + 0.5 * step)[1]
    plus = (d_other <= 0) if delta > 0 else (d_other > 0)
    return alpha, np.where(plus, delta, -delta)


def bounds_disc(geometry, side: int, psi, turn) -> np.ndarray:
    """Whether each foot point lies on the part of its turned profile that bounds the
    disc: a pin whose foot point falls beyond the corner where the two turned flanks meet
    (the tip corner at a large rotation modification) faces the other flank there, not
    this one, and stands clear of the disc by more than the projection says.

    Parameters
    ----------
    geometry : toothfem.geometry.cycloid.CycloidGeometry
    side : {1, -1}
        The torque's sign (the detailed mode's pose, :func:`frame_turn`).
    psi : array_like, shape (C,)
        Foot points' parameters on the unturned profile [rad] (:func:`project`).
    turn : array_like, shape (C,)
        The turn of the profile each was projected on, in the detailed mode's frame
        (:func:`flank_turn`).

    Returns
    -------
    numpy.ndarray of bool, shape (C,)
        All True without a rotation modification.
    """
    psi = np.asarray(psi, float)
    if not geometry.rotation_rad:
        return np.ones(psi.shape, bool)
    alpha, own = half_lobe_turns(geometry)
    a = np.asarray(turn, float) - frame_turn(geometry, side)   # the turn from the nominal
    x = working_profile(geometry.generating(), psi)
    polar = np.mod(np.arctan2(x[1], x[0]) + a, 2 * math.pi)
    k = np.minimum((polar // (alpha[1] - alpha[0])).astype(int), own.size - 1)
    return np.isclose(own[k], a, rtol=0, atol=1e-12)


def disc_rings(model, side: int, inserts=(), base_per_lobe: int = 48):
    """The disc's outline and holes in the detailed mode's frame (turned by side Delta
    delta), with each contact zone's parameters kept as vertices.

    Without a rotation modification: :func:`toothfem.fem.cycloid_fe.model._disc_rings`.
    With one, the outline runs over the half-lobes between the symmetry lines (tips and
    roots), each on the turned profile that bounds the intersection (union) there, and
    meets the next at the corner where the two cross on the symmetry line.

    Parameters
    ----------
    model : CycloidFEModel
    side : {1, -1}
        The torque's sign (the pose).
    inserts : sequence of (psi, turn)
        Profile parameters [rad] of a zone on the profile turned by ``turn`` [rad] (the
        detailed mode's frame, :func:`flank_turn`).
    base_per_lobe : int
        Coarse samples per lobe.

    Returns
    -------
    rings : list of numpy.ndarray, shape (2, N)
    names : list of str
        "profile" and the holes' labels.
    """
    g = model.geometry
    delta = g.rotation_rad
    if not delta:
        return _disc_rings(model, [np.asarray(psi, float) for psi, _ in inserts], base_per_lobe)
    gen = g.generating()
    za = g.lobe_count
    pose = frame_turn(g, side)
    alpha, a_own = half_lobe_turns(g)               # symmetry lines, own frame
    base_step = 2 * math.pi / (za * base_per_lobe)
    margin = 0.5 * base_step
    pieces = []
    for k in range(2 * za):
        a = float(a_own[k])
        lo, hi = polar_parameter(gen, np.array([alpha[k] - a, alpha[k + 1] - a]))
        zones = [np.asarray(psi, float) for psi, t in inserts
                 if math.isclose(t - pose, a, abs_tol=1e-15)]
        zones = [z[(z > lo + margin) & (z < hi - margin)] for z in zones]
        zones = [z for z in zones if z.size]
        base = np.arange(math.ceil(lo / base_step), math.floor(hi / base_step) + 1) * base_step
        keep = (base > lo + margin) & (base < hi - margin)
        for z in zones:
            keep &= ~((base >= z.min() - margin) & (base <= z.max() + margin))
        psi = np.sort(np.concatenate([[lo], base[keep], *zones]))
        psi = psi[np.concatenate([[True], np.diff(psi) > 1e-12])]
        pieces.append(rotate(working_profile(gen, psi), a + pose))
    rings, names = [np.concatenate(pieces, axis=1)], ["profile"]
    for x, y, r, label in model.holes.circles():
        n = max(48, int(2 * math.pi * r / (0.02 * g.pin_circle_radius_m)))
        t = np.linspace(0, 2 * math.pi, n, endpoint=False)
        rings.append(rotate(np.stack([x + r * np.cos(t), y + r * np.sin(t)]), pose))
        names.append(label)
    return rings, names
