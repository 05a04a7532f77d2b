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

from dataclasses import dataclass
from typing import Any

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


@dataclass(**_RECORD)
class OutputMechanismSI:
    """Pins in holes (W mechanism) and the eccentric bearing of a K-H-V stage."""
    pin_count: int
    pin_hole_circle_radius_m: float
    pin_radius_m: float
    eccentric_bearing_inner_radius_m: float
    plain_bearing_friction_torque_Nm: float


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


@dataclass(**_RECORD)
class ThermalSI:
    """The housing's heat balance; None: the cited estimate (efficiency/thermal.py)."""
    ambient_C: float
    housing_area_m2: float | None
    heat_transfer_W_m2K: float | None
    emissivity: float
    heat_capacity_J_K: float | None
    sensor_resistance_K_W: float    # the loop's thermal effect (K per W of loss)


@dataclass(**_RECORD)
class DutyPointSI:
    """One row of a duty cycle."""
    output_torque_Nm: float
    input_speed_rad_s: float
    time_share: float


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
    seals: SealsSI | None = None
    bearings: BearingsSI | None = None
    thermal: ThermalSI | None = None
    duty_cycle: tuple = ()

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
