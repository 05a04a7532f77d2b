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

#: Colour of the contacts a per-contact picture does not name (light grey: there, not
#: competing with the named ones).
OTHER_CONTACTS = "0.72"
#: Colour map of stress fields (perceptually ordered, unlike jet).
FIELD_CMAP = "turbo"
#: The whole member's colour scale ends at this percentile of the field by area, the rest
#: saturated (marked on the colour bar): the body's stress readable beside the contact peaks.
FIELD_PERCENTILE = 99.0
#: The polar view of the load around the ring shows only the sector of the loaded contacts
#: when they span less than this [deg] (the sine pair's three teeth within 10 deg), at least
#: +- the half-width below around their middle.
POLAR_SECTOR_BELOW_DEG = 120.0
POLAR_SECTOR_MIN_HALF_DEG = 20.0
#: Most tick labels of contact numbers along an axis before they are thinned.
MAX_CONTACT_TICKS = 20
#: Most contacts named one by one (a qualitative palette and a legend entry each: the ones
#: carrying most); the others are drawn grey.
MAX_LEGEND_SERIES = 8
#: Characters per title line of a field picture (8.5 in wide at 9 pt) and of the
#: mesh-rotation picture (9 in at 10 pt).
FIELD_TITLE_CHARS = 105
TE_TITLE_CHARS = 112


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


def _highlighted(numbers, force, ph) -> dict:
    """A colour per contact number: up to MAX_LEGEND_SERIES named in a qualitative palette
    (first those that are the largest force or pressure at some position, then by their
    largest force), the others grey (one legend entry for all of them)."""
    palette = pyplot().get_cmap("tab10")
    colours = [palette(i) for i in range(10) if i != 7]        # tab10 less its grey
    first = list(dict.fromkeys(np.concatenate([np.argmax(force, axis=1),
                                               np.argmax(ph, axis=1)]).tolist()))
    by_force = np.argsort(-force.max(axis=0), kind="stable").tolist()
    top = list(dict.fromkeys(first + by_force))[:MAX_LEGEND_SERIES]
    named = sorted(int(numbers[k]) for k in top)
    return {int(n): colours[named.index(int(n))] if int(n) in named else OTHER_CONTACTS
            for n in numbers}


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
        Two panels (force [N], P_h [MPa]) against crank angle [deg], one line per contact:
        the MAX_LEGEND_SERIES carrying most in a qualitative palette named in the legend,
        the others grey; the largest over the contacts dashed.
    """
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True, layout="constrained")
    deg = np.degrees(ls.position_rad)
    numbers, force, ph = _series(ls)
    colour = _highlighted(numbers, force, ph)
    others = [n for n in numbers if colour[n] == OTHER_CONTACTS]
    for grey in (True, False):          # the grey ones below, the named ones on top
        for k, n in enumerate(numbers):
            if (colour[n] == OTHER_CONTACTS) != grey:
                continue
            label = (None if grey else f"{labels.contact} {n}")
            if grey and n == others[0]:
                label = f"the other {len(others)} loaded {labels.contacts}"
            a1.plot(deg, force[:, k], lw=0.8 if grey else 1.6, color=colour[n], label=label,
                    zorder=1 if grey else 2)
            a2.plot(deg, ph[:, k] / 1e6, lw=0.8 if grey else 1.6, color=colour[n],
                    zorder=1 if grey else 2)
    a1.plot(deg, ls.force.max(axis=1), "k--", lw=1.5, zorder=3,
            label=f"largest over the {labels.contacts}")
    a2.plot(deg, ls.ph.max(axis=1) / 1e6, "k--", lw=1.5, zorder=3)
    a1.set_ylabel(f"normal force per {labels.contact} [N]")
    a2.set_ylabel(_pressure_label(ls))
    a2.set_xlabel("crank angle [deg]")
    handles, names = a1.get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", frameon=False, fontsize=8,
               ncol=min(len(names), 6))
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
    span = float(np.ptp(ang)) if len(ang) > 1 else 0.0
    sector = span < POLAR_SECTOR_BELOW_DEG
    if sector:      # the loaded contacts in a narrow arc: show that sector, not the circle
        mid = 0.5 * (float(ang.min()) + float(ang.max()))
        half = max(0.5 * span + 2 * math.degrees(width), POLAR_SECTOR_MIN_HALF_DEG)
        polar.set_thetamin(mid - half)
        polar.set_thetamax(mid + half)
    polar.set_title(f"normal force per {labels.contact} [N] around the ring"
                    + (f"\n(the {2 * half:.0f} deg sector where they carry)" if sector else ""),
                    fontsize=9)
    polar.tick_params(labelsize=7)
    if not sector:
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
    """The mesh's rotation of one member held at its bearing seats over one meshing period
    [arcsec]: the mesh's part of the reducer's transmission error (the whole TE, supports
    and output mechanism included, is the system model's: docs/stiffness.md).

    Parameters
    ----------
    ls : toothfem.fem.load_sharing.LoadSharing
        ``transmission_error`` in rad (the member's rotation under load, held at its
        bearing seats).
    labels : ContactLabels

    Returns
    -------
    matplotlib.figure.Figure
        The rotation against crank angle, its mean dashed; the title says which part of
        the TE it is, with its mean and peak-to-peak ripple.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.8), layout="constrained")
    deg = np.degrees(ls.position_rad)
    te = ls.transmission_error / ARCSEC
    ax.plot(deg, te, "o-", ms=3, lw=1.4, color="#08519c",
            label=f"mesh rotation of one {labels.member}")
    ax.axhline(float(te.mean()), color="k", ls="--", lw=1, label=f"mean {te.mean():.3g} arcsec")
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel(f"rotation of the {labels.member} under load [arcsec]")
    ax.grid(alpha=0.3)
    fig.legend(loc="outside lower center", fontsize=8, frameon=False, ncol=2)
    ax.set_title(wrap(labels.title(
        f"The mesh's part of the TE (one {labels.member} held at its bearing seats): mean "
        f"{te.mean():.3g} arcsec, ripple {np.ptp(te):.3g} arcsec peak to peak; the reducer's "
        "TE is the summary's system-model row"),
        TE_TITLE_CHARS), loc="left", fontsize=10)
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


def robust_max(tri, value) -> float:
    """The colour scale's top of a whole-member field: the FIELD_PERCENTILE-th percentile
    of the triangles' mean values weighted by their area (the contact spots' peaks, a
    small area on a fine mesh, would otherwise darken the whole body).

    Parameters
    ----------
    tri : matplotlib.tri.Triangulation
    value : numpy.ndarray
        Nodal values.

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
    at = np.searchsorted(cum, FIELD_PERCENTILE / 100 * cum[-1])
    top = float(mean[order][min(at, mean.size - 1)])
    return top if top > 0 else float(value.max())


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
        vmax = robust_max(tri, value)
    peak = float(value.max())
    saturated = peak > vmax * (1 + 1e-9)
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
    bar = fig.colorbar(art, ax=ax, shrink=0.85, extend="max" if saturated else "neither")
    bar.set_label(f"{scalar.removesuffix('_MPa').replace('_', ' ')} stress [MPa]"
                  + (" (colour scale of this view)" if zoom_centre is not None else "")
                  + (f"\nsaturated above {vmax:.4g} MPa ({FIELD_PERCENTILE:g}th percentile "
                     f"by area); largest {peak:.4g} MPa" if saturated else ""))
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
