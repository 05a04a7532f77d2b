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
