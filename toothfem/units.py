"""Units, once: the factors between SI and the units a reducer engineer reads and writes.

Every computation works in SI (m, N, N m, Pa, rad, rad/s, W, s); a case's keys and a rig's
columns carry their unit in the name (``_mm``, ``_rpm``, ``_arcmin``), converted into SI
once where they are read (``toothfem.si``, the loop's readers), and back only where a
record is written or shown. The factors live here; a base module every layer may import
(docs/architecture.md).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

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
#: Pascals per Vickers hardness number (1 kgf/mm^2: g_n = 9.80665 m/s^2 per mm^2).
PA_PER_HV = 9.80665e6


@dataclass(frozen=True)
class Unit:
    """A unit as the key and column names carry it (``pin_radius_mm``: suffix "mm"): what
    it is called on a page, the SI unit of the computation, and the factor and offset from
    a value in it to SI (``si = factor * value + offset``)."""
    suffix: str
    symbol: str
    si: str
    factor: float
    offset: float = 0.0

    def to_si(self, value):
        """``value`` in this unit, in SI.

        Parameters
        ----------
        value : float or array_like

        Returns
        -------
        float or numpy.ndarray
        """
        return _scaled(value, self.factor) + self.offset if self.offset else \
            _scaled(value, self.factor)

    def from_si(self, value):
        """An SI ``value`` in this unit.

        Parameters
        ----------
        value : float or array_like

        Returns
        -------
        float or numpy.ndarray
        """
        if self.offset:
            return _scaled(_scaled(value, 1.0) - self.offset, 1.0 / self.factor)
        return _scaled(value, 1.0 / self.factor)


#: Every unit a case key, a rig column or an output names, once (temperatures stay in
#: deg C inside the computation, the one exception to SI: every law of the package is
#: stated in deg C). The longest suffix of a name wins (:func:`unit_of`).
UNITS: tuple[Unit, ...] = (
    Unit("Nm_per_arcmin", "N m/arcmin", "N m/rad", 1.0 / ARCMIN),
    Unit("arcmin_per_Nm", "arcmin/(N m)", "rad/(N m)", ARCMIN),
    Unit("1_per_GPa", "1/GPa", "1/Pa", 1.0 / PA_PER_GPA),
    Unit("W_m2K", "W/(m² K)", "W/(m² K)", 1.0), Unit("W_mK", "W/(m K)", "W/(m K)", 1.0),
    Unit("mm2_s", "mm²/s", "m²/s", 1.0 / MM2_PER_M2), Unit("kg_m3", "kg/m³", "kg/m³", 1.0),
    Unit("Pa_s", "Pa s", "Pa s", 1.0), Unit("J_K", "J/K", "J/K", 1.0),
    Unit("K_W", "K/W", "K/W", 1.0),
    Unit("Nmm", "N mm", "N m", M_PER_MM), Unit("kNm", "kN m", "N m", N_PER_KN),
    Unit("Nm", "N m", "N m", 1.0), Unit("kN", "kN", "N", N_PER_KN),
    Unit("GPa", "GPa", "Pa", PA_PER_GPA), Unit("MPa", "MPa", "Pa", PA_PER_MPA),
    Unit("HV", "HV", "Pa", PA_PER_HV),
    Unit("rpm", "rpm", "rad/s", RAD_S_PER_RPM), Unit("rad_s", "rad/s", "rad/s", 1.0),
    Unit("rps", "rps", "rad/s", 2.0 * math.pi),
    Unit("kW", "kW", "W", W_PER_KW), Unit("W", "W", "W", 1.0),
    Unit("arcmin", "arcmin", "rad", ARCMIN), Unit("arcsec", "arcsec", "rad", ARCSEC),
    Unit("deg", "deg", "rad", DEG), Unit("rad", "rad", "rad", 1.0),
    Unit("mm", "mm", "m", M_PER_MM), Unit("um", "µm", "m", M_PER_UM),
    Unit("kgm2", "kg m²", "kg m²", 1.0), Unit("kg", "kg", "kg", 1.0),
    Unit("Hz", "Hz", "Hz", 1.0),
    Unit("m2", "m²", "m²", 1.0), Unit("m", "m", "m", 1.0),
    Unit("C", "°C", "°C", 1.0), Unit("K", "K", "°C", 1.0, -273.15),
    Unit("F", "°F", "°C", 5.0 / 9.0, -160.0 / 9.0),
    Unit("h", "h", "s", S_PER_H), Unit("min", "min", "s", 60.0), Unit("s", "s", "s", 1.0),
    Unit("N", "N", "N", 1.0), Unit("pct", "%", "-", 0.01),
)
_BY_SUFFIX = {u.suffix: u for u in UNITS}


def unit(suffix: str) -> Unit:
    """The unit of a suffix ("mm", "Nm", "arcmin").

    Parameters
    ----------
    suffix : str

    Returns
    -------
    Unit

    Raises
    ------
    KeyError
        For a suffix no unit has, naming the known ones.
    """
    try:
        return _BY_SUFFIX[suffix]
    except KeyError:
        raise KeyError(f"unit {suffix!r} is not one of {sorted(_BY_SUFFIX)}") from None


def unit_of(name: str) -> Unit | None:
    """The unit a key or column name ends with (``face_width_mm`` -> mm; the longest
    suffix wins: ``_Nm_per_arcmin`` before ``_arcmin``), or None for a name without one.

    Parameters
    ----------
    name : str

    Returns
    -------
    Unit or None
    """
    best = None
    for u in UNITS:
        if name.endswith("_" + u.suffix) and (best is None or len(u.suffix) > len(best.suffix)):
            best = u
    return best


def symbol_of(name: str) -> str:
    """What a page shows for the unit a key or column name ends with ("" for none):
    ``face_width_mm`` -> "mm", ``vogel_B_C`` -> "°C".

    Parameters
    ----------
    name : str

    Returns
    -------
    str
    """
    u = unit_of(name)
    return "" if u is None else u.symbol


def conversion(suffix: str, to: str) -> tuple[float, float]:
    """(factor, offset) from a value in unit ``suffix`` to one in unit ``to`` of the same
    SI quantity: ``value_to = factor * value + offset``; "" is a plain number (1).

    Parameters
    ----------
    suffix, to : str
        Suffixes of :data:`UNITS`, or "" for a dimensionless value.

    Returns
    -------
    tuple of float

    Raises
    ------
    KeyError
        For a suffix no unit has.
    ValueError
        For two units of different quantities.
    """
    a, b = (Unit("", "", "-", 1.0) if x == "" else unit(x) for x in (suffix, to))
    if a.si != b.si:
        raise ValueError(f"unit {suffix!r} ({a.si}) does not convert to {to!r} ({b.si})")
    if a.suffix == b.suffix:
        return 1.0, 0.0
    return a.factor / b.factor, (a.offset - b.offset) / b.factor


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
