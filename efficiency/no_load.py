"""Load-independent losses: churning, seals and the bearings' viscous drag.

Every drive has them, whatever its torque: they are why a reducer's efficiency falls at
part load and, growing faster than the speed, why it falls with speed at a fixed torque.
One cited law per mechanism, none counted twice:

* ``churning`` (``lubricant.lubrication = "oil_bath"``): the no-load loss of each gear
  stage in the bath, the law the sine paper takes for its K-H-V stage (Lu & Xu 2024,
  Eq. 42, :func:`toothfem.efficiency.lubricant.churning_lu_xu_2024`), with a0 the stage's
  centre distance and n its pinion's speed relative to its carrier: the K-H-V pair (a0 the
  eccentricity, n the crank speed) and, in a 2K-V drive, the spur first stage (a0 = m (z1 +
  z2)/2, n the sun's speed relative to the carrier). The law stands for the agitation of
  everything in the bath, the bearings' viscous drag included (Palmgren's "oil bath" f0
  would count them twice).
* ``bearing_drag`` (grease, oil mist, oil jet: no bath): Palmgren's viscous friction
  moment of every bearing of the reducer's set (:mod:`.bearing_set`,
  :func:`.palmgren.palmgren_no_load_moment`), f0 by bearing type and lubrication
  (:data:`.palmgren.PALMGREN_F0`); a cycloid or RV reducer counts each bearing's in that bearing's own
  row instead (``bearings=False``). A grease fill is pushed aside by the
  parts within minutes (channelling: Lugt, *Grease Lubrication in Rolling Bearings*, 2013):
  its drag is that of the bearings' grease column.
* ``seals``: radial lip seals on the input and the output shaft, ISO/TR 14179-1:2001
  (:func:`seal_loss`), at the shaft diameters of :mod:`.envelope`. The sine paper's P0
  includes its rig's seals, so the sine prototype case declares its seal diameters 0.
* ``drag``: a declared drag torque on the input shaft (``friction.drag_torque_Nmm``, e.g.
  bearing preload; 0 by default).
* ``windage``: a declared drag on the input shaft that grows with the square of the speed
  (``friction.windage_torque_Nmm``, its value at :data:`WINDAGE_REFERENCE_RPM`): the
  aerodynamic (turbulent) drag of parts spinning in air and oil mist, whose torque goes as
  rho omega^2 r^5 (P. H. Dawson, "Windage loss in larger high-speed gears", Proc. IMechE
  198A (1984) 51-59: power as n^2.9 near n^3); 0 by default, as the reducers here turn
  slowly in an oil bath (churning covers the bath).
* ``viscous_drag``: a declared drag on the input shaft that grows in proportion to the speed
  and the oil's viscosity (``friction.viscous_drag_Nmm``, its value at
  :data:`WINDAGE_REFERENCE_RPM` and the lubricant's reference viscosity): an oil film of
  fixed gap sheared between a shaft and a sleeve, a bushing or a close-running part
  (N. Petroff, "Friction in machines and the effect of the lubricant", Inzh. Zh. 1883;
  Hamrock, Schmid & Jacobson, *Fundamentals of Fluid Film Lubrication*, 2004, Eq. 8.52:
  T = 2 pi eta r^3 L omega / c, laminar and concentric, so T ~ eta omega). Between the
  constant ``drag`` and the speed-squared ``windage``; 0 by default.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .envelope import Envelope, envelope
from .lubricant import churning_lu_xu_2024
from .bearing_friction import bearing_losses
from .palmgren import palmgren_f0, palmgren_no_load_moment
from ..fem.drives.assembly import PathFriction
from ..units import MM_PER_M, RPM_PER_RAD_S, rpm_to_rad_s

#: ISO/TR 14179-1:2001 seal loss P = SEAL_LOSS_W * D^2 n [W] for D [mm], n [rpm]: the
#: friction of a radial lip seal on a shaft of diameter D (torque 7.34e-5 D^2 N m).
#: Provenance (issue 13 worked checks, docs/efficiency.md): the standard's text and a worked
#: example of it were not obtainable; the same coefficient, units (W, mm, rpm) and form
#: appear in an independent public gearbox-loss script that attributes them to ISO/TR
#: 14179-2, and the torque it gives (0.18 N m on a 50 mm shaft) is of the order of lip-seal
#: makers' friction curves (SKF radial shaft seals, "Friction"). Kept, not confirmed.
SEAL_LOSS_W = 7.69e-6
#: The input speed at which ``friction.windage_torque_Nmm`` is stated [rpm] (a round
#: figure inside every shipped case's speed range).
WINDAGE_REFERENCE_RPM = 1000.0
WINDAGE_REFERENCE_RAD_S = rpm_to_rad_s(WINDAGE_REFERENCE_RPM)
#: Main bearing type of an SI record without [bearings] (toothfem.case.Bearings default).
DEFAULT_MAIN_TYPE = "angular_ball"


def seal_loss(diameter_m, speed_rad_s):
    """Friction loss of a radial lip seal [W], ISO/TR 14179-1:2001:
    P = 7.69e-6 D^2 n, D [mm] the shaft diameter, n [rpm].

    Parameters
    ----------
    diameter_m : float
        Shaft diameter under the seal [m] (0: no seal).
    speed_rad_s : array_like
        Shaft speed relative to the seal [rad/s].

    Returns
    -------
    numpy.ndarray
        The loss [W].
    """
    d_mm = diameter_m * MM_PER_M
    return SEAL_LOSS_W * d_mm ** 2 * np.abs(np.asarray(speed_rad_s, float)) * RPM_PER_RAD_S


@dataclass(frozen=True, kw_only=True)
class NoLoadPoints:
    """What a load-independent loss is computed from, at M operating points: the gear
    stages' (centre distance a0 [m], (M,) pinion speed relative to its carrier [rad/s]),
    the input's and the output's speeds (M,) [rad/s], the oil's viscosity factor
    eta(T)/eta(T_ref) (M,), whether the bearings' drag is counted here (``bearings``), and
    the seals' and bearings' sizes (:class:`~toothfem.efficiency.envelope.Envelope`)."""
    stages: tuple
    input_rad_s: np.ndarray
    output_rad_s: np.ndarray
    viscosity_factor: np.ndarray
    bearings: bool
    envelope: Envelope


@dataclass(frozen=True)
class NoLoadLoss:
    """A load-independent loss (module docstring): its ``name`` (a key of
    :data:`toothfem.efficiency.losses.LOSSES`, which holds its law and source), its power
    law ``power(si, drive, points) -> (M,) [W]`` and ``applies(si, points) -> bool``,
    whether a case has it (None: every case). A new one is one more of these in
    :data:`NO_LOAD`."""
    name: str
    power: Callable[..., np.ndarray]
    applies: Callable[..., bool] | None = None


def _churning_applies(si, points) -> bool:
    lub = si.lubricant
    return lub.lubrication == "oil_bath" and lub.churning != "none"


def _churning(si, drive, points):
    """Each gear stage in the oil bath (Lu & Xu 2024, Eq. 42), times churning_scale."""
    lub = si.lubricant
    nu = lub.kinematic_viscosity_m2_s * np.asarray(points.viscosity_factor, float)
    return lub.churning_scale * sum(
        churning_lu_xu_2024(a0, np.abs(n) * RPM_PER_RAD_S, nu) for a0, n in points.stages)


def _bearing_drag_applies(si, points) -> bool:
    return si.lubricant.lubrication != "oil_bath" and points.bearings


def _bearing_drag(si, drive, points):
    """Every bearing of the set at its speed, no load term (no bath to churn)."""
    return sum(bearing_losses(si, drive, {}, points.input_rad_s,
                              points.viscosity_factor).values())


def _seals(si, drive, points):
    """The input's and the output's lip seals (ISO/TR 14179-1)."""
    env = points.envelope
    return (seal_loss(env.input_seal_diameter_m, points.input_rad_s)
            + seal_loss(env.output_seal_diameter_m, points.output_rad_s))


def _drag(si, drive, points):
    """A declared drag torque on the input."""
    return si.friction.drag_torque_Nm * np.abs(points.input_rad_s)


def _windage_applies(si, points) -> bool:
    return bool(si.friction.windage_torque_Nm)


def _windage(si, drive, points):
    """A declared drag on the input growing with the square of its speed."""
    w = np.abs(points.input_rad_s)
    return si.friction.windage_torque_Nm * (w / WINDAGE_REFERENCE_RAD_S) ** 2 * w


def _viscous_applies(si, points) -> bool:
    return bool(si.friction.viscous_drag_Nm)


def _viscous(si, drive, points):
    """A declared drag on the input growing with its speed and the oil's viscosity."""
    w = np.abs(points.input_rad_s)
    return (si.friction.viscous_drag_Nm * (w / WINDAGE_REFERENCE_RAD_S)
            * points.viscosity_factor * w)


#: The load-independent losses, in the order the summaries list them.
NO_LOAD: tuple[NoLoadLoss, ...] = (
    NoLoadLoss("churning", _churning, _churning_applies),
    NoLoadLoss("bearing_drag", _bearing_drag, _bearing_drag_applies),
    NoLoadLoss("seals", _seals),
    NoLoadLoss("drag", _drag),
    NoLoadLoss("windage", _windage, _windage_applies),
    NoLoadLoss("viscous_drag", _viscous, _viscous_applies),
)


def no_load_losses(si, drive, *, stages, input_rad_s, output_rad_s, viscosity_factor,
                   bearings=True) -> dict:
    """The load-independent losses of a drive at M operating points [W]: each of
    :data:`NO_LOAD` the case has (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    stages : sequence of (float, numpy.ndarray)
        The gear stages' (centre distance a0 [m], (M,) pinion speed relative to the
        carrier [rad/s]) for the churning law.
    input_rad_s, output_rad_s : numpy.ndarray
        (M,) speeds [rad/s] of the input shaft and of the output (the seals'; each
        bearing's own speed is its record's, :mod:`.bearing_set`).
    viscosity_factor : numpy.ndarray
        (M,) eta(T)/eta(T_ref) of the oil.
    bearings : bool
        Whether ``bearing_drag`` is counted here (False: the caller counts every bearing's
        viscous moment with its load, :mod:`.bearing_friction`).

    Returns
    -------
    dict
        ``churning`` (oil bath) or ``bearing_drag`` (otherwise), ``seals``, ``drag``, and
        ``windage`` and ``viscous_drag`` where declared: (M,) arrays.
    """
    points = NoLoadPoints(stages=tuple(stages), input_rad_s=input_rad_s,
                          output_rad_s=output_rad_s, viscosity_factor=viscosity_factor,
                          bearings=bearings, envelope=envelope(si, drive))
    return {x.name: x.power(si, drive, points) for x in NO_LOAD
            if x.applies is None or x.applies(si, points)}


#: An output speed of a slow twist test [rad/s] (a few degrees per minute): Palmgren's
#: moment is then on its low-speed branch and the seal's torque does not depend on it.
CREEP_SPEED_RAD_S = 1e-3


def output_friction_torque(si, drive) -> float:
    """The load-independent friction torque the output meets when it is turned slowly
    against the housing, input held (the catalogue's twist test): its lip seal (ISO/TR
    14179-1, a torque independent of the speed) and its main bearings' no-load moment on
    Palmgren's low-speed branch, 160e-7 f0 d_m^3 N mm.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    float
        [N m].
    """
    env = envelope(si, drive)
    w = CREEP_SPEED_RAD_S
    main_type = DEFAULT_MAIN_TYPE if si.bearings is None else si.bearings.main_type
    main = env.main_count * palmgren_no_load_moment(
        palmgren_f0(main_type, si.lubricant.lubrication), si.lubricant.kinematic_viscosity_m2_s,
        w, env.main_pitch_diameter_m)
    return float(seal_loss(env.output_seal_diameter_m, w) / w + main)


def path_friction(si, drive) -> PathFriction:
    """The case's friction in the quasi-static path: the pin contacts, output pins and
    grooves slide at creep speed with no film, so with their boundary coefficients
    (``friction.boundary_coefficient`` for the pin contacts, ``pin_groove_coefficient``,
    ``output_pin_coefficient``); the bearings with ``bearing_coefficient``; the output's
    seal and main bearings (:func:`output_friction_torque`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    toothfem.fem.drives.assembly.PathFriction
    """
    f = si.friction
    return PathFriction(pin_disc=f.boundary_coefficient, pin_groove=f.pin_groove_coefficient,
                        bearing=f.bearing_coefficient, output_pin=f.output_pin_coefficient,
                        output_torque_Nm=output_friction_torque(si, drive))
