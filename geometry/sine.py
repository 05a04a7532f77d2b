"""Sine gear pair with a small tooth difference: planet profile, conjugate ring profile and
meshing kinematics over the crank angle.

Source: Y. Lu, L. Xu, Heliyon 10 (2024) e26300 (seeds/sine-profile-reducer-efficiency.txt),
Sec. 2; the corrections and numerical checks are in docs/derivations.md, section 3 (S1-S9).

Notation (SI): planet with z1 teeth, pitch radius r1 = m z1/2; fixed ring with z2 >= z1 + 1
teeth, r2 = m z2/2; centre distance a0 = r2 - r1; tooth height (sine amplitude) a.

Planet profile (planet frame, centre at the origin), paper Eq. (1) written with
counter-clockwise angles from the x-axis, u(phi) = (cos phi, sin phi) instead of the
paper's (sin phi, cos phi). That is the mirror image in the line x = y; the profile is
symmetric (r(-phi) = r(phi)), so the shape is the same:

    p(phi) = r(phi) u(phi),   r(phi) = a cos(z1 phi) + sqrt(r1^2 - a^2 sin^2(z1 phi))

Tooth j of the planet has its tip at phi = 2 pi j / z1; its flank -1 is the half-open
window phi in [tip - pi/z1, tip), its flank +1 is [tip, tip + pi/z1).

Motion (ring frame, ring centre at the origin): the crank (input) angle chi puts the planet
centre at O1 = a0 u(chi) and turns the planet by theta1 = -chi (z2 - z1)/z1 (the pitch
circles roll without slip; the planet's instant centre is the pitch point P = r2 u(chi)).

Ring profile: the envelope of the planet's positions. A planet point is in contact when its
normal passes through P (meshing equation); seen from the planet, P sits on the planet's
pitch circle at angle psi = chi z2/z1. The normal at p(phi) meets the pitch circle (nearer
intersection) at

    psi(phi) = phi - beta + arcsin((r/r1) sin beta),   tan beta = r'/r,

so that point is in contact at chi(phi) = psi(phi) z1/z2, and the ring point it generates is
X(phi) = O1(chi) + R(theta1(chi)) p(phi). The ring is parametrised by the same phi:
X(phi + 2 pi/z1) is X(phi) turned by 2 pi/z2, so phi in [0, 2 pi z2/z1) is the whole ring.

Curvatures are signed positive where the surface is convex toward the mating gear (the
planet's tooth tips, the ring's tooth tips), as in :class:`MeshingState`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

import numpy as np

from ..errors import GeometryError, check_range
from .kinematics import MeshingState, slide_to_roll

#: Fewest planet teeth accepted (the case model's range starts there too).
MIN_PLANET_TEETH = 10
#: Default number of teeth taken on each side of the pitch point by :func:`meshing`
#: (2k+1 teeth, both flanks each: 2(2k+1) candidates). For the prototype the teeth beyond
#: (5th to 8th from the one nearest the pitch point) are at least 20.2 um away.
DEFAULT_CANDIDATES = 4
#: Samples per half tooth used by the validity predicates (bounds on a).
_PRED_SAMPLES = 2049
#: Crank positions per tooth pitch and planet samples per tooth in the interference check.
_INTERF_CRANKS = 24
_INTERF_SAMPLES = 32
#: Radial overlap (m) above which planet and ring are said to interfere; the ring radius is
#: interpolated with a periodic cubic spline whose error is ~a (2 pi/1024)^4 < 2e-15 m for
#: the prototype (docs S7).
_INTERF_TOL = 1e-11
#: Bisection on a stops at this relative width.
_BOUND_RTOL = 1e-9
#: Newton: tolerance on parameter steps (rad; rounding leaves steps of ~1e-14) and
#: iteration limit.
_NEWTON_TOL = 1e-12
_NEWTON_MAXITER = 30
#: Samples per flank for the start of the closest-approach search.
_APPROACH_SAMPLES = 17
#: Points per ring tooth in the radius / parameter tables (start values, interference).
_TABLE_POINTS = 1025
#: A stationary point closer than this (rad) to a flank-window boundary is put on it, so
#: that it belongs to exactly one of the two windows that meet there.
_SNAP = 1e-10
#: Step (fraction of the window) of the check that a stationary point is a minimum.
_MIN_CHECK = 1e-2


# ---------------------------------------------------------------------------------------
# small vector helpers: vectors are stacked on the first axis, shape (2, ...)
def _u(a):
    return np.stack([np.cos(a), np.sin(a)])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _perp(v):
    """k x v: v turned counter-clockwise by 90 degrees."""
    return np.stack([-v[1], v[0]])


def _rot(theta, v):
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SineGearPair:
    """Planet (external sine gear) inside a fixed ring (its conjugate), SI units.

    Refused (GeometryError naming the parameter, its value and the bound): non-integer or
    too few teeth, ring_teeth <= planet_teeth, module or face width <= 0, tooth height
    outside (0, r1) (Eq. 1 needs a < r1), and tooth heights for which the conjugate ring is
    cusped or self-intersecting, the contact path reverses on the planet, or the planet
    interferes with the ring somewhere on its circumference (bounds from
    :func:`tooth_height_limits`).
    """
    planet_teeth: int
    ring_teeth: int
    module_m: float
    tooth_height_m: float
    face_width_m: float

    def __post_init__(self):
        z1 = _teeth("planet_teeth", self.planet_teeth, MIN_PLANET_TEETH,
                    "fewer teeth are outside the tested range")
        _teeth("ring_teeth", self.ring_teeth, z1 + 1,
               "the ring needs at least one tooth more than the planet (z2 - z1 >= 1)")
        m = check_range("module_m", self.module_m, 0, None, lo_open=True, error=GeometryError)
        check_range("face_width_m", self.face_width_m, 0, None, lo_open=True,
                    error=GeometryError)
        r1 = m * z1 / 2
        a = check_range("tooth_height_m", self.tooth_height_m, 0, r1, lo_open=True,
                        hi_open=True, error=GeometryError,
                        why="Eq. 1 needs a < r1 (planet pitch radius)")
        g = _Params(int(z1), int(self.ring_teeth), float(m), float(a))
        for rule in _RULES:
            if not rule.holds(g):
                # the bound is the bisection's; min() keeps the refusal should the scan
                # and the direct check ever disagree at the very edge
                bound = min(rule.bound(g.z1, g.z2, g.m), a)
                check_range("tooth_height_m", a, 0, bound, lo_open=True, hi_open=True,
                            error=GeometryError, why=rule.why)

    @property
    def planet_pitch_radius_m(self) -> float:
        return self.module_m * self.planet_teeth / 2

    @property
    def ring_pitch_radius_m(self) -> float:
        return self.module_m * self.ring_teeth / 2

    @property
    def centre_distance_m(self) -> float:
        """a0 = r2 - r1 = m (z2 - z1)/2."""
        return self.module_m * (self.ring_teeth - self.planet_teeth) / 2

    @property
    def tooth_difference(self) -> int:
        return self.ring_teeth - self.planet_teeth

    @property
    def crank_pitch_rad(self) -> float:
        """Crank angle 2 pi/z2 after which the mesh repeats (turned by 2 pi/z2, with the
        planet tooth index advanced by one)."""
        return 2 * math.pi / self.ring_teeth


def _teeth(name, z, lo, why):
    try:
        integral = not isinstance(z, bool) and float(z) == int(z)
    except (TypeError, ValueError, OverflowError):
        integral = False
    if not integral:
        raise GeometryError(f"{name} = {z!r} must be an integer")
    return int(check_range(name, z, lo, None, error=GeometryError, why=why))


@dataclass(frozen=True)
class _Params:
    """The numbers the formulas need (hashable, so tables can be cached per geometry)."""
    z1: int
    z2: int
    m: float
    a: float

    @property
    def r1(self):
        return self.m * self.z1 / 2

    @property
    def r2(self):
        return self.m * self.z2 / 2

    @property
    def a0(self):
        return self.m * (self.z2 - self.z1) / 2

    @property
    def w(self):
        """Planet angular velocity per unit crank speed, -(z2 - z1)/z1."""
        return -(self.z2 - self.z1) / self.z1


def _params(pair: SineGearPair) -> _Params:
    return _Params(int(pair.planet_teeth), int(pair.ring_teeth), float(pair.module_m),
                   float(pair.tooth_height_m))


# ---------------------------------------------------------------------------------------
# planet profile (Eq. 1) and its derivatives
def _radius(g: _Params, phi):
    """r(phi) and its first three derivatives (Eq. 1 / Eq. 11), analytic."""
    z, a = g.z1, g.a
    u = z * phi
    s, c = np.sin(u), np.cos(u)
    s2, c2 = np.sin(2 * u), np.cos(2 * u)
    S = g.r1**2 - (a * s) ** 2                        # under the root
    S1 = -a * a * z * s2
    S2 = -2 * a * a * z * z * c2
    S3 = 4 * a * a * z**3 * s2
    w = np.sqrt(S)
    w1 = S1 / (2 * w)
    w2 = S2 / (2 * w) - S1**2 / (4 * w**3)
    w3 = S3 / (2 * w) - 3 * S1 * S2 / (4 * w**3) + 3 * S1**3 / (8 * w**5)
    return (a * c + w, -a * z * s + w1, -a * z * z * c + w2, a * z**3 * s + w3)


def _planet(g: _Params, phi, order=2):
    """p and its derivatives d^k p/dphi^k, k <= order (<= 3), each (2, ...)."""
    r, r1, r2, r3 = _radius(g, phi)
    e, f = _u(phi), _u(phi + math.pi / 2)
    out = [r * e, r1 * e + r * f, (r2 - r) * e + 2 * r1 * f,
           (r3 - 3 * r1) * e + (3 * r2 - r) * f]
    return out[:order + 1]


def _curvature(d1, d2):
    """Standard signed curvature (x'y'' - y'x'')/|p'|^3 (positive turning left)."""
    return _cross(d1, d2) / np.hypot(d1[0], d1[1]) ** 3


def curvature_eq6(d1, d2):
    """Paper Eq. (6) as printed: K = (x''y' - x'y'')/(x'^2 + y'^2)^(3/2).

    ``d1``, ``d2``: first and second derivatives (2, ...). This is minus the standard
    signed curvature; evaluated on the paper's clockwise parametrisation
    (x, y) = r (sin, cos) it is positive on convex parts and equals the convex-positive
    ``curvature`` of :func:`planet_curve` (docs S3).
    """
    d1, d2 = np.asarray(d1, float), np.asarray(d2, float)
    return -_curvature(d1, d2)


@dataclass(frozen=True)
class ProfileCurve:
    """A parametric profile sampled at ``phi`` (N,): points and derivatives (2, N).

    ``curvature``: signed, positive where the surface is convex toward the mating gear.
    ``crank_angle``: (ring only) the crank angle chi(phi) at which the point is in contact.
    """
    phi: np.ndarray
    point: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    curvature: np.ndarray
    crank_angle: np.ndarray | None = None

    @property
    def radius(self) -> np.ndarray:
        """Signed curvature radius (inf at inflection points)."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.curvature


def planet_profile(pair: SineGearPair, phi) -> np.ndarray:
    """Planet profile points (2, N) in the planet frame, Eq. (1) (counter-clockwise)."""
    return _planet(_params(pair), np.asarray(phi, float), 0)[0]


def planet_curve(pair: SineGearPair, phi) -> ProfileCurve:
    """Planet profile with analytic derivatives and curvature (Eq. 6, positive convex)."""
    phi = np.asarray(phi, float)
    p, d1, d2 = _planet(_params(pair), phi, 2)
    return ProfileCurve(phi, p, d1, d2, _curvature(d1, d2))


# ---------------------------------------------------------------------------------------
# meshing equation and ring profile (envelope)
def _psi(g: _Params, phi, order=0):
    """Planet-frame angle psi of the pitch point at which p(phi) is in contact, and its
    derivatives (order <= 2). Closed form for psi; implicit differentiation of the meshing
    equation G = (p - P1(psi)) . p' = 0, P1 = r1 u(psi), for the derivatives."""
    pd = _planet(g, phi, order + 1)
    p, p1 = pd[0], pd[1]
    r = np.hypot(p[0], p[1])
    rp = _dot(p, p1) / r
    beta = np.arctan2(rp, r)
    psi = phi - beta + np.arcsin(r * np.sin(beta) / g.r1)
    if order == 0:
        return (psi,)
    P1 = g.r1 * _u(psi)
    P1d = _perp(P1)
    gpsi = -_dot(P1d, p1)
    gphi = _dot(p1, p1) + _dot(p - P1, pd[2])
    psid = -gphi / gpsi
    if order == 1:
        return psi, psid
    gff = 3 * _dot(p1, pd[2]) + _dot(p - P1, pd[3])
    gfs = -_dot(P1d, pd[2])
    gss = _dot(P1, p1)
    psidd = -(gff + 2 * gfs * psid + gss * psid**2) / gpsi
    return psi, psid, psidd


def pitch_point_angle(pair: SineGearPair, phi):
    """psi(phi): planet-frame angle of the pitch point when p(phi) is in contact."""
    return _psi(_params(pair), np.asarray(phi, float))[0]


def contact_crank_angle(pair: SineGearPair, phi):
    """chi(phi) = psi(phi) z1/z2: crank angle at which planet point phi is in contact."""
    g = _params(pair)
    return _psi(g, np.asarray(phi, float))[0] * g.z1 / g.z2


def _ring(g: _Params, phi, order=2):
    """Ring point X(phi) and derivatives (ring frame), plus chi(phi) and chi'(phi)."""
    psi, psid, psidd = _psi(g, phi, 2)
    k = g.z1 / g.z2
    chi, chid, chidd = k * psi, k * psid, k * psidd
    p, p1, p2 = _planet(g, phi, 2)
    th = g.w * chi
    Rp, Rp1, Rp2 = _rot(th, p), _rot(th, p1), _rot(th, p2)
    e = _u(chi)
    f = _perp(e)
    X = g.a0 * e + Rp
    Xc = g.a0 * f + g.w * _perp(Rp)               # dX/dchi at fixed phi
    X1 = Xc * chid + Rp1
    if order < 2:
        return X, X1, None, chi, chid
    Xcc = -g.a0 * e - g.w**2 * Rp
    X2 = Xcc * chid**2 + 2 * g.w * _perp(Rp1) * chid + Xc * chidd + Rp2
    return X, X1, X2, chi, chid


def ring_profile(pair: SineGearPair, phi) -> np.ndarray:
    """Ring profile points (2, N) in the ring frame, parametrised by the planet parameter
    phi of the generating point (phi in [0, 2 pi z2/z1) covers the whole ring)."""
    return _ring(_params(pair), np.asarray(phi, float), 1)[0]


def ring_curve(pair: SineGearPair, phi) -> ProfileCurve:
    """Ring profile with analytic first/second derivatives and curvature (positive where
    the ring tooth is convex toward the planet), and the crank angle of each point."""
    phi = np.asarray(phi, float)
    X, X1, X2, chi, _ = _ring(_params(pair), phi, 2)
    return ProfileCurve(phi, X, X1, X2, -_curvature(X1, X2), chi)


# ---------------------------------------------------------------------------------------
# poses and polygons
def planet_pose(pair: SineGearPair, crank_angle_rad):
    """(centre (2, P), rotation theta1 (P,)) of the planet for crank angles chi."""
    g = _params(pair)
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    return g.a0 * _u(chi), g.w * chi


def planet_rotation(pair: SineGearPair, crank_angle_rad):
    """Absolute planet rotation theta1 = -chi (z2 - z1)/z1 (rad)."""
    return np.asarray(crank_angle_rad, float) * _params(pair).w


def pitch_point(pair: SineGearPair, crank_angle_rad):
    """P = r2 u(chi), (2, P): the planet's instant centre in the ring frame."""
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    return pair.ring_pitch_radius_m * _u(chi)


def planet_polygon(pair: SineGearPair, points_per_tooth: int = 64, crank_angle_rad=None):
    """Planet as a shapely Polygon, in its own frame (centre at the origin) or, given a
    crank angle, placed in the ring frame."""
    from shapely.geometry import Polygon

    phi = np.linspace(0, 2 * math.pi, pair.planet_teeth * int(points_per_tooth),
                      endpoint=False)
    p = planet_profile(pair, phi)
    if crank_angle_rad is not None:
        centre, th = planet_pose(pair, float(crank_angle_rad))
        p = _rot(th[0], p) + centre
    return Polygon(p.T)


def ring_polygon(pair: SineGearPair, outer_radius_m: float | None = None,
                 points_per_tooth: int = 64):
    """Ring gear as a shapely annulus: outer circle of ``outer_radius_m`` (default r2 + 5 m)
    with the tooth profile as the hole; ring centre at the origin."""
    from shapely.geometry import Polygon

    g = _params(pair)
    ro = g.r2 + 5 * g.m if outer_radius_m is None else float(outer_radius_m)
    check_range("outer_radius_m", ro, g.r2 + g.a, None, lo_open=True, error=GeometryError,
                why="the rim must lie outside the ring's tooth spaces (r2 + a)")
    n = int(points_per_tooth)
    phi = np.linspace(0, 2 * math.pi * g.z2 / g.z1, g.z2 * n, endpoint=False)
    hole = ring_profile(pair, phi)
    t = np.linspace(0, 2 * math.pi, max(720, 4 * g.z2), endpoint=False)
    return Polygon(ro * _u(t).T, [hole.T])


# ---------------------------------------------------------------------------------------
# tables of the ring: radius and parameter versus polar angle over one ring tooth
@lru_cache(maxsize=32)
def _ring_table(g: _Params):
    from scipy.interpolate import CubicSpline

    phi = np.linspace(-math.pi / g.z1, math.pi / g.z1, _TABLE_POINTS)
    X = _ring(g, phi, 1)[0]
    gam = np.arctan2(X[1], X[0])
    gam[0], gam[-1] = -math.pi / g.z2, math.pi / g.z2    # exact by symmetry
    rad = np.hypot(X[0], X[1])
    rad[-1] = rad[0]
    return gam, phi, CubicSpline(gam, rad, bc_type="periodic")


def _ring_radius_at(g: _Params, gamma):
    """Ring radius at polar angle gamma (star-shaped ring; spline error < 2e-15 m for the
    prototype, measured on 1e5 points)."""
    _, _, spl = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    gb = gamma - pitch * np.round(gamma / pitch)
    return spl(gb)


def _approx_gap(g: _Params, K):
    """Normal gap of points K (2, ...) from the ring to first order: radial clearance
    times the cosine of the ring normal's angle to the radius (start values only)."""
    _, _, spl = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    gam = np.arctan2(K[1], K[0])
    gb = gam - pitch * np.round(gam / pitch)
    rad, drad = spl(gb), spl(gb, 1)
    return (rad - np.hypot(K[0], K[1])) * rad / np.hypot(rad, drad)


def _ring_param_at(g: _Params, gamma):
    """Start value of the ring parameter whose point has polar angle gamma."""
    gam, phi, _ = _ring_table(g)
    pitch = 2 * math.pi / g.z2
    n = np.round(gamma / pitch)
    return np.interp(gamma - n * pitch, gam, phi) + n * 2 * math.pi / g.z1


# ---------------------------------------------------------------------------------------
# validity rules for the tooth height
def _half_tooth(g):
    return np.linspace(0, math.pi / g.z1, _PRED_SAMPLES)


def _envelope_regular(g: _Params) -> bool:
    """The normal of every planet point meets the pitch circle, the envelope X(phi) has
    no cusp (X' = lambda R p' with lambda > 0) and the ring is star-shaped about its
    centre (polar angle strictly increasing: no self-intersection)."""
    phi = _half_tooth(g)
    with np.errstate(all="ignore"):
        p, p1 = _planet(g, phi, 1)
        r = np.hypot(p[0], p[1])
        arg = _dot(p, p1) / (g.r1 * np.hypot(p1[0], p1[1]))
        if not np.all(np.abs(arg) < 1):
            return False
        X, X1, _, chi, _ = _ring(g, phi, 1)
        lam = _dot(X1, _rot(g.w * chi, p1)) / _dot(p1, p1)
        gam = np.unwrap(np.arctan2(X[1], X[0]))
    return bool(np.all(np.isfinite(lam)) and np.all(lam > 0) and np.all(np.diff(gam) > 0)
                and np.all(np.isfinite(r)))


def _contact_monotone(g: _Params) -> bool:
    """d psi/d phi > 0: the contact point moves one way along the planet, so each crank
    angle has one conjugate contact and its equivalent radius is finite."""
    with np.errstate(all="ignore"):
        psid = _psi(g, _half_tooth(g), 1)[1]
    return bool(np.all(psid > 0))


def _min_radial_clearance(g: _Params) -> float:
    """Smallest radial clearance ring - planet over the whole circumference and one crank
    pitch (negative: the planet enters the ring): samples in (chi, phi), then the worst few
    refined by nested grids, each 4x finer (final spacing ~1e-6 rad: clearance error
    below 1e-12 m for the curvatures met here)."""
    pitch_c = 2 * math.pi / g.z2
    chi = np.linspace(0, pitch_c, _INTERF_CRANKS, endpoint=False)
    phi = np.linspace(0, 2 * math.pi, g.z1 * _INTERF_SAMPLES, endpoint=False)

    def clearance(c, f):
        K = g.a0 * _u(c) + _rot(g.w * c, _planet(g, f, 0)[0])
        return _ring_radius_at(g, np.arctan2(K[1], K[0])) - np.hypot(K[0], K[1])

    cl = clearance(chi[:, None], phi[None, :])
    worst = np.argpartition(cl, 4, axis=None)[:4]
    i, j = np.unravel_index(worst, cl.shape)
    c0, f0 = chi[i], phi[j]
    hc, hf = chi[1] - chi[0], phi[1] - phi[0]
    off = np.linspace(-1, 1, 9)
    best = float(cl.min())
    for _ in range(6):
        cc = c0[:, None, None] + hc * off[None, :, None]
        ff = f0[:, None, None] + hf * off[None, None, :]
        v = clearance(cc, ff).reshape(len(c0), -1)
        k = np.argmin(v, axis=1)
        c0 = np.take_along_axis(np.broadcast_to(cc, v.shape[:1] + (9, 9)).reshape(len(c0), -1),
                                k[:, None], 1)[:, 0]
        f0 = np.take_along_axis(np.broadcast_to(ff, v.shape[:1] + (9, 9)).reshape(len(f0), -1),
                                k[:, None], 1)[:, 0]
        best = min(best, float(v.min()))
        hc, hf = hc / 4, hf / 4
    return best


def _no_interference(g: _Params) -> bool:
    return _min_radial_clearance(g) >= -_INTERF_TOL


@dataclass(frozen=True)
class _Rule:
    """One validity rule on the tooth height: its predicate and the reason in messages."""
    name: str
    holds_fn: Callable[[_Params], bool]
    why: str

    def holds(self, g):
        return self.holds_fn(g)

    def bound(self, z1, z2, m):
        return getattr(tooth_height_limits(z1, z2, m), self.name)


_RULES = (
    _Rule("envelope", _envelope_regular,
          "the conjugate ring profile would be cusped or self-intersecting (bound: largest a "
          "with a regular, star-shaped envelope, by bisection)"),
    _Rule("interference", _no_interference,
          "the planet would interfere with the ring away from the conjugate contact (bound: "
          "largest a with non-negative radial clearance over the circumference and a crank "
          "pitch, by bisection)"),
    _Rule("contact", _contact_monotone,
          "the contact path would reverse on the planet tooth tip (d psi/d phi <= 0: several "
          "simultaneous conjugate contacts, infinite equivalent radius; bound by bisection, "
          "analytically m/2)"),
)


@dataclass(frozen=True)
class ToothHeightLimits:
    """Largest tooth height a (m) allowed by each validity rule, for given z1, z2, m.

    ``envelope``: regular (uncusped, non-self-intersecting) conjugate ring profile;
    ``interference``: no overlap of planet and ring anywhere over the meshing cycle (for
    z2 - z1 = 1 the tips meet opposite the pitch point at a = a0 = m/2);
    ``contact``: contact path monotone along the planet (analytically a < m/2).
    Each is searched below the ones before it, so ``max`` is the binding one.
    """
    envelope: float
    interference: float
    contact: float

    @property
    def max(self) -> float:
        return min(self.envelope, self.interference, self.contact)


def _largest_valid(pred, z1, z2, m, hi, scan=8, rtol=_BOUND_RTOL):
    """Largest a below ``hi`` such that pred holds for all smaller a: a scan from 0 finds
    the first failure, bisection narrows it to rtol*m; ``hi`` if none fails."""
    lo = 0.0
    for a in hi * np.arange(1, scan + 1) / scan * (1 - _BOUND_RTOL):
        if not pred(_Params(z1, z2, m, float(a))):
            hi = float(a)
            break
        lo = float(a)
    else:
        return hi
    while hi - lo > rtol * m:
        mid = 0.5 * (lo + hi)
        if pred(_Params(z1, z2, m, mid)):
            lo = mid
        else:
            hi = mid
    return lo


@lru_cache(maxsize=64)
def tooth_height_limits(planet_teeth: int, ring_teeth: int, module_m: float):
    """Bounds on the tooth height a for tooth numbers and module (cached)."""
    z1, z2, m = int(planet_teeth), int(ring_teeth), float(module_m)
    r1 = m * z1 / 2
    env = _largest_valid(_envelope_regular, z1, z2, m, r1)
    itf = _largest_valid(_no_interference, z1, z2, m, env)
    con = _largest_valid(_contact_monotone, z1, z2, m, min(env, itf))
    return ToothHeightLimits(env, itf, con)


def max_tooth_height_m(pair: SineGearPair) -> float:
    """The binding bound on the tooth height for the pair's z1, z2, m."""
    return tooth_height_limits(pair.planet_teeth, pair.ring_teeth, pair.module_m).max


# ---------------------------------------------------------------------------------------
# Load-carrying contact at every crank angle: a LOWER bound on the tooth height (issue 14).
# Over one mesh period the conjugate contact runs over both flanks of a tooth, so it carries
# the output torque (negative moment arm) for only part of the period; the rest must come
# from the drive flanks of the neighbouring teeth. Low teeth leave crank angles where no
# drive flank is near (the analytic split then has no contact to load, the FE cycle mode
# no hat to select): such a pair is refused with the smallest tooth height that works.
#: A drive flank must be within this gap (m) at every crank angle: farther, the planet
#: turns freely before it takes the load (a jump of the transmission error every pitch),
#: and the FE cycle mode's contact selection (loaded hats up to 0.6 x 96 um) cannot reach
#: it.
LOAD_CARRYING_GAP_M = 40e-6
#: A moment arm below this fraction of r1 carries no torque (the conjugate contact at a
#: tooth tip or root lies on the line of centres: its arm is zero up to rounding).
_CARRY_ARM_REL = 1e-6
#: Crank positions per mesh period, then nested refinement around the worst few (the
#: largest gap sits next to a hand-over, where one flank's minimum leaves its window).
_CARRY_GRID, _CARRY_WORST, _CARRY_ROUNDS = 24, 3, 3
#: Width (a fraction of the module) at which the bisection for the bound stops.
_CARRY_RTOL = 1e-3


def _drive_gap(g: _Params, chi) -> np.ndarray:
    """(P,) smallest gap of a flank that can carry the output torque at crank angles chi: a
    gap minimum of its own (the conjugate contact: gap 0) with a negative moment arm
    (:func:`meshing`'s convention); inf where there is none."""
    chi = np.atleast_1d(np.asarray(chi, float))
    k = min(DEFAULT_CANDIDATES, (g.z1 - 1) // 2)        # the teeth meshing() looks at
    with np.errstate(all="ignore"):
        _, _, chi2, f1, f2, own, conj = _candidate_points(g, chi, k)
        K1 = _placed(g, chi2, f1, 0)[0]
        X, X1 = _ring(g, f2, 1)[:2]
        n = _perp(X1) / np.hypot(X1[0], X1[1])
        gap = np.where(conj, 0.0, _dot(K1 - X, n))
        arm = _cross(K1 - g.a0 * _u(chi2), n)
    carry = own & (arm < -_CARRY_ARM_REL * g.r1)
    return np.min(np.where(carry, gap, np.inf), axis=1)


@lru_cache(maxsize=256)
def max_drive_gap_m(g: _Params) -> float:
    """Largest, over a mesh period, of the smallest gap of a load-carrying flank (m): a
    grid, then nested grids around the worst positions. inf: some crank angle has none."""
    pitch = 2 * math.pi / g.z2
    chi = np.arange(_CARRY_GRID) * pitch / _CARRY_GRID
    h = _drive_gap(g, chi)
    if not np.all(np.isfinite(h)):
        return math.inf
    worst = chi[np.argsort(h)[-_CARRY_WORST:]]
    step, best = pitch / _CARRY_GRID, float(h.max())
    off = np.linspace(-1.0, 1.0, 9)
    for _ in range(_CARRY_ROUNDS):
        c = worst[:, None] + step * off[None, :]
        v = _drive_gap(g, c.ravel()).reshape(c.shape)
        best = max(best, float(v.max()))
        if not math.isfinite(best):
            return math.inf
        worst = c[np.arange(len(worst)), np.argmax(v, axis=1)]
        step /= 4
    return best


def _carries(g: _Params) -> bool:
    return max_drive_gap_m(g) <= LOAD_CARRYING_GAP_M


@lru_cache(maxsize=64)
def min_tooth_height_m(planet_teeth: int, ring_teeth: int, module_m: float) -> float:
    """Smallest tooth height a (m) with a drive flank within LOAD_CARRYING_GAP_M at every
    crank angle, by scan and bisection (the largest gap falls as a grows), to
    _CARRY_RTOL*m above; the upper bound :func:`tooth_height_limits` ``.max`` itself if no
    tooth height works."""
    z1, z2, m = int(planet_teeth), int(ring_teeth), float(module_m)
    top = tooth_height_limits(z1, z2, m).max
    lo = _largest_valid(lambda g: not _carries(g), z1, z2, m, top, rtol=_CARRY_RTOL)
    return top if lo >= top else min(lo + _CARRY_RTOL * m, top)


def check_load_carrying(pair: SineGearPair) -> SineGearPair:
    """``pair`` if a drive flank is within LOAD_CARRYING_GAP_M at every crank angle; else
    GeometryError naming tooth_height_m, its value and the valid range (the lower bound
    :func:`min_tooth_height_m`). Not part of the pair's own validation (a pair with low
    teeth is a valid shape); the case model applies it to a reducer's sine stage."""
    g = _params(pair)
    if _carries(g):
        return pair
    lo = min_tooth_height_m(g.z1, g.z2, g.m)
    hi = tooth_height_limits(g.z1, g.z2, g.m).max
    check_range("tooth_height_m", g.a, max(lo, g.a), hi, lo_open=lo <= g.a, hi_open=True,
                error=GeometryError,
                why=f"at some crank angles no drive flank is within "
                    f"{LOAD_CARRYING_GAP_M * 1e6:g} um to carry the torque (lower bound by "
                    "bisection" + ("; none of these tooth numbers and module works)"
                                   if lo >= hi else ")"))
    return pair


# ---------------------------------------------------------------------------------------
# conjugate contact and closest approach
def conjugate_contact(pair: SineGearPair, crank_angle_rad):
    """Planet parameter phi* (P,) of the conjugate contact at each crank angle: the root
    of psi(phi) = chi z2/z1 (psi is increasing; bracketed bisection, Newton polish)."""
    return _conjugate(_params(pair), np.atleast_1d(np.asarray(crank_angle_rad, float)))


def _conjugate(g: _Params, chi):
    target = chi * g.z2 / g.z1
    dev = _psi_deviation(g)
    lo, hi = target - dev, target + dev
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = _psi(g, mid)[0] < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        if np.max(hi - lo) < 1e-9:
            break
    phi = 0.5 * (lo + hi)
    for _ in range(3):
        psi, psid = _psi(g, phi, 1)
        phi = phi - (psi - target) / psid
    return phi


@lru_cache(maxsize=32)
def _psi_deviation(g: _Params) -> float:
    """Bracket half-width for the conjugate search: max |psi - phi| plus margin."""
    phi = np.linspace(-math.pi / g.z1, math.pi / g.z1, 4097)
    return float(np.max(np.abs(_psi(g, phi)[0] - phi))) * 1.5 + 1e-9


@dataclass(frozen=True)
class Approach:
    """Closest approach of planet flanks to the ring at crank angles (arrays of one shape).

    ``phi_planet``/``phi_ring``: parameters of the closest points; ``gap``: normal gap
    (positive: clearance, negative: overlap) along ``normal`` (2, ...), the ring's unit
    normal at the ring point, pointing into the free space (toward the planet);
    ``planet_point``/``ring_point`` (2, ...) in the ring frame. ``own``: the flank has a
    local minimum of the gap of its own (a stationary point inside its half-open window).
    Where it has not, the gap still falls beyond the flank's end, the nearest point belongs
    to the neighbouring flank, and the pair returned is the end point and its foot point.
    """
    crank_angle: np.ndarray
    phi_planet: np.ndarray
    phi_ring: np.ndarray
    planet_point: np.ndarray
    ring_point: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    own: np.ndarray


def flank_window(pair_or_teeth, tooth, flank):
    """Half-open planet-parameter window [lo, hi) of a flank: flank +1 is
    [tip, tip + pi/z1), flank -1 is [tip - pi/z1, tip), tip = 2 pi tooth/z1."""
    z1 = getattr(pair_or_teeth, "planet_teeth", pair_or_teeth)
    half = math.pi / z1
    k = 2 * np.asarray(tooth) - (np.asarray(flank) < 0)   # window = [k, k+1) half-teeth
    # boundaries are half * integer, computed as in _snap, so that windows meeting at a
    # tip or root share the very same float
    return half * k, half * (k + 1)


def closest_approach(pair: SineGearPair, crank_angle_rad, tooth, flank) -> Approach:
    """Closest approach of planet tooth ``tooth`` (tip at 2 pi tooth/z1), flank ``flank``
    (+1 / -1), to the ring, found on the parametric curves: start at the best of a few
    samples along the flank, then Newton on (phi1, phi2) for
        E1 = (K1 - X) . X' = 0   (K1 on the ring normal at X)
        E2 = K1' x X' = 0        (parallel tangents),
    whose Jacobian is regular when the relative curvature is not zero (docs S6).
    Arguments broadcast together."""
    g = _params(pair)
    chi, tooth, flank = np.broadcast_arrays(np.asarray(crank_angle_rad, float),
                                            np.asarray(tooth), np.asarray(flank))
    lo, hi = flank_window(g.z1, tooth, flank)
    f1, f2, own = _approach(g, chi, lo, hi)
    K1 = _placed(g, chi, f1, 0)[0]
    X, X1 = _ring(g, f2, 1)[:2]
    n = _perp(X1) / np.hypot(X1[0], X1[1])
    return Approach(chi, f1, f2, K1, X, n, _dot(K1 - X, n), own)


def _placed(g: _Params, chi, phi, order=2):
    """Planet point phi in the ring frame at crank chi, its d/dphi derivatives up to
    ``order``, and (last) dK/dchi, the material velocity per unit crank speed."""
    th = g.w * chi
    pd = _planet(g, phi, order)
    Rp = _rot(th, pd[0])
    K = g.a0 * _u(chi) + Rp
    V = g.a0 * _perp(_u(chi)) + g.w * _perp(Rp)
    return [K] + [_rot(th, d) for d in pd[1:]] + [V]


def _approach(g: _Params, chi, lo, hi):
    """(phi1, phi2, own) of the closest approach of flank windows [lo, hi) to the ring."""
    width = hi - lo
    t = np.linspace(0.0, 1.0, _APPROACH_SAMPLES)
    fs = lo[..., None] + width[..., None] * t
    Ks = _placed(g, chi[..., None], fs, 0)[0]
    k = np.argmin(_approx_gap(g, Ks), axis=-1)
    a1 = np.take_along_axis(fs, k[..., None], axis=-1)[..., 0]
    K0 = np.take_along_axis(Ks, k[None, ..., None], axis=-1)[..., 0]
    a2 = _foot(g, K0, _ring_param_at(g, np.arctan2(K0[1], K0[0])))
    for _ in range(_NEWTON_MAXITER):
        K1, T1, T1d, _ = _placed(g, chi, a1, 2)
        X, X1, X2 = _ring(g, a2, 2)[:3]
        d = K1 - X
        e1, e2 = _dot(d, X1), _cross(T1, X1)
        j11, j12 = _dot(T1, X1), -_dot(X1, X1) + _dot(d, X2)
        j21, j22 = _cross(T1d, X1), _cross(T1, X2)
        det = j11 * j22 - j12 * j21
        s1 = np.clip((e1 * j22 - e2 * j12) / det, -width, width)
        s2 = np.clip((j11 * e2 - j21 * e1) / det, -width, width)
        a1, a2 = a1 - s1, a2 - s2
        if np.all(np.abs(s1) + np.abs(s2) < _NEWTON_TOL):
            break
    conv = np.isfinite(a1) & np.isfinite(a2) & (np.abs(s1) + np.abs(s2) < 1e2 * _NEWTON_TOL)
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
    fl2 = _foot(g, K_lo, _ring_param_at(g, np.arctan2(K_lo[1], K_lo[0])))
    fh2 = _foot(g, K_hi, _ring_param_at(g, np.arctan2(K_hi[1], K_hi[0])))
    use_lo = _normal_gap(g, K_lo, fl2) <= _normal_gap(g, K_hi, fh2)
    e1 = np.where(use_lo, lo, hi)
    e2 = np.where(use_lo, fl2, fh2)
    return np.where(own, a1, e1), np.where(own, a2, e2), own


def _snap(g: _Params, phi):
    """Put parameters within _SNAP of a tip or root exactly on it, so that a point there
    belongs to exactly one of the two half-open flank windows that meet there."""
    half = math.pi / g.z1
    b = half * np.round(phi / half)
    return np.where(np.abs(phi - b) < _SNAP, b, phi)


def _gap_at(g, chi, f1, f2_start):
    K = _placed(g, chi, f1, 0)[0]
    return _normal_gap(g, K, _foot(g, K, f2_start))


def _normal_gap(g, K, f2):
    X, X1 = _ring(g, f2, 1)[:2]
    return _dot(K - X, _perp(X1)) / np.hypot(X1[0], X1[1])


def _foot(g: _Params, K, f2):
    """Ring parameter of the foot of the perpendicular from K (Newton)."""
    f2 = np.array(f2, float, copy=True)
    for _ in range(_NEWTON_MAXITER):
        X, X1, X2 = _ring(g, f2, 2)[:3]
        d = K - X
        step = _dot(d, X1) / (-_dot(X1, X1) + _dot(d, X2))
        f2 = f2 - step
        if np.all(np.abs(step) < _NEWTON_TOL):
            break
    return f2


def distance_to_ring(pair: SineGearPair, points) -> np.ndarray:
    """Signed normal distance of ring-frame points (2, ...) from the ring profile, found
    on the parametric curve (Newton foot point started from the polar-angle table):
    positive in the free space inside the ring, negative inside the ring's material."""
    g = _params(pair)
    K = np.asarray(points, float)
    f2 = _foot(g, K, _ring_param_at(g, np.arctan2(K[1], K[0])))
    return _normal_gap(g, K, f2)


# ---------------------------------------------------------------------------------------
def _candidates(g: _Params, chi, k):
    """Tooth indices (P, C) and flanks (C,) of the 2k+1 teeth nearest the pitch point."""
    j0 = np.round(chi * g.z2 / (2 * math.pi)).astype(int)    # psi_P z1/(2 pi)
    offs = np.repeat(np.arange(-k, k + 1), 2)
    flank = np.tile([-1, 1], 2 * k + 1)
    return j0[:, None] + offs[None, :], flank


def _candidate_points(g: _Params, chi, k):
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
    neighbouring flank's: reporting it twice would double a contact). ``point`` is the
    planet point, ``normal`` the ring normal there, pointing into the planet.
    ``pressure_angle``: between the normal and the velocity of the planet point about its
    own (fixed) axis, perpendicular to O1K (Eqs. 8-10). Velocities along t = k x n:
    ``sliding_velocity`` = planet minus ring surface (ring fixed); rolling speeds
    u_i = (velocity of the closest point along surface i - material velocity) . t,
    ``entrainment_velocity`` = (u1 + u2)/2 (the cycloid module's convention). A
    counter-clockwise crank turns the planet clockwise; the output torque is carried by
    the contacts with negative moment arm.
    """
    check_range("crank_speed_rad_s", crank_speed_rad_s, error=GeometryError)
    k = int(check_range("candidates", candidates, 1, (pair.planet_teeth - 1) // 2,
                        error=GeometryError))
    g = _params(pair)
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    om = float(crank_speed_rad_s)
    teeth, flank, chi2, f1, f2, own, conj = _candidate_points(g, chi, k)

    K1, T1, T1d, V = _placed(g, chi2, f1, 2)
    X, X1, X2 = _ring(g, f2, 2)[:3]
    n = _perp(X1) / np.hypot(X1[0], X1[1])
    gap = np.where(conj, 0.0, np.where(own, _dot(K1 - X, n), np.inf))
    point = np.where(conj[None], X, K1)
    centre = g.a0 * _u(chi)
    rel = point - centre[:, :, None]
    arm = _cross(rel, n)
    pressure = np.arccos(np.clip(np.abs(arm) / np.hypot(rel[0], rel[1]), 0.0, 1.0))

    # rates of the closest-approach parameters: J [phi1', phi2'] = -dE/dchi * chi'
    d = K1 - X
    j11, j12 = _dot(T1, X1), -_dot(X1, X1) + _dot(d, X2)
    j21, j22 = _cross(T1d, X1), _cross(T1, X2)
    e1c = _dot(V, X1)
    e2c = _cross(g.w * _perp(T1), X1)
    det = j11 * j22 - j12 * j21
    rate1 = np.where(own, -(e1c * j22 - e2c * j12) / det * om, 0.0)
    rate2 = np.where(own, -(j11 * e2c - j21 * e1c) / det * om, -e1c / j12 * om)

    t = _perp(n)
    sliding = _dot(V * om, t)
    u_planet = _dot(T1, t) * rate1        # the closest point moves along the planet
    u_ring = _dot(X1, t) * rate2
    entrain = 0.5 * (u_planet + u_ring)

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
    """Number of tooth pairs (planet flank / ring flank) in contact or within ``gap_m``
    at each crank angle, (P,) int: the local minima of the gap (one per flank at most,
    the conjugate contact included) not above ``gap_m``. With ``candidates`` None the
    number of teeth searched grows until the outermost ones are farther than ``gap_m``."""
    check_range("gap_m", gap_m, 0, None, error=GeometryError)
    g = _params(pair)
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
# pressure angles: numerical and the seed's closed forms (Eqs. 8-14)
def pressure_angles(pair: SineGearPair, phi):
    """Numerical pressure angles (alpha_k1, alpha_k2) at the conjugate contact of planet
    point phi: acute angles between the contact normal and the velocity of K as a point of
    the planet turning about O1 (perpendicular to O1K), resp. of the ring turning about O2
    (perpendicular to O2K) - the fixed-axis (carrier) frame of Fig. 2."""
    g = _params(pair)
    phi = np.asarray(phi, float)
    X, X1, _, chi, _ = _ring(g, phi, 1)
    n = _perp(X1) / np.hypot(X1[0], X1[1])
    rel1 = X - g.a0 * _u(chi)
    a1 = np.arccos(np.clip(np.abs(_cross(rel1, n)) / np.hypot(rel1[0], rel1[1]), 0, 1))
    a2 = np.arccos(np.clip(np.abs(_cross(X, n)) / np.hypot(X[0], X[1]), 0, 1))
    return a1, a2


@dataclass(frozen=True)
class SeedPressureAngles:
    """The seed's Eqs. (8)-(14) at planet points phi (arrays of phi's shape)."""
    alpha_k1: np.ndarray           # Eq. (8) with (9), (10)
    r_k1: np.ndarray               # Eq. (11)
    r_k2: np.ndarray               # Eq. (12)
    zeta: np.ndarray               # Eq. (13), "a cos" read as arccos
    alpha_k2_printed: np.ndarray   # Eq. (14) as printed: alpha_k1 - zeta
    alpha_k2: np.ndarray           # Eq. (14) corrected: alpha_k1 - s zeta (docs S9)
    sign: np.ndarray               # s: +1 where the angle O1-K-P is acute, else -1


def seed_pressure_angles(pair: SineGearPair, phi) -> SeedPressureAngles:
    """The seed's closed forms for the pressure angles at the conjugate contact of p(phi).

    Eq. (8)-(10): alpha_k1 = atan|(k_n - k_v)/(1 + k_n k_v)|, k_v = -x/y, k_n = -dx/dy in
    the paper's planet frame (x, y) = r(phi) (sin phi, cos phi); evaluated multiplied
    through by y dy, tan alpha_k1 = |x y' - y x'| / |x x' + y y'|, which is the same
    number without infinite slopes. Eq. (11) r_k1 = r(phi); Eq. (12) r_k2 = |O2 K| from
    the ring-frame contact point; Eq. (13) zeta = arccos((r_k1^2 + r_k2^2 - a0^2) /
    (2 r_k1 r_k2)); Eq. (14) alpha_k2 = alpha_k1 - zeta as printed holds only where the
    angle O1-K-P is acute (s = +1: K beyond the planet's pitch circle, on the addendum,
    apart from a sliver); elsewhere alpha_k2 = alpha_k1 + zeta (docs S9).
    """
    g = _params(pair)
    phi = np.asarray(phi, float)
    r, rp = _radius(g, phi)[:2]
    x, y = r * np.sin(phi), r * np.cos(phi)
    dx, dy = rp * np.sin(phi) + r * np.cos(phi), rp * np.cos(phi) - r * np.sin(phi)
    alpha1 = np.arctan2(np.abs(x * dy - y * dx), np.abs(x * dx + y * dy))
    X, _, _, chi, _ = _ring(g, phi, 1)
    rk2 = np.hypot(X[0], X[1])
    zeta = np.arccos(np.clip((r**2 + rk2**2 - g.a0**2) / (2 * r * rk2), -1.0, 1.0))
    # s = +1 where the angle O1-K-P is acute (docs S9)
    P = g.r2 * _u(chi)
    s = np.where(_dot(P - X, g.a0 * _u(chi) - X) > 0, 1.0, -1.0)
    return SeedPressureAngles(alpha1, r, rk2, zeta, alpha1 - zeta, alpha1 - s * zeta, s)
