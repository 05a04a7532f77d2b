"""Units, once: the factors between SI and the units a reducer engineer reads and writes.

Every computation works in SI (m, N, N m, Pa, rad, rad/s, W, s); a case's keys and a rig's
columns carry their unit in the name (``_mm``, ``_rpm``, ``_arcmin``), converted into SI
once where they are read (``toothfem.si``, the loop's readers), and back only where a
record is written or shown. The factors live here; a base module every layer may import
(docs/architecture.md).
"""
from __future__ import annotations

import math

import numpy as np

#: rad/s per rpm (one revolution 2 pi rad, a minute 60 s).
RAD_S_PER_RPM = 2.0 * math.pi / 60.0
#: rpm per rad/s.
RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)
#: One degree [rad].
DEG = math.pi / 180.0
#: One arc minute and one arc second [rad].
ARCMIN = math.pi / (180.0 * 60.0)
ARCSEC = ARCMIN / 60.0
#: Lengths: metres per millimetre and per micrometre, millimetres and micrometres per metre.
M_PER_MM = 1e-3
M_PER_UM = 1e-6
MM_PER_M = 1e3
UM_PER_M = 1e6
#: Pressures and moduli: pascals per megapascal and per gigapascal.
PA_PER_MPA = 1e6
PA_PER_GPA = 1e9
#: The reverse, for a record in MPa or GPa written as a product (``p * MPA_PER_PA``).
MPA_PER_PA = 1e-6
GPA_PER_PA = 1e-9
#: Kinematic viscosity: mm^2/s (cSt) per m^2/s; dynamic viscosity: centipoise (mPa s) per Pa s.
MM2_PER_M2 = 1e6
CP_PER_PA_S = 1e3
#: Forces and powers: newtons per kilonewton, watts per kilowatt.
N_PER_KN = 1e3
W_PER_KW = 1e3
#: Seconds per hour.
S_PER_H = 3600.0


def rpm_to_rad_s(speed_rpm):
    """A speed in rpm as rad/s.

    Parameters
    ----------
    speed_rpm : float or array_like
        [rpm].

    Returns
    -------
    float or numpy.ndarray
        [rad/s].
    """
    return _scaled(speed_rpm, RAD_S_PER_RPM)


def rad_s_to_rpm(speed_rad_s):
    """A speed in rad/s as rpm.

    Parameters
    ----------
    speed_rad_s : float or array_like
        [rad/s].

    Returns
    -------
    float or numpy.ndarray
        [rpm].
    """
    return _scaled(speed_rad_s, RPM_PER_RAD_S)


def _scaled(x, factor: float):
    """``x`` times ``factor``: a float for a number, an array for an array."""
    if isinstance(x, (int, float, np.floating, np.integer)):
        return float(x) * factor
    return np.asarray(x, float) * factor
