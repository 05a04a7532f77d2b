"""Manufacturing deviations of one built reducer, drawn from its tolerances.

A deviation moves or resizes the parts by a few micrometres. It changes the initial gaps of
the candidate contacts and not their compliance (the influence tables of the nominal
design stay valid to first order in deviation / part size), so a sampled reducer costs a
complementarity solve per position and no factorisation (docs/tolerance.md).

Tolerance zones (ISO 1101 true position: a circle of the zone's diameter; a symmetric
limit +-a; deviation limits [lo, hi]) become random values by a named distribution:
``uniform`` over the zone, or ``normal`` with three standard deviations at its limit (per
component for a true-position zone), the usual assumption of a capable process
(Cpk = 1).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import ToothfemError

DISTRIBUTIONS = ("normal", "uniform")
#: Standard deviations from the mean to the limit of a zone under ``normal``.
SIGMAS_AT_LIMIT = 3.0


def symmetric(rng, limit: float, size, distribution: str) -> np.ndarray:
    """Values within a symmetric limit.

    Parameters
    ----------
    rng : numpy.random.Generator
    limit : float
        The zone is +-``limit`` (same unit as the values).
    size : int or tuple
        Shape of the values.
    distribution : {"normal", "uniform"}
        normal: sigma = limit/3; uniform over the zone.

    Returns
    -------
    numpy.ndarray
    """
    if distribution == "uniform":
        return rng.uniform(-limit, limit, size)
    return rng.normal(0.0, limit / SIGMAS_AT_LIMIT, size)


def between(rng, lo: float, hi: float, size, distribution: str) -> np.ndarray:
    """Values within deviation limits.

    Parameters
    ----------
    rng : numpy.random.Generator
    lo, hi : float
        The limits (ISO 286 lower and upper deviations), lo <= hi.
    size : int or tuple
    distribution : {"normal", "uniform"}
        normal: mean at the middle, 3 sigma at each limit; uniform over [lo, hi].

    Returns
    -------
    numpy.ndarray
    """
    if distribution == "uniform":
        return rng.uniform(lo, hi, size)
    return rng.normal(0.5 * (lo + hi), (hi - lo) / (2 * SIGMAS_AT_LIMIT), size)


def in_zone(rng, diameter: float, count: int, distribution: str) -> np.ndarray:
    """Offsets of points in an ISO 1101 true-position zone.

    Parameters
    ----------
    rng : numpy.random.Generator
    diameter : float
        The zone's diameter.
    count : int
        Points drawn.
    distribution : {"normal", "uniform"}
        uniform over the circle's area, or normal per component with 3 sigma at its radius.

    Returns
    -------
    numpy.ndarray, shape (2, count)
    """
    r_zone = 0.5 * diameter
    if distribution == "uniform":
        r = r_zone * np.sqrt(rng.uniform(0.0, 1.0, count))
        a = rng.uniform(0.0, 2 * math.pi, count)
        return np.stack([r * np.cos(a), r * np.sin(a)])
    return rng.normal(0.0, r_zone / SIGMAS_AT_LIMIT, (2, count))


@dataclass(frozen=True, kw_only=True)
class CycloidDeviation:
    """Deviations of a cycloid disc stage [m]: ``pin_offset`` (2, Zb) each pin centre off its
    place (housing frame; the pin-circle radius error included); ``pin_radius`` (Zb,) each
    pin's radius change; ``profile`` (Za, 2) material added along the normal of each lobe's
    flank that carries a positive (column 0) or negative (column 1) torque;
    ``member_offset`` (2,) the disc's profile off its crank bore(s) (disc frame);
    ``eccentricity`` the crank's eccentricity error (every crank alike: the pins' gaps
    shifted by the discs' move);
    ``crank_eccentricity_m`` (cranks,) each crank's own eccentricity error [m] and
    ``crank_phase_rad`` (cranks,) its direction from the eccentric's [rad] (crank k's
    eccentric at disc j stands at e u(phi_j) + de_k u(phi_j + theta_k); a K-H-V drive has
    one crank, its input shaft), or (cranks, discs) each eccentric's own: the system
    model's crank bearings take them
    (:class:`toothfem.fem.drives.assembly.CycloidSystem`); empty: none (a zero phase where
    only the errors are given)."""
    pin_offset: np.ndarray
    pin_radius: np.ndarray
    profile: np.ndarray
    member_offset: np.ndarray
    eccentricity: float = 0.0
    crank_eccentricity_m: tuple = ()
    crank_phase_rad: tuple = ()

    @classmethod
    def zero(cls, pins: int, lobes: int) -> CycloidDeviation:
        """The stage as designed.

        Parameters
        ----------
        pins : int
            Zb, the pin count.
        lobes : int
            Za, the disc's lobe count.

        Returns
        -------
        CycloidDeviation
            Every deviation zero.
        """
        return cls(pin_offset=np.zeros((2, pins)), pin_radius=np.zeros(pins),
                   profile=np.zeros((lobes, 2)), member_offset=np.zeros(2))


@dataclass(frozen=True, kw_only=True)
class SineDeviation:
    """Deviations of a sine pair [m]: material added along the normal of each flank of the
    planet (Zp, 2) and of the ring (Zr, 2) (column 0, 1: the two flanks of a tooth), and
    the eccentricity error of the crank; ``crank_eccentricity_m`` and ``crank_phase_rad``
    (one value each: the input shaft) as :class:`CycloidDeviation`'s, taken by the system
    model's eccentric bearing."""
    planet_profile: np.ndarray
    ring_profile: np.ndarray
    eccentricity: float = 0.0
    crank_eccentricity_m: tuple = ()
    crank_phase_rad: tuple = ()

    @classmethod
    def zero(cls, planet_teeth: int, ring_teeth: int) -> SineDeviation:
        """The pair as designed.

        Parameters
        ----------
        planet_teeth, ring_teeth : int
            Zp and Zr.

        Returns
        -------
        SineDeviation
            No profile material added, no eccentricity error.
        """
        return cls(planet_profile=np.zeros((planet_teeth, 2)),
                   ring_profile=np.zeros((ring_teeth, 2)))


def only(tolerances, name: str):
    """The reducer built with one tolerance at a time.

    Parameters
    ----------
    tolerances : toothfem.si.TolerancesSI
        Zones and a ``distribution``.
    name : str
        The tolerance kept (a field name without its unit, e.g. ``pin_diameter`` for both
        its limits).

    Returns
    -------
    toothfem.si.TolerancesSI
        Every other zone zero.

    Raises
    ------
    ToothfemError
        For a name that matches no tolerance.
    """
    zones = [f.name for f in fields(tolerances)
             if isinstance(getattr(tolerances, f.name), (int, float))
             and not isinstance(getattr(tolerances, f.name), bool)]
    if not any(z.startswith(name) for z in zones):
        raise ToothfemError(f"no tolerance named {name!r}")
    zero = {z: 0.0 for z in zones if not z.startswith(name)}
    return replace(tolerances, **zero)
