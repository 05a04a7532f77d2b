"""Pictures of stress fields: a nodal field of a VTU file (von Mises [MPa] on points in mm,
:mod:`toothfem.fem.export`) as a PNG in the member's frame, a whole member or a close-up of
a contact, with its colour scale's top chosen by area and the fixed member's outlines
(matplotlib, off-screen; nothing is shown on screen).
"""
from __future__ import annotations

import numpy as np

from ..errors import ToothfemError
from . import pyplot, save, wrap
from ..units import MM_PER_M, PA_PER_MPA

#: Colour map of stress fields (perceptually ordered, unlike jet).
FIELD_CMAP = "turbo"
#: The whole member's colour scale ends at this percentile of the field by area, the rest
#: saturated (marked on the colour bar): the body's stress readable beside the contact peaks.
FIELD_PERCENTILE = 99.0
#: Characters per title line of a field picture (9 in wide at 9 pt).
FIELD_TITLE_CHARS = 112


def _field_mm_MPa(mesh, scalar: str):
    """(x [mm], y [mm], values [MPa]) of a VTU's stress field ``scalar`` (named with its
    unit, ``_MPa``, the points in mm: :mod:`toothfem.fem.export`); a file written before
    the units went into the names holds ``von_mises`` in Pa on points in m."""
    points = np.asarray(mesh.points, float)
    if scalar in mesh.point_data:
        return points[:, 0], points[:, 1], np.asarray(mesh.point_data[scalar], float)
    legacy = scalar.removesuffix("_MPa")
    if legacy != scalar and legacy in mesh.point_data:
        return (points[:, 0] * MM_PER_M, points[:, 1] * MM_PER_M,
                np.asarray(mesh.point_data[legacy], float) / PA_PER_MPA)
    raise ToothfemError(f"scalar = {scalar!r} is not a field of the VTU (its fields: "
                        f"{sorted(mesh.point_data)})")


def robust_max(tri, value, percentile: float = FIELD_PERCENTILE) -> float:
    """The colour scale's top of a whole-member field: the FIELD_PERCENTILE-th percentile
    of the triangles' mean values weighted by their area (the contact spots' peaks, a
    small area on a fine mesh, would otherwise darken the whole body).

    Parameters
    ----------
    tri : matplotlib.tri.Triangulation
    value : numpy.ndarray
        Nodal values.
    percentile : float
        The percentile [%] (a close-up's: CLOSE_UP_PERCENTILE).

    Returns
    -------
    float
        The percentile (the largest value where it is not positive).
    """
    t = tri.triangles
    x, y = tri.x[t], tri.y[t]
    area = 0.5 * np.abs((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0])
                        - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
    mean = value[t].mean(axis=1)
    order = np.argsort(mean)
    cum = np.cumsum(area[order])
    at = np.searchsorted(cum, percentile / 100 * cum[-1])
    top = float(mean[order][min(at, mean.size - 1)])
    return top if top > 0 else float(value.max())


#: Mesh edges of a close-up: thin and faint, so a densely refined contact zone shows its
#: field, not a black patch.
MESH_EDGES = dict(color="k", lw=0.1, alpha=0.22)
#: Margin around a whole member's view, a fraction of its span (beyond the outlines).
FIELD_MARGIN = 0.03
#: A close-up's colour scale ends at this percentile by area of the triangles in its view:
#: a peak on a few sub-pixel elements at the contact's edge is saturated (its value said on
#: the colour bar and its place marked), not the top of a scale the view never shows.
CLOSE_UP_PERCENTILE = 99.9
#: Marker of the largest value in a close-up's view.
VIEW_MAX_MARKER = dict(marker="^", ms=7, mfc="none", mec="w", mew=1.6, ls="none")


def view_max(tri, value, xlim, ylim) -> tuple:
    """The largest value at the triangles' nodes inside a view, and where it is.

    Parameters
    ----------
    tri : matplotlib.tri.Triangulation
    value : numpy.ndarray
        Nodal values.
    xlim, ylim : (float, float)
        The view's limits.

    Returns
    -------
    (float, (float, float)) or (None, None)
        The largest value at the triangles' nodes inside the view (what the view shows:
        nodes of no triangle are not drawn), and that node's (x, y); None where no node
        is inside.
    """
    nodes = np.unique(tri.triangles)
    x, y = tri.x[nodes], tri.y[nodes]
    nodes = nodes[(x >= xlim[0]) & (x <= xlim[1]) & (y >= ylim[0]) & (y <= ylim[1])]
    if nodes.size == 0:
        return None, None
    top = nodes[np.argmax(value[nodes])]
    return float(value[top]), (float(tri.x[top]), float(tri.y[top]))


def field_limits(tri, outlines=()) -> tuple:
    """The limits [mm] of a whole member's view: the mesh and the outlines (a pin drawn
    beyond the member is not cut), FIELD_MARGIN of the span around them.

    Parameters
    ----------
    tri : matplotlib.tri.Triangulation
        The member [mm].
    outlines : sequence of (2, N) arrays
        The fixed member's outlines [m].

    Returns
    -------
    ((float, float), (float, float))
        x and y limits [mm].
    """
    xs = [np.asarray(tri.x, float)] + [np.asarray(o, float)[0] * MM_PER_M for o in outlines]
    ys = [np.asarray(tri.y, float)] + [np.asarray(o, float)[1] * MM_PER_M for o in outlines]
    lims = []
    for v in (np.concatenate(xs), np.concatenate(ys)):
        lo, hi = float(v.min()), float(v.max())
        pad = FIELD_MARGIN * (hi - lo)
        lims.append((lo - pad, hi + pad))
    return tuple(lims)


def field_png(vtu_path, png_path, *, title, scalar="von_mises_MPa", outlines=(),
              zoom_centre=None, zoom_radius=None, mark=None, marks=()):
    """A nodal field of a VTU file as a PNG: filled triangles in the member's frame [mm],
    with a colour bar and the fixed member's outlines.

    Parameters
    ----------
    vtu_path, png_path : path
    title : str
        Says which field this is (structural or contact-resolved) and for which load.
    scalar : str
        Point-data name of a stress [MPa] (:mod:`toothfem.fem.export`: ``von_mises_MPa``).
    outlines : sequence of (2, N) arrays
        Closed outlines [m] in the member's frame drawn over the field (pins, ring teeth).
    zoom_centre : (2,) array, optional
        Centre [m] of a close-up of half-width ``zoom_radius`` [m] (mesh edges drawn).
    mark : (2,) array, optional
        A point [m] marked with a cross (the most loaded contact).
    marks : sequence of ((2,) array, str)
        Further points [m], each with its marker ("x" or "+"), e.g. the contact with the
        largest P_h and the one with the largest force.

    Returns
    -------
    path
        ``png_path``. A whole member's view takes in the outlines; its colour scale ends
        at FIELD_PERCENTILE by area. A close-up's ends at CLOSE_UP_PERCENTILE by area of
        the triangles in its view, the view's largest value said and marked (open
        triangle); its mesh edges faint.
    """
    import meshio
    from matplotlib.tri import Triangulation

    plt = pyplot()
    mesh = meshio.read(str(vtu_path))
    x_mm, y_mm, value = _field_mm_MPa(mesh, scalar)
    tri = Triangulation(x_mm, y_mm, mesh.cells_dict["triangle"])
    fig, ax = plt.subplots(figsize=(9, 7.5), layout="constrained")
    top_at = None
    if zoom_centre is not None:
        x0, y0 = np.asarray(zoom_centre, float) * MM_PER_M
        r = float(zoom_radius) * MM_PER_M
        xlim, ylim = (x0 - r, x0 + r), (y0 - r, y0 + r)
        peak, top_at = view_max(tri, value, xlim, ylim)
        if peak is None or peak <= 0:
            peak, top_at = float(value.max()), None
        cx, cy = tri.x[tri.triangles].mean(axis=1), tri.y[tri.triangles].mean(axis=1)
        shown = ((cx >= xlim[0]) & (cx <= xlim[1]) & (cy >= ylim[0]) & (cy <= ylim[1]))
        vmax = (robust_max(Triangulation(x_mm, y_mm, tri.triangles[shown]), value,
                           CLOSE_UP_PERCENTILE) if np.any(shown) else peak)
        vmax = peak if not 0 < vmax <= peak else vmax
        scale = f"this view's {CLOSE_UP_PERCENTILE:g}th percentile by area"
    else:
        xlim, ylim = field_limits(tri, outlines)
        vmax, peak = robust_max(tri, value), float(value.max())
        scale = f"{FIELD_PERCENTILE:g}th percentile by area"
    saturated = peak > vmax * (1 + 1e-9)
    art = ax.tripcolor(tri, value, shading="gouraud", cmap=FIELD_CMAP, vmin=0.0, vmax=vmax)
    if zoom_centre is not None:
        ax.triplot(tri, **MESH_EDGES)
    for o in outlines:           # lines, not fills: a ring's outline encloses the member
        xy = np.asarray(o, float) * MM_PER_M
        ax.plot(np.append(xy[0], xy[0, 0]), np.append(xy[1], xy[1, 0]), color="0.25",
                lw=0.8)
    for point, marker in ([(mark, "x")] if mark is not None else []) + list(marks):
        x, y = np.asarray(point, float) * MM_PER_M
        ax.plot(x, y, marker, color="w", ms=11, mew=3.5)
        ax.plot(x, y, marker, color="k", ms=9, mew=1.5)
    if top_at is not None:
        ax.plot(*top_at, **VIEW_MAX_MARKER)
        ax.plot(*top_at, **{**VIEW_MAX_MARKER, "mec": "k", "mew": 0.8})
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (member frame)")
    ax.set_ylabel("y [mm]")
    bar = fig.colorbar(art, ax=ax, shrink=0.85, extend="max" if saturated else "neither")
    largest = ("its largest" if zoom_centre is not None else "largest") + f" {peak:.4g} MPa" \
        + (" (open triangle)" if top_at is not None else "")
    bar.set_label(f"{scalar.removesuffix('_MPa').replace('_', ' ')} stress [MPa]"
                  + (" (colour scale of this view)" if zoom_centre is not None else "")
                  + (f"\nsaturated above {vmax:.4g} MPa ({scale})\n{largest}" if saturated
                     else f"\n{largest}" if zoom_centre is not None else ""))
    ax.set_title(wrap(title, FIELD_TITLE_CHARS), loc="left", fontsize=9)
    return save(fig, png_path)
