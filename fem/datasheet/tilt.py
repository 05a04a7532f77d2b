"""The output (main) bearing pair of a precision reducer under a radial force, an axial force
and a tilting moment: its tilt, its ball loads and Hertz pressures, the catalogue's "moment
rigidity" (N m/arcmin) and the moment at a given contact pressure.

The pair is the RV-E's (Nabtesco): two rows of angular-contact balls back to back (O
arrangement), preloaded, the inner raceways ground on the carrier (the output, loaded) and the
outer raceways in the housing (held). Units SI everywhere (N, m, Pa, rad); the catalogue's
N m/arcmin only in the names that say so.

Model
-----
* Rigid rings (carrier and housing), balls without mass (quasi-static, no centrifugal or
  gyroscopic load: a reducer's output turns at a few rpm), no friction. Only the Hertz
  approach of each ball on its two raceways is elastic; the housing, the carrier's flanges,
  the bolts and the rings' own bending are rigid here (the catalogue's rigidity includes them).
* Geometry of one row (Harris & Kotzalas 2007a, Ch. 2): Z balls of diameter D_w on the pitch
  diameter d_m, groove radii r_i = f_i D_w and r_e = f_e D_w; the centres of curvature of the two
  grooves of one ball lie on its contact line, A = (f_i + f_e - 1) D_w apart when the ball just
  touches both (no load, no preload), at the free ("nominal") contact angle alpha_0. The inner
  groove's centres lie on a circle of radius R_i = d_m/2 + (f_i - 1/2) D_w cos(alpha_0).
* Both rows are alike. ``row_span_m`` is the axial distance between the two rows' ball-centre
  planes (the drawing's dimension). Back to back, each row's contact lines meet the axis
  outside the pair, d_m/2 tan(alpha_0) beyond its ball plane: the distance of the
  pressure-cone apexes is ``BallPair.pressure_centre_spread_m`` = span + d_m tan(alpha_0).
* Axes: z along the bearing axis, x along the radial force, y completes the right-handed set.
  Row 0 sits at z = -span/2 and carries an axial force on the carrier toward +z; row 1 sits at
  z = +span/2 and carries one toward -z. The moment is M_y about the pair's centre (the point
  of the axis midway between the rows), the tilt theta is the carrier's rotation about y.
  Ball j of a row sits at psi_j = 2 pi j / Z from +x (half a pitch further with
  ``half_pitch_offset``); both rows alike, so the loads stay in the x-z plane.
* Preload (Harris & Kotzalas 2007a, Ch. 1; "axial preload"): given as the axial force
  ``preload_N`` each row carries at zero external load. It is applied as an axial
  interference: each row's inner groove centres are moved e into contact along the axis; e is
  solved from the preload once (:func:`preload_state`). Between the rows the interference is
  2 e (the axial play of the free pair is -2 e).
* Ball load (Jones 1960; Harris & Kotzalas 2007b, Ch. 1): the carrier's displacement
  (delta_x, delta_z, theta) moves ball j's inner groove centre by u_r = (delta_x + theta z_c)
  cos(psi_j) radially and u_z = delta_z - theta R_i cos(psi_j) axially, z_c being that centre's
  axial position. The groove-centre distance becomes
  L = |(A cos(alpha_0) + u_r, A sin(alpha_0) + e + s u_z)| (s = +1 row 0, -1 row 1); the ball's
  approach is delta = L - A, its loaded contact angle alpha = atan2(A sin(alpha_0) + e + s u_z,
  A cos(alpha_0) + u_r), and its load Q = K max(delta, 0)^1.5 along that line (a ball that
  loses contact carries nothing). With ``contact_angle_model="fixed"`` the angle stays alpha_0
  and delta = e sin(alpha_0) + cos(alpha_0) u_r + sin(alpha_0) s u_z (the first model of
  Harris's Ch. 7); it holds while both rows keep balls in contact (alone, a row's ball
  forces all pass through its pressure-cone apex and cannot balance a radial force and a
  moment independently: the solver then says so). Forces and their arms are taken at the
  unloaded positions of the groove centres (small displacements).
* K is Hertz's for the inner and the outer contact in series: delta = (c_i + c_e) Q^(2/3),
  K = (c_i + c_e)^(-3/2), each contact's c from its principal radii (Harris & Kotzalas 2007a,
  Ch. 2; gamma = D_w cos(alpha)/d_m): inner R_x = D_w (1 - gamma)/2, outer
  R_x = D_w (1 + gamma)/2 (rolling direction), R_y = f D_w/(2 f - 1) (across the groove).
  K is taken at alpha_0 (a change of the contact angle by 5 deg changes K by well under 1 %);
  each ball's pressure at its loaded angle.
* Hertz's elliptic point contact, ``hertz_method="exact"`` (default): the ellipse's eccentricity
  from alpha_r = R_y/R_x = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)) (Johnson 1985, Sec. 4.2, K
  and E the complete elliptic integrals), written with Carlson's symmetric integrals of
  scipy.special (``ellipk``, ``elliprd``) so that it has no cancellation near a circle;
  ``"hamrock_brewe"``: Hamrock & Brewe's (1983) closed-form approximations
  k = alpha_r^(2/pi), E ~ 1 + q/alpha_r, K ~ pi/2 + q ln(alpha_r), q = pi/2 - 1 (also in
  Hamrock, Schmid & Jacobson 2004, Ch. 8), within about 1.5 % of the exact approach and
  pressure for the alpha_r of ball bearings (5 to 30).
* The solver is Newton's method with the analytic tangent stiffness (the ball's
  k n n^T + (Q/L)(I - n n^T), the second term the turning of its contact line) and a
  backtracking line search; a failure raises :class:`TiltConvergenceError` naming the loads.

Catalogue quantities
--------------------
* Moment rigidity (Nabtesco's "moment rigidity", N m/arcmin): the secant M / theta at the given
  moment, theta measured from the tilt at zero moment under the same radial and axial force
  (:func:`moment_rigidity_Nm_per_arcmin`); the tangent dM/dtheta is
  :func:`tangent_moment_rigidity_Nm_per_arcmin`.
* The moment at a contact pressure (:func:`moment_at_pressure`): ISO 76's static rating
  corresponds to 4200 MPa at the centre of the most heavily loaded contact of a ball bearing
  (4600 MPa for self-aligning ones), :data:`ISO76_BALL_PRESSURE_PA`.

Sources
-------
* H. Hertz (1882), J. reine angew. Math. 92, 156-171; K. L. Johnson, *Contact Mechanics*,
  Cambridge University Press 1985, Sec. 4.2 (circular and elliptic contact).
* B. J. Hamrock, D. E. Brewe (1983), "Simplified solution for stresses and deformations",
  ASME J. Lubrication Technology 105, 171-177; B. J. Hamrock, S. R. Schmid, B. O. Jacobson,
  *Fundamentals of Machine Elements*, 2nd ed., McGraw-Hill 2004, Ch. 8.
* A. B. Jones (1960), "A general theory for elastically constrained ball and radial roller
  bearings under arbitrary load and speed conditions", ASME J. Basic Eng. 82, 309-320.
* T. A. Harris, M. N. Kotzalas, *Essential Concepts of Bearing Technology* (2007a) and
  *Advanced Concepts of Bearing Technology* (2007b), 5th ed., CRC Press: geometry (Ch. 2 of
  the first), Hertz contact (Ch. 6), load distribution and Stribeck's 4.37 (Ch. 7), loaded
  contact angle with rigid rings (Ch. 1 of the second).
* R. Stribeck (1901), "Kugellager fuer beliebige Belastungen", Z. VDI 45.
* ISO 76:2006, Rolling bearings - Static load ratings (4200 MPa); ISO 76 and ISO 281 base
  their f_0 and f_c tables on groove radii of at most 0.52 D_w (inner) and 0.53 D_w (outer) of
  radial and angular-contact ball bearings: the default conformities here, since a reducer
  catalogue does not give its raceways' radii.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipk, elliprd

from ...errors import ToothfemError, check_range
from ..hertz import reduced_modulus
from ...units import ARCMIN, PA_PER_MPA

#: ISO 76's contact pressure at the static load rating of a ball bearing (self-aligning
#: ones excepted: 4600 MPa) [Pa].
ISO76_BALL_PRESSURE_PA = 4200e6
#: Stribeck's integral factor of a ball bearing with zero clearance under a radial load
#: (half the raceway loaded, epsilon = 0.5): Q_max = 4.37 F_r / (Z cos alpha) (Harris &
#: Kotzalas 2007a, Ch. 7; NSK CAT. No. E728g, Sec. 5.1, gives the same 4.37). With clearance, the
#: engineering value is 5 F_r / Z.
STRIBECK_POINT = 4.37
#: Newton's tolerance on the scaled force and moment residual (fractions of the load scale;
#: round-off of the sums over 2 Z balls is near 1e-15).
_TOL = 1e-12
_MAX_ITER = 100
_MODELS = ("varying", "fixed")
_METHODS = ("exact", "hamrock_brewe")


class TiltConvergenceError(ToothfemError):
    """The bearing pair's equilibrium was not found (the message names the loads)."""


@dataclass(frozen=True)
class BallPair:
    """A back-to-back (O) pair of identical angular-contact ball rows; every field in SI.

    ``contact_angle_rad`` is the free contact angle alpha_0 (balls just touching, no load, no
    preload); ``row_span_m`` the axial distance between the rows' ball-centre planes;
    ``preload_N`` the axial force each row carries at zero external load (0: zero clearance,
    no preload). ``f_inner``/``f_outer`` are r_i/D_w and r_e/D_w; 0.52 and 0.53 are the
    largest groove radii that ISO 76's and ISO 281's rating factors assume, and a reducer's
    catalogue does not give its own. ``youngs_modulus_Pa``/``poisson_ratio``: bearing steel
    (both bodies). ``half_pitch_offset`` turns both rows by half a ball pitch (ball 0 off the
    load line). ``contact_angle_model``: "varying" (Jones) or "fixed"; ``hertz_method``:
    "exact" (elliptic integrals) or "hamrock_brewe" (1983 approximations).
    """

    balls_per_row: int
    ball_diameter_m: float
    pitch_diameter_m: float
    contact_angle_rad: float
    row_span_m: float
    preload_N: float
    f_inner: float = 0.52
    f_outer: float = 0.53
    youngs_modulus_Pa: float = 208e9
    poisson_ratio: float = 0.3
    half_pitch_offset: bool = False
    contact_angle_model: str = "varying"
    hertz_method: str = "exact"

    def __post_init__(self):
        if isinstance(self.balls_per_row, bool) or not isinstance(self.balls_per_row,
                                                                   (int, np.integer)):
            raise ToothfemError(f"balls_per_row = {self.balls_per_row!r} is not an integer")
        check_range("balls_per_row", self.balls_per_row, 3, why="balls in a row")
        check_range("ball_diameter_m", self.ball_diameter_m, 0.0, lo_open=True)
        check_range("pitch_diameter_m", self.pitch_diameter_m, self.ball_diameter_m,
                    lo_open=True, why="the pitch diameter exceeds the ball diameter")
        check_range("contact_angle_rad", self.contact_angle_rad, 0.0, math.pi / 2,
                    hi_open=True, why="free contact angle in [0, pi/2)")
        check_range("row_span_m", self.row_span_m, 0.0, why="distance of the ball planes")
        check_range("preload_N", self.preload_N, 0.0, why="axial preload of each row")
        check_range("f_inner", self.f_inner, 0.5, lo_open=True, why="groove radius / D_w")
        check_range("f_outer", self.f_outer, 0.5, lo_open=True, why="groove radius / D_w")
        check_range("youngs_modulus_Pa", self.youngs_modulus_Pa, 0.0, lo_open=True)
        check_range("poisson_ratio", self.poisson_ratio, -1.0, 0.5, lo_open=True)
        if self.contact_angle_model not in _MODELS:
            raise ToothfemError(f"contact_angle_model = {self.contact_angle_model!r}: "
                                f"one of {_MODELS}")
        if self.hertz_method not in _METHODS:
            raise ToothfemError(f"hertz_method = {self.hertz_method!r}: one of {_METHODS}")
        if (self.contact_angle_model == "fixed" and self.preload_N > 0
                and self.contact_angle_rad == 0):
            raise ToothfemError("a fixed contact angle of 0 cannot carry an axial preload")
        if self.balls_per_row * self.ball_diameter_m >= math.pi * self.pitch_diameter_m:
            raise ToothfemError(f"{self.balls_per_row} balls of {self.ball_diameter_m:g} m "
                                f"do not fit on the pitch circle of {self.pitch_diameter_m:g} m")

    @property
    def groove_centre_distance_m(self) -> float:
        """A = (f_i + f_e - 1) D_w [m], the groove-centre distance of a just-touching ball."""
        return (self.f_inner + self.f_outer - 1.0) * self.ball_diameter_m

    @property
    def inner_centre_radius_m(self) -> float:
        """R_i [m], radius of the circle of the inner groove's curvature centres."""
        return (0.5 * self.pitch_diameter_m
                + (self.f_inner - 0.5) * self.ball_diameter_m * math.cos(self.contact_angle_rad))

    @property
    def inner_centre_z_m(self) -> tuple:
        """Axial positions [m] of the inner groove centres of rows 0 and 1."""
        off = (self.f_inner - 0.5) * self.ball_diameter_m * math.sin(self.contact_angle_rad)
        return (-0.5 * self.row_span_m + off, 0.5 * self.row_span_m - off)

    @property
    def pressure_centre_spread_m(self) -> float:
        """Axial distance [m] of the two rows' pressure-cone apexes: span + d_m tan(alpha_0)."""
        return self.row_span_m + self.pitch_diameter_m * math.tan(self.contact_angle_rad)

    @property
    def azimuths_rad(self) -> np.ndarray:
        """Azimuths psi_j [rad] of the balls of a row, from the radial force's direction."""
        z = self.balls_per_row
        return 2 * np.pi * (np.arange(z) + (0.5 if self.half_pitch_offset else 0.0)) / z


# ---------------------------------------------------------------------------------------
# Hertz point contact
# ---------------------------------------------------------------------------------------

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
        raise ToothfemError(f"hertz method {method!r}: one of {_METHODS}")
    ab = a * b
    p = np.where(ab > 0, 3 * q / (2 * np.pi * np.where(ab > 0, ab, 1.0)), 0.0)
    return HertzPoint(delta, a, b, p, k)


@dataclass(frozen=True)
class RacewayContact:
    """A ball on its two raceways at one contact angle: approach delta = c Q^(2/3) and peak
    pressure p = c_p Q^(1/3) of each contact; K of both in series."""

    approach_coeff_inner: float     # c_i [m N^(-2/3)]
    approach_coeff_outer: float     # c_e [m N^(-2/3)]
    pressure_coeff_inner: float     # [Pa N^(-1/3)]
    pressure_coeff_outer: float     # [Pa N^(-1/3)]
    ellipticity_inner: float        # a/b
    ellipticity_outer: float
    radii_inner_m: tuple            # (R_x, R_y)
    radii_outer_m: tuple

    @property
    def K_inner(self) -> float:
        """Q = K_i delta_i^1.5 of the inner contact [N m^-1.5]."""
        return self.approach_coeff_inner ** -1.5

    @property
    def K_outer(self) -> float:
        """Q = K_e delta_e^1.5 of the outer contact [N m^-1.5]."""
        return self.approach_coeff_outer ** -1.5

    @property
    def K(self) -> float:
        """Q = K delta^1.5 of both contacts in series, delta = delta_i + delta_e [N m^-1.5]."""
        return (self.approach_coeff_inner + self.approach_coeff_outer) ** -1.5


def _contact_radii(pair: BallPair, alpha) -> tuple[tuple[float | np.ndarray, float],
                                                   tuple[float | np.ndarray, float]]:
    """(R_x, R_y) of the inner and the outer contact at contact angle(s) alpha [m]."""
    d = pair.ball_diameter_m
    gamma = d * np.cos(alpha) / pair.pitch_diameter_m
    inner = (0.5 * d * (1 - gamma), pair.f_inner * d / (2 * pair.f_inner - 1))
    outer = (0.5 * d * (1 + gamma), pair.f_outer * d / (2 * pair.f_outer - 1))
    return inner, outer


def _e_star(pair: BallPair) -> float:
    e, nu = pair.youngs_modulus_Pa, pair.poisson_ratio
    return float(reduced_modulus(e, nu, e, nu))


def raceway_contact(pair: BallPair, contact_angle_rad: float | None = None) -> RacewayContact:
    """Hertz constants of a ball on its inner and outer raceway (Harris & Kotzalas 2007a,
    Chs. 2 and 6) with ``pair.hertz_method``.

    Parameters
    ----------
    pair : BallPair
        The bearing (one row's geometry; both rows are alike).
    contact_angle_rad : float, optional
        The contact angle [rad]; default the free angle alpha_0.

    Returns
    -------
    RacewayContact
        Approach and pressure coefficients of both contacts, their ellipticities and radii;
        ``.K`` is the load-deflection constant of the ball (both contacts in series).
    """
    alpha = pair.contact_angle_rad if contact_angle_rad is None else float(contact_angle_rad)
    inner, outer = _contact_radii(pair, alpha)
    es = _e_star(pair)
    hi = hertz_point_contact(1.0, *inner, es, pair.hertz_method)
    ho = hertz_point_contact(1.0, *outer, es, pair.hertz_method)
    return RacewayContact(float(hi.approach_m), float(ho.approach_m), float(hi.p_max_Pa),
                          float(ho.p_max_Pa), float(hi.ellipticity), float(ho.ellipticity),
                          tuple(float(r) for r in inner), tuple(float(r) for r in outer))


def ball_pressure_Pa(pair: BallPair, load_N, contact_angle_rad):
    """Peak Hertz pressure [Pa] of balls: the larger of the inner and the outer contact.

    Parameters
    ----------
    pair : BallPair
        The bearing.
    load_N : array_like
        Ball loads Q [N].
    contact_angle_rad : array_like
        Their contact angles [rad] (the radii in the rolling direction depend on them).

    Returns
    -------
    numpy.ndarray
        max(p_inner, p_outer) [Pa], the broadcast shape.
    """
    q, alpha = np.broadcast_arrays(np.asarray(load_N, float),
                                   np.asarray(contact_angle_rad, float))
    inner, outer = _contact_radii(pair, alpha)
    es = _e_star(pair)
    p_in = hertz_point_contact(q, *inner, es, pair.hertz_method).p_max_Pa
    p_out = hertz_point_contact(q, *outer, es, pair.hertz_method).p_max_Pa
    return np.maximum(p_in, p_out)


# ---------------------------------------------------------------------------------------
# Preload and ball kinematics
# ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PreloadState:
    """Each row at zero external load (SI)."""

    interference_m: float      # e: axial shift of each row's inner groove centres into contact
    approach_m: float          # delta_0 of every ball
    contact_angle_rad: float   # loaded contact angle alpha_p of every ball
    ball_load_N: float         # Q_0 = F_pre / (Z sin(alpha_p))


def _row_force(pair: BallPair, k_const: float, e: float):
    """(axial force of a row, delta, alpha, Q) for an axial interference e."""
    a0 = pair.groove_centre_distance_m
    al = pair.contact_angle_rad
    if pair.contact_angle_model == "fixed":
        delta, alpha = e * math.sin(al), al
    else:
        vr, va = a0 * math.cos(al), a0 * math.sin(al) + e
        delta, alpha = math.hypot(vr, va) - a0, math.atan2(va, vr)
    q = k_const * max(delta, 0.0) ** 1.5
    return pair.balls_per_row * q * math.sin(alpha), delta, alpha, q


def preload_state(pair: BallPair) -> PreloadState:
    """The axial interference that gives each row ``pair.preload_N``, and the balls' state.

    Parameters
    ----------
    pair : BallPair
        The bearing pair.

    Returns
    -------
    PreloadState
        Interference e [m] (each row; 2 e between the rows), approach, contact angle and load
        of every ball at zero external load.
    """
    k_const = raceway_contact(pair).K
    if pair.preload_N == 0:
        return PreloadState(0.0, 0.0, pair.contact_angle_rad, 0.0)
    f = lambda e: _row_force(pair, k_const, e)[0] - pair.preload_N      # noqa: E731
    hi = pair.ball_diameter_m * 1e-4
    while f(hi) < 0:
        hi *= 2
        if hi > pair.ball_diameter_m:
            raise ToothfemError(f"preload_N = {pair.preload_N:g} needs an interference above "
                                "the ball diameter")
    e = brentq(f, 0.0, hi, xtol=1e-18, rtol=1e-14)
    _, delta, alpha, q = _row_force(pair, k_const, e)
    return PreloadState(e, delta, alpha, q)


@dataclass(frozen=True)
class _Rows:
    """Every ball of the rows in play, flattened (row-major)."""

    sign: np.ndarray        # s = +1 (carries +z on the carrier) or -1
    zc: np.ndarray          # axial position of the inner groove centre [m]
    cpsi: np.ndarray        # cos(psi)
    row: np.ndarray         # row index
    interference: float     # e [m]
    n_rows: int


def _pair_rows(pair: BallPair, interference: float) -> _Rows:
    z = pair.balls_per_row
    cpsi = np.cos(pair.azimuths_rad)
    zc0, zc1 = pair.inner_centre_z_m
    return _Rows(np.repeat([1.0, -1.0], z), np.repeat([zc0, zc1], z), np.tile(cpsi, 2),
                 np.repeat([0, 1], z), interference, 2)


def _single_row(pair: BallPair) -> _Rows:
    z = pair.balls_per_row
    off = (pair.f_inner - 0.5) * pair.ball_diameter_m * math.sin(pair.contact_angle_rad)
    return _Rows(np.ones(z), np.full(z, off), np.cos(pair.azimuths_rad), np.zeros(z, int),
                 0.0, 1)


def _state(pair: BallPair, rows: _Rows, k_const: float, x):
    """Ball approach, load, angle, local unit normal, the generalised force G (on the
    carrier, by the balls, with the sign of the external load it balances) and the tangent
    stiffness J = dG/dx at x = (delta_x, delta_z, theta)."""
    dx, dz, th = x
    a0 = pair.groove_centre_distance_m
    al0 = pair.contact_angle_rad
    rc = pair.inner_centre_radius_m
    s, zc, cpsi = rows.sign, rows.zc, rows.cpsi
    ur = (dx + th * zc) * cpsi
    uz = dz - th * rc * cpsi
    # B maps x to the local (radial, own-axial) displacement: rows of dv/dx
    b_r = np.stack([cpsi, np.zeros_like(cpsi), zc * cpsi], axis=1)
    b_a = np.stack([np.zeros_like(cpsi), s, -s * rc * cpsi], axis=1)
    if pair.contact_angle_model == "fixed":
        nr = np.full_like(cpsi, math.cos(al0))
        na = np.full_like(cpsi, math.sin(al0))
        delta = rows.interference * math.sin(al0) + nr * ur + na * s * uz
        alpha = np.full_like(cpsi, al0)
        length = None
    else:
        vr = a0 * math.cos(al0) + ur
        va = a0 * math.sin(al0) + rows.interference + s * uz
        length = np.hypot(vr, va)
        delta = length - a0
        alpha = np.arctan2(va, vr)
        nr, na = vr / length, va / length
    dpos = np.maximum(delta, 0.0)
    q = k_const * dpos ** 1.5
    kn = 1.5 * k_const * np.sqrt(dpos)
    # generalised force of each ball: B^T (Q n)
    bn = b_r * nr[:, None] + b_a * na[:, None]          # n^T B, (N, 3)
    g = (q[:, None] * bn).sum(axis=0)
    jac = (kn[:, None, None] * bn[:, :, None] * bn[:, None, :]).sum(axis=0)
    if length is not None:
        bt = -b_r * na[:, None] + b_a * nr[:, None]      # t^T B, t = (-n_a, n_r)
        geo = q / length
        jac = jac + (geo[:, None, None] * bt[:, :, None] * bt[:, None, :]).sum(axis=0)
    return delta, q, alpha, nr, na, g, jac


def _newton(pair: BallPair, rows: _Rows, k_const: float, load, free, what: str):
    """Solve G(x) = load on the free degrees of freedom (the others held at 0)."""
    load = np.asarray(load, float)
    free = np.asarray(free, bool)
    l_ref = 0.5 * pair.pitch_diameter_m
    f_ref = max(abs(load[0]), abs(load[1]), abs(load[2]) / l_ref,
                pair.preload_N if rows.n_rows == 2 else 0.0)
    x = np.zeros(3)
    if f_ref == 0:
        return x, 0, 0.0
    w = np.array([1.0, 1.0, 1.0 / l_ref]) / f_ref

    def residual(x):
        st = _state(pair, rows, k_const, x)
        r = np.where(free, load - st[5], 0.0)
        return st, r, float(np.sum((w * r) ** 2))

    # start: the tangent at zero load, or (no contact force yet) every ball as a linear
    # spring of the stiffness it would have at an even share of the load
    st, r, phi = residual(x)
    jac = st[6]
    if not np.all(np.isfinite(jac)) or np.linalg.matrix_rank(jac[np.ix_(free, free)]) < free.sum():
        q_est = f_ref / rows.sign.size
        k_est = 1.5 * k_const ** (2 / 3) * q_est ** (1 / 3)
        al0 = pair.contact_angle_rad
        nr, na = math.cos(al0), math.sin(al0)
        cpsi, zc, s = rows.cpsi, rows.zc, rows.sign
        rc = pair.inner_centre_radius_m
        bn = np.stack([nr * cpsi, na * s, (nr * zc - na * s * rc) * cpsi], axis=1)
        jac = k_est * bn.T @ bn
    jf = jac[np.ix_(free, free)]
    x[free] = np.linalg.lstsq(jf, r[free], rcond=1e-12)[0]
    st, r, phi = residual(x)
    for it in range(1, _MAX_ITER + 1):
        if np.max(np.abs(w * r)) < _TOL:
            return x, it, float(np.max(np.abs(w * r)))
        jf = st[6][np.ix_(free, free)]
        step = np.zeros(3)
        step[free] = np.linalg.lstsq(jf, r[free], rcond=1e-14)[0]
        lam = 1.0
        while True:
            xn = x + lam * step
            stn, rn, phin = residual(xn)
            if phin < (1 - 1e-4 * lam) * phi or phin == 0:
                break
            lam *= 0.5
            if lam < 1e-12:
                raise TiltConvergenceError(
                    f"{what}: the line search stalled at iteration {it} (scaled residual "
                    f"{math.sqrt(phi):.3g}){_hint(pair, rows, st)}")
        x, st, r, phi = xn, stn, rn, phin
    raise TiltConvergenceError(f"{what}: no convergence in {_MAX_ITER} Newton iterations "
                               f"(scaled residual {np.max(np.abs(w * r)):.3g})"
                               f"{_hint(pair, rows, st)}")


def _hint(pair: BallPair, rows: _Rows, st) -> str:
    """Why a fixed contact angle fails: a row out of contact leaves the other row alone,
    whose ball forces all pass through its pressure-cone apex."""
    if pair.contact_angle_model != "fixed" or rows.n_rows < 2:
        return ""
    idle = [i for i in range(rows.n_rows) if not np.any(st[1][rows.row == i] > 0)]
    if not idle:
        return ""
    return (f"; row {idle[0]} carries nothing, and with a fixed contact angle the other row's "
            "ball forces all pass through its pressure-cone apex, so it cannot take a radial "
            "force and a moment independently: use contact_angle_model='varying'")




# ---------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TiltResult:
    """Equilibrium of the carrier on the bearing (SI). Ball arrays are (rows, Z): row 0 at
    z = -span/2 (carries +z axial force), row 1 at +span/2; ball j at ``azimuth_rad[j]``."""

    radial_N: float
    axial_N: float
    moment_Nm: float
    radial_displacement_m: float      # delta_x of the carrier
    axial_displacement_m: float       # delta_z
    tilt_rad: float                   # theta about y
    azimuth_rad: np.ndarray           # (Z,)
    ball_load_N: np.ndarray           # Q, 0 where a ball lost contact
    contact_angle_rad: np.ndarray     # loaded contact angle
    approach_m: np.ndarray            # delta = L - A (negative: out of contact)
    pressure_Pa: np.ndarray           # peak Hertz pressure, larger of inner and outer contact
    max_ball_load_N: float
    max_ball_index: tuple             # (row, j) of the most loaded ball
    max_pressure_Pa: float            # its peak pressure (the largest of all)
    row_radial_N: np.ndarray          # (rows,) x force each row takes from the carrier
    row_axial_N: np.ndarray           # (rows,) z force, signed (sum: the axial load)
    row_moment_Nm: np.ndarray         # (rows,) moment about the pair's centre (sum: M)
    stiffness: np.ndarray             # (3, 3) tangent dG/d(delta_x, delta_z, theta)
    tangent_moment_rigidity_Nm_per_rad: float   # dM/dtheta, the forces held
    iterations: int
    preload: PreloadState = field(repr=False)

    @property
    def tilt_arcmin(self) -> float:
        """Tilt [arcmin]."""
        return self.tilt_rad / ARCMIN

    @property
    def balls_in_contact(self) -> int:
        """Balls that carry load."""
        return int(np.count_nonzero(self.ball_load_N > 0))


def _result(pair, rows, k_const, x, it, load, pre, shape) -> TiltResult:
    delta, q, alpha, nr, na, g, jac = _state(pair, rows, k_const, x)
    rc = pair.inner_centre_radius_m
    fr = q * nr * rows.cpsi
    fz = q * na * rows.sign
    mom = q * (nr * rows.zc - rows.sign * na * rc) * rows.cpsi
    n = rows.n_rows
    row_sum = lambda v: np.array([v[rows.row == i].sum() for i in range(n)])   # noqa: E731
    p = np.zeros_like(q)
    on = q > 0
    if np.any(on):
        p[on] = ball_pressure_Pa(pair, q[on], alpha[on])
    imax = int(np.argmax(q))
    try:
        tangent = 1.0 / np.linalg.inv(jac)[2, 2]
    except np.linalg.LinAlgError:
        tangent = float("nan")
    return TiltResult(
        float(load[0]), float(load[1]), float(load[2]), float(x[0]), float(x[1]), float(x[2]),
        pair.azimuths_rad, q.reshape(shape), alpha.reshape(shape), delta.reshape(shape),
        p.reshape(shape), float(q[imax]), divmod(imax, pair.balls_per_row), float(p.max()),
        row_sum(fr), row_sum(fz), row_sum(mom), jac, float(tangent), it, pre)


def _what(fn, radial_N, axial_N, moment_Nm):
    return (f"tilt.{fn}(radial_N={radial_N:g}, axial_N={axial_N:g}, "
            f"moment_Nm={moment_Nm:g})")


def _loads(radial_N, axial_N, moment_Nm):
    for name, v in (("radial_N", radial_N), ("axial_N", axial_N), ("moment_Nm", moment_Nm)):
        check_range(name, v)
    return np.array([radial_N, axial_N, moment_Nm], float)


def solve(pair: BallPair, radial_N: float, axial_N: float, moment_Nm: float) -> TiltResult:
    """Equilibrium of the carrier on the preloaded pair under external loads.

    Parameters
    ----------
    pair : BallPair
        The bearing pair.
    radial_N : float
        Radial force on the carrier along +x [N], acting in the pair's centre plane.
    axial_N : float
        Axial force on the carrier along +z [N] (row 0 carries the positive sense).
    moment_Nm : float
        Tilting moment M_y on the carrier about the pair's centre [N m].

    Returns
    -------
    TiltResult
        Carrier displacements (radial, axial, tilt), every ball's load, loaded contact angle,
        approach and peak pressure, the most loaded ball and its pressure, each row's
        resultants, the tangent stiffness.

    Raises
    ------
    TiltConvergenceError
        When Newton's method does not converge (the message names the loads).
    """
    load = _loads(radial_N, axial_N, moment_Nm)
    pre = preload_state(pair)
    k_const = raceway_contact(pair).K
    rows = _pair_rows(pair, pre.interference_m)
    x, it, _ = _newton(pair, rows, k_const, load, (True, True, True),
                       _what("solve", radial_N, axial_N, moment_Nm))
    return _result(pair, rows, k_const, x, it, load, pre, (2, pair.balls_per_row))


def solve_row(pair: BallPair, radial_N: float, axial_N: float,
              hold_axial: bool = False) -> TiltResult:
    """One row of the pair alone (row 0's geometry at z = 0, no preload, zero clearance),
    its tilt held: the textbook single bearing of the checks (Stribeck, pure axial load).

    Parameters
    ----------
    pair : BallPair
        The bearing (its preload and span are not used).
    radial_N : float
        Radial force on the inner ring along +x [N].
    axial_N : float
        Axial force on the inner ring along +z [N], >= 0 for contact (ignored with
        ``hold_axial``).
    hold_axial : bool
        Hold the axial displacement at 0 (the reaction is ``row_axial_N``): the radial load
        of Stribeck's half-loaded raceway on an angular-contact row.

    Returns
    -------
    TiltResult
        As :func:`solve`, ball arrays (1, Z); ``moment_Nm`` is the moment the held tilt
        takes, ``tilt_rad`` 0.

    Raises
    ------
    TiltConvergenceError
        When Newton's method does not converge.
    """
    load = _loads(radial_N, 0.0 if hold_axial else axial_N, 0.0)
    if not hold_axial:
        check_range("axial_N", axial_N, 0.0, why="a single row takes thrust toward +z only")
    k_const = raceway_contact(pair).K
    rows = _single_row(pair)
    x, it, _ = _newton(pair, rows, k_const, load, (True, not hold_axial, False),
                       f"tilt.solve_row(radial_N={radial_N:g}, axial_N={axial_N:g}, "
                       f"hold_axial={hold_axial})")
    pre = PreloadState(0.0, 0.0, pair.contact_angle_rad, 0.0)
    res = _result(pair, rows, k_const, x, it, load, pre, (1, pair.balls_per_row))
    return _replace_loads(res, load[0], float(res.row_axial_N.sum()),
                          float(res.row_moment_Nm.sum()))


def _replace_loads(res: TiltResult, radial, axial, moment) -> TiltResult:
    return replace(res, radial_N=float(radial), axial_N=float(axial), moment_Nm=float(moment))


# ---------------------------------------------------------------------------------------
# Catalogue quantities
# ---------------------------------------------------------------------------------------

def moment_rigidity_Nm_per_arcmin(pair: BallPair, moment_Nm: float, radial_N: float = 0.0,
                                  axial_N: float = 0.0) -> float:
    """The catalogue's moment rigidity: the secant M / theta [N m/arcmin].

    theta is the tilt at ``moment_Nm`` less the tilt at zero moment under the same radial
    and axial force (0 for the symmetric pair under a radial force in its centre plane).

    Parameters
    ----------
    pair : BallPair
        The bearing pair.
    moment_Nm : float
        The tilting moment [N m]; 0 gives the tangent at zero moment.
    radial_N, axial_N : float
        External radial and axial force [N] held while the moment acts.

    Returns
    -------
    float
        M / theta [N m/arcmin].
    """
    if moment_Nm == 0:
        return tangent_moment_rigidity_Nm_per_arcmin(pair, 0.0, radial_N, axial_N)
    th = solve(pair, radial_N, axial_N, moment_Nm).tilt_rad
    th0 = solve(pair, radial_N, axial_N, 0.0).tilt_rad
    return moment_Nm / (th - th0) * ARCMIN


def tangent_moment_rigidity_Nm_per_arcmin(pair: BallPair, moment_Nm: float,
                                          radial_N: float = 0.0, axial_N: float = 0.0
                                          ) -> float:
    """The tangent moment rigidity dM/dtheta at a moment [N m/arcmin] (forces held).

    Parameters
    ----------
    pair : BallPair
        The bearing pair.
    moment_Nm : float
        The tilting moment [N m].
    radial_N, axial_N : float
        External radial and axial force [N].

    Returns
    -------
    float
        dM/dtheta [N m/arcmin].
    """
    res = solve(pair, radial_N, axial_N, moment_Nm)
    return res.tangent_moment_rigidity_Nm_per_rad * ARCMIN


def moment_at_pressure(pair: BallPair, pressure_Pa: float = ISO76_BALL_PRESSURE_PA,
                       radial_N: float = 0.0, axial_N: float = 0.0) -> float:
    """The tilting moment [N m] at which the most loaded ball reaches a peak Hertz pressure.

    Parameters
    ----------
    pair : BallPair
        The bearing pair.
    pressure_Pa : float
        The pressure [Pa]; default ISO 76's 4200 MPa of ball bearings (static rating).
    radial_N, axial_N : float
        External radial and axial force [N] acting with the moment.

    Returns
    -------
    float
        M >= 0 [N m] (the positive sense; the pair is symmetric).

    Raises
    ------
    ToothfemError
        When the preload and the forces alone already reach the pressure.
    """
    check_range("pressure_Pa", pressure_Pa, 0.0, lo_open=True)
    p = lambda m: solve(pair, radial_N, axial_N, m).max_pressure_Pa - pressure_Pa  # noqa: E731
    p0 = p(0.0)
    if p0 >= 0:
        raise ToothfemError(f"moment_at_pressure: the preload and the forces alone give "
                            f"{(p0 + pressure_Pa) / PA_PER_MPA:.0f} MPa >= "
                            f"{pressure_Pa / PA_PER_MPA:.0f} MPa")
    # bracket: a moment that gives each ball of the loaded half a few times the pressure's load
    hi = max(pair.preload_N, abs(radial_N), abs(axial_N), 1.0) * pair.pressure_centre_spread_m
    while p(hi) < 0:
        hi *= 2
    return brentq(p, 0.0, hi, xtol=1e-9 * hi, rtol=1e-10)
