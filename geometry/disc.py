"""The cycloid disc as a polygon with its holes (centre bore, crank-bearing holes, carrier
pillar holes, the output pins' holes of a K-H-V drive): the outline of the FE mesh and of
the drawings, with the checks that the holes stay inside the disc and apart."""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import GeometryError
from .cycloid import CycloidGeometry, profile_points
from ..units import MM_PER_M


@dataclass(frozen=True)
class DiscHolesSI:
    """Disc holes in metres (see the case model's DiscHoles for the meaning)."""
    centre_bore_radius_m: float = 0.0
    crank_hole_count: int = 0
    crank_hole_circle_radius_m: float = 0.0
    crank_hole_radius_m: float = 0.0
    pillar_hole_count: int = 0
    pillar_hole_circle_radius_m: float = 0.0
    pillar_hole_radius_m: float = 0.0
    output_hole_count: int = 0              # K-H-V: the output pins' holes
    output_hole_circle_radius_m: float = 0.0
    output_hole_radius_m: float = 0.0

    @property
    def symmetry(self) -> int:
        """The hole pattern's rotational symmetry: the gcd of the hole counts (0: none)."""
        return math.gcd(math.gcd(self.crank_hole_count, self.pillar_hole_count),
                        self.output_hole_count)

    @property
    def carrying_count(self) -> int:
        """The holes through which the disc's torque leaves it: its crank holes (2K-V), else
        the output pins' holes (K-H-V)."""
        return self.crank_hole_count or self.output_hole_count

    def circles(self):
        """Every hole as a circle; crank and output-pin holes start on +x, pillars halfway.

        Returns
        -------
        list of (float, float, float, str)
            (x [m], y [m], radius [m], label) per hole, the centre bore first.
        """
        out = []
        if self.centre_bore_radius_m > 0:
            out.append((0.0, 0.0, self.centre_bore_radius_m, "centre_bore"))
        for kind, offset in (("crank", 0.0), ("pillar", 0.5), ("output", 0.0)):
            n = getattr(self, f"{kind}_hole_count")
            rc = getattr(self, f"{kind}_hole_circle_radius_m")
            rh = getattr(self, f"{kind}_hole_radius_m")
            for k in range(n):
                a = 2 * math.pi * (k + offset) / n
                out.append((rc * math.cos(a), rc * math.sin(a), rh, f"{kind}_{k}"))
        return out


#: Smallest ligament between a hole and the root circle or another hole, relative to Rz.
MIN_LIGAMENT_REL = 0.005


def disc_polygon(geom: CycloidGeometry, holes: DiscHolesSI | None = None,
                 points_per_lobe: int = 96, hole_points: int = 96):
    """The disc as a shapely Polygon (disc frame) with its holes.

    With a rotation modification the disc is the intersection (Delta delta > 0: each flank
    turned toward its tooth centre) or the union (< 0: away) of the profile turned by
    +Delta delta and by -Delta delta (docs/derivations.md 8).

    Parameters
    ----------
    geom : CycloidGeometry
        The disc's profile.
    holes : DiscHolesSI, optional
        Its holes [m]; None: no holes.
    points_per_lobe : int
        Samples of the profile per lobe.
    hole_points : int
        Samples per hole circle.

    Returns
    -------
    shapely.geometry.Polygon
        The disc [m], exterior counter-clockwise.

    Raises
    ------
    GeometryError
        If a hole leaves the disc, holes overlap, or the polygon is invalid.
    """
    import shapely
    from shapely.geometry import Point, Polygon

    if geom.rotation_rad:       # > 0: flanks turned toward the tooth centre; < 0: away
        turned = [Polygon(profile_points(geom, points_per_lobe, f).T) for f in (1, -1)]
        outer = turned[0].intersection(turned[1]) if geom.rotation_rad > 0 \
            else turned[0].union(turned[1])
    else:
        outer = Polygon(profile_points(geom, points_per_lobe).T)
    if not outer.is_valid or outer.geom_type != "Polygon":
        raise GeometryError(f"disc outline is not a simple polygon: "
                            f"{shapely.is_valid_reason(outer)}")
    holes = holes or DiscHolesSI()
    lig = MIN_LIGAMENT_REL * geom.pin_circle_radius_m
    circles = holes.circles()
    shapes = []
    for x, y, r, label in circles:
        reach = math.hypot(x, y) + r
        if reach > geom.root_radius_m - lig:
            raise GeometryError(
                f"{label} hole reaches radius {reach * MM_PER_M:.6g} mm, outside the valid range "
                f"(0, {(geom.root_radius_m - lig) * MM_PER_M:.6g}) mm (root radius "
                f"{geom.root_radius_m * MM_PER_M:.6g} mm less a ligament of {lig * MM_PER_M:.3g} mm)")
        shapes.append((Point(x, y).buffer(r, quad_segs=max(hole_points // 4, 4)), label))
    for i in range(len(shapes)):
        for j in range(i + 1, len(shapes)):
            if shapes[i][0].distance(shapes[j][0]) < lig:
                raise GeometryError(f"holes {shapes[i][1]} and {shapes[j][1]} are closer than "
                                    f"the minimum ligament {lig * MM_PER_M:.3g} mm")
    poly = Polygon(outer.exterior.coords, [list(s.exterior.coords)[::-1] for s, _ in shapes])
    if not poly.is_valid:
        raise GeometryError(f"disc polygon is invalid: {shapely.is_valid_reason(poly)}")
    return shapely.geometry.polygon.orient(poly, 1.0)


# ---------------------------------------------------------------------------------------
# Kinematics
