"""Heat: the oil temperature at which the losses leave through the housing, and the warm-up.

Heat balance of a lumped reducer (the oil, the parts and the housing wall at one
temperature T, the practice of ISO/TR 14179-1/-2): the losses P(T) (which depend on T
through the oil's viscosity) leave by natural convection and radiation from the housing,

    P(T) = h(T) A (T - T_a),    h = h_conv + h_rad

* h_conv: natural convection from a horizontal cylinder in air, laminar, Holman's
  simplified correlation h = 1.32 (dT/d)^(1/4) W/(m^2 K) (J.P. Holman, *Heat Transfer*,
  10th ed. 2010, Table 7-2), d the housing diameter;
* h_rad = eps sigma (T^2 + T_a^2)(T + T_a) (kelvin), the exact linearisation of
  eps sigma (T^4 - T_a^4); eps = 0.9 for a painted housing (Incropera & DeWitt,
  *Fundamentals of Heat and Mass Transfer*, Table A.11: paints 0.9-0.98).

At T - T_a = 40 K on a 0.16 m housing: h_conv = 5.2, h_rad = 6.9 (eps 0.9, 60/20 C):
12 W/(m^2 K), within the 10-20 W/(m^2 K) of gear housings in still air (ISO/TR 14179-2).
Mounted by one flange on a machine (``thermal.mounting = "flange"``), the flange's end
face sheds heat by conduction instead of convection: through the bolted joint (contact
conductance h_c over the face, ASSUMPTION 1000 W/(m^2 K): bolted steel joints 400-1700,
F. P. Incropera & D. P. DeWitt, *Fundamentals of Heat and Mass Transfer*, Table 3.1) in
series with the spreading into the machine, taken as a semi-infinite body at the ambient
temperature (the shape factor of an isothermal disc of diameter D on a semi-infinite
medium, S = 2 D, Incropera Table 4.1: R = 1/(2 k D), k the machine's conductivity):

    P(T) = h(T) (A - A_f) (T - T_a) + (T - T_a) / (1/(h_c A_f) + 1/(2 k D))

The case may declare A, h and the heat capacity (``[thermal]``); the defaults (the housing
of :mod:`.envelope`, half of its envelope in steel) are ASSUMPTIONS. The equilibrium is the
fixed point T = T_a + P(T)/(h(T) A), iterated to 0.1 K (bracketed, so it cannot wander);
the warm-up is C dT/dt = P(T) - h(T) A (T - T_a) from the ambient.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .. import limits
from ..errors import CaseError, ToothfemError, check_range
from ..fem.drives import drive_for
from .envelope import envelope
from .evaluation import Efficiency, evaluate
from .lubricant import temperature_range
from .mesh_table import LoadsMemo
from ..si import si_of

#: Stefan-Boltzmann constant [W/(m^2 K^4)] (CODATA 2018, exact in SI).
STEFAN_BOLTZMANN = 5.670374419e-8
#: Holman's laminar natural convection from a horizontal cylinder in air,
#: h = HOLMAN_CYLINDER (dT/d)^(1/4) [W/(m^2 K)], dT [K], d [m] (Table 7-2).
HOLMAN_CYLINDER = 1.32
#: Specific heat of carbon and low-alloy steels [J/(kg K)] at 300 K: 434-477 (Incropera &
#: DeWitt, Table A.1); 450 taken.
STEEL_SPECIFIC_HEAT = 450.0
#: Share of the housing envelope (a cylinder of its radius and length) that is steel, for
#: the default heat capacity. ASSUMPTION: half (an RV-40E, 190 mm x about 100 mm, weighs
#: about 9 kg, 0.4 of its envelope in steel).
HOUSING_STEEL_SHARE = 0.5
#: Conduction shape factor of an isothermal disc on a semi-infinite medium, S = 2 D
#: (Incropera & DeWitt, Table 4.1).
SPREADING_SHAPE_FACTOR = 2.0
#: Tolerance of the equilibrium temperature [K] and the iteration cap.
TEMPERATURE_TOL_K = 0.1
MAX_ITERATIONS = 100
KELVIN = 273.15


@dataclass(frozen=True, kw_only=True)
class Housing:
    """The surface and heat capacity that take the losses (SI, temperatures in deg C)."""
    area_m2: float
    diameter_m: float
    ambient_C: float
    emissivity: float
    heat_transfer_W_m2K: float | None   # declared; None: convection + radiation
    heat_capacity_J_K: float
    flange_area_m2: float = 0.0         # the end face bolted to the machine (0: free)
    flange_conductance_W_K: float = 0.0  # joint and spreading in series


def housing(si, drive=None) -> Housing:
    """The housing of a case: ``[thermal]`` or the envelope's cylinder (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive, optional

    Returns
    -------
    Housing
    """
    th = si.thermal
    env = envelope(si, drive or drive_for(si))
    r, length = env.housing_radius_m, env.housing_length_m
    area = th.housing_area_m2 or 2 * math.pi * r * length + 2 * math.pi * r ** 2
    capacity = th.heat_capacity_J_K or (HOUSING_STEEL_SHARE * math.pi * r ** 2 * length
                                        * si.material.density_kg_m3 * STEEL_SPECIFIC_HEAT)
    face, conductance = 0.0, 0.0
    if th.mounting == "flange":
        face = min(math.pi * r ** 2, area)
        conductance = 1.0 / (1.0 / (th.contact_conductance_W_m2K * face)
                             + 1.0 / (SPREADING_SHAPE_FACTOR * 2 * r
                                      * th.mount_conductivity_W_mK))
    return Housing(area_m2=area, diameter_m=2 * r, ambient_C=th.ambient_C,
                   emissivity=th.emissivity, heat_transfer_W_m2K=th.heat_transfer_W_m2K,
                   heat_capacity_J_K=capacity, flange_area_m2=face,
                   flange_conductance_W_K=conductance)


def convection_coefficient(delta_K, diameter_m):
    """Holman's laminar natural convection of a horizontal cylinder in air [W/(m^2 K)].

    Parameters
    ----------
    delta_K : array_like
        Surface minus ambient temperature [K] (floored at 0).
    diameter_m : float
        Cylinder diameter [m].

    Returns
    -------
    numpy.ndarray
        h = HOLMAN_CYLINDER (dT/d)^(1/4) [W/(m^2 K)], shape of ``delta_K``.
    """
    return HOLMAN_CYLINDER * (np.maximum(np.asarray(delta_K, float), 0.0) / diameter_m) ** 0.25


def radiation_coefficient(surface_C, ambient_C, emissivity):
    """eps sigma (T^2 + T_a^2)(T + T_a) [W/(m^2 K)], temperatures in deg C.

    Parameters
    ----------
    surface_C : array_like
        Surface temperature [deg C].
    ambient_C : float
        Ambient temperature [deg C].
    emissivity : float
        eps [-].

    Returns
    -------
    numpy.ndarray
        The linearised radiation coefficient [W/(m^2 K)], shape of ``surface_C``.
    """
    t = np.asarray(surface_C, float) + KELVIN
    ta = ambient_C + KELVIN
    return emissivity * STEFAN_BOLTZMANN * (t ** 2 + ta ** 2) * (t + ta)


def heat_transfer_coefficient(h: Housing, temperature_C):
    """h(T) of the housing [W/(m^2 K)]: the declared one, else convection + radiation.

    Parameters
    ----------
    h : Housing
        The housing.
    temperature_C : array_like
        Surface (oil) temperature [deg C].

    Returns
    -------
    numpy.ndarray
        h [W/(m^2 K)], shape of ``temperature_C``.
    """
    t = np.asarray(temperature_C, float)
    if h.heat_transfer_W_m2K is not None:
        return np.full_like(t, h.heat_transfer_W_m2K)
    return (convection_coefficient(t - h.ambient_C, h.diameter_m)
            + radiation_coefficient(t, h.ambient_C, h.emissivity))


def heat_flow(h: Housing, temperature_C):
    """Heat the housing sheds at oil temperature T [W]: h(T) A (T - T_a).

    Parameters
    ----------
    h : Housing
        The housing.
    temperature_C : array_like
        Oil temperature [deg C].

    Returns
    -------
    numpy.ndarray
        Heat flow [W], shape of ``temperature_C``.
    """
    t = np.asarray(temperature_C, float)
    return shed_per_kelvin(h, t) * (t - h.ambient_C)


def shed_per_kelvin(h: Housing, temperature_C):
    """The housing's heat loss per kelvin above the ambient [W/K]: convection and
    radiation from the free surface, conduction through a bolted flange.

    Parameters
    ----------
    h : Housing
        The housing.
    temperature_C : array_like
        Oil temperature [deg C].

    Returns
    -------
    numpy.ndarray
        [W/K], shape of ``temperature_C``.
    """
    t = np.asarray(temperature_C, float)
    return (heat_transfer_coefficient(h, t) * (h.area_m2 - h.flange_area_m2)
            + h.flange_conductance_W_K)


def _check_ambient(si, h: Housing):
    lo, hi = temperature_range(si.lubricant)
    if not lo <= h.ambient_C < hi:
        raise CaseError(f"thermal.ambient_C = {h.ambient_C!r} is outside the valid range "
                        f"[{lo:g}, {hi:g}) of the lubricant (pour point to "
                        "max_temperature_C)")


@dataclass(frozen=True, kw_only=True)
class HeatBalance:
    """Equilibrium oil temperature at M operating points, and the efficiency there."""
    temperature_C: np.ndarray
    heat_transfer_W_m2K: np.ndarray
    housing: Housing
    iterations: int
    evaluation: Efficiency          # the efficiency at T
    warnings: tuple = ()            # toothfem.limits.Exceeded: the case's temperature
                                    # limit and the evaluation's at T

    @property
    def efficiency(self) -> np.ndarray:
        return self.evaluation.efficiency

    @property
    def losses_W(self) -> np.ndarray:
        return self.evaluation.input_power_W - self.evaluation.output_power_W


def _total_loss(si, n, t, temp, **kw):
    e = evaluate(si, n, t, temp, **kw)
    return e.input_power_W - e.output_power_W, e


def heat_balance(case, speed_rpm, torque_Nm, *, tol_K=TEMPERATURE_TOL_K, **kw) -> HeatBalance:
    """The oil temperature at which the losses equal the heat the housing sheds.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    speed_rpm, torque_Nm : array_like
        Input speed [rpm] and output torque [N m]; broadcast together.
    tol_K : float
        Convergence of the fixed point [K].
    **kw
        As :func:`toothfem.efficiency.evaluate` (``loads``, ``positions``, ``memo``: the
        balance's evaluations share one, the caller's where given).

    Returns
    -------
    HeatBalance

    Raises
    ------
    CaseError
        An ambient outside the oil's range, or losses the housing cannot shed below the
        oil's ``max_temperature_C``.
    """
    si = si_of(case)
    kw = {"memo": LoadsMemo(), **kw}          # every evaluation at one drive's loads
    h = housing(si)
    _check_ambient(si, h)
    n, t = (np.ravel(a).astype(float) for a in np.broadcast_arrays(
        np.asarray(speed_rpm, float), np.asarray(torque_Nm, float)))
    t_max = temperature_range(si.lubricant)[1]
    hot, _ = _total_loss(si, n, t, np.full_like(n, t_max), **kw)
    over = hot > heat_flow(h, t_max)
    if np.any(over):
        raise CaseError(f"no heat balance below lubricant.max_temperature_C = {t_max:g} C: "
                        f"{float(hot[over][0]):.4g} W of losses against "
                        f"{float(heat_flow(h, t_max)):.4g} W shed by the housing "
                        f"(A = {h.area_m2:.3g} m^2); give [thermal] a larger "
                        "housing_area_m2 or heat_transfer_W_m2K, or mounting = 'flange'")
    lo, hi = np.full_like(n, h.ambient_C), np.full_like(n, t_max)
    temp = lo.copy()
    for it in range(1, MAX_ITERATIONS + 1):
        loss, _ = _total_loss(si, n, t, temp, **kw)
        shed_per_K = shed_per_kelvin(h, temp)
        step = h.ambient_C + loss / shed_per_K            # the fixed point's next value
        above = step > temp                               # g(T) > 0: the root lies above
        lo = np.where(above, temp, lo)
        hi = np.where(above, hi, temp)
        new = np.where((step > lo) & (step < hi), step, 0.5 * (lo + hi))
        done = np.abs(new - temp) < tol_K
        temp = new
        if np.all(done):
            _, ev = _total_loss(si, n, t, temp, **kw)
            return HeatBalance(temperature_C=temp,
                               heat_transfer_W_m2K=heat_transfer_coefficient(h, temp),
                               housing=h, iterations=it, evaluation=ev,
                               warnings=tuple(limits.case_temperature(si, drive_for(si),
                                                                      temp)) + ev.warnings)
    raise ToothfemError(f"the heat balance did not converge to {tol_K:g} K in "
                        f"{MAX_ITERATIONS} iterations")


@dataclass(frozen=True, kw_only=True)
class WarmUp:
    """Oil temperature and efficiency over time from the ambient (one operating point)."""
    time_s: np.ndarray
    temperature_C: np.ndarray
    efficiency: np.ndarray
    time_constant_s: float          # C / (h A) at the equilibrium
    equilibrium: HeatBalance


def warm_up(case, speed_rpm, torque_Nm, duration_s, *, samples=41, **kw) -> WarmUp:
    """The warm-up C dT/dt = P(T) - h(T) A (T - T_a) from T = T_a at one operating point.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    speed_rpm, torque_Nm : float
        Input speed [rpm] and output torque [N m].
    duration_s : float
        Time to follow [s], > 0.
    samples : int
        Times reported, evenly over the duration.
    **kw
        As :func:`toothfem.efficiency.evaluate`.

    Returns
    -------
    WarmUp

    Raises
    ------
    CaseError
        If the duration is not positive.
    """
    check_range("duration_s", duration_s, 0.0, None, lo_open=True, error=CaseError)
    si = si_of(case)
    kw = {"memo": LoadsMemo(), **kw}          # every evaluation at one drive's loads
    eq = heat_balance(si, speed_rpm, torque_Nm, **kw)
    h = eq.housing
    n, t = float(np.ravel(speed_rpm)[0]), float(np.ravel(torque_Nm)[0])

    def rate(_, temp):
        temp = np.minimum(temp, eq.temperature_C)     # the equilibrium bounds the rise
        loss, _ = _total_loss(si, n, t, temp, **kw)
        return (loss - heat_flow(h, temp)) / h.heat_capacity_J_K

    tau = h.heat_capacity_J_K / float(shed_per_kelvin(h, eq.temperature_C)[0])
    times = np.linspace(0.0, duration_s, samples)
    sol = solve_ivp(rate, (0.0, duration_s), [h.ambient_C], t_eval=times, rtol=1e-4,
                    atol=0.01, max_step=tau / 10)
    temp = sol.y[0]
    eta = evaluate(si, n, t, temp, **kw).efficiency
    return WarmUp(time_s=times, temperature_C=temp, efficiency=eta, time_constant_s=tau,
                  equilibrium=eq)
