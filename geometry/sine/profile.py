"""Planet profile of the sine gear pair (the sine paper's Eq. 1), its analytic derivatives
and curvature, and the record of the numbers every formula of the pair needs.

Source: Y. Lu, L. Xu, "Transmission efficiency of one tooth difference sine tooth profile
planetary reducer", Heliyon 10 (2024) e26300 (the sine paper), Sec. 2; the corrections
and numerical checks are in docs/derivations.md, section 3 (S1-S9).

Notation (SI): planet with z1 teeth, pitch radius r1 = m z1/2; fixed ring with z2 >= z1 + 1
teeth, r2 = m z2/2; centre distance a0 = r2 - r1; tooth height (sine amplitude) a.

Planet profile (planet frame, centre at the origin), Eq. (1) written with counter-clockwise
angles from the x-axis, u(phi) = (cos phi, sin phi) instead of the paper's
(sin phi, cos phi). That is the mirror image in the line x = y; the profile is symmetric
(r(-phi) = r(phi)), so the shape is the same:

    p(phi) = r(phi) u(phi),   r(phi) = a cos(z1 phi) + sqrt(r1^2 - a^2 sin^2(z1 phi))

Tooth j of the planet has its tip at phi = 2 pi j / z1; its flank -1 is the half-open
window phi in [tip - pi/z1, tip), its flank +1 is [tip, tip + pi/z1).

Curvatures are signed positive where the surface is convex toward the mating gear (the
planet's tooth tips, the ring's tooth tips), as in ``MeshingState``. Points and vectors are
``(2, ...)`` arrays (``toothfem.geometry.vectors``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..vectors import cross, unit

if TYPE_CHECKING:   # annotations only: the record is validated with the bounds of limits.py
    from .pair import SineGearPair


@dataclass(frozen=True)
class ProfileParams:
    """The numbers the formulas of the pair need, in SI units (hashable, so tables can be
    cached per geometry; built from a pair by :func:`profile_params`).

    Attributes
    ----------
    z1, z2 : int
        Planet and ring tooth numbers.
    m : float
        Module (m).
    a : float
        Tooth height, the sine amplitude of Eq. (1) (m).
    """
    z1: int
    z2: int
    m: float
    a: float

    @property
    def r1(self) -> float:
        """Planet pitch radius m z1/2 (m)."""
        return self.m * self.z1 / 2

    @property
    def r2(self) -> float:
        """Ring pitch radius m z2/2 (m)."""
        return self.m * self.z2 / 2

    @property
    def a0(self) -> float:
        """Centre distance r2 - r1 = m (z2 - z1)/2 (m)."""
        return self.m * (self.z2 - self.z1) / 2

    @property
    def w(self) -> float:
        """Planet angular velocity per unit crank speed, -(z2 - z1)/z1."""
        return -(self.z2 - self.z1) / self.z1


def profile_params(pair: SineGearPair) -> ProfileParams:
    """The :class:`ProfileParams` of a pair (tooth numbers, module, tooth height).

    Parameters
    ----------
    pair : SineGearPair
        Any record with ``planet_teeth``, ``ring_teeth``, ``module_m`` and
        ``tooth_height_m``.

    Returns
    -------
    ProfileParams
        Hashable (used as the key of the cached ring tables).
    """
    return ProfileParams(int(pair.planet_teeth), int(pair.ring_teeth), float(pair.module_m),
                         float(pair.tooth_height_m))


# ---------------------------------------------------------------------------------------
# planet profile (Eq. 1) and its derivatives
def _radius(g: ProfileParams, phi):
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


def _planet(g: ProfileParams, phi, order=2):
    """p and its derivatives d^k p/dphi^k, k <= order (<= 3), each (2, ...)."""
    r, r1, r2, r3 = _radius(g, phi)
    e, f = unit(phi), unit(phi + math.pi / 2)
    out = [r * e, r1 * e + r * f, (r2 - r) * e + 2 * r1 * f,
           (r3 - 3 * r1) * e + (3 * r2 - r) * f]
    return out[:order + 1]


def _curvature(d1, d2):
    """Standard signed curvature (x'y'' - y'x'')/|p'|^3 (positive turning left)."""
    return cross(d1, d2) / np.hypot(d1[0], d1[1]) ** 3


def curvature_eq6(d1, d2):
    """The sine paper's Eq. (6) as printed: K = (x''y' - x'y'')/(x'^2 + y'^2)^(3/2).

    This is minus the standard signed curvature; evaluated on the paper's clockwise
    parametrisation (x, y) = r (sin, cos) it is positive on convex parts and equals the
    convex-positive ``curvature`` of :func:`planet_curve` (docs/derivations.md, S3).

    Parameters
    ----------
    d1, d2 : array_like, shape (2, ...)
        First and second derivatives of the curve with respect to its parameter.

    Returns
    -------
    numpy.ndarray, shape (...)
        Curvature (1/m).
    """
    d1, d2 = np.asarray(d1, float), np.asarray(d2, float)
    return -_curvature(d1, d2)


@dataclass(frozen=True)
class ProfileCurve:
    """A parametric profile sampled at ``phi``.

    Attributes
    ----------
    phi : numpy.ndarray, shape (N,)
        Curve parameter (rad): the planet parameter of the point, or for the ring that of
        the generating planet point.
    point, d1, d2 : numpy.ndarray, shape (2, N)
        Points (m) and their first and second derivatives with respect to phi.
    curvature : numpy.ndarray, shape (N,)
        Signed curvature (1/m), positive where the surface is convex toward the mating gear.
    crank_angle : numpy.ndarray, shape (N,), or None
        (Ring only) the crank angle chi(phi) at which the point is in contact (rad).
    """
    phi: np.ndarray
    point: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    curvature: np.ndarray
    crank_angle: np.ndarray | None = None

    @property
    def radius(self) -> np.ndarray:
        """Signed curvature radius (m; inf at inflection points)."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.curvature


def planet_profile(pair: SineGearPair, phi) -> np.ndarray:
    """Planet profile points in the planet frame, Eq. (1) (counter-clockwise angles).

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like
        Planet parameter, the polar angle of the point (rad), any shape S; tooth j has its
        tip at 2 pi j/z1.

    Returns
    -------
    numpy.ndarray
        Points p(phi) (m), shape (2, *S).
    """
    return _planet(profile_params(pair), np.asarray(phi, float), 0)[0]


def planet_curve(pair: SineGearPair, phi) -> ProfileCurve:
    """Planet profile with analytic derivatives and curvature (Eq. 6, positive convex).

    Parameters
    ----------
    pair : SineGearPair
    phi : array_like, shape (N,)
        Planet parameter (rad).

    Returns
    -------
    ProfileCurve
        ``crank_angle`` is None.
    """
    phi = np.asarray(phi, float)
    p, d1, d2 = _planet(profile_params(pair), phi, 2)
    return ProfileCurve(phi, p, d1, d2, _curvature(d1, d2))
