"""The dynamic transmission error and output torque ripple of a case against input speed
(``toothfem modes --response``; the mechanics: :mod:`toothfem.fem.system.response`,
docs/dynamics.md "Dynamic response at speed").

The static path u_s over the full period (every coordinate of the system model at each
crank angle under the output torque, input held at that angle: the TE and every body's
deflection) is filled from sampled pitches as the TE of ``toothfem stiffness`` is
(:func:`toothfem.fem.datasheet.transmission.fourier_fill`); its harmonics, orders per
output revolution, excite the linearised system at each input speed (harmonic balance with
the mean tangent and modal damping). The input is driven at constant speed (held in the
turning frame: a stiff speed loop), the load is an inertia under the steady torque; the
output torque ripple is what the load receives beyond that torque, J_load x_out''.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .efficiency import rated_output_torque
from .errors import CaseError, check_range
from .fem.datasheet.transmission import fourier_fill, sampled_pitches
from .fem.drives import drive_for
from .fem.system import inertia as fi, modes as fm
from .fem.system.response import ModalSystem, harmonics_of, path_of
from .units import ARCSEC

#: The modal damping ratio by default, and its source: the damping ratio of gear meshes
#: measured between 0.03 and 0.17 (R. Kasuba & J.W. Evans, "An extended model for
#: determining dynamic loads in spur gearing", ASME J. Mech. Des. 103 (1981) 398-409, as
#: Oezgueven & Houser 1988 review it); ASSUMPTION: the cycloid's rolling contacts and
#: needle bearings alike, at the low end with 0.05 (a resonance's amplification 1/(2 zeta)
#: = 10).
DAMPING_RATIO = 0.05
DAMPING_SOURCE = ("ASSUMPTION: 0.05, the low end of the 0.03-0.17 measured on gear meshes "
                  "(Kasuba & Evans, ASME J. Mech. Des. 103 (1981) 398; reviewed by "
                  "Oezgueven & Houser, J. Sound Vib. 121 (1988) 383)")
#: Speeds of the sweep by default, log-spaced from SPEED_FROM of the top speed to the top.
SPEEDS, SPEED_FROM = 50, 1e-3
#: The full-period sampling of the static path (as ``toothfem stiffness``'s TE).
SAMPLES, PER_PITCH = 6, 12


@dataclass(frozen=True, kw_only=True)
class DynamicResponse:
    """Dynamic TE and output torque ripple against input speed (peak to peak over the full
    period), the static TE, the damping ratio with its source, and each crossing's
    response at its own speed."""
    case_name: str
    torque_Nm: float
    load_kgm2: float
    damping_ratio: float
    damping_source: str
    speeds_rpm: np.ndarray
    te_pp_arcsec: np.ndarray
    ripple_pp_Nm: np.ndarray
    static_te_pp_arcsec: float
    crossings: list                # {order_name, mode, speed_rpm, te_pp_arcsec, ripple_pp_Nm}
    method: str

    def rows(self) -> list:
        """The sweep's rows (dynamic.csv).

        Returns
        -------
        list of tuple
            (speed_rpm, te_pp_arcsec, ripple_pp_Nm).
        """
        return list(zip(self.speeds_rpm.tolist(), self.te_pp_arcsec.tolist(),
                        self.ripple_pp_Nm.tolist()))


def static_path(drive, supports, torque_Nm: float, *, samples: int = SAMPLES,
                per_pitch: int = PER_PITCH) -> tuple:
    """Every coordinate of the system model over the full period under the output torque.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    torque_Nm : float
    samples, per_pitch : int
        Sampled pitches over the full period, positions per pitch.

    Returns
    -------
    path : numpy.ndarray, shape (N, n)
        [m, rad], N = full period x per_pitch.
    span_rad : float
        The output's rotation over the full period [rad].
    """
    k = drive.full_period_pitches
    pitches = sampled_pitches(k, samples)
    rows = []
    for m in pitches:
        system: Any = drive.system_model(supports, per_pitch, pitch=m)
        last, us = None, []
        for p in range(per_pitch):
            last = system.solve(torque_Nm, p, start=last)
            us.append(last.equilibrium.u)
        rows.append(np.concatenate(us))
    n = rows[0].size // per_pitch
    full = fourier_fill(pitches, np.array(rows), k).reshape(k * per_pitch, n)
    w = drive.speeds()
    span = k * drive.period_rad * abs(w["output"] / w["crank"])
    return full, span


def response_sweep(system, lins, mass, path, span_rad: float, *, speeds_rpm, load_kgm2,
                   zeta: float) -> tuple:
    """The dynamic TE and torque ripple (peak to peak) at each speed.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    lins : list of toothfem.fem.system.modes.Linearised
        The tangents over one meshing period (input held); their mean is taken.
    mass : numpy.ndarray
    path : numpy.ndarray, shape (N, n)
    span_rad : float
    speeds_rpm : array_like
    load_kgm2, zeta : float

    Returns
    -------
    (te_pp_rad, ripple_pp_Nm) : numpy.ndarray each, shape (S,)
    """
    k = sum(lin.k for lin in lins) / len(lins)
    modal = ModalSystem(k, mass, zeta)
    u = harmonics_of(path)
    force = u @ k.T                                          # K u_s,h
    orders = np.arange(u.shape[0]) * (2 * math.pi / span_rad)
    w = system.drive.speeds()
    ratio = abs(w["output"] / w["input"])
    out = system.coords.index["out"].start
    te, ripple = [], []
    for n in np.atleast_1d(speeds_rpm):
        omega = orders * (n * 2 * math.pi / 60 * ratio)
        x = modal.response(force, omega)[:, out]
        te_t = path_of(x[:, None], path.shape[0])[:, 0]
        acc = path_of((-omega ** 2 * x)[:, None], path.shape[0])[:, 0]
        te.append(np.ptp(te_t))
        ripple.append(load_kgm2 * np.ptp(acc))
    return np.array(te), np.array(ripple)


def dynamic_response(case, *, load_kgm2: float, torque_Nm: float | None = None,
                     zeta: float = DAMPING_RATIO, speeds: int = SPEEDS, crossings=(),
                     top_rpm: float, samples: int = SAMPLES,
                     per_pitch: int = PER_PITCH) -> DynamicResponse:
    """The sweep of a case (module docstring).

    Parameters
    ----------
    case : toothfem.case.Case
    load_kgm2 : float
        The load's inertia [kg m^2].
    torque_Nm : float, optional
        Default the rated output torque.
    zeta : float
        Modal damping ratio.
    speeds : int
        Speeds of the sweep, log-spaced to ``top_rpm`` (each crossing's speed added).
    crossings : sequence of dict
        ``toothfem.dynamics.find_crossings``' (each also solved at its own speed).
    top_rpm : float
        The top input speed [rpm].
    samples, per_pitch : int
        The static path's sampling.

    Returns
    -------
    DynamicResponse
    """
    check_range("speeds", speeds, 2, 10000, error=CaseError)
    check_range("damping_ratio", zeta, 0.0, 1.0, hi_open=True, error=CaseError)
    si = case.to_si()
    t = rated_output_torque(si)[0] if torque_Nm is None else float(torque_Nm)
    drive = drive_for(si)
    supports = drive.supports(si.supports)
    system: Any = drive.system_model(supports, per_pitch)
    from .cad_parts import part_drawing
    bodies = fi.reducer_bodies(system, part_drawing(si, drive=drive).regions[0],
                               si.material.density_kg_m3,
                               output_pins=drive.path.output_mechanism,
                               first_stage=getattr(drive.path, "first_stage", None))
    mass = fi.mass_matrix(system, bodies, load_kgm2=load_kgm2, motor_kgm2=0.0)
    last, lins = None, []
    for p in range(per_pitch):
        last = system.solve(t, p, start=last)
        lins.append(fm.linearise(system, last))
    path, span = static_path(drive, supports, t, samples=samples, per_pitch=per_pitch)
    at = [float(c["speed_rpm"]) for c in crossings]
    # the sweep's speeds with each crossing's own among them (the curve through its peak)
    grid = np.unique(np.concatenate([np.geomspace(SPEED_FROM * top_rpm, top_rpm,
                                                  int(speeds)), at]))
    te, ripple = response_sweep(system, lins, mass, path, span, speeds_rpm=grid,
                                load_kgm2=load_kgm2, zeta=zeta)
    named = []
    for c, n in zip(crossings, at):
        i = int(np.argmin(np.abs(grid - n)))
        named.append({**{k: c[k] for k in ("order_name", "order", "mode", "frequency_Hz",
                                            "speed_rpm", "amplitude_arcsec")},
                      "te_pp_arcsec": float(te[i] / ARCSEC), "ripple_pp_Nm": float(ripple[i])})
    out = system.coords.index["out"].start
    return DynamicResponse(
        case_name=case.name, torque_Nm=t, load_kgm2=load_kgm2, damping_ratio=zeta,
        damping_source=DAMPING_SOURCE, speeds_rpm=grid, te_pp_arcsec=te / ARCSEC,
        ripple_pp_Nm=ripple, static_te_pp_arcsec=float(np.ptp(path[:, out]) / ARCSEC),
        crossings=named,
        method="harmonic balance of the system model linearised about its static path "
               "(the static TE through the mean tangent stiffness; modal damping), input "
               "driven at constant speed, the load an inertia")
