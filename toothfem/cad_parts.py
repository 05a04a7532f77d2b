"""The parts of a drive as a drawing (:class:`toothfem.cad.PartDrawing`): what the DXF, SVG
and STEP writers of :mod:`toothfem.cad` draw.

One builder per member (a layout's ``Layout.cad_parts`` picks it), each from the drive's
own records (SI):

* cycloid and RV drives: layer ``DISC_PROFILE`` (the disc's working profile, the outline of
  ``profile.csv``), ``DISC_HOLES`` (centre bore, crank-bearing holes, carrier-pillar holes,
  a K-H-V drive's output-pin holes: ``DiscHolesSI.circles``), ``PINS`` (the pin ring),
  ``OUTPUT_PINS`` (a K-H-V drive's output pins, with their roller sleeves), ``HOUSING`` (the
  pin housing: its bore with the pins' grooves, or with the integral pins' teeth, and its
  outer circle). The first disc only, at crank angle 0 (its centre at (e, 0), not turned),
  as ``drawing.png`` places it; the second disc of a pair runs half a turn of the crank
  behind.
* sine pair: ``PLANET_PROFILE``, ``PLANET_HOLES`` (the eccentric bearing's bore and the
  output pins' holes), ``OUTPUT_PINS``, ``RING`` (the ring's tooth outline and its rim).

The drawing is in the housing frame (the pins' or ring's centre at the origin); each STEP
region is in its part's own frame (the disc's or planet's centre at the origin), but the
pins' (``pins``: conventional pins; integral pins are the housing's teeth), the output
pins' (``output_pins``) and their rollers' (``output_rollers``): one solid per pin at its
place in the housing frame at crank angle 0, as the drawing places them.
"""
from __future__ import annotations

import math

import numpy as np

from .cad import Body, PartDrawing, Region
from .errors import CaseError, GeometryError, check_range
from .fem.drives import drive_for
from .fem.sine_fe.model import model_from_pair
from .geometry import cycloid_mesh as cym, sine as sg
from .geometry.disc import DiscHolesSI
from .geometry.vectors import rotate
from .si import si_of
from .units import MM_PER_M

#: The case's default housing outer radius: the pin circle radius plus this many pin radii
#: (toothfem.case_sections.CycloidStage: "a wall of 5 pin radii by default"); a housing at
#: exactly this radius is reported as assumed.
HOUSING_DEFAULT_WALL_PIN_RADII = 5
#: Relative tolerance of "exactly the default" (the mm -> m conversion's round-off).
DEFAULT_MATCH_REL = 1e-9
#: Decimals of a summary's lengths in mm (1e-9 mm: the model's own round-off is ~1e-12 mm).
DIMENSION_DECIMALS = 9
#: Fewest points of the housing bore's circle between the pins (per pin pitch, as many as
#: a pin's circle has, and no fewer than this over the whole bore).
BORE_MIN_POINTS = 720


def _placed(points, centre, angle: float) -> np.ndarray:
    """(2, N) points [m] of a part's own frame turned by ``angle`` and moved to
    ``centre`` (the drawing's frame)."""
    return rotate(np.asarray(points, float), angle) + np.asarray(centre, float).reshape(2, 1)


def _placed_circles(circles, centre, angle: float) -> tuple:
    """Circles (x, y, r) [m] of a part's own frame placed as :func:`_placed`."""
    out = []
    for x, y, r in circles:
        (px,), (py,) = _placed(np.array([[x], [y]]), centre, angle)
        out.append((float(px), float(py), float(r)))
    return tuple(out)


def _ring_of(count: int, radius_m: float, circle_m: float) -> tuple:
    """``count`` circles of radius ``circle_m`` on a circle of ``radius_m`` about the
    origin, the first on +x."""
    a = 2 * math.pi * np.arange(count) / count
    return tuple((radius_m * math.cos(t), radius_m * math.sin(t), circle_m) for t in a)


def _rounded(mm: float) -> float:
    """A length [mm] for the summary: to 1e-9 mm (no 1e-15 round-off of a zero)."""
    return round(float(mm), DIMENSION_DECIMALS) + 0.0


def _tidy(dims: dict) -> dict:
    """The summary's dimensions with every length :func:`_rounded`."""
    return {k: _rounded(v) if isinstance(v, float) else v for k, v in dims.items()}


def _listed(holes: DiscHolesSI) -> list:
    """Each hole of a disc or planet (its own frame) as the summary lists it [mm]."""
    return [{"hole": label, "x_mm": _rounded(x * MM_PER_M), "y_mm": _rounded(y * MM_PER_M),
             "diameter_mm": _rounded(2 * r * MM_PER_M)} for x, y, r, label in holes.circles()]


def _pins_body(om, layer_text: str) -> Body:
    """The output pins (with their roller sleeves, if any) at crank angle 0."""
    pins = _ring_of(om.pin_count, om.pin_hole_circle_radius_m, om.pin_radius_m)
    rollers = () if om.roller_radius_m is None else _ring_of(
        om.pin_count, om.pin_hole_circle_radius_m, om.roller_radius_m)
    return Body(layer="OUTPUT_PINS", description=layer_text + (
        " with their roller sleeves" if rollers else ""), circles=pins + rollers)


def housing_bore(geometry, integral: bool, points_per_pin: int = 96) -> np.ndarray:
    """The pin housing's inner outline: the circle of radius Rz with a groove of each pin's
    circle (conventional pins, seated in grooves), or with each pin's inner half standing
    out of it (integral pins, part of the housing).

    Parameters
    ----------
    geometry : toothfem.geometry.cycloid.CycloidGeometry
        The pin ring.
    integral : bool
        Integral pins (teeth of the housing) instead of pins in grooves.
    points_per_pin : int
        Points on each pin's circle, [8, 10000].

    Returns
    -------
    numpy.ndarray, shape (2, N)
        The closed outline [m], housing frame, counter-clockwise, no repeated end.

    Raises
    ------
    GeometryError
        If the pins overlap so that the bore is not one simple outline.
    """
    from shapely.geometry import Point
    from shapely.ops import unary_union

    check_range("points_per_pin", points_per_pin, 8, 10000)
    q = max(points_per_pin // 4, 2)
    big = max(BORE_MIN_POINTS, geometry.pin_count * points_per_pin) // 4
    bore = Point(0.0, 0.0).buffer(geometry.pin_circle_radius_m, quad_segs=big)
    pins = unary_union([Point(x, y).buffer(geometry.pin_radius_m, quad_segs=q)
                        for x, y in cym.pin_centres(geometry).T])
    shape = bore.difference(pins) if integral else bore.union(pins)
    if shape.geom_type != "Polygon" or shape.interiors:
        raise GeometryError("the pin housing's bore is not one simple outline (pins "
                            "overlapping or standing apart from the pin circle)")
    return np.asarray(shape.exterior.coords).T[:, :-1]


def cycloid_parts(si, drive, points_per_tooth: int) -> PartDrawing:
    """The disc with its holes, the pins, the output pins (K-H-V) and the pin housing.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    points_per_tooth : int
        Samples per lobe or tooth.

    Returns
    -------
    toothfem.cad.PartDrawing
    """
    st, g, h = drive.stage, drive.geometry, drive.stage.holes
    profiles, _ = drive.profiles(points_per_tooth)     # checks the holes (disc_polygon)
    profile = profiles["profile"]
    holes = tuple((x, y, r) for x, y, r, _ in h.circles())
    centre, turn = cym.disc_pose(g, 0.0)
    disc_at = (centre[:, 0], float(turn[0]))
    integral = st.pin_structure == "integral"
    bore = housing_bore(g, integral, points_per_tooth)
    r_out = st.housing_outer_radius_m
    length = st.disc_count * st.face_width_m
    bodies = [
        Body(layer="DISC_PROFILE", description="the disc's working profile (disc 1 at "
             "crank angle 0, its centre at (e, 0))", polylines=(_placed(profile, *disc_at),)),
        Body(layer="DISC_HOLES", description="the disc's holes: centre bore, crank-bearing "
             "holes, carrier-pillar holes, output-pin holes",
             circles=_placed_circles(holes, *disc_at)),
        Body(layer="PINS", description=f"the {g.pin_count} pins" + (
            " (integral: teeth of the housing)" if integral else " in the housing's grooves"),
             circles=tuple((float(x), float(y), g.pin_radius_m)
                           for x, y in cym.pin_centres(g).T)),
    ]
    if drive.output is not None:
        bodies.append(_pins_body(drive.output, "the output pins in the disc's holes"))
    bodies.append(Body(layer="HOUSING", description="the pin housing: its bore "
                       + ("with the integral pins" if integral else "with the pins' grooves")
                       + " and its outer circle", polylines=(bore,),
                       circles=((0.0, 0.0, r_out),)))
    assumed = {"housing_length_mm": f"the discs' stack, disc_count x face width = "
               f"{length * MM_PER_M:.6g} mm (the housing's own length is not in the case)"}
    default = g.pin_circle_radius_m + HOUSING_DEFAULT_WALL_PIN_RADII * g.pin_radius_m
    if math.isclose(r_out, default, rel_tol=DEFAULT_MATCH_REL):
        assumed["housing_outer_radius_mm"] = (
            f"cycloid.housing_outer_radius_mm is not in the case: its default, the pin "
            f"circle radius + {HOUSING_DEFAULT_WALL_PIN_RADII} pin radii = "
            f"{r_out * MM_PER_M:.6g} mm (the FE model's integral housing takes the same)")
    dims = {"pin_count": g.pin_count, "pin_circle_radius_mm": g.pin_circle_radius_m * MM_PER_M,
            "pin_radius_mm": g.pin_radius_m * MM_PER_M,
            "eccentricity_mm": g.eccentricity_m * MM_PER_M,
            "disc_centre_mm": [_rounded(v * MM_PER_M) for v in centre[:, 0]],
            "face_width_mm": st.face_width_m * MM_PER_M,
            "housing_outer_radius_mm": r_out * MM_PER_M,
            "housing_length_mm": length * MM_PER_M,
            "disc_holes_in_disc_frame": _listed(h)}
    regions: tuple[Region, ...] = (
        Region(name="disc", outer=profile, holes=holes, thickness_m=st.face_width_m),
        Region(name="housing", outer=(0.0, 0.0, r_out), holes=(bore,), thickness_m=length))
    if not integral:            # integral pins are the housing's teeth (its bore)
        regions += (Region(name="pins", outer=(0.0, 0.0, g.pin_radius_m),
                           at=tuple((float(x), float(y)) for x, y in cym.pin_centres(g).T),
                           thickness_m=length),)
    if drive.output is not None:
        regions += _output_pin_regions(drive.output, length)
    return PartDrawing(bodies=tuple(bodies), regions=regions, dimensions_mm=_tidy(dims),
                       assumed=assumed)


def _output_pin_regions(om, length_m: float) -> tuple:
    """The output pins' STEP regions at crank angle 0 in the housing frame, as the drawing
    places them: the pins, and their roller sleeves (a ring of the roller's radius on the
    pin's) where they have them, each over the members' stack ``length_m``."""
    centres = tuple((float(x), float(y)) for x, y, _ in _ring_of(
        om.pin_count, om.pin_hole_circle_radius_m, om.pin_radius_m))
    out: tuple[Region, ...] = (Region(name="output_pins", outer=(0.0, 0.0, om.pin_radius_m),
                                      at=centres, thickness_m=length_m),)
    if om.roller_radius_m is not None:
        out += (Region(name="output_rollers", outer=(0.0, 0.0, om.roller_radius_m),
                       holes=((0.0, 0.0, om.pin_radius_m),), at=centres,
                       thickness_m=length_m),)
    return out


def _planet_holes(si, drive) -> tuple:
    """(bore radius [m], holes as DiscHolesSI, assumed) of the sine planet: the eccentric
    bearing's outer raceway r_p + d_w (its rollers on the eccentric, the sizing of
    efficiency.bearing_set's eccentric bearing) and the output pins' holes (radius
    ``hole_radius``, else the pin's contact radius + a0); without an output mechanism the
    FE model's support radius and no pin holes."""
    pair, om = drive.pair, drive.output_mechanism
    assumed = {}
    if om is None:
        bore = model_from_pair(pair, drive.material_si).planet_bore_radius
        assumed["planet_bore_radius_mm"] = (
            f"no [output_mechanism]: the FE model's planet support, r1/2 = "
            f"{bore * MM_PER_M:.6g} mm")
        return bore, DiscHolesSI(centre_bore_radius_m=bore), assumed
    supports = drive.supports(si.supports)
    bore = om.eccentric_bearing_inner_radius_m + supports.bearing_roller_diameter_m
    if "bearing_roller_diameter_m" in supports.assumed:
        assumed["planet_bore_radius_mm"] = (
            f"the eccentric bearing's outer raceway r_p + d_w = {bore * MM_PER_M:.6g} mm, "
            f"its roller diameter d_w = {supports.bearing_roller_diameter_m * MM_PER_M:.4g} "
            "mm assumed (supports.bearing_roller_diameter_mm is not in the case)")
    hole = om.hole_radius_m if om.hole_radius_m is not None else (
        om.contact_radius_m + pair.centre_distance_m)
    return bore, DiscHolesSI(centre_bore_radius_m=bore, output_hole_count=om.pin_count,
                             output_hole_circle_radius_m=om.pin_hole_circle_radius_m,
                             output_hole_radius_m=hole), assumed


def _check_planet(planet_profile, holes: DiscHolesSI) -> None:
    """Every hole inside the planet's outline and apart from the others, or the error
    naming the keys that set them."""
    from shapely.geometry import Point, Polygon

    outline = Polygon(planet_profile.T)
    shapes = [(Point(x, y).buffer(r), label) for x, y, r, label in holes.circles()]
    for (shape, label), (x, y, r, _) in zip(shapes, holes.circles()):
        if not outline.contains(shape):
            raise CaseError(f"the planet's {label} hole reaches radius "
                            f"{(math.hypot(x, y) + r) * MM_PER_M:.4g} mm, outside the planet: "
                            "output_mechanism.pin_hole_circle_radius_mm, hole_radius_mm or "
                            "eccentric_bearing_inner_radius_mm too large")
    for i, (a, la) in enumerate(shapes):
        for b, lb in shapes[i + 1:]:
            if a.intersects(b):
                raise CaseError(f"the planet's holes {la} and {lb} overlap: "
                                "output_mechanism.pin_hole_circle_radius_mm, hole_radius_mm "
                                "or eccentric_bearing_inner_radius_mm")


def sine_parts(si, drive, points_per_tooth: int) -> PartDrawing:
    """The planet with its bore and output-pin holes, the output pins and the ring.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    points_per_tooth : int
        Samples per lobe or tooth.

    Returns
    -------
    toothfem.cad.PartDrawing
    """
    pair = drive.pair
    profiles, _ = drive.profiles(points_per_tooth)
    planet, ring = profiles["planet"], profiles["ring"]
    bore, holes, assumed = _planet_holes(si, drive)
    _check_planet(planet, holes)
    circles = tuple((x, y, r) for x, y, r, _ in holes.circles())
    centre, turn = sg.planet_pose(pair, 0.0)
    at = (centre[:, 0], float(turn[0]))
    rim = pair.ring_pitch_radius_m + sg.RING_RIM_MODULES * pair.module_m
    assumed["ring_outer_radius_mm"] = (
        f"the ring's rim, r2 + {sg.RING_RIM_MODULES} modules = {rim * MM_PER_M:.6g} mm "
        "(geometry.sine.RING_RIM_MODULES, as drawing.png and the FE model: the sine paper "
        "gives no housing)")
    assumed["ring_length_mm"] = (f"the pair's face width, {pair.face_width_m * MM_PER_M:.6g} "
                                 "mm (the ring's own width is not in the case)")
    bodies = [
        Body(layer="PLANET_PROFILE", description="the planet's tooth profile (at crank "
             "angle 0, its centre at (a0, 0))", polylines=(_placed(planet, *at),)),
        Body(layer="PLANET_HOLES", description="the planet's holes: the eccentric bearing's "
             "bore and the output pins' holes", circles=_placed_circles(circles, *at)),
    ]
    if drive.output_mechanism is not None:
        bodies.append(_pins_body(drive.output_mechanism,
                                 "the output pins in the planet's holes"))
    bodies.append(Body(layer="RING", description="the fixed ring: its tooth outline and rim",
                       polylines=(ring,), circles=((0.0, 0.0, rim),)))
    dims = {"planet_teeth": pair.planet_teeth, "ring_teeth": pair.ring_teeth,
            "module_mm": pair.module_m * MM_PER_M,
            "centre_distance_mm": pair.centre_distance_m * MM_PER_M,
            "planet_centre_mm": [_rounded(v * MM_PER_M) for v in centre[:, 0]],
            "face_width_mm": pair.face_width_m * MM_PER_M,
            "planet_bore_radius_mm": bore * MM_PER_M, "ring_outer_radius_mm": rim * MM_PER_M,
            "planet_holes_in_planet_frame": _listed(holes)}
    regions: tuple[Region, ...] = (
        Region(name="planet", outer=planet, holes=circles, thickness_m=pair.face_width_m),
        Region(name="ring", outer=(0.0, 0.0, rim), holes=(ring,),
               thickness_m=pair.face_width_m))
    if drive.output_mechanism is not None:
        regions += _output_pin_regions(drive.output_mechanism, pair.face_width_m)
    return PartDrawing(bodies=tuple(bodies), regions=regions, dimensions_mm=_tidy(dims),
                       assumed=assumed)




def part_drawing(case, points_per_tooth: int = 96, *, drive=None) -> PartDrawing:
    """The parts of a case's drive: the drawing's bodies and the STEP regions.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
        Anything with ``to_si()``.
    points_per_tooth : int
        Profile points per lobe or tooth (and per pin of the housing's bore), [8, 10000].
    drive : toothfem.fem.drives.Drive, optional
        The case's drive, if the caller has it (else ``drive_for(case)``).

    Returns
    -------
    toothfem.cad.PartDrawing
        Bodies in the housing frame [m], regions in their parts' frames [m], the
        dimensions [mm] and what is assumed (key -> reason).

    Raises
    ------
    CaseError
        If ``points_per_tooth`` is outside its range, or the planet's holes do not fit.
    GeometryError
        If the disc's holes or the pins do not fit (the drive's own checks).
    """
    check_range("points_per_tooth", points_per_tooth, 8, 10000, error=CaseError)
    si = si_of(case)
    drive = drive_for(si) if drive is None else drive
    return drive.layout.cad_parts(si, drive, int(points_per_tooth))
