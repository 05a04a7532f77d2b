"""The ring of the sine gear pair as the envelope of the planet's positions: the meshing
equation, the ring profile, the conjugate contact over the crank angle and its pressure
angles (with the paper's closed forms, Eqs. 8-14), and foot points on the ring.

Source: the sine paper (Y. Lu, L. Xu, Heliyon 10 (2024) e26300), Eq. (2) and Sec. 2;
derivations and corrections in docs/derivations.md, S4 (envelope), S6 (foot points) and
S9 (pressure angles, the correction of Eq. 14).

Motion (ring frame, ring centre at the origin): the crank (input) angle chi puts the planet
centre at O1 = a0 u(chi) and turns the planet by theta1 = -chi (z2 - z1)/z1 (the pitch
circles roll without slip; the planet's instant centre is the pitch point P = r2 u(chi)).

Ring profile: the envelope of the planet's positions (not the raw family of Eq. 2). A
planet point is in contact when its normal passes through P (meshing equation); seen from
the planet, P sits on the planet's pitch circle at angle psi = chi z2/z1. The normal at
p(phi) meets the pitch circle (nearer intersection) at

    psi(phi) = phi - beta + arcsin((r/r1) sin beta),   tan beta = r'/r,

so that point is in contact at chi(phi) = psi(phi) z1/z2, and the ring point it generates is
X(phi) = O1(chi) + R(theta1(chi)) p(phi). The ring is parametrised by the same phi:
X(phi + 2 pi/z1) is X(phi) turned by 2 pi/z2, so phi in [0, 2 pi z2/z1) is the whole ring.
Points and vectors are ``(2, ...)`` arrays.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from ..vectors import cross, dot, perp, rotate, unit
from .profile import (ProfileCurve, ProfileParams, _curvature, _planet, _radius,
                      profile_params)

if TYPE_CHECKING:
    from .pair import SineGearPair

#: Newton: tolerance on parameter steps (rad; rounding leaves steps of ~1e-14) and
#: iteration limit (foot points here, closest approach in meshing.py).
_NEWTON_TOL = 1e-12
_NEWTON_MAXITER = 30
#: Points per ring tooth in the radius / parameter tables (start values, interference).
_TABLE_POINTS = 1025
#: Bisection for the conjugate contact: iteration limit and the bracket width (rad) at
#: which a Newton polish takes over (quadratic: one step from 1e-9 rad reaches rounding,
#: three for margin).
_CONJ_BISECT_MAXITER = 60
_CONJ_BISECT_TOL = 1e-9
_CONJ_NEWTON_STEPS = 3
#: Samples over one planet tooth for the bracket of the conjugate search.
_DEVIATION_SAMPLES = 4097


# ---------------------------------------------------------------------------------------
# meshing equation and ring profile (envelope)
def _psi(g: ProfileParams, phi, order=0):
    """Planet-frame angle psi of the pitch point at which p(phi) is in contact, and its
    derivatives (order <= 2). Closed form for psi; implicit differentiation of the meshing
    equation G = (p - P1(psi)) . p' = 0, P1 = r1 u(psi), for the derivatives."""
    pd = _planet(g, phi, order + 1)
    p, p1 = pd[0], pd[1]
    r = np.hypot(p[0], p[1])
    rp = dot(p, p1) / r
    beta = np.arctan2(rp, r)
    psi = phi - beta + np.arcsin(r * np.sin(beta) / g.r1)
    if order == 0:
        return (psi,)
    P1 = g.r1 * unit(psi)
    P1d = perp(P1)
    gpsi = -dot(P1d, p1)
    gphi = dot(p1, p1) + dot(p - P1, pd[2])
    psid = -gphi / gpsi
    if order == 1:
        return psi, psid
    gff = 3 * dot(p1, pd[2]) + dot(p - P1, pd[3])
    gfs = -dot(P1d, pd[2])
    gss = dot(P1, p1)
    psidd = -(gff + 2 * gfs * psid + gss * psid**2) / gpsi
    return psi, psid, psidd


def pitch_point_angle(pair: SineGearPair, phi):
    """psi(phi): planet-frame angle of the pitch point when p(phi) is in contact.

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like
        Planet parameter of the point in contact (rad), any shape.

    Returns
    -------
    numpy.ndarray
        psi (rad), the shape of ``phi``; psi(phi + 2 pi/z1) = psi(phi) + 2 pi/z1.
    """
    return _psi(profile_params(pair), np.asarray(phi, float))[0]


def contact_crank_angle(pair: SineGearPair, phi):
    """chi(phi) = psi(phi) z1/z2: crank angle at which planet point phi is in contact.

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like, shape (...)
        Planet parameter (rad).

    Returns
    -------
    numpy.ndarray, shape (...)
        Crank angle chi (rad).
    """
    g = profile_params(pair)
    return _psi(g, np.asarray(phi, float))[0] * g.z1 / g.z2


def _ring(g: ProfileParams, phi, order=2):
    """Ring point X(phi) and derivatives (ring frame), plus chi(phi) and chi'(phi)."""
    psi, psid, psidd = _psi(g, phi, 2)
    k = g.z1 / g.z2
    chi, chid, chidd = k * psi, k * psid, k * psidd
    p, p1, p2 = _planet(g, phi, 2)
    th = g.w * chi
    Rp, Rp1, Rp2 = rotate(p, th), rotate(p1, th), rotate(p2, th)
    e = unit(chi)
    f = perp(e)
    X = g.a0 * e + Rp
    Xc = g.a0 * f + g.w * perp(Rp)               # dX/dchi at fixed phi
    X1 = Xc * chid + Rp1
    if order < 2:
        return X, X1, None, chi, chid
    Xcc = -g.a0 * e - g.w**2 * Rp
    X2 = Xcc * chid**2 + 2 * g.w * perp(Rp1) * chid + Xc * chidd + Rp2
    return X, X1, X2, chi, chid


def ring_profile(pair: SineGearPair, phi) -> np.ndarray:
    """Ring profile points in the ring frame, parametrised by the planet parameter of the
    generating point.

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like, shape (...)
        Planet parameter of the generating point (rad); [0, 2 pi z2/z1) covers the whole
        ring.

    Returns
    -------
    numpy.ndarray, shape (2, ...)
        Points X(phi) (m).
    """
    return _ring(profile_params(pair), np.asarray(phi, float), 1)[0]


def ring_curve(pair: SineGearPair, phi) -> ProfileCurve:
    """Ring profile with analytic first/second derivatives and curvature, and the crank
    angle of each point.

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like, shape (N,)
        Planet parameter of the generating point (rad).

    Returns
    -------
    ProfileCurve
        ``curvature`` positive where the ring tooth is convex toward the planet;
        ``crank_angle`` chi(phi).
    """
    phi = np.asarray(phi, float)
    X, X1, X2, chi, _ = _ring(profile_params(pair), phi, 2)
    return ProfileCurve(phi, X, X1, X2, -_curvature(X1, X2), chi)


# ---------------------------------------------------------------------------------------
# tables of the ring: radius and parameter versus polar angle over one ring tooth
@lru_cache(maxsize=32)
def _ring_table(g: ProfileParams):
    from scipy.interpolate import CubicSpline

    phi = np.linspace(-math.pi / g.z1, math.pi / g.z1, _TABLE_POINTS)
    X = _ring(g, phi, 1)[0]
    gam = np.arctan2(X[1], X[0])
    gam[0], gam[-1] = -math.pi / g.z2, math.pi / g.z2    # exact by symmetry
    rad = np.hypot(X[0], X[1])
    rad[-1] = rad[0]
    return gam, phi, CubicSpline(gam, rad, bc_type="periodic")


def _ring_radius_at(g: ProfileParams, gamma):
    """Ring radius at polar angle gamma (star-shaped ring; spline error < 2e-15 m for the
    prototype, measured on 1e5 points)."""
    _, _, spl = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    gb = gamma - pitch * np.round(gamma / pitch)
    return spl(gb)


def _approx_gap(g: ProfileParams, K):
    """Normal gap of points K (2, ...) from the ring to first order: radial clearance
    times the cosine of the ring normal's angle to the radius (start values only)."""
    _, _, spl = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    gam = np.arctan2(K[1], K[0])
    gb = gam - pitch * np.round(gam / pitch)
    rad, drad = spl(gb), spl(gb, 1)
    return (rad - np.hypot(K[0], K[1])) * rad / np.hypot(rad, drad)


def _ring_param_at(g: ProfileParams, gamma):
    """Start value of the ring parameter whose point has polar angle gamma."""
    gam, phi, _ = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    n = np.round(gamma / pitch)
    return np.interp(gamma - n * pitch, gam, phi) + n * 2 * math.pi / g.z1


# ---------------------------------------------------------------------------------------
# conjugate contact
def conjugate_contact(pair: SineGearPair, crank_angle_rad):
    """Planet parameter of the conjugate contact at each crank angle: the root phi* of
    psi(phi) = chi z2/z1 (psi is increasing; bracketed bisection, Newton polish).

    Parameters
    ----------
    pair : SineGearPair
    crank_angle_rad : float or array_like of shape (P,)
        Crank angles chi (rad), not reduced to a pitch: phi* grows by 2 pi z2/z1 per turn.

    Returns
    -------
    numpy.ndarray, shape (P,)
        phi* (rad).
    """
    return _conjugate(profile_params(pair),
                      np.atleast_1d(np.asarray(crank_angle_rad, float)))


def _conjugate(g: ProfileParams, chi):
    target = chi * g.z2 / g.z1
    dev = _psi_deviation(g)
    lo, hi = target - dev, target + dev
    for _ in range(_CONJ_BISECT_MAXITER):
        mid = 0.5 * (lo + hi)
        below = _psi(g, mid)[0] < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        if np.max(hi - lo) < _CONJ_BISECT_TOL:
            break
    phi = 0.5 * (lo + hi)
    for _ in range(_CONJ_NEWTON_STEPS):
        psi, psid = _psi(g, phi, 1)
        phi = phi - (psi - target) / psid
    return phi


@lru_cache(maxsize=32)
def _psi_deviation(g: ProfileParams) -> float:
    """Bracket half-width for the conjugate search: max |psi - phi| times 1.5 plus 1e-9
    rad (margin beyond the sampled maximum)."""
    phi = np.linspace(-math.pi / g.z1, math.pi / g.z1, _DEVIATION_SAMPLES)
    return float(np.max(np.abs(_psi(g, phi)[0] - phi))) * 1.5 + 1e-9


# ---------------------------------------------------------------------------------------
# foot points on the ring
def _normal_gap(g: ProfileParams, K, f2):
    """Signed distance of K from the ring's tangent at ring parameter f2 (positive in the
    free space)."""
    X, X1 = _ring(g, f2, 1)[:2]
    return dot(K - X, perp(X1)) / np.hypot(X1[0], X1[1])


def _foot(g: ProfileParams, K, f2):
    """Ring parameter of the foot of the perpendicular from K (Newton from f2)."""
    f2 = np.array(f2, float, copy=True)
    for _ in range(_NEWTON_MAXITER):
        X, X1, X2 = _ring(g, f2, 2)[:3]
        d = K - X
        step = dot(d, X1) / (-dot(X1, X1) + dot(d, X2))
        f2 = f2 - step
        if np.all(np.abs(step) < _NEWTON_TOL):
            break
    return f2


def _foot_start(g: ProfileParams, K):
    """Start value of the foot-point Newton: the ring parameter at K's polar angle."""
    return _ring_param_at(g, np.arctan2(K[1], K[0]))


def foot_point(pair: SineGearPair, points, phi_start=None):
    """Foot of the perpendicular from ring-frame points on the ring profile, found on the
    parametric curve: Newton on (K - X(phi)) . X'(phi) = 0 (docs/derivations.md, S6).

    Parameters
    ----------
    pair : SineGearPair
    points : array_like, shape (2, ...)
        Points K in the ring frame (m).
    phi_start : array_like, shape (...), optional
        Start values of the ring parameter; by default the parameter of the ring point at
        K's polar angle (interpolated in a table over one ring tooth), the start every
        foot point of this package uses.

    Returns
    -------
    phi_ring : numpy.ndarray, shape (...)
        Ring parameter of the foot point (rad; ``ring_profile(pair, phi_ring)`` is it).
    gap : numpy.ndarray, shape (...)
        Signed normal distance (m): positive in the free space inside the ring, negative
        inside the ring's material.
    """
    g = profile_params(pair)
    K = np.asarray(points, float)
    start = _foot_start(g, K) if phi_start is None else phi_start
    f2 = _foot(g, K, start)
    return f2, _normal_gap(g, K, f2)


def distance_to_ring(pair: SineGearPair, points) -> np.ndarray:
    """Signed normal distance of ring-frame points from the ring profile (the ``gap`` of
    :func:`foot_point`).

    Parameters
    ----------
    pair : SineGearPair
    points : array_like, shape (2, ...)
        Points in the ring frame (m).

    Returns
    -------
    numpy.ndarray, shape (...)
        Distance (m), positive in the free space inside the ring, negative inside the
        ring's material.
    """
    return foot_point(pair, points)[1]


# ---------------------------------------------------------------------------------------
# pressure angles: numerical and the sine paper's closed forms (Eqs. 8-14)
def pressure_angles(pair: SineGearPair, phi):
    """Numerical pressure angles at the conjugate contact of planet point phi: acute
    angles between the contact normal and the velocity of K as a point of the planet
    turning about O1 (perpendicular to O1K), resp. of the ring turning about O2
    (perpendicular to O2K) - the fixed-axis (carrier) frame of the paper's Fig. 2.

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like, shape (...)
        Planet parameter of the contact (rad).

    Returns
    -------
    alpha_k1, alpha_k2 : numpy.ndarray, shape (...)
        Planet and ring pressure angles (rad).
    """
    g = profile_params(pair)
    phi = np.asarray(phi, float)
    X, X1, _, chi, _ = _ring(g, phi, 1)
    n = perp(X1) / np.hypot(X1[0], X1[1])
    rel1 = X - g.a0 * unit(chi)
    a1 = np.arccos(np.clip(np.abs(cross(rel1, n)) / np.hypot(rel1[0], rel1[1]), 0, 1))
    a2 = np.arccos(np.clip(np.abs(cross(X, n)) / np.hypot(X[0], X[1]), 0, 1))
    return a1, a2


@dataclass(frozen=True)
class SeedPressureAngles:
    """The sine paper's Eqs. (8)-(14) at planet points phi (arrays of phi's shape)."""
    alpha_k1: np.ndarray           # Eq. (8) with (9), (10)
    r_k1: np.ndarray               # Eq. (11)
    r_k2: np.ndarray               # Eq. (12)
    zeta: np.ndarray               # Eq. (13), "a cos" read as arccos
    alpha_k2_printed: np.ndarray   # Eq. (14) as printed: alpha_k1 - zeta
    alpha_k2: np.ndarray           # Eq. (14) corrected: alpha_k1 - s zeta (docs S9)
    sign: np.ndarray               # s: +1 where the angle O1-K-P is acute, else -1


def seed_pressure_angles(pair: SineGearPair, phi) -> SeedPressureAngles:
    """The sine paper's closed forms for the pressure angles at the conjugate contact of
    p(phi).

    Eq. (8)-(10): alpha_k1 = atan|(k_n - k_v)/(1 + k_n k_v)|, k_v = -x/y, k_n = -dx/dy in
    the paper's planet frame (x, y) = r(phi) (sin phi, cos phi); evaluated multiplied
    through by y dy, tan alpha_k1 = |x y' - y x'| / |x x' + y y'|, which is the same
    number without infinite slopes. Eq. (11) r_k1 = r(phi); Eq. (12) r_k2 = |O2 K| from
    the ring-frame contact point; Eq. (13) zeta = arccos((r_k1^2 + r_k2^2 - a0^2) /
    (2 r_k1 r_k2)); Eq. (14) alpha_k2 = alpha_k1 - zeta as printed holds only where the
    angle O1-K-P is acute (s = +1: K beyond the planet's pitch circle, on the addendum,
    apart from a sliver); elsewhere alpha_k2 = alpha_k1 + zeta (docs/derivations.md, S9).

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like
        Planet parameter of the contact, p(phi) (rad); every field has its shape.

    Returns
    -------
    SeedPressureAngles
    """
    g = profile_params(pair)
    phi = np.asarray(phi, float)
    r, rp = _radius(g, phi)[:2]
    x, y = r * np.sin(phi), r * np.cos(phi)
    dx, dy = rp * np.sin(phi) + r * np.cos(phi), rp * np.cos(phi) - r * np.sin(phi)
    alpha1 = np.arctan2(np.abs(x * dy - y * dx), np.abs(x * dx + y * dy))
    X, _, _, chi, _ = _ring(g, phi, 1)
    rk2 = np.hypot(X[0], X[1])
    zeta = np.arccos(np.clip((r**2 + rk2**2 - g.a0**2) / (2 * r * rk2), -1.0, 1.0))
    # s = +1 where the angle O1-K-P is acute (docs S9)
    P = g.r2 * unit(chi)
    s = np.where(dot(P - X, g.a0 * unit(chi) - X) > 0, 1.0, -1.0)
    return SeedPressureAngles(alpha1, r, rk2, zeta, alpha1 - zeta, alpha1 - s * zeta, s)
