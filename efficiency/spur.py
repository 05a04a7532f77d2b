"""Load-dependent mesh loss of an involute spur pair (the first stage of RV-type drives).

Tooth loss factor of Ohlendorf (1958), as used by ISO/TR 14179-2:2001 (Eq. 9 there)::

    H_V = pi (u + 1) / (z1 u cos(beta_b)) * (1 - eps_a + eps_1^2 + eps_2^2)

with eps_1, eps_2 the addendum contact ratios and eps_a = eps_1 + eps_2; the mesh loss is
P_VZP = mu_mz H_V P (P the power through the mesh in the carrier frame), i.e. the mesh
efficiency eta = 1 - mu_mz H_V. Mean friction coefficient of Schlenk (1994), ISO/TR
14179-2 Eq. 10, SI units as there::

    mu_mz = 0.048 (F_bt/b / (v_sum_C rho_redC))^0.2 eta_oil^-0.05 Ra^0.25 X_L

F_bt/b [N/mm] the transverse base-circle load per face width, v_sum_C [m/s] the sum
velocity at the pitch point, rho_redC [mm] the relative radius of curvature there,
eta_oil [mPa s] the dynamic viscosity, Ra [um] the mean arithmetic roughness, X_L the
lubricant factor (1 for mineral oil). Standard addendum h_a = m (no profile shift); for
internal gears pass ``internal=True`` (z2 the ring).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import check_range
from ..units import CP_PER_PA_S, M_PER_MM, MM_PER_M, UM_PER_M


def contact_ratios(z1: int, z2: int, pressure_angle_rad: float, internal: bool = False):
    """Addendum contact ratios of a standard spur pair (h_a = m, x = 0).

    Parameters
    ----------
    z1, z2 : int
        Pinion and wheel teeth, >= 6.
    pressure_angle_rad : float
        Pressure angle [rad].
    internal : bool
        An internal wheel (ring gear).

    Returns
    -------
    tuple of (float, float)
        (eps_1, eps_2) [-].

    Raises
    ------
    ToothfemError
        If a tooth number is below 6.
    """
    check_range("z1", z1, 6, None)
    check_range("z2", z2, 6, None)
    a = pressure_angle_rad
    ra1 = (z1 + 2) / 2
    rb1 = z1 / 2 * math.cos(a)
    e1 = z1 / (2 * math.pi) * (math.tan(math.acos(rb1 / ra1)) - math.tan(a))
    if internal:
        ra2 = (z2 - 2) / 2
        rb2 = z2 / 2 * math.cos(a)
        e2 = z2 / (2 * math.pi) * (math.tan(a) - math.tan(math.acos(rb2 / ra2)))
    else:
        ra2 = (z2 + 2) / 2
        rb2 = z2 / 2 * math.cos(a)
        e2 = z2 / (2 * math.pi) * (math.tan(math.acos(rb2 / ra2)) - math.tan(a))
    return e1, e2


def loss_factor(z1: int, z2: int, pressure_angle_rad: float, internal: bool = False) -> float:
    """Ohlendorf's tooth loss factor H_V of a standard spur pair (beta = 0).

    Parameters
    ----------
    z1 : int
        Teeth of the pinion (the sun), >= 6.
    z2 : int
        Teeth of the wheel (the planet), >= 6; u = z2/z1.
    pressure_angle_rad : float
        Transverse pressure angle alpha [rad].
    internal : bool
        True for an internal mesh (u + 1 becomes u - 1).

    Returns
    -------
    float
        H_V [-].

    Raises
    ------
    ToothfemError
        As :func:`contact_ratios`.
    """
    e1, e2 = contact_ratios(z1, z2, pressure_angle_rad, internal)
    u = z2 / z1
    sign = -1.0 if internal else 1.0
    return math.pi * (u + sign) / (z1 * u) * (1 - (e1 + e2) + e1 ** 2 + e2 ** 2)


def schlenk_mu(load_per_width_N_mm, sum_velocity_m_s, rho_red_mm, eta_oil_mPa_s,
               ra_um, x_l: float = 1.0):
    """ISO/TR 14179-2 Eq. 10 mean friction coefficient (Schlenk 1994), arrays broadcast.

    Valid for lubricated steel gears at v_sum > 0; the velocity is floored at 0.1 m/s,
    below which the formula's (v)^-0.2 is not supported by its data. The units are the
    standard's.

    Parameters
    ----------
    load_per_width_N_mm : array_like
        Transverse load in the plane of action per face width, F_bt/b [N/mm]
        (floored at 1e-9).
    sum_velocity_m_s : array_like
        Sum velocity at the pitch point [m/s].
    rho_red_mm : array_like
        Reduced radius of curvature at the pitch point [mm].
    eta_oil_mPa_s : array_like
        Dynamic viscosity of the oil [mPa s].
    ra_um : float
        Arithmetic mean roughness Ra [um].
    x_l : float
        Lubricant factor X_L [-] (1 for mineral oil).

    Returns
    -------
    numpy.ndarray
        mu_mz [-], the broadcast shape.
    """
    v = np.maximum(np.asarray(sum_velocity_m_s, float), 0.1)
    w = np.maximum(np.asarray(load_per_width_N_mm, float), 1e-9)
    return 0.048 * (w / (v * rho_red_mm)) ** 0.2 * np.asarray(eta_oil_mPa_s, float) ** -0.05 \
        * ra_um ** 0.25 * x_l


def mesh_efficiency(stage, sun_torque_Nm, relative_speed_rad_s, eta_oil_Pa_s, ra_m,
                    planets: int | None = None):
    """Efficiency of the sun-planet mesh in the carrier frame, eta = 1 - mu_mz H_V.

    Parameters
    ----------
    stage : toothfem.si.SpurStageSI
        Teeth, module, pressure angle, face width and planets of the stage.
    sun_torque_Nm, relative_speed_rad_s : array_like
        Sun torque [N m] and the sun's speed relative to the carrier [rad/s].
    eta_oil_Pa_s : array_like
        Dynamic viscosity of the oil [Pa s].
    ra_m : float
        Arithmetic mean roughness Ra of the flanks [m].
    planets : int, optional
        Planets sharing the sun's torque (default: the stage's).

    Returns
    -------
    numpy.ndarray
        The mesh efficiency.
    """
    z1, z2 = stage.sun_teeth, stage.planet_teeth
    a = stage.pressure_angle_rad
    m_mm = stage.module_m * MM_PER_M                        # Schlenk's law works in mm
    n_p = planets or stage.planet_count
    r1 = z1 * m_mm / 2                                      # mm
    f_bt = np.asarray(sun_torque_Nm, float) * MM_PER_M / (r1 * math.cos(a)) / n_p     # N
    width = stage.face_width_m * MM_PER_M                   # mm
    v_t = np.abs(np.asarray(relative_speed_rad_s, float)) * r1 * M_PER_MM      # m/s
    v_sum = 2 * v_t * math.sin(a)                           # sum velocity at the pitch point
    rho1, rho2 = r1 * math.sin(a), z2 * m_mm / 2 * math.sin(a)
    rho_red = rho1 * rho2 / (rho1 + rho2)
    mu = schlenk_mu(f_bt / width, v_sum, rho_red, np.asarray(eta_oil_Pa_s) * CP_PER_PA_S,
                   ra_m * UM_PER_M)
    return 1 - mu * loss_factor(z1, z2, a)
