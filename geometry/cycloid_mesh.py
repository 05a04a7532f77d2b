"""Cycloid-pin meshing: the disc in its housing, the pin contacts and their clearances.

Notation, the profile and the modifications: :mod:`toothfem.geometry.cycloid` (the
pin-housing paper of Y. Wang et al., Sec. 2). This module places the disc (pin centres and
disc poses, housing frame, m and rad), gives the kinematics of every pin contact
(:func:`meshing`) and the exact initial clearance of every pin of a modified disc
(:func:`clearance_at`, :func:`clearance_exact`, m). The kinematics (crank angle phi, disc
turn -phi/Za, pitch point, the pin's angle theta_b from the line of centres):
docs/derivations.md, section C3. Distances measured on the parametric working curve:
:mod:`toothfem.geometry.cycloid_distance`; the disc before load (backlash, placement, the
first-order clearance): :mod:`toothfem.geometry.cycloid_backlash`.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import GeometryError, angles_1d, check_range, of_type
from .cycloid import CycloidGeometry, _rho_of_theta
from .cycloid_distance import modified_distance
from .kinematics import MeshingState, equivalent_radius, slide_to_roll
from .vectors import cross, perp, rotate, unit


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
        If ``geom`` is not a CycloidGeometry, ``pin_motion`` is not one of the two,
        ``crank_speed_rad_s`` is not finite, or the angles are not a scalar or 1-D.
    """
    of_type("geom", geom, CycloidGeometry, "case.cycloid.geometry() (a Case holds one)",
            error=GeometryError)
    if pin_motion not in ("fixed", "rolling"):
        raise GeometryError(f"pin_motion = {pin_motion!r} is not one of ['fixed', 'rolling']")
    check_range("crank_speed_rad_s", crank_speed_rad_s, error=GeometryError)
    phi = angles_1d("crank_angle_rad", crank_angle_rad, error=GeometryError)
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
# Exact clearances of the modified disc

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
    (:func:`~toothfem.geometry.cycloid_distance.modified_distance`) minus rz.

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
