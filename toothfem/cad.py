"""CAD files in millimetres: the working profiles (one closed polyline per file), the full
drawing of a drive's parts (one DXF layer and one SVG group per body) and STEP solids.

* :func:`write_dxf`, :func:`write_svg`: one profile, as ``toothfem geometry`` writes its CSV.
* :func:`write_drawing_dxf`, :func:`write_drawing_svg`: a :class:`PartDrawing` (the disc or
  planet with every hole, the pins, the housing or ring body; built by
  :func:`toothfem.cad_parts.part_drawing`), one layer or group per :class:`Body`.
* :func:`write_step`: one :class:`Region` extruded over its thickness, through the optional
  extra ``[cad]`` (the OCP wheel of cadquery, ``cadquery-ocp-novtk``).

Geometry is SI (m) in the records; the writers convert to mm. ezdxf and OCP are imported
inside their writers (seconds to import; only these writers need them).
"""
from __future__ import annotations

import importlib.util
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from . import signals
from .errors import MissingExtra, ToothfemError, shown
from .units import MM_PER_M   # profiles are SI (m) inside, CAD files in mm

#: SVG stroke width [mm] (thin enough for a 0.1 mm feature at 1:1).
SVG_STROKE_MM = 0.02
#: SVG margin around the profile [mm].
SVG_MARGIN_MM = 1.0
#: SVG stroke width of a full drawing [mm]: a fine pen line at 1:1 that still parts a pin
#: of 1 mm radius from its groove.
DRAWING_STROKE_MM = 0.1
#: The optional extra that brings the STEP writer's library, and its install line.
CAD_EXTRA = "cad"
CAD_EXTRA_INSTALL = "pip install 'toothfem[cad]'"
#: Each layer's colour: (SVG stroke, DXF AutoCAD colour index). Bodies told apart by colour
#: as well as by name; a layer not listed is drawn black (7).
LAYER_COLOURS = {
    "DISC_PROFILE": ("#1f77b4", 5), "DISC_HOLES": ("#2ca02c", 3),
    "PLANET_PROFILE": ("#1f77b4", 5), "PLANET_HOLES": ("#2ca02c", 3),
    "PINS": ("#d62728", 1), "OUTPUT_PINS": ("#ff7f0e", 30),
    "HOUSING": ("#555555", 8), "RING": ("#555555", 8),
}


@dataclass(frozen=True, kw_only=True)
class Body:
    """One body of a drawing: its closed outlines and circles in the drawing's frame (the
    housing's, the fixed member's centre at the origin), SI."""
    layer: str                       # DXF layer and SVG group id, e.g. "DISC_HOLES"
    description: str                 # what it is (SVG title, the summary's layer list)
    polylines: tuple = ()            # closed outlines, each (2, N) [m], no repeated end
    circles: tuple = ()              # (x [m], y [m], radius [m]) each


@dataclass(frozen=True, kw_only=True)
class Region:
    """A plane part to extrude along z for STEP, in its own frame (its centre at the
    origin): one outer boundary and the holes inside it, each a closed (2, N) polyline [m]
    or a circle (x [m], y [m], radius [m])."""
    name: str                        # the part, the STEP file's stem ("disc", "housing")
    outer: object
    holes: tuple = ()
    thickness_m: float = 0.0
    at: tuple = ()                   # (x [m], y [m]) of each copy (the pins: one solid
                                     # each in one file); empty: once, at its own origin


@dataclass(frozen=True, kw_only=True)
class PartDrawing:
    """The parts of a drive as a drawing (bodies) and as solids (regions), with the
    dimensions used [mm] and those that are not in the case (``assumed``: key -> reason)."""
    bodies: tuple                    # of Body, one layer / group each
    regions: tuple                   # of Region, one STEP file each
    dimensions_mm: dict = field(default_factory=dict)
    assumed: dict = field(default_factory=dict)


def _mm(points) -> np.ndarray:
    """(2, N) closed outline [m] -> (N, 2) [mm], the closing duplicate dropped."""
    xy = np.asarray(points, float).T * MM_PER_M
    if len(xy) > 1 and np.allclose(xy[0], xy[-1]):
        xy = xy[:-1]
    return xy


def write_dxf(path, points, layer: str = "PROFILE") -> Path:
    """One profile as a closed LWPOLYLINE in a DXF R2010 file, drawing units millimetres.

    Parameters
    ----------
    path : path
        The DXF file to write.
    points : (2, N) array
        Closed outline [m] (the last point may repeat the first).
    layer : str
        Layer name of the polyline.

    Returns
    -------
    Path
    """
    doc = _new_dxf()
    doc.layers.add(layer)
    doc.modelspace().add_lwpolyline(_mm(points), format="xy", close=True,
                                    dxfattribs={"layer": layer})
    path = Path(path)
    doc.saveas(path)
    return path


def _new_dxf():
    """An empty DXF R2010 document in millimetres ($INSUNITS = 4, metric)."""
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new("R2010")
    doc.units = units.MM                       # $INSUNITS = 4
    doc.header["$MEASUREMENT"] = 1             # metric
    return doc


def write_svg(path, points) -> Path:
    """One profile as a closed SVG path, 1 user unit = 1 mm, y up as in the CSV.

    Parameters
    ----------
    path : path
        The SVG file to write.
    points : (2, N) array
        Closed outline [m].

    Returns
    -------
    Path
    """
    xy = _mm(points)
    lo = xy.min(axis=0) - SVG_MARGIN_MM
    size = xy.max(axis=0) + SVG_MARGIN_MM - lo
    top = -(lo[1] + size[1])
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]:.4f}mm" '
           f'height="{size[1]:.4f}mm" viewBox="{lo[0]:.4f} {top:.4f} {size[0]:.4f} '
           f'{size[1]:.4f}">\n'
           f'  <path d="{_svg_path(xy)}" fill="none" stroke="black" '
           f'stroke-width="{SVG_STROKE_MM}"/>\n'
           "</svg>\n")
    path = Path(path)
    path.write_text(svg)
    return path


def _svg_path(xy) -> str:
    """A closed SVG path through (N, 2) points [mm], drawn at (x, -y): SVG's y points down,
    so the picture reads as the CSV."""
    return "M " + " L ".join(f"{x:.6f},{-y:.6f}" for x, y in xy) + " Z"


def _checked_drawing(drawing) -> PartDrawing:
    if not isinstance(drawing, PartDrawing) or not drawing.bodies:
        raise ToothfemError(f"drawing = {type(drawing).__name__} is not a PartDrawing with "
                            "bodies (toothfem.cad_parts.part_drawing builds one)")
    return drawing


def write_drawing_dxf(path, drawing: PartDrawing) -> Path:
    """The drawing as DXF R2010 in millimetres: one layer per body, each outline a closed
    LWPOLYLINE, each circle (hole, pin, outer edge) a CIRCLE.

    Parameters
    ----------
    path : path
        The DXF file to write.
    drawing : PartDrawing
        The bodies [m].

    Returns
    -------
    Path

    Raises
    ------
    ToothfemError
        If ``drawing`` is not a PartDrawing with bodies.
    """
    drawing = _checked_drawing(drawing)
    doc = _new_dxf()
    msp = doc.modelspace()
    for body in drawing.bodies:
        colour = LAYER_COLOURS.get(body.layer, ("#000000", 7))[1]
        doc.layers.add(body.layer, color=colour)
        attribs = {"layer": body.layer}
        for pts in body.polylines:
            msp.add_lwpolyline(_mm(pts), format="xy", close=True, dxfattribs=attribs)
        for x, y, r in body.circles:
            msp.add_circle((x * MM_PER_M, y * MM_PER_M), r * MM_PER_M, dxfattribs=attribs)
    path = Path(path)
    doc.saveas(path)
    return path


def _extent_mm(drawing: PartDrawing):
    """(lower left, upper right) [mm] of every outline and circle of the drawing."""
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for body in drawing.bodies:
        for pts in body.polylines:
            xy = _mm(pts)
            lo, hi = np.minimum(lo, xy.min(axis=0)), np.maximum(hi, xy.max(axis=0))
        for x, y, r in body.circles:
            c = np.array([x, y]) * MM_PER_M
            lo, hi = np.minimum(lo, c - r * MM_PER_M), np.maximum(hi, c + r * MM_PER_M)
    return lo, hi


def write_drawing_svg(path, drawing: PartDrawing) -> Path:
    """The drawing as SVG, 1 user unit = 1 mm, y up: one ``<g>`` per body, its ``id`` the
    body's layer, its ``<title>`` the body's description, each body in its own colour
    (:data:`LAYER_COLOURS`); outlines as closed paths, circles as ``<circle>``.

    Parameters
    ----------
    path : path
        The SVG file to write.
    drawing : PartDrawing
        The bodies [m].

    Returns
    -------
    Path

    Raises
    ------
    ToothfemError
        If ``drawing`` is not a PartDrawing with bodies.
    """
    drawing = _checked_drawing(drawing)
    lo, hi = _extent_mm(drawing)
    lo, size = lo - SVG_MARGIN_MM, hi - lo + 2 * SVG_MARGIN_MM
    top = -(lo[1] + size[1])
    lines = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]:.4f}mm" '
             f'height="{size[1]:.4f}mm" viewBox="{lo[0]:.4f} {top:.4f} {size[0]:.4f} '
             f'{size[1]:.4f}">',
             "  <desc>toothfem drawing: lengths in mm (1 user unit = 1 mm), y up (drawn as "
             "-y); one group per body, its id the DXF layer</desc>"]
    for body in drawing.bodies:
        colour = LAYER_COLOURS.get(body.layer, ("#000000", 7))[0]
        lines.append(f'  <g id="{escape(body.layer)}" class="body" fill="none" '
                     f'stroke="{colour}" stroke-width="{DRAWING_STROKE_MM}">')
        lines.append(f"    <title>{escape(body.description)}</title>")
        lines += [f'    <path d="{_svg_path(_mm(pts))}"/>' for pts in body.polylines]
        lines += [f'    <circle cx="{x * MM_PER_M:.6f}" cy="{-y * MM_PER_M:.6f}" '
                  f'r="{r * MM_PER_M:.6f}"/>' for x, y, r in body.circles]
        lines.append("  </g>")
    lines.append("</svg>\n")
    path = Path(path)
    path.write_text("\n".join(lines))
    return path


def step_available() -> bool:
    """Whether the STEP writer's library (the extra ``[cad]``: OCP) is installed.

    Returns
    -------
    bool
    """
    try:
        return importlib.util.find_spec("OCP") is not None
    except ValueError:            # sys.modules holds None for it: hidden, as if absent
        return False


def _ocp():
    """The OCP modules the STEP writer needs (their trace printing silenced), or the
    one-line error naming the extra."""
    try:
        # a signal during the extension's initialisation fails the import as an ImportError
        # (the probe: SIGTERM at 1.3 s of `run` ended "needs the extra", exit 2): only
        # noted until the import is done, then raised
        with signals.deferred():
            from OCP import (BRep, BRepBuilderAPI, BRepPrimAPI, GeomAPI, IFSelect,
                             Interface, Message, STEPControl, TopoDS, gp)
    except ImportError:
        raise MissingExtra(f"STEP needs the optional extra [{CAD_EXTRA}] (OCP, the "
                           f"cadquery-ocp-novtk wheel): {CAD_EXTRA_INSTALL}") from None
    try:                                   # OCP 8 keeps the arrays in OCP.collections
        from OCP.collections import HArray1_gp_Pnt as points
    except ImportError:                    # OCP 7.8, 7.9
        from OCP.TColgp import TColgp_HArray1OfPnt as points
    for printer in Message.Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message.Message_Gravity.Message_Fail)
    return dict(api=BRepBuilderAPI, prism=BRepPrimAPI, geomapi=GeomAPI, ifselect=IFSelect,
                interface=Interface, step=STEPControl, points=points, gp=gp, brep=BRep,
                topods=TopoDS)


#: A polyline turning by more than this at a point has a corner there [deg]: the STEP
#: writer's splines end at corners (the housing's bore meeting a pin's groove, ~90 deg)
#: and pass smoothly through the other points (a profile sampled at 96 points per tooth
#: turns by a few degrees from one point to the next).
CORNER_DEG = 20.0
#: Points of a spline closer than this are one point [mm] (OCP's interpolation refuses
#: them): far below a profile's point spacing (> 0.01 mm) and above its round-off.
SPLINE_SAME_POINT_MM = 1e-9


def corners(xy) -> np.ndarray:
    """Indices of the corners of a closed polyline: where it turns by more than
    :data:`CORNER_DEG`.

    Parameters
    ----------
    xy : (N, 2) array
        The closed polyline's points (any unit), the first not repeated.

    Returns
    -------
    numpy.ndarray of int
        Ascending point indices.
    """
    xy = np.asarray(xy, float)
    d_in = xy - np.roll(xy, 1, axis=0)
    d_out = np.roll(xy, -1, axis=0) - xy
    cross = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]
    turn = np.degrees(np.abs(np.arctan2(cross, np.einsum("ij,ij->i", d_in, d_out))))
    return np.flatnonzero(turn > CORNER_DEG)


def _spline(ocp, xy, periodic: bool):
    """An OCP edge [mm]: the C2 B-spline through (N, 2) points [mm] (periodic: closed,
    the first point not repeated), or a straight edge between two points."""
    gp = ocp["gp"]
    pts = [gp.gp_Pnt(float(x), float(y), 0.0) for x, y in xy]
    if len(pts) == 2 and not periodic:
        return ocp["api"].BRepBuilderAPI_MakeEdge(pts[0], pts[1]).Edge()
    arr = ocp["points"](1, len(pts))
    for i, p in enumerate(pts, start=1):
        arr.SetValue(i, p)
    fit = ocp["geomapi"].GeomAPI_Interpolate(arr, periodic, SPLINE_SAME_POINT_MM)
    fit.Perform()
    if not fit.IsDone():
        raise ToothfemError("OCP could not fit a spline through the outline's points")
    return ocp["api"].BRepBuilderAPI_MakeEdge(fit.Curve()).Edge()


def _wire(ocp, boundary, hole: bool):
    """An OCP wire [mm] of a circle (x, y, r) [m] (exact), or of a closed (2, N) polyline
    [m] as C2 splines through its points from corner to corner (:func:`corners`); a hole's
    runs clockwise seen from +z, the outer boundary counter-clockwise."""
    api, gp = ocp["api"], ocp["gp"]
    if isinstance(boundary, tuple) and len(boundary) == 3 and np.ndim(boundary[0]) == 0:
        x, y, r = (float(v) * MM_PER_M for v in boundary)
        axis = gp.gp_Ax2(gp.gp_Pnt(x, y, 0.0), gp.gp_Dir(0.0, 0.0, -1.0 if hole else 1.0))
        edge = api.BRepBuilderAPI_MakeEdge(gp.gp_Circ(axis, r)).Edge()
        return api.BRepBuilderAPI_MakeWire(edge).Wire()
    xy = _mm(boundary)
    x, y = xy.T
    if (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) > 0) == hole:
        xy = xy[::-1]
    wire = api.BRepBuilderAPI_MakeWire()
    cut = corners(xy)
    if cut.size == 0:
        wire.Add(_spline(ocp, xy, periodic=True))
    else:
        closed = np.roll(xy, -cut[0], axis=0)          # start at a corner ...
        closed = np.vstack([closed, closed[:1]])       # ... and end there
        ends = np.append(cut - cut[0], len(xy))
        for a, b in zip(ends[:-1], ends[1:]):          # corner to corner
            wire.Add(_spline(ocp, closed[a:b + 1], periodic=False))
    if not wire.IsDone():
        raise ToothfemError("OCP could not close the outline's wire")
    return wire.Wire()


def _copies(ocp, solid, at):
    """One compound of ``solid`` moved to each (x, y) [m] of ``at`` (a translation each)."""
    gp = ocp["gp"]
    compound = ocp["topods"].TopoDS_Compound()
    builder = ocp["brep"].BRep_Builder()
    builder.MakeCompound(compound)
    for x, y in at:
        move = gp.gp_Trsf()
        move.SetTranslation(gp.gp_Vec(float(x) * MM_PER_M, float(y) * MM_PER_M, 0.0))
        builder.Add(compound, ocp["api"].BRepBuilderAPI_Transform(solid, move, True).Shape())
    return compound


def write_step(path, region: Region) -> Path:
    """One part as a STEP AP214 solid in millimetres: the region's outer boundary less its
    holes (circles exact; polylines as C2 B-splines through their points from corner to
    corner, :func:`corners`) extruded from z = 0 over its thickness; with ``region.at``,
    one such solid at each of its points, in one compound (the pins). Needs the optional
    extra ``[cad]``.

    Parameters
    ----------
    path : path
        The STEP file to write.
    region : Region
        The part [m], its thickness > 0.

    Returns
    -------
    Path

    Raises
    ------
    MissingExtra
        Without the extra ``[cad]`` (one line naming it and its install command).
    ToothfemError
        If ``region`` is not a Region of positive thickness, or OCP fails to build or
        write the solid.
    """
    if not isinstance(region, Region):
        raise ToothfemError(f"region = {type(region).__name__} is not a toothfem.cad.Region")
    if not region.thickness_m > 0:
        raise ToothfemError(f"region.thickness_m = {region.thickness_m!r} must be > 0")
    ocp = _ocp()
    face = ocp["api"].BRepBuilderAPI_MakeFace(_wire(ocp, region.outer, hole=False), True)
    for hole in region.holes:
        face.Add(_wire(ocp, hole, hole=True))
    if not face.IsDone():
        raise ToothfemError(f"region {region.name!r}: OCP could not build its face")
    solid = ocp["prism"].BRepPrimAPI_MakePrism(
        face.Face(), ocp["gp"].gp_Vec(0.0, 0.0, region.thickness_m * MM_PER_M)).Shape()
    if region.at:
        solid = _copies(ocp, solid, region.at)
    step = ocp["step"]
    writer = step.STEPControl_Writer()          # registers the write.step.* settings
    static = ocp["interface"].Interface_Static
    static.SetCVal_s("write.step.unit", "MM")
    static.SetCVal_s("write.step.schema", "AP214IS")
    static.SetCVal_s("write.step.product.name", region.name)
    writer.Transfer(solid, step.STEPControl_AsIs)
    path = Path(path)
    try:
        str(path).encode("utf-8")
        direct = True
    except UnicodeEncodeError:   # bytes of another locale: OCP takes only UTF-8 names
        direct = False
    with tempfile.TemporaryDirectory(prefix="toothfem-step-") as scratch:
        into = path if direct else Path(scratch) / "part.step"
        if writer.Write(str(into)) != ocp["ifselect"].IFSelect_RetDone:
            raise ToothfemError(f"{shown(path)}: OCP could not write the STEP file")
        if not direct:
            shutil.move(into, path)
    return path
