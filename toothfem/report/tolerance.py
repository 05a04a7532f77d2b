"""Pictures and text of the tolerance ensemble (``toothfem tolerance``): each output's
distribution with the nominal and percentiles marked, each tolerance's variance share."""
from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..quantities import ALONE_OVER_ALL, side_of
from . import NBSP, pyplot, save, wrap
from .tolerance_table import (  # noqa: F401  (summary_rows, TAIL_COLUMNS: the API's)
    TAIL_COLUMNS, _row_values, _tail_of, number_format, screen_table, summary_rows)

if TYPE_CHECKING:      # annotations only: the record's .write() calls this module
    from ..tolerance_result import ToleranceResult

#: A value marked on a histogram (the nominal design, a limit) farther outside the sample's
#: range than this many of its spans is drawn as an arrow at the axis' edge with its value:
#: widening the axis to it would crush the sample's bins into a spike.
FAR = 1.5
#: Margin of a histogram's x-axis beyond the outermost value drawn, as a fraction of the
#: range shown: no marked line lies on the frame.
MARGIN = 0.05
#: The count axis' top over the highest bar where an arrow marks a value off the axis: the
#: arrows sit above the bars.
HEADROOM = 1.35
#: Colour of each percentile's line by its tail: the median, 1 in 10, 1 in 100.
TAIL_COLOURS = {50: "tab:green", 10: "tab:orange", 90: "tab:orange", 1: "tab:red",
                99: "tab:red"}
#: Colour of a limit's line (the allowable contact stress).
LIMIT_COLOUR = "tab:purple"
#: Characters per line of an axis label, a legend entry and a title.
LABEL_WIDTH, LEGEND_WIDTH, TITLE_WIDTH = 58, 40, 110


def _glued(text: str) -> str:
    """``text`` with no-break spaces: one unit :func:`toothfem.report.wrap` never breaks."""
    return text.replace(" ", NBSP)


def operating_text(summary: dict) -> str:
    """'operating point 40 N m output, 1500 rpm input' of an ensemble's summary.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.

    Returns
    -------
    str
        '' where the summary has no operating point.
    """
    t, n = summary.get("operating_output_torque_Nm"), summary.get("operating_speed_rpm")
    if t is None or n is None:
        return ""
    return f"operating point {t:.4g} N m output, {n:.4g} rpm input"


def model_text(summary: dict) -> str:
    """Which model solved the rings, at which positions (one line).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.

    Returns
    -------
    str
    """
    member = summary.get("member", "disc")
    several = summary.get("members", 2) > 1
    model = (f"system model (every {member} free on its supports, the split between them "
             "solved)" if several else f"system model (the {member} free on its supports)")
    where = (f", {summary['positions']} positions over the pairing period of "
             f"{summary['pairing_period_pitches']} meshing periods"
             if "positions" in summary and "pairing_period_pitches" in summary else "")
    return model + where


def _zones(summary: dict) -> list:
    """Each nonzero tolerance zone as one glued phrase ("pin position 0.005 mm"), its own
    distribution in brackets where it has one."""
    own = summary.get("distributions") or {}
    out = []
    for k, v in summary.get("tolerances_mm", {}).items():
        name = k[:-3]
        base = name.removesuffix("_lower").removesuffix("_upper")
        extra = f" ({own[base]})" if base in own else ""
        out.append(_glued(f"{name.replace('_', ' ')} {v:g} mm{extra}"))
    return out


def histograms_title(summary: dict) -> str:
    """The title of histograms.png: the case and the sample; the tolerance zones, the title
    broken only between them; the operating point and the model.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.

    Returns
    -------
    str
        Lines separated by newlines (wrap each with :func:`toothfem.report.wrap`).
    """
    lines = [f"{summary['case']}: {summary['samples']} built reducers "
             f"({summary.get('distribution', 'normal')} distributions)",
             "tolerances: " + ", ".join(_zones(summary))]
    op = operating_text(summary)
    lines.append("; ".join(x for x in (op, model_text(summary)) if x))
    return "\n".join(lines)


def shares_title(summary: dict) -> str:
    """The title of shares.png: the case, the operating point and how many reducers each
    one-tolerance run had (the shares a ranking).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.

    Returns
    -------
    str
    """
    n = summary.get("share_samples", 0)
    lines = [f"{summary['case']}: where the scatter comes from",
             "; ".join(x for x in (operating_text(summary), model_text(summary)) if x),
             "each tolerance alone in " + _glued(f"{n} built reducers") + ": its variance "
             "over the tolerances' sum, a ranking (few reducers: a rough one, not a "
             "decomposition)"]
    return "\n".join(lines)


def histograms(result, outputs: dict, title: str):
    """One histogram per output over the sampled reducers, the nominal design (black), the
    median and the unfavourable tail's percentiles (P90/P99, or P10/P1 where low is worse,
    both tails of a two-sided output; dashed, their 95 % interval shaded) and the limits
    (``result.limits``: the allowable contact stress on the pressure's) marked; a
    percentile the sample is too small for is named with the reducers it needs. A marked
    value far outside the sample's range (FAR) is an arrow at the axis' edge with its value;
    the x-axis reaches MARGIN past every line drawn; counts have integer ticks.

    Parameters
    ----------
    result : toothfem.tolerance_result.ToleranceResult
    outputs : dict
        {column: (label, unit)} of the outputs to draw.
    title : str
        Lines separated by newlines, each wrapped.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.ticker import MaxNLocator

    plt = pyplot()
    keys = list(outputs)
    cols = 2
    rows = (len(keys) + 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(11.5, 3.2 * rows), squeeze=False)
    pct = result.percentiles()
    limits = getattr(result, "limits", {}) or {}
    for ax, k in zip(axes.flat, keys):
        label, unit = outputs[k]
        v = np.asarray(result.samples[k], float)
        nominal = float(result.nominal[k])
        fmt = number_format(_row_values(nominal, pct[k]), unit)
        counts = k == "contacts_min" and np.all(v == np.round(v))
        lo, hi = float(np.min(v)), float(np.max(v))
        span = hi - lo or max(abs(hi) * 0.1, 1.0 if counts else 1e-9)
        near = lambda x, lo=lo, hi=hi, span=span: lo - FAR * span <= x <= hi + FAR * span  # noqa: E731
        shown_unit = f" {unit}" if unit not in ("-", "") else ""
        marks: list[dict[str, Any]] = [
            {"value": nominal, "text": f"nominal {nominal:{fmt}}", "colour": "k",
             "ls": "-", "short": f"nominal {nominal:{fmt}}{shown_unit}"}]
        for q, p in pct[k].items():
            if p["value"] is None:
                marks.append({"value": None, "text": f"{q}: needs {p['rings_needed']} "
                                                     "reducers"})
                continue
            lo_ci, hi_ci = p["ci"]
            side = ""
            if side_of(k) == "both" and q != "P50":
                side = " (low side)" if _tail_of(q) < 50 else " (high side)"
            marks.append({"value": p["value"], "ci": (lo_ci, hi_ci), "ls": "--",
                          "colour": TAIL_COLOURS[_tail_of(q)],
                          "text": f"{q}{side} {p['value']:{fmt}} [{lo_ci:{fmt}}, "
                                  f"{hi_ci:{fmt}}]",
                          "short": f"{q} {p['value']:{fmt}}{shown_unit}"})
        for i, lim in enumerate(limits.get(k, ())):
            if i > 0 and not near(lim["value"]):
                continue                   # beyond the first limit: drawn only in range
            marks.append({"value": lim["value"], "colour": LIMIT_COLOUR,
                          "ls": "-." if i == 0 else ":",
                          "text": f"{lim['name']} {lim['value']:.4g} {lim['unit']} "
                                  f"({lim['source']})",
                          "short": f"{lim['name']} {lim['value']:.4g} {lim['unit']}"})
        for m in marks:
            m["far"] = m["value"] is not None and not near(m["value"])
        shown = [m for m in marks if m["value"] is not None and not m["far"]]
        x0 = min([lo] + [m["value"] for m in shown] + [m["ci"][0] for m in shown if "ci" in m])
        x1 = max([hi] + [m["value"] for m in shown] + [m["ci"][1] for m in shown if "ci" in m])
        if counts:                         # whole bars around each count
            x0, x1 = min(x0, lo - 0.5), max(x1, hi + 0.5)
        pad = MARGIN * ((x1 - x0) or span)
        bins: np.ndarray | list[float]
        if counts:
            bins = np.arange(lo - 0.5, hi + 1.5)
        elif hi > lo:
            bins = np.linspace(lo, hi, min(40, max(8, v.size // 10)) + 1)
        else:
            bins = [lo - 0.5 * pad, lo + 0.5 * pad]
        ax.hist(v, bins=bins, color="tab:blue", alpha=0.7, label=f"{v.size} built reducers")
        arrows = {"left": 0, "right": 0}
        for m in marks:
            if m["value"] is None:
                ax.plot([], [], " ", label=m["text"])
            elif m["far"]:
                side = "left" if m["value"] < lo else "right"
                ax.plot([], [], color=m["colour"], ls=m["ls"], lw=1.5,
                        label=f"{m['text']}: off the axis ({side} arrow)")
                _edge_arrow(ax, side, 0.93 - 0.08 * arrows[side], m["short"], m["colour"])
                arrows[side] += 1
            else:
                if "ci" in m:
                    ax.axvspan(*m["ci"], color=m["colour"], alpha=0.15, lw=0)
                limit = m["colour"] == LIMIT_COLOUR
                ax.axvline(m["value"], color=m["colour"], ls=m["ls"],
                           lw=1.8 if limit else 1.5 if m["colour"] == "k" else 1.2,
                           zorder=4 if limit else None, label=m["text"])
        ax.set_xlim(x0 - pad, x1 + pad)
        if any(arrows.values()):           # room above the bars for the arrows
            ax.set_ylim(0, ax.get_ylim()[1] * HEADROOM)
        ax.ticklabel_format(axis="x", useOffset=False)     # values, not offsets from them
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        if counts:
            ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_xlabel(wrap(f"{label} [{unit}]", LABEL_WIDTH), fontsize=9)
        ax.set_ylabel("reducers")
        ax.grid(alpha=0.3)
        if unit == "%":                    # long tick labels (99.9955): fewer of them
            ax.xaxis.set_major_locator(MaxNLocator(nbins=4))
        handles, texts = ax.get_legend_handles_labels()
        ax.legend(handles, [wrap(x, LEGEND_WIDTH) for x in texts], fontsize=7,
                  loc="upper left", bbox_to_anchor=(1.01, 1.0))
    for ax in list(axes.flat)[len(keys):]:
        ax.set_visible(False)
    fig.suptitle(wrap(title, TITLE_WIDTH), fontsize=10)
    fig.tight_layout()
    return fig


def _edge_arrow(ax, side: str, y: float, text: str, colour) -> None:
    """An arrow at the ``side`` edge of the axes (axes fraction ``y``) pointing out to a
    value beyond it, with its text."""
    tip, tail = (0.0, 0.13) if side == "left" else (1.0, 0.87)
    ax.annotate(text, xy=(tip, y), xytext=(tail, y), xycoords="axes fraction",
                textcoords="axes fraction", ha="left" if side == "left" else "right",
                va="center", fontsize=7, color=colour,
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": colour, "lw": 0.6},
                arrowprops={"arrowstyle": "->", "color": colour, "lw": 1.5})


def shares(result, outputs: dict, title: str):
    """Horizontal bars: for each output, the share of its variance due to each tolerance
    alone (runs with one tolerance at a time); an output none of those runs scatters says
    "no scatter" (and whether the whole ensemble does).

    Parameters
    ----------
    result : toothfem.tolerance_result.ToleranceResult
        Its ``shares`` (ALONE_OVER_ALL left out).
    outputs : dict
        {column: (label, unit)}, one group of bars each.
    title : str
        Lines separated by newlines, each wrapped.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    names = [n for n in result.shares if n != ALONE_OVER_ALL]
    keys = list(outputs)
    n_alone = result.settings.get("share_samples", 0)
    group = max(0.75, 0.2 * len(names) + 0.25)
    fig, ax = plt.subplots(figsize=(11, group * len(keys) + 1.6))
    height = 0.8 / max(len(names), 1)
    y = np.arange(len(keys))
    for i, name in enumerate(names):
        vals = [100 * result.shares[name][k] for k in keys]
        ax.barh(y + i * height, vals, height=height, label=name.replace("_", " "))
    for j, k in enumerate(keys):
        if names and sum(result.shares[n][k] for n in names) == 0:
            whole = float(np.var(result.samples[k])) if k in result.samples else 0.0
            note = ("no scatter: every built reducer gives the same value" if whole == 0
                    else f"no scatter with any tolerance alone ({n_alone} reducers each); "
                         "the whole ensemble's comes from the tolerances together")
            ax.text(1, j + 0.4 - height / 2, note, va="center", ha="left", fontsize=8,
                    style="italic", color="0.3")
    ax.set_yticks(y + 0.4 - height / 2)
    ax.set_yticklabels([wrap(f"{outputs[k][0]} [{outputs[k][1]}]", LABEL_WIDTH)
                        for k in keys], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(0, 100)
    ax.set_xlabel("share of the output's variance from this tolerance alone [%] "
                  "(normalised over the tolerances: a ranking)")
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="tolerance")
    ax.set_title(wrap(title, 100), fontsize=10)
    return fig


def markdown(summary: dict, outputs: dict) -> str:
    """report.md of the ensemble: settings (the model and positions, and why the nominal
    differs from ``toothfem contact`` and ``toothfem run``), percentiles beside the nominal,
    the limits checked and passed, shares.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary` with ``share_samples``.
    outputs : dict
        {column: (label, unit)}, one table row each.

    Returns
    -------
    str
        Markdown.
    """
    member = summary.get("member", "disc")
    several = summary.get("members", 2) > 1
    model = ("Every output is the system model's: the whole reducer at the operating "
             + (f"torque, every {member} free on its supports, the split between them "
                f"solved (no load factor); the forces, pressures and counts are the worst "
                f"over every {member}, the efficiencies take the first {member}'s loads "
                f"for every {member}. " if several else
                f"torque, the {member} free on its supports. "))
    differs = (f"The nominal design's figures are therefore not `toothfem contact`'s, "
               f"whose contacts and forces are one {member} held at its bearing seats over "
               "one pitch, nor `toothfem run`'s efficiency, whose loads are the analytic "
               f"split (or that held {member}'s FE loads): a {member} free on its "
               "bearings carries its torque on another set of contacts, with another sum "
               "of contact forces, so its contact and bearing losses differ")
    ref = summary.get("nominal_total_efficiency_analytic_loads_pct")
    nominal_eta = summary.get("nominal", {}).get("total_efficiency_pct")
    if ref is not None and nominal_eta is not None:
        differs += (f" (total efficiency of the nominal design {nominal_eta:.2f} % here, "
                    f"{ref:.2f} % with the analytic loads at the same operating point)")
    model += differs + ". "
    lines = [f"# Tolerance ensemble: {summary['case']}", "",
             f"{summary['samples']} built reducers (seed {summary['seed']}, "
             f"{summary['distribution']} distributions), {summary['positions']} positions "
             f"spread over the pairing period of {summary['pairing_period_pitches']} "
             f"meshing periods (every pin meets every lobe); operating point "
             f"{summary['operating_speed_rpm']:.6g} rpm, "
             f"{summary['operating_output_torque_Nm']:.6g} N m; lost motion at "
             f"+-3 % of {summary['rated_torque_Nm']:.6g} N m. " + model, "",
             "Tolerances [mm]: " + ", ".join(f"{k} = {v:g}" for k, v in
                                             summary["tolerances_mm"].items()), "",
             "Percentiles on each output's unfavourable side (1 in 10 and 1 in 100 of the "
             "built reducers worse than the value: P90 and P99 where high is worse, P10 and "
             "P1 where low is; both for the backlash, whose low side is interference and "
             "high side play), each with its 95 % confidence interval from the sample "
             "count (distribution-free, order statistics); a percentile the sample is too "
             "small for is not given.", "",
             "| output | nominal | " + " | ".join(TAIL_COLUMNS) + " |",
             "|---|---|---|---|---|"]
    for label, unit, cells in summary_rows(summary, outputs):
        lines.append(f"| {label} [{unit}] | {cells['nominal']} | "
                     + " | ".join(cells[c] for c in TAIL_COLUMNS) + " |")
    lines += ["", "## Limits checked", "", *limits_text(summary)]
    shares = summary["variance_shares"]
    names = [n for n in shares if n != ALONE_OVER_ALL]
    if len(names) > 1:
        lines += ["", f"Share of each output's variance from each tolerance alone "
                  f"({summary['share_samples']} reducers per tolerance: a ranking, rough with "
                  "so few), normalised over "
                  "the tolerances; the last column sums the one-tolerance "
                  "variances over the whole ensemble's: 1 where the tolerances add up, "
                  "above 1 where they mask each other (one tolerance's interference already "
                  "decides which pins carry), below 1 where they compound; \"no scatter\" "
                  "where no one-tolerance run varies:",
                  "", "| output | " + " | ".join(names) + " | sum alone / all |",
                  "|---" * (len(names) + 2) + "|"]
        for k, (label, _unit) in outputs.items():
            if sum(shares[n][k] for n in names) == 0:
                lines.append(f"| {label} | " + " | ".join("no scatter" for _ in names)
                             + " | – |")
                continue
            lines.append(f"| {label} | " + " | ".join(f"{100 * shares[n][k]:.0f} %"
                                                      for n in names)
                         + f" | {shares[ALONE_OVER_ALL][k]:.2f} |")
    found = summary.get("warnings") or []
    if found:
        lines += ["", "## Warnings", ""] + [f"- {w['message']}" for w in found]
    lines += ["", "Files: samples.csv (one row per reducer), summary.json, histograms.png, "
              "shares.png.", ""]
    return "\n".join(lines)


def limits_text(summary: dict) -> list:
    """The limits the ensemble was checked against, with the figures checked (the nominal
    design and each percentile given) and how many it passes (the warnings list them).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.

    Returns
    -------
    list of str
        Markdown lines (a list).
    """
    found = summary.get("warnings") or []
    out = []
    ph = summary.get("percentiles", {}).get("max_ph_MPa", {})
    lims = summary.get("limits", {}).get("max_ph_MPa", [])
    if lims and "max_ph_MPa" in summary.get("nominal", {}):
        figures = [f"nominal {summary['nominal']['max_ph_MPa']:.4g}"] + [
            f"{q} {p['value']:.4g}" for q, p in ph.items() if p["value"] is not None]
        out.append("- largest Hertz pressure P_h (" + ", ".join(figures) + " MPa) against "
                   + " and ".join(f"the {x['name']} {x['value']:.4g} {x['unit']} "
                                  f"({x['source']})" for x in lims)
                   + f": {_passed(found, 'Hertz pressure')}")
    for where, vals in (summary.get("film_ratio_lowest") or {}).items():
        lowest = ", ".join(
            f"{q} {'at least 1' if v is None else format(v, '.3g')}" for q, v in vals.items())
        out.append(f"- lowest film ratio of {where} ({lowest}) against 1 (boundary "
                   "lubrication) and 0.1 (the film carries next to nothing), "
                   "toothfem.limits: " + _passed(found, f"film ratio of {where}"))
    t = summary.get("operating_output_torque_Nm")
    if t is not None:
        out.append(f"- output torque {t:.4g} N m against the case's ratings "
                   "(operating.rated_torque_Nm, start_stop_torque_Nm, momentary_torque_Nm; "
                   "none where the case names none): " + _passed(found, "output torque"))
    return out or ["No limit applies to these outputs."]


def _passed(found: list, quantity: str) -> str:
    hits = [w for w in found if quantity in w["quantity"]]
    if not hits:
        return "within."
    return (f"passed by {len(hits)} of the figures (see the warnings): "
            + "; ".join(f"{w['value']:.4g} {w['unit']}".rstrip() for w in hits) + ".")


def tolerance_figures(result: ToleranceResult) -> dict:
    """The ensemble's pictures: the histograms of every output and, with several
    tolerances, each one's share of each output's variance.

    Parameters
    ----------
    result : ToleranceResult

    Returns
    -------
    dict
        File name -> matplotlib Figure.
    """
    outputs, summary = result.outputs(), result.summary()
    out = {"histograms.png": histograms(result, outputs, histograms_title(summary))}
    if len(result.shares) > 1:
        out["shares.png"] = shares(result, outputs, shares_title(summary))
    return out


def write_tolerance(result: ToleranceResult, folder) -> dict:
    """Write the ensemble's files.

    Parameters
    ----------
    result : ToleranceResult
    folder : str or pathlib.Path
        An existing folder; it receives samples.csv, summary.json, histograms.png,
        shares.png (several tolerances) and report.md.

    Returns
    -------
    dict
        The summary as written, with the names of the ``files``.
    """
    folder = Path(folder)
    outputs = result.outputs()
    with open(folder / "samples.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["sample", *outputs])
        for i in range(len(next(iter(result.samples.values())))):
            w.writerow([i, *(f"{result.samples[k][i]:.9g}" for k in outputs)])
    summary = result.summary()
    files = ["samples.csv", "summary.json", "histograms.png", "report.md"]
    for name, fig in tolerance_figures(result).items():
        save(fig, folder / name)
        if name == "shares.png":
            files.insert(3, name)
    summary["files"] = files
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    (folder / "report.md").write_text(markdown(summary, outputs))
    return summary
