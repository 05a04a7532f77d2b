"""Basic load ratings of radial rolling bearings from their internal geometry.

Standards and what is taken from each:

* ISO 281:2007, "Rolling bearings - Dynamic load ratings and rating life": the basic
  dynamic radial load rating C_r (N, mm inside the formulas)

  - ball bearings (Sec. 5.1): C_r = b_m f_c (i cos a)^0.7 Z^(2/3) D_w^1.8 for D_w <= 25.4 mm,
                               C_r = 3.647 b_m f_c (i cos a)^0.7 Z^(2/3) D_w^1.4  above;
  - roller bearings (Sec. 7.1): C_r = b_m f_c (i L_we cos a)^(7/9) Z^(3/4) D_we^(29/27);

  the rating factor b_m of its Table 1 (:data:`B_M`) and f_c of its Table 2 (radial ball
  bearings, column "single-row radial contact groove ball bearings and single- and
  double-row angular contact groove ball bearings", :data:`FC_BALL`) and Table 7 (radial
  roller bearings, :data:`FC_ROLLER`) against gamma = D_w cos a / D_pw, interpolated
  linearly as ISO 281 prescribes for intermediate values.
* ISO 76:2006, "Rolling bearings - Static load ratings": the basic static radial load rating

  - radial ball bearings: C_0r = f_0 i Z D_w^2 cos a, f_0 of its Table 1 (column "radial
    contact groove and angular contact groove ball bearings", :data:`F0_BALL`), linear in
    between;
  - radial roller bearings: C_0r = 44 (1 - D_we cos a / D_pw) i Z L_we D_we cos a.

Where the tabulated values come from, and how they were checked (tests/test_rating.py,
docs/bearing_rating.md):

* f_c, ball: the 40 values 0.01..0.40 as quoted in public code (two unrelated repositories
  in the search index). They are the Lundberg-Palmgren closed form of ISO/TR 1281-1,
  f_c = K g^0.3 (1-g)^1.39 / (1+g)^(1/3) {1 + [1.04 ((1-g)/(1+g))^1.72]^(10/3)}^(-0.3),
  with the conformity ratio term equal to 1 (equal groove radii) and one constant
  K = 39.9 (lambda eta) (2f/(2f-1))^0.41 = 145.28 (lambda eta = 0.9573 at f = 0.52): that
  reproduces every printed digit. K was fitted here, not read from ISO/TR 1281-1; the form
  with inner/outer groove radii 0.52/0.53 does NOT reproduce the table (up to 2.2 off).
* f_c, roller: the 30 values 0.01..0.30 as quoted in public code; ISO/TR 1281-1's closed
  form f_c = 207.9 (lambda nu) g^(2/9) (1-g)^(29/27) / (1+g)^(1/4)
  {1 + [1.04 ((1-g)/(1+g))^(143/108)]^(9/2)}^(-2/9) with lambda nu = 0.83 reproduces every
  printed digit.
* f_0, ball: the 41 values 0.00..0.40 as quoted in public code (one entry of that source,
  at 0.06, is a typo: 15.7 for 15.9). Derived here from first principles, the Hertz
  point contact at ISO 76's 4 200 MPa (groove radii 0.52 D_w inner, 0.53 D_w outer, steel
  E = 207 GPa, nu = 0.3, the more loaded of the two contacts, Q_max = 5 F_r / (Z cos a))
  gives 40 of the 41 printed values when rounded (15.9 at 0.06 included); the 41st (0.13:
  15.653 for a printed 15.6) is 0.003 past the rounding bound, and a common 0.02 % scale
  (0.9998, within the uncertainty of the elastic constants) gives all 41.
* The roller factor 44 is Hertz line contact at ISO 76's 4 000 MPa with the same Stribeck
  factor 5: 44.2 (1 - gamma) per mm^2 (checked in the tests).

SI at the interface (m, N); millimetres only inside the standards' formulas.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ToothfemError, check_range
from ..units import MM_PER_M

#: Bearing types understood here.
BEARING_TYPES = ("ball", "angular_ball", "cylindrical", "tapered", "needle")
#: The ball types (ISO 281 Sec. 5, ISO 76 ball formula); the others are roller types.
BALL_TYPES = ("ball", "angular_ball")

#: Rating factor b_m, ISO 281:2007 Table 1. Rows used: "radial ball bearings" 1.3 (deep
#: groove and angular contact; filling-slot and insert bearings have other values and are
#: not covered); "cylindrical roller bearings", "tapered roller bearings" and "needle
#: roller bearings with machined rings" 1.1 (drawn-cup needle roller bearings, 1.0, are not
#: covered: use needle for machined-ring bearings and cage assemblies on hardened raceways).
B_M = {"ball": 1.3, "angular_ball": 1.3, "cylindrical": 1.1, "tapered": 1.1, "needle": 1.1}

#: gamma = D_w cos(a) / D_pw grid of :data:`FC_BALL` (ISO 281:2007 Table 2).
FC_BALL_GAMMA = tuple(round(0.01 * k, 2) for k in range(1, 41))
#: f_c of radial ball bearings, ISO 281:2007 Table 2, column "single-row radial contact
#: groove ball bearings and single- and double-row angular contact groove ball bearings",
#: at gamma 0.01, 0.02, ..., 0.40. Values as quoted in public code (search index: a
#: bearing-design Python script and a JS ISO 281/76 calculator); reproduced to the printed
#: digit by the closed form above (tests/test_rating.py).
FC_BALL = (29.1, 35.8, 40.3, 43.8, 46.7, 49.1, 51.1, 52.8, 54.3, 55.5,
           56.6, 57.5, 58.2, 58.8, 59.3, 59.6, 59.8, 59.9, 60.0, 59.9,
           59.8, 59.6, 59.3, 59.0, 58.6, 58.2, 57.7, 57.1, 56.6, 56.0,
           55.3, 54.6, 53.9, 53.2, 52.4, 51.7, 50.9, 50.0, 49.2, 48.4)

#: gamma = D_we cos(a) / D_pw grid of :data:`FC_ROLLER` (ISO 281:2007 Table 7).
FC_ROLLER_GAMMA = tuple(round(0.01 * k, 2) for k in range(1, 31))
#: f_c of radial roller bearings, ISO 281:2007 Table 7, at gamma 0.01, 0.02, ..., 0.30.
#: Values as quoted in public code (search index: a MATLAB routine F04.m); reproduced to
#: the printed digit by ISO/TR 1281-1's closed form with lambda nu = 0.83.
FC_ROLLER = (52.1, 60.8, 66.5, 70.7, 74.1, 76.9, 79.2, 81.2, 82.8, 84.2,
             85.4, 86.4, 87.1, 87.7, 88.2, 88.5, 88.7, 88.8, 88.8, 88.7,
             88.5, 88.2, 87.9, 87.5, 87.0, 86.4, 85.8, 85.2, 84.5, 83.8)

#: gamma = D_w cos(a) / D_pw grid of :data:`F0_BALL` (ISO 76:2006 Table 1).
F0_BALL_GAMMA = tuple(round(0.01 * k, 2) for k in range(0, 41))
#: f_0 of radial ball bearings, ISO 76:2006 Table 1, column "radial contact groove and
#: angular contact groove ball bearings", at gamma 0.00, 0.01, ..., 0.40. Values as quoted
#: in public code (search index: a JS ISO 281/76 calculator, whose 0.06 entry 15.7 is a
#: typo) and checked against the Hertz contact at 4 200 MPa: every entry within 0.055 of
#: it, 40 of 41 equal to it rounded (module docstring; tests/test_rating.py).
F0_BALL = (14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5,
           16.4, 16.1, 15.9, 15.6, 15.4, 15.2, 14.9, 14.7, 14.4, 14.2,
           14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8,
           11.6, 11.4, 11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4)

#: Ball diameter [mm] above which ISO 281 Sec. 5.1 uses 3.647 D_w^1.4 for D_w^1.8
#: (25.4 mm = 1 in; 3.647 = 25.4^0.4, so both forms meet there).
LARGE_BALL_MM = 25.4
#: Factor of the D_w^1.4 branch, ISO 281:2007 Sec. 5.1.
LARGE_BALL_FACTOR = 3.647
#: Factor of the static rating of radial roller bearings, ISO 76:2006 Sec. 6.1 [N/mm^2]:
#: C_0r = 44 (1 - D_we cos a / D_pw) i Z L_we D_we cos a.
STATIC_ROLLER_FACTOR = 44.0
#: Nominal contact angle range of radial bearings [deg] (ISO 281 / ISO 76: radial
#: bearings have a nominal contact angle from 0 deg to 45 deg inclusive).
CONTACT_ANGLE_RANGE_DEG = (0.0, 45.0)


def _integer(name, value, lo, hi=None, why=""):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ToothfemError(f"{name} = {value!r} is not an integer")
    check_range(name, int(value), lo, hi, why=why)
    return int(value)


def _geometry(bearing_type, rows, elements, element_diameter_m, element_length_m,
              pitch_diameter_m, contact_angle_deg):
    """Checked inputs in the standards' units: (i, Z, D_w mm, L_we mm or None, D_pw mm,
    alpha rad, gamma)."""
    if bearing_type not in BEARING_TYPES:
        raise ToothfemError(f"bearing_type = {bearing_type!r} is not one of "
                            f"{', '.join(BEARING_TYPES)}")
    ball = bearing_type in BALL_TYPES
    if bearing_type == "ball":
        i = _integer("rows", rows, 1, 1, why="single-row deep groove ball bearings only "
                     "(ISO 281 rates double-row deep groove bearings with another f_c "
                     "column, not carried here)")
    else:
        i = _integer("rows", rows, 1)
    z = _integer("elements", elements, 1)
    d = check_range("element_diameter_m", element_diameter_m, 0.0, lo_open=True)
    p = check_range("pitch_diameter_m", pitch_diameter_m, 0.0, lo_open=True)
    a = check_range("contact_angle_deg", contact_angle_deg, *CONTACT_ANGLE_RANGE_DEG,
                    why="radial bearings (ISO 281, ISO 76)")
    if ball:
        if element_length_m is not None:
            raise ToothfemError(f"element_length_m = {element_length_m!r} is given for "
                                f"bearing_type = {bearing_type!r}: it applies to roller "
                                "bearings only; leave it None")
        length_mm = None
    else:
        if element_length_m is None:
            raise ToothfemError(f"element_length_m = None: the effective roller length is "
                                f"required for bearing_type = {bearing_type!r}")
        length_mm = check_range("element_length_m", element_length_m, 0.0,
                                lo_open=True) * MM_PER_M
    alpha = math.radians(float(a))
    gamma = float(d) * math.cos(alpha) / float(p)
    return (i, z, float(d) * MM_PER_M, length_mm, float(p) * MM_PER_M, alpha, gamma)


_GAMMA_NAME = "element_diameter_m*cos(contact_angle_deg)/pitch_diameter_m"


def fc_factor(bearing_type: str, gamma: float) -> float:
    """ISO 281 factor f_c, linear in gamma between the tabulated values.

    Parameters
    ----------
    bearing_type : str
        One of :data:`BEARING_TYPES`; the ball types read ISO 281 Table 2
        (:data:`FC_BALL`), the roller types Table 7 (:data:`FC_ROLLER`).
    gamma : float
        D_w cos(a) / D_pw (ball) or D_we cos(a) / D_pw (roller) [-].

    Returns
    -------
    float
        f_c [-] (for ISO 281's formulas in N and mm).

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for an unknown type or a gamma outside
        the table: [0.01, 0.40] ball, [0.01, 0.30] roller.
    """
    if bearing_type not in BEARING_TYPES:
        raise ToothfemError(f"bearing_type = {bearing_type!r} is not one of "
                            f"{', '.join(BEARING_TYPES)}")
    grid, values, table = ((FC_BALL_GAMMA, FC_BALL, "ISO 281 Table 2")
                           if bearing_type in BALL_TYPES
                           else (FC_ROLLER_GAMMA, FC_ROLLER, "ISO 281 Table 7"))
    check_range(_GAMMA_NAME, gamma, grid[0], grid[-1], why=f"the range of {table}")
    return float(np.interp(float(gamma), grid, values))


def f0_factor(gamma: float) -> float:
    """ISO 76 factor f_0 of radial ball bearings, linear in gamma between the table's
    values.

    Parameters
    ----------
    gamma : float
        D_w cos(a) / D_pw [-].

    Returns
    -------
    float
        f_0 [N/mm^2] (:data:`F0_BALL`).

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) for a gamma outside [0, 0.40], the range of
        ISO 76 Table 1.
    """
    check_range(_GAMMA_NAME, gamma, F0_BALL_GAMMA[0], F0_BALL_GAMMA[-1],
                why="the range of ISO 76 Table 1")
    return float(np.interp(float(gamma), F0_BALL_GAMMA, F0_BALL))


def dynamic_rating_N(bearing_type: str, *, rows: int, elements: int,
                     element_diameter_m: float, element_length_m: float | None = None,
                     pitch_diameter_m: float, contact_angle_deg: float = 0.0) -> float:
    """Basic dynamic radial load rating C_r by ISO 281:2007 from the internal geometry.

    Ball bearings: C_r = b_m f_c (i cos a)^0.7 Z^(2/3) D_w^1.8 (D_w <= 25.4 mm), else
    3.647 b_m f_c (i cos a)^0.7 Z^(2/3) D_w^1.4. Roller bearings:
    C_r = b_m f_c (i L_we cos a)^(7/9) Z^(3/4) D_we^(29/27). N and mm inside; b_m from
    :data:`B_M`, f_c from :func:`fc_factor`.

    Parameters
    ----------
    bearing_type : str
        "ball" (single-row deep groove), "angular_ball" (single- or double-row angular
        contact), "cylindrical", "tapered" or "needle" (machined rings or a cage assembly
        on hardened raceways).
    rows : int
        Rows of rolling elements i (1 for "ball").
    elements : int
        Rolling elements per row Z.
    element_diameter_m : float
        Ball diameter D_w, or roller diameter D_we (tapered: the mean diameter) [m].
    element_length_m : float, optional
        Effective roller length L_we [m]; required for roller bearings, None for balls.
    pitch_diameter_m : float
        Pitch diameter of the rolling-element set D_pw [m].
    contact_angle_deg : float
        Nominal contact angle a [deg], 0 to 45.

    Returns
    -------
    float
        C_r [N].

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) naming the parameter, its value and the
        valid range: unknown type, non-integer or out-of-range rows/elements, non-positive
        sizes, a missing or superfluous length, a contact angle outside [0, 45] deg, or
        gamma = D_w cos(a)/D_pw outside the f_c table.
    """
    i, z, dw, lwe, _dpw, alpha, gamma = _geometry(
        bearing_type, rows, elements, element_diameter_m, element_length_m,
        pitch_diameter_m, contact_angle_deg)
    fc = fc_factor(bearing_type, gamma)
    bm = B_M[bearing_type]
    cos_a = math.cos(alpha)
    if bearing_type in BALL_TYPES:
        size = dw ** 1.8 if dw <= LARGE_BALL_MM else LARGE_BALL_FACTOR * dw ** 1.4
        return bm * fc * (i * cos_a) ** 0.7 * z ** (2.0 / 3.0) * size
    return bm * fc * (i * lwe * cos_a) ** (7.0 / 9.0) * z ** 0.75 * dw ** (29.0 / 27.0)


def static_rating_N(bearing_type: str, *, rows: int, elements: int,
                    element_diameter_m: float, element_length_m: float | None = None,
                    pitch_diameter_m: float, contact_angle_deg: float = 0.0) -> float:
    """Basic static radial load rating C_0r by ISO 76:2006 from the internal geometry.

    Radial ball bearings: C_0r = f_0 i Z D_w^2 cos a (f_0 from :func:`f0_factor`). Radial
    roller bearings: C_0r = 44 (1 - D_we cos a / D_pw) i Z L_we D_we cos a. N and mm inside.

    Parameters
    ----------
    bearing_type : str
        "ball", "angular_ball", "cylindrical", "tapered" or "needle" (as for
        :func:`dynamic_rating_N`).
    rows : int
        Rows of rolling elements i (1 for "ball").
    elements : int
        Rolling elements per row Z.
    element_diameter_m : float
        Ball diameter D_w, or roller diameter D_we (tapered: the mean diameter) [m].
    element_length_m : float, optional
        Effective roller length L_we [m]; required for roller bearings, None for balls.
    pitch_diameter_m : float
        Pitch diameter of the rolling-element set D_pw [m].
    contact_angle_deg : float
        Nominal contact angle a [deg], 0 to 45.

    Returns
    -------
    float
        C_0r [N].

    Raises
    ------
    ValueError
        (:class:`toothfem.errors.ToothfemError`) naming the parameter, its value and the
        valid range, as :func:`dynamic_rating_N`; for balls gamma must lie in [0, 0.40]
        (ISO 76 Table 1), for rollers in (0, 1).
    """
    i, z, dw, lwe, _dpw, alpha, gamma = _geometry(
        bearing_type, rows, elements, element_diameter_m, element_length_m,
        pitch_diameter_m, contact_angle_deg)
    cos_a = math.cos(alpha)
    if bearing_type in BALL_TYPES:
        return f0_factor(gamma) * i * z * dw ** 2 * cos_a
    check_range(_GAMMA_NAME, gamma, 0.0, 1.0, lo_open=True, hi_open=True,
                why="the roller must fit inside its pitch circle")
    return STATIC_ROLLER_FACTOR * (1.0 - gamma) * i * z * lwe * dw * cos_a
