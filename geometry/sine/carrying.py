"""Load-carrying contact at every crank angle: a LOWER bound on the tooth height.

Over one mesh period the conjugate contact runs over both flanks of a tooth, so it carries
the output torque (negative moment arm) for only part of the period; the rest must come
from the drive flanks of the neighbouring teeth. Low teeth leave crank angles where no
drive flank is near (the analytic split then has no contact to load, the FE cycle mode no
hat to select): such a pair is refused with the smallest tooth height that works
(:func:`check_load_carrying`, applied by the case model to a reducer's sine stage).
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ...errors import GeometryError, check_range
from ..vectors import cross, dot, perp, unit
from .conjugate import _ring
from .limits import _largest_valid, tooth_height_limits
from .meshing import DEFAULT_CANDIDATES, _candidate_points, _placed
from .pair import SineGearPair
from .profile import ProfileParams, profile_params
from ...units import UM_PER_M

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


def _drive_gap(g: ProfileParams, chi) -> np.ndarray:
    """(P,) smallest gap of a flank that can carry the output torque at crank angles chi: a
    gap minimum of its own (the conjugate contact: gap 0) with a negative moment arm
    (:func:`meshing`'s convention); inf where there is none."""
    chi = np.atleast_1d(np.asarray(chi, float))
    k = min(DEFAULT_CANDIDATES, (g.z1 - 1) // 2)        # the teeth meshing() looks at
    with np.errstate(all="ignore"):
        _, _, chi2, f1, f2, own, conj = _candidate_points(g, chi, k)
        K1 = _placed(g, chi2, f1, 0)[0]
        X, X1 = _ring(g, f2, 1)[:2]
        n = perp(X1) / np.hypot(X1[0], X1[1])
        gap = np.where(conj, 0.0, dot(K1 - X, n))
        arm = cross(K1 - g.a0 * unit(chi2), n)
    carry = own & (arm < -_CARRY_ARM_REL * g.r1)
    return np.min(np.where(carry, gap, np.inf), axis=1)


@lru_cache(maxsize=256)
def max_drive_gap_m(g: ProfileParams) -> float:
    """Largest, over a mesh period, of the smallest gap of a load-carrying flank: a grid,
    then nested grids around the worst positions.

    Parameters
    ----------
    g : ProfileParams
        The pair.

    Returns
    -------
    float
        The gap [m]; inf where some crank angle has no load-carrying flank.
    """
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


def _carries(g: ProfileParams) -> bool:
    return max_drive_gap_m(g) <= LOAD_CARRYING_GAP_M


@lru_cache(maxsize=64)
def min_tooth_height_m(planet_teeth: int, ring_teeth: int, module_m: float) -> float:
    """Smallest tooth height a with a drive flank within LOAD_CARRYING_GAP_M at every crank
    angle, by scan and bisection (the largest gap falls as a grows), to _CARRY_RTOL*m above.

    Parameters
    ----------
    planet_teeth, ring_teeth : int
        Tooth numbers z1, z2.
    module_m : float
        Module [m].

    Returns
    -------
    float
        Tooth height [m]; the upper bound :func:`tooth_height_limits` ``.max`` itself if no
        tooth height works.
    """
    z1, z2, m = int(planet_teeth), int(ring_teeth), float(module_m)
    top = tooth_height_limits(z1, z2, m).max
    lo = _largest_valid(lambda g: not _carries(g), z1, z2, m, top, rtol=_CARRY_RTOL)
    return top if lo >= top else min(lo + _CARRY_RTOL * m, top)


def check_load_carrying(pair: SineGearPair) -> SineGearPair:
    """The pair if a drive flank is within LOAD_CARRYING_GAP_M at every crank angle.

    Not part of the pair's own validation (a pair with low teeth is a valid shape); the case
    model applies it to a reducer's sine stage.

    Parameters
    ----------
    pair : SineGearPair
        The pair to check.

    Returns
    -------
    SineGearPair
        ``pair`` itself.

    Raises
    ------
    GeometryError
        Naming tooth_height_m, its value and the valid range (the lower bound
        :func:`min_tooth_height_m`) when some crank angle has no carrying flank.
    """
    g = profile_params(pair)
    if _carries(g):
        return pair
    lo = min_tooth_height_m(g.z1, g.z2, g.m)
    hi = tooth_height_limits(g.z1, g.z2, g.m).max
    check_range("tooth_height_m", g.a, max(lo, g.a), hi, lo_open=lo <= g.a, hi_open=True,
                error=GeometryError,
                why=f"at some crank angles no drive flank is within "
                    f"{LOAD_CARRYING_GAP_M * UM_PER_M:g} um to carry the torque (lower bound by "
                    "bisection" + ("; none of these tooth numbers and module works)"
                                   if lo >= hi else ")"))
    return pair
