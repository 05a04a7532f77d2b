"""Drawings (matplotlib, off-screen). Each function takes data, returns the figure and never
calls show(); matplotlib is imported here only, so ``import toothfem`` stays light."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import pyplot
from ..geometry import cycloid_mesh as cym, sine
from ..geometry.disc import disc_polygon
from ..units import MM_PER_M


def _draw_polygon(ax, poly, scale=MM_PER_M, **kw):
    x, y = poly.exterior.xy
    ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, **kw)
    for ring in poly.interiors:
        x, y = ring.xy
        ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, color="white", lw=0.5,
                ec=kw.get("ec", "k"))


def cycloid_drawing(geom, holes, crank_angle_rad=0.0, title="", case_name=""):
    """Disc with holes placed at a crank angle among its pins, the loaded pins' contact
    normals meeting at the pitch point (+); right: close-up of the pin circle 90 deg ahead
    of the crank with those normals (the pitch point, inside the pin circle, is outside it).

    Parameters
    ----------
    geom : toothfem.geometry.cycloid.CycloidGeometry
        The disc and pin ring.
    holes : toothfem.geometry.disc.DiscHolesSI
        The disc's holes.
    crank_angle_rad : float
        Crank angle [rad].
    title : str
        The figure's title; default: the dimensions.
    case_name : str
        Named in the default title.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels, lengths in mm.
    """
    from shapely import affinity


    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.3), layout="constrained")
    disc = disc_polygon(geom, holes)
    centre, rot = cym.disc_pose(geom, crank_angle_rad)
    placed = affinity.translate(affinity.rotate(disc, float(rot[0]), origin=(0, 0),
                                                use_radians=True), *centre[:, 0])
    m = cym.meshing(geom, crank_angle_rad)
    pins = cym.pin_centres(geom)
    t = np.linspace(0, 2 * math.pi, 60)
    for ax in axes:
        _draw_polygon(ax, placed, color="#9ecae1", ec="k", lw=0.5)
        for i in range(geom.pin_count):
            loaded = m.moment_arm[0, i] < 0
            ax.fill((pins[0, i] + geom.pin_radius_m * np.cos(t)) * MM_PER_M,
                    (pins[1, i] + geom.pin_radius_m * np.sin(t)) * MM_PER_M,
                    color="#d62728" if loaded else "#7f7f7f", alpha=0.8)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
    pitch = geom.pin_pitch_radius_m * np.array([math.cos(crank_angle_rad),
                                                math.sin(crank_angle_rad)])
    for j in np.flatnonzero(m.moment_arm[0] < 0):
        pt = m.point[0, j]
        for ax in axes:
            ax.plot([pt[0] * MM_PER_M, pitch[0] * MM_PER_M],
                    [pt[1] * MM_PER_M, pitch[1] * MM_PER_M], "k-", lw=0.4)
    axes[0].plot(*pitch * MM_PER_M, "k+", ms=12, mew=1.6)
    r = geom.pin_circle_radius_m * MM_PER_M
    a0 = crank_angle_rad + math.pi / 2
    cx, cy_ = r * math.cos(a0), r * math.sin(a0)
    w = 0.18 * r
    axes[1].set_xlim(cx - w, cx + w)
    axes[1].set_ylim(cy_ - w, cy_ + w)
    fig.suptitle(title or (
        f"Cycloid disc ({geom.lobe_count} lobes) in {geom.pin_count} pins: pin circle "
        f"radius {geom.pin_circle_radius_m * MM_PER_M:g} mm, eccentricity "
        f"{geom.eccentricity_m * MM_PER_M:g} mm, pin radius {geom.pin_radius_m * MM_PER_M:g} mm; crank "
        f"angle {math.degrees(crank_angle_rad):.1f} deg" + (f"\n{case_name}" if case_name
                                                            else "")),
        fontsize=10, x=0.01, ha="left")
    axes[0].set_title("disc among its pins (red: loaded; lines: their normals, through the "
                      "pitch point +)", fontsize=9)
    axes[1].set_title("close-up 90 deg from the crank: loaded pins' normals, toward the pitch "
                      "point (+, left)", fontsize=9)
    return fig


def sine_drawing(pair, crank_angle_rad=0.0, title="", case_name=""):
    """Planet inside the ring at a crank angle; right: close-up at the pitch point.

    Parameters
    ----------
    pair : toothfem.geometry.sine.SineGearPair
        The pair.
    crank_angle_rad : float
        Crank angle chi [rad] placing the planet.
    title : str
        Overrides the title (tooth numbers, module, tooth height).
    case_name : str
        A second line of the default title.

    Returns
    -------
    matplotlib.figure.Figure
        Whole pair and close-up [mm].
    """
    from shapely import affinity


    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.3), layout="constrained")
    ring = sine.ring_polygon(pair)
    planet = sine.planet_polygon(pair)
    rot = -crank_angle_rad * (pair.ring_teeth - pair.planet_teeth) / pair.planet_teeth
    a0 = pair.centre_distance_m
    placed = affinity.translate(affinity.rotate(planet, rot, origin=(0, 0), use_radians=True),
                                a0 * math.cos(crank_angle_rad), a0 * math.sin(crank_angle_rad))
    for ax in axes:
        _draw_polygon(ax, ring, color="#bdbdbd", ec="k", lw=0.4)
        _draw_polygon(ax, placed, color="#9ecae1", ec="k", lw=0.4)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
    r2 = pair.ring_pitch_radius_m * MM_PER_M
    px, py = r2 * math.cos(crank_angle_rad), r2 * math.sin(crank_angle_rad)
    w = 4 * pair.module_m * MM_PER_M
    axes[1].set_xlim(px - w, px + w)
    axes[1].set_ylim(py - w, py + w)
    axes[1].plot(px, py, "k+", ms=10)
    fig.suptitle(title or (
        f"Sine-profile pair: planet {pair.planet_teeth} teeth in ring {pair.ring_teeth} teeth, "
        f"module {pair.module_m * MM_PER_M:g} mm, tooth height {pair.tooth_height_m * MM_PER_M:g} mm, "
        f"centre distance {a0 * MM_PER_M:g} mm; crank angle {math.degrees(crank_angle_rad):.1f} deg"
        + (f"\n{case_name}" if case_name else "")), fontsize=10, x=0.01, ha="left")
    axes[0].set_title("planet (blue) in the fixed ring (grey)", fontsize=9)
    axes[1].set_title("close-up at the pitch point (+)", fontsize=9)
    return fig


@dataclass(frozen=True, kw_only=True)
class Marked:
    """A point drawn over a chart: where, and what it is (``kind`` picks its marker)."""
    x: float
    y: float                       # efficiency as a fraction, or the chart's y unit
    label: str
    kind: str = "measured"         # "measured" | "published" | "operating"


#: Marker style of each kind of marked point (told apart in colour and shape; none of
#: their colours is a line's, LINE_COLOURS).
MARKERS = {"measured": dict(marker="o", color="k", ms=7, ls="none", zorder=5),
           "published": dict(marker="s", mfc="none", mec="#d62728", mew=1.8, ms=9, ls="none",
                             zorder=5),
           "operating": dict(marker="*", color="#ffd700", mec="k", mew=1.4, ms=15, ls="none",
                             zorder=6)}
#: Colours of the curves of a chart with marked points, in order: none of them a marker's
#: (black, red, gold) nor close to one (orange).
LINE_COLOURS = ("#1f77b4", "#2ca02c", "#9467bd", "#17becf", "#8c564b", "#e377c2", "#7f7f7f")
#: A curve within this fraction of the chart's span of an earlier one everywhere is drawn
#: dashed on top of it (both seen where they coincide).
OVERLAP_FRACTION = 0.01


#: Margin kept between a marked point and the axes' edge, a fraction of the axis span.
MARK_MARGIN = 0.04


def _include(ax, points) -> None:
    """Widen the axes' limits (never narrow them) so each point lies inside, MARK_MARGIN
    of the span from the edge: a marked point is never cut by the frame."""
    for axis, get, put in ((0, ax.get_xlim, ax.set_xlim), (1, ax.get_ylim, ax.set_ylim)):
        lo, hi = get()
        vals = [p[axis] for p in points if np.isfinite(p[axis])]
        if not vals:
            continue
        pad = MARK_MARGIN * (max(hi, *vals) - min(lo, *vals))
        put(min(lo, min(vals) - pad), max(hi, max(vals) + pad))


def efficiency_vs_torque(torque, curves: dict, marked=(), title="", dashed=()):
    """Efficiency [%] against output torque [N m].

    Parameters
    ----------
    torque : (N,) array
        Output torque [N m].
    curves : dict
        Label -> (N,) efficiency (fraction).
    marked : sequence of Marked
        Measured points, a paper's figures and the operating point (efficiency as fractions).
    title : str
    dashed : sequence of str
        Labels of ``curves`` drawn dash-dotted (e.g. another speed).

    Returns
    -------
    matplotlib.figure.Figure
        The curves (LINE_COLOURS; one that lies on an earlier one dashed on top of it), the
        points told apart by marker, in colours no line has, the legend beside the axes.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 5.2), layout="constrained")
    pct = {label: 100 * np.asarray(eta, float) for label, eta in curves.items()}
    for i, (label, style) in enumerate(curve_styles(pct, dashed).items()):
        ax.plot(torque, pct[label], lw=1.8, color=LINE_COLOURS[i % len(LINE_COLOURS)],
                zorder=2 + 0.1 * i, label=label, **style)
    for m in marked:
        ax.plot(m.x, 100 * m.y, label=m.label, **MARKERS[m.kind])
    ax.set_xlabel("output torque [N m]")
    ax.set_ylabel("efficiency [%]")
    ax.set_xlim(left=0)
    _include(ax, [(m.x, 100 * m.y) for m in marked])
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_title(title, loc="left", fontsize=10)
    return fig


def curve_styles(curves: dict, dashed=()) -> dict:
    """The line style of each curve: solid; dash-dotted if named in ``dashed``; dashed
    where it lies within OVERLAP_FRACTION of the chart's span of an earlier curve
    everywhere (drawn on top of it, so both show where they coincide).

    Parameters
    ----------
    curves : dict
        Label -> (N,) values, on one grid.
    dashed : sequence of str
        Labels drawn dash-dotted.

    Returns
    -------
    dict
        Label -> {"ls": style}.
    """
    vals = [np.asarray(v, float) for v in curves.values()]
    finite = np.concatenate([v[np.isfinite(v)] for v in vals]) if vals else np.array([])
    span = float(np.ptp(finite)) if finite.size else 0.0
    styles = {}
    for i, (label, v) in enumerate(curves.items()):
        lies_on = any(np.nanmax(np.abs(v - w)) <= OVERLAP_FRACTION * span
                      for w in vals[:i]) if i else False
        styles[label] = {"ls": "-." if label in dashed else (0, (5, 3)) if lies_on
                         else "-"}
    return styles


#: Iso-efficiency lines of a map: at these quantiles of the map's values, so the lines
#: spread over the area (a map is mostly a plateau with a steep edge at low torque).
ISO_QUANTILES = np.linspace(5, 95, 8)
#: Most labelled iso-lines (more crowd the steep edge).
MAX_ISO_LABELS = 6


def _iso_levels(pct) -> np.ndarray:
    """Round iso-efficiency levels [%]: whole percent, or half percent on a flat map."""
    q = np.nanpercentile(pct, ISO_QUANTILES)
    for step in (1.0, 0.5, 0.1):
        levels = np.unique(np.round(q / step) * step)
        if len(levels) >= 4:
            return levels
    return levels


def efficiency_map(x, y, eta, xlabel, ylabel, title="", marked=()):
    """Catalogue-style efficiency chart: filled contours of efficiency [%] over a grid,
    labelled iso-lines, and marked points (the operating point, measured points).

    Parameters
    ----------
    x, y : (M, N) arrays
        The grid (e.g. output torque [N m], input speed [rpm]).
    eta : (M, N) array
        Efficiency (fraction).
    xlabel, ylabel, title : str
    marked : sequence of Marked
        Points over the map (their ``y`` in the map's y unit).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9.5, 5.8), layout="constrained")
    pct = 100 * np.asarray(eta)
    cs = ax.contourf(x, y, pct, levels=24, cmap="viridis")
    levels = _iso_levels(pct)
    lines = ax.contour(x, y, pct, levels=levels, colors="k", linewidths=0.6)
    k = max(1, int(np.ceil(len(levels) / MAX_ISO_LABELS)))
    ax.clabel(lines, levels=lines.levels[::-k], fmt="%g %%", fontsize=8, inline=True,
              inline_spacing=4)
    fig.colorbar(cs, ax=ax, label="efficiency [%]", pad=0.02)
    for m in marked:
        ax.plot(m.x, m.y, label=m.label, **MARKERS[m.kind])
    _include(ax, [(m.x, m.y) for m in marked])
    if marked:
        fig.legend(loc="outside lower center", fontsize=8, frameon=False, ncol=len(marked))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, loc="left", fontsize=10)
    return fig


def share_text(pct: float) -> str:
    """A loss share's value label [%]: three significant figures (11.5, 6.53, 0.0503; a
    paper's 3.55 as it gives it), "0" for none, "" for a missing one.

    Parameters
    ----------
    pct : float
        The share [% of input power].

    Returns
    -------
    str
    """
    if not np.isfinite(pct):
        return ""
    if pct == 0:
        return "0"
    # three figures move a share of 1 to 100 % by at most 0.05 points (11.49 and 11.51
    # both 11.5, not 11 and 12), a smaller one by at most 0.5 % of itself
    return f"{pct:#.3g}".rstrip(".")


#: The published shares' bars: hatched and outlined (a paper's figures, not ours).
PUBLISHED_BARS = dict(color="white", edgecolor="#d62728", hatch="///", lw=1.0)
#: Headroom above the tallest bar, a fraction of it, for its upright value label.
LABEL_HEADROOM = 0.16


def loss_shares(labels, shares: dict, title="", published=None):
    """Grouped bars: loss shares [% of input power] per component, one group per source.

    Parameters
    ----------
    labels : sequence of str
        Loss components.
    shares : dict
        Source (e.g. "analytic", "fem", a paper's method) -> {component: share of input
        power}.
    title : str
    published : dict, optional
        The case's published shares {component: share} (its ``[published]`` keys
        ``loss_share_<component>``): one more, hatched group; a component of ours not
        among them has no bar there, one of theirs not among ours gets its own place.

    Returns
    -------
    matplotlib.figure.Figure
        The bars with their values upright above them (three significant figures):
        labels of neighbouring bars never overlap.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 4.8), layout="constrained")
    groups = dict(shares)
    if published:
        labels = list(labels) + [n for n in published if n not in labels]
        groups["published (the case's paper)"] = dict(published)
    k = len(groups)
    width = 0.8 / max(k, 1)
    x = np.arange(len(labels))
    top = 0.0
    for i, (src, vals) in enumerate(groups.items()):
        pct = np.array([100 * vals.get(n, np.nan) for n in labels], float)
        style = PUBLISHED_BARS if published and i == k - 1 else {}
        bars = ax.bar(x + (i - (k - 1) / 2) * width, pct, width, label=src, **style)
        ax.bar_label(bars, labels=[share_text(v) for v in pct], fontsize=7, padding=2,
                     rotation=90)
        if np.any(np.isfinite(pct)):
            top = max(top, float(np.nanmax(pct)))
    ax.set_ylim(0, (1 + LABEL_HEADROOM) * top if top > 0 else 1.0)
    ours = {n for vals in shares.values() for n in vals}
    ax.set_xticks(x, [n.replace("_", " ") + ("" if n in ours else "\n(published only)")
                      for n in labels], rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("loss [% of input power]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False,
              title="loads / method", title_fontsize=8)
    ax.set_title(title, loc="left", fontsize=10)
    return fig


#: The bodies of a part drawing the pair's own drawing leaves out, drawn over it by
#: :func:`drawing` (the profiles, the pin ring and the ring are the pair's own).
OVERLAID = ("DISC_HOLES", "PLANET_HOLES", "OUTPUT_PINS", "HOUSING")
#: Each overlaid body's look: holes white with their outline, pins filled, the housing's
#: outlines only.
OVERLAY_COLOURS = {"DISC_HOLES": "#2ca02c", "PLANET_HOLES": "#2ca02c",
                   "OUTPUT_PINS": "#ff7f0e", "HOUSING": "#555555"}


def draw_parts(ax, parts) -> list:
    """The bodies of ``parts`` the pair's drawing leaves out (:data:`OVERLAID`: the holes,
    the output pins with their rollers, the housing) over ``ax`` [mm], as the DXF and SVG
    hold them.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    parts : toothfem.cad.PartDrawing

    Returns
    -------
    list
        A legend handle per body drawn, labelled with its layer and description.
    """
    from matplotlib.patches import Patch

    t = np.linspace(0, 2 * math.pi, 90)
    handles = []
    for body in parts.bodies:
        if body.layer not in OVERLAID:
            continue
        colour = OVERLAY_COLOURS[body.layer]
        for x, y, r in sorted(body.circles, key=lambda c: -c[2]):    # rollers under pins
            cx, cy_ = (x + r * np.cos(t)) * MM_PER_M, (y + r * np.sin(t)) * MM_PER_M
            if body.layer.endswith("HOLES"):
                ax.fill(cx, cy_, color="white", ec=colour, lw=0.8, zorder=3)
            elif body.layer == "OUTPUT_PINS":
                ax.fill(cx, cy_, color=colour, ec="k", lw=0.4, alpha=0.75, zorder=4)
            else:
                ax.plot(cx, cy_, color=colour, lw=0.8, zorder=0.5)
        for xy in body.polylines:
            ax.plot(*np.vstack([xy.T, xy[:, :1].T]).T * MM_PER_M, color=colour, lw=0.6,
                    zorder=0.5)
        filled = body.layer != "HOUSING"
        handles.append(Patch(facecolor=colour if body.layer == "OUTPUT_PINS" else "white",
                             edgecolor=colour, fill=filled,
                             label=f"{body.layer}: {body.description}"))
    return handles


def drawing(drive, case_name="", parts=None):
    """The drawing of a drive's pair, its layout's (``Layout.drawing``: :func:`cycloid_drawing`
    or :func:`sine_drawing`), titled with its dimensions and ``case_name``.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        A cycloid or sine drive.
    case_name : str
        Named in the title.
    parts : toothfem.cad.PartDrawing, optional
        The drive's parts (:func:`toothfem.cad_parts.part_drawing`): their holes, output
        pins and housing drawn over the pair (:func:`draw_parts`), as the DXF and SVG.

    Returns
    -------
    matplotlib.figure.Figure
        The drawing.
    """
    fig = drive.layout.drawing(drive, case_name)
    if parts is not None:
        handles = []
        for ax in fig.axes:
            handles = draw_parts(ax, parts)
        if handles:
            fig.legend(handles=handles, loc="outside lower center", fontsize=8, ncol=2,
                       frameon=False)
    return fig
