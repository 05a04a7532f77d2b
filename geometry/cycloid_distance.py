"""Distances on the cycloid disc's working profile, measured on the parametric curve: foot
points (:func:`foot_point`), signed distances from the working profile
(:func:`distance_to_profile`) and from the modified disc, whose rotation modification turns
each flank (:func:`modified_distance`), and the parameter at a polar angle
(:func:`polar_parameter`). Lengths in m, angles and parameters psi in rad, points (2, N)
in the disc frame. The profile and its modifications: :mod:`toothfem.geometry.cycloid` and
docs/derivations.md, sections C1, C6 and 8.
"""
from __future__ import annotations

import math

import numpy as np

from .cycloid import (CycloidGeometry, _Generating, inward_normal, theoretical_profile,
                      working_profile)
from .vectors import rotate

#: Newton tolerance on the foot-point parameter (rad); far below 1e-6*Rz in distance.
_FOOT_TOL = 1e-14
_FOOT_MAXITER = 50


def foot_point(g: _Generating, points, psi0):
    """Parameter of the point of the working curve nearest to ``points`` (2, N).

    Newton on f(psi) = (w(psi) - c) . p'(psi) = 0 (the working and theoretical curves share
    their tangent), started from the nearest point within half a lobe of ``psi0``.

    Parameters
    ----------
    g : _Generating
    points : numpy.ndarray, shape (2, N)
        Points in the disc frame [m].
    psi0 : array_like, shape (N,)
        Starting parameters [rad].

    Returns
    -------
    psi : numpy.ndarray, shape (N,)
        Parameters of the foot points [rad].
    distance : numpy.ndarray, shape (N,)
        Signed distance from the curve along the outward normal [m].
    """
    # start at the nearest point within half a lobe (nested grids): Newton from psi0 itself
    # can settle on a farther stationary point or wander where K1 is near 1 (issue 14)
    grid = _nearest_in_window(g, points, psi0)
    psi = grid.copy()
    h = 1e-6
    with np.errstate(all="ignore"):
        for _ in range(_FOOT_MAXITER):
            f = _foot_f(g, psi, points)
            df = (_foot_f(g, psi + h, points) - _foot_f(g, psi - h, points)) / (2 * h)
            step = f / df
            psi -= step
            if np.max(np.abs(step)) < _FOOT_TOL:
                break
    # where Newton did not settle near the grid's point, the grid's point stands
    stuck = ~((np.abs(step) <= 1e-9) & (np.abs(psi - grid) <= _NEST_SPAN * _nest_step(g)))
    psi[stuck] = grid[stuck]
    w = working_profile(g, psi)
    out = -inward_normal(g, psi)
    return psi, np.sum((points - w) * out, axis=0)


#: Nested-grid search for the start of the foot-point Newton: samples per window and
#: rounds, each window 4 grid steps wide around the best sample of the last (final
#: spacing (2 pi/Za)/32/8^4, 1.2e-6 rad for Za = 39: where Newton does not settle, the
#: grid's distance is within ds^2/(2 rho) ~ 1e-12 m of the minimum).
_NEST_SAMPLES, _NEST_ROUNDS = 33, 5


#: Newton may move this many final grid steps away from the grid's point.
_NEST_SPAN = 4


def _nest_step(g) -> float:
    """Final spacing of :func:`_nearest_in_window` (rad)."""
    return math.pi / (g.zb - 1) * (4.0 / (_NEST_SAMPLES - 1)) ** (_NEST_ROUNDS - 1) \
        * 2 / (_NEST_SAMPLES - 1)


def _nearest_in_window(g, points, psi0):
    """Parameter of the working-curve point nearest to each of ``points`` (2, N) within
    half a lobe of ``psi0`` (N,), by nested grids (robust where Newton on the foot-point
    equation wanders, root of a strongly curtate profile; issue 14)."""
    half = math.pi / (g.zb - 1)
    centre = np.array(psi0, float, copy=True).reshape(-1)
    t = np.linspace(-1.0, 1.0, _NEST_SAMPLES)
    for _ in range(_NEST_ROUNDS):
        psi = centre[:, None] + half * t[None, :]
        w = working_profile(g, psi)
        d2 = (w[0] - points[0][:, None]) ** 2 + (w[1] - points[1][:, None]) ** 2
        centre = np.take_along_axis(psi, np.argmin(d2, axis=1)[:, None], axis=1)[:, 0]
        half *= 4.0 / (_NEST_SAMPLES - 1)
    return centre


def _foot_f(g, psi, points):
    return np.sum((working_profile(g, psi) - points) * theoretical_profile(g, psi, 1), axis=0)


def _nearest_psi(g, points, samples=8192, chunk=256):
    """Coarse global nearest parameter for each point (brute force in chunks)."""
    psi = np.linspace(0, 2 * math.pi, samples, endpoint=False)
    w = working_profile(g, psi)
    out = np.empty(points.shape[1])
    for i in range(0, points.shape[1], chunk):
        p = points[:, i:i + chunk]
        d2 = (p[0][:, None] - w[0][None]) ** 2 + (p[1][:, None] - w[1][None]) ** 2
        out[i:i + chunk] = psi[np.argmin(d2, axis=1)]
    return out


def distance_to_profile(geom: CycloidGeometry, points, flank: int = 0, psi0=None):
    """Exact signed distance of disc-frame points (2, N) from the working profile
    (positive outside the disc), found on the parametric curve (Newton foot point).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc, as generated.
    points : array_like, shape (2, N)
        Points in the disc frame [m].
    flank : int
        With a rotation modification, the point is first turned by -flank*Delta delta
        (+1 or -1; 0 ignores the rotation).
    psi0 : array_like, shape (N,), optional
        Starting parameters [rad]; by default a global brute-force search on 8192 samples.

    Returns
    -------
    numpy.ndarray, shape (N,)
        Signed distance [m].
    """
    g = geom.generating()
    pts = np.asarray(points, float)
    if flank and geom.rotation_rad:
        a = -flank * geom.rotation_rad
        pts = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]) @ pts
    if psi0 is None:
        psi0 = _nearest_psi(g, pts)
    return foot_point(g, pts, psi0)[1]


#: A foot point of one turned profile counts as inside the other turned profile's
#: material when its signed distance from that profile is below this [m] (round-off).
_INSIDE_TOL = 1e-12


def modified_distance(geom: CycloidGeometry, points, rotation_rad: float = 0.0,
                      psi0=None) -> np.ndarray:
    """Exact signed distance of points from the modified disc, turned by ``rotation_rad``
    (counter-clockwise) from its nominal pose; positive outside the disc.

    The points (2, N) are given in the disc frame of the nominal pose. With a rotation
    modification Delta delta > 0 the disc is the intersection of the working profile turned
    by +Delta delta and by -Delta delta (each flank turned toward its tooth centre, material
    removed); with Delta delta < 0 it is their union (each flank turned away from its tooth
    centre, material added), so that the first-order clearance is Delta delta |l| for
    either sign (docs/derivations.md C6, 8). For a point outside both turned discs the
    distance from a union is the smaller of the two distances; the distance from an
    intersection is the distance from one turned profile where its foot point lies inside
    the other turned disc, else the distance from their crossing (the corner at a tooth tip
    or root, on the symmetry line of the lobe).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc, as generated.
    points : array_like, shape (2, N)
        Points in the disc frame of the nominal pose [m] (pin centres: outside the disc).
    rotation_rad : float
        Turn of the disc from its nominal pose [rad], counter-clockwise.
    psi0 : array_like, shape (N,), optional
        Starting profile parameters [rad]; by default a global search.

    Returns
    -------
    numpy.ndarray, shape (N,)
        Signed distance [m].
    """
    g = geom.generating()
    pts = rotate(points, -rotation_rad) if rotation_rad else np.asarray(points, float)
    if psi0 is None:
        psi0 = _nearest_psi(g, pts)
    psi0 = np.asarray(psi0, float)
    delta = geom.rotation_rad
    if not delta:
        return foot_point(g, pts, psi0)[1]
    feet, dist = [], []
    for a in (delta, -delta):                 # the profile turned by a: the point by -a
        psi, d = foot_point(g, rotate(pts, -a), psi0)
        feet.append(psi)
        dist.append(d)
    if delta < 0:                             # union: the nearer of the two
        return np.minimum(dist[0], dist[1])
    # intersection: a foot point counts where it lies inside the other turned disc
    out = np.empty_like(dist[0])
    done = np.zeros(out.shape, bool)
    for k, a in enumerate((delta, -delta)):
        # foot on the profile turned by a, seen from the profile turned by -a: turned by 2a
        inside = foot_point(g, rotate(working_profile(g, feet[k]), 2 * a), feet[k])[1] \
            <= _INSIDE_TOL
        take = inside & ~done
        out[take] = dist[k][take]
        done |= take
    if not np.all(done):
        corner = _corner(g, delta, pts[:, ~done])
        out[~done] = np.hypot(*(pts[:, ~done] - corner))
    return out


def _corner(g: _Generating, delta: float, points) -> np.ndarray:
    """Where the profiles turned by +delta and -delta cross on the symmetry line (tooth tip
    or root) nearest to each point (2, N): the working-curve point at polar angle
    alpha - delta, turned by +delta (the profile is symmetric about alpha)."""
    step = math.pi / (g.zb - 1)              # roots at even, tips at odd multiples
    alpha = step * np.round(np.arctan2(points[1], points[0]) / step)
    return rotate(working_profile(g, polar_parameter(g, alpha - delta)), delta)


def polar_parameter(g: _Generating, target) -> np.ndarray:
    """Parameters psi where the working curve's polar angle (about the disc centre) is
    ``target``.

    Newton from psi = target: the working curve's polar angle grows with psi, and equals
    it on the symmetry lines (tips and roots).

    Parameters
    ----------
    g : _Generating
    target : array_like, shape (N,)
        Polar angles [rad].

    Returns
    -------
    numpy.ndarray, shape (N,)
        psi [rad].
    """
    target = np.asarray(target, float)
    psi = target.copy()
    h = 1e-7

    def polar(x):
        w = working_profile(g, x)
        return np.arctan2(w[1], w[0])

    for _ in range(_FOOT_MAXITER):
        f = np.angle(np.exp(1j * (polar(psi) - target)))
        df = np.angle(np.exp(1j * (polar(psi + h) - polar(psi - h)))) / (2 * h)
        d = f / df
        psi -= d
        if np.max(np.abs(d), initial=0.0) < _FOOT_TOL:
            break
    return psi
