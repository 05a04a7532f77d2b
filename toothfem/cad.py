"""Tooth profiles for CAD: DXF (closed LWPOLYLINE, millimetres) and SVG (closed path,
millimetres), one file per profile as ``toothfem geometry`` writes its CSV.

ezdxf is imported inside :func:`write_dxf` (seconds to import; only this writer needs it).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

#: Millimetres per metre: profiles are SI (m) inside, CAD files in mm.
MM_PER_M = 1e3
#: SVG stroke width [mm] (thin enough for a 0.1 mm feature at 1:1).
SVG_STROKE_MM = 0.02
#: SVG margin around the profile [mm].
SVG_MARGIN_MM = 1.0


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
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new("R2010")
    doc.units = units.MM                       # $INSUNITS = 4
    doc.header["$MEASUREMENT"] = 1             # metric
    doc.layers.add(layer)
    doc.modelspace().add_lwpolyline(_mm(points), format="xy", close=True,
                                    dxfattribs={"layer": layer})
    path = Path(path)
    doc.saveas(path)
    return path


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
    # SVG's y axis points down: draw (x, -y) so the picture reads as the CSV
    d = "M " + " L ".join(f"{x:.6f},{-y:.6f}" for x, y in xy) + " Z"
    top = -(lo[1] + size[1])
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]:.4f}mm" '
           f'height="{size[1]:.4f}mm" viewBox="{lo[0]:.4f} {top:.4f} {size[0]:.4f} '
           f'{size[1]:.4f}">\n'
           f'  <path d="{d}" fill="none" stroke="black" stroke-width="{SVG_STROKE_MM}"/>\n'
           "</svg>\n")
    path = Path(path)
    path.write_text(svg)
    return path
