"""Pictures of the datasheet: the catalogue hysteresis curve and the loaded transmission
error. Functions take result records and return a matplotlib figure."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from typing import TYPE_CHECKING

from ..fem.datasheet.sheet import plural
from ..quantities import DATASHEET
from ..units import ARCSEC
from . import pyplot, save

if TYPE_CHECKING:      # annotations only: the record's .write() calls this module
    from ..datasheet import StiffnessResult


def hysteresis(sheet, title: str = ""):
    """Output twist against output torque over the loop (0 -> +T -> -T -> +T): left the
    whole loop with the rigidity secants, right the window of +-3 % of the rated torque
    (both branches at -3 %, 0, +3 %), with the lost-motion points (the midpoints of the
    width at +-3 %) and the hysteresis loss (the width at zero torque) marked.

    Parameters
    ----------
    sheet : toothfem.fem.datasheet.sheet.Datasheet
    title : str
        The figure's title (default: the rated torque).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    loop = sheet.loop
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(12, 5.6),
                                   gridspec_kw={"width_ratios": [1.25, 1]})
    t, th = loop.torque_Nm, loop.twist_arcmin
    rated = sheet.rated_torque_Nm
    spread = float(np.max(loop.twist_max_arcmin - loop.twist_min_arcmin))
    ax.plot(t, th, "o-", color="tab:blue", ms=3, lw=1.2,
            label=f"mean over the positions (0 → +T → −T → +T); their range ≤ {spread:.2g} "
                  "arcmin")
    for a in (ax, zoom):
        a.axhline(0, color="k", lw=0.5)
        a.axvline(0, color="k", lw=0.5)
        a.set_xlabel("output torque [N m]")
        a.set_ylabel("output twist [arcmin]")
        a.grid(alpha=0.3)
    for side in (1, -1):        # rigidity: the 50-100 % secant of each loading branch
        up = np.array([k for k in range(1, t.size) if side * (t[k] - t[k - 1]) > 0
                       and side * t[k] > 0])
        order = np.argsort(t[up])
        k = sheet.rigidity_by_direction[0 if side > 0 else 1]
        x0 = side * 0.5 * rated
        y0 = np.interp(x0, t[up][order], th[up][order])
        xr = np.array([x0, side * rated])
        ax.plot(xr, y0 + (xr - x0) / k, "--", color="tab:red", lw=1.5,
                label=f"rigidity 50-100 % of rated: {sheet.rigidity_Nm_per_arcmin:.4g} "
                      "N m/arcmin" if side > 0 else None)
    t_lm = 0.03 * rated
    ax.axvspan(-t_lm, t_lm, color="tab:orange", alpha=0.2, label="±3 % of rated (right)")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title("the loop", fontsize=10)
    w = sheet.window
    zoom.axvspan(-t_lm, t_lm, color="tab:orange", alpha=0.2, label="±3 % of rated")
    zoom.plot(w["torque_Nm"], w["rising_arcmin"], "^-", color="tab:green", ms=6,
              label="torque rising")
    zoom.plot(w["torque_Nm"], w["falling_arcmin"], "v-", color="tab:red", ms=6,
              label="torque falling")
    mid = 0.5 * (w["rising_arcmin"] + w["falling_arcmin"])
    zoom.plot(w["torque_Nm"][[0, 2]], mid[[0, 2]], "ks", ms=6,
              label=f"lost motion (midpoints at ±3 %): {sheet.lost_motion_arcmin:.3g} arcmin")
    x_lm = 1.3 * t_lm                  # the lost motion as a span between the midpoints
    for y in mid[[0, 2]]:
        zoom.plot([w["torque_Nm"][2], x_lm], [y, y], ":", color="k", lw=0.8)
    zoom.annotate("", xy=(x_lm, mid[2]), xytext=(x_lm, mid[0]),
                  arrowprops=dict(arrowstyle="<->", color="k", lw=1.2))
    zoom.text(x_lm, 0.5 * (mid[0] + mid[2]), " lost\n motion", fontsize=8, va="center",
              ha="left")
    zoom.plot([0, 0], [w["rising_arcmin"][1], w["falling_arcmin"][1]], color="tab:purple",
              lw=4, alpha=0.7, label=f"hysteresis loss (width at 0): "
                                     f"{sheet.hysteresis_loss_arcmin:.3g} arcmin")
    zoom.plot([], [], " ", label=f"backlash (clearances): {sheet.backlash_arcmin:.3g} arcmin")
    lo = min(np.min(w["rising_arcmin"]), np.min(w["falling_arcmin"]))
    hi = max(np.max(w["rising_arcmin"]), np.max(w["falling_arcmin"]))
    pad = 0.2 * max(hi - lo, 1e-6)
    zoom.set_xlim(-1.6 * t_lm, 1.6 * t_lm)
    zoom.set_ylim(lo - pad, hi + 2.5 * pad)
    zoom.legend(fontsize=8, loc="upper left")
    zoom.set_title("near zero torque (±3 % of rated)", fontsize=10)
    assumed = (" (rated = the operating output torque: no rating named)"
               if sheet.rated_torque_assumed else "")
    fig.suptitle(title or f"torsional stiffness: rated torque {rated:.4g} N m{assumed}",
                 fontsize=10)
    fig.tight_layout()
    return fig


def transmission_error(te, title: str = "", heading: str = ""):
    """The figure of a :class:`~toothfem.fem.datasheet.transmission.LoadedTE`: the TE over
    the full period against crank angle (output angle on the top axis), and below the
    amplitudes of its largest harmonics by order per output revolution.

    Parameters
    ----------
    te : toothfem.fem.datasheet.transmission.LoadedTE
        The loaded TE.
    title : str
        The top panel's title; default: the torque and the period.
    heading : str
        A line above the default title (the case and which TE it is).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels, TE in arcsec.
    """
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7.5))
    arcsec = 1 / ARCSEC
    crank = np.degrees(te.crank_angle_rad)
    a1.plot(crank, te.te_rad * arcsec, lw=1.2, color="tab:blue", label="output twist (TE)")
    a1.set_xlabel("crank angle [deg]")
    a1.set_ylabel("loaded TE [arcsec]")
    top = a1.secondary_xaxis("top", functions=(
        lambda x: x * (te.output_angle_rad[1] / te.crank_angle_rad[1]
                       if te.crank_angle_rad.size > 1 else 1.0),
        lambda x: x / (te.output_angle_rad[1] / te.crank_angle_rad[1]
                       if te.crank_angle_rad.size > 1 else 1.0)))
    top.set_xlabel("output angle [deg]")
    a1.grid(alpha=0.3)
    a1.legend(fontsize=8, loc="lower right")
    pitches = f"{te.full_period_pitches} pitch" + ("es" if te.full_period_pitches > 1 else "")
    a1.set_title(title or (f"{heading}\n" if heading else "")
                 + f"loaded TE at {te.output_torque_Nm:.4g} N m over the full period "
                 f"({pitches}): peak-to-peak "
                 f"{te.peak_to_peak_arcsec:.3g} arcsec, RMS {te.rms_arcsec:.3g} arcsec",
                 fontsize=10)
    h = te.harmonics(12)
    a2.stem([x["order_per_output_rev"] for x in h], [x["amplitude_arcsec"] for x in h],
            basefmt=" ")
    a2.set_xscale("log")
    a2.set_xlabel("order [per output revolution]")
    a2.set_ylabel("amplitude [arcsec]")
    a2.set_title("largest harmonics", fontsize=10)
    a2.grid(alpha=0.3, which="both")
    fig.tight_layout()
    return fig


def member_split(split, member_name: str = "disc", case_name: str = ""):
    """The figure of a :class:`~toothfem.fem.datasheet.transmission.MemberSplit`: each
    member's share of the output torque over the full period, the even share dashed.

    Parameters
    ----------
    split : toothfem.fem.datasheet.transmission.MemberSplit
        The split.
    member_name : str
        What a member is called ("disc").
    case_name : str
        The case, first line of the title.

    Returns
    -------
    matplotlib.figure.Figure
        One panel, shares in percent against crank angle.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    crank = np.degrees(split.crank_angle_rad)
    m = split.share.shape[0]
    styles = [("-", 2.4), ("--", 1.6), (":", 2.0), ("-.", 1.4)]   # overlapping shares show
    for j in range(m):
        ls, lw = styles[j % len(styles)]
        ax.plot(crank, 100 * split.share[j], ls=ls, lw=lw,
                label=f"{member_name} {j + 1} (mean {100 * split.share[j].mean():.2f} %)")
    ax.axhline(100 / m, color="k", ls=(0, (6, 3)), lw=0.8, label=f"even share {100 / m:.2f} %")
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel("share of the output torque [%]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    head = f"{case_name}\n" if case_name else ""
    ax.set_title(f"{head}torque split between the {member_name}s at "
                 f"{split.output_torque_Nm:.4g} N m (FE): load factor {split.load_factor:.3f}",
                 fontsize=10)
    fig.tight_layout()
    return fig


HYSTERESIS_COLUMNS = ("torque_Nm", "twist_arcmin", "twist_min_arcmin", "twist_max_arcmin")


def stiffness_figures(result: StiffnessResult) -> dict:
    """The datasheet's pictures: the hysteresis loop, the reducer's TE over the full period
    and, where the layout does not make it even, the split between the members.

    Parameters
    ----------
    result : StiffnessResult

    Returns
    -------
    dict
        File name -> matplotlib Figure.
    """
    sheet = result.sheet
    title = (f"{result.case_name}\nrated {sheet.rated_torque_Nm:.4g} N m"
             + (" (the operating output torque: no rating named)"
                if sheet.rated_torque_assumed else "")
             + f", rigidity {sheet.rigidity_Nm_per_arcmin:.4g} N m/arcmin")
    out = {"hysteresis.png": hysteresis(sheet, title=title),
           "te.png": transmission_error(result.te, heading=f"{result.case_name}: the "
                                        "reducer's TE (system model, input held)")}
    if result.split is not None and not result.split.even_by_layout:
        out["split.png"] = member_split(result.split, sheet.member_name, result.case_name)
    return out


def write_stiffness(result: StiffnessResult, folder: Path) -> dict:
    """hysteresis.csv/png, te.csv/png, split.csv (several members), split.png (a split the
    layout does not make even) and summary.json into
    ``folder``.

    Parameters
    ----------
    result : StiffnessResult
        The data sheet, loaded TE and split.
    folder : pathlib.Path
        Where the files go (it must exist).

    Returns
    -------
    dict
        The data sheet's figures and the names of the files written.
    """
    folder = Path(folder)
    sheet, te = result.sheet, result.te
    contacts = f"{plural(sheet.contact_name)}_in_contact"
    with open(folder / "hysteresis.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(HYSTERESIS_COLUMNS + (contacts,))
        for row in sheet.loop.rows():
            w.writerow([f"{v:.9g}" for v in row])
    arcsec = 1 / ARCSEC
    with open(folder / "te.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["crank_angle_deg", "output_angle_deg", "te_arcsec", "mesh_arcsec"])
        for row in zip(np.degrees(te.crank_angle_rad), np.degrees(te.output_angle_rad),
                       te.te_rad * arcsec, te.mesh_rad * arcsec):
            w.writerow([f"{v:.9g}" for v in row])
    files = ["hysteresis.csv", "hysteresis.png", "te.csv", "te.png", "summary.json"]
    b = result.bearings
    with open(folder / "bearings.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["crank_angle_deg"] + [f"{n.replace(' ', '_')}_N" for n in b.names])
        for g, phi in enumerate(np.degrees(b.crank_angle_rad)):
            w.writerow([f"{phi:.9g}"] + [f"{x:.9g}" for x in b.load_N[:, g]])
    files.append("bearings.csv")
    if result.split is not None:
        with open(folder / "split.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            share = result.split.share
            w.writerow(["crank_angle_deg"] + [f"share_{sheet.member_name}_{j}"
                                              for j in range(share.shape[0])])
            for g, phi in enumerate(np.degrees(result.split.crank_angle_rad)):
                w.writerow([f"{phi:.9g}"] + [f"{x:.9g}" for x in share[:, g]])
        files.append("split.csv")
    for name, fig in stiffness_figures(result).items():
        save(fig, folder / name, dpi=120)
        if name == "split.png":
            files.append(name)
    summary = {**result.summary, "files": files}
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def datasheet_rows(summary: dict) -> list:
    """(quantity, value) rows of the datasheet table of a report.

    Parameters
    ----------
    summary : dict
        The summary :func:`write_stiffness` returns.

    Returns
    -------
    list of (str, str)
        Quantity with its unit, and the formatted value.
    """
    def named(key, **words):
        q = DATASHEET[key]
        return f"{q.label.format(**words)} [{q.unit_symbol()}]"

    k = summary["te_full_period_pitches"]
    period = (f"{k} pitch{'' if k == 1 else 'es'}, {summary['te_positions_per_pitch']} "
              "positions each")
    rows = [(named("rated_torque_Nm"), f"{summary['rated_torque_Nm']:.4g}"
             + (" (the operating output torque: no rating named)"
                if summary["rated_torque_assumed"] else ""))]
    maker = summary.get("maker") or {}
    rows += [(named(key), f"{summary[key]:.4g}" + (
        f" (maker: {maker[key]:g})" if key in maker else "")) for key in (
        "torsional_rigidity_Nm_per_arcmin", "lost_motion_arcmin", "backlash_arcmin",
        "hysteresis_loss_arcmin")]
    rows += [(named("te_mean_arcsec", torque=f"{summary['te_torque_Nm']:.4g}"),
              f"{summary['te_mean_arcsec']:.4g}"),
             (named("te_peak_to_peak_arcsec", period=period),
              f"{summary['te_peak_to_peak_arcsec']:.4g}")]
    if "member_share_max" in summary:
        rows.append(("largest member share of the torque (FE; case's factor)",
                     f"{summary['member_share_max']:.4f} "
                     f"(load factor {summary['member_load_factor_fe']:.4f}; case "
                     f"{summary['member_load_factor_case']:.3g})"))
    for name, share in summary["compliance_shares"].items():
        rows.append((f"compliance share: {name}", f"{100 * share:.1f} %"))
    return rows
