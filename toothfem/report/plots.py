"""Drawings (matplotlib, off-screen). Each function takes data, returns the figure and never
calls show(); matplotlib is imported here only, so ``import toothfem`` stays light."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import pyplot
from ..geometry import cycloid_mesh as cym, sine
from ..geometry.disc import disc_polygon


def _draw_polygon(ax, poly, scale=1e3, **kw):
    x, y = poly.exterior.xy
    ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, **kw)
    for ring in poly.interiors:
        x, y = ring.xy
        ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, color="white", lw=0.5,
                ec=kw.get("ec", "k"))


def cycloid_drawing(geom, holes, crank_angle_rad=0.0, title="", case_name=""):
    """Disc with holes placed at a crank angle among its pins; right: close-up of the
    loaded zone with the contact normals through the pitch point.

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
        for j in range(geom.pin_count):
            loaded = m.moment_arm[0, j] < 0
            ax.fill((pins[0, j] + geom.pin_radius_m * np.cos(t)) * 1e3,
                    (pins[1, j] + geom.pin_radius_m * np.sin(t)) * 1e3,
                    color="#d62728" if loaded else "#7f7f7f", alpha=0.8)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
    pitch = geom.pin_pitch_radius_m * np.array([math.cos(crank_angle_rad),
                                                math.sin(crank_angle_rad)])
    for j in np.flatnonzero(m.moment_arm[0] < 0):
        k = m.point[0, j]
        axes[1].plot([k[0] * 1e3, pitch[0] * 1e3], [k[1] * 1e3, pitch[1] * 1e3], "k-", lw=0.4)
    axes[1].plot(*pitch * 1e3, "k+", ms=10)
    r = geom.pin_circle_radius_m * 1e3
    a0 = crank_angle_rad + math.pi / 2
    cx, cy_ = r * math.cos(a0), r * math.sin(a0)
    w = 0.18 * r
    axes[1].set_xlim(cx - w, cx + w)
    axes[1].set_ylim(cy_ - w, cy_ + w)
    fig.suptitle(title or (
        f"Cycloid disc ({geom.lobe_count} lobes) in {geom.pin_count} pins: pin circle "
        f"radius {geom.pin_circle_radius_m * 1e3:g} mm, eccentricity "
        f"{geom.eccentricity_m * 1e3:g} mm, pin radius {geom.pin_radius_m * 1e3:g} mm; crank "
        f"angle {math.degrees(crank_angle_rad):.1f} deg" + (f"\n{case_name}" if case_name
                                                            else "")),
        fontsize=10, x=0.01, ha="left")
    axes[0].set_title("disc among its pins (red: pins whose normal carries load)", fontsize=9)
    axes[1].set_title("close-up: contact normals through the pitch point (+)", fontsize=9)
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
    r2 = pair.ring_pitch_radius_m * 1e3
    px, py = r2 * math.cos(crank_angle_rad), r2 * math.sin(crank_angle_rad)
    w = 4 * pair.module_m * 1e3
    axes[1].set_xlim(px - w, px + w)
    axes[1].set_ylim(py - w, py + w)
    axes[1].plot(px, py, "k+", ms=10)
    fig.suptitle(title or (
        f"Sine-profile pair: planet {pair.planet_teeth} teeth in ring {pair.ring_teeth} teeth, "
        f"module {pair.module_m * 1e3:g} mm, tooth height {pair.tooth_height_m * 1e3:g} mm, "
        f"centre distance {a0 * 1e3:g} mm; crank angle {math.degrees(crank_angle_rad):.1f} deg"
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


#: Marker style of each kind of marked point (told apart in colour and shape).
MARKERS = {"measured": dict(marker="o", color="k", ms=7, ls="none"),
           "published": dict(marker="s", mfc="none", mec="#d62728", mew=1.8, ms=9, ls="none"),
           "operating": dict(marker="*", color="#ff7f0e", mec="k", ms=13, ls="none")}


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
        Labels of ``curves`` drawn dashed (e.g. another speed).

    Returns
    -------
    matplotlib.figure.Figure
        The curves, the points told apart by marker, the legend beside the axes.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 5.2), layout="constrained")
    for label, eta in curves.items():
        ax.plot(torque, 100 * np.asarray(eta), lw=1.6, ls="--" if label in dashed else "-",
                label=label)
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


def loss_shares(labels, shares: dict, title=""):
    """Grouped bars: loss shares [% of input power] per component, one group per source.

    Parameters
    ----------
    labels : sequence of str
        Loss components.
    shares : dict
        Source (e.g. "analytic", "fem", a paper) -> {component: share of input power}.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 4.8), layout="constrained")
    k = len(shares)
    width = 0.8 / max(k, 1)
    x = np.arange(len(labels))
    for i, (src, vals) in enumerate(shares.items()):
        bars = ax.bar(x + (i - (k - 1) / 2) * width,
                      [100 * vals.get(n, np.nan) for n in labels], width, label=src)
        ax.bar_label(bars, fmt="%.2g", fontsize=7, padding=1)
    ax.set_xticks(x, [n.replace("_", " ") for n in labels], rotation=20, ha="right",
                  fontsize=8)
    ax.set_ylabel("loss [% of input power]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False,
              title="loads / method", title_fontsize=8)
    ax.set_title(title, loc="left", fontsize=10)
    return fig


def drawing(drive, case_name=""):
    """The drawing of a drive's pair (:func:`cycloid_drawing` or :func:`sine_drawing`),
    titled with its dimensions and ``case_name``.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        A cycloid or sine drive.
    case_name : str
        Named in the title.

    Returns
    -------
    matplotlib.figure.Figure
        The drawing.
    """
    draw = {"cycloid": lambda d: cycloid_drawing(d.geometry, d.stage.holes,
                                                 case_name=case_name),
            "sine": lambda d: sine_drawing(d.pair, case_name=case_name)}
    return draw[drive.kind](drive)
