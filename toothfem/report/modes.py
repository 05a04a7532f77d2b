"""The files of ``toothfem modes`` (docs/dynamics.md): the mode list with its energy shares,
the bodies' masses and inertias, the Campbell diagram's orders and crossings, and two
pictures (the first modes, the Campbell diagram). Functions take the record
(:class:`toothfem.dynamics.ModesResult`) and return rows, figures or the summary."""
from __future__ import annotations

import csv
import json
import math
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import pyplot, save

if TYPE_CHECKING:      # annotations only: the record's .write() calls this module
    from ..dynamics import ModesResult

#: The no-break space that keeps a number with its % while a line wraps.
NBSP = "\u00a0"
#: Modes drawn in modes.png.
MODES_DRAWN = 4
#: The Campbell diagram's speeds: from this fraction of the top speed (log scale).
SPEED_DECADES = 1e-3
#: An order line is drawn solid where its amplitude is at least this fraction of the
#: largest (below: round-off of a line the nominal TE does not carry).
CARRIED_REL = 1e-6
#: Modes labelled in the Campbell diagram.
MODES_LABELLED = 6
#: A strain-energy share below this is left out of the screen's list (it is in the files).
SHARE_SHOWN = 0.01


def _shares_text(shares: dict) -> str:
    """'crank bearings 45 %, mesh 20 %' by falling share, the small ones left out."""
    top = sorted(((v, g) for g, v in shares.items() if v >= SHARE_SHOWN), reverse=True)
    return ", ".join(f"{g} {100 * v:.0f} %" for v, g in top)


def _motion_text(kinetic: dict) -> str:
    """The bodies that move: their kinetic-energy shares by falling share."""
    top = sorted(((v, b) for b, v in kinetic.items() if v >= 0.05), reverse=True)
    return ", ".join(f"{b} {100 * v:.0f} %" for v, b in top)


def mode_rows(result: ModesResult) -> list:
    """The table's rows: each mode's frequency, its range over the meshing positions and
    its largest strain-energy share (the full list: :func:`mode_lines`).

    Parameters
    ----------
    result : ModesResult

    Returns
    -------
    list of (str, str, dict)
    """
    rows = []
    m = result.modes
    for i, f in enumerate(m.frequency_Hz):
        lo, hi = result.frequency_range_Hz[i]
        top = max(m.shares[i].items(), key=lambda kv: kv[1], default=("", 0.0))
        rows.append((f"mode {i + 1}", "Hz", {
            "value": f"{f:.5g}", "over the mesh": f"{lo:.4g}-{hi:.4g}",
            "largest share": f"{top[0]} {100 * top[1]:.0f} %" if top[1] else "rigid"}))
    return rows


def mode_lines(result: ModesResult, width: int = 100) -> list:
    """The mode list as the terminal shows it: each mode's frequency with its range over
    the meshing positions and the bodies that move, then its strain-energy shares, wrapped
    at ``width`` columns.

    Parameters
    ----------
    result : ModesResult
    width : int

    Returns
    -------
    list of str
    """
    m = result.modes
    out = []
    for i, f in enumerate(m.frequency_Hz):
        lo, hi = result.frequency_range_Hz[i]
        head = (f"mode {i + 1:>2}  {f:>9.5g} Hz  ({lo:.4g}-{hi:.4g} over the mesh)  moves: "
                f"{_motion_text(m.kinetic[i])}")
        shares = "strain energy: " + (_shares_text(m.shares[i]) or "none (a rigid motion)")
        # a share's number and its % kept on one line (a no-break space while wrapping)
        out += [ln.replace(NBSP, " ") for ln in textwrap.wrap(
            head.replace(" %", NBSP + "%"), width, subsequent_indent=" " * 10)]
        out += [ln.replace(NBSP, " ") for ln in textwrap.wrap(
            shares.replace(" %", NBSP + "%"), width, initial_indent=" " * 10,
            subsequent_indent=" " * 25)]
    return out


def summary(result: ModesResult) -> dict:
    """The summary (summary.json, ``--json``).

    Parameters
    ----------
    result : ModesResult

    Returns
    -------
    dict
    """
    m = result.modes
    modes = []
    for i, f in enumerate(m.frequency_Hz):
        modes.append({
            "mode": i + 1, "frequency_Hz": float(f),
            "frequency_range_over_mesh_Hz": [float(v) for v in result.frequency_range_Hz[i]],
            "strain_energy_shares": {g: float(v) for g, v in m.shares[i].items()},
            "kinetic_energy_shares": {b: float(v) for b, v in m.kinetic[i].items()},
            "shape": {nm: float(v) for nm, v in zip(m.names, m.shapes[:, i])}})
    return {
        "case": result.case_name, "output_torque_Nm": result.torque_Nm,
        "input": "free" if result.input_free else "held",
        "load_inertia_kgm2": result.load_kgm2, "motor_inertia_kgm2": result.motor_kgm2,
        "assumed": result.assumed,
        "tangent_rigidity_Nm_per_arcmin": result.rigidity_Nm_per_rad * np.pi / 10800,
        "two_inertia_frequency_Hz": result.two_inertia_Hz,
        "two_inertia_definition": "sqrt(k / J_out) / (2 pi): k the tangent rigidity at the "
                                  "torque (input held), J_out the load and the output's own",
        "modes": modes,
        "frequency_by_torque_Hz": {f"{t:.6g}": v for t, v in result.by_torque.items()},
        "bodies": result.bodies.rows(),
        "speed_range_rpm": list(result.speed_range_rpm),
        "output_per_input": result.output_per_input,
        "te_orders": result.orders, "crossings": result.crossings,
        "torque_bandwidth": result.bandwidth, "warnings": result.warnings}


def modes_figure(result: ModesResult):
    """The first modes: each one's shape (every coordinate, scaled to its largest) and its
    strain-energy shares.

    Parameters
    ----------
    result : ModesResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    m = result.modes
    shown = [i for i in range(m.frequency_Hz.size) if m.frequency_Hz[i] > 0][:MODES_DRAWN]
    fig, axes = plt.subplots(len(shown), 2, figsize=(13, 2.6 * len(shown) + 0.8),
                             gridspec_kw={"width_ratios": [3, 1.3]}, squeeze=False)
    x = np.arange(len(m.names))
    for row, i in enumerate(shown):
        ax, bx = axes[row]
        v = m.shapes[:, i] / max(np.max(np.abs(m.shapes[:, i])), 1e-300)
        ax.bar(x, v, color="tab:blue")
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel("shape [-]", fontsize=8)
        ax.set_title(f"mode {i + 1}: {m.frequency_Hz[i]:.4g} Hz", fontsize=10, loc="left")
        ax.set_xticks(x)
        ax.set_xticklabels(m.names if row == len(shown) - 1 else [""] * len(x),
                           rotation=90, fontsize=7)
        ax.set_xlim(-0.6, len(x) - 0.4)
        shares = sorted(m.shares[i].items(), key=lambda kv: kv[1])
        bx.barh([g for g, _ in shares], [100 * s for _, s in shares], color="tab:orange")
        bx.set_xlim(0, 100)
        bx.tick_params(axis="y", labelsize=8)
        if row == len(shown) - 1:
            bx.set_xlabel("strain energy [%]")
    inp = "input free" if result.input_free else "input held"
    fig.suptitle(f"{result.case_name}: first modes at {result.torque_Nm:g} N m, {inp}, "
                 f"load {result.load_kgm2:g} kg m², motor {result.motor_kgm2:g} kg m²\n"
                 "shape: each coordinate (translations [m], rotations [rad]) over the "
                 "largest; right: the mode's strain energy by part", fontsize=10)
    fig.tight_layout()
    return fig


def campbell_figure(result: ModesResult):
    """The Campbell diagram, log-log (the orders are parallel lines of slope 1): each TE
    order's excitation frequency against input speed (line width by its amplitude; dotted:
    a line the TE spectrum does not carry), the modes as horizontal lines (dotted grey: at
    the other torques), the crossings inside the speed range marked (filled: warned).

    Parameters
    ----------
    result : ModesResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(11, 7))
    hi = result.speed_range_rpm[1]
    n = np.geomspace(hi * SPEED_DECADES, 1.25 * hi, 2)
    top_a = max((o["amplitude_arcsec"] for o in result.orders), default=0.0) or 1.0
    freqs = [f for fs in result.by_torque.values() for f in fs if f > 0]
    orders = [o["order"] for o in result.orders]
    f_lo = min([n[0] / 60 * result.output_per_input * min(orders, default=1.0)] + freqs)
    f_hi = max([n[1] / 60 * result.output_per_input * max(orders, default=1.0)] + freqs)
    cmap = plt.get_cmap("tab10")
    def base_of(o):                   # a named order's family, the other lines one label
        name = o["name"].split(" x ", 1)[-1]
        return "other lines of the TE spectrum" if o["harmonic"] == 0 else name

    names = sorted({base_of(o) for o in result.orders})
    drawn = set()
    for o in result.orders:
        base = base_of(o)
        carried = o["amplitude_arcsec"] >= CARRIED_REL * top_a
        ax.plot(n, n / 60 * result.output_per_input * o["order"],
                lw=0.7 + 2.8 * o["amplitude_arcsec"] / top_a,
                color=cmap(names.index(base) % 10), ls="-" if carried else ":",
                label=base if base not in drawn else None)
        drawn.add(base)
    labels = []
    for t, fs in result.by_torque.items():
        for i, f in enumerate(fs):
            if f <= 0:
                continue
            if t == result.torque_Nm:
                ax.axhline(f, color="0.2", lw=1.0)
                if i < MODES_LABELLED:
                    labels.append((f, f"mode {i + 1}: {f:.4g} Hz"))
            else:
                ax.axhline(f, color="0.6", lw=0.6, ls=":")
    for c in result.crossings:
        ax.plot(c["speed_rpm"], c["frequency_Hz"], "o", ms=8 if c["warned"] else 4,
                mfc="red" if c["warned"] else "none", mec="red", zorder=5)
    ax.axvspan(max(result.speed_range_rpm[0], n[0]), hi, color="tab:green", alpha=0.07,
               label="the case's speed range")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(n[0], n[1])
    ax.set_ylim(0.8 * f_lo, 1.25 * f_hi)
    _spread_labels(ax, labels, 1.27 * hi)
    ax.set_xlabel("input speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    inp = "input free" if result.input_free else "input held"
    ax.set_title(f"{result.case_name}\nCampbell diagram: TE orders (width: amplitude; "
                 f"dotted: not in the spectrum), modes at {result.torque_Nm:g} N m, {inp} "
                 "(dotted grey: at the other torques); red: crossings (filled: warned)",
                 fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig


#: Least distance between two mode labels on the Campbell diagram's log axis, as a share of
#: the axis' height in decades (a 7-point line on the figure's about 6-inch axis).
LABEL_GAP = 0.025


def _spread_labels(ax, labels, x) -> None:
    """Each mode's label at its frequency, moved just enough to clear its neighbours (close
    modes would print on each other) and kept inside the axis; the text holds the frequency
    itself."""
    lo, hi = (math.log10(v) for v in ax.get_ylim())
    gap = LABEL_GAP * (hi - lo)
    ordered = sorted(labels)
    ys: list[float] = []
    for f, _ in ordered:                        # up, clear of the one below
        ys.append(max(math.log10(f), ys[-1] + gap) if ys else math.log10(f))
    top = hi - gap / 2
    for k in range(len(ys) - 1, -1, -1):        # down, below the axis' top and the one above
        ys[k] = min(ys[k], top if k == len(ys) - 1 else ys[k + 1] - gap)
    for (_, text), y in zip(ordered, ys):
        ax.text(x, 10 ** y, text, va="center", fontsize=7)


def modes_figures(result: ModesResult) -> dict:
    """File name -> figure.

    Parameters
    ----------
    result : ModesResult

    Returns
    -------
    dict
    """
    out = {"modes.png": modes_figure(result)}
    if result.orders:
        out["campbell.png"] = campbell_figure(result)
    return out


def write_modes(result: ModesResult, folder) -> dict:
    """modes.csv, bodies.csv, campbell.csv (orders and crossings), modes.png,
    campbell.png and summary.json into ``folder`` (it must exist).

    Parameters
    ----------
    result : ModesResult
    folder : path

    Returns
    -------
    dict
        The summary with the files written (``files``).
    """
    folder = Path(folder)
    m = result.modes
    groups = sorted({g for s in m.shares for g in s})
    with open(folder / "modes.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mode", "frequency_Hz", "min_over_mesh_Hz", "max_over_mesh_Hz"]
                   + [f"share_{g.replace(' ', '_')}" for g in groups])
        for i, f in enumerate(m.frequency_Hz):
            w.writerow([i + 1, f"{f:.9g}", *(f"{v:.9g}" for v in result.frequency_range_Hz[i]),
                        *(f"{m.shares[i].get(g, 0.0):.6g}" for g in groups)])
    with open(folder / "bodies.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["body", "mass_kg", "inertia_kgm2", "formula"])
        for r in result.bodies.rows():
            w.writerow([r["name"], f"{r['mass_kg']:.9g}", f"{r['inertia_kgm2']:.9g}",
                        r["formula"]])
    files = ["modes.csv", "bodies.csv"]
    if result.orders:
        with open(folder / "campbell.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["order_name", "order_per_output_rev", "amplitude_arcsec", "mode",
                        "frequency_Hz", "crossing_speed_rpm", "warned"])
            for c in result.crossings:
                w.writerow([c["order_name"], f"{c['order']:.9g}",
                            f"{c['amplitude_arcsec']:.6g}", c["mode"],
                            f"{c['frequency_Hz']:.9g}", f"{c['speed_rpm']:.9g}",
                            c["warned"]])
        files.append("campbell.csv")
    for name, fig in modes_figures(result).items():
        save(fig, folder / name, dpi=120)
        files.append(name)
    out = summary(result)
    out["files"] = files + ["summary.json"]
    (folder / "summary.json").write_text(finite_json(out) + "\n", encoding="utf-8")
    return out


def finite_json(summary: dict) -> str:
    """The modes' summary as strict JSON (a float that is not finite written null; the
    ``self_locking`` flag beside a backdrive torque says why).

    Parameters
    ----------
    summary : dict

    Returns
    -------
    str
    """
    from ..efficiency.loop.report import jsonable
    return json.dumps(jsonable(summary), indent=2, allow_nan=False)


def dynamic_summary(dr) -> dict:
    """The dynamic sweep's summary (summary.json's ``dynamic``).

    Parameters
    ----------
    dr : toothfem.dynamic_response.DynamicResponse

    Returns
    -------
    dict
    """
    return {"method": dr.method, "damping_ratio": dr.damping_ratio,
            "damping_source": dr.damping_source, "output_torque_Nm": dr.torque_Nm,
            "load_inertia_kgm2": dr.load_kgm2,
            "static_te_peak_to_peak_arcsec": dr.static_te_pp_arcsec,
            "speeds_rpm": dr.speeds_rpm.tolist(),
            "te_peak_to_peak_arcsec": dr.te_pp_arcsec.tolist(),
            "torque_ripple_peak_to_peak_Nm": dr.ripple_pp_Nm.tolist(),
            "crossings": dr.crossings}


def dynamic_figure(dr):
    """Dynamic TE and output torque ripple (peak to peak) against input speed, the static
    TE, the crossings named.

    Parameters
    ----------
    dr : toothfem.dynamic_response.DynamicResponse

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(10, 8), sharex=True)
    ax.plot(dr.speeds_rpm, dr.te_pp_arcsec, "-o", ms=3, label="dynamic TE")
    ax.axhline(dr.static_te_pp_arcsec, color="0.4", ls="--", label="static TE")
    bx.plot(dr.speeds_rpm, dr.ripple_pp_Nm, "-o", ms=3, color="tab:red")
    for i, c in enumerate(dr.crossings):
        for axis, v in ((ax, c["te_pp_arcsec"]), (bx, c["ripple_pp_Nm"])):
            axis.plot(c["speed_rpm"], v, "D", color="k", ms=5)
        ax.annotate(f"{i + 1}", (c["speed_rpm"], c["te_pp_arcsec"]), fontsize=8,
                    xytext=(4, 4), textcoords="offset points")
    names = "; ".join(f"{i + 1}: {c['order_name']} x mode {c['mode']}"
                      for i, c in enumerate(dr.crossings))
    ax.set_xscale("log")
    ax.set_ylabel("TE peak to peak [arcsec]")
    bx.set_ylabel("output torque ripple\npeak to peak [N m]")
    bx.set_xlabel("input speed [rpm]")
    ax.legend(fontsize=8)
    ax.set_title(f"{dr.case_name}\ndynamic TE and torque ripple at {dr.torque_Nm:g} N m, "
                 f"load {dr.load_kgm2:g} kg m², damping ratio {dr.damping_ratio:g}",
                 fontsize=9)
    if names:
        fig.text(0.01, 0.005, "\n".join(textwrap.wrap("crossings: " + names, 150)),
                 fontsize=7)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    return fig


def write_dynamic(dr, folder) -> list:
    """dynamic.csv and dynamic.png into ``folder``.

    Parameters
    ----------
    dr : toothfem.dynamic_response.DynamicResponse
    folder : path

    Returns
    -------
    list of str
        The files written.
    """
    folder = Path(folder)
    with open(folder / "dynamic.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["input_speed_rpm", "te_pp_arcsec", "torque_ripple_pp_Nm"])
        for row in dr.rows():
            w.writerow([f"{v:.9g}" for v in row])
    save(dynamic_figure(dr), folder / "dynamic.png", dpi=120)
    return ["dynamic.csv", "dynamic.png"]
