"""The sine gear pair as shapely polygons (drawings, areas, FE outlines)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ...errors import GeometryError, check_range
from ..vectors import rotate, unit
from .conjugate import ring_profile
from .meshing import planet_pose
from .profile import planet_profile, profile_params

if TYPE_CHECKING:
    from .pair import SineGearPair

#: Default rim of the ring polygon beyond the ring's pitch circle, in modules
#: (ASSUMPTION: the sine paper gives no housing).
RING_RIM_MODULES = 5
#: Fewest points on the ring polygon's outer circle (and at least 4 per ring tooth).
_RIM_MIN_POINTS = 720


def planet_polygon(pair: SineGearPair, points_per_tooth: int = 64, crank_angle_rad=None):
    """Planet as a shapely Polygon.

    Parameters
    ----------
    pair : SineGearPair
    points_per_tooth : int
        Profile samples per planet tooth.
    crank_angle_rad : float, optional
        None: in the planet's own frame (centre at the origin); else placed in the ring
        frame at this crank angle (rad).

    Returns
    -------
    shapely.geometry.Polygon
    """
    from shapely.geometry import Polygon

    phi = np.linspace(0, 2 * math.pi, pair.planet_teeth * int(points_per_tooth),
                      endpoint=False)
    p = planet_profile(pair, phi)
    if crank_angle_rad is not None:
        centre, th = planet_pose(pair, float(crank_angle_rad))
        p = rotate(p, th[0]) + centre
    return Polygon(p.T)


def ring_polygon(pair: SineGearPair, outer_radius_m: float | None = None,
                 points_per_tooth: int = 64):
    """Ring gear as a shapely annulus, the tooth profile as the hole, centre at the origin.

    Parameters
    ----------
    pair : SineGearPair
    outer_radius_m : float, optional
        Outer (rim) radius (m), > r2 + a; default r2 + ``RING_RIM_MODULES`` m.
    points_per_tooth : int
        Profile samples per ring tooth.

    Returns
    -------
    shapely.geometry.Polygon

    Raises
    ------
    GeometryError
        If the outer radius does not lie outside the ring's tooth spaces (r2 + a).
    """
    from shapely.geometry import Polygon

    g = profile_params(pair)
    ro = g.r2 + RING_RIM_MODULES * g.m if outer_radius_m is None else float(outer_radius_m)
    check_range("outer_radius_m", ro, g.r2 + g.a, None, lo_open=True, error=GeometryError,
                why="the rim must lie outside the ring's tooth spaces (r2 + a)")
    n = int(points_per_tooth)
    phi = np.linspace(0, 2 * math.pi * g.z2 / g.z1, g.z2 * n, endpoint=False)
    hole = ring_profile(pair, phi)
    t = np.linspace(0, 2 * math.pi, max(_RIM_MIN_POINTS, 4 * g.z2), endpoint=False)
    return Polygon(ro * unit(t).T, [hole.T])
