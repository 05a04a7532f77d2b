"""A back-to-back (O) pair of angular-contact ball rows, the output (main) bearing of a
precision reducer (:class:`BallPair`, SI), and the Hertz constants of a ball on its two
raceways: the approach and peak-pressure coefficients (:func:`raceway_contact`) and the peak
pressure of loaded balls (:func:`ball_pressure_Pa`, Pa). The pair's geometry and the contact
model: docs/tilt.md, section "Model"; its tilt under load: :mod:`.tilt`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import ToothfemError, check_range
from ..hertz import reduced_modulus
from .hertz_point import HERTZ_METHODS, hertz_point_contact

_MODELS = ("varying", "fixed")


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
        if self.hertz_method not in HERTZ_METHODS:
            raise ToothfemError(f"hertz_method = {self.hertz_method!r}: one of {HERTZ_METHODS}")
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
