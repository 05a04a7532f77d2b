"""SI records of a case: what fem/ and efficiency/ read.

The case file and :mod:`toothfem.case` keep the units of their keys (mm, GPa, rpm, um ...);
:meth:`toothfem.case.Case.to_si` converts once into these frozen records, and the
analyses read SI only (m, N, N m, Pa, Pa s, rad, rad/s, W). Two exceptions, named where
they are: temperatures stay in deg C (Vogel's law is stated in deg C), and the churning
law of the sine paper (Eq. 42) takes its own units inside its function.

The geometry records (:class:`~toothfem.geometry.cycloid.CycloidGeometry`,
:class:`~toothfem.geometry.disc.DiscHolesSI`,
:class:`~toothfem.geometry.sine.SineGearPair`) are SI already and are used as they are.
"""
from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from .errors import ToothfemError, short_repr
from .units import (ARCMIN, M_PER_MM, M_PER_UM, PA_PER_GPA, PA_PER_HV, PA_PER_MPA,
                    rad_s_to_rpm, rpm_to_rad_s)

if TYPE_CHECKING:
    from .layout import Layout

_RECORD = dict(frozen=True, kw_only=True)


@dataclass(**_RECORD)
class MaterialSI:
    """Elastic material of the gears, pins and discs (one material for all), its hardness
    (the asperities' flow pressure) and the limits of the strength checks."""
    youngs_modulus_Pa: float
    poisson_ratio: float
    density_kg_m3: float
    hardness_Pa: float
    allowable_contact_stress_Pa: float
    static_contact_stress_Pa: float
    yield_strength_Pa: float
    fatigue_limit_Pa: float


@dataclass(**_RECORD)
class CycloidStageSI:
    """A cycloid disc on its pin ring (K-H-V stage of a cycloid or RV drive)."""
    geometry: Any                   # toothfem.geometry.cycloid.CycloidGeometry
    holes: Any                      # toothfem.geometry.disc.DiscHolesSI
    face_width_m: float
    disc_count: int
    pin_structure: str              # "conventional" | "integral"
    disc_load_factor: float         # peak disc torque = factor * output torque / disc_count
    housing_outer_radius_m: float
    lobe_count: int
    #: the face width in slices: FaceSpec's fields (fem/cycloid_fe/slices.py), pairs
    face: tuple = ()


@dataclass(**_RECORD)
class SineStageSI:
    """The one-tooth-difference sine pair (planet inside a fixed ring)."""
    pair: Any                       # toothfem.geometry.sine.SineGearPair (face width inside)


@dataclass(**_RECORD)
class SpurStageSI:
    """The involute spur first stage of an RV-type drive (sun on the input shaft)."""
    sun_teeth: int
    planet_teeth: int
    planet_count: int
    module_m: float
    pressure_angle_rad: float
    face_width_m: float             # the case's, or 10 modules
    mesh_efficiency: float | None   # declared; None: from the friction model


@dataclass(**_RECORD)
class RVTrainSI:
    """Tooth numbers of a 2K-V train (RV paper notation z1, z2, z4, z5)."""
    sun_teeth: int
    planet_teeth: int
    disc_teeth: int
    pin_count: int
    disc_count: int
    mesh_efficiency: float


@dataclass(**_RECORD)
class OperatingSI:
    """The declared operating point; torques and power None where not declared."""
    input_speed_rad_s: float
    output_torque_Nm: float | None
    input_torque_Nm: float | None
    input_power_W: float | None
    rated_torque_Nm: float | None = None     # the catalogue's rated output torque
    start_stop_torque_Nm: float | None = None    # its start/stop allowable torque
    momentary_torque_Nm: float | None = None     # its momentary maximum torque

    @property
    def input_speed_rpm(self) -> float:
        return rad_s_to_rpm(self.input_speed_rad_s)


@dataclass(**_RECORD)
class LubricantSI:
    """Oil at its reference temperature; Vogel's law eta = A exp(B/(T + C)) in deg C."""
    dynamic_viscosity_Pa_s: float
    kinematic_viscosity_m2_s: float
    density_kg_m3: float
    pressure_viscosity_1_per_Pa: float
    reference_temperature_C: float
    roughness_Ra_m: float           # arithmetic mean roughness of each surface
    vogel_B_C: float
    vogel_C_C: float
    churning: str
    churning_scale: float
    lubrication: str                # "oil_bath" | "oil_mist" | "oil_jet" | "grease"
    pour_point_C: float             # validity of the viscosity law, deg C
    max_temperature_C: float


@dataclass(**_RECORD)
class FrictionSI:
    """Friction coefficients and laws; the drag torque on the input shaft in N m."""
    coefficient: float
    bearing_coefficient: float
    output_pin_coefficient: float
    pin_groove_coefficient: float
    mesh_law: str
    boundary_coefficient: float
    drag_torque_Nm: float
    windage_torque_Nm: float = 0.0     # at 1000 rpm input, growing with speed squared
    viscous_drag_Nm: float = 0.0       # at 1000 rpm input and eta_ref, growing with speed


@dataclass(**_RECORD)
class OutputMechanismSI:
    """Pins in holes (W mechanism) and the eccentric bearing of a K-H-V stage."""
    pin_count: int
    pin_hole_circle_radius_m: float
    pin_radius_m: float
    eccentric_bearing_inner_radius_m: float
    plain_bearing_friction_torque_Nm: float
    roller_radius_m: float | None = None    # a roller sleeve on each pin (None: bare pins)
    hole_radius_m: float | None = None      # None: the contact radius + the eccentricity

    @property
    def contact_radius_m(self) -> float:
        """The radius that touches the hole: the roller's, else the pin's [m]."""
        return self.roller_radius_m if self.roller_radius_m is not None else self.pin_radius_m


@dataclass(**_RECORD)
class SupportsSI:
    """The elastic supports in series with the mesh (torsional stiffness): the crank or
    eccentric bearings' rollers, the crankshafts and the output carrier; None where the
    case gives none (the drive then assumes a value and says so)."""
    bearing_roller_count: int | None = None
    bearing_roller_length_m: float | None = None
    bearing_roller_diameter_m: float | None = None
    crankshaft_diameter_m: float | None = None
    crankshaft_span_m: float | None = None
    carrier_stiffness_Nm_per_rad: float | None = None


@dataclass(**_RECORD)
class SealsSI:
    """Shaft diameters under the input and output lip seals [m]; None: the drive's own."""
    input_diameter_m: float | None
    output_diameter_m: float | None


@dataclass(**_RECORD)
class BearingsSI:
    """Eccentric (crank) bearings and the main bearing pair; None: the drive's own or not
    given. Loads in N, moment in N m, ratings in N."""
    eccentric_type: str | None
    eccentric_pitch_diameter_m: float | None
    eccentric_dynamic_rating_N: float | None
    main_type: str
    main_pitch_diameter_m: float | None
    main_dynamic_rating_N: float | None
    main_span_m: float | None
    external_radial_load_N: float
    external_axial_load_N: float
    external_moment_Nm: float
    external_radial_offset_m: float = 0.0
    external_axial_radius_m: float = 0.0
    contamination: str | None = None     # ISO 281 Table 13 level: the modified life
    main_preload_N: float | None = None  # each main row's axial preload; None: assumed

    @property
    def tilting_moment_Nm(self) -> float:
        """The tilting moment on the main pair [N m]: the declared moment plus the radial
        load at its offset and the axial load at its radius (the catalogue's
        M = W1 l + W2 l3, the arms from the pair's centre)."""
        return (self.external_moment_Nm
                + self.external_radial_load_N * self.external_radial_offset_m
                + self.external_axial_load_N * self.external_axial_radius_m)


@dataclass(**_RECORD)
class ThermalSI:
    """The housing's heat balance; None: the cited estimate (efficiency/thermal.py)."""
    ambient_C: float
    housing_area_m2: float | None
    heat_transfer_W_m2K: float | None
    emissivity: float
    heat_capacity_J_K: float | None
    sensor_resistance_K_W: float    # the loop's thermal effect (K per W of loss)
    case_temperature_limit_C: float | None = None   # the maker's surface limit
    mounting: str = "free"                          # "free" | "flange"
    contact_conductance_W_m2K: float = 1000.0       # the bolted flange joint
    mount_conductivity_W_mK: float = 50.0           # the machine it is bolted to


@dataclass(**_RECORD)
class DutyPointSI:
    """One row of a duty cycle."""
    output_torque_Nm: float
    input_speed_rad_s: float
    time_share: float


@dataclass(**_RECORD)
class TolerancesSI:
    """Manufacturing tolerances [m] (toothfem.case_design.Tolerances): zone diameters
    (``*_position_m``), symmetric limits, the pin diameter's deviation limits."""
    distribution: str = "normal"
    pin_position_m: float = 0.0
    pin_diameter_lower_m: float = 0.0
    pin_diameter_upper_m: float = 0.0
    pin_circle_radius_m: float = 0.0
    disc_profile_m: float = 0.0
    eccentricity_m: float = 0.0
    crank_hole_position_m: float = 0.0
    tooth_profile_m: float = 0.0
    #: (tolerance, distribution) of those with a distribution of their own
    distributions: tuple = ()

    def distribution_of(self, name: str) -> str:
        """The distribution of tolerance ``name`` (e.g. ``pin_position``).

        Parameters
        ----------
        name : str
            The tolerance's name without its unit.

        Returns
        -------
        str
            Its own distribution, else the section's ``distribution``.
        """
        return dict(self.distributions).get(name, self.distribution)

    def active(self) -> list:
        """Names of the tolerances with a nonzero zone (the pin diameter's two limits as
        one, ``pin_diameter``).

        Returns
        -------
        list of str
            The names without their ``_m`` suffix.
        """
        out = []
        for f in dataclasses.fields(self):
            if not f.name.endswith("_m") or not getattr(self, f.name):
                continue
            name = f.name[:-2]
            if name.startswith("pin_diameter"):
                name = "pin_diameter"
            if name not in out:
                out.append(name)
        return out


@dataclass(**_RECORD)
class CaseSI:
    """A whole case in SI; ``ratio`` is the signed input/output speed ratio, ``layout`` the
    case's :class:`toothfem.layout.Layout` (what the cores ask of it)."""
    name: str
    drive: str
    layout: Layout = field(compare=False, repr=False)
    ratio: float
    material: MaterialSI | None
    cycloid: CycloidStageSI | None
    first_stage: SpurStageSI | None
    sine: SineStageSI | None
    rv: RVTrainSI | None
    operating: OperatingSI
    lubricant: LubricantSI
    friction: FrictionSI
    output_mechanism: OutputMechanismSI | None
    supports: SupportsSI = SupportsSI()
    tolerances: TolerancesSI = TolerancesSI()
    seals: SealsSI | None = None
    bearings: BearingsSI | None = None
    thermal: ThermalSI | None = None
    duty_cycle: tuple = ()

    def to_si(self) -> CaseSI:
        """Itself: analyses accept a case or its SI record alike.

        Returns
        -------
        CaseSI
            ``self``.
        """
        return self

    def declared_output_torque_Nm(self) -> float | None:
        """The output torque the operating point declares, lossless: the output torque, else the
        input torque or power times |ratio|.

        Returns
        -------
        float or None
            Output torque [N m]; None if none is declared.
        """
        op = self.operating
        if op.output_torque_Nm:
            return float(op.output_torque_Nm)
        if op.input_torque_Nm:
            return float(op.input_torque_Nm) * abs(self.ratio)
        if op.input_power_W:
            return op.input_power_W / op.input_speed_rad_s * abs(self.ratio)
        return None


_MM, _GPA, _UM = M_PER_MM, PA_PER_GPA, M_PER_UM     # SI per unit of the case's keys
#: Face width of a spur first stage that declares none, in modules: ASSUMPTION, the middle
#: of the usual 8-12 m of industrial spur gears (the RV paper gives no width).
SPUR_DEFAULT_WIDTH_MODULES = 10.0
_PER_ARCMIN = 1 / ARCMIN               # (N m/arcmin) -> N m/rad


def si_of(case, name: str = "case") -> CaseSI:
    """The SI record of ``case``, or the error naming the argument.

    Parameters
    ----------
    case : toothfem.case.Case or CaseSI
        Anything with ``to_si()``.
    name : str
        The argument, as the message names it.

    Returns
    -------
    CaseSI

    Raises
    ------
    ToothfemError
        For anything else (a path: load it first with ``toothfem.load_case``).
    """
    to_si = getattr(case, "to_si", None)
    if not callable(to_si):
        hint = ("load it first: toothfem.load_case(path)"
                if isinstance(case, (str, os.PathLike))
                else "give a toothfem.Case (toothfem.load_case(path)) or its SI record")
        raise ToothfemError(f"{name} = {short_repr(case)} is not a case; {hint}")
    return to_si()


def _si_or_none(value, factor):
    """``value * factor``, or None for a key the case leaves out."""
    return None if value is None else value * factor


_MPA, _HV = PA_PER_MPA, PA_PER_HV     # Pa per MPa, per Vickers number (units.py)


def from_case(case) -> CaseSI:
    """Every section of a :class:`toothfem.case.Case` as its SI record: the one place units
    change (:meth:`toothfem.case.Case.to_si` calls it once per case).

    Parameters
    ----------
    case : toothfem.case.Case
        The case, in its own units (mm, GPa, um, deg, rpm).

    Returns
    -------
    CaseSI
        Every section in SI (m, Pa, rad, rad/s, N m, W).
    """
    mat = case.material
    cyc = case.cycloid
    fs = case.first_stage
    op = case.operating
    lub = case.lubricant
    fri = case.friction
    om = case.output_mechanism
    return CaseSI(
        name=case.name, drive=case.drive, layout=case.layout, ratio=case.ratio(),
        material=None if mat is None else MaterialSI(
            youngs_modulus_Pa=mat.youngs_modulus_GPa * _GPA, poisson_ratio=mat.poisson_ratio,
            density_kg_m3=mat.density_kg_m3, hardness_Pa=mat.hardness_HV * _HV,
            allowable_contact_stress_Pa=mat.allowable_contact_stress_MPa * _MPA,
            static_contact_stress_Pa=mat.static_contact_stress_MPa * _MPA,
            yield_strength_Pa=mat.yield_strength_MPa * _MPA,
            fatigue_limit_Pa=mat.fatigue_limit_MPa * _MPA),
        cycloid=None if cyc is None else CycloidStageSI(
            geometry=cyc.geometry(), holes=cyc.holes_si(case.khv_output()),
            face_width_m=cyc.face_width_mm * _MM, disc_count=cyc.disc_count,
            pin_structure=cyc.pin_structure, disc_load_factor=cyc.disc_load_factor,
            housing_outer_radius_m=cyc.housing_outer_radius_mm * _MM,
            lobe_count=cyc.lobe_count, face=(
                ("slices", cyc.face_slices), ("tilt_rad", cyc.disc_tilt_arcmin * ARCMIN),
                ("crown_m", cyc.face_crowning_um * M_PER_UM),
                ("form", cyc.face_crowning_form),
                ("flat_fraction", cyc.face_crowning_flat_fraction),
                ("crown_load_N_per_m", None if cyc.face_crowning_load_N is None
                 else cyc.face_crowning_load_N / (cyc.face_width_mm * _MM)),
                ("pin_span_m", None if cyc.pin_span_mm is None else cyc.pin_span_mm * _MM))),
        first_stage=None if fs is None else SpurStageSI(
            sun_teeth=fs.sun_teeth, planet_teeth=fs.planet_teeth,
            planet_count=fs.planet_count, module_m=fs.module_mm * _MM,
            pressure_angle_rad=math.radians(fs.pressure_angle_deg),
            face_width_m=(fs.face_width_mm if fs.face_width_mm else
                          SPUR_DEFAULT_WIDTH_MODULES * fs.module_mm) * _MM,
            mesh_efficiency=fs.mesh_efficiency),
        sine=None if case.sine is None else SineStageSI(pair=case.sine.geometry()),
        rv=None if case.rv is None else RVTrainSI(
            sun_teeth=case.rv.sun_teeth, planet_teeth=case.rv.planet_teeth,
            disc_teeth=case.rv.disc_teeth, pin_count=case.rv.pin_count,
            disc_count=case.rv.disc_count, mesh_efficiency=case.rv.mesh_efficiency),
        operating=OperatingSI(
            input_speed_rad_s=rpm_to_rad_s(op.input_speed_rpm),
            output_torque_Nm=op.output_torque_Nm or None,
            input_torque_Nm=op.input_torque_Nm or None,
            input_power_W=None if not op.input_power_kW else op.input_power_kW * 1e3,
            rated_torque_Nm=op.rated_torque_Nm,
            start_stop_torque_Nm=op.start_stop_torque_Nm,
            momentary_torque_Nm=op.momentary_torque_Nm),
        supports=SupportsSI() if case.supports is None else _supports_si(case.supports),
        tolerances=_tolerances_si(case.tolerances),
        lubricant=LubricantSI(
            dynamic_viscosity_Pa_s=lub.dynamic_viscosity_Pa_s,
            kinematic_viscosity_m2_s=lub.kinematic_viscosity_mm2_s * _MM ** 2,
            density_kg_m3=lub.density_kg_m3,
            pressure_viscosity_1_per_Pa=lub.pressure_viscosity_1_per_GPa / _GPA,
            reference_temperature_C=lub.reference_temperature_C,
            roughness_Ra_m=lub.roughness_Ra_um * _UM, vogel_B_C=lub.vogel_B_C,
            vogel_C_C=lub.vogel_C_C, churning=lub.churning,
            churning_scale=lub.churning_scale, lubrication=lub.lubrication,
            pour_point_C=lub.pour_point_C, max_temperature_C=lub.max_temperature_C),
        friction=FrictionSI(
            coefficient=fri.coefficient, bearing_coefficient=fri.bearing_coefficient,
            output_pin_coefficient=fri.output_pin_coefficient,
            pin_groove_coefficient=fri.pin_groove_coefficient, mesh_law=fri.mesh_law,
            boundary_coefficient=fri.boundary_coefficient,
            drag_torque_Nm=fri.drag_torque_Nmm * _MM,
            windage_torque_Nm=fri.windage_torque_Nmm * _MM,
            viscous_drag_Nm=fri.viscous_drag_Nmm * _MM),
        output_mechanism=None if om is None else OutputMechanismSI(
            pin_count=om.pin_count, pin_hole_circle_radius_m=om.pin_hole_circle_radius_mm * _MM,
            pin_radius_m=om.pin_radius_mm * _MM,
            eccentric_bearing_inner_radius_m=om.eccentric_bearing_inner_radius_mm * _MM,
            plain_bearing_friction_torque_Nm=om.plain_bearing_friction_torque_Nmm * _MM,
            roller_radius_m=None if om.roller_radius_mm is None else om.roller_radius_mm * _MM,
            hole_radius_m=None if om.hole_radius_mm is None else om.hole_radius_mm * _MM),
        seals=_seals_si(case.seals), bearings=_bearings_si(case.bearings),
        thermal=ThermalSI(
            ambient_C=case.thermal.ambient_C, housing_area_m2=case.thermal.housing_area_m2,
            heat_transfer_W_m2K=case.thermal.heat_transfer_W_m2K,
            emissivity=case.thermal.emissivity,
            heat_capacity_J_K=case.thermal.heat_capacity_J_K,
            sensor_resistance_K_W=case.thermal.sensor_resistance_K_W,
            case_temperature_limit_C=case.thermal.case_temperature_limit_C,
            mounting=case.thermal.mounting,
            contact_conductance_W_m2K=case.thermal.contact_conductance_W_m2K,
            mount_conductivity_W_mK=case.thermal.mount_conductivity_W_mK),
        duty_cycle=tuple(DutyPointSI(
            output_torque_Nm=d.output_torque_Nm,
            input_speed_rad_s=rpm_to_rad_s(d.input_speed_rpm),
            time_share=d.time_share) for d in case.duty_cycle))


def _tolerances_si(tol) -> TolerancesSI:
    """Every ``*_mm`` key of [tolerances] in m, and the tolerances' own distributions."""
    own = "_distribution"
    return TolerancesSI(
        distribution=tol.distribution,
        distributions=tuple((f.name[:-len(own)], getattr(tol, f.name))
                            for f in dataclasses.fields(tol)
                            if f.name.endswith(own) and getattr(tol, f.name) is not None),
        **{f.name[:-3] + "_m": getattr(tol, f.name) * _MM
           for f in dataclasses.fields(tol) if f.name.endswith("_mm")})


def _seals_si(seals) -> SealsSI:
    return SealsSI(input_diameter_m=_si_or_none(seals.input_diameter_mm, _MM),
                      output_diameter_m=_si_or_none(seals.output_diameter_mm, _MM))


def _bearings_si(b) -> BearingsSI:
    return BearingsSI(
        eccentric_type=b.eccentric_type,
        eccentric_pitch_diameter_m=_si_or_none(b.eccentric_pitch_diameter_mm, _MM),
        eccentric_dynamic_rating_N=_si_or_none(b.eccentric_dynamic_rating_kN, 1e3),
        main_type=b.main_type, main_pitch_diameter_m=_si_or_none(b.main_pitch_diameter_mm, _MM),
        main_dynamic_rating_N=_si_or_none(b.main_dynamic_rating_kN, 1e3),
        main_span_m=_si_or_none(b.main_span_mm, _MM),
        external_radial_load_N=b.external_radial_load_N,
        external_axial_load_N=b.external_axial_load_N,
        external_moment_Nm=b.external_moment_Nm,
        external_radial_offset_m=b.external_radial_offset_mm * _MM,
        external_axial_radius_m=b.external_axial_radius_mm * _MM,
        contamination=b.contamination, main_preload_N=b.main_preload_N)


def _supports_si(sup) -> SupportsSI:
    return SupportsSI(
        bearing_roller_count=sup.bearing_roller_count,
        bearing_roller_length_m=_si_or_none(sup.bearing_roller_length_mm, _MM),
        bearing_roller_diameter_m=_si_or_none(sup.bearing_roller_diameter_mm, _MM),
        crankshaft_diameter_m=_si_or_none(sup.crankshaft_diameter_mm, _MM),
        crankshaft_span_m=_si_or_none(sup.crankshaft_span_mm, _MM),
        carrier_stiffness_Nm_per_rad=_si_or_none(sup.carrier_stiffness_Nm_per_arcmin,
                                                 _PER_ARCMIN))
