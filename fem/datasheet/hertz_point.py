"""Hertz's elliptic point contact of two bodies under a normal load: the mutual approach,
the semi-axes and the peak pressure (SI: N, m, Pa), exact (complete elliptic integrals) or by
Hamrock & Brewe's closed forms. The formulas, their sources and the accuracy of the closed
forms: docs/tilt.md, section "Model" (the Hertz bullet) and "Sources".
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import ellipk, elliprd

from ...errors import ToothfemError

#: The ways :func:`hertz_point_contact` solves the contact: "exact" (Johnson 1985, Sec. 4.2)
#: or "hamrock_brewe" (Hamrock & Brewe 1983).
HERTZ_METHODS = ("exact", "hamrock_brewe")


@dataclass(frozen=True)
class HertzPoint:
    """Hertz's elliptic contact of two bodies under a normal load (SI)."""

    approach_m: np.ndarray        # mutual approach delta of distant points
    semi_major_m: np.ndarray      # a, along the larger principal radius
    semi_minor_m: np.ndarray      # b
    p_max_Pa: np.ndarray          # 3 Q / (2 pi a b)
    ellipticity: np.ndarray       # k = a / b


def _eccentricity_sq(ratio):
    """m = e^2 of the contact ellipse for alpha_r = R_major / R_minor >= 1 (vectorised
    bisection on t = -ln(1 - m); alpha_r(m) = (3 K(m)/R_D(0, 1-m, 1) - 1)/(1 - m) rises
    monotonically from 1)."""
    ratio = np.asarray(ratio, float)

    def alpha_r(t):
        m = -np.expm1(-t)
        return (3 * ellipk(m) / elliprd(0.0, np.exp(-t), 1.0) - 1.0) * np.exp(t)

    lo = np.zeros_like(ratio)
    hi = np.full_like(ratio, 36.0)          # 1 - m = 2.3e-16: alpha_r ~ 1e15
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        low = alpha_r(mid) < ratio
        lo = np.where(low, mid, lo)
        hi = np.where(low, hi, mid)
    return -np.expm1(-0.5 * (lo + hi))


def hertz_point_contact(load_N, rx_m, ry_m, reduced_modulus_Pa, method: str = "exact"
                        ) -> HertzPoint:
    """Hertz's elliptic point contact: approach, semi-axes and peak pressure.

    Parameters
    ----------
    load_N : array_like
        Normal load Q [N], >= 0.
    rx_m, ry_m : array_like
        Effective principal radii of relative curvature [m] (1/R = 1/R_body1 + 1/R_body2 in
        each principal plane; a concave body's radius negative), > 0.
    reduced_modulus_Pa : float
        E* [Pa], 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Hamrock's E' is 2 E*).
    method : str
        "exact": complete elliptic integrals (Johnson 1985, Sec. 4.2, through scipy.special);
        "hamrock_brewe": the closed forms of Hamrock & Brewe (1983).

    Returns
    -------
    HertzPoint
        Approach [m], semi-major and semi-minor axes [m], peak pressure [Pa] and a/b, each in
        the broadcast shape of the inputs.
    """
    q = np.maximum(np.asarray(load_N, float), 0.0)
    rx, ry = np.broadcast_arrays(np.asarray(rx_m, float), np.asarray(ry_m, float))
    if np.any(rx <= 0) or np.any(ry <= 0):
        raise ToothfemError("hertz_point_contact: the radii of relative curvature must be > 0")
    r_major, r_minor = np.maximum(rx, ry), np.minimum(rx, ry)
    ratio = r_major / r_minor
    es = float(reduced_modulus_Pa)
    if method == "exact":
        m = _eccentricity_sq(ratio)
        kk = ellipk(m)
        rd = elliprd(0.0, 1.0 - m, 1.0)
        # a^3 = 3 Q R_major (K - E)/(pi E* m) = Q R_major R_D(0, 1-m, 1)/(pi E*)
        a = np.cbrt(q * r_major * rd / (np.pi * es))
        b = a * np.sqrt(1.0 - m)
        delta = np.where(a > 0, 3 * q * kk / (2 * np.pi * np.where(a > 0, a, 1.0) * es), 0.0)
        k = 1.0 / np.sqrt(1.0 - m)
    elif method == "hamrock_brewe":
        qa = np.pi / 2 - 1.0
        k = ratio ** (2 / np.pi)
        e_bar = 1.0 + qa / ratio
        f_bar = np.pi / 2 + qa * np.log(ratio)
        r = 1.0 / (1.0 / rx + 1.0 / ry)
        e_prime = 2 * es
        a = np.cbrt(6 * k * k * e_bar * q * r / (np.pi * e_prime))
        b = np.cbrt(6 * e_bar * q * r / (np.pi * k * e_prime))
        delta = f_bar * np.cbrt(9 / (2 * e_bar * r) * (q / (np.pi * k * e_prime)) ** 2)
    else:
        raise ToothfemError(f"hertz method {method!r}: one of {HERTZ_METHODS}")
    ab = a * b
    p = np.where(ab > 0, 3 * q / (2 * np.pi * np.where(ab > 0, ab, 1.0)), 0.0)
    return HertzPoint(delta, a, b, p, k)
