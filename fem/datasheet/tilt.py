"""The output (main) bearing pair of a precision reducer under a radial force, an axial force
and a tilting moment: its tilt, its ball loads and Hertz pressures (:func:`solve`), the
catalogue's "moment rigidity" (N m/arcmin, :func:`moment_rigidity_Nm_per_arcmin`) and the
moment at a given contact pressure (:func:`moment_at_pressure`, N m). Units SI everywhere (N,
m, Pa, rad); the catalogue's N m/arcmin only in the names that say so.

The pair (:class:`~toothfem.fem.datasheet.ball_pair.BallPair`) is the RV-E's: two rows of
angular-contact balls back to back, preloaded, the carrier loaded and the housing held. The
model (rigid rings, Jones's loaded contact angle, the preload as an axial interference,
Newton's method on the carrier's displacement), the catalogue quantities and the sources:
docs/tilt.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import brentq

from ...errors import ToothfemError, check_range
from ...units import ARCMIN, PA_PER_MPA
from .ball_pair import BallPair, ball_pressure_Pa, raceway_contact

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


class TiltConvergenceError(ToothfemError):
    """The bearing pair's equilibrium was not found (the message names the loads)."""


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
