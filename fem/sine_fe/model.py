"""The sine pair FE model: the record of the pair, its material and supports
(fem/sine_fe/__init__.py)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import ToothfemError, check_range
from ...geometry import sine
from ..elastic import SameMaterial
from ...units import MM_PER_M

# ---------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class SineFEModel(SameMaterial):
    """The sine pair, its material and the two supports (SI units)."""
    pair: sine.SineGearPair
    youngs_modulus: float
    poisson_ratio: float
    planet_bore_radius: float
    ring_outer_radius: float
    plane: str = "strain"
    candidates: int = sine.DEFAULT_CANDIDATES

    def __post_init__(self):
        if not isinstance(self.pair, sine.SineGearPair):
            raise ToothfemError(f"pair = {self.pair!r} is not a SineGearPair")
        check_range("youngs_modulus", self.youngs_modulus, 0, None, lo_open=True)
        check_range("poisson_ratio", self.poisson_ratio, -1, 0.5, lo_open=True, hi_open=True)
        p = self.pair
        root = p.planet_pitch_radius_m - p.tooth_height_m
        check_range("planet_bore_radius", self.planet_bore_radius, 0, 0.95 * root,
                    lo_open=True, why="the bore must lie inside the planet's root circle "
                    "(r1 - a) with a rim of at least 5 % of it")
        phi = np.linspace(-math.pi, math.pi, 65) / p.planet_teeth
        ring_root = float(np.max(np.hypot(*sine.ring_profile(p, phi))))
        check_range("ring_outer_radius", self.ring_outer_radius, 1.05 * ring_root, None,
                    lo_open=True, why="the rim must lie outside the ring's tooth spaces "
                    f"(radius {ring_root:.6g} m) with a rim of at least 5 % of it")
        if isinstance(self.candidates, bool) or int(self.candidates) != self.candidates:
            raise ToothfemError(f"candidates = {self.candidates!r} must be an integer")
        check_range("candidates", self.candidates, 1, (p.planet_teeth - 1) // 4,
                    why="teeth taken on each side of the pitch point")
        if self.plane not in ("strain", "stress"):
            raise ToothfemError(f"plane = {self.plane!r} is not one of ['strain', 'stress']")

    @property
    def face_width(self) -> float:
        return self.pair.face_width_m

    def describe(self) -> dict:
        """The model's supports as a report shows them.

        Returns
        -------
        dict
            planet_bore_radius_mm and ring_outer_radius_mm [mm].
        """
        return {"planet_bore_radius_mm": self.planet_bore_radius * MM_PER_M,
                "ring_outer_radius_mm": self.ring_outer_radius * MM_PER_M}



#: Ring rim per module outside the ring's pitch circle when the case gives none: the
#: default outline of geometry.sine.ring_polygon (ASSUMPTION, the paper gives no housing).
RING_RIM_MODULES = sine.RING_RIM_MODULES


def model_from_pair(pair, material, output_mechanism=None, *,
                    planet_bore_radius_m: float | None = None,
                    ring_outer_radius_m: float | None = None, **kw) -> SineFEModel:
    """The FE model of a sine pair.

    Defaults (ASSUMPTIONS, the paper gives neither): the planet is held at the inner edge
    of its output-pin holes, R_w - (r_x + a0) (19.75 mm for the prototype; the holes
    themselves are not modelled: a solid web, stiffer than the real one), or at r1/2
    without an output mechanism; the ring is clamped at r2 + 5 m.

    Parameters
    ----------
    pair : toothfem.geometry.sine.SineGearPair
        The pair.
    material : toothfem.si.MaterialSI
        Young's modulus [Pa] and Poisson ratio.
    output_mechanism : toothfem.si.OutputMechanismSI, optional
        Places the planet's support; None: at r1/2.
    planet_bore_radius_m, ring_outer_radius_m : float, optional
        The supports [m], instead of the defaults.
    **kw
        Further :class:`SineFEModel` fields (plane, candidates).

    Returns
    -------
    SineFEModel
        The model.

    Raises
    ------
    ToothfemError
        As :class:`SineFEModel` (a support outside its range).
    """
    if planet_bore_radius_m is None:
        om = output_mechanism
        if om is not None:
            planet_bore_radius_m = om.pin_hole_circle_radius_m - om.pin_radius_m \
                - pair.centre_distance_m
        else:
            planet_bore_radius_m = 0.5 * pair.planet_pitch_radius_m
    if ring_outer_radius_m is None:
        ring_outer_radius_m = pair.ring_pitch_radius_m + RING_RIM_MODULES * pair.module_m
    return SineFEModel(pair=pair, youngs_modulus=material.youngs_modulus_Pa,
                       poisson_ratio=material.poisson_ratio,
                       planet_bore_radius=float(planet_bore_radius_m),
                       ring_outer_radius=float(ring_outer_radius_m), **kw)
