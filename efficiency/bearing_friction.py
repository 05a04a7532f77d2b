"""Friction of a reducer's rolling bearings: Palmgren's moment of one bearing,
M = M0 + M1 [N m] (:func:`friction_moment`: the viscous M0 of :mod:`.palmgren` and the load
term mu P d_m / 2 with the case's ``friction.bearing_coefficient``), and the loss [W] of
every bearing group of a reducer (:func:`bearing_losses`). The model, its sources and why
Palmgren's and not SKF's four-term model: docs/efficiency.md, "Every bearing, the
lubrication and the RV-40E against its maker".
"""
from __future__ import annotations

import numpy as np

from .bearing_set import Bearing, reducer_bearings
from .palmgren import palmgren_f0, palmgren_no_load_moment


def friction_moment(bearing: Bearing, load_N, nu_m2_s, speed_rad_s, lubrication: str,
                    coefficient: float):
    """Palmgren's friction moment of one bearing [N m]: M0 (viscous, f0 of the type and
    lubrication) + mu P d_m / 2 (module docstring).

    Parameters
    ----------
    bearing : Bearing
    load_N : array_like
        Equivalent load P on the bearing [N].
    nu_m2_s : array_like
        The oil's (grease's base oil's) kinematic viscosity [m^2/s].
    speed_rad_s : array_like
        Speed of the rotating ring relative to the other [rad/s].
    lubrication : str
        "grease", "oil_mist", "oil_bath" or "oil_jet".
    coefficient : float
        mu = 2 f1 [-] (``friction.bearing_coefficient``).

    Returns
    -------
    numpy.ndarray
        M [N m].
    """
    m0 = palmgren_no_load_moment(palmgren_f0(bearing.bearing_type, lubrication), nu_m2_s,
                                 speed_rad_s, bearing.pitch_diameter_m)
    return m0 + coefficient * np.abs(np.asarray(load_N, float)) * bearing.pitch_diameter_m / 2


def bearing_losses(si, drive, loads: dict, input_rad_s, viscosity_factor) -> dict:
    """Friction loss of every bearing group of a reducer [W]: each bearing's Palmgren
    moment (:func:`friction_moment`) at its load and its speed relative to its other ring;
    in an oil bath with a churning law its load term only (the law lumps the bearings'
    viscous drag, :mod:`.no_load`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    loads : dict
        Group name -> (M,) sum of the loads on the group's bearings [N] (a group left out
        carries none: its viscous moment only).
    input_rad_s, viscosity_factor : numpy.ndarray
        (M,) input speed [rad/s] and eta(T)/eta_ref of the oil.

    Returns
    -------
    dict
        Group name -> (M,) [W].
    """
    lub = si.lubricant
    nu = lub.kinematic_viscosity_m2_s * np.asarray(viscosity_factor, float)
    # in an oil bath the churning law lumps the bearings' viscous drag (efficiency/no_load.py)
    lumped = lub.lubrication == "oil_bath" and lub.churning != "none"
    out = {}
    for b in reducer_bearings(si, drive):
        speed = np.abs(input_rad_s) * b.speed_per_input
        m0 = 0.0 if lumped else friction_moment(b, 0.0, nu, speed, lub.lubrication, 0.0)
        load = loads.get(b.name, 0.0)
        m1 = si.friction.bearing_coefficient * load * b.pitch_diameter_m / 2
        out[b.name] = (b.count * m0 + m1) * speed
    return out
