"""SI records of a case: what fem/ and efficiency/ read.

The case file and :mod:`toothfem.case` keep the units of their keys (mm, GPa, rpm, um ...);
:meth:`toothfem.case.Case.to_si` converts once into these frozen records, and the
analyses read SI only (m, N, N m, Pa, Pa s, rad, rad/s, W). Two exceptions, named where
they are: temperatures stay in deg C (Vogel's law is stated in deg C), and the churning
law of the sine paper (Eq. 42) takes its own units inside its function.

The geometry records (:class:`~toothfem.geometry.cycloid.CycloidGeometry`,
:class:`~toothfem.geometry.cycloid.DiscHolesSI`,
:class:`~toothfem.geometry.sine.SineGearPair`) are SI already and are used as they are.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

_RECORD = dict(frozen=True, kw_only=True)


@dataclass(**_RECORD)
class MaterialSI:
    """Elastic material of the gears, pins and discs (one material for all)."""
    youngs_modulus_Pa: float
    poisson_ratio: float
    density_kg_m3: float


@dataclass(**_RECORD)
class CycloidStageSI:
    """A cycloid disc on its pin ring (K-H-V stage of a cycloid or RV drive)."""
    geometry: Any                   # toothfem.geometry.cycloid.CycloidGeometry
    holes: Any                      # toothfem.geometry.cycloid.DiscHolesSI
    face_width_m: float
    disc_count: int
    pin_structure: str              # "conventional" | "integral"
    disc_load_factor: float         # peak disc torque = factor * output torque / disc_count
    housing_outer_radius_m: float
    lobe_count: int


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

    @property
    def input_speed_rpm(self) -> float:
        return self.input_speed_rad_s * 60.0 / (2.0 * 3.141592653589793)


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


@dataclass(**_RECORD)
class OutputMechanismSI:
    """Pins in holes (W mechanism) and the eccentric bearing of a K-H-V stage."""
    pin_count: int
    pin_hole_circle_radius_m: float
    pin_radius_m: float
    eccentric_bearing_inner_radius_m: float
    plain_bearing_friction_torque_Nm: float


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
class CaseSI:
    """A whole case in SI; ``ratio`` is the signed input/output speed ratio."""
    name: str
    drive: str
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

    def to_si(self) -> "CaseSI":
        """Itself: analyses accept a case or its SI record alike."""
        return self

    def declared_output_torque_Nm(self) -> float | None:
        """The output torque [N m] the operating point declares, lossless: the output torque,
        else the input torque or power times |ratio|; None if none is declared."""
        op = self.operating
        if op.output_torque_Nm:
            return float(op.output_torque_Nm)
        if op.input_torque_Nm:
            return float(op.input_torque_Nm) * abs(self.ratio)
        if op.input_power_W:
            return op.input_power_W / op.input_speed_rad_s * abs(self.ratio)
        return None

    def rated_output_torque_Nm(self) -> tuple[float | None, bool]:
        """(torque [N m], assumed): the rated output torque, else the declared one (assumed
        True: the case names no rating); (None, True) if it declares neither."""
        if self.operating.rated_torque_Nm:
            return float(self.operating.rated_torque_Nm), False
        return self.declared_output_torque_Nm(), True

_MM, _GPA, _UM = 1e-3, 1e9, 1e-6       # SI per unit of the case's keys
#: Face width of a spur first stage that declares none, in modules: ASSUMPTION, the middle
#: of the usual 8-12 m of industrial spur gears (the RV paper gives no width).
SPUR_DEFAULT_WIDTH_MODULES = 10.0
_PER_ARCMIN = 180 * 60 / math.pi        # (N m/arcmin) -> N m/rad


def _si_or_none(value, factor):
    """``value * factor``, or None for a key the case leaves out."""
    return None if value is None else value * factor


def from_case(case) -> CaseSI:
    """Every section of a :class:`toothfem.case.Case` as its SI record: the one place units
    change (:meth:`toothfem.case.Case.to_si` calls it once per case)."""
    mat = case.material
    cyc = case.cycloid
    fs = case.first_stage
    op = case.operating
    lub = case.lubricant
    fri = case.friction
    om = case.output_mechanism
    sup = case.supports
    return CaseSI(
        name=case.name, drive=case.drive, ratio=case.ratio(),
        material=None if mat is None else MaterialSI(
            youngs_modulus_Pa=mat.youngs_modulus_GPa * _GPA, poisson_ratio=mat.poisson_ratio,
            density_kg_m3=mat.density_kg_m3),
        cycloid=None if cyc is None else CycloidStageSI(
            geometry=cyc.geometry(), holes=cyc.holes_si(),
            face_width_m=cyc.face_width_mm * _MM, disc_count=cyc.disc_count,
            pin_structure=cyc.pin_structure, disc_load_factor=cyc.disc_load_factor,
            housing_outer_radius_m=cyc.housing_outer_radius_mm * _MM,
            lobe_count=cyc.lobe_count),
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
            input_speed_rad_s=op.input_speed_rpm * 2 * math.pi / 60,
            output_torque_Nm=op.output_torque_Nm or None,
            input_torque_Nm=op.input_torque_Nm or None,
            input_power_W=None if not op.input_power_kW else op.input_power_kW * 1e3,
            rated_torque_Nm=op.rated_torque_Nm),
        supports=SupportsSI() if case.supports is None else SupportsSI(
            bearing_roller_count=sup.bearing_roller_count,
            bearing_roller_length_m=_si_or_none(sup.bearing_roller_length_mm, _MM),
            bearing_roller_diameter_m=_si_or_none(sup.bearing_roller_diameter_mm, _MM),
            crankshaft_diameter_m=_si_or_none(sup.crankshaft_diameter_mm, _MM),
            crankshaft_span_m=_si_or_none(sup.crankshaft_span_mm, _MM),
            carrier_stiffness_Nm_per_rad=_si_or_none(sup.carrier_stiffness_Nm_per_arcmin,
                                                     _PER_ARCMIN)),
        lubricant=LubricantSI(
            dynamic_viscosity_Pa_s=lub.dynamic_viscosity_Pa_s,
            kinematic_viscosity_m2_s=lub.kinematic_viscosity_mm2_s * _MM ** 2,
            density_kg_m3=lub.density_kg_m3,
            pressure_viscosity_1_per_Pa=lub.pressure_viscosity_1_per_GPa / _GPA,
            reference_temperature_C=lub.reference_temperature_C,
            roughness_Ra_m=lub.roughness_Ra_um * _UM, vogel_B_C=lub.vogel_B_C,
            vogel_C_C=lub.vogel_C_C, churning=lub.churning,
            churning_scale=lub.churning_scale),
        friction=FrictionSI(
            coefficient=fri.coefficient, bearing_coefficient=fri.bearing_coefficient,
            output_pin_coefficient=fri.output_pin_coefficient,
            pin_groove_coefficient=fri.pin_groove_coefficient, mesh_law=fri.mesh_law,
            boundary_coefficient=fri.boundary_coefficient,
            drag_torque_Nm=fri.drag_torque_Nmm * _MM),
        output_mechanism=None if om is None else OutputMechanismSI(
            pin_count=om.pin_count, pin_hole_circle_radius_m=om.pin_hole_circle_radius_mm * _MM,
            pin_radius_m=om.pin_radius_mm * _MM,
            eccentric_bearing_inner_radius_m=om.eccentric_bearing_inner_radius_mm * _MM,
            plain_bearing_friction_torque_Nm=om.plain_bearing_friction_torque_Nmm * _MM))
