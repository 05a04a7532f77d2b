"""The modes of a case's reducer and its Campbell diagram, as Python calls: ``modes_analysis``
(what ``toothfem modes`` calls; its files: :mod:`toothfem.report.modes`; the mechanics:
:mod:`toothfem.fem.system.inertia` and :mod:`toothfem.fem.system.modes`;
docs/dynamics.md).

The Campbell diagram: each named order of the transmission error (the drive's
``te_orders``: pin passing, lobe passing, crank, pin mesh, the first stage's mesh) and its
harmonics, with its amplitude in the TE spectrum over the full period
(:func:`toothfem.fem.system.datasheet.system_te`, the same TE ``stiffness`` writes), is an
excitation of frequency f = order x n_out, n_out the output's speed; it meets mode f_i at
the input speed n_in = 60 f_i / (order |w_out|) [rpm], w_out the output's speed per unit
input. A crossing inside the case's speed range of an order the spectrum carries is
warned.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .backdrive import torque_bandwidth
from .cad_parts import part_drawing
from .case import Case, as_case
from .efficiency import rated_output_torque
from .errors import CaseError, check_range
from .fem.drives import MAX_POSITIONS, drive_for
from .fem.system import inertia as fi, modes as fm
from .fem.system.datasheet import system_te
from .dynamic_response import DAMPING_RATIO

#: Positions per meshing period whose modes are averaged (each mode's range over them is
#: reported: the mesh stiffness's variation).
MODE_POSITIONS = 12
#: Harmonics of each named TE order drawn and searched for crossings.
HARMONICS = 3
#: An order whose spectral amplitude is below this fraction of the largest line is drawn
#: but its crossings are not warned (a line the nominal reducer's TE does not carry, e.g.
#: the first stage's mesh with a constant mesh stiffness).
WARN_AMPLITUDE_REL = 0.01
#: A spectral line below this fraction of the largest is round-off (a line the nominal TE
#: does not carry: the solver's RTOL is 1e-8 of the twist): its amplitude is taken as 0.
CARRIED_REL = 1e-6
#: The name of a line of the TE spectrum that is no named order's harmonic, and the
#: fraction of the largest line from which such a line is listed (a rich spectrum, a K-H-V
#: drive's sidebands of the mesh by the pin passing, has tens of lines at 1 %).
OTHER_LINE, OTHER_LINE_REL = "TE line", 0.1
#: The output torques, as fractions of the modes' torque, at which the lowest modes are
#: also found (how they move with torque: the contacts and rollers stiffen with load).
TORQUE_FRACTIONS = (0.25, 0.5, 2.0)
#: Modes listed (and written) at most.
MODES_LISTED = 12
#: Full-period TE sampling (as ``toothfem stiffness``'s default).
TE_SAMPLES, TE_PER_PITCH = 6, 12


@dataclass(frozen=True, kw_only=True)
class ModesResult:
    """The modes of a case at one output torque, its bodies, and the Campbell diagram."""
    case_name: str
    torque_Nm: float
    input_free: bool
    load_kgm2: float
    motor_kgm2: float
    bodies: fi.ReducerBodies
    modes: fm.Modes
    frequency_range_Hz: np.ndarray            # (modes, 2): min, max over the positions
    by_torque: dict                           # torque [N m] -> (modes,) [Hz]
    assumed: dict
    rigidity_Nm_per_rad: float                # the tangent at the torque, input held
    two_inertia_Hz: float                     # sqrt(k / J_out) / (2 pi)
    orders: list                              # {name, order, harmonic, amplitude_arcsec}
    crossings: list                           # {order name, mode, speed_rpm, warned}
    speed_range_rpm: tuple
    output_per_input: float
    warnings: list = field(default_factory=list)
    bandwidth: dict | None = None             # the input free: the torque bandwidth

    def table(self) -> list:
        """The mode list with each mode's strain-energy shares, as the terminal shows it.

        Returns
        -------
        list of (str, str, dict)
            (quantity, unit, {column: value}) rows (:func:`toothfem.report.summary.text`).
        """
        from .report.modes import mode_rows
        return mode_rows(self)

    def plot(self) -> dict:
        """The pictures: the first modes and the Campbell diagram.

        Returns
        -------
        dict
            File name -> matplotlib Figure.
        """
        from .report.modes import modes_figures
        return modes_figures(self)

    def write(self, folder) -> dict:
        """modes.csv, bodies.csv, campbell.csv, the pictures and summary.json into an
        existing ``folder``.

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary.
        """
        from .report.modes import write_modes
        return write_modes(self, folder)


def case_speed_range_rpm(case: Case) -> tuple[float, float]:
    """(0, the top input speed) of the case: ``operating.max_input_speed_rpm``, else the
    highest input speed of the operating point and the duty cycle [rpm].

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    tuple of float
    """
    op = case.operating
    if op.max_input_speed_rpm:
        return 0.0, float(op.max_input_speed_rpm)
    speeds = [op.input_speed_rpm] + [d.input_speed_rpm for d in case.duty_cycle]
    return 0.0, float(max(speeds))


def _states(system, torque: float) -> list:
    """The system's states at every position, each from its neighbour's."""
    out, last = [], None
    for p in range(system.n_positions):
        last = system.solve(torque, p, start=last)
        out.append(last)
    return out


def _linearised(system, states, input_free: bool) -> list:
    return [fm.linearise(system, s, input_free=input_free) for s in states]


def _over_positions(lins, mass, count: int) -> tuple:
    """The modes over the positions of one period: each position's own (a mechanism's
    kinematics move with the crank angle, so a mean of the tangents would lose the free
    input's exact rigid motion); the i-th frequency and shares averaged over them, the
    shape of the position nearest those frequencies, each frequency's range."""
    each = [fm.modes(lin, mass, count) for lin in lins]
    freq = np.array([m.frequency_Hz for m in each])
    mean = freq.mean(axis=0)
    near = each[int(np.argmin(np.abs(freq - mean).sum(axis=1)))]
    groups = {g for m in each for s in m.shares for g in s}
    blocks = {b for m in each for s in m.kinetic for b in s}
    shares = [{g: float(np.mean([m.shares[i].get(g, 0.0) for m in each])) for g in groups}
              for i in range(mean.size)]
    kinetic = [{b: float(np.mean([m.kinetic[i].get(b, 0.0) for m in each])) for b in blocks}
               for i in range(mean.size)]
    found = fm.Modes(frequency_Hz=mean, shapes=near.shapes, names=near.names,
                     shares=shares, kinetic=kinetic)
    return found, np.stack([freq.min(axis=0), freq.max(axis=0)], axis=1)


def modes_analysis(case, *, load_kgm2: float | None = None, motor_kgm2: float | None = None,
                   torque_Nm: float | None = None, input_free: bool = False,
                   positions: int = MODE_POSITIONS, count: int = MODES_LISTED,
                   campbell: bool = True) -> ModesResult:
    """The modes of a case's reducer at an output torque, and its Campbell diagram.

    Parameters
    ----------
    case : toothfem.case.Case
    load_kgm2, motor_kgm2 : float, optional
        The load's and the motor's inertia [kg m^2]; default the case's ``[operating]``.
    torque_Nm : float, optional
        The output torque the system is linearised at [N m], > 0; default the rated.
    input_free : bool
        The input free (the motor's inertia on it) or held.
    positions : int
        Positions per meshing period the tangent is averaged over.
    count : int
        Modes kept.
    campbell : bool
        Also the TE over the full period and the crossings.

    Returns
    -------
    ModesResult

    Raises
    ------
    CaseError
        For a value out of its range.
    """
    case = as_case(case)
    si = case.to_si()
    op = case.operating
    load = op.load_inertia_kgm2 if load_kgm2 is None else float(load_kgm2)
    motor = op.motor_inertia_kgm2 if motor_kgm2 is None else float(motor_kgm2)
    check_range("load_inertia_kgm2", load, 0.0, 1e6, error=CaseError)
    check_range("motor_inertia_kgm2", motor, 0.0, 1e4, error=CaseError)
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    check_range("count", count, 1, 1000, error=CaseError)
    if torque_Nm is None:
        torque_Nm = rated_output_torque(si)[0]
    check_range("torque_Nm", torque_Nm, 0.0, 1e6, lo_open=True, error=CaseError)
    t = float(torque_Nm)
    drive = drive_for(si)
    supports = drive.supports(si.supports)
    # the assembly itself (its coordinates and elements), beyond the ReducerModel protocol
    system: Any = drive.system_model(supports, int(positions))
    # each layout's builder lists its member first (toothfem/cad_parts.py)
    member = part_drawing(si, drive=drive).regions[0]
    bodies = fi.reducer_bodies(system, member, si.material.density_kg_m3,
                               output_pins=drive.path.output_mechanism,
                               first_stage=getattr(drive.path, "first_stage", None))
    n_in = system.coords.n if input_free else None
    mass = fi.mass_matrix(system, bodies, load_kgm2=load, motor_kgm2=motor,
                          input_index=n_in)
    states = _states(system, t)
    lins = _linearised(system, states, input_free)
    found, ranges = _over_positions(lins, mass, count)
    out = system.coords.index["out"].start
    bandwidth = torque_bandwidth(lins, mass, DAMPING_RATIO, out) if input_free else None
    held = lins if not input_free else _linearised(system, states, False)
    compliance = float(np.mean([fm.output_compliance(lin, out) for lin in held]))
    j_out = mass[out, out]
    by_torque = {t: found.frequency_Hz.tolist()}
    for f in TORQUE_FRACTIONS:
        lt = _linearised(system, _states(system, f * t), input_free)
        by_torque[f * t] = _over_positions(lt, mass, count)[0].frequency_Hz.tolist()
    w = drive.speeds()
    ratio = abs(w["output"] / w["input"])
    speed_range = case_speed_range_rpm(case)
    orders, crossings, warnings = [], [], []
    if campbell:
        te, _, _ = system_te(drive, supports, t, samples=TE_SAMPLES, per_pitch=TE_PER_PITCH)
        orders = te_orders(drive.te_orders(), te.orders_per_output_rev, te.amplitude_arcsec)
        crossings = find_crossings(orders, found.frequency_Hz, ratio, speed_range)
        for c in crossings:
            if c["warned"]:
                warnings.append(
                    f"{c['order_name']} (order {c['order']:g}, "
                    f"{c['amplitude_arcsec']:.3g} arcsec) crosses mode {c['mode']} "
                    f"({c['frequency_Hz']:.4g} Hz) at {c['speed_rpm']:.4g} rpm input, inside "
                    f"the case's speed range")
    return ModesResult(
        case_name=case.name, torque_Nm=t, input_free=input_free, load_kgm2=load,
        motor_kgm2=motor, bodies=bodies, modes=found,
        frequency_range_Hz=ranges, by_torque=by_torque, assumed=lins[0].assumed,
        rigidity_Nm_per_rad=1.0 / compliance,
        two_inertia_Hz=math.sqrt(1.0 / compliance / j_out) / (2 * math.pi),
        orders=orders, crossings=crossings, speed_range_rpm=speed_range,
        output_per_input=ratio, warnings=warnings, bandwidth=bandwidth)


def te_orders(named: dict, spectrum_orders, amplitude_arcsec) -> list:
    """Each named order and its harmonics with its amplitude in the TE spectrum.

    Parameters
    ----------
    named : dict
        Name -> order per output revolution (``Drive.te_orders``).
    spectrum_orders, amplitude_arcsec : array_like
        The TE's harmonics over the full period: order [per output rev], amplitude
        [arcsec].

    Returns
    -------
    list of dict
        ``name``, ``order``, ``harmonic``, ``amplitude_arcsec`` (0 where the spectrum has
        no line at that order), by rising order; then every other line of the spectrum at
        OTHER_LINE_REL of its largest or more (a higher harmonic, a sideband), named
        OTHER_LINE, harmonic 0.
    """
    so = np.asarray(spectrum_orders, float)
    amp = np.asarray(amplitude_arcsec, float)
    top = float(np.max(amp, initial=0.0))
    out = []
    for name, order in named.items():
        for h in range(1, HARMONICS + 1):
            o = h * float(order)
            hit = np.flatnonzero(np.isclose(so, o, rtol=1e-9, atol=1e-9))
            a = float(amp[hit[0]]) if hit.size else 0.0
            a = a if a >= CARRIED_REL * top else 0.0
            out.append({"name": name if h == 1 else f"{h} x {name}", "order": o,
                        "harmonic": h, "amplitude_arcsec": a})
    # the spectrum's other lines that count (a higher harmonic, a sideband of the mesh by
    # the pin passing): each an excitation of its own
    named_orders = [float(r["order"]) for r in out]
    for o, a in zip(so, amp):
        if a >= OTHER_LINE_REL * top > 0 and not any(
                math.isclose(o, x, rel_tol=1e-9) for x in named_orders):
            out.append({"name": OTHER_LINE, "order": float(o), "harmonic": 0,
                        "amplitude_arcsec": float(a)})
    return sorted(out, key=lambda r: r["order"])


def find_crossings(orders: list, frequency_Hz, output_per_input: float,
                   speed_range_rpm) -> list:
    """Where each order meets each mode: n_in = 60 f_i / (order |w_out / w_in|).

    Parameters
    ----------
    orders : list of dict
        :func:`te_orders`.
    frequency_Hz : array_like
        The modes (0 Hz: a rigid motion, no crossing).
    output_per_input : float
        |w_out / w_in|.
    speed_range_rpm : (float, float)
        The case's input speed range.

    Returns
    -------
    list of dict
        ``order_name``, ``order``, ``amplitude_arcsec``, ``mode`` (from 1),
        ``frequency_Hz``, ``speed_rpm``, ``warned`` (its amplitude at least
        WARN_AMPLITUDE_REL of the largest line), the ones inside the range, by speed.
    """
    top = max((o["amplitude_arcsec"] for o in orders), default=0.0)
    lo, hi = speed_range_rpm
    out = []
    for o in orders:
        for i, f in enumerate(np.asarray(frequency_Hz, float)):
            if f <= 0:
                continue
            n = 60.0 * f / (o["order"] * output_per_input)
            if lo <= n <= hi:
                out.append({"order_name": o["name"], "order": o["order"],
                            "amplitude_arcsec": o["amplitude_arcsec"], "mode": i + 1,
                            "frequency_Hz": float(f), "speed_rpm": float(n),
                            "warned": bool(top > 0 and o["amplitude_arcsec"]
                                           >= WARN_AMPLITUDE_REL * top)})
    return sorted(out, key=lambda c: c["speed_rpm"])
