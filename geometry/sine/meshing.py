"""Meshing of the sine gear pair over the crank angle: the planet's pose, the closest
approach of every candidate flank to the ring, the ``MeshingState`` (points, normals,
gaps, moment arms, pressure angles, sliding and rolling speeds, curvature radii), the
number of pairs in contact, and the kinematics at any chosen contact point.

Source: the sine paper (Y. Lu, L. Xu, Heliyon 10 (2024) e26300), Sec. 2; closest approach
and the kinematic conventions in docs/derivations.md, S6 and S8.

Motion (ring frame): the crank angle chi puts the planet centre at O1 = a0 u(chi) and turns
the planet by theta1 = -chi (z2 - z1)/z1; the instant centre is the pitch point
P = r2 u(chi). A counter-clockwise crank turns the planet clockwise; the output torque is
carried by the contacts with negative moment arm. Points and vectors are ``(2, ...)``
arrays, except in the ``MeshingState`` record, whose points are ``(P, C, 2)``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import GeometryError, angles_1d, check_range, of_type
from ..kinematics import MeshingState, slide_to_roll
from ..vectors import cross, dot, perp, rotate, unit
from .conjugate import (_NEWTON_MAXITER, _NEWTON_TOL, _approx_gap, _conjugate, _foot,
                        _foot_start, _normal_gap, _ring)
from .profile import ProfileParams, _curvature, _planet, profile_params

if TYPE_CHECKING:
    from .pair import SineGearPair

#: Default number of teeth taken on each side of the pitch point by :func:`meshing`
#: (2k+1 teeth, both flanks each: 2(2k+1) candidates). For the prototype the teeth beyond
#: (5th to 8th from the one nearest the pitch point) are at least 20.2 um away.
DEFAULT_CANDIDATES = 4
#: Samples per flank for the start of the closest-approach search.
_APPROACH_SAMPLES = 17
#: A Newton run of the closest approach counts as converged when its last steps sum below
#: this many times the Newton tolerance (rounding can stall it just above).
_CONVERGED_FACTOR = 1e2
#: A stationary point closer than this (rad) to a flank-window boundary is put on it, so
#: that it belongs to exactly one of the two windows that meet there.
_SNAP = 1e-10
#: Step (fraction of the window) of the check that a stationary point is a minimum.
_MIN_CHECK = 1e-2


# ---------------------------------------------------------------------------------------
# poses
def planet_pose(pair: SineGearPair, crank_angle_rad):
    """Centre and rotation of the planet at crank angles chi.

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : float or array_like of shape (P,)
        Crank angle(s) chi (rad); a scalar gives P = 1.

    Returns
    -------
    centre : numpy.ndarray, shape (2, P)
        O1 = a0 u(chi) in the ring frame (m).
    rotation : numpy.ndarray, shape (P,)
        theta1 = -chi (z2 - z1)/z1 (rad).
    """
    g = profile_params(pair)
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    return g.a0 * unit(chi), g.w * chi


def planet_rotation(pair: SineGearPair, crank_angle_rad):
    """Absolute planet rotation theta1 = -chi (z2 - z1)/z1 (the second output of
    :func:`planet_pose`, keeping the shape of its argument).

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like
        chi (rad), any shape, scalar included.

    Returns
    -------
    numpy.ndarray
        theta1 (rad), of that shape.
    """
    return np.asarray(crank_angle_rad, float) * profile_params(pair).w


def pitch_point(pair: SineGearPair, crank_angle_rad):
    """The pitch point P = r2 u(chi), the planet's instant centre in the ring frame.

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles chi (rad): P turns with the crank.

    Returns
    -------
    numpy.ndarray, shape (2, P)
        P (m).
    """
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    return pair.ring_pitch_radius_m * unit(chi)


def _placed(g: ProfileParams, chi, phi, order=2):
    """Planet point phi in the ring frame at crank chi, its d/dphi derivatives up to
    ``order``, and (last) dK/dchi, the material velocity per unit crank speed."""
    th = g.w * chi
    pd = _planet(g, phi, order)
    Rp = rotate(pd[0], th)
    K = g.a0 * unit(chi) + Rp
    V = g.a0 * perp(unit(chi)) + g.w * perp(Rp)
    return [K] + [rotate(d, th) for d in pd[1:]] + [V]


# ---------------------------------------------------------------------------------------
# closest approach of planet flanks to the ring
@dataclass(frozen=True)
class PointPair:
    """A planet point at crank angles chi and its foot on the ring (arrays of one shape S,
    points and normals (2, *S)).

    Attributes
    ----------
    crank_angle : numpy.ndarray
        chi (rad).
    phi_planet, phi_ring : numpy.ndarray
        Parameters of the planet point and of its foot on the ring (rad).
    planet_point, ring_point : numpy.ndarray, shape (2, ...)
        The two points in the ring frame (m).
    normal : numpy.ndarray, shape (2, ...)
        The ring's unit normal at the ring point, pointing into the free space (toward the
        planet).
    gap : numpy.ndarray
        Normal gap (m): positive clearance, negative overlap.
    """
    crank_angle: np.ndarray
    phi_planet: np.ndarray
    phi_ring: np.ndarray
    planet_point: np.ndarray
    ring_point: np.ndarray
    normal: np.ndarray
    gap: np.ndarray


@dataclass(frozen=True)
class Approach(PointPair):
    """Closest approach of planet flanks to the ring: the :class:`PointPair` of the closest
    points, and whether the flank has a minimum of its own.

    Where a flank has no local minimum of the gap of its own (``own`` False), the gap still
    falls beyond the flank's end, the nearest point belongs to the neighbouring flank, and
    the pair returned is the end point and its foot point.

    Attributes
    ----------
    own : numpy.ndarray of bool
        The flank has a stationary point of the gap inside its half-open window.
    """
    own: np.ndarray


def flank_window(pair_or_teeth, tooth, flank):
    """Half-open planet-parameter window [lo, hi) of a flank: flank +1 is
    [tip, tip + pi/z1), flank -1 is [tip - pi/z1, tip), tip = 2 pi tooth/z1.

    Parameters
    ----------
    pair_or_teeth : SineGearPair or int
        The pair, or its planet tooth number z1.
    tooth : array_like of int
        Planet tooth index (any integer; the tip is at 2 pi tooth/z1).
    flank : array_like of int
        -1 or +1; broadcasts with ``tooth``.

    Returns
    -------
    lo, hi : numpy.ndarray
        Window bounds (rad); windows meeting at a tip or root share the very same float.
    """
    z1 = getattr(pair_or_teeth, "planet_teeth", pair_or_teeth)
    half = math.pi / z1
    k = 2 * np.asarray(tooth) - (np.asarray(flank) < 0)   # window = [k, k+1) half-teeth
    # boundaries are half * integer, computed as in _snap, so that windows meeting at a
    # tip or root share the very same float
    return half * k, half * (k + 1)


def closest_approach(pair: SineGearPair, crank_angle_rad, tooth, flank) -> Approach:
    """Closest approach of planet tooth ``tooth``, flank ``flank``, to the ring, found on
    the parametric curves: start at the best of a few samples along the flank, then Newton
    on (phi1, phi2) for
        E1 = (K1 - X) . X' = 0   (K1 on the ring normal at X)
        E2 = K1' x X' = 0        (parallel tangents),
    whose Jacobian is regular when the relative curvature is not zero
    (docs/derivations.md, S6).

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like
        Crank angles chi (rad).
    tooth : array_like of int
        Planet tooth index (tip at 2 pi tooth/z1).
    flank : array_like of int
        -1 or +1 (see :func:`flank_window`). The three arguments broadcast together.

    Returns
    -------
    Approach
    """
    g = profile_params(pair)
    chi, tooth, flank = np.broadcast_arrays(np.asarray(crank_angle_rad, float),
                                            np.asarray(tooth), np.asarray(flank))
    lo, hi = flank_window(g.z1, tooth, flank)
    f1, f2, own = _approach(g, chi, lo, hi)
    K1 = _placed(g, chi, f1, 0)[0]
    X, X1 = _ring(g, f2, 1)[:2]
    n = perp(X1) / np.hypot(X1[0], X1[1])
    return Approach(chi, f1, f2, K1, X, n, dot(K1 - X, n), own)


def _approach(g: ProfileParams, chi, lo, hi):
    """(phi1, phi2, own) of the closest approach of flank windows [lo, hi) to the ring."""
    width = hi - lo
    t = np.linspace(0.0, 1.0, _APPROACH_SAMPLES)
    fs = lo[..., None] + width[..., None] * t
    Ks = _placed(g, chi[..., None], fs, 0)[0]
    k = np.argmin(_approx_gap(g, Ks), axis=-1)
    a1 = np.take_along_axis(fs, k[..., None], axis=-1)[..., 0]
    K0 = np.take_along_axis(Ks, k[None, ..., None], axis=-1)[..., 0]
    a2 = _foot(g, K0, _foot_start(g, K0))
    for _ in range(_NEWTON_MAXITER):
        K1, T1, T1d, _ = _placed(g, chi, a1, 2)
        X, X1, X2 = _ring(g, a2, 2)[:3]
        d = K1 - X
        e1, e2 = dot(d, X1), cross(T1, X1)
        j11, j12 = dot(T1, X1), -dot(X1, X1) + dot(d, X2)
        j21, j22 = cross(T1d, X1), cross(T1, X2)
        det = j11 * j22 - j12 * j21
        s1 = np.clip((e1 * j22 - e2 * j12) / det, -width, width)
        s2 = np.clip((j11 * e2 - j21 * e1) / det, -width, width)
        a1, a2 = a1 - s1, a2 - s2
        if np.all(np.abs(s1) + np.abs(s2) < _NEWTON_TOL):
            break
    conv = (np.isfinite(a1) & np.isfinite(a2)
            & (np.abs(s1) + np.abs(s2) < _CONVERGED_FACTOR * _NEWTON_TOL))
    a1 = np.where(conv, a1, lo)
    a2 = np.where(conv, a2, a2 * 0)
    a1 = _snap(g, a1)
    gi = _normal_gap(g, _placed(g, chi, a1, 0)[0], a2)
    step = _MIN_CHECK * width
    up = _gap_at(g, chi, a1 + step, a2)
    down = _gap_at(g, chi, a1 - step, a2)
    own = conv & (a1 >= lo) & (a1 < hi) & (up >= gi) & (down >= gi)
    # no minimum of its own: the better end of the window and its foot point
    K_lo, K_hi = _placed(g, chi, lo, 0)[0], _placed(g, chi, hi, 0)[0]
    fl2 = _foot(g, K_lo, _foot_start(g, K_lo))
    fh2 = _foot(g, K_hi, _foot_start(g, K_hi))
    use_lo = _normal_gap(g, K_lo, fl2) <= _normal_gap(g, K_hi, fh2)
    e1 = np.where(use_lo, lo, hi)
    e2 = np.where(use_lo, fl2, fh2)
    return np.where(own, a1, e1), np.where(own, a2, e2), own


def _snap(g: ProfileParams, phi):
    """Put parameters within _SNAP of a tip or root exactly on it, so that a point there
    belongs to exactly one of the two half-open flank windows that meet there."""
    half = math.pi / g.z1
    b = half * np.round(phi / half)
    return np.where(np.abs(phi - b) < _SNAP, b, phi)


def _gap_at(g, chi, f1, f2_start):
    K = _placed(g, chi, f1, 0)[0]
    return _normal_gap(g, K, _foot(g, K, f2_start))


# ---------------------------------------------------------------------------------------
# meshing state
def _candidates(g: ProfileParams, chi, k):
    """Tooth indices (P, C) and flanks (C,) of the 2k+1 teeth nearest the pitch point."""
    j0 = np.round(chi * g.z2 / (2 * math.pi)).astype(int)    # psi_P z1/(2 pi)
    offs = np.repeat(np.arange(-k, k + 1), 2)
    flank = np.tile([-1, 1], 2 * k + 1)
    return j0[:, None] + offs[None, :], flank


def _surface_speeds(V, T1, X1, t, rate1, rate2, om):
    """Sliding speed (planet minus ring surface along t; the ring is fixed) and
    entrainment speed (u1 + u2)/2, u_i the speed of the contact point along surface i
    relative to its material, from the material velocity V per unit crank speed, the
    tangents T1 = dK/dphi1, X1 = dX/dphi2 and the parameter rates (1/s)."""
    sliding = dot(V * om, t)
    u_planet = dot(T1, t) * rate1        # the contact point moves along the planet
    u_ring = dot(X1, t) * rate2
    return sliding, 0.5 * (u_planet + u_ring)


def _candidate_points(g: ProfileParams, chi, k):
    """Candidate flanks of :func:`meshing` at crank angles chi (P,): (teeth (P, C), flanks
    (C,), chi (P, C), planet and ring parameters f1, f2 (P, C), ``own`` (a local minimum of
    the gap, the conjugate contact included), ``conj`` (the column of the conjugate contact:
    its exact point from the meshing equation, gap 0))."""
    teeth, flank = _candidates(g, chi, k)
    chi2 = np.broadcast_to(chi[:, None], teeth.shape)
    lo, hi = flank_window(g.z1, teeth, flank[None, :])
    f1, f2, own = _approach(g, chi2, lo, hi)
    fs = _snap(g, _conjugate(g, chi))
    conj = (lo <= fs[:, None]) & (fs[:, None] < hi)
    if not np.all(conj.sum(axis=1) == 1):
        raise GeometryError("the conjugate contact is not among the candidates")
    f1 = np.where(conj, fs[:, None], f1)
    f2 = np.where(conj, fs[:, None], f2)
    return teeth, flank, chi2, f1, f2, own | conj, conj


def meshing(pair: SineGearPair, crank_angle_rad, crank_speed_rad_s: float = 1.0,
            candidates: int = DEFAULT_CANDIDATES) -> MeshingState:
    """Kinematics of the candidate tooth pairs at each crank angle (vectorised).

    Candidates: the 2k+1 planet teeth nearest the pitch point (k = ``candidates``), both
    flanks of each, C = 2(2k+1) columns ordered (tooth j0-k, flank -1), (j0-k, +1), ...,
    (j0+k, +1); ``contact_id`` is the planet tooth index (0..z1-1), the flank is the column
    parity (even -1, odd +1). The column holding the conjugate contact gets the exact
    contact point from the meshing equation and gap 0; the others the closest-approach pair
    of their flank (:func:`closest_approach`, on the parametric curves) and its normal gap,
    or gap = inf where the flank has no minimum of its own (the nearest point is the
    neighbouring flank's: reporting it twice would double a contact; the speeds of such a
    column are those at the flank's end, see :func:`kinematics_at` for any other point).
    ``point`` is the planet point, ``normal`` the ring normal there, pointing into the
    planet. ``pressure_angle``: between the normal and the velocity of the planet point
    about its own (fixed) axis, perpendicular to O1K (Eqs. 8-10). Velocities along
    t = k x n: ``sliding_velocity`` = planet minus ring surface (ring fixed); rolling speeds
    u_i = (velocity of the closest point along surface i - material velocity) . t,
    ``entrainment_velocity`` = (u1 + u2)/2 (the cycloid module's convention).

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles chi (rad).
    crank_speed_rad_s : float
        Crank (input) speed (rad/s); counter-clockwise positive.
    candidates : int
        k, teeth on each side of the one nearest the pitch point, 1 <= k <= (z1 - 1)//2.

    Returns
    -------
    MeshingState
        Shapes (P, C), points and normals (P, C, 2); ``drive`` "sine".

    Raises
    ------
    GeometryError
        If ``pair`` is not a SineGearPair, the crank speed is not finite, ``candidates``
        is outside [1, (z1 - 1)//2], or the angles are not a scalar or 1-D.
    """
    from .pair import SineGearPair          # at call time, as the type hints take it
    of_type("pair", pair, SineGearPair, "case.sine.geometry() (a Case holds one)",
            error=GeometryError)
    check_range("crank_speed_rad_s", crank_speed_rad_s, error=GeometryError)
    k = int(check_range("candidates", candidates, 1, (pair.planet_teeth - 1) // 2,
                        error=GeometryError))
    g = profile_params(pair)
    chi = angles_1d("crank_angle_rad", crank_angle_rad, error=GeometryError)
    om = float(crank_speed_rad_s)
    teeth, flank, chi2, f1, f2, own, conj = _candidate_points(g, chi, k)

    K1, T1, T1d, V = _placed(g, chi2, f1, 2)
    X, X1, X2 = _ring(g, f2, 2)[:3]
    n = perp(X1) / np.hypot(X1[0], X1[1])
    gap = np.where(conj, 0.0, np.where(own, dot(K1 - X, n), np.inf))
    point = np.where(conj[None], X, K1)
    centre = g.a0 * unit(chi)
    rel = point - centre[:, :, None]
    arm = cross(rel, n)
    pressure = np.arccos(np.clip(np.abs(arm) / np.hypot(rel[0], rel[1]), 0.0, 1.0))

    # rates of the closest-approach parameters: J [phi1', phi2'] = -dE/dchi * chi'
    d = K1 - X
    j11, j12 = dot(T1, X1), -dot(X1, X1) + dot(d, X2)
    j21, j22 = cross(T1d, X1), cross(T1, X2)
    e1c = dot(V, X1)
    e2c = cross(g.w * perp(T1), X1)
    det = j11 * j22 - j12 * j21
    rate1 = np.where(own, -(e1c * j22 - e2c * j12) / det * om, 0.0)
    rate2 = np.where(own, -(j11 * e2c - j21 * e1c) / det * om, -e1c / j12 * om)
    sliding, entrain = _surface_speeds(V, T1, X1, perp(n), rate1, rate2, om)

    p1, p2 = _planet(g, f1, 2)[1:]
    kp = _curvature(p1, p2)
    kr = -_curvature(X1, X2)
    with np.errstate(divide="ignore"):
        r_planet, r_ring, r_eq = 1.0 / kp, 1.0 / kr, 1.0 / (kp + kr)
    return MeshingState(
        drive="sine", position_rad=chi, contact_id=np.mod(teeth, g.z1),
        point=np.moveaxis(point, 0, -1), normal=np.moveaxis(n, 0, -1),
        centre=centre.T.copy(), moment_arm=arm, pressure_angle=pressure, gap=gap,
        sliding_velocity=sliding, entrainment_velocity=entrain,
        slide_to_roll=slide_to_roll(sliding, entrain),
        radius_moving=r_planet, radius_fixed=r_ring, equivalent_radius=r_eq,
        crank_speed_rad_s=om)


def contact_count(pair: SineGearPair, crank_angle_rad, gap_m: float,
                  candidates: int | None = None) -> np.ndarray:
    """Number of tooth pairs (planet flank / ring flank) in contact or within ``gap_m``:
    the local minima of the gap (one per flank at most, the conjugate contact included)
    not above ``gap_m``.

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like, shape (P,) or scalar
        Crank angles chi (rad); the count repeats after a crank pitch 2 pi/z2.
    gap_m : float
        Largest gap counted (m), >= 0.
    candidates : int, optional
        Teeth searched on each side of the pitch point (as in :func:`meshing`); None:
        doubled from ``DEFAULT_CANDIDATES`` until the outermost ones are farther than
        ``gap_m``.

    Returns
    -------
    numpy.ndarray of int, shape (P,)

    Raises
    ------
    GeometryError
        If ``gap_m`` is negative or not finite.
    """
    check_range("gap_m", gap_m, 0, None, error=GeometryError)
    g = profile_params(pair)
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    kmax = (g.z1 - 1) // 2
    k = min(DEFAULT_CANDIDATES if candidates is None else int(candidates), kmax)
    while True:
        teeth, flank = _candidates(g, chi, k)
        chi2 = np.broadcast_to(chi[:, None], teeth.shape)
        lo, hi = flank_window(g.z1, teeth, flank[None, :])
        f1, f2, own = _approach(g, chi2, lo, hi)
        gap = np.where(own, _normal_gap(g, _placed(g, chi2, f1, 0)[0], f2), np.inf)
        outer = np.concatenate([gap[:, :2], gap[:, -2:]], axis=1)
        if candidates is not None or np.all(outer > gap_m) or k == kmax:
            return np.sum(gap <= gap_m, axis=1)
        k = min(2 * k, kmax)


# ---------------------------------------------------------------------------------------
# kinematics at a chosen contact point
@dataclass(frozen=True)
class ContactKinematics(PointPair):
    """Kinematics with a chosen planet point taken as the contact point: the
    :class:`PointPair` of that point (arrays of the broadcast shape of the inputs) and its
    speeds, with the conventions of :func:`meshing` (velocities along t = k x n, n the ring
    normal into the planet).

    Attributes
    ----------
    sliding_velocity, entrainment_velocity, slide_to_roll : numpy.ndarray
        Planet minus ring surface speed, (u1 + u2)/2 (m/s), and their ratio.
    """
    sliding_velocity: np.ndarray
    entrainment_velocity: np.ndarray
    slide_to_roll: np.ndarray


def kinematics_at(pair: SineGearPair, crank_angle_rad, phi, crank_speed_rad_s: float = 1.0,
                  phi_rate=0.0) -> ContactKinematics:
    """Sliding and entrainment speeds with planet point ``phi`` as the contact point, for
    contacts that are not at a gap minimum (an FE contact on a loaded flank whose gap has
    no minimum of its own, where :func:`meshing` reports the flank's end).

    The planet side is the point itself, moving along the planet at ``phi_rate`` per unit
    crank angle; the ring side is its foot point, whose parameter rate follows from
    differentiating the foot-point condition (K - X) . X' = 0 over the crank angle:
    phi2' = -(V + K' phi_rate) . X' / (-X'.X' + (K - X) . X''), V the planet's material
    velocity per unit crank speed. The sliding speed does not depend on ``phi_rate``.
    With ``phi_rate`` 0 (the default: the contact stays at one point of the planet, as at
    a tip or a flank end) this is :func:`meshing`'s column without a minimum of its own;
    with the rate of the conjugate contact, (z2/z1)/psi'(phi), it is the conjugate column.

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : array_like
        Crank angles chi (rad).
    phi : array_like
        Planet parameter of the contact point (rad); broadcasts with the crank angles.
    crank_speed_rad_s : float
        Crank speed (rad/s).
    phi_rate : array_like
        d phi/d chi of the contact point along the planet (-); broadcasts.

    Returns
    -------
    ContactKinematics

    Raises
    ------
    GeometryError
        If the crank speed is not finite.
    """
    check_range("crank_speed_rad_s", crank_speed_rad_s, error=GeometryError)
    g = profile_params(pair)
    chi, f1, rate = np.broadcast_arrays(np.asarray(crank_angle_rad, float),
                                        np.asarray(phi, float), np.asarray(phi_rate, float))
    om = float(crank_speed_rad_s)
    K1, T1, V = _placed(g, chi, f1, 1)
    f2 = _foot(g, K1, _foot_start(g, K1))
    X, X1, X2 = _ring(g, f2, 2)[:3]
    n = perp(X1) / np.hypot(X1[0], X1[1])
    d = K1 - X
    j12 = -dot(X1, X1) + dot(d, X2)
    rate2 = -(dot(V, X1) + dot(T1, X1) * rate) / j12 * om
    sliding, entrain = _surface_speeds(V, T1, X1, perp(n), rate * om, rate2, om)
    return ContactKinematics(chi, f1, f2, K1, X, n, dot(d, n), sliding, entrain,
                             slide_to_roll(sliding, entrain))
