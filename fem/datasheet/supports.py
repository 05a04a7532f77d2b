"""The elastic supports of the system model: roller bearings, shafts, the carrier.

Small closed forms, each with its source; the system model (:mod:`toothfem.fem.drives.
assembly`) takes them as its elements' laws. Units SI: N, m, rad.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...units import ARCMIN, M_PER_MM, MM_PER_M

#: Palmgren's approach of one steel roller on one raceway (line contact), in his units:
#: delta [mm] = PALMGREN_LINE_MM Q[N]^0.9 / l[mm]^0.8 (A. Palmgren, Ball and Roller
#: Bearing Engineering, 3rd ed., 1959; T. A. Harris, M. N. Kotzalas, Essential Concepts
#: of Bearing Technology, 5th ed., 2007, Sec. 6.4). A roller touches two raceways.
PALMGREN_LINE_MM = 3.84e-5
#: Stribeck's factor of a radial roller bearing with zero clearance: the most loaded of Z
#: rollers carries Q_max = STRIBECK_LINE F_r / Z (line contact; Harris & Kotzalas Sec. 7.3,
#: NSK's bearing-load tables give the same 4.08).
STRIBECK_LINE = 4.08
#: Timoshenko's shear coefficient of a solid circular section (Cowper 1966, nu = 0.3).
SHEAR_COEFFICIENT_CIRCLE = 0.9


def roller_approach(load_N, length_m):
    """Approach [m] of one roller on one raceway under ``load_N`` (Palmgren, line contact).

    Parameters
    ----------
    load_N : array_like
        Roller load Q [N], >= 0.
    length_m : float
        Effective roller length l [m].

    Returns
    -------
    numpy.ndarray
        delta = 3.84e-5 Q^0.9 / l^0.8 in mm, returned in m.
    """
    q = np.maximum(np.asarray(load_N, float), 0.0)
    return PALMGREN_LINE_MM * q ** 0.9 / (length_m * MM_PER_M) ** 0.8 * M_PER_MM


def radial_bearing_deflection(load_N, rollers: int, length_m: float):
    """Radial deflection [m] of a roller bearing with zero clearance under a radial load:
    the approach of its most loaded roller (Stribeck's Q_max = 4.08 F_r / Z) on both of its
    raceways (inner and outer: twice Palmgren's single contact).

    Parameters
    ----------
    load_N : array_like
        Radial load F_r [N].
    rollers : int
        Rollers Z in the row.
    length_m : float
        Effective roller length [m].

    Returns
    -------
    numpy.ndarray
        Deflection along the load [m].
    """
    q_max = STRIBECK_LINE * np.abs(np.asarray(load_N, float)) / rollers
    return 2 * roller_approach(q_max, length_m)


def simply_supported_influence(x_m, a_m, span_m, diameter_m, youngs_modulus_Pa,
                               poisson_ratio):
    """Deflection [m per N] at ``x`` of a solid round shaft on two simple supports ``span``
    apart under a unit force at ``a`` (both from one support): Euler-Bernoulli bending
    (Roark, Table 8.1 case 1e) plus Timoshenko's shear deflection.

    Parameters
    ----------
    x_m, a_m : array_like
        Where the deflection is read and where the force acts [m], 0 <= x, a <= span.
    span_m, diameter_m : float
        Support span and shaft diameter [m].
    youngs_modulus_Pa, poisson_ratio : float

    Returns
    -------
    numpy.ndarray
        w(x; a) per unit force, symmetric in x and a (Maxwell).
    """
    x, a = np.broadcast_arrays(np.asarray(x_m, float), np.asarray(a_m, float))
    lo, hi = np.minimum(x, a), np.maximum(x, a)
    b = span_m - hi
    e, nu = youngs_modulus_Pa, poisson_ratio
    inertia = math.pi * diameter_m ** 4 / 64
    bend = b * lo * (span_m ** 2 - b ** 2 - lo ** 2) / (6 * span_m * e * inertia)
    shear_modulus = e / (2 * (1 + nu))
    area = math.pi * diameter_m ** 2 / 4
    shear = lo * b / (span_m * SHEAR_COEFFICIENT_CIRCLE * shear_modulus * area)
    return bend + shear


def torsion_compliance(length_m, diameter_m, youngs_modulus_Pa, poisson_ratio) -> float:
    """Twist [rad per N m] of a solid round shaft of ``length`` under a torque: L/(G J).

    Parameters
    ----------
    length_m, diameter_m : float
        Shaft length and diameter [m].
    youngs_modulus_Pa : float
        Young's modulus [Pa].
    poisson_ratio : float
        Poisson ratio [-] (G = E / (2 (1 + nu))).

    Returns
    -------
    float
        Compliance [rad/(N m)].
    """
    shear_modulus = youngs_modulus_Pa / (2 * (1 + poisson_ratio))
    return length_m / (shear_modulus * math.pi * diameter_m ** 4 / 32)


#: ASSUMPTION: running clearance between a carrier pillar and the disc's pillar hole
#: beyond the disc's orbit (the hole's radius is the pillar's + the eccentricity + this).
PILLAR_GAP_M = 0.5e-3


def guided_beam_compliance(length_m, diameter_m, youngs_modulus_Pa, poisson_ratio) -> float:
    """Lateral compliance [m/N] of a solid round beam fixed in two plates that move apart
    sideways without turning (fixed-guided): Euler-Bernoulli bending L^3 / (12 E I) (W. C.
    Young, R. G. Budynas, Roark's Formulas for Stress and Strain, 7th ed., Table 8.1 case
    1e) plus Timoshenko's shear L / (kappa G A).

    Parameters
    ----------
    length_m, diameter_m : float
        Free length between the plates and diameter [m].
    youngs_modulus_Pa, poisson_ratio : float

    Returns
    -------
    float
        delta / F [m/N].
    """
    inertia = math.pi * diameter_m ** 4 / 64
    area = math.pi * diameter_m ** 2 / 4
    shear_modulus = youngs_modulus_Pa / (2 * (1 + poisson_ratio))
    return (length_m ** 3 / (12 * youngs_modulus_Pa * inertia)
            + length_m / (SHEAR_COEFFICIENT_CIRCLE * shear_modulus * area))


def pillar_carrier_stiffness(count: int, circle_radius_m: float, pillar_diameter_m: float,
                             length_m: float, youngs_modulus_Pa: float, poisson_ratio: float,
                             plate_share: float = 0.5) -> float:
    """Torsional stiffness [N m/rad] the output sees in series from a 2K-V carrier whose
    end plate is joined to the output flange by ``count`` pillars through the discs.

    Each crank rests on a support bearing in the flange and one in the end plate; the
    plate's bearings take ``plate_share`` s of the cranks' tangential force (1/2 for discs
    set symmetrically between them), so s T crosses the pillars, each a fixed-guided beam
    (:func:`guided_beam_compliance`) at the radius R_p: the plate turns by
    s T / k_p against the flange, k_p = n R_p^2 / c_beam. The discs' plane moves with
    s of the plate's turn (the crank a lever between its supports), so the output twists
    by s^2 T / k_p more: the series stiffness is k_p / s^2 (4 k_p for s = 1/2).

    Parameters
    ----------
    count : int
        Pillars.
    circle_radius_m, pillar_diameter_m, length_m : float
        Their circle's radius, their diameter and their free length between the plates [m].
    youngs_modulus_Pa, poisson_ratio : float
    plate_share : float
        s, the end plate's share of the cranks' support force.

    Returns
    -------
    float
        [N m/rad].
    """
    c = guided_beam_compliance(length_m, pillar_diameter_m, youngs_modulus_Pa, poisson_ratio)
    return count * circle_radius_m ** 2 / c / plate_share ** 2


@dataclass(frozen=True, kw_only=True)
class Supports:
    """The supports of one drive as analysed: every value SI, and the names of the values
    the case did not give (``assumed``: the drive chose them, the outputs say so)."""
    bearing_roller_count: int
    bearing_roller_length_m: float
    bearing_roller_diameter_m: float
    crankshaft_diameter_m: float | None
    crankshaft_span_m: float | None
    carrier_stiffness_Nm_per_rad: float | None     # None: rigid carrier
    assumed: tuple = ()

    def describe(self) -> dict:
        """The values in the case's units, each with ``assumed`` True or False.

        Returns
        -------
        dict
            name (in mm or N m/arcmin) -> {"value": float or None, "assumed": bool}.
        """
        mm, per_arcmin = MM_PER_M, ARCMIN
        rows = {
            "bearing_roller_count": self.bearing_roller_count,
            "bearing_roller_length_mm": self.bearing_roller_length_m * mm,
            "bearing_roller_diameter_mm": self.bearing_roller_diameter_m * mm,
            "crankshaft_diameter_mm": (None if self.crankshaft_diameter_m is None
                                       else self.crankshaft_diameter_m * mm),
            "crankshaft_span_mm": (None if self.crankshaft_span_m is None
                                   else self.crankshaft_span_m * mm),
            "carrier_stiffness_Nm_per_arcmin": (
                None if self.carrier_stiffness_Nm_per_rad is None
                else self.carrier_stiffness_Nm_per_rad * per_arcmin),
        }
        names = {"bearing_roller_count": "bearing_roller_count",
                 "bearing_roller_length_mm": "bearing_roller_length_m",
                 "bearing_roller_diameter_mm": "bearing_roller_diameter_m",
                 "crankshaft_diameter_mm": "crankshaft_diameter_m",
                 "crankshaft_span_mm": "crankshaft_span_m",
                 "carrier_stiffness_Nm_per_arcmin": "carrier_stiffness_Nm_per_rad"}
        return {k: {"value": v, "assumed": names[k] in self.assumed}
                for k, v in rows.items()}


#: Assumed bearing rollers when the case gives none: diameter a quarter of the radius of
#: the raceway they run on (needle and cylindrical roller bearings of reducers: 0.2-0.3),
#: rollers ROLLER_PITCH_REL diameters apart on their pitch circle (cage webs between them).
ROLLER_DIAMETER_REL, ROLLER_PITCH_REL = 0.25, 1.2


def resolved(declared, *, raceway_radius_m: float, roller_length_m: float,
             crankshaft_diameter_m: float | None = None,
             crankshaft_span_m: float | None = None, outer_raceway: bool = True,
             carrier_stiffness_Nm_per_rad: float | None = None) -> Supports:
    """The case's supports (:class:`toothfem.si.SupportsSI`) with the drive's assumptions
    where it gives none.

    Parameters
    ----------
    declared : toothfem.si.SupportsSI
        The case's supports; None fields are assumed.
    raceway_radius_m : float
        Radius of the raceway the rollers run on in the member: the crank hole (outer
        raceway) or the eccentric's inner ring (``outer_raceway`` False) [m].
    roller_length_m : float
        Assumed roller length (the member's face width) [m].
    crankshaft_diameter_m, crankshaft_span_m : float, optional
        Assumed crankshaft dimensions [m] (None: the drive has no crankshafts).
    outer_raceway : bool
        Whether the rollers run on an outer raceway of radius ``raceway_radius_m``.
    carrier_stiffness_Nm_per_rad : float, optional
        The drive's carrier where the case declares none (2K-V: its pillars,
        :func:`pillar_carrier_stiffness`); None: a rigid carrier.

    Returns
    -------
    Supports
        Every value SI; ``assumed`` names the values the case did not give.
    """
    assumed = []

    def pick(name, default):
        v = getattr(declared, name)
        if v is None:
            assumed.append(name)
            return default
        return v

    d = pick("bearing_roller_diameter_m", ROLLER_DIAMETER_REL * raceway_radius_m)
    pitch_radius = raceway_radius_m - 0.5 * d if outer_raceway else raceway_radius_m + 0.5 * d
    n_default = max(int(2 * math.pi * pitch_radius / (ROLLER_PITCH_REL * d)), 3)
    count = pick("bearing_roller_count", n_default)
    length = pick("bearing_roller_length_m", roller_length_m)
    shaft_d = shaft_l = None
    if crankshaft_diameter_m is not None:
        shaft_d = pick("crankshaft_diameter_m", crankshaft_diameter_m)
        shaft_l = pick("crankshaft_span_m", crankshaft_span_m)
    carrier = pick("carrier_stiffness_Nm_per_rad", carrier_stiffness_Nm_per_rad)
    return Supports(bearing_roller_count=int(count), bearing_roller_length_m=float(length),
                    bearing_roller_diameter_m=float(d), crankshaft_diameter_m=shaft_d,
                    crankshaft_span_m=shaft_l, carrier_stiffness_Nm_per_rad=carrier,
                    assumed=tuple(assumed))
