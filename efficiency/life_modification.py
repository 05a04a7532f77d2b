"""Modified rating life of radial rolling bearings, L_nm = a1 a_ISO L10 (ISO 281:2007).

ISO 281:2007, "Rolling bearings - Dynamic load ratings and rating life", clause 9
("modified rating life"), and what is taken from it here:

* the modified rating life L_nm = a1 a_ISO L10 (:func:`modified_life`), L10 the basic
  rating life (efficiency/bearings.py);
* a1, the life modification factor for reliability, ISO 281:2007 Table 12
  (:func:`reliability_factor`): 1 at 90 %, 0.64 at 95 %, 0.55 at 96 %, 0.47 at 97 %,
  0.37 at 98 %, 0.25 at 99 % (as quoted by public code: a JavaScript bearing calculator
  and a Python ISO 281 data module in the search index). Computed here from the Weibull
  expression a1 = 0.95 [ln(1/R) / ln(1/0.9)]^(2/3) + 0.05 (Weibull slope 1.5, a
  failure-free life of 0.05 L10; the derivation ISO/TR 1281-2 is said to give, not read
  here), which gives every one of those printed values to its printed digit (tests). The
  same expression without the 0.05 floor, [ln(1/R)/ln(1/0.9)]^(2/3), gives the older
  values 0.62, 0.53, 0.44, 0.33, 0.21 that SKF catalogues still print (tests).
* a_ISO, the life modification factor for the systems approach (clause 9.3; equations as
  numbered in a public implementation of the standard: (31)-(33) ball, (34)-(36) roller),
  for radial bearings (:func:`a_iso`), with x = e_C C_u / P:

  - radial ball bearings:
    a_ISO = 0.1 [1 - (2.5671 - c/kappa^q)^0.83 x^(1/3)]^(-9.3);
  - radial roller bearings:
    a_ISO = 0.1 [1 - (1.5859 - c/kappa^q) x^0.4]^(-9.185);

  (c, q) by viscosity ratio: 0.1 <= kappa < 0.4: c = 2.2649 ball, 1.3993 roller,
  q = 0.054381; 0.4 <= kappa < 1: c = 1.9987 ball, 1.2348 roller, q = 0.19087;
  1 <= kappa <= 4: c = 1.9987 ball, 1.2348 roller, q = 0.071739 (:data:`A_ISO_BANDS`).
  kappa > 4 is taken as 4 (the standard, and SKF: "if kappa > 4, use curve for
  kappa = 4"); below 0.1 the method does not apply: the value at 0.1 is returned and a
  :class:`LifeModificationWarning` issued. a_ISO is capped at 50 (:data:`A_ISO_MAX`); a
  bracket <= 0 (the series' pole) is that cap too. Sources of the constants (public code
  in the search index; the standard's text was not available):

  - ball: all constants in three unrelated implementations (a Rust ISO 281/16281 solver
    that numbers the equations, two Python bearing modules), except the middle-band
    exponent q, 0.19087 in the first and 0.019087 in both others. 0.19087 is used: the
    roller middle band has 0.19087 in every source (one of those two Python modules
    included), and only 0.19087 makes the ball pieces meet at kappa = 0.4 (with 0.019087
    the kappa term would jump from 0.186 to 0.533 there, a_ISO at e_C C_u/P = 0.1 from
    0.31 to 2.0);
  - roller: all constants in two Python implementations (a wind-turbine bearing script, a
    Python ISO 281 data module); the first applies the kappa term with exponent 1, the
    second raises it to 0.4 as well. Exponent 1 is used (the form as recalled from the
    standard); no third source was found to decide it.

  With these constants the pieces meet: at kappa = 0.4 the kappa terms of the two bands
  differ by 7.1e-5 of 0.186 (ball) and 7.5e-7 of 0.115 (roller), a_ISO by at most 0.28 %
  (ball) and 2.4e-5 (roller) below the cap; at kappa = 1 the two bands are the same
  expression (no step). At kappa = 0.1 the kappa term is ~0 (7.5e-5 ball,
  -5.9e-5 roller), so a_ISO is the floor 0.1 there at any load (to +0.6 % ball, -0.1 %
  roller for e_C C_u/P up to 5); and as e_C C_u/P -> 0, a_ISO -> 0.1 at every kappa, as
  SKF states for its diagrams ("as eta_c Pu/P tends to zero, a_SKF tends to 0.1 for all
  values of kappa").
* the viscosity ratio kappa = nu / nu1 (:func:`viscosity_ratio`) with the rated viscosity
  nu1 = 45 000 n^-0.83 D_pw^-0.5 mm^2/s for n < 1 000 r/min and
  nu1 = 4 500 n^-0.5 D_pw^-0.5 for n >= 1 000 r/min (D_pw in mm), the closed form of the
  standard's nu1 diagram, as three public implementations give it. The two branches do
  not meet: at 1 000 r/min the first gives 2.3 % more than the second. Note that SKF's
  catalogue diagram and its online calculator give nu1 15-17 % below this formula
  (8.15 mm^2/s at 3 000 r/min, d_m = 72.5 mm, against 9.65; 10.4 at 1 800 r/min against
  12.5); the ISO formula is used here.
* the contamination factor e_C, ISO 281:2007 Table 13, guide values by contamination
  level and D_pw < 100 mm / >= 100 mm (:data:`CONTAMINATION_TABLE`, as quoted by the
  MESYS manual, SKF's table of eta_c and a public Python ISO 281 module, all agreeing).
  The table gives ranges; :func:`contamination_factor` returns the middle of the range
  unless asked for an end. The standard's Annex A formulae (e_C from kappa, D_pw and the
  ISO 4406 oil cleanliness code or the grease cleanliness class) are not implemented: only
  one public source for their constants was found (an SKF catalogue quoting ISO 281), so
  they could not be verified.
* the fatigue load limit C_u estimated from the static rating, ISO 281:2007 Annex B,
  simplified method (:func:`fatigue_load_limit_N`): ball bearings C_u = C_0 / 22 for
  D_pw <= 100 mm, C_0 / 22 (100 / D_pw)^0.5 above; roller bearings C_u = C_0 / 8.2, and
  C_0 / 8.2 (100 / D_pw)^0.3 above (equations (B.18)-(B.20) as a public implementation
  numbers them). The ball rule and the roller divisor 8.2 are in two public sources; the
  roller size exponent 0.3 in none found (as recalled; not confirmed).
  Annex B says its detailed method (from the internal geometry and the 1 500 MPa contact
  stress) takes precedence over this estimate. Check against a maker's value: SKF 6309,
  C_0 = 31.5 kN, d_m = 72.5 mm, catalogue P_u = 1.34 kN; C_0/22 = 1.43 kN (+7 %).

Not covered: thrust bearings (their own a_ISO constants and C_u), the EP-additive rule
(kappa < 1 and e_C >= 0.2 with proven EP additives: kappa = 1 may be used with
a_ISO <= 3), and the Annex A e_C formulae.

SI at the interface (m, N, m^2/s, r/min); millimetres and mm^2/s only inside the
standard's formulas. Functions take scalars or numpy arrays (broadcast) and return a float
for scalar input.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import ToothfemError, check_range
from .rating import BALL_TYPES, BEARING_TYPES
from ..units import MM2_PER_M2, MM_PER_M

#: Speed [r/min] at which the rated-viscosity formula changes branch (ISO 281:2007).
NU1_BRANCH_RPM = 1000.0
#: Rated viscosity nu1 [mm^2/s] = coefficient * n^exponent * D_pw[mm]^-0.5, by branch:
#: n < 1 000 r/min and n >= 1 000 r/min.
NU1_LOW_SPEED = (45000.0, -0.83)
NU1_HIGH_SPEED = (4500.0, -0.5)

#: Valid range of the viscosity ratio for a_ISO (ISO 281:2007): below 0.1 the method does
#: not apply (value at 0.1 returned, with a warning), above 4 kappa = 4 is used.
KAPPA_RANGE = (0.1, 4.0)
#: Upper limit of a_ISO (ISO 281:2007).
A_ISO_MAX = 50.0
#: a_ISO constants, radial bearings: family -> (A, exponent on the kappa term,
#: exponent on x = e_C C_u / P, outer exponent); a_ISO = 0.1 [1 - (A - c/kappa^q)^m x^s]^-w.
A_ISO_FORM = {"ball": (2.5671, 0.83, 1.0 / 3.0, 9.3),
              "roller": (1.5859, 1.0, 0.4, 9.185)}
#: kappa bands of a_ISO: (lower kappa, c ball, c roller, q); a band runs up to the next
#: lower bound (the last to kappa = 4 inclusive).
A_ISO_BANDS = ((0.1, 2.2649, 1.3993, 0.054381),
               (0.4, 1.9987, 1.2348, 0.19087),
               (1.0, 1.9987, 1.2348, 0.071739))

#: Fatigue load limit estimate, ISO 281:2007 Annex B simplified method: family ->
#: (C_0 / C_u below the reference pitch diameter, size exponent above it).
CU_SIMPLIFIED = {"ball": (22.0, 0.5), "roller": (8.2, 0.3)}
#: Reference pitch diameter [mm] of the Annex B size factor (100 / D_pw)^k.
CU_REFERENCE_DPW_MM = 100.0

#: Contamination factor e_C, ISO 281:2007 Table 13: level -> ((low, high) for
#: D_pw < 100 mm, (low, high) for D_pw >= 100 mm).
CONTAMINATION_TABLE = {
    "extreme_cleanliness": ((1.0, 1.0), (1.0, 1.0)),
    "high_cleanliness": ((0.6, 0.8), (0.8, 0.9)),
    "normal_cleanliness": ((0.5, 0.6), (0.6, 0.8)),
    "slight_contamination": ((0.3, 0.5), (0.4, 0.6)),
    "typical_contamination": ((0.1, 0.3), (0.2, 0.4)),
    "severe_contamination": ((0.0, 0.1), (0.0, 0.1)),
    "very_severe_contamination": ((0.0, 0.0), (0.0, 0.0)),
}
#: Pitch diameter [mm] that splits the columns of Table 13 (< 100 mm, >= 100 mm).
CONTAMINATION_SPLIT_DPW_MM = 100.0
#: Which value of a Table 13 range :func:`contamination_factor` returns.
RANGE_POINTS = ("middle", "lower", "upper")

#: Reliability range of ISO 281:2007 Table 12 [-].
RELIABILITY_RANGE = (0.90, 0.9995)
#: Weibull slope and failure-free life fraction of the expression that reproduces Table 12.
A1_WEIBULL_SLOPE = 1.5
A1_FLOOR = 0.05


class LifeModificationWarning(UserWarning):
    """An input outside the range where ISO 281's a_ISO method applies (kappa < 0.1)."""


def _family(bearing_type):
    if bearing_type not in BEARING_TYPES:
        raise ToothfemError(f"bearing_type = {bearing_type!r} is not one of "
                            f"{', '.join(BEARING_TYPES)}")
    return "ball" if bearing_type in BALL_TYPES else "roller"


def _checked(name, value, lo=None, hi=None, *, lo_open=False, hi_open=False, why=""):
    """``value`` as a float array, every element checked by :func:`check_range` (the first
    bad one is reported by name, value and range)."""
    if np.ndim(value) == 0:
        return np.asarray(float(check_range(name, value, lo, hi, lo_open=lo_open,
                                            hi_open=hi_open, why=why)))
    arr = np.asarray(value)
    if arr.dtype.kind not in "iuf":
        raise ToothfemError(f"{name} = {value!r} is not an array of numbers")
    arr = arr.astype(float)
    bad = ~np.isfinite(arr)
    if lo is not None:
        bad |= arr <= lo if lo_open else arr < lo
    if hi is not None:
        bad |= arr >= hi if hi_open else arr > hi
    if np.any(bad):                 # the first bad element raises, naming the parameter
        check_range(name, float(arr[bad].ravel()[0]), lo, hi, lo_open=lo_open,
                    hi_open=hi_open, why=why)
    return arr


def _out(x):
    x = np.asarray(x, float)
    return float(x) if x.ndim == 0 else x


def rated_viscosity_m2_s(speed_rpm, pitch_diameter_m):
    """Rated kinematic viscosity nu1 for adequate lubrication (ISO 281:2007).

    nu1 = 45 000 n^-0.83 D_pw^-0.5 mm^2/s for n < 1 000 r/min,
    nu1 = 4 500 n^-0.5 D_pw^-0.5 mm^2/s for n >= 1 000 r/min, D_pw in mm.

    Parameters
    ----------
    speed_rpm : float or array_like
        Rotational speed n [r/min], > 0.
    pitch_diameter_m : float or array_like
        Pitch diameter of the rolling-element set D_pw [m], > 0 (the mean diameter
        (d + D)/2 of catalogues where D_pw is not given).

    Returns
    -------
    float or numpy.ndarray
        nu1 [m^2/s].

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for a non-positive or non-finite speed or
        pitch diameter.
    """
    n = _checked("speed_rpm", speed_rpm, 0.0, lo_open=True)
    d = _checked("pitch_diameter_m", pitch_diameter_m, 0.0, lo_open=True) * MM_PER_M
    (a_lo, e_lo), (a_hi, e_hi) = NU1_LOW_SPEED, NU1_HIGH_SPEED
    nu1 = np.where(n < NU1_BRANCH_RPM, a_lo * n ** e_lo, a_hi * n ** e_hi) / np.sqrt(d)
    return _out(nu1 / MM2_PER_M2)


def viscosity_ratio(nu_m2_s, speed_rpm, pitch_diameter_m):
    """Viscosity ratio kappa = nu / nu1 (ISO 281:2007), nu1 by
    :func:`rated_viscosity_m2_s`.

    Parameters
    ----------
    nu_m2_s : float or array_like
        Kinematic viscosity of the lubricant at the operating temperature [m^2/s] (for
        grease, of its base oil), > 0.
    speed_rpm : float or array_like
        Rotational speed n [r/min], > 0.
    pitch_diameter_m : float or array_like
        Pitch diameter D_pw [m], > 0.

    Returns
    -------
    float or numpy.ndarray
        kappa [-], not clamped (:func:`a_iso` clamps it to [0.1, 4]).

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for a non-positive or non-finite input.
    """
    nu = _checked("nu_m2_s", nu_m2_s, 0.0, lo_open=True)
    return _out(nu / np.asarray(rated_viscosity_m2_s(speed_rpm, pitch_diameter_m)))


def fatigue_load_limit_N(bearing_type, static_rating_N, pitch_diameter_m):
    """Fatigue load limit C_u estimated from the basic static load rating, ISO 281:2007
    Annex B, simplified method.

    Ball bearings: C_u = C_0/22 for D_pw <= 100 mm, C_0/22 (100/D_pw)^0.5 above; roller
    bearings: C_u = C_0/8.2, and C_0/8.2 (100/D_pw)^0.3 above (D_pw in mm). Annex B's
    detailed method, or the maker's catalogue value, takes precedence over this estimate.

    Parameters
    ----------
    bearing_type : str
        "ball", "angular_ball" (radial ball) or "cylindrical", "tapered", "needle"
        (radial roller).
    static_rating_N : float or array_like
        Basic static radial load rating C_0r [N], > 0.
    pitch_diameter_m : float or array_like
        Pitch diameter D_pw [m], > 0.

    Returns
    -------
    float or numpy.ndarray
        C_u [N].

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for an unknown type or a non-positive
        rating or pitch diameter.
    """
    divisor, k = CU_SIMPLIFIED[_family(bearing_type)]
    c0 = _checked("static_rating_N", static_rating_N, 0.0, lo_open=True)
    d = _checked("pitch_diameter_m", pitch_diameter_m, 0.0, lo_open=True) * MM_PER_M
    size = np.minimum(1.0, CU_REFERENCE_DPW_MM / d) ** k
    return _out(c0 / divisor * size)


def contamination_factor(level, pitch_diameter_m, kappa=None, *, point="middle"):
    """Contamination factor e_C, ISO 281:2007 Table 13 (guide values).

    The table gives a range for most levels; the middle of the range is returned unless
    ``point`` asks for an end. Columns: D_pw < 100 mm and D_pw >= 100 mm.

    ===========================  =============  ==============
    level                        D_pw < 100 mm  D_pw >= 100 mm
    ===========================  =============  ==============
    extreme_cleanliness          1              1
    high_cleanliness             0.6 to 0.8     0.8 to 0.9
    normal_cleanliness           0.5 to 0.6     0.6 to 0.8
    slight_contamination         0.3 to 0.5     0.4 to 0.6
    typical_contamination        0.1 to 0.3     0.2 to 0.4
    severe_contamination         0 to 0.1       0 to 0.1
    very_severe_contamination    0              0
    ===========================  =============  ==============

    Parameters
    ----------
    level : str
        One of the keys of :data:`CONTAMINATION_TABLE` (above).
    pitch_diameter_m : float
        Pitch diameter D_pw [m], > 0.
    kappa : float, optional
        Viscosity ratio [-], >= 0. Not used by Table 13 (the standard's Annex A formulae
        use it; they are not implemented, see the module docstring); checked if given.
    point : str
        "middle" (default), "lower" or "upper": which value of the range.

    Returns
    -------
    float
        e_C [-], 0 to 1.

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for an unknown level or point, a
        non-positive pitch diameter or a negative kappa.
    """
    if level not in CONTAMINATION_TABLE:
        raise ToothfemError(f"level = {level!r} is not one of "
                            f"{', '.join(CONTAMINATION_TABLE)} (ISO 281:2007 Table 13)")
    if point not in RANGE_POINTS:
        raise ToothfemError(f"point = {point!r} is not one of {', '.join(RANGE_POINTS)}")
    d = float(check_range("pitch_diameter_m", pitch_diameter_m, 0.0, lo_open=True))
    if kappa is not None:
        check_range("kappa", kappa, 0.0)
    small, large = CONTAMINATION_TABLE[level]
    lo, hi = small if d * MM_PER_M < CONTAMINATION_SPLIT_DPW_MM else large
    return {"middle": 0.5 * (lo + hi), "lower": lo, "upper": hi}[point]


def a_iso(bearing_type, kappa, e_c, fatigue_load_limit_N, equivalent_load_N):
    """Life modification factor a_ISO of a radial bearing, ISO 281:2007 (clause 9.3).

    Ball: a_ISO = 0.1 [1 - (2.5671 - c/kappa^q)^0.83 (e_C C_u/P)^(1/3)]^-9.3; roller:
    a_ISO = 0.1 [1 - (1.5859 - c/kappa^q) (e_C C_u/P)^0.4]^-9.185, (c, q) by kappa band
    (:data:`A_ISO_BANDS`). kappa > 4 is taken as 4; kappa < 0.1 is outside the method:
    the value at 0.1 is returned and a :class:`LifeModificationWarning` issued. The
    result is capped at 50.

    Parameters
    ----------
    bearing_type : str
        "ball", "angular_ball" (radial ball) or "cylindrical", "tapered", "needle"
        (radial roller).
    kappa : float or array_like
        Viscosity ratio nu/nu1 [-], >= 0 (:func:`viscosity_ratio`).
    e_c : float or array_like
        Contamination factor [-], 0 to 1 (:func:`contamination_factor`).
    fatigue_load_limit_N : float or array_like
        Fatigue load limit C_u [N], > 0 (catalogue, or :func:`fatigue_load_limit_N`).
    equivalent_load_N : float or array_like
        Dynamic equivalent load P [N], > 0.

    Returns
    -------
    float or numpy.ndarray
        a_ISO [-], 0.1 (roller at kappa = 0.1: up to 0.1 % less) to 50.

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for an unknown type, a negative or
        non-finite kappa, e_C outside [0, 1], or a non-positive C_u or P.

    Warns
    -----
    LifeModificationWarning
        If any kappa < 0.1.
    """
    a, m, s, w = A_ISO_FORM[_family(bearing_type)]
    roller = bearing_type not in BALL_TYPES
    k = _checked("kappa", kappa, 0.0)
    ec = _checked("e_c", e_c, 0.0, 1.0, why="ISO 281:2007 Table 13")
    cu = _checked("fatigue_load_limit_N", fatigue_load_limit_N, 0.0, lo_open=True)
    p = _checked("equivalent_load_N", equivalent_load_N, 0.0, lo_open=True)
    k_lo, k_hi = KAPPA_RANGE
    if np.any(k < k_lo):
        warnings.warn(f"a_iso: kappa = {float(np.min(k)):.4g} is below {k_lo:g}, where the "
                      "ISO 281:2007 a_ISO method does not apply; the value at kappa = "
                      f"{k_lo:g} is returned", LifeModificationWarning, stacklevel=2)
    k = np.clip(k, k_lo, k_hi)
    c = np.zeros_like(k)
    q = np.zeros_like(k)
    for lower, c_ball, c_roller, q_band in A_ISO_BANDS:
        here = k >= lower
        c = np.where(here, c_roller if roller else c_ball, c)
        q = np.where(here, q_band, q)
    term = a - c / k ** q
    if not roller:              # ~7.5e-5 at kappa = 0.1; never negative, but guard the
        term = np.maximum(term, 0.0)    # fractional power against rounding
    x = ec * cu / p
    bracket = 1.0 - term ** m * x ** s
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(bracket > 0.0, 0.1 * np.where(bracket > 0.0, bracket, 1.0) ** -w,
                         A_ISO_MAX)
    return _out(np.minimum(value, A_ISO_MAX))


def reliability_factor(reliability=0.9):
    """Life modification factor for reliability a1, ISO 281:2007 Table 12.

    a1 = 0.95 [ln(1/R) / ln(1/0.9)]^(2/3) + 0.05 (Weibull slope 1.5, failure-free life
    0.05 L10), which gives the table's printed values 1, 0.64, 0.55, 0.47, 0.37, 0.25 at
    R = 90, 95, 96, 97, 98, 99 % to their printed digit (its derivation in ISO/TR 1281-2
    was not read; between and beyond those rows the expression, not the table, is used).

    Parameters
    ----------
    reliability : float or array_like
        Reliability R [-], 0.90 to 0.9995 (the range of Table 12); 0.9 gives L10m, a1 = 1.

    Returns
    -------
    float or numpy.ndarray
        a1 [-].

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for R outside [0.90, 0.9995].
    """
    r = _checked("reliability", reliability, *RELIABILITY_RANGE,
                 why="the range of ISO 281:2007 Table 12")
    ratio = np.log(1.0 / r) / math.log(1.0 / 0.9)
    return _out((1.0 - A1_FLOOR) * ratio ** (1.0 / A1_WEIBULL_SLOPE) + A1_FLOOR)


def modified_life(l10, bearing_type, kappa, e_c, fatigue_load_limit_N, equivalent_load_N,
                  reliability=0.9):
    """Modified rating life L_nm = a1 a_ISO L10 (ISO 281:2007, clause 9).

    Parameters
    ----------
    l10 : float or array_like
        Basic rating life L10 (revolutions, millions of revolutions or hours: the result
        has the same unit), >= 0.
    bearing_type : str
        As :func:`a_iso`.
    kappa : float or array_like
        Viscosity ratio [-] (:func:`viscosity_ratio`).
    e_c : float or array_like
        Contamination factor [-] (:func:`contamination_factor`).
    fatigue_load_limit_N : float or array_like
        Fatigue load limit C_u [N].
    equivalent_load_N : float or array_like
        Dynamic equivalent load P [N], the one L10 was computed with.
    reliability : float
        Reliability R [-], 0.90 (default: L10m, a1 = 1) to 0.9995
        (:func:`reliability_factor`).

    Returns
    -------
    float or numpy.ndarray
        L_nm, in the unit of ``l10``.

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) as :func:`a_iso` and
        :func:`reliability_factor`, or for a negative or non-finite L10.

    Warns
    -----
    LifeModificationWarning
        If any kappa < 0.1 (see :func:`a_iso`).
    """
    life = _checked("l10", l10, 0.0)
    a1 = reliability_factor(reliability)
    factor = a_iso(bearing_type, kappa, e_c, fatigue_load_limit_N, equivalent_load_N)
    return _out(a1 * np.asarray(factor) * life)
