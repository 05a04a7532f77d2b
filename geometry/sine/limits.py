"""Validity bounds on the tooth height of a sine gear pair: a regular (uncusped,
non-self-intersecting) conjugate ring, no interference of planet and ring away from the
conjugate contact, and a contact path that does not reverse on the planet (no undercut of
the tooth tip).

These rules are not in the sine paper (Y. Lu, L. Xu, Heliyon 10 (2024) e26300); they and
their bounds for the paper's prototype are derived in docs/derivations.md, S7. Each bound
is the largest tooth height for which the rule holds for every smaller one (scan, then
bisection).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING
from collections.abc import Callable

import numpy as np

from ...errors import GeometryError, check_range
from ..vectors import dot, rotate, unit
from .conjugate import _psi, _ring, _ring_radius_at
from .profile import ProfileParams, _planet

if TYPE_CHECKING:
    from .pair import SineGearPair

#: Samples per half tooth used by the validity predicates (bounds on a).
_PRED_SAMPLES = 2049
#: Crank positions per tooth pitch and planet samples per tooth in the interference check.
_INTERF_CRANKS = 24
_INTERF_SAMPLES = 32
#: Radial overlap (m) above which planet and ring are said to interfere; the ring radius is
#: interpolated with a periodic cubic spline whose error is ~a (2 pi/1024)^4 < 2e-15 m for
#: the prototype (docs/derivations.md, S7).
_INTERF_TOL = 1e-11
#: Interference refinement: the worst samples refined, the refinement rounds (each grid 4x
#: finer: final spacing ~1e-6 rad, clearance error below 1e-12 m for the curvatures met
#: here) and the points per axis of each refinement grid.
_INTERF_WORST = 4
_INTERF_ROUNDS = 6
_INTERF_GRID = 9
#: Bisection on a stops at this relative width (of the module).
_BOUND_RTOL = 1e-9
#: Scan steps from 0 to the upper limit before bisection: the first failing step brackets
#: the bound.
_BOUND_SCAN = 8


def _half_tooth(g):
    return np.linspace(0, math.pi / g.z1, _PRED_SAMPLES)


def _envelope_regular(g: ProfileParams) -> bool:
    """The normal of every planet point meets the pitch circle, the envelope X(phi) has
    no cusp (X' = lambda R p' with lambda > 0) and the ring is star-shaped about its
    centre (polar angle strictly increasing: no self-intersection)."""
    phi = _half_tooth(g)
    with np.errstate(all="ignore"):
        p, p1 = _planet(g, phi, 1)
        r = np.hypot(p[0], p[1])
        arg = dot(p, p1) / (g.r1 * np.hypot(p1[0], p1[1]))
        if not np.all(np.abs(arg) < 1):
            return False
        X, X1, _, chi, _ = _ring(g, phi, 1)
        lam = dot(X1, rotate(p1, g.w * chi)) / dot(p1, p1)
        gam = np.unwrap(np.arctan2(X[1], X[0]))
    return bool(np.all(np.isfinite(lam)) and np.all(lam > 0) and np.all(np.diff(gam) > 0)
                and np.all(np.isfinite(r)))


def _contact_monotone(g: ProfileParams) -> bool:
    """d psi/d phi > 0: the contact point moves one way along the planet, so each crank
    angle has one conjugate contact and its equivalent radius is finite."""
    with np.errstate(all="ignore"):
        psid = _psi(g, _half_tooth(g), 1)[1]
    return bool(np.all(psid > 0))


def _min_radial_clearance(g: ProfileParams) -> float:
    """Smallest radial clearance ring - planet over the whole circumference and one crank
    pitch (negative: the planet enters the ring): samples in (chi, phi), then the worst few
    refined by nested grids (``_INTERF_WORST``, ``_INTERF_ROUNDS``)."""
    pitch_c = 2 * math.pi / g.z2
    chi = np.linspace(0, pitch_c, _INTERF_CRANKS, endpoint=False)
    phi = np.linspace(0, 2 * math.pi, g.z1 * _INTERF_SAMPLES, endpoint=False)

    def clearance(c, f):
        K = g.a0 * unit(c) + rotate(_planet(g, f, 0)[0], g.w * c)
        return _ring_radius_at(g, np.arctan2(K[1], K[0])) - np.hypot(K[0], K[1])

    cl = clearance(chi[:, None], phi[None, :])
    worst = np.argpartition(cl, _INTERF_WORST, axis=None)[:_INTERF_WORST]
    i, j = np.unravel_index(worst, cl.shape)
    c0, f0 = chi[i], phi[j]
    hc, hf = chi[1] - chi[0], phi[1] - phi[0]
    n = _INTERF_GRID
    off = np.linspace(-1, 1, n)
    best = float(cl.min())
    for _ in range(_INTERF_ROUNDS):
        cc = c0[:, None, None] + hc * off[None, :, None]
        ff = f0[:, None, None] + hf * off[None, None, :]
        v = clearance(cc, ff).reshape(len(c0), -1)
        k = np.argmin(v, axis=1)
        c0 = np.take_along_axis(np.broadcast_to(cc, v.shape[:1] + (n, n)).reshape(len(c0), -1),
                                k[:, None], 1)[:, 0]
        f0 = np.take_along_axis(np.broadcast_to(ff, v.shape[:1] + (n, n)).reshape(len(f0), -1),
                                k[:, None], 1)[:, 0]
        best = min(best, float(v.min()))
        hc, hf = hc / 4, hf / 4
    return best


def _no_interference(g: ProfileParams) -> bool:
    return _min_radial_clearance(g) >= -_INTERF_TOL


@dataclass(frozen=True)
class _Rule:
    """One validity rule on the tooth height: its predicate and the reason in messages."""
    name: str
    holds_fn: Callable[[ProfileParams], bool]
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


def check_tooth_height(g: ProfileParams) -> None:
    """Refuse a tooth height that breaks a validity rule.

    Parameters
    ----------
    g : ProfileParams
        The pair's numbers (tooth numbers, module, tooth height).

    Raises
    ------
    GeometryError
        Naming ``tooth_height_m``, its value, the bound of the first rule broken (from
        :func:`tooth_height_limits`) and the reason.
    """
    for rule in _RULES:
        if not rule.holds(g):
            # the bound is the bisection's; min() keeps the refusal should the scan
            # and the direct check ever disagree at the very edge
            bound = min(rule.bound(g.z1, g.z2, g.m), g.a)
            check_range("tooth_height_m", g.a, 0, bound, lo_open=True, hi_open=True,
                        error=GeometryError, why=rule.why)


@dataclass(frozen=True)
class ToothHeightLimits:
    """Largest tooth height a (m) allowed by each validity rule, for given z1, z2, m.

    Each is searched below the ones before it, so ``max`` is the binding one.

    Attributes
    ----------
    envelope : float
        Regular (uncusped, non-self-intersecting) conjugate ring profile.
    interference : float
        No overlap of planet and ring anywhere over the meshing cycle (for z2 - z1 = 1 the
        tips meet opposite the pitch point at a = a0 = m/2).
    contact : float
        Contact path monotone along the planet (analytically a < m/2).
    """
    envelope: float
    interference: float
    contact: float

    @property
    def max(self) -> float:
        """The binding bound, min(envelope, interference, contact) (m)."""
        return min(self.envelope, self.interference, self.contact)


def _largest_valid(pred, z1, z2, m, hi, scan=_BOUND_SCAN, rtol=_BOUND_RTOL):
    """Largest a below ``hi`` such that pred holds for all smaller a: a scan from 0 finds
    the first failure, bisection narrows it to rtol*m; ``hi`` if none fails."""
    lo = 0.0
    for a in hi * np.arange(1, scan + 1) / scan * (1 - _BOUND_RTOL):
        if not pred(ProfileParams(z1, z2, m, float(a))):
            hi = float(a)
            break
        lo = float(a)
    else:
        return hi
    while hi - lo > rtol * m:
        mid = 0.5 * (lo + hi)
        if pred(ProfileParams(z1, z2, m, mid)):
            lo = mid
        else:
            hi = mid
    return lo


@lru_cache(maxsize=64)
def tooth_height_limits(planet_teeth: int, ring_teeth: int,
                        module_m: float) -> ToothHeightLimits:
    """Bounds on the tooth height a for tooth numbers and module (cached).

    Parameters
    ----------
    planet_teeth, ring_teeth : int
        z1 and z2.
    module_m : float
        Module (m).

    Returns
    -------
    ToothHeightLimits
    """
    z1, z2, m = int(planet_teeth), int(ring_teeth), float(module_m)
    r1 = m * z1 / 2
    env = _largest_valid(_envelope_regular, z1, z2, m, r1)
    itf = _largest_valid(_no_interference, z1, z2, m, env)
    con = _largest_valid(_contact_monotone, z1, z2, m, min(env, itf))
    return ToothHeightLimits(env, itf, con)


def max_tooth_height_m(pair: SineGearPair) -> float:
    """The binding bound on the tooth height for the pair's z1, z2, m.

    Parameters
    ----------
    pair : SineGearPair
        Its tooth height is not used: the bound is what it may be raised to.

    Returns
    -------
    float
        ``tooth_height_limits(z1, z2, m).max`` (m).
    """
    return tooth_height_limits(pair.planet_teeth, pair.ring_teeth, pair.module_m).max
