"""The cycle mode's local contact law: each candidate's approach per force [m per N/m] that
the influence tables leave out (the Hertz approach at its half-width b(F), for conventional
pins the pin's own compliance), as a function of the contact forces. Why the centre's
approach differs from the tables' mean approach: docs/derivations.md, section 6.
"""
from __future__ import annotations

import math

import numpy as np

from ..elastic import plane_modulus
from ..hertz import line_half_width
from .model import _Position, strip_width_correction

#: A body's approach at the centre of a Hertzian strip less its pressure-weighted mean,
#: per unit force per length, times E': 1/(2 pi) (docs/derivations.md, 6).
CENTRE_APPROACH = 1 / (2 * math.pi)


def local_law(model, pin, b_ref: float, q: _Position, q_load: float):
    """Each candidate's local approach per force of one position, as a function of the
    forces alone (what does not depend on them taken once): the Hertz approach at the
    half-width b(F) less the strips of the influence tables, and, for conventional pins, the
    pin's own compliance (a secant: the approach is this times the force).

    Parameters
    ----------
    model : CycloidFEModel
        The disc's model (its pin structure, moduli).
    pin : PinModel or None
        The conventional pin's compliance model (None for the other structures).
    b_ref : float
        The patch half-width of the disc's influence tables [m].
    q : _Position
        One position's candidates.
    q_load : float
        The member torque per length [N m/m] (its sign picks the carrying flank).

    Returns
    -------
    callable
        lam (..., C) [N/m] -> (..., C) [m per N/m] (an unloaded candidate: the width of
        the mean load).
    """
    m = model
    e_p = m.e_plane
    # the tables measure each body's pressure-weighted mean approach; the gap closes at
    # the contact's centre, F/(2 pi E') further per elastic body (docs/derivations.md 6)
    fixed = CENTRE_APPROACH * (1 if m.pin_structure == "rigid" else 2) / e_p
    strips = [(b_ref, e_p)]                      # the disc's strip of b_ref
    if m.pin_structure == "integral":           # housing tooth: strip of b_ref/2
        strips.append((b_ref / 2, e_p))
    elif m.pin_structure == "conventional":     # the pin's table and its strip
        fixed = fixed + np.interp(q.gamma, pin.angles, pin.table)
        strips.append((pin.b_ref, plane_modulus(pin.youngs_modulus, pin.poisson_ratio,
                                                pin.plane)))
    mean, r_eq, e_star = _mean_load(q_load, q.arm), np.abs(q.r_eq), m.e_star

    def law(lam):
        lam = np.asarray(lam, float)
        b = line_half_width(np.where(lam > 0, lam, mean), r_eq, e_star)
        return fixed + sum(strip_width_correction(b, ref, e) for ref, e in strips)
    return law


def _mean_load(q_load, arm) -> float:
    """The force per length [N/m] an unloaded candidate's half-width is taken at: the
    member's load shared over the carrying flank's arms."""
    carry = (arm < 0) if q_load > 0 else (arm > 0)
    return abs(q_load) / np.sum(np.abs(arm[carry])) if np.any(carry) else abs(q_load)
