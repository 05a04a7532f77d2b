"""Train kinematics from tooth numbers.

Sign convention (written once, used everywhere): every angular velocity is measured about
the reducer axis, counter-clockwise positive, in the frame of the housing. A ratio is
``i = omega_input / omega_output``; i > 0 means output turns the same way as the input.

Willis' equation for a gear pair (a, b) on a carrier H:
``(omega_a - omega_H) / (omega_b - omega_H) = -z_b / z_a`` for an external mesh and
``+z_b / z_a`` for an internal mesh (pin ring, ring gear).

K-H-V (cycloid stage, sine pair): crank H is the input, the internal member with
``z_fixed`` teeth (pin ring, ring gear) is held, the moving member (disc, planet, with
``z_moving`` teeth) is the output through a pins-in-holes (V) mechanism.

2K-V (RV): the sun (input) drives planets on crankshafts that are carried by the output
carrier; the crankshafts are the H of the K-H-V stage, whose disc turns with the carrier
(RV paper Eqs. 1-3).

The ratios are obtained by solving the Willis equations as a linear system
(:func:`solve_train`), not typed as closed forms; the closed forms are kept for the docs
and cross-checked in the tests.
"""
from __future__ import annotations

import numpy as np

from ..errors import GeometryError, check_range


def _teeth(name, z):
    if isinstance(z, bool) or int(z) != z:
        raise GeometryError(f"{name} = {z!r} must be an integer")
    return int(check_range(name, z, 1, None, error=GeometryError))


def solve_train(equations, fixed, names):
    """Solve linear speed constraints.

    Parameters
    ----------
    equations : list of (dict, float)
        ``({name: coefficient}, rhs)`` rows, each linear in the angular velocities.
    fixed : dict
        ``{name: value}`` speeds imposed (input = 1, housing = 0), any consistent unit.
    names : list of str
        The members.

    Returns
    -------
    dict
        ``{name: omega}``, the unit of ``fixed``; the imposed speeds exactly.

    Raises
    ------
    GeometryError
        If the train is not determined.
    """
    idx = {n: k for k, n in enumerate(names)}
    rows, rhs = [], []
    for coeffs, b in equations:
        row = np.zeros(len(names))
        for n, c in coeffs.items():
            row[idx[n]] = c
        rows.append(row)
        rhs.append(b)
    for n, v in fixed.items():
        row = np.zeros(len(names))
        row[idx[n]] = 1.0
        rows.append(row)
        rhs.append(v)
    a = np.array(rows)
    if np.linalg.matrix_rank(a) < len(names):
        raise GeometryError("the train's speeds are not determined by its constraints")
    sol = dict(zip(names, np.linalg.lstsq(a, np.array(rhs, float), rcond=None)[0]))
    sol.update({n: float(v) for n, v in fixed.items()})  # imposed speeds exactly
    return sol


def willis(a, b, carrier, z_a, z_b, internal):
    """Willis row: (w_a - w_H) - k (w_b - w_H) = 0 with k = +-z_b/z_a.

    Parameters
    ----------
    a, b : str
        Names of the two meshing members.
    carrier : str
        Name of the carrier H.
    z_a, z_b : int
        Their tooth numbers.
    internal : bool
        An internal mesh (k = +z_b/z_a) or an external one (k = -z_b/z_a).

    Returns
    -------
    tuple of (dict, float)
        One row for :func:`solve_train`.
    """
    k = (z_b / z_a) if internal else -(z_b / z_a)
    return ({a: 1.0, carrier: -1.0 + k, b: -k}, 0.0)


def khv_speeds(z_moving, z_fixed):
    """Speeds of a K-H-V stage for unit crank speed.

    Parameters
    ----------
    z_moving : int
        Teeth of the moving member (disc lobes, planet teeth), >= 1.
    z_fixed : int
        Teeth of the held member (pins, ring teeth), >= 1, not ``z_moving``.

    Returns
    -------
    dict
        {'crank', 'moving', 'fixed'} angular velocities per unit crank speed [-].

    Raises
    ------
    GeometryError
        If a tooth number is not a positive integer or the two are equal.
    """
    z_moving = _teeth("z_moving", z_moving)
    z_fixed = _teeth("z_fixed", z_fixed)
    if z_moving == z_fixed:
        raise GeometryError(f"z_fixed = {z_fixed} must differ from z_moving = {z_moving}")
    return solve_train([willis("moving", "fixed", "crank", z_moving, z_fixed, internal=True)],
                       {"crank": 1.0, "fixed": 0.0}, ["crank", "moving", "fixed"])


def khv_ratio(z_moving, z_fixed) -> float:
    """Crank-to-output ratio of a K-H-V stage; closed form z_m/(z_m - z_f) (-39 for a
    39-lobe disc in 40 pins, -79 for the 79/80 sine pair).

    Parameters
    ----------
    z_moving : int
        Teeth of the moving member (disc lobes, planet teeth).
    z_fixed : int
        Teeth of the held member (pins, ring teeth).

    Returns
    -------
    float
        i = omega_crank / omega_moving [-].

    Raises
    ------
    GeometryError
        As :func:`khv_speeds`.
    """
    w = khv_speeds(z_moving, z_fixed)
    return w["crank"] / w["moving"]


def rv_speeds(z_sun, z_planet, z_disc, z_pins):
    """Speeds of a 2K-V (RV) train for unit sun speed.

    Members: sun 1, planet/crankshaft 2=3, disc 4 = output carrier 6/7, pins 5 (fixed).
    RV paper Eq. 1: (w1 - w7)/(w2 - w7) = -z2/z1; Eq. 2: (w4 - w3)/(w5 - w3) = z5/z4;
    Eq. 3: w2 = w3, w4 = w6 = w7. In Eq. 2 the crankshaft's absolute speed w3 acts as the
    K-H-V crank, because the disc's orbit follows the crank's absolute angle when the disc
    turns with the carrier.

    Parameters
    ----------
    z_sun, z_planet, z_disc, z_pins : int
        Tooth numbers (>= 1; ``z_pins`` not ``z_disc``).

    Returns
    -------
    dict
        {'sun', 'planet', 'disc', 'carrier', 'pins'} angular velocities per unit sun
        speed [-].

    Raises
    ------
    GeometryError
        If a tooth number is not a positive integer or z_pins == z_disc.
    """
    for name, z in (("z_sun", z_sun), ("z_planet", z_planet), ("z_disc", z_disc),
                    ("z_pins", z_pins)):
        _teeth(name, z)
    if z_pins == z_disc:
        raise GeometryError(f"z_pins = {z_pins} must differ from z_disc = {z_disc}")
    names = ["sun", "planet", "disc", "carrier", "pins"]
    eqs = [
        willis("sun", "planet", "carrier", z_sun, z_planet, internal=False),
        willis("disc", "pins", "planet", z_disc, z_pins, internal=True),
        ({"disc": 1.0, "carrier": -1.0}, 0.0),
    ]
    return solve_train(eqs, {"sun": 1.0, "pins": 0.0}, names)


def rv_ratio(z_sun, z_planet, z_disc, z_pins) -> float:
    """Sun-to-output ratio of a 2K-V train; closed form
    1 + (z_planet/z_sun) * z_pins/(z_pins - z_disc) (121 for RV-40E: 1 + 3*40).

    Parameters
    ----------
    z_sun, z_planet, z_disc, z_pins : int
        Tooth numbers.

    Returns
    -------
    float
        i = omega_sun / omega_carrier [-] (positive: output and input turn the same way).

    Raises
    ------
    GeometryError
        For a tooth number that is not a positive integer, or equal disc and pin counts.
    """
    w = rv_speeds(z_sun, z_planet, z_disc, z_pins)
    return w["sun"] / w["carrier"]
