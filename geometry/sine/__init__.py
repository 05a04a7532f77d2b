"""Sine gear pair with a small tooth difference (installed as ``toothfem.geometry.sine``):
planet profile, conjugate ring profile, validity bounds and meshing kinematics over the
crank angle.

Source: Y. Lu, L. Xu, "Transmission efficiency of one tooth difference sine tooth profile
planetary reducer", Heliyon 10 (2024) e26300 (the sine paper), Sec. 2; the corrections and
numerical checks are in docs/derivations.md, section 3 (S1-S9).

One job per module (each depends only on those above it):

- ``profile``: the numbers of a pair (:class:`ProfileParams`), the planet profile
  (Eq. 1) with analytic derivatives and curvature;
- ``conjugate``: the meshing equation, the ring as the envelope of the planet's positions,
  the conjugate contact and its pressure angles (Eqs. 8-14), foot points on the ring;
- ``limits``: bounds on the tooth height (regular envelope, no interference, no undercut
  of the contact path);
- ``pair``: the :class:`SineGearPair` record, validated against those bounds;
- ``meshing``: poses, closest approach, the ``MeshingState``, contact counts, kinematics
  at a chosen contact point;
- ``drawing``: shapely polygons.

Every public name is re-exported here: ``from toothfem.geometry import sine; sine.meshing``.
"""
from .conjugate import (SeedPressureAngles, conjugate_contact, contact_crank_angle,
                        distance_to_ring, foot_point, pitch_point_angle, pressure_angles,
                        ring_curve, ring_profile, seed_pressure_angles)
from .drawing import RING_RIM_MODULES, planet_polygon, ring_polygon
from .carrying import (LOAD_CARRYING_GAP_M, check_load_carrying, max_drive_gap_m,
                       min_tooth_height_m)
from .limits import (ToothHeightLimits, check_tooth_height, max_tooth_height_m,
                     tooth_height_limits)
from .meshing import (DEFAULT_CANDIDATES, Approach, ContactKinematics, PointPair,
                      closest_approach, contact_count, flank_window, kinematics_at, meshing,
                      pitch_point, planet_pose, planet_rotation)
from .pair import MIN_PLANET_TEETH, SineGearPair
from .profile import (ProfileCurve, ProfileParams, curvature_eq6, planet_curve,
                      planet_profile, profile_params)

__all__ = [
    "Approach", "ContactKinematics", "DEFAULT_CANDIDATES", "LOAD_CARRYING_GAP_M",
    "MIN_PLANET_TEETH", "check_load_carrying", "max_drive_gap_m", "min_tooth_height_m",
    "PointPair", "ProfileCurve", "ProfileParams", "RING_RIM_MODULES", "SeedPressureAngles",
    "SineGearPair", "ToothHeightLimits", "check_tooth_height", "closest_approach",
    "conjugate_contact", "contact_count", "contact_crank_angle", "curvature_eq6",
    "distance_to_ring", "flank_window", "foot_point", "kinematics_at", "max_tooth_height_m",
    "meshing", "pitch_point", "pitch_point_angle", "planet_curve", "planet_polygon",
    "planet_pose", "planet_profile", "planet_rotation", "pressure_angles", "profile_params",
    "ring_curve", "ring_polygon", "ring_profile", "seed_pressure_angles",
    "tooth_height_limits",
]
