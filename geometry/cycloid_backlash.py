"""The cycloid disc on its pins before any load: where it sits (:func:`placement`), how far
it can turn (the backlash, :func:`closing_rotation`, :func:`before_load`) and the
first-order initial clearance of a modified disc in closed form
(:func:`clearance_closed_form`; docs/derivations.md, sections C4 and C6). Lengths in m,
angles in rad; :func:`before_load` reports in um and arcmin.
"""
from __future__ import annotations

import math

import numpy as np

from .cycloid import CycloidGeometry
from .cycloid_mesh import _moment_arms, clearance_exact, seed_moment_arm
from ..units import ARCMIN, UM_PER_M


def placement(gap, arm):
    """Where the disc sits before load: the turn that makes its worst pin's clearance the
    largest, per position.

    With g_i(beta) = g_i + beta l_i (both flanks, linear in the turn beta), the disc can
    be put on its pins without load where some beta leaves every g_i(beta) >= 0; the
    largest smallest clearance, max over beta of min_i g_i(beta), is the disc's clearance
    before load, and where it is negative it is the smallest interference any turn leaves
    (both flanks closed: the pins are preloaded on assembly).

    Parameters
    ----------
    gap : array_like, shape (P, C)
        g0 of the pins [m] (:func:`~toothfem.geometry.cycloid_mesh.clearance_exact`; inf: a
        pin that cannot touch).
    arm : array_like, shape (P, C)
        Their moment arms [m] (:func:`~toothfem.geometry.cycloid_mesh.meshing`'s sign).

    Returns
    -------
    beta : numpy.ndarray, shape (P,)
        The turn [rad] (inf where one flank has no reachable pin).
    clearance : numpy.ndarray, shape (P,)
        min_i g_i(beta) [m] (< 0: interference).
    """
    gap = np.atleast_2d(np.asarray(gap, float))
    arm = np.atleast_2d(np.asarray(arm, float))
    beta = np.empty(gap.shape[0])
    worst = np.empty(gap.shape[0])
    for p in range(gap.shape[0]):
        g, a = gap[p], arm[p]
        ok = np.isfinite(g)
        g, a = g[ok], a[ok]
        up, down = a > 0, a < 0              # g grows with beta / shrinks with beta
        if not (np.any(up) and np.any(down)):
            beta[p], worst[p] = math.inf, math.inf
            continue
        # the optimum lies where a shrinking and a growing gap are equal
        gi, ai = g[down][:, None], a[down][:, None]
        gj, aj = g[up][None, :], a[up][None, :]
        cand = ((gj - gi) / (ai - aj)).ravel()
        vals = np.min(g[None, :] + cand[:, None] * a[None, :], axis=1)
        k = int(np.argmax(vals))
        beta[p], worst[p] = cand[k], vals[k]
    return beta, worst


def clearance_closed_form(geom: CycloidGeometry, theta_b):
    """First-order initial clearance per pin versus pin angle theta_b (docs C4).

    Before any turning of the disc (nominal pose):
        D0 = Delta_rz - Delta_Rz (1 - K1 cos theta) / sqrt(S) + Delta_delta |l(theta)|
    with S = 1 + K1^2 - 2 K1 cos theta and l the moment arm of Eq. (14).
    Turning the disc by beta0 = min over 0 < theta < pi of D0/|l| closes the first gap on
    the load-carrying flank and leaves
        D(theta) = D0(theta) - beta0 |l(theta)|
    which for Delta_rz >= 0, Delta_Rz <= 0 is the textbook expression
        D = Delta_rz (1 - sin(theta)/sqrt(S)) - Delta_Rz (1 - K1 cos theta
            - sqrt(1 - K1^2) sin theta)/sqrt(S)
    (Li Lixing, Cycloid pin-wheel planetary transmission, 1987; also Blagojevic et al.,
    Strojniski vestnik 58 (2012)).

    Parameters
    ----------
    geom : CycloidGeometry
    theta_b : array_like
        Pin angles theta from the line of centres [rad], loaded flank 0 < theta < pi.

    Returns
    -------
    d0 : numpy.ndarray
        Clearance at the nominal pose [m], shape of ``theta_b``.
    d : numpy.ndarray
        Clearance after the turn beta0 [m], shape of ``theta_b``.
    beta0 : float
        The closing rotation [rad] (:func:`closing_rotation`).
    """
    theta = np.asarray(theta_b, float)
    k1 = geom.k1
    s = np.sqrt(1 + k1**2 - 2 * k1 * np.cos(theta))
    arm = np.abs(seed_moment_arm(geom, theta))
    d0 = (geom.equidistant_m - geom.move_distance_m * (1 - k1 * np.cos(theta)) / s
          + geom.rotation_rad * arm)
    beta0 = closing_rotation(geom)
    return d0, d0 - beta0 * arm, beta0


def closing_rotation(geom: CycloidGeometry) -> float:
    """beta0 = min over the loaded flank of D0/|l| (first order, closed form): the disc's
    angular lost motion (backlash) in one direction.

    For Delta_rz, -Delta_Rz >= 0 both terms are smallest at cos(theta) = K1, giving
    beta0 = (Delta_rz - Delta_Rz sqrt(1 - K1^2)) / r_a + Delta_delta; otherwise it is
    found on a fine grid.

    Parameters
    ----------
    geom : CycloidGeometry

    Returns
    -------
    float
        beta0 [rad].
    """
    k1 = geom.k1
    if geom.equidistant_m >= 0 and geom.move_distance_m <= 0:
        return ((geom.equidistant_m - geom.move_distance_m * math.sqrt(1 - k1**2))
                / geom.disc_pitch_radius_m + geom.rotation_rad)
    from scipy.optimize import minimize_scalar

    def ratio(theta):
        s = np.sqrt(1 + k1**2 - 2 * k1 * np.cos(theta))
        d0 = geom.equidistant_m - geom.move_distance_m * (1 - k1 * np.cos(theta)) / s
        return d0 / np.abs(seed_moment_arm(geom, theta))

    theta = np.linspace(1e-3, math.pi - 1e-3, 4001)
    k = int(np.argmin(ratio(theta)))
    lo, hi = theta[max(k - 1, 0)], theta[min(k + 1, theta.size - 1)]
    res = minimize_scalar(lambda t: float(ratio(t)), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-12})
    return float(min(res.fun, ratio(theta[k]))) + geom.rotation_rad


def before_load(geom: CycloidGeometry, crank_angle_rad) -> dict:
    """The disc on its pins before any load, over the given crank angles: how far it can
    turn (the backlash) and the clearance or interference that remains wherever it is
    put (:func:`placement` on the exact gaps of both flanks,
    :func:`~toothfem.geometry.cycloid_mesh.clearance_exact`).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc with its modifications.
    crank_angle_rad : array_like, shape (P,)
        Crank angles [rad] (e.g. one meshing period).

    Returns
    -------
    dict
        ``backlash_min_arcmin``, ``backlash_max_arcmin``: the sum of both flanks' closing
        rotations (min over each flank's pins of g0/|l|) over the positions (None where
        the disc interferes: it has no backlash); ``clearance_before_load_um``: the
        smallest, over the positions, of the largest smallest clearance any turn of the
        disc leaves (negative: interference);
        ``interference_before_load_um`` (0 without interference), and where it is
        largest ``interference_position_deg``, ``interference_pins`` (pin indices within
        1 nm of it) and ``interference_flanks`` ("+": the flank that carries a positive
        disc torque, moment arm < 0; "-": the other).
    """
    phi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    arm = _moment_arms(geom, phi)
    gap = clearance_exact(geom, phi, 0) if geom.modified else np.zeros_like(arm)
    with np.errstate(divide="ignore", invalid="ignore"):
        close_pos = np.min(np.where(arm < 0, gap / np.where(arm < 0, -arm, 1), np.inf), axis=1)
        close_neg = np.min(np.where(arm > 0, gap / np.where(arm > 0, arm, 1), np.inf), axis=1)
    backlash = close_pos + close_neg
    beta, clear = placement(gap, arm)
    p = int(np.argmin(clear))
    worst = float(clear[p])
    at = gap[p] + beta[p] * arm[p]
    pins = np.flatnonzero(at <= worst + _NAMED_TOL) if worst < 0 else np.array([], int)
    arcmin = 1 / ARCMIN
    free = worst >= 0
    return {
        "backlash_min_arcmin": float(np.min(backlash) * arcmin) if free else None,
        "backlash_max_arcmin": float(np.max(backlash) * arcmin) if free else None,
        "clearance_before_load_um": worst * UM_PER_M,
        "interference_before_load_um": max(0.0, -worst * UM_PER_M),
        "interference_position_deg": math.degrees(float(phi[p])) if worst < 0 else None,
        "interference_pins": [int(j) for j in pins],
        "interference_flanks": ["+" if arm[p, j] < 0 else "-" for j in pins],
    }


#: Pins whose interference is within this of the largest are named with it [m].
_NAMED_TOL = 1e-9
