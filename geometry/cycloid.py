"""Cycloid disc geometry: the record, the generating curve and the working profile.

Notation (the pin-housing paper: Y. Wang, G. Liu, H. Yu, H. Mao, K. He, R. Du, "Analysis of
meshing characteristics of pins and pin housing integral structure in cycloidal planetary
drive", Sec. 2):
Zb pins of radius rz on a circle of radius Rz; disc with Za = Zb - 1 lobes; eccentricity
A (= e); shortening coefficient K1 = A*Zb/Rz; disc and pin pitch radii r_a = A*Za,
r_b = A*Zb.

Profile (disc frame, disc centre at the origin). We write the paper's Eq. (1) with
counter-clockwise angles from the x-axis, u(a) = (cos a, sin a) instead of its
(sin a, cos a); that is the mirror image in the line x = y, and since the profile is
symmetric the shape is the same:

    theoretical  p(psi) = Rz*u(psi) - A*u(Zb*psi)                            (Eq. 1)
    working      w(psi) = p(psi) + rz*n(psi),
                 n = (K1*u(Zb*psi) - u(psi)) / sqrt(S),  S = 1 + K1^2 - 2*K1*cos(Za*psi)

n is the inward unit normal. The paper prints S with cos(Zb*psi) (Eq. 3); the tangent
|p'|^2 = Rz^2 (1 + K1^2 - 2 K1 cos((Zb-1) psi)) shows the argument is Za*psi
(docs/derivations.md, C1).

Modifications (generating parameters of the grinding machine): equidistant Delta rz
(the disc is generated with pin radius rz + Delta rz), move-distance Delta Rz (generated
with pin-circle radius Rz + Delta Rz, same A), rotation Delta delta (each flank turned by
Delta delta toward its tooth centre: the disc is the intersection of the profile turned
by +Delta delta and by -Delta delta; a negative Delta delta turns each flank away, the
disc is their union: docs/derivations.md 8).

The disc in its housing (pose, pin contacts, ``meshing``, exact clearances):
:mod:`toothfem.geometry.cycloid_mesh`; foot points and distances on the profile:
:mod:`toothfem.geometry.cycloid_distance`; the disc before load (backlash, first-order
clearance): :mod:`toothfem.geometry.cycloid_backlash`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, check_range
from .vectors import perp, unit


@dataclass(frozen=True)
class CycloidGeometry:
    """Cycloid disc and pin ring in SI units (see the module docstring)."""
    pin_count: int
    pin_circle_radius_m: float
    eccentricity_m: float
    pin_radius_m: float
    equidistant_m: float = 0.0
    move_distance_m: float = 0.0
    rotation_rad: float = 0.0

    def __post_init__(self):
        zb = self.pin_count
        if isinstance(zb, bool) or int(zb) != zb:
            raise GeometryError(f"pin_count = {zb!r} must be an integer")
        check_range("pin_count", zb, 4, None, error=GeometryError)
        rz_ = check_range("pin_circle_radius_m", self.pin_circle_radius_m, 0, None,
                          lo_open=True, error=GeometryError)
        check_range("eccentricity_m", self.eccentricity_m, 0, rz_ / zb, lo_open=True,
                    hi_open=True, error=GeometryError,
                    why="K1 = A*Zb/Rz must be below 1 (K1 >= 1 gives a looped profile)")
        check_range("pin_radius_m", self.pin_radius_m, 0, None, lo_open=True,
                    error=GeometryError)
        for name, v in (("equidistant_m", self.equidistant_m),
                        ("move_distance_m", self.move_distance_m)):
            check_range(name, v, -0.01 * rz_, 0.01 * rz_, error=GeometryError,
                        why="modifications are small corrections (|value| <= 1% of Rz)")
        check_range("rotation_rad", self.rotation_rad, -math.radians(1), math.radians(1),
                    error=GeometryError)
        # The pins on the line of centres (tooth root and tip, zero moment arm) cannot be
        # cleared by turning the disc: their clearance Delta_rz - Delta_Rz must not be negative.
        check_range("equidistant_m - move_distance_m", self.equidistant_m - self.move_distance_m,
                    0, None, error=GeometryError,
                    why="the disc would interfere with the pins at the tooth tip and root "
                        "(radial clearance)")
        # Pins must not overlap their neighbours.
        pitch_half = self.pin_circle_radius_m * math.sin(math.pi / zb)
        check_range("pin_radius_m", self.pin_radius_m, 0, pitch_half, lo_open=True,
                    hi_open=True, error=GeometryError,
                    why="neighbouring pins would overlap (bound Rz*sin(pi/Zb))")
        # Undercut: the generating pin radius must stay below the smallest convex curvature
        # radius of the (generating) theoretical profile.
        gen = self.generating()
        rho_min = min_convex_curvature_radius(gen)
        if not self.generating_pin_radius < rho_min:
            name = "pin_radius_m" if self.equidistant_m == 0 else "pin_radius_m + equidistant_m"
            check_range(name, self.generating_pin_radius, 0, rho_min, lo_open=True,
                        hi_open=True, error=GeometryError,
                        why="the working profile would be undercut (bound: smallest convex "
                            "curvature radius of the theoretical profile)")

    # -- derived quantities ------------------------------------------------------------
    @property
    def lobe_count(self) -> int:
        return self.pin_count - 1

    @property
    def k1(self) -> float:
        """Shortening coefficient K1 = A*Zb/Rz."""
        return self.eccentricity_m * self.pin_count / self.pin_circle_radius_m

    @property
    def disc_pitch_radius_m(self) -> float:
        """r_a = A*Za (rolling circle of the disc)."""
        return self.eccentricity_m * self.lobe_count

    @property
    def pin_pitch_radius_m(self) -> float:
        """r_b = A*Zb."""
        return self.eccentricity_m * self.pin_count

    @property
    def generating_pin_radius(self) -> float:
        return self.pin_radius_m + self.equidistant_m

    @property
    def modified(self) -> bool:
        return bool(self.equidistant_m or self.move_distance_m or self.rotation_rad)

    def generating(self) -> _Generating:
        """The parameters the grinding machine uses (with modifications applied).

        Returns
        -------
        _Generating
            Zb, Rz + Delta Rz [m], A [m] and the offset rz + Delta rz [m].
        """
        return _Generating(self.pin_count, self.pin_circle_radius_m + self.move_distance_m,
                           self.eccentricity_m, self.pin_radius_m + self.equidistant_m)

    def nominal(self) -> _Generating:
        """The unmodified parameters (no equidistant, move-distance or rotation).

        Returns
        -------
        _Generating
            Zb, Rz [m], A [m] and the pin radius rz [m] as the offset.
        """
        return _Generating(self.pin_count, self.pin_circle_radius_m, self.eccentricity_m,
                           self.pin_radius_m)

    @property
    def root_radius_m(self) -> float:
        g = self.generating()
        return g.rz_circle - g.a - g.r

    @property
    def tip_radius_m(self) -> float:
        g = self.generating()
        return g.rz_circle + g.a - g.r


@dataclass(frozen=True)
class _Generating:
    """Raw generating parameters (no validation): Zb, Rz, A, r (offset)."""
    zb: int
    rz_circle: float
    a: float
    r: float

    @property
    def k1(self):
        return self.a * self.zb / self.rz_circle


# ---------------------------------------------------------------------------------------
# Profiles

def theoretical_profile(g: _Generating | CycloidGeometry, psi, order=0):
    """Theoretical profile p(psi) (Eq. 1) and its derivatives: (2, N) arrays.

    Parameters
    ----------
    g : _Generating or CycloidGeometry
        Generating parameters; a CycloidGeometry is taken as generated (modifications
        applied).
    psi : array_like, shape (N,)
        Profile parameters psi [rad].
    order : int
        0, 1, 2 returns p, p', p'' respectively.

    Returns
    -------
    numpy.ndarray, shape (2, N)
        p [m], or its first or second derivative by psi [m/rad, m/rad^2].

    Raises
    ------
    ValueError
        If ``order`` is not 0, 1 or 2.
    """
    g = g.generating() if isinstance(g, CycloidGeometry) else g
    psi = np.asarray(psi, float)
    zb = g.zb
    if order == 0:
        return g.rz_circle * unit(psi) - g.a * unit(zb * psi)
    if order == 1:
        return g.rz_circle * perp(unit(psi)) - g.a * zb * perp(unit(zb * psi))
    if order == 2:
        return -g.rz_circle * unit(psi) + g.a * zb**2 * unit(zb * psi)
    raise ValueError(f"order = {order!r} is outside the valid range [0, 2]")


def inward_normal(g, psi):
    """Unit inward normal n(psi) of the theoretical profile (Eqs. 3-4 corrected).

    Parameters
    ----------
    g : _Generating or CycloidGeometry
    psi : array_like, shape (N,)
        Profile parameters [rad].

    Returns
    -------
    numpy.ndarray, shape (2, N)
        Unit normals pointing into the disc.
    """
    g = g.generating() if isinstance(g, CycloidGeometry) else g
    psi = np.asarray(psi, float)
    k1 = g.k1
    s = 1 + k1**2 - 2 * k1 * np.cos((g.zb - 1) * psi)
    return (k1 * unit(g.zb * psi) - unit(psi)) / np.sqrt(s)


def working_profile(g, psi):
    """Working (disc) profile w(psi) = p(psi) + r n(psi), unmodified or as generated.

    Parameters
    ----------
    g : _Generating or CycloidGeometry
    psi : array_like, shape (N,)
        Where the profile is evaluated [rad].

    Returns
    -------
    numpy.ndarray of float, shape (2, N)
        Points of the working profile in the disc frame [m].
    """
    g = g.generating() if isinstance(g, CycloidGeometry) else g
    return theoretical_profile(g, psi) + g.r * inward_normal(g, psi)


def curvature_radius(g, psi):
    """Signed curvature radius of the theoretical profile, positive where convex:

        rho = Rz S^{3/2} / (1 + Zb K1^2 - K1 (Zb + 1) cos(Za psi))

    (from rho = |p'|^3 / (p' x p''); docs/derivations.md C2).

    Parameters
    ----------
    g : _Generating or CycloidGeometry
    psi : array_like
        Profile parameters [rad].

    Returns
    -------
    numpy.ndarray
        rho [m], shape of ``psi`` (inf at an inflection point).
    """
    g = g.generating() if isinstance(g, CycloidGeometry) else g
    theta = (g.zb - 1) * np.asarray(psi, float)
    return _rho_of_theta(g, theta)


def _rho_of_theta(g, theta):
    k1 = g.k1
    s = 1 + k1**2 - 2 * k1 * np.cos(theta)
    den = 1 + g.zb * k1**2 - k1 * (g.zb + 1) * np.cos(theta)
    with np.errstate(divide="ignore"):
        return g.rz_circle * s**1.5 / den


def min_convex_curvature_radius(g) -> float:
    """Smallest positive curvature radius of the theoretical profile over one lobe.

    The profile is convex where 1 + Zb K1^2 - K1 (Zb+1) cos(theta) > 0; rho is smooth there
    and we minimise it on a fine grid and polish with a bounded scalar search.

    Parameters
    ----------
    g : _Generating

    Returns
    -------
    float
        The smallest convex curvature radius [m] (the undercut bound of the generating pin
        radius).
    """
    from scipy.optimize import minimize_scalar

    theta = np.linspace(0, math.pi, 4001)
    rho = _rho_of_theta(g, theta)
    rho = np.where(rho > 0, rho, np.inf)
    k = int(np.argmin(rho))
    lo, hi = theta[max(k - 1, 0)], theta[min(k + 1, theta.size - 1)]
    if hi > lo:
        res = minimize_scalar(lambda t: float(_rho_of_theta(g, t)), bounds=(lo, hi),
                              method="bounded", options={"xatol": 1e-12})
        return float(min(res.fun, rho[k]))
    return float(rho[k])


def profile_points(geom: CycloidGeometry, points_per_lobe: int = 96, flank=0) -> np.ndarray:
    """Working profile as a closed polyline (2, N) in the disc frame (N = Za*points).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc, as generated (modifications applied).
    points_per_lobe : int
        Samples per lobe.
    flank : int
        +1/-1 rotates the whole profile by +-Delta delta (rotation modification); 0 ignores
        the rotation.

    Returns
    -------
    numpy.ndarray, shape (2, N)
        Profile points [m], counter-clockwise, the first point not repeated.
    """
    n = geom.lobe_count * int(points_per_lobe)
    psi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    pts = working_profile(geom, psi)
    if flank and geom.rotation_rad:
        c, s = math.cos(flank * geom.rotation_rad), math.sin(flank * geom.rotation_rad)
        pts = np.array([[c, -s], [s, c]]) @ pts
    return pts
