"""Pictures and text of the tolerance ensemble (``toothfem tolerance``): the distribution of
each output with the nominal design and the percentiles marked, and the share of each
tolerance in each output's variance."""
from __future__ import annotations

import numpy as np

from ..tolerance import ALONE_OVER_ALL
from . import pyplot, wrap


def histograms(result, outputs: dict, title: str):
    """One histogram per output over the sampled reducers, the nominal design (black) and
    the median and the unfavourable tail's percentiles (P90/P99, or P10/P1 where low is
    worse; dashed, their 95 % interval shaded) marked; a percentile the sample is too small
    for is named with the reducers it needs.

    Parameters
    ----------
    result : toothfem.tolerance.ToleranceResult
    outputs : dict
        {column: (label, unit)} of the outputs to draw.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    keys = list(outputs)
    cols = 2
    rows = (len(keys) + 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(11, 2.9 * rows))
    pct = result.percentiles()
    for ax, k in zip(axes.flat, keys):
        label, unit = outputs[k]
        fmt = ".3f" if unit == "%" else ".4g"      # efficiencies near 100 %: decimals
        v = result.samples[k]
        ax.hist(v, bins=min(40, max(8, v.size // 10)), color="tab:blue", alpha=0.7,
                label=f"{v.size} built reducers")
        ax.axvline(result.nominal[k], color="k", lw=1.5,
                   label=f"nominal {result.nominal[k]:{fmt}}")
        for (q, p), colour in zip(pct[k].items(), ("tab:green", "tab:orange", "tab:red")):
            if p["value"] is None:
                ax.plot([], [], " ", label=f"{q}: needs {p['rings_needed']} reducers")
                continue
            lo, hi = p["ci"]
            ax.axvspan(lo, hi, color=colour, alpha=0.15, lw=0)
            ax.axvline(p["value"], color=colour, ls="--", lw=1.2,
                       label=f"{q} {p['value']:{fmt}} [{lo:{fmt}}, {hi:{fmt}}]")
        ax.ticklabel_format(axis="x", useOffset=False)     # values, not offsets from them
        ax.set_xlabel(f"{label} [{unit}]")
        ax.set_ylabel("reducers")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    for ax in list(axes.flat)[len(keys):]:
        ax.set_visible(False)
    fig.suptitle(wrap(title, 110), fontsize=10)
    fig.tight_layout()
    return fig


def shares(result, outputs: dict, title: str):
    """Horizontal bars: for each output, the share of its variance due to each tolerance
    alone (runs with one tolerance at a time).

    Parameters
    ----------
    result : toothfem.tolerance.ToleranceResult
        Its ``shares`` (ALONE_OVER_ALL left out).
    outputs : dict
        {column: (label, unit)}, one group of bars each.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    names = [n for n in result.shares if n != ALONE_OVER_ALL]
    keys = list(outputs)
    fig, ax = plt.subplots(figsize=(10, 0.55 * len(keys) * max(1, len(names)) / 2 + 2))
    height = 0.8 / max(len(names), 1)
    y = np.arange(len(keys))
    for i, name in enumerate(names):
        vals = [100 * result.shares[name][k] for k in keys]
        ax.barh(y + i * height, vals, height=height, label=name.replace("_", " "))
    ax.set_yticks(y + 0.4 - height / 2)
    ax.set_yticklabels([f"{outputs[k][0]} [{outputs[k][1]}]" for k in keys], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(0, 100)
    ax.set_xlabel("share of the output's variance from this tolerance alone [%]")
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="tolerance")
    ax.set_title(wrap(title, 100), fontsize=10)
    return fig


def markdown(summary: dict, outputs: dict) -> str:
    """report.md of the ensemble: settings, percentiles beside the nominal, shares.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance.ToleranceResult.summary` with ``share_samples``.
    outputs : dict
        {column: (label, unit)}, one table row each.

    Returns
    -------
    str
        Markdown.
    """
    lines = [f"# Tolerance ensemble: {summary['case']}", "",
             f"{summary['samples']} built reducers (seed {summary['seed']}, "
             f"{summary['distribution']} distributions), {summary['positions']} positions "
             f"spread over the pairing period of {summary['pairing_period_pitches']} "
             f"meshing periods; operating point {summary['operating_speed_rpm']:.6g} rpm, "
             f"{summary['operating_output_torque_Nm']:.6g} N m; lost motion at "
             f"+-3 % of {summary['rated_torque_Nm']:.6g} N m.", "",
             "Tolerances [mm]: " + ", ".join(f"{k} = {v:g}" for k, v in
                                             summary["tolerances_mm"].items()), "",
             "Percentiles on each output's unfavourable side (1 in 10 and 1 in 100 of the "
             "built reducers worse than the value: P90 and P99 where high is worse, P10 and "
             "P1 where low is), each with its 95 % confidence interval from the sample "
             "count (distribution-free, order statistics); a percentile the sample is too "
             "small for is not given.", "",
             "| output | nominal | " + " | ".join(TAIL_COLUMNS) + " |",
             "|---|---|---|---|---|"]
    for label, unit, cells in summary_rows(summary, outputs):
        lines.append(f"| {label} [{unit}] | {_md_number(cells['nominal'], unit)} | "
                     + " | ".join(cells[c] for c in TAIL_COLUMNS) + " |")
    shares = summary["variance_shares"]
    names = [n for n in shares if n != ALONE_OVER_ALL]
    if len(names) > 1:
        lines += ["", f"Share of each output's variance from each tolerance alone "
                  f"({summary['share_samples']} reducers per tolerance), normalised over "
                  "the tolerances (a ranking); the last column sums the one-tolerance "
                  "variances over the whole ensemble's: 1 where the tolerances add up, "
                  "above 1 where they mask each other (one tolerance's interference already "
                  "decides which pins carry), below 1 where they compound:",
                  "", "| output | " + " | ".join(names) + " | sum alone / all |",
                  "|---" * (len(names) + 2) + "|"]
        for k, (label, unit) in outputs.items():
            lines.append(f"| {label} | " + " | ".join(f"{100 * shares[n][k]:.0f} %"
                                                      for n in names)
                         + f" | {shares[ALONE_OVER_ALL][k]:.2f} |")
    lines += ["", "Files: samples.csv (one row per reducer), summary.json, histograms.png, "
              "shares.png.", ""]
    return "\n".join(lines)


def summary_rows(summary: dict, outputs: dict) -> list:
    """The ensemble's key figures as rows of :func:`toothfem.report.summary.text`: each
    output's nominal value and percentiles.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance.ToleranceResult.summary`.
    outputs : dict
        Column -> (label, unit) (:data:`toothfem.tolerance.OUTPUTS`).

    Returns
    -------
    list of (str, str, dict)
        (label, unit, {"nominal": float, and per TAIL_COLUMNS the percentile's text with
        its 95 % interval, or the reducers it needs}).
    """
    rows = []
    for k, (label, unit) in outputs.items():
        if k not in summary["percentiles"]:
            continue
        cells = {"nominal": summary["nominal"][k]}
        for column, (q, p) in zip(TAIL_COLUMNS, summary["percentiles"][k].items()):
            cells[column] = _percentile_text(q, p, unit)
        rows.append((label, unit, cells))
    return rows


#: The columns of the percentile table: the median and the unfavourable tail.
TAIL_COLUMNS = ("median", "1 in 10 worse than", "1 in 100 worse than")


def _md_number(value, unit: str) -> str:
    return f"{value:{'.3f' if unit == '%' else '.4g'}}"     # efficiencies: decimals


def _percentile_text(q: str, p: dict, unit: str) -> str:
    """'P90 1234 [1200, 1260]', or 'P99: needs 368 reducers'."""
    if p["value"] is None:
        return f"{q}: needs {p['rings_needed']} reducers"
    lo, hi = p["ci"]
    return (f"{q} {_md_number(p['value'], unit)} [{_md_number(lo, unit)}, "
            f"{_md_number(hi, unit)}]")
