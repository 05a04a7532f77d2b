"""The RV paper's split/virtual power method for the efficiency of a 2K-V (RV) reducer.

Source: C. Wang, "A calculation method of transmission efficiency for RV reducer",
Eqs. 8-15, as printed, so that :func:`rv_split_power` reproduces the paper's RV-40E example
from its inputs. ``efficiency.evaluate`` uses it for ``method="rv_split_power"`` through
:func:`split_power_losses`. Derivations,
checks and the numbers on RV-40E: ``docs/derivations.md``, section 5, which also shows why
the method is not a consistent power balance; the general virtual-power flow of Chen &
Angeles (J. Mech. Des. 129 (2007) 107-113) it is compared with is a test oracle,
``tests/oracles/power_flow.py``.

Conventions (those of :mod:`toothfem.geometry.train`): angular velocities about the
reducer axis, counter-clockwise positive, housing frame; powers in W.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import CaseError, ToothfemError, check_range
from ..geometry.train import rv_speeds
from .drive_losses import DriveLosses

__all__ = ["RVSplitPower", "rv_split_power", "split_power_losses"]


def _teeth(name, z):
    if isinstance(z, bool) or not isinstance(z, (int, np.integer, float)) or int(z) != z:
        raise ToothfemError(f"{name} = {z!r} must be an integer tooth number")
    return int(check_range(name, z, 1, None))


def _efficiency(name, eta):
    return float(check_range(name, eta, 0.0, 1.0, lo_open=True,
                             why="a mesh efficiency is a fraction of the power passed"))


def _power(name, p):
    return float(check_range(name, p, 0.0, None, lo_open=True))


def _pins_exceed_disc(z_disc, z_pins, disc_name="z_disc", pins_name="z_pins"):
    z_disc, z_pins = _teeth(disc_name, z_disc), _teeth(pins_name, z_pins)
    check_range(pins_name, z_pins, z_disc + 1, None,
                 why=f"the internal member must have more teeth than {disc_name} = {z_disc}")
    return z_disc, z_pins


@dataclass(frozen=True)
class RVSplitPower:
    """Result of :func:`rv_split_power` (powers in W, ratios dimensionless)."""

    input_power_W: float
    ratio: float                #: i16 = w1/w6, from the Willis system (121 for RV-40E)
    crank_disc_ratio: float     #: w3/w4, Eq. 4 (-39 for RV-40E)
    beta: float                 #: split power ratio, Eq. 8: P/(P - V) = -w2/w4
    alpha: float                #: virtual power ratio, Eq. 10/12: (w4 - w3)/w4
    split_power_V_W: float      #: V, Eq. 9
    virtual_power_U_W: float    #: U, Eq. 12 (revised sign) or Eq. 11
    loss_L1_W: float            #: Eq. 13: P (1 - eta1)
    loss_L2_W: float            #: Eq. 14: (P + U - L1)(1 - eta2)
    output_power_W: float       #: P - L1 - L2
    efficiency: float           #: Eq. 15 (as a fraction, not %)


def rv_split_power(z_sun, z_planet, z_disc, z_pins, input_power_W, mesh_efficiency_1,
                   mesh_efficiency_2, *, u_equation: int = 12) -> RVSplitPower:
    """The RV paper's efficiency of a 2K-V (RV) reducer, Eqs. 8-15, as printed.

    The ratios come from the Willis system (:func:`~toothfem.geometry.train.rv_speeds`):
    ``beta = -w2/w4`` (Eq. 8), ``V = P (1 - 1/beta)`` (= Eq. 9 ``(2 z4 - z5)/z4 P``),
    ``alpha = (w4 - w3)/w4`` (= ``z5/(z5 - z4)``), and

    * ``u_equation=12`` (default, the paper's worked example): ``(P + U)/(P - V) = alpha``,
      ``U = (z5 - z4)/z4 P > 0`` (Eq. 12, the "revised" Fig. 7 direction);
    * ``u_equation=11``: ``(P - U)/(P - V) = alpha``, ``U = (z4 - z5)/z4 P < 0`` (Eqs. 10-11).

    then ``L1 = P (1 - eta1)`` (Eq. 13), ``L2 = (P + U - L1)(1 - eta2)`` (Eq. 14),
    ``eta = (P - L1 - L2)/P`` (Eq. 15). RV-40E (12/36/39/40, 2270 W, 0.94): V = 2211.79 W,
    U = 58.2051 W, L1 = 136.2 W, L2 = 131.52 W, eta = 0.88206. The method is NOT a
    consistent power balance (the docs show why); the general virtual-power flow
    (``rv_power_flow`` in ``tests/oracles/power_flow.py``) is.

    Parameters
    ----------
    z_sun, z_planet, z_disc, z_pins : int
        Tooth numbers z1, z2, z4, z5 (z_pins > z_disc).
    input_power_W : float
        P [W], > 0.
    mesh_efficiency_1 : float
        Sun-planet pair (eta1), in (0, 1].
    mesh_efficiency_2 : float
        Cycloid-pin pair (eta2), in (0, 1].
    u_equation : {11, 12}
        The paper's equation for U.

    Returns
    -------
    RVSplitPower
        Ratios, split and virtual power, losses [W] and the efficiency.

    Raises
    ------
    ToothfemError
        Naming the first argument outside its range.
    """
    z_sun, z_planet = _teeth("z_sun", z_sun), _teeth("z_planet", z_planet)
    z_disc, z_pins = _pins_exceed_disc(z_disc, z_pins)
    p = _power("input_power_W", input_power_W)
    eta1 = _efficiency("mesh_efficiency_1", mesh_efficiency_1)
    eta2 = _efficiency("mesh_efficiency_2", mesh_efficiency_2)
    if u_equation not in (11, 12):
        raise ToothfemError(f"u_equation = {u_equation!r} must be 11 or 12")

    w = {n: float(v) for n, v in rv_speeds(z_sun, z_planet, z_disc, z_pins).items()}
    w2, w3, w4 = w["planet"], w["planet"], w["disc"]       # Eq. 3: w2 = w3, w4 = w6 = w7
    beta = -w2 / w4                                          # Eq. 8
    v = p * (1.0 - 1.0 / beta)                               # Eq. 8 solved for V (Eq. 9)
    alpha = (w4 - w3) / w4                                   # Eq. 10 / 12
    u = alpha * (p - v) - p if u_equation == 12 else p - alpha * (p - v)
    l1 = p * (1.0 - eta1)                                    # Eq. 13
    l2 = (p + u - l1) * (1.0 - eta2)                         # Eq. 14
    out = p - l1 - l2
    return RVSplitPower(input_power_W=p, ratio=w["sun"] / w["carrier"],
                        crank_disc_ratio=w3 / w4, beta=beta, alpha=alpha,
                        split_power_V_W=v, virtual_power_U_W=u, loss_L1_W=l1,
                        loss_L2_W=l2, output_power_W=out, efficiency=out / p)


def split_power_losses(si, input_speed_rad_s, output_torque_Nm) -> DriveLosses:
    """The RV paper's method at each operating point of a case with the declared mesh
    efficiency (``[rv] mesh_efficiency`` for both meshes).

    The method is linear in the input power: the losses per watt of input, scaled.

    Parameters
    ----------
    si : toothfem.si.CaseSI
        An RV case.
    input_speed_rad_s : numpy.ndarray, shape (M,)
        Input speed [rad/s].
    output_torque_Nm : numpy.ndarray, shape (M,)
        Output torque [N m].

    Returns
    -------
    DriveLosses
        Output power and the two mesh losses [W] at the M points.

    Raises
    ------
    CaseError
        If the case is not an RV drive.
    """
    if si.rv is None:
        raise CaseError(f"method = 'rv_split_power' needs drive = 'rv', not {si.drive!r}")
    z = si.rv
    eta1 = z.mesh_efficiency
    r = rv_split_power(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count, 1.0, eta1, eta1)
    p_out = output_torque_Nm * np.abs(input_speed_rad_s / r.ratio)
    p_in = p_out / r.efficiency
    return DriveLosses(
        output_power_W=p_out,
        losses_W={"sun_planet_mesh": p_in * r.loss_L1_W, "cycloid_mesh": p_in * r.loss_L2_W},
        notes=("RV paper Eqs. 8-15 with the declared mesh efficiency",),
        mesh_efficiency={"sun_planet": np.full_like(p_out, eta1),
                         "cycloid": np.full_like(p_out, eta1)})
