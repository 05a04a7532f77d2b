"""Pictures and text of the tolerance ensemble (``toothfem tolerance``): the distribution of
each output with the nominal design and the percentiles marked, and the share of each
tolerance in each output's variance."""
from __future__ import annotations

import numpy as np

from ..tolerance import ALONE_OVER_ALL
from . import pyplot, wrap


def histograms(result, outputs: dict, title: str):
    """One histogram per output over the sampled reducers, the nominal design (black) and
    P50/P90/P99 (dashed) marked.

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
        for (q, x), colour in zip(pct[k].items(), ("tab:green", "tab:orange", "tab:red")):
            ax.axvline(x, color=colour, ls="--", lw=1.2, label=f"{q} {x:{fmt}}")
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
             "| output | nominal | P50 | P90 | P99 |", "|---|---|---|---|---|"]
    for k, (label, unit) in outputs.items():
        p = summary["percentiles"][k]
        fmt = ".3f" if unit == "%" else ".4g"      # efficiencies near 100 %: decimals
        lines.append(f"| {label} [{unit}] | {summary['nominal'][k]:{fmt}} | "
                     f"{p['P50']:{fmt}} | {p['P90']:{fmt}} | {p['P99']:{fmt}} |")
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
        (label, unit, {"nominal", "P50", "P90", "P99"}).
    """
    quantiles = ("P50", "P90", "P99")
    return [(label, unit, {"nominal": summary["nominal"][k],
                           **{q: summary["percentiles"][k].get(q) for q in quantiles}})
            for k, (label, unit) in outputs.items() if k in summary["percentiles"]]
