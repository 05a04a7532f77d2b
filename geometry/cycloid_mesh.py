"""Cycloid-pin meshing: the disc in its housing, the pin contacts and the clearances.

Notation, the profile and the modifications: :mod:`toothfem.geometry.cycloid` (the
pin-housing paper of Y. Wang et al., Sec. 2). This module places the disc and measures
against its profile: pin centres and disc poses, the kinematics of every pin contact
(:func:`meshing`), foot points and signed distances on the parametric working curve, and
the initial clearance of a modified disc, exact and to first order.

Kinematics (housing frame): pin j centre C_j = Rz*u(2*pi*j/Zb); crank angle phi puts the
disc centre at O_a = A*u(phi) and turns the disc by theta_d = -phi/Za, which places every
pin centre exactly on the theoretical profile (C_j = O_a + R(theta_d) p(psi_j) with
psi_j = theta_j - theta_d). The pin's angle from the line of centres is
theta_b = theta_j - phi; the pitch point (instant centre of the disc) is P = r_b*u(phi),
and every contact normal passes through it.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import GeometryError, check_range, checked_array
# fem/cycloid_fe reaches CycloidGeometry, inward_normal and working_profile through this
# module too (one import for the pose and the profile)
from .cycloid import (CycloidGeometry, _Generating, _rho_of_theta,
                      inward_normal, theoretical_profile, working_profile)
from .kinematics import MeshingState, equivalent_radius, slide_to_roll
from .vectors import cross, perp, rotate, unit
from ..units import ARCMIN, UM_PER_M

#: Newton tolerance on the foot-point parameter (rad); far below 1e-6*Rz in distance.
_FOOT_TOL = 1e-14
_FOOT_MAXITER = 50


# ---------------------------------------------------------------------------------------
# Disc pose and pin contacts

def pin_centres(geom: CycloidGeometry) -> np.ndarray:
    """(2, Zb) pin centres in the housing frame; pin 0 on +x.

    Parameters
    ----------
    geom : CycloidGeometry
        The pin ring (Zb pins on the circle of radius Rz).

    Returns
    -------
    numpy.ndarray, shape (2, Zb)
        Pin centres [m].
    """
    theta = 2 * math.pi * np.arange(geom.pin_count) / geom.pin_count
    return geom.pin_circle_radius_m * unit(theta)


def disc_pose(geom: CycloidGeometry, crank_angle_rad):
    """(centre (2, P), rotation (P,)) of the disc for crank angles phi (K-H-V: -phi/Za).

    Parameters
    ----------
    geom : CycloidGeometry
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles phi [rad] of the poses.

    Returns
    -------
    centre : numpy.ndarray, shape (2, P)
        Disc centre A u(phi) in the housing frame [m].
    rotation : numpy.ndarray, shape (P,)
        Disc rotation -phi/Za [rad].
    """
    phi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    return geom.eccentricity_m * unit(phi), -phi / geom.lobe_count


def to_disc_frame(geom, crank_angle_rad, points):
    """Housing-frame points (2, P, C) -> disc frame for each crank angle.

    Parameters
    ----------
    geom : CycloidGeometry
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angle phi [rad] of each set of points.
    points : numpy.ndarray, shape (2, P, C)
        Points in the housing frame [m], one set of C per crank angle.

    Returns
    -------
    numpy.ndarray, shape (2, P, C)
        The same points in the disc frame [m].
    """
    centre, rot = disc_pose(geom, crank_angle_rad)
    return rotate(points - centre[:, :, None], -rot[:, None])


def seed_moment_arm(geom: CycloidGeometry, theta_b):
    """Seed Eq. (14): l = r_a Rz sin(theta_b)/sqrt(Rz^2 + r_b^2 - 2 Rz r_b cos(theta_b)).

    Unsigned as printed; the load-carrying pins have sin(theta_b) > 0 for a
    counter-clockwise crank (see :func:`meshing`).

    Parameters
    ----------
    geom : CycloidGeometry
    theta_b : array_like
        Pin angles from the line of centres [rad].

    Returns
    -------
    numpy.ndarray
        Moment arm l [m], shape of ``theta_b``.
    """
    rz, rb = geom.pin_circle_radius_m, geom.pin_pitch_radius_m
    theta_b = np.asarray(theta_b, float)
    return geom.disc_pitch_radius_m * rz * np.sin(theta_b) / np.sqrt(
        rz**2 + rb**2 - 2 * rz * rb * np.cos(theta_b))


def meshing(geom: CycloidGeometry, crank_angle_rad, crank_speed_rad_s: float = 1.0,
            pin_motion: str = "fixed") -> MeshingState:
    """Kinematics of all Zb pin contacts at each crank angle (vectorised).

    Contact points, normals, moment arms and velocities are those of the conjugate
    (unmodified) profile, whose normals pass through the pitch point; ``gap`` is the initial
    clearance g0 of the modified profile (zero if unmodified): exact at the nominal pose, or
    with a rotation modification exact where the pin's own flank is turned back
    (:func:`clearance_exact` with ``side=0``).
    A counter-clockwise crank (crank_speed > 0) turns the disc clockwise; the pins that
    carry the output torque are those with negative moment arm (0 < theta_b < pi).

    Parameters
    ----------
    geom : CycloidGeometry
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles phi [rad] (counter-clockwise from +x).
    crank_speed_rad_s : float
        Crank (input) speed [rad/s], counter-clockwise positive.
    pin_motion : {"fixed", "rolling"}
        "fixed" (pins one piece with the housing, the integral structure: the disc slides on
        the pins) or "rolling" (conventional pins turning freely in their grooves: no sliding
        at the disc, the pin surface speed there equals the disc's, and the pin slides in its
        groove at that speed instead).

    Returns
    -------
    MeshingState
        P positions by C = Zb pins (see :mod:`toothfem.geometry.kinematics`).

    Raises
    ------
    GeometryError
        If ``pin_motion`` is not one of the two, or ``crank_speed_rad_s`` is not finite.
    """
    if pin_motion not in ("fixed", "rolling"):
        raise GeometryError(f"pin_motion = {pin_motion!r} is not one of ['fixed', 'rolling']")
    check_range("crank_speed_rad_s", crank_speed_rad_s, error=GeometryError)
    phi = np.atleast_1d(checked_array("crank_angle_rad", crank_angle_rad))
    zb, za = geom.pin_count, geom.lobe_count
    omega = float(crank_speed_rad_s)
    omega_d = -omega / za                                    # disc angular velocity
    c = pin_centres(geom)[:, None, :]                        # (2, 1, C)
    centre = geom.eccentricity_m * unit(phi)                 # (2, P)
    pitch = geom.pin_pitch_radius_m * unit(phi)[:, :, None]  # (2, P, 1)
    d = pitch - c                                            # pin -> pitch point
    dist = np.hypot(d[0], d[1])                              # |P - C|, (P, C)
    n = d / dist                                             # normal into the disc
    k = c + geom.pin_radius_m * n                            # contact point
    rel = k - centre[:, :, None]
    arm = cross(rel, n)
    pressure = np.arccos(np.clip(np.abs(arm) / np.hypot(rel[0], rel[1]), 0.0, 1.0))
    t = perp(n)                                              # tangent k x n
    # disc material velocity at K: rotation about the pitch point (instant centre)
    kp = k - pitch
    v_disc = omega_d * perp(kp)
    # contact point velocity: K = C + rz n, n = (P - C)/|P - C|
    dp = geom.pin_pitch_radius_m * omega * perp(unit(phi))[:, :, None]
    dn = (dp - n * np.sum(n * dp, axis=0)) / dist
    dk = geom.pin_radius_m * dn
    v_disc_t = np.sum(v_disc * t, axis=0)
    dk_t = np.sum(dk * t, axis=0)
    pin_surface_t = np.zeros_like(v_disc_t) if pin_motion == "fixed" else v_disc_t
    sliding = v_disc_t - pin_surface_t
    u_disc = dk_t - v_disc_t
    u_pin = dk_t - pin_surface_t
    entrain = 0.5 * (u_disc + u_pin)
    theta_b = np.mod(2 * math.pi * np.arange(zb)[None, :] / zb - phi[:, None], 2 * math.pi)
    g = geom.nominal()
    rho0 = _rho_of_theta(g, theta_b)
    r_disc = rho0 - geom.pin_radius_m            # inf at an inflection point
    r_pin = np.full_like(r_disc, geom.pin_radius_m)
    gap = clearance_exact(geom, phi) if geom.modified else np.zeros_like(arm)
    return MeshingState(
        drive="cycloid", position_rad=phi,
        contact_id=np.broadcast_to(np.arange(zb), arm.shape).copy(),
        point=np.moveaxis(k, 0, -1), normal=np.moveaxis(n, 0, -1),
        centre=centre.T.copy(), moment_arm=arm, pressure_angle=pressure, gap=gap,
        sliding_velocity=sliding, entrainment_velocity=entrain,
        slide_to_roll=slide_to_roll(sliding, entrain),
        radius_moving=r_disc, radius_fixed=r_pin,
        equivalent_radius=equivalent_radius(r_disc, r_pin),
        crank_speed_rad_s=omega)


# ---------------------------------------------------------------------------------------
# Foot points and clearances measured on the parametric curve

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


def _moment_arms(geom: CycloidGeometry, phi) -> np.ndarray:
    """(P, Zb) moment arms of the conjugate contacts (:func:`meshing`'s ``moment_arm``)."""
    c = pin_centres(geom)[:, None, :]
    centre = geom.eccentricity_m * unit(phi)
    d = geom.pin_pitch_radius_m * unit(phi)[:, :, None] - c
    n = d / np.hypot(d[0], d[1])
    return cross(c + geom.pin_radius_m * n - centre[:, :, None], n)


def clearance_at(geom: CycloidGeometry, crank_angle_rad, rotation_rad=0.0) -> np.ndarray:
    """Exact clearance of every pin, (P, Zb), with the disc turned by ``rotation_rad`` from
    its nominal pose: the distance from the pin centre to the modified disc
    (:func:`modified_distance`) minus rz.

    Parameters
    ----------
    geom : CycloidGeometry
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles phi [rad] of the nominal poses.
    rotation_rad : float or array_like, shape (P,)
        The disc's turn from each nominal pose [rad], counter-clockwise.

    Returns
    -------
    numpy.ndarray, shape (P, Zb)
        Clearance [m] (< 0: interference).
    """
    phi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    zb = geom.pin_count
    turn = np.broadcast_to(np.asarray(rotation_rad, float), phi.shape)
    c = np.broadcast_to(pin_centres(geom)[:, None, :], (2, phi.size, zb))
    local = to_disc_frame(geom, phi, c)
    local = rotate(local, -turn[:, None]).reshape(2, -1)
    # the unmodified contact parameter psi_j = theta_j - theta_d - turn starts the search
    psi0 = (2 * math.pi * np.arange(zb)[None, :] / zb
            + phi[:, None] / geom.lobe_count - turn[:, None]).ravel()
    d = modified_distance(geom, local, 0.0, psi0)
    return d.reshape(phi.size, zb) - geom.pin_radius_m


def clearance_exact(geom: CycloidGeometry, crank_angle_rad, side: int = 0) -> np.ndarray:
    """Initial clearance of every pin, (P, Zb), as the contact solvers use it: the gap at
    the nominal pose of a model that is linear in the disc's turn beta,
    g(beta) = g0 + beta l (l the moment arm, :func:`meshing`'s sign).

    Without a rotation modification g0 is the exact clearance at the nominal pose. A
    rotation modification Delta delta turns the flank that carries a torque of sign s
    by -s Delta delta: with the disc turned by beta_s = s Delta delta that flank lies
    exactly where the unmodified one did. g0 is then the exact clearance at that pose
    carried back linearly, g0 = g(beta_s) - beta_s l, so that the linear model is exact where
    the disc stands under load (turned by beta_s and a few arcseconds) and the second-order
    terms of a turn of Delta delta (micrometres at the tooth root: the corner where the two
    turned profiles cross) do not enter as false gaps (docs/derivations.md, 8).

    Parameters
    ----------
    geom : CycloidGeometry
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles phi [rad] of the nominal poses.
    side : {1, -1, 0}
        The flank the model is linearised on: the one that carries a torque of that sign,
        for every pin; 0: each pin on its own flank (l < 0: +1, else -1), the closing
        rotation of either torque sign exact.

    Returns
    -------
    numpy.ndarray, shape (P, Zb)
        g0 [m] (< 0: interference).

    Raises
    ------
    GeometryError
        If ``side`` is not 1, -1 or 0.
    """
    if side not in (1, -1, 0):
        raise GeometryError(f"side = {side!r} is not one of [1, -1, 0]")
    phi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    delta = geom.rotation_rad
    if not delta:
        return clearance_at(geom, phi)
    arm = _moment_arms(geom, phi)
    out = {}
    for s in ((1, -1) if side == 0 else (side,)):
        out[s] = clearance_at(geom, phi, s * delta) - s * delta * arm
    if side:
        return out[side]
    return np.where(arm < 0, out[1], out[-1])


def placement(gap, arm):
    """Where the disc sits before load: the turn that makes its worst pin's clearance the
    largest, per position.

    With g_i(beta) = g_i + beta l_i (both flanks, linear in the turn beta), the disc can
    be put on its pins without load where some beta leaves every g_i(beta) >= 0; the
    largest smallest clearance, max over beta of min_i g_i(beta), is the disc's clearance
    before load, and where it is negative it is the smallest interference any turn leaves
    (both flanks closed: the pins are preloaded on assembly).

    Parameters
    ----------
    gap : array_like, shape (P, C)
        g0 of the pins [m] (:func:`clearance_exact`; inf: a pin that cannot touch).
    arm : array_like, shape (P, C)
        Their moment arms [m] (:func:`meshing`'s sign).

    Returns
    -------
    beta : numpy.ndarray, shape (P,)
        The turn [rad] (inf where one flank has no reachable pin).
    clearance : numpy.ndarray, shape (P,)
        min_i g_i(beta) [m] (< 0: interference).
    """
    gap = np.atleast_2d(np.asarray(gap, float))
    arm = np.atleast_2d(np.asarray(arm, float))
    beta = np.empty(gap.shape[0])
    worst = np.empty(gap.shape[0])
    for p in range(gap.shape[0]):
        g, a = gap[p], arm[p]
        ok = np.isfinite(g)
        g, a = g[ok], a[ok]
        up, down = a > 0, a < 0              # g grows with beta / shrinks with beta
        if not (np.any(up) and np.any(down)):
            beta[p], worst[p] = math.inf, math.inf
            continue
        # the optimum lies where a shrinking and a growing gap are equal
        gi, ai = g[down][:, None], a[down][:, None]
        gj, aj = g[up][None, :], a[up][None, :]
        cand = ((gj - gi) / (ai - aj)).ravel()
        vals = np.min(g[None, :] + cand[:, None] * a[None, :], axis=1)
        k = int(np.argmax(vals))
        beta[p], worst[p] = cand[k], vals[k]
    return beta, worst


def clearance_closed_form(geom: CycloidGeometry, theta_b):
    """First-order initial clearance per pin versus pin angle theta_b (docs C4).

    Before any turning of the disc (nominal pose):
        D0 = Delta_rz - Delta_Rz (1 - K1 cos theta) / sqrt(S) + Delta_delta |l(theta)|
    with S = 1 + K1^2 - 2 K1 cos theta and l the moment arm of Eq. (14).
    Turning the disc by beta0 = min over 0 < theta < pi of D0/|l| closes the first gap on
    the load-carrying flank and leaves
        D(theta) = D0(theta) - beta0 |l(theta)|
    which for Delta_rz >= 0, Delta_Rz <= 0 is the textbook expression
        D = Delta_rz (1 - sin(theta)/sqrt(S)) - Delta_Rz (1 - K1 cos theta
            - sqrt(1 - K1^2) sin theta)/sqrt(S)
    (Li Lixing, Cycloid pin-wheel planetary transmission, 1987; also Blagojevic et al.,
    Strojniski vestnik 58 (2012)).

    Parameters
    ----------
    geom : CycloidGeometry
    theta_b : array_like
        Pin angles theta from the line of centres [rad], loaded flank 0 < theta < pi.

    Returns
    -------
    d0 : numpy.ndarray
        Clearance at the nominal pose [m], shape of ``theta_b``.
    d : numpy.ndarray
        Clearance after the turn beta0 [m], shape of ``theta_b``.
    beta0 : float
        The closing rotation [rad] (:func:`closing_rotation`).
    """
    theta = np.asarray(theta_b, float)
    k1 = geom.k1
    s = np.sqrt(1 + k1**2 - 2 * k1 * np.cos(theta))
    arm = np.abs(seed_moment_arm(geom, theta))
    d0 = (geom.equidistant_m - geom.move_distance_m * (1 - k1 * np.cos(theta)) / s
          + geom.rotation_rad * arm)
    beta0 = closing_rotation(geom)
    return d0, d0 - beta0 * arm, beta0


def closing_rotation(geom: CycloidGeometry) -> float:
    """beta0 = min over the loaded flank of D0/|l| (first order, closed form): the disc's
    angular lost motion (backlash) in one direction.

    For Delta_rz, -Delta_Rz >= 0 both terms are smallest at cos(theta) = K1, giving
    beta0 = (Delta_rz - Delta_Rz sqrt(1 - K1^2)) / r_a + Delta_delta; otherwise it is
    found on a fine grid.

    Parameters
    ----------
    geom : CycloidGeometry

    Returns
    -------
    float
        beta0 [rad].
    """
    k1 = geom.k1
    if geom.equidistant_m >= 0 and geom.move_distance_m <= 0:
        return ((geom.equidistant_m - geom.move_distance_m * math.sqrt(1 - k1**2))
                / geom.disc_pitch_radius_m + geom.rotation_rad)
    from scipy.optimize import minimize_scalar

    def ratio(theta):
        s = np.sqrt(1 + k1**2 - 2 * k1 * np.cos(theta))
        d0 = geom.equidistant_m - geom.move_distance_m * (1 - k1 * np.cos(theta)) / s
        return d0 / np.abs(seed_moment_arm(geom, theta))

    theta = np.linspace(1e-3, math.pi - 1e-3, 4001)
    k = int(np.argmin(ratio(theta)))
    lo, hi = theta[max(k - 1, 0)], theta[min(k + 1, theta.size - 1)]
    res = minimize_scalar(lambda t: float(ratio(t)), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-12})
    return float(min(res.fun, ratio(theta[k]))) + geom.rotation_rad


def before_load(geom: CycloidGeometry, crank_angle_rad) -> dict:
    """The disc on its pins before any load, over the given crank angles: how far it can
    turn (the backlash) and the clearance or interference that remains wherever it is
    put (:func:`placement` on the exact gaps of both flanks, :func:`clearance_exact`).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc with its modifications.
    crank_angle_rad : array_like, shape (P,)
        Crank angles [rad] (e.g. one meshing period).

    Returns
    -------
    dict
        ``backlash_min_arcmin``, ``backlash_max_arcmin``: the sum of both flanks' closing
        rotations (min over each flank's pins of g0/|l|) over the positions (None where
        the disc interferes: it has no backlash); ``clearance_before_load_um``: the
        smallest, over the positions, of the largest smallest clearance any turn of the
        disc leaves (negative: interference);
        ``interference_before_load_um`` (0 without interference), and where it is
        largest ``interference_position_deg``, ``interference_pins`` (pin indices within
        1 nm of it) and ``interference_flanks`` ("+": the flank that carries a positive
        disc torque, moment arm < 0; "-": the other).
    """
    phi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    arm = _moment_arms(geom, phi)
    gap = clearance_exact(geom, phi, 0) if geom.modified else np.zeros_like(arm)
    with np.errstate(divide="ignore", invalid="ignore"):
        close_pos = np.min(np.where(arm < 0, gap / np.where(arm < 0, -arm, 1), np.inf), axis=1)
        close_neg = np.min(np.where(arm > 0, gap / np.where(arm > 0, arm, 1), np.inf), axis=1)
    backlash = close_pos + close_neg
    beta, clear = placement(gap, arm)
    p = int(np.argmin(clear))
    worst = float(clear[p])
    at = gap[p] + beta[p] * arm[p]
    pins = np.flatnonzero(at <= worst + _NAMED_TOL) if worst < 0 else np.array([], int)
    arcmin = 1 / ARCMIN
    free = worst >= 0
    return {
        "backlash_min_arcmin": float(np.min(backlash) * arcmin) if free else None,
        "backlash_max_arcmin": float(np.max(backlash) * arcmin) if free else None,
        "clearance_before_load_um": worst * UM_PER_M,
        "interference_before_load_um": max(0.0, -worst * UM_PER_M),
        "interference_position_deg": math.degrees(float(phi[p])) if worst < 0 else None,
        "interference_pins": [int(j) for j in pins],
        "interference_flanks": ["+" if arm[p, j] < 0 else "-" for j in pins],
    }


#: Pins whose interference is within this of the largest are named with it [m].
_NAMED_TOL = 1e-9
