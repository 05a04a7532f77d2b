"""Pictures and Markdown of the measured-data loop: a :class:`LoopReport` in, a figure or text
out (``toothfem loop`` writes them as residuals_before.png, residuals_after.png, report.md).

This is the one place the loop's Markdown is written; the JSON is the record's own
(:meth:`LoopReport.to_dict`).
"""
from __future__ import annotations

import math

import numpy as np

from ..efficiency.loop import LoopReport
from . import pyplot

#: Size [in] of one covariate's panel of the residual figure (legible at dpi 110).
PANEL_SIZE_IN = (4.2, 3.2)
#: Panels per row of the residual figure (three keep a page-wide figure legible).
MAX_COLUMNS = 3
#: Fewest points for the signature table: a correlation over fewer is +-1 or undefined.
MIN_POINTS_CORRELATION = 3



def plot_residuals(report: LoopReport, stage="before"):
    """Residual [efficiency points] against every covariate of the data.

    Parameters
    ----------
    report : LoopReport
        The loop's report (its covariates, residuals and trends).
    stage : {"before", "after"}
        ``"before"``: the baseline's residual; ``"after"``: the final model's held-out
        residuals (the ones that measure the model), or its fit residual when there was
        no selection.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per covariate, titled with the trend's R^2 and p-value (not shown).
    """
    plt = pyplot()
    if stage == "before":
        r, trends, title = report.baseline_fit.residual, report.trends_before, "baseline"
    else:
        r = report.final.residual if report.selection else report.final_fit.residual
        trends, title = report.trends_after, "after the loop (held-out)"
    covs = report.covariates
    k = max(len(covs), 1)
    cols = min(k, MAX_COLUMNS)
    rows = math.ceil(k / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(PANEL_SIZE_IN[0] * cols,
                                                  PANEL_SIZE_IN[1] * rows), squeeze=False)
    tr = {t.covariate: t for t in trends}
    for ax, (name, x) in zip(axes.flat, covs.items()):
        x = np.asarray(x)
        if x.dtype == object:
            levels = sorted(set(x.astype(str)))
            xi = np.array([levels.index(v) for v in x.astype(str)], float)
            ax.set_xticks(range(len(levels)), levels, rotation=45, fontsize=7)
            ax.plot(xi, 100 * r, ".", ms=4, alpha=0.7)
        else:
            ax.plot(x.astype(float), 100 * r, ".", ms=4, alpha=0.7)
        ax.axhline(0.0, color="k", lw=0.6)
        t = tr.get(name)
        label = name if t is None else (f"{name}: R² {t.r2:.2f}, p {t.p_value:.1g}"
                                        + (" FOLLOWS" if t.follows else ""))
        ax.set_title(label, fontsize=8)
        ax.set_xlabel(name, fontsize=8)
        ax.set_ylabel("residual [points]", fontsize=8)
    for ax in list(axes.flat)[len(covs):]:
        ax.set_visible(False)
    fig.suptitle(f"{report.case_name}: residual {title}; R² and p of the fitted model's "
                 "residual", fontsize=9)
    fig.tight_layout()
    return fig


def _pct(x) -> str:
    """A fraction as efficiency points, three decimals."""
    return f"{100 * x:.3f}"


def markdown(report: LoopReport, images=("residuals_before.png", "residuals_after.png")) -> str:
    """The report.md text of a loop.

    Parameters
    ----------
    report : LoopReport
        The loop's report.
    images : tuple of str
        Paths of the residual figures before and after, linked at the end.

    Returns
    -------
    str
        Markdown: errors before and after, effects added, selection steps (or, for small
        data, each point against its uncertainty and what each candidate would need),
        residual trends, signatures, skipped candidates and refused rows.
    """
    out = _header(report) + _errors(report) + _effects(report)
    if report.steps:
        out += _steps(report)
    if not report.selection:
        out += _points(report)
    if report.closing:
        out += ["## What each candidate would need (too few points to select)", "",
                "| effect | value(s) | RMSE after [points] | note |", "|---|---|---|---|"]
        for c in report.closing:
            out.append(f"| {c.name} | {', '.join(f'{v:.4g}' for v in c.values)} | "
                       f"{_pct(c.rmse)} | {c.note} |")
        out.append("")
    out += _trends(report)
    if report.signatures and report.n_points >= MIN_POINTS_CORRELATION:
        out += ["## Residual against each candidate's signature (baseline)", "",
                "| effect | correlation |", "|---|---|"]
        out += [f"| {k} | {v:+.3f} |" for k, v in report.signatures.items()] + [""]
    if report.skipped:
        out += ["## Not candidates", ""] + [f"- {k}: {v}" for k, v in report.skipped.items()]
        out.append("")
    if report.rejected_rows:
        out += ["## Refused rows", ""] + [f"- {r}" for r in report.rejected_rows] + [""]
    out += [f"![residuals before]({images[0]})", "", f"![residuals after]({images[1]})", "",
            f"Loop time {report.elapsed_s:.1f} s, {report.evaluations} model evaluations.", ""]
    return "\n".join(out)


def _header(report: LoopReport) -> list:
    out = [f"# Measured-data loop: {report.case_name}", "",
           f"Data: `{report.data_source}`, {report.n_points} points"
           + (f" ({len(report.rejected_rows)} rows refused)" if report.rejected_rows else "")
           + ("; weighted by the sensors' uncertainty" if report.weighted else "; unweighted"),
           ""]
    src = report.provenance.get("source") if report.provenance else None
    if src:
        out += [f"Provenance: {src}", ""]
    return out


def _errors(report: LoopReport) -> list:
    b, f = report.baseline, report.final
    out = ["## Error before and after", "",
           "| | baseline | final |", "|---|---|---|",
           f"| held-out RMSE [points] | {_pct(b.rmse)} | {_pct(f.rmse)} |",
           f"| held-out max abs error [points] | {_pct(b.max_abs)} | {_pct(f.max_abs)} |",
           f"| fit RMSE [points] | {_pct(report.baseline_fit.rmse)} | "
           f"{_pct(report.final_fit.rmse)} |",
           f"| mean residual [points] | {_pct(np.mean(report.baseline_fit.residual))} | "
           f"{_pct(np.mean(report.final_fit.residual))} |", ""]
    if not report.selection:
        out += ["Held-out errors need data to hold out: with so few points the 'final' "
                "column equals the baseline.", ""]
    return out


def _effects(report: LoopReport) -> list:
    out = ["## Effects added", ""]
    if report.effects:
        out += ["| effect | parameter | value | std. error | unit | note |",
                "|---|---|---|---|---|---|"]
        for e in report.effects:
            for pname, p in e.parameters.items():
                out.append(f"| {e.name} | {pname} | {p['value']:.5g} | {p['stderr']:.2g} | "
                           f"{p['unit']} | {'at bound' if p['at_bound'] else ''} |")
        out += [""] + [f"- {e.name}: {e.equation} ({e.citation}); sets "
                       f"{', '.join(e.case_fields)}" for e in report.effects] + [""]
    else:
        out += ["None.", ""]
    return out + [f"Stop: {report.stop_reason}", ""]


def _steps(report: LoopReport) -> list:
    out = ["## Selection steps", ""]
    for s in report.steps:
        out += [f"Step {s.index}: {s.reason}", "",
                "| candidate | values | std. error | fit RMSE [points] | held-out weighted RMS "
                "| ΔBIC | passes |", "|---|---|---|---|---|---|---|"]
        for c in s.candidates:
            out.append(f"| {c.name} | {', '.join(f'{v:.4g}' for v in c.values)} | "
                       f"{', '.join(f'{v:.2g}' for v in c.stderr)} | {_pct(c.rmse)} | "
                       f"{c.cv_wrmse:.4g} | {c.delta_bic:+.1f} | "
                       f"{'yes' if c.passed else 'no'}"
                       f"{' (' + c.note + ')' if c.note else ''} |")
        out.append("")
    return out


def _points(report: LoopReport) -> list:
    """Small data: each point against its measurement uncertainty."""
    r = report.baseline_fit.residual
    sig = report.sigma
    covs = report.covariates
    out = ["## Each point against its measurement uncertainty", "",
           "| point | speed [rpm] | torque [N m] | measured [%] | model [%] | residual "
           "[points] | sensor sigma [points] |", "|---|---|---|---|---|---|---|"]
    for i in range(report.n_points):
        s_i = "–" if sig is None else f"{100 * sig[i]:.2f}"
        out.append(f"| {i + 1} | {covs['input_speed_rpm'][i]:g} | "
                   f"{covs['output_torque_Nm'][i]:g} | {100 * report.measured[i]:.2f} | "
                   f"{100 * report.baseline_fit.prediction[i]:.2f} | {100 * r[i]:+.2f} | "
                   f"{s_i} |")
    return out + [""]


def _trends(report: LoopReport) -> list:
    trends = [t for t in report.trends_before if math.isfinite(t.r2)]
    out = ["## Residual against the covariates", ""]
    if trends:
        out += ["| covariate | R² before | p before | R² after | p after | follows after |",
                "|---|---|---|---|---|---|"]
    else:
        out += ["Too few points (or no covariate that varies) for a trend test.", ""]
    after = {t.covariate: t for t in report.trends_after}
    for t in trends:
        a = after.get(t.covariate)
        out.append(f"| {t.covariate} | {t.r2:.3f} | {t.p_value:.2g} | "
                   f"{a.r2 if a else float('nan'):.3f} | {a.p_value if a else float('nan'):.2g} | "
                   f"{'yes' if a and a.follows else 'no'} |")
    return out + ["", f"Unexplained: {', '.join(report.unexplained) or 'nothing'}"
                  + (" (the final residual still follows these covariates; no catalog effect "
                     "accounts for it)" if report.unexplained else ""), ""]
