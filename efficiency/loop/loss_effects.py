"""Effects of the reducer the default model takes at a default or leaves out: the oil's
viscosity grade, a drag growing with the square of the speed or in proportion to it, the
main bearings' preload.

* ``viscosity_grade``: the oil in the rig is not the case's (a VG 32 fill where the case
  says VG 68): its kinematic viscosity at 40 C is fitted, the case's Vogel law kept
  (ISO 3448:1992 grades by the viscosity at 40 C). It acts on everything the viscosity
  does: the EHL friction, the film ratio (mixed lubrication), churning and the bearings'
  viscous drag. Always a candidate: the case names an oil, the rig may run another.
* ``windage``: a drag torque on the input that grows with the square of the speed
  (``friction.windage_torque_Nmm`` at 1000 rpm; :mod:`toothfem.efficiency.no_load`), the
  turbulent drag of parts turning in air and mist (Dawson 1984), or lip seals running
  short of oil (their friction rising with speed).
* ``viscous_drag``: a drag torque on the input that grows in proportion to the speed and the
  oil's viscosity (``friction.viscous_drag_Nmm`` at 1000 rpm and the reference viscosity;
  :mod:`toothfem.efficiency.no_load`): an oil film of fixed gap sheared by the input shaft
  (Petroff's law), between the constant ``drag_torque`` and the speed-squared ``windage``.
* ``bearing_preload``: the axial preload of each main bearing row
  (``bearings.main_preload_N``; by default 2 % of the row's C0, an ASSUMPTION of
  :mod:`toothfem.efficiency.main_bearing`), its Palmgren load term mu F d_m / 2 at the
  output's speed. Up to 10 % of C0.
"""
from __future__ import annotations

import dataclasses
import math

from ...fem.drives import drive_for
from ..bearing_set import main_pair
from .effect_base import Effect, Parameter, declared_if_changed, setter

#: ISO 3448:1992 viscosity grades run from VG 2 to VG 3200, each +-10 % about its
#: nominal viscosity at 40 C; the fit stays inside VG 2 (-10 %) to VG 1500 (+10 %), the
#: grades of gear oils (a VG 2200 or 3200 is a worm-gear oil).
VG_RANGE_MM2_S = (1.8, 1650.0)
#: Starting values of the fit as factors on the case's nu40: one and two grades either way
#: (ISO 3448's grades step by about 1.5), and a tenth (a gear oil where a hydraulic oil runs).
GRADE_STARTS = (1.0, 0.5, 0.2, 0.1, 2.0)
#: The temperature of the grade [deg C].
GRADE_TEMPERATURE_C = 40.0
#: Largest main-bearing preload the fit may take, as a share of the row's static rating
#: C0: makers' heavy preload class of matched angular contact pairs stays below a few
#: percent of C0 (e.g. SKF's class C/D for super-precision pairs); 10 % is beyond any.
MAX_PRELOAD_PER_C0 = 0.10


def grade_viscosity_mm2_s(lubricant) -> float:
    """Kinematic viscosity at 40 C of a case's lubricant by its Vogel law [mm^2/s].

    Parameters
    ----------
    lubricant : toothfem.case_running.Lubricant
        The case's lubricant (viscosity at its reference temperature, Vogel B and C).

    Returns
    -------
    float
        nu(40 C) [mm^2/s].
    """
    b, c = lubricant.vogel_B_C, lubricant.vogel_C_C
    return lubricant.kinematic_viscosity_mm2_s * math.exp(
        b / (GRADE_TEMPERATURE_C + c) - b / (lubricant.reference_temperature_C + c))


def _set_grade(case, values):
    lub = case.lubricant
    s = float(values[0]) / grade_viscosity_mm2_s(lub)
    return dataclasses.replace(case, lubricant=dataclasses.replace(
        lub, kinematic_viscosity_mm2_s=lub.kinematic_viscosity_mm2_s * s,
        dynamic_viscosity_Pa_s=lub.dynamic_viscosity_Pa_s * s))


def _grade_bounds(case, points):
    lub = case.lubricant
    nu40 = grade_viscosity_mm2_s(lub)
    # the case's own ranges of the two viscosities at its reference temperature
    s_lo = max(0.1 / lub.kinematic_viscosity_mm2_s, 1e-4 / lub.dynamic_viscosity_Pa_s)
    s_hi = min(1e4 / lub.kinematic_viscosity_mm2_s, 10.0 / lub.dynamic_viscosity_Pa_s)
    return ((max(VG_RANGE_MM2_S[0], s_lo * nu40), min(VG_RANGE_MM2_S[1], s_hi * nu40),
             0.1 * nu40, tuple(f * nu40 for f in GRADE_STARTS)),)


def viscosity_grade() -> Effect:
    """The oil's viscosity grade: its kinematic viscosity at 40 C, the case's Vogel law
    kept (module docstring).

    Returns
    -------
    Effect
        Parameter viscosity_40C_mm2_s [mm^2/s] (lubricant.kinematic_viscosity_mm2_s and
        dynamic_viscosity_Pa_s scaled together).
    """
    return Effect(
        name="viscosity_grade",
        summary="the oil's viscosity grade (its viscosity at 40 C) differs from the case's",
        equation="nu(T) = nu40 exp(B/(T + C) - B/(40 + C))",
        citation="ISO 3448:1992 (viscosity grades at 40 C); H. Vogel, Phys. Z. 22 (1921) 645",
        parameters=(Parameter("viscosity_40C_mm2_s", "mm^2/s", *VG_RANGE_MM2_S,
                              (68.0,), 10.0, "kinematic viscosity at 40 C, nu40"),),
        case_fields=("lubricant.kinematic_viscosity_mm2_s",
                     "lubricant.dynamic_viscosity_Pa_s"),
        set_fields=_set_grade, declared_by=lambda case: None, bounds_for=_grade_bounds,
        direct_test="a viscosity measurement of an oil sample at 40 C (ISO 3104), or the "
                    "oil's data sheet")


def windage() -> Effect:
    """Drag on the input growing with the square of the speed (module docstring).

    Returns
    -------
    Effect
        Parameter windage_torque_Nmm [N mm] at 1000 rpm (friction.windage_torque_Nmm).
    """
    return Effect(
        name="windage",
        summary="drag on the input growing with speed squared (windage, seals short of oil)",
        equation="P = T_w (n / 1000 rpm)^2 omega_in",
        citation="P. H. Dawson, Proc. IMechE 198A (1984) 51-59 (windage power ~ n^2.9); "
                 "ISO/TR 14179-2:2001 (no-load losses)",
        parameters=(Parameter("windage_torque_Nmm", "N mm", 0.0, 1e6, (5.0, 50.0, 500.0),
                              50.0, "drag torque at 1000 rpm input"),),
        case_fields=("friction.windage_torque_Nmm",),
        set_fields=setter("friction", "windage_torque_Nmm"),
        declared_by=declared_if_changed("friction", "windage_torque_Nmm",
                                         "friction.windage_torque_Nmm"),
        linear_in=lambda case: "windage",
        direct_test="no-load runs (output uncoupled) at three or more input speeds: a drag "
                    "torque rising with the square of the speed")


def viscous_drag() -> Effect:
    """Drag on the input growing with the speed and the oil's viscosity (module docstring).

    Returns
    -------
    Effect
        Parameter viscous_drag_Nmm [N mm] at 1000 rpm and the reference viscosity
        (friction.viscous_drag_Nmm).
    """
    return Effect(
        name="viscous_drag",
        summary="drag on the input growing with speed and viscosity (a sheared oil film)",
        equation="P = T_v (n / 1000 rpm) (eta / eta_ref) omega_in",
        citation="N. Petroff (1883); B. J. Hamrock, S. R. Schmid, B. O. Jacobson, "
                 "Fundamentals of Fluid Film Lubrication (2004), Eq. 8.52",
        parameters=(Parameter("viscous_drag_Nmm", "N mm", 0.0, 1e6, (5.0, 50.0, 500.0),
                              50.0, "drag torque at 1000 rpm input"),),
        case_fields=("friction.viscous_drag_Nmm",),
        set_fields=setter("friction", "viscous_drag_Nmm"),
        declared_by=declared_if_changed("friction", "viscous_drag_Nmm",
                                         "friction.viscous_drag_Nmm"),
        linear_in=lambda case: "viscous_drag",
        direct_test="no-load runs (output uncoupled) at three or more input speeds and two "
                    "oil temperatures: a drag torque rising in proportion to the speed and "
                    "the viscosity")


def _static_rating(case):
    return main_pair(case.to_si(), drive_for(case)).static_rating_N


def _preload_bounds(case, points):
    c0 = _static_rating(case)
    return ((0.0, MAX_PRELOAD_PER_C0 * c0, 0.01 * c0, (0.02 * c0, 0.05 * c0)),)


def _preload_declared(case):
    if case.bearings.main_preload_N is not None:
        return f"bearings.main_preload_N = {case.bearings.main_preload_N!r}"
    return None


def bearing_preload() -> Effect:
    """Axial preload of the main bearing rows (module docstring).

    Returns
    -------
    Effect
        Parameter main_preload_N [N] (bearings.main_preload_N).
    """
    return Effect(
        name="bearing_preload",
        summary="axial preload of the main bearing rows (their Palmgren load term)",
        equation="P = mu_b F_p d_m / 2 omega_out per row",
        citation="A. Palmgren, Ball and Roller Bearing Engineering (1959); SKF, 'The SKF "
                 "model for calculating the frictional moment' (2018)",
        parameters=(Parameter("main_preload_N", "N", 0.0, 1e7, (1000.0,), 100.0,
                              "axial preload of each main bearing row"),),
        acts_on="main_bearings",
        case_fields=("bearings.main_preload_N",),
        set_fields=setter("bearings", "main_preload_N"), declared_by=_preload_declared,
        bounds_for=_preload_bounds,
        direct_test="the main bearings' rolling torque measured on the assembled output "
                    "before the discs are fitted (the makers' preload check)")
