"""Force laws of the system model's elastic elements: linear springs and the radial
rolling-element bearing with play, roller by roller (docs/stiffness.md, "The system
model"). SI units: N, m, rad.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..datasheet.supports import PALMGREN_LINE_MM
from .solve import Linear
from ...units import MM_PER_M

#: Every bearing also carries this linear stiffness [N/m] beside its rollers: the rollers'
#: law has zero slope at zero load and none inside the play, where nothing else would hold
#: the body. 1e3 N/m moves a body held by its rollers (1e8-1e9 N/m) by 1e-6 of its
#: deflection, and a body floating in its play by 1 um per mN.
BEARING_HOLD_N_PER_M = 1e3
#: Palmgren's exponent of a roller's line contact: delta ~ Q^0.9, Q ~ delta^(10/9).
LINE_EXPONENT = 1 / 0.9


def linear(stiffness):
    """A linear law f = K delta.

    Parameters
    ----------
    stiffness : array_like, shape (d, d) or scalar
        K [N/m, N m/rad, ...].

    Returns
    -------
    toothfem.fem.system.solve.Linear
        delta (d,) -> (f (d,), K (d, d)); the solver assembles it once per solve.
    """
    return Linear(stiffness)


class Scaled:
    """A law with its force and tangent scaled: f = s f_law(delta), K = s K_law(delta)
    (a part stiffer or softer than its model by the factor s, e.g. fitted to a rig); the
    law's ``homogeneity`` kept.

    Parameters
    ----------
    law : callable
        delta -> (f, K), batched over leading axes as the law is.
    factor : float
        s, > 0.
    """

    def __init__(self, law, factor: float):
        if not (math.isfinite(factor) and factor > 0):
            raise ValueError(f"factor = {factor!r}: > 0 and finite")
        self.law, self.factor = law, float(factor)
        self.homogeneity = getattr(law, "homogeneity", 1.0)

    def __call__(self, delta):
        """(s f, s K) at the deformation.

        Parameters
        ----------
        delta : array_like
            As the law takes it.

        Returns
        -------
        force, tangent : numpy.ndarray
        """
        f, k = self.law(delta)
        return self.factor * f, self.factor * k


def scaled(law, factor: float):
    """A law ``factor`` times as stiff: a linear law stays linear (the solver assembles it
    once), any other is wrapped (:class:`Scaled`); a factor of 1 returns the law itself.

    Parameters
    ----------
    law : Linear or callable
    factor : float
        > 0.

    Returns
    -------
    Linear or Scaled or the law
    """
    if factor == 1.0:
        return law
    if isinstance(law, Linear):
        if not (math.isfinite(factor) and factor > 0):
            raise ValueError(f"factor = {factor!r}: > 0 and finite")
        return Linear(law.k * factor)
    return Scaled(law, factor)


def roller_constant(length_m: float) -> float:
    """K_n [N/m^(10/9)] of one roller between two raceways, Q = K_n delta^(10/9): Palmgren's
    approach delta = 3.84e-5 Q^0.9 / l^0.8 [mm, N] on each raceway (Harris & Kotzalas,
    Essential Concepts of Bearing Technology, 5th ed., 2007, Sec. 6.4), two in series.

    Parameters
    ----------
    length_m : float
        Effective roller length l [m].

    Returns
    -------
    float
        [N m^(-10/9)].
    """
    # delta_mm = 2 c Q^0.9 / l_mm^0.8  ->  Q = (delta_m 1e3 l_mm^0.8 / (2 c))^(1/0.9)
    return (MM_PER_M * (length_m * MM_PER_M) ** 0.8 / (2 * PALMGREN_LINE_MM)) ** LINE_EXPONENT


@dataclass(frozen=True)
class RollerBearing:
    """A radial roller (or needle) bearing: Z rollers of effective length l at contact angle
    alpha (0 for cylindrical and needle rollers), diametral play c (> 0 clearance, < 0
    preload), the rollers at angles 2 pi j / Z + ``cage_rad`` in the frame the deformation
    is given in. The deformation delta (2,) is the inner ring's displacement against the
    outer ring; roller j is compressed by delta . u_j cos(alpha) - c/2 and pushes back
    with Q_j = K_n (that)^(10/9) (Harris & Kotzalas 2007, Sec. 7.2: the load of each
    rolling element from the rings' relative displacement). The force is the sum of
    Q_j cos(alpha) u_j, the rings' mutual force along delta."""
    rollers: int
    length_m: float
    play_m: float = 0.0
    contact_angle_rad: float = 0.0
    cage_rad: float = 0.0

    def __post_init__(self):
        if int(self.rollers) != self.rollers or self.rollers < 3:
            raise ValueError(f"rollers = {self.rollers!r}: at least 3 (an integer)")
        if not (self.length_m > 0 and math.isfinite(self.length_m)):
            raise ValueError(f"length_m = {self.length_m!r}: > 0 and finite")

    #: f(t delta) = t^a f(delta) without play (the solver's secant steps from rest)
    homogeneity = LINE_EXPONENT

    @cached_property
    def directions(self) -> np.ndarray:
        """(2, Z) unit vectors toward each roller."""
        a = 2 * math.pi * np.arange(self.rollers) / self.rollers + self.cage_rad
        return np.stack([np.cos(a), np.sin(a)])

    def roller_loads(self, delta) -> np.ndarray:
        """Each roller's load.

        Parameters
        ----------
        delta : array_like, shape (2,)
            The inner ring's displacement against the outer [m].

        Returns
        -------
        numpy.ndarray, shape (Z,)
            Q_j [N].
        """
        ca = math.cos(self.contact_angle_rad)
        squeeze = np.asarray(delta, float) @ self.directions * ca - 0.5 * self.play_m
        return roller_constant(self.length_m) * np.maximum(squeeze, 0.0) ** LINE_EXPONENT

    def __call__(self, delta):
        """The rings' mutual force and its tangent.

        Parameters
        ----------
        delta : array_like, shape (2,) or (B, 2)
            The inner ring's displacement against the outer [m] (B bearings alike at once).

        Returns
        -------
        force : numpy.ndarray, shape (2,) or (B, 2)
            [N], along the deformation's conjugate (the element's internal force).
        tangent : numpy.ndarray, shape (2, 2) or (B, 2, 2)
            [N/m].
        """
        ca = math.cos(self.contact_angle_rad)
        u = self.directions
        delta = np.asarray(delta, float)
        squeeze = np.maximum(delta @ u * ca - 0.5 * self.play_m, 0.0)       # (..., Z)
        kn = roller_constant(self.length_m)
        q = kn * squeeze ** LINE_EXPONENT
        dq = kn * LINE_EXPONENT * squeeze ** (LINE_EXPONENT - 1)
        force = ca * (q @ u.T) + BEARING_HOLD_N_PER_M * delta
        tangent = ca * ca * np.einsum("...z,iz,jz->...ij", dq, u, u) \
            + BEARING_HOLD_N_PER_M * np.eye(2)
        return force, tangent
