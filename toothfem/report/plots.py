"""Drawings (matplotlib, off-screen). Each function takes data, returns the figure and never
calls show(); matplotlib is imported here only, so ``import toothfem`` stays light."""
from __future__ import annotations

import math

import numpy as np

from . import pyplot




def _draw_polygon(ax, poly, scale=1e3, **kw):
    x, y = poly.exterior.xy
    ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, **kw)
    for ring in poly.interiors:
        x, y = ring.xy
        ax.fill(np.asarray(x) * scale, np.asarray(y) * scale, color="white", lw=0.5,
                ec=kw.get("ec", "k"))


def cycloid_drawing(geom, holes, crank_angle_rad=0.0, title=""):
    """Disc with holes placed at a crank angle among its pins; right: close-up of the
    loaded zone with the contact normals through the pitch point."""
    from shapely import affinity

    from ..geometry import cycloid as cy

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    disc = cy.disc_polygon(geom, holes)
    centre, rot = cy.disc_pose(geom, crank_angle_rad)
    placed = affinity.translate(affinity.rotate(disc, float(rot[0]), origin=(0, 0),
                                                use_radians=True), *centre[:, 0])
    m = cy.meshing(geom, crank_angle_rad)
    pins = cy.pin_centres(geom)
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
    axes[0].set_title(title or f"disc at crank angle {math.degrees(crank_angle_rad):.1f} deg "
                      "(red: load-carrying pins)")
    axes[1].set_title("close-up: normals through the pitch point (+)")
    fig.tight_layout()
    return fig


def sine_drawing(pair, crank_angle_rad=0.0, title=""):
    """Planet inside the ring at a crank angle; right: close-up at the pitch point."""
    from shapely import affinity

    from ..geometry import sine

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
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
    axes[0].set_title(title or f"sine pair {pair.planet_teeth}/{pair.ring_teeth} at crank "
                      f"angle {math.degrees(crank_angle_rad):.1f} deg")
    axes[1].set_title("close-up at the pitch point (+)")
    fig.tight_layout()
    return fig


def efficiency_vs_torque(torque, curves: dict, measured=(), title=""):
    """Efficiency [%] against output torque; ``curves`` label -> efficiency array;
    ``measured``: (torque, efficiency, label) points."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 5))
    for label, eta in curves.items():
        ax.plot(torque, 100 * np.asarray(eta), lw=1.5, label=label)
    for t, e, label in measured:
        ax.plot(t, 100 * e, "ko", ms=6)
        ax.annotate(label, (t, 100 * e), textcoords="offset points", xytext=(-10, -14),
                    fontsize=8, ha="right")
    ax.set_xlabel("output torque [N m]")
    ax.set_ylabel("efficiency [%]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    return fig


def efficiency_map(x, y, eta, xlabel, ylabel, title=""):
    """Catalogue-style efficiency chart: filled contours of efficiency [%] over a grid."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    levels = np.unique(np.clip(np.round(np.linspace(np.nanmin(eta), np.nanmax(eta), 12)
                                        * 100), 0, 100))
    cs = ax.contourf(x, y, 100 * np.asarray(eta), levels=24, cmap="viridis")
    lines = ax.contour(x, y, 100 * np.asarray(eta), levels=levels, colors="k",
                       linewidths=0.5)
    ax.clabel(lines, fmt="%.0f %%", fontsize=7)
    fig.colorbar(cs, ax=ax, label="efficiency [%]")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    fig.tight_layout()
    return fig


def loss_shares(labels, shares: dict, title=""):
    """Grouped bars: loss shares [% of input power] per component, one group per source."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    k = len(shares)
    width = 0.8 / max(k, 1)
    x = np.arange(len(labels))
    for i, (src, vals) in enumerate(shares.items()):
        ax.bar(x + (i - (k - 1) / 2) * width, [100 * vals.get(n, np.nan) for n in labels],
               width, label=src)
    ax.set_xticks(x, labels, rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("loss [% of input power]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    return fig


def drawing(drive):
    """The drawing of a drive's pair (:func:`cycloid_drawing` or :func:`sine_drawing`)."""
    draw = {"cycloid": lambda d: cycloid_drawing(d.geometry, d.stage.holes),
            "sine": lambda d: sine_drawing(d.pair)}
    return draw[drive.kind](drive)
