"""Pictures of contact results: load per contact over the meshing period, load around the
ring, transmission error, contacts against torque (matplotlib, off-screen).

Every function takes a :class:`~toothfem.fem.load_sharing.LoadSharing` and a
:class:`ContactLabels` (what the user asked for, in the drive's own words: pin or tooth,
disc or planet) and returns a figure; nothing is shown on screen. The stress field of the
moving member: :mod:`toothfem.report.field`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..units import ARCSEC
from . import pyplot, wrap
from ..units import DEG, PA_PER_MPA

#: Colour of the contacts a per-contact picture does not name (light grey: there, not
#: competing with the named ones).
OTHER_CONTACTS = "0.72"
#: The polar view of the load around the ring shows only the sector of the loaded contacts
#: when they span less than this [deg] (the sine pair's three teeth within 10 deg): their
#: span and one contact pitch either side, its ends on whole degrees, its ticks on a round
#: step (POLAR_TICK_STEPS_DEG, at most POLAR_MAX_TICKS intervals).
POLAR_SECTOR_BELOW_DEG = 120.0
POLAR_TICK_STEPS_DEG = (1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0)
POLAR_MAX_TICKS = 8
#: Margin below zero of a force or pressure axis, a fraction of its top: a point at 0 N
#: (a contact that carries nothing at the worst position) sits above the frame, not on it.
ZERO_MARGIN = 0.04
#: Most tick labels of contact numbers along an axis before they are thinned.
MAX_CONTACT_TICKS = 20
#: Most contacts named one by one (a qualitative palette and a legend entry each: the ones
#: carrying most); the others are drawn grey.
MAX_LEGEND_SERIES = 8
#: Characters per title line of the mesh-rotation and load-per-contact pictures (10 in at
#: 10 pt) and of the load around the ring (13 in at 10 pt).
TE_TITLE_CHARS = 124
PER_CONTACT_TITLE_CHARS = 124
RING_TITLE_CHARS = 160
#: The largest over the contacts in the load-per-contact picture: a light band behind the
#: series (the named series it follows stay visible on top of it).
ENVELOPE = dict(color="0.45", lw=7.0, alpha=0.3, solid_capstyle="butt", zorder=0.5)


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
    # the reducer-wide largest force [N] and P_h [MPa] of the system model (every member
    # free on its supports; the summary's max_force_reducer_N, max_ph_reducer_MPa), where
    # the run has them: the pictures show one member held, and say so beside these
    reducer_max_force_N: float | None = None
    reducer_max_ph_MPa: float | None = None

    @property
    def torque_text(self) -> str:
        """'167 N m output, 91.85 N m on each of 2 discs' (the user's torque first)."""
        share = (f"{self.member_torque_Nm:.4g} N m on the {self.member}" if self.members == 1
                 else f"{self.member_torque_Nm:.4g} N m on each of {self.members} "
                      f"{self.member}s")
        return f"{self.output_torque_Nm:.4g} N m output, {share}"

    @property
    def model_text(self) -> str:
        """'one disc held at its bearing seats': the model whose loads the contact pictures
        show (the load sharing of one member, not the reducer's system model)."""
        return f"one {self.member} held at its bearing seats"

    @property
    def reducer_text(self) -> str:
        """The reducer-wide largest force and P_h of the system model, for comparison with
        the one member held ('' where the run has none)."""
        return self.reducer()

    def reducer(self, *, force: bool = True) -> str:
        """The reducer-wide largest P_h (and force) of the system model, for comparison
        with the one member held.

        Parameters
        ----------
        force : bool
            Name the largest force as well as the largest P_h.

        Returns
        -------
        str
            'the reducer, every disc free on its supports (system model, the summary's
            headline): largest force 2649 N, P_h 2483 MPa'; '' where the run has none.
        """
        parts = ([f"largest force {self.reducer_max_force_N:.4g} N"]
                 if force and self.reducer_max_force_N is not None else [])
        parts += ([f"{'P_h' if parts else 'largest P_h'} {self.reducer_max_ph_MPa:.4g} MPa"]
                  if self.reducer_max_ph_MPa is not None else [])
        if not parts:
            return ""
        every = (f"the {self.member}" if self.members == 1 else f"every {self.member}")
        return (f"the reducer, {every} free on its supports (system model, the summary's "
                f"headline): {', '.join(parts)}")

    def title(self, what: str, *, reducer: bool = False) -> str:
        """What the picture shows, then the case with its load and mode; with ``reducer``
        a third line with the reducer-wide figures (:attr:`reducer_text`), where known.

        Parameters
        ----------
        what : str
            What the picture shows.
        reducer : bool
            Add the reducer-wide largest force and P_h for comparison.

        Returns
        -------
        str
            The title.
        """
        lines = [what, f"{self.case_name}: {self.torque_text} ({self.mode} mode)"]
        if reducer and self.reducer_text:
            lines.append(self.reducer_text)
        return "\n".join(lines)


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


def _named(force, ph) -> list:
    """Column indices of the contacts a per-contact picture names, at most
    MAX_LEGEND_SERIES: first those that are the largest force or pressure at some
    position, then the top ones by largest force and by largest P_h in turn (the union:
    the pressure panel's highest contacts are named as well as the force panel's)."""
    first = list(dict.fromkeys(np.concatenate([np.argmax(force, axis=1),
                                               np.argmax(ph, axis=1)]).tolist()))
    by_force = np.argsort(-force.max(axis=0), kind="stable").tolist()
    by_ph = np.argsort(-ph.max(axis=0), kind="stable").tolist()
    turns = [k for pair in zip(by_force, by_ph) for k in pair]
    return list(dict.fromkeys(first + turns))[:MAX_LEGEND_SERIES]


def _highlighted(numbers, force, ph) -> dict:
    """A colour per contact number: up to MAX_LEGEND_SERIES named in a qualitative palette
    (:func:`_named`: the largest at some position, then the top ones by force and by
    pressure), the others grey (one legend entry for all of them)."""
    palette = pyplot().get_cmap("tab10")
    colours = [palette(i) for i in range(10) if i != 7]        # tab10 less its grey
    top = _named(force, ph)
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
        the others grey; the largest over the contacts a light band behind them. The
        title says the model (one member held) and the reducer's figures beside.
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
            a2.plot(deg, ph[:, k] / PA_PER_MPA, lw=0.8 if grey else 1.6, color=colour[n],
                    zorder=1 if grey else 2)
    a1.plot(deg, ls.force.max(axis=1), label=f"largest over the {labels.contacts} (band)",
            **ENVELOPE)
    a2.plot(deg, ls.ph.max(axis=1) / PA_PER_MPA, **ENVELOPE)
    a1.set_ylabel(f"normal force per {labels.contact} [N]")
    a2.set_ylabel(_pressure_label(ls))
    a2.set_xlabel("crank angle [deg]")
    handles, names = a1.get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", frameon=False, fontsize=8,
               ncol=min(len(names), 6))
    a1.set_title(wrap(labels.title(f"Force and contact pressure per {labels.contact} over "
                                   f"one meshing period: {labels.model_text}", reducer=True),
                      PER_CONTACT_TITLE_CHARS), loc="left", fontsize=10)
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


def polar_sector(angles_deg):
    """The sector [deg] a polar view of the loaded contacts shows, or None for the whole
    circle (they span POLAR_SECTOR_BELOW_DEG or more).

    Parameters
    ----------
    angles_deg : array_like
        The loaded contacts' angles around the ring [deg], unwrapped (one piece).

    Returns
    -------
    tuple of (float, float, numpy.ndarray) or None
        (start, end, ticks) [deg]: the contacts' span and one contact pitch (the median
        spacing of neighbours) either side, widened to whole degrees; the ticks on the
        smallest round step of POLAR_TICK_STEPS_DEG with at most POLAR_MAX_TICKS
        intervals over the sector, the ends ticked too where no tick is near.
    """
    ang = np.sort(np.asarray(angles_deg, float))
    if ang.size < 2 or float(np.ptp(ang)) >= POLAR_SECTOR_BELOW_DEG:
        return None
    pitch = float(np.median(np.diff(ang)))
    start = float(math.floor(float(ang[0]) - pitch))
    end = float(math.ceil(float(ang[-1]) + pitch))
    step = next((st for st in POLAR_TICK_STEPS_DEG if (end - start) / st <= POLAR_MAX_TICKS),
                POLAR_TICK_STEPS_DEG[-1])
    ticks = np.arange(math.ceil(start / step), math.floor(end / step) + 1) * step
    ends = [e for e in (start, end) if np.min(np.abs(ticks - e), initial=step) >= 0.5 * step]
    return start, end, np.sort(np.concatenate([ticks, ends]))


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
    sector = polar_sector(ang)
    if sector:      # the loaded contacts in a narrow arc: show that sector, not the circle
        start, end, ticks = sector
        polar.set_thetamin(start)
        polar.set_thetamax(end)
        polar.set_thetagrids(ticks)
    polar.set_title(f"normal force per {labels.contact} [N] around the ring"
                    + (f"\n(the {end - start:g} deg sector from {start:g} to {end:g} deg, "
                       f"where they carry)" if sector else ""), fontsize=9)
    polar.tick_params(labelsize=7)
    if not sector:
        polar.set_rlabel_position(float(ang[np.argmax(fmax)]) + 180.0)   # away from the load
    polar.legend(loc="upper center", bbox_to_anchor=(0.5, -0.06), fontsize=8, frameon=False)
    a1.bar(ang, fmax, width=width / DEG, color="#c6dbef", edgecolor="#6baed6",
           lw=0.5, label="largest over the period")
    a1.plot(ang, fw, "o", color="#d62728", ms=4, label="at the worst position")
    a2.bar(ang, pmax / PA_PER_MPA, width=width / DEG, color="#fdd0a2", edgecolor="#fd8d3c",
           lw=0.5, label="largest over the period")
    a2.plot(ang, pw / PA_PER_MPA, "o", color="#a63603", ms=4, label="at the worst position")
    a1.set_ylabel(f"normal force per {labels.contact} [N]")
    a2.set_ylabel(_pressure_label(ls))
    a2.set_xlabel(f"position of the {labels.contact} on the ring [deg] (0 on +x, "
                  "counter-clockwise; where it carries most)")
    _contact_axis(a1, ang, num, labels)
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
        top = a.get_ylim()[1]
        a.set_ylim(-ZERO_MARGIN * top, top)       # a point at 0 above the frame, not on it
        a.axhline(0.0, color="0.3", lw=0.6, zorder=1)
    fig.suptitle(wrap(labels.title(f"Load per {labels.contact} around the ring: "
                                   f"{labels.model_text}", reducer=True), RING_TITLE_CHARS),
                 fontsize=10, x=0.01, ha="left")
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
    fig, ax = plt.subplots(figsize=(10, 4.8), layout="constrained")
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
        f"The mesh's part of the TE ({labels.model_text}): mean {te.mean():.3g} arcsec, "
        f"ripple {np.ptp(te):.3g} arcsec peak to peak;\nthe reducer's TE is the summary's "
        "system-model row"),
        TE_TITLE_CHARS), loc="left", fontsize=10)
    return fig


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
