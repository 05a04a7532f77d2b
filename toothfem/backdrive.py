"""Backdrive and starting torque, the no-load running torque against speed, and the torque
bandwidth of a joint (``toothfem modes``; docs/dynamics.md "Starting, backdrive and
bandwidth").

Backdrive. A torque T on the output with the input free turns the train as its rigid
motion (:func:`toothfem.fem.system.modes.rigid_motion`); every friction pair of the system
model (fem/system/friction.py: the pin contacts, the crank and support bearings, the
output pins, the output's seal) slips by that motion per unit output rotation, under the
contact forces T sets up. The friction torque the output meets is T_f(T) = c0 + c1 |T|
(Coulomb: forces in proportion to the load, c0 the load-independent seal), found at two
torques (the fit's residual at the answer is reported); motion starts at
T_b = c0 / (1 - c1), and the train is self-locking where c1 >= 1. Both flanks.
Starting torque at the input, the output free: the mesh carries the friction torque the
output meets, the same T_b, so T_in = T_b / |i| (the input's own bearings are not in the
system model: add their torque).

The no-load running torque: the efficiency model's losses at a vanishing output torque
(toothfem.efficiency.evaluate; churning, seals, bearings' load-independent parts) over the
input speed.

Torque bandwidth: the input free with the motor's inertia on it, a harmonic motor torque;
the torque that accelerates the output and its load, J_out x_out'' (J_out: the load and the
output's own inertia), against frequency; its -3 dB point above the flat part (its first
fall below 1/sqrt(2) of its low-frequency value), at each meshing position.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .efficiency import rated_output_torque
from .efficiency.evaluation import evaluate
from .efficiency.no_load import path_friction
from .fem.drives import drive_for
from .fem.system import modes as fm
from .fem.system.friction import friction_torques
from .fem.system.response import ModalSystem
from .fem.system.solve import ContactSet

#: The two torques of the friction's fit, as fractions of the rated torque.
FIT_TORQUES = (0.02, 1.0)
#: The no-load running torque's speeds: log-spaced from this fraction of the top speed.
NO_LOAD_FROM, NO_LOAD_SPEEDS = 0.01, 10
#: A vanishing output torque for the no-load losses [N m] (the efficiency model needs one).
NO_LOAD_TORQUE_NM = 1e-3
#: The bandwidth's frequency grid: from 1e-2 to 1e2 of the first flexible mode.
BANDWIDTH_POINTS = 800


def _pins(system, state) -> list:
    """(ContactSet, MeshContacts) of each member as the state solved them (what
    :func:`toothfem.fem.system.friction.friction_torques` reads: the set's name)."""
    out = []
    for s, sol in zip(system.slots, state.mesh):
        mc = sol.contacts
        out.append((ContactSet(f"mesh {system.drive.member_name} {s.index + 1}", "mesh",
                               mc.g0, np.zeros((mc.g0.size, system.coords.n))), mc))
    return out


def friction_of_motion(system, states, friction) -> dict:
    """The friction torque on the output per source as the train turns rigidly, the mean
    over the states' positions [N m].

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    states : list of toothfem.fem.system.parts.SystemState
    friction : toothfem.fem.system.friction.PathFriction

    Returns
    -------
    dict of str to float
    """
    acc: dict[str, float] = {}
    for st in states:
        r, _ = fm.rigid_motion(system, st)
        eq = dataclasses.replace(st.equilibrium, rate=r)
        for k, v in friction_torques(system, st.position_rad, _pins(system, st), eq,
                                     friction).items():
            acc[k] = acc.get(k, 0.0) + v / len(states)
    return acc


def backdrive(case, *, positions: int = 12) -> dict:
    """Backdrive torque at the output and starting torque at the input, both directions.

    Parameters
    ----------
    case : toothfem.case.Case
    positions : int
        Positions per meshing period (their mean).

    Returns
    -------
    dict
        ``by_direction``: per flank (``positive``, ``negative``) the backdrive torque
        [N m], the input starting torque [N m], c0, c1, the fit's residual, the friction by
        source at T_b, ``self_locking``; and the definition.
    """
    si = case.to_si()
    drive = drive_for(si)
    supports = drive.supports(si.supports)
    system: Any = drive.system_model(supports, positions)
    fr = path_friction(si, drive)
    rated = rated_output_torque(si)[0]
    w = drive.speeds()
    ratio = abs(w["input"] / w["output"])

    def states(t):
        out, last = [], None
        for p in range(positions):
            last = system.solve(t, p, start=last)
            out.append(last)
        return out

    result = {}
    for name, sign in (("positive", 1.0), ("negative", -1.0)):
        t1, t2 = (f * rated for f in FIT_TORQUES)
        f1 = sum(friction_of_motion(system, states(sign * t1), fr).values())
        f2 = sum(friction_of_motion(system, states(sign * t2), fr).values())
        c1 = (f2 - f1) / (t2 - t1)
        c0 = f1 - c1 * t1
        locking = c1 >= 1.0
        tb = math.inf if locking else c0 / (1.0 - c1)
        at = {} if locking else friction_of_motion(system, states(sign * max(tb, 1e-6)), fr)
        result[name] = {
            "backdrive_torque_Nm": tb, "input_starting_torque_Nm": tb / ratio,
            "friction_constant_Nm": c0, "friction_per_torque": c1, "self_locking": locking,
            "fit_residual_Nm": (math.nan if locking else sum(at.values()) - tb),
            "friction_by_source_Nm": at}
    return {"by_direction": result, "definition": (
        "the output torque that turns the train from rest with the input free: T_b = c0 / "
        "(1 - c1), the friction T_f = c0 + c1 |T| of every friction pair of the system "
        "model slipping with the train's rigid motion (fit at "
        f"{FIT_TORQUES[0]:g} and {FIT_TORQUES[1]:g} x the rated torque); the input's "
        "starting torque T_b / |i| (the input's own bearings not included)"),
        "friction": {"pin_disc": fr.pin_disc, "pin_groove": fr.pin_groove,
                     "bearing": fr.bearing, "output_pin": fr.output_pin,
                     "output_torque_Nm": fr.output_torque_Nm}}


def no_load_torque(case, top_rpm: float) -> dict:
    """The no-load running torque at the input against input speed.

    Parameters
    ----------
    case : toothfem.case.Case
    top_rpm : float

    Returns
    -------
    dict
        ``speeds_rpm``, ``torque_Nm`` (at the input), the losses' sum [W].
    """
    speeds = np.geomspace(NO_LOAD_FROM * top_rpm, top_rpm, NO_LOAD_SPEEDS)
    e = evaluate(case, speeds, NO_LOAD_TORQUE_NM)
    loss = np.asarray(e.input_power_W, float) - np.asarray(e.output_power_W, float)
    torque = loss / (speeds * 2 * math.pi / 60)
    return {"speeds_rpm": speeds.tolist(), "input_torque_Nm": torque.tolist(),
            "loss_W": loss.tolist(),
            "definition": "the efficiency model's losses at a vanishing output torque "
                          f"({NO_LOAD_TORQUE_NM:g} N m) over the input speed"}


def torque_bandwidth(lins_free, mass, zeta: float, out_index: int) -> dict:
    """The -3 dB frequency of the output torque's response to the motor torque, each
    position's (the input free: ``lins_free`` with the input's coordinate last).

    Parameters
    ----------
    lins_free : list of toothfem.fem.system.modes.Linearised
    mass : numpy.ndarray
        With the input's coordinate (the motor's inertia on it).
    zeta : float
        Modal damping ratio.
    out_index : int

    Returns
    -------
    dict
        ``bandwidth_Hz`` (mean), its ``range_Hz`` over the positions, and the first
        flexible mode's mean [Hz].
    """
    bw, first = [], []
    j_out = mass[out_index, out_index]
    for lin in lins_free:
        modal = ModalSystem(lin.k, mass, zeta)
        w = np.sqrt(modal.w2[modal.w2 > fm.RIGID_RTOL * modal.w2.max()])
        w1 = float(w.min())
        first.append(w1 / (2 * math.pi))
        omega = np.geomspace(1e-2 * w1, 1e2 * w1, BANDWIDTH_POINTS)
        force = np.zeros((1, lin.k.shape[0]))
        force[0, -1] = 1.0
        x = modal.response(np.repeat(force, omega.size, axis=0), omega)[:, out_index]
        gain = j_out * omega ** 2 * np.abs(x)
        gain = gain / gain[0]
        below = np.flatnonzero(gain < 1 / math.sqrt(2))
        if below.size == 0:
            bw.append(math.inf)
            continue
        i = below[0]
        # log-linear interpolation between the grid points about the crossing
        a, b = np.log(gain[i - 1]), np.log(gain[i])
        f = (math.log(1 / math.sqrt(2)) - a) / (b - a)
        bw.append(float(np.exp(np.log(omega[i - 1]) + f * np.log(omega[i] / omega[i - 1]))
                        / (2 * math.pi)))
    return {"bandwidth_Hz": float(np.mean(bw)), "range_Hz": [min(bw), max(bw)],
            "first_mode_Hz": float(np.mean(first)),
            "definition": "the -3 dB point of J_out x_out'' per motor torque (input free), "
                          "J_out the load and the output's own inertia"}
