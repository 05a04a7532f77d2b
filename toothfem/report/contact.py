"""Pictures of contact results: load per contact over the meshing period, load around the
ring, transmission error, and the stress field of the moving member (matplotlib, off-screen).

Every function takes a :class:`~toothfem.fem.load_sharing.LoadSharing` (or a VTU file) and
a :class:`ContactLabels` (what the user asked for, in the drive's own words: pin or tooth,
disc or planet) and returns a figure or writes a PNG; nothing is shown on screen.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ToothfemError
from ..fem.datasheet.twist import ARCSEC
from . import pyplot, save, wrap

#: Colour map of the per-contact series (many lines: a continuous map keyed by contact
#: number, with a colour bar instead of a legend).
SERIES_CMAP = "viridis"
#: Colour map of stress fields (perceptually ordered, unlike jet).
FIELD_CMAP = "turbo"
#: Most tick labels of contact numbers along an axis before they are thinned.
MAX_CONTACT_TICKS = 20
#: Most contacts named one by one in a legend; more get a colour map and a colour bar.
MAX_LEGEND_SERIES = 8
#: Characters per title line of a field picture (8.5 in wide at 9 pt).
FIELD_TITLE_CHARS = 105


@dataclass(frozen=True, kw_only=True)
class ContactLabels:
    """What a contact picture says about its case: names from the drive
    (:attr:`~toothfem.fem.drives.Drive.contact_name` ...) and the torques the user asked for."""
    case_name: str
    contact: str                 # "pin" | "tooth"
    contacts: str                # "pins" | "teeth"
    member: str                  # "disc" | "planet"
    members: int                 # moving members sharing the output torque
    output_torque_Nm: float      # the reducer's output torque of the analysis
    member_torque_Nm: float      # the torque on one member (the load factor included)
    mode: str                    # "cycle" | "detailed" | "analytic"

    @property
    def torque_text(self) -> str:
        """'167 N m output, 91.85 N m on each of 2 discs' (the user's torque first)."""
        share = (f"{self.member_torque_Nm:.4g} N m on the {self.member}" if self.members == 1
                 else f"{self.member_torque_Nm:.4g} N m on each of {self.members} "
                      f"{self.member}s")
        return f"{self.output_torque_Nm:.4g} N m output, {share}"

    def title(self, what: str) -> str:
        """Two lines: what the picture shows, then the case with its load and mode.

        Parameters
        ----------
        what : str
            What the picture shows.

        Returns
        -------
        str
            The title.
        """
        return f"{what}\n{self.case_name}: {self.torque_text} ({self.mode} mode)"


def _series(ls):
    """Per contact number that carries load somewhere: (numbers, force (P, K) [N],
    P_h (P, K) [Pa]). A number is one pin or tooth through the period, whichever column of
    the record holds it at each position (the sine pair's candidate window moves)."""
    numbers = np.unique(ls.contact_id[ls.force > 0]).astype(int)
    force = np.stack([np.where(ls.contact_id == n, ls.force, 0.0).sum(axis=1)
                      for n in numbers], axis=1)
    ph = np.stack([np.where(ls.contact_id == n, ls.ph, 0.0).max(axis=1) for n in numbers],
                  axis=1)
    return numbers, force, ph


def _pressure_label(ls) -> str:
    """P_h is Hertz's, or the FE's peak where Hertz's assumptions fail (record flags)."""
    if np.any(ls.pressure_from_fe):
        return "peak pressure P_h [MPa]\n(Hertz; FE where Hertz fails)"
    return "Hertz pressure P_h [MPa]"


def _colours(fig, axes, numbers, labels: ContactLabels) -> dict:
    """A colour per contact number: a categorical palette named in the legend for a few
    contacts, else a continuous map with a colour bar beside ``axes`` (outside the data)."""
    plt = pyplot()
    if len(numbers) <= MAX_LEGEND_SERIES:
        palette = plt.get_cmap("tab10")
        return {n: palette(i) for i, n in enumerate(numbers)}
    lo, hi = int(numbers.min()), int(numbers.max())
    norm = plt.Normalize(lo - 0.5, hi + 0.5)
    cmap = plt.get_cmap(SERIES_CMAP)
    bar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes, pad=0.02,
                       fraction=0.04)
    bar.set_label(f"{labels.contact} number (contact_id in load_sharing.csv)")
    step = max(1, math.ceil((hi - lo + 1) / MAX_CONTACT_TICKS))
    bar.set_ticks(range(lo, hi + 1, step))
    return {n: cmap(norm(n)) for n in numbers}


def load_per_contact(ls, labels: ContactLabels):
    """Normal force and Hertz pressure of every loaded contact over one meshing period.

    Parameters
    ----------
    ls : toothfem.fem.load_sharing.LoadSharing
        Force [N] and P_h [Pa] per position and contact.
    labels : ContactLabels
        The drive's words and the user's torque (title, axes).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels (force [N], P_h [MPa]) against crank angle [deg], one line per contact
        told apart by its number (legend for a few, colour bar for many), the largest over
        the contacts dashed.
    """
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True, layout="constrained")
    deg = np.degrees(ls.position_rad)
    numbers, force, ph = _series(ls)
    colour = _colours(fig, [a1, a2], numbers, labels)
    few = len(numbers) <= MAX_LEGEND_SERIES
    for k, n in enumerate(numbers):
        a1.plot(deg, force[:, k], lw=1.3, color=colour[n],
                label=f"{labels.contact} {n}" if few else None)
        a2.plot(deg, ph[:, k] / 1e6, lw=1.3, color=colour[n])
    a1.plot(deg, ls.force.max(axis=1), "k--", lw=1.5,
            label=f"largest over the {labels.contacts}")
    a2.plot(deg, ls.ph.max(axis=1) / 1e6, "k--", lw=1.5)
    a1.set_ylabel(f"normal force per {labels.contact} [N]")
    a2.set_ylabel(_pressure_label(ls))
    a2.set_xlabel("crank angle [deg]")
    fig.legend(loc="outside lower center", frameon=False, fontsize=8,
               ncol=min(len(numbers) + 1, MAX_LEGEND_SERIES + 1))
    a1.set_title(labels.title(f"Force and contact pressure per {labels.contact} over one "
                              "meshing period"), loc="left", fontsize=10)
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.set_ylim(bottom=0)
    return fig


def _around_ring(ls):
    """Per contact number: angle around the ring [deg], force [N] and P_h [Pa] at the worst
    position and the largest over the period, sorted by angle. Angles are unwrapped about
    the most loaded contact (a loaded zone across 0 deg stays in one piece)."""
    worst = int(np.argmax(ls.force.max(axis=1)))
    numbers, force, ph = _series(ls)
    peak = np.argmax(force, axis=0)                         # each contact's largest force
    angle = np.degrees(np.arctan2(ls.point[..., 1], ls.point[..., 0]))
    ang = np.array([angle[p][ls.contact_id[p] == n][0] for p, n in zip(peak, numbers)])
    centre = ang[np.argmax(force.max(axis=0))]
    ang = centre + (ang - centre + 180.0) % 360.0 - 180.0
    order = np.argsort(ang)
    return (worst, ang[order], numbers[order], force[worst, order], force.max(axis=0)[order],
            ph[worst, order], ph.max(axis=0)[order])


def _contact_axis(ax, angles, numbers, labels: ContactLabels):
    """Contact numbers on a top axis at their angles (thinned to MAX_CONTACT_TICKS)."""
    top = ax.secondary_xaxis("top")
    step = max(1, math.ceil(len(numbers) / MAX_CONTACT_TICKS))
    top.set_xticks(angles[::step], [str(n) for n in numbers[::step]], fontsize=7)
    top.set_xlabel(f"{labels.contact} number", fontsize=8)


def load_around_ring(ls, labels: ContactLabels):
    """Force and P_h per contact around the ring: at the worst position and the largest
    over the meshing period.

    Parameters
    ----------
    ls : toothfem.fem.load_sharing.LoadSharing
        Its contact points place each contact on the ring (their angle).
    labels : ContactLabels

    Returns
    -------
    matplotlib.figure.Figure
        Left: polar view of the force per contact at its place on the ring (housing frame,
        0 deg on +x, counter-clockwise). Right: the same unrolled, force [N] and P_h [MPa]
        per contact against its angle, contact numbers on the top axis.
    """
    plt = pyplot()
    worst, ang, num, fw, fmax, pw, pmax = _around_ring(ls)
    worst_deg = math.degrees(ls.position_rad[worst])
    fig = plt.figure(figsize=(13, 6.2), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.35))
    polar = fig.add_subplot(grid[:, 0], projection="polar")
    a1 = fig.add_subplot(grid[0, 1])
    a2 = fig.add_subplot(grid[1, 1], sharex=a1)
    th = np.radians(ang)
    width = np.radians(np.min(np.diff(ang))) * 0.8 if len(ang) > 1 else 0.05
    polar.bar(th, fmax, width=width, color="#c6dbef", edgecolor="#6baed6", lw=0.5,
              label="largest over the period")
    polar.bar(th, fw, width=width * 0.6, color="#d62728", label=f"at the worst position "
              f"({worst_deg:.2f} deg crank)")
    polar.set_title(f"normal force per {labels.contact} [N] around the ring", fontsize=9)
    polar.tick_params(labelsize=7)
    polar.set_rlabel_position(float(ang[np.argmax(fmax)]) + 180.0)   # away from the load
    polar.legend(loc="upper center", bbox_to_anchor=(0.5, -0.06), fontsize=8, frameon=False)
    a1.bar(ang, fmax, width=width * 180 / math.pi, color="#c6dbef", edgecolor="#6baed6",
           lw=0.5, label="largest over the period")
    a1.plot(ang, fw, "o", color="#d62728", ms=4, label="at the worst position")
    a2.bar(ang, pmax / 1e6, width=width * 180 / math.pi, color="#fdd0a2", edgecolor="#fd8d3c",
           lw=0.5, label="largest over the period")
    a2.plot(ang, pw / 1e6, "o", color="#a63603", ms=4, label="at the worst position")
    a1.set_ylabel(f"normal force per {labels.contact} [N]")
    a2.set_ylabel(_pressure_label(ls))
    a2.set_xlabel(f"position of the {labels.contact} on the ring [deg] (0 on +x, "
                  "counter-clockwise; where it carries most)")
    _contact_axis(a1, ang, num, labels)
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle(labels.title(f"Load per {labels.contact} around the ring"), fontsize=10,
                 x=0.01, ha="left")
    return fig


def transmission_error(ls, labels: ContactLabels):
    """Transmission error [arcsec] over one meshing period.

    Parameters
    ----------
    ls : toothfem.fem.load_sharing.LoadSharing
        ``transmission_error`` in rad (the lag of the output member under load).
    labels : ContactLabels

    Returns
    -------
    matplotlib.figure.Figure
        TE against crank angle, its mean dashed; title with mean and peak-to-peak ripple.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.8), layout="constrained")
    deg = np.degrees(ls.position_rad)
    te = ls.transmission_error / ARCSEC
    ax.plot(deg, te, "o-", ms=3, lw=1.4, color="#08519c", label="transmission error")
    ax.axhline(float(te.mean()), color="k", ls="--", lw=1, label=f"mean {te.mean():.3g} arcsec")
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel(f"lag of the {labels.member} under load [arcsec]")
    ax.grid(alpha=0.3)
    fig.legend(loc="outside lower center", fontsize=8, frameon=False, ncol=2)
    ax.set_title(labels.title(f"Transmission error under load: mean {te.mean():.3g} arcsec, "
                              f"ripple {np.ptp(te):.3g} arcsec peak to peak"),
                 loc="left", fontsize=10)
    return fig


def _field_mm_MPa(mesh, scalar: str):
    """(x [mm], y [mm], values [MPa]) of a VTU's stress field ``scalar`` (named with its
    unit, ``_MPa``, the points in mm: :mod:`toothfem.fem.export`); a file written before
    the units went into the names holds ``von_mises`` in Pa on points in m."""
    points = np.asarray(mesh.points, float)
    if scalar in mesh.point_data:
        return points[:, 0], points[:, 1], np.asarray(mesh.point_data[scalar], float)
    legacy = scalar.removesuffix("_MPa")
    if legacy != scalar and legacy in mesh.point_data:
        return (points[:, 0] * 1e3, points[:, 1] * 1e3,
                np.asarray(mesh.point_data[legacy], float) / 1e6)
    raise ToothfemError(f"scalar = {scalar!r} is not a field of the VTU (its fields: "
                        f"{sorted(mesh.point_data)})")


def field_png(vtu_path, png_path, *, title, scalar="von_mises_MPa", outlines=(),
              zoom_centre=None, zoom_radius=None, mark=None):
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

    Returns
    -------
    path
        ``png_path``.
    """
    import meshio
    from matplotlib.tri import Triangulation

    plt = pyplot()
    mesh = meshio.read(str(vtu_path))
    x_mm, y_mm, value = _field_mm_MPa(mesh, scalar)
    tri = Triangulation(x_mm, y_mm, mesh.cells_dict["triangle"])
    fig, ax = plt.subplots(figsize=(8.5, 7.5), layout="constrained")
    if zoom_centre is not None:
        x0, y0 = np.asarray(zoom_centre, float) * 1e3
        r = float(zoom_radius) * 1e3
        inside = ((np.abs(tri.x - x0) < r) & (np.abs(tri.y - y0) < r))
        vmax = float(value[inside].max()) if np.any(inside) else float(value.max())
    else:
        vmax = float(value.max())
    art = ax.tripcolor(tri, value, shading="gouraud", cmap=FIELD_CMAP, vmin=0.0, vmax=vmax)
    if zoom_centre is not None:
        ax.triplot(tri, color="k", lw=0.15, alpha=0.5)
    for o in outlines:           # lines, not fills: a ring's outline encloses the member
        xy = np.asarray(o, float) * 1e3
        ax.plot(np.append(xy[0], xy[0, 0]), np.append(xy[1], xy[1, 0]), color="0.25",
                lw=0.8)
    if mark is not None:
        x, y = np.asarray(mark, float) * 1e3
        ax.plot(x, y, "x", color="w", ms=11, mew=3.5)
        ax.plot(x, y, "x", color="k", ms=9, mew=1.5)
    if zoom_centre is not None:
        ax.set_xlim(x0 - r, x0 + r)
        ax.set_ylim(y0 - r, y0 + r)
    else:
        ax.set_xlim(tri.x.min() * 1.08, tri.x.max() * 1.08)
        ax.set_ylim(tri.y.min() * 1.08, tri.y.max() * 1.08)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (member frame)")
    ax.set_ylabel("y [mm]")
    bar = fig.colorbar(art, ax=ax, shrink=0.85)
    bar.set_label(f"{scalar.removesuffix('_MPa').replace('_', ' ')} stress [MPa]"
                  + (" (colour scale of this view)" if zoom_centre is not None else ""))
    ax.set_title(wrap(title, FIELD_TITLE_CHARS), loc="left", fontsize=9)
    return save(fig, png_path)


def contacts_versus_torque(torques, counts, max_forces, labels, title="",
                           contacts="pins", member="disc"):
    """Contacts carrying load (and the largest force) against the member torque, one line
    per design (``labels``).

    Parameters
    ----------
    torques : array_like, shape (T,)
        Member torques [N m].
    counts : sequence of array_like, shape (T,)
        Contacts carrying load, one series per design.
    max_forces : sequence of array_like, shape (T,)
        Largest contact force [N], one series per design.
    labels : sequence of str
        The designs.
    title : str
        The figure's title.
    contacts, member : str
        The drive's words ("pins", "disc"; "teeth", "planet").

    Returns
    -------
    matplotlib.figure.Figure
        Two panels.
    """
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
    for n, f, lab in zip(counts, max_forces, labels):
        a1.plot(torques, n, "o-", label=lab)
        a2.plot(torques, f, "o-", label=lab)
    a1.set_xlabel(f"{member} torque [N m]")
    a1.set_ylabel(f"{contacts} in contact")
    a2.set_xlabel(f"{member} torque [N m]")
    a2.set_ylabel(f"largest force on one of the {contacts} [N]")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    a2.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle(title)
    return fig
