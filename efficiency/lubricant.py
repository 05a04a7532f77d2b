"""The oil: viscosity over temperature and the no-load (churning) loss law."""
from __future__ import annotations

import numpy as np

from ..errors import CaseError
from ..units import MM2_PER_M2, MM_PER_M, W_PER_KW

#: Margin above Vogel's pole T = -C [K] below which the law is refused (it diverges there).
VOGEL_POLE_MARGIN_K = 1.0


def temperature_range(lubricant) -> tuple:
    """The oil temperatures the viscosity law is used at.

    The lowest is the pour point (below it the oil does not flow; the law has no data) or
    just above Vogel's pole, whichever is higher; the highest the oil's
    ``max_temperature_C`` (mineral oil: 150 C, where oxidation runs away;
    docs/case_schema.md).

    Parameters
    ----------
    lubricant : toothfem.si.LubricantSI
        Pour point, Vogel's C and the highest temperature [deg C].

    Returns
    -------
    tuple of (float, float)
        (lowest, highest) oil temperature [deg C].
    """
    lo = max(lubricant.pour_point_C, -lubricant.vogel_C_C + VOGEL_POLE_MARGIN_K)
    return lo, lubricant.max_temperature_C


def check_oil_temperature(lubricant, oil_temp_C, name="oil_temp_C"):
    """``oil_temp_C`` as an array, refused where a temperature leaves
    :func:`temperature_range`.

    Parameters
    ----------
    lubricant : toothfem.si.LubricantSI
        The oil.
    oil_temp_C : array_like
        Oil temperatures [deg C].
    name : str
        The parameter's name in the message.

    Returns
    -------
    numpy.ndarray
        The temperatures [deg C], shape of ``oil_temp_C``.

    Raises
    ------
    CaseError
        One line: the first bad value and the valid range.
    """
    t = np.asarray(oil_temp_C, float)
    lo, hi = temperature_range(lubricant)
    bad = ~np.isfinite(t) | (t < lo) | (t > hi)
    if np.any(bad):
        raise CaseError(f"{name} = {float(t[bad].flat[0])!r} is outside the valid range "
                        f"[{lo:g}, {hi:g}] of the lubricant's viscosity law (pour point "
                        f"{lubricant.pour_point_C:g} C, max_temperature_C "
                        f"{lubricant.max_temperature_C:g} C, Vogel C = "
                        f"{lubricant.vogel_C_C:g} C)")
    return t


def viscosity_factor(lubricant, oil_temp_C):
    """eta(T)/eta(T_ref) by Vogel's law eta = A exp(B/(T + C)) (Vogel 1921; T in deg C).

    Parameters
    ----------
    lubricant : toothfem.si.LubricantSI
        Vogel's B and C [deg C], the reference temperature and the law's validity
        (:func:`temperature_range`: refused outside with one line).
    oil_temp_C : array_like or None
        Oil temperatures [deg C]; None means the reference temperature (factor 1).

    Returns
    -------
    float or numpy.ndarray
        The viscosity ratio, shape of ``oil_temp_C``.
    """
    if oil_temp_C is None:
        return 1.0
    t = check_oil_temperature(lubricant, oil_temp_C)
    b, c = lubricant.vogel_B_C, lubricant.vogel_C_C
    return np.exp(b / (t + c) - b / (lubricant.reference_temperature_C + c))


def churning_lu_xu_2024(centre_distance_m, speed_rpm, kinematic_viscosity_m2_s):
    """No-load loss of the sine paper (Lu & Xu 2024), Eq. 42 [W].

    P0 = 1e-7 a0 (n1/60)^(4/3) (nu/n1)^0.1 (nu + 90) kW with a0 in mm, n1 in rpm and nu in
    mm^2/s (the law's own units; converted here). The printed 'z50' is read as the
    viscosity nu50 (OCR of the same symbol as gamma50); the kW unit is the one that gives
    the paper's 1.85 % share (docs/efficiency.md).

    Parameters
    ----------
    centre_distance_m : float
        a0 [m] (the eccentricity of a cycloid drive).
    speed_rpm : array_like
        Crank (input) speed [rpm].
    kinematic_viscosity_m2_s : array_like
        Oil kinematic viscosity at the operating temperature [m^2/s].

    Returns
    -------
    numpy.ndarray
        The loss [W].
    """
    a0_mm = centre_distance_m * MM_PER_M
    n = np.asarray(speed_rpm, float)
    nu = np.asarray(kinematic_viscosity_m2_s, float) * MM2_PER_M2   # mm^2/s
    return 1e-7 * a0_mm * (n / 60.0) ** (4.0 / 3.0) * (nu / n) ** 0.1 * (nu + 90.0) * W_PER_KW
