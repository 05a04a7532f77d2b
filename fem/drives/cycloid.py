"""The cycloid disc on its pin ring: K-H-V cycloid drives and the second stage of RV-type
(2K-V) drives."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import CaseError
from ...geometry import cycloid as cy
from ...geometry.train import khv_speeds, rv_speeds
from .. import cycloid_fe as cf
from .base import Drive


@dataclass(frozen=True, kw_only=True)
class CycloidDrive(Drive):
    """A cycloid disc stage in SI (:class:`toothfem.si.CycloidStageSI`) with its train:
    ``first_teeth`` (sun, planet) of the spur first stage of a 2K-V drive, or None for a
    K-H-V drive whose disc is the output member."""
    stage: object                   # toothfem.si.CycloidStageSI
    material_si: object             # toothfem.si.MaterialSI
    first_teeth: tuple[int, int] | None = None

    kind = "cycloid"
    member_name = "disc"
    contact_name = "pin"
    contacts_name = "pins"
    analytic_weight = "moment_arm"
    fe_options = {"pin_structure": cf.PIN_STRUCTURES}

    @classmethod
    def from_case(cls, si) -> "CycloidDrive":
        if si.cycloid is None:
            raise CaseError(f"drive = {si.drive!r}: a [cycloid] section (disc and pins) is "
                            "required for the contact analyses of this drive")
        if si.material is None:
            raise CaseError("a [material] section is required for the contact analyses")
        if si.rv is not None:
            first = (si.rv.sun_teeth, si.rv.planet_teeth)
        elif si.first_stage is not None:
            first = (si.first_stage.sun_teeth, si.first_stage.planet_teeth)
        else:
            first = None
        return cls(stage=si.cycloid, material_si=si.material, first_teeth=first)

    @property
    def geometry(self) -> cy.CycloidGeometry:
        return self.stage.geometry

    @property
    def period_rad(self) -> float:
        return 2 * math.pi / self.geometry.pin_count

    @property
    def members(self) -> int:
        return self.stage.disc_count

    @property
    def load_factor(self) -> float:
        return self.stage.disc_load_factor

    @property
    def face_width_m(self) -> float:
        return self.stage.face_width_m

    @property
    def material(self):
        return self.material_si

    @property
    def analytic_in_mesh_gap_m(self) -> float:
        """The seed's rigid split ignores modifications: every load-carrying pin shares."""
        return math.inf

    @property
    def two_stage(self) -> bool:
        """A 2K-V (RV-type) train: a spur first stage drives the cranks."""
        return self.first_teeth is not None

    def speeds(self) -> dict:
        z4, z5 = self.stage.lobe_count, self.geometry.pin_count
        if self.first_teeth is not None:
            w = rv_speeds(*self.first_teeth, z4, z5)
            return {"input": 1.0, "crank": w["planet"], "member": w["disc"],
                    "output": w["carrier"]}
        w = khv_speeds(z4, z5)
        return {"input": 1.0, "crank": 1.0, "member": w["moving"], "output": w["moving"]}

    def meshing(self, positions_rad, crank_speed_rad_s: float = 1.0):
        """Pins fixed: the sliding speed at the disc (conventional pins that turn in their
        grooves are handled by the friction rule of the efficiency model)."""
        return cy.meshing(self.geometry, positions_rad, crank_speed_rad_s, pin_motion="fixed")

    def fe_model(self, *, pin_structure: str | None = None, plane: str = "strain"):
        st, m = self.stage, self.material_si
        return cf.CycloidFEModel(
            geometry=st.geometry, holes=st.holes, youngs_modulus=m.youngs_modulus_Pa,
            poisson_ratio=m.poisson_ratio, face_width=st.face_width_m,
            pin_structure=pin_structure or st.pin_structure, plane=plane,
            housing_outer_radius=st.housing_outer_radius_m)

    def _new_cycle_solver(self, model, positions_rad, cache, **options):
        return cf.CycleSolver(model, positions_rad, cache=cache, **options)

    def solve_detailed(self, model, position_rad: float, member_torque_Nm: float):
        return cf.solve_detailed(model, position_rad, member_torque_Nm)

    def profiles(self, points_per_tooth: int):
        """The disc's working outline with its holes' polygon checks (``profile``)."""
        disc = cy.disc_polygon(self.geometry, self.stage.holes,
                               points_per_lobe=points_per_tooth)
        return ({"profile": np.asarray(disc.exterior.coords).T[:, :-1]},
                {"disc_area_mm2": float(disc.area * 1e6),
                 "disc_polygon_valid": bool(disc.is_valid)})

    def member_frame_point(self, model, position_rad: float, point):
        pts = np.asarray(point, float)
        local = cy.to_disc_frame(model.geometry, [position_rad], pts.reshape(2, 1, -1))
        return local[:, 0, :].reshape(pts.shape)

    def fixed_outlines(self, points_per_tooth: int = 48) -> list:
        """Each pin's circle (pin j centred at angle 2 pi j / Zb)."""
        g = self.geometry
        t = np.linspace(0.0, 2 * math.pi, points_per_tooth, endpoint=False)
        circle = g.pin_radius_m * np.stack([np.cos(t), np.sin(t)])
        return [c[:, None] + circle for c in cy.pin_centres(g).T]
