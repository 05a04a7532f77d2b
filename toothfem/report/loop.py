"""Pictures and Markdown of the measured-data loop: a :class:`LoopReport` in, a figure or text
out (``toothfem loop`` writes them as residuals_before.png, residuals_after.png, report.md).

This is the one place the loop's Markdown is written; the JSON is the record's own
(:meth:`LoopReport.to_dict`).
"""
from __future__ import annotations

import math

import numpy as np

from ..efficiency.loop import LoopReport
from ..efficiency.loop import effects as fx
from ..errors import ToothfemError
from ..units import unit_of
from . import pyplot

#: Size [in] of one covariate's panel of the residual figure (legible at dpi 110).
PANEL_SIZE_IN = (4.2, 3.2)
#: Panels per row of the residual figure (three keep a page-wide figure legible).
MAX_COLUMNS = 3
#: Fewest points for the signature table: a correlation over fewer is +-1 or undefined.
MIN_POINTS_CORRELATION = 3



def axis_label(name: str) -> str:
    """'input_speed_rpm' -> 'input speed [rpm]' (a covariate's name with its unit).

    Parameters
    ----------
    name : str
        A covariate's name with its unit suffix.

    Returns
    -------
    str
        The label.
    """
    u = unit_of(name)
    if u is None:
        return name.replace("_", " ")
    return f"{name[:-len(u.suffix) - 1].replace('_', ' ')} [{u.symbol}]"


def _trend_title(t) -> str:
    """A panel's title: the trend test of the residual against its covariate."""
    if t is None or not math.isfinite(t.r2):
        return "no trend test (too few points or a constant covariate)"
    return (f"trend of the residual: R² {t.r2:.2f}, p {t.p_value:.2g}"
            + (" - it follows this covariate" if t.follows else ""))


def plot_residuals(report: LoopReport, stage="before"):
    """Residual (measured - model) [efficiency points] against every covariate of the data.

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
        One panel per covariate, titled with the trend test of the residual (R², p).
    """
    plt = pyplot()
    if stage == "before":
        r, trends = report.baseline_fit.residual, report.trends_before
        title = "the baseline model (the case as given)"
    else:
        r = report.final.residual if report.selection else report.final_fit.residual
        trends = report.trends_after
        added = ", ".join(e.name for e in report.effects) or "no effect"
        title = (f"the final model (baseline + {added}), held-out residuals"
                 if report.selection else
                 "the final model (= baseline: too few points to select an effect)")
    covs = report.covariates
    k = max(len(covs), 1)
    cols = min(k, MAX_COLUMNS)
    rows = math.ceil(k / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(PANEL_SIZE_IN[0] * cols,
                                                  PANEL_SIZE_IN[1] * rows + 0.6),
                             squeeze=False, layout="constrained")
    tr = {t.covariate: t for t in trends}
    for ax, (name, x) in zip(axes.flat, covs.items()):
        x = np.asarray(x)
        if x.dtype == object:
            levels = sorted(set(x.astype(str)))
            xi = np.array([levels.index(v) for v in x.astype(str)], float)
            ax.set_xticks(range(len(levels)), levels, rotation=45, fontsize=7)
            ax.plot(xi, 100 * r, "o", ms=4, alpha=0.7)
        else:
            ax.plot(x.astype(float), 100 * r, "o", ms=4, alpha=0.7)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_title(_trend_title(tr.get(name)), fontsize=8)
        ax.set_xlabel(axis_label(name), fontsize=8)
        ax.set_ylabel("measured - model [efficiency points]", fontsize=8)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(covs):]:
        ax.set_visible(False)
    points = (f"{report.n_points} points binned from {report.n_rows} measured rows"
              if report.n_rows != report.n_points else
              f"{report.n_points} measured point{'s' if report.n_points != 1 else ''}")
    fig.suptitle(f"Residual of {title} against each covariate, {points}\n{report.case_name}",
                 fontsize=9, x=0.01, ha="left")
    return fig


def _pct(x) -> str:
    """A fraction as efficiency points, three decimals."""
    return f"{100 * x:.3f}"


def markdown(report: LoopReport, images=("residuals_before.png", "residuals_after.png"),
             effects=None) -> str:
    """The report.md text of a loop.

    Parameters
    ----------
    report : LoopReport
        The loop's report.
    images : tuple of str
        Paths of the residual figures before and after, linked at the end.
    effects : sequence of Effect, optional
        The catalog the loop drew from, for the candidates' parameter names and units
        (default :func:`toothfem.efficiency.loop.effects.catalog`).

    Returns
    -------
    str
        Markdown: what was done to the data (its notes: dropped columns, binning), errors
        before and after, effects added, selection steps (or, for small data, each point
        against its uncertainty and what each candidate would need), residual trends,
        signatures, skipped candidates and refused rows.
    """
    out = _header(report) + _errors(report) + _effects(report) + _groups(report)
    if report.steps:
        out += _steps(report, effects)
    if not report.selection:
        out += _points(report)
    if report.closing:
        out += ["## What each candidate would need (too few points to select)", "",
                "| effect | parameter = value | RMSE after [points] | note |",
                "|---|---|---|---|"]
        for c in report.closing:
            out.append(f"| {c.name} | {_values(c.name, c.values, effects)} | "
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
    """Title, the data (rows, points, refused rows, weights), provenance and what was done
    to the data (the notes: dropped columns, binning)."""
    size = (f"{report.n_rows} rows binned onto {report.n_points} points"
            if report.n_rows != report.n_points else f"{report.n_points} points")
    out = [f"# Measured-data loop: {report.case_name}", "",
           f"Data: `{report.data_source}`, {size}"
           + (f" ({len(report.rejected_rows)} rows refused)" if report.rejected_rows else "")
           + ("; weighted by each point's uncertainty (1/sigma)" if report.weighted
              else "; unweighted"), ""]
    src = report.provenance.get("source") if report.provenance else None
    if src:
        out += [f"Provenance: {src}", ""]
    if report.notes:
        out += ["## What was done to the data", ""] + [f"- {n}" for n in report.notes] + [""]
    return out


def _errors(report: LoopReport) -> list:
    b, f = report.baseline, report.final
    held = report.selection      # a held-out error exists only where points were held out
    none = "– (none formed)"
    out = ["## Error before and after", "",
           "| | baseline | final |", "|---|---|---|",
           f"| held-out RMSE [points] | {_pct(b.rmse) if held else none} | "
           f"{_pct(f.rmse) if held else none} |",
           f"| held-out max abs error [points] | {_pct(b.max_abs) if held else none} | "
           f"{_pct(f.max_abs) if held else none} |",
           f"| fit RMSE [points] | {_pct(report.baseline_fit.rmse)} | "
           f"{_pct(report.final_fit.rmse)} |",
           f"| mean residual (measured - model) [points] | "
           f"{_pct(np.mean(report.baseline_fit.residual))} | "
           f"{_pct(np.mean(report.final_fit.residual))} |", ""]
    if not held:
        out += [f"With {report.n_points} point(s) no held-out error can be formed (it needs "
                "points to hold out); the 'final' model is the baseline.", ""]
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


def _values(name: str, values, effects) -> str:
    """'drag_torque_Nmm = 4.988 N mm': each fitted value with its parameter and unit (from
    the catalog's effect of that name)."""
    try:
        params = fx.by_name(name, effects).parameters
    except ToothfemError:
        params = ()
    if len(params) != len(values):
        return ", ".join(f"{v:.4g}" for v in values)
    return ", ".join(f"{p.name} = {v:.4g}" + (f" {p.unit}" if p.unit not in ("", "-") else "")
                     for p, v in zip(params, values))


def _groups(report: LoopReport) -> list:
    """The alias groups: each member's values and meaning, the points that would separate
    them, or the direct measurement where no point does."""
    if not report.alias_groups:
        return []
    out = ["## Effects the data cannot tell apart", ""]
    for g in report.alias_groups:
        out += [f"Step {g.step}: {g.note}", "", "| effect | fitted | what it would mean | "
                "measured directly by |", "|---|---|---|---|"]
        for m in g.members:
            vals = ", ".join(f"{k} = {v['value']:.4g} {v['unit']}" for k, v in m.values.items())
            out.append(f"| {m.name} | {vals} | {m.meaning} | {m.direct_test or '–'} |")
        out.append("")
        if g.points:
            names = [m.name for m in g.members]
            out += ["Proposed measurements (where their predictions differ most against the "
                    "noise of one reading):", "",
                    "| speed [rpm] | torque [N m] | oil [deg C] | time [h] | "
                    + " | ".join(f"{n} [%]" for n in names)
                    + " | sigma [points] | apart [sigma] | readings for 3 sigma |",
                    "|---|---|---|---|" + "---|" * len(names) + "---|---|---|"]
            for p in g.points:
                def col(v, key, fmt, p=p):
                    return "any" if key in p.free else ("–" if v is None else format(v, fmt))
                out.append(f"| {p.input_speed_rpm:.0f} | {p.output_torque_Nm:.4g} | "
                           f"{col(p.oil_temp_C, 'oil_temp_C', '.0f')} | "
                           f"{col(p.time_h, 'time_h', '.3g')} | "
                           + " | ".join(f"{100 * p.efficiency[n]:.2f}" for n in names)
                           + f" | {100 * p.sigma:.2f} | {p.separation:.2g} | {p.repeats} |")
            out.append("")
    return out


def _steps(report: LoopReport, effects=None) -> list:
    out = ["## Selection steps", ""]
    for s in report.steps:
        if s.trend is not None:
            t = s.trend
            follows = ("follows" if t.follows else "follows no covariate significantly; "
                       "most")
            after = (f" After this step the residual {follows} {t.covariate} "
                     f"(R² {t.r2:.2f}, p {t.p_value:.2g}).")
        else:
            after = ""
        out += [f"Step {s.index}: {s.reason}.{after}", "",
                "| candidate | parameter = value | std. error | fit RMSE [points] | held-out "
                "weighted RMS "
                "| ΔBIC | passes |", "|---|---|---|---|---|---|---|"]
        for c in s.candidates:
            out.append(f"| {c.name} | {_values(c.name, c.values, effects)} | "
                       f"{', '.join(f'{v:.2g}' for v in c.stderr)} | {_pct(c.rmse)} | "
                       f"{c.cv_wrmse:.4g} | {c.delta_bic:+.1f} | "
                       f"{'yes' if c.passed else 'no, at its bound' if c.bounded else 'no'}"
                       f"{' (' + c.note + ')' if c.note else ''} |")
        out.append("")
    return out


def _points(report: LoopReport) -> list:
    """Small data: each point against its measurement uncertainty."""
    r = report.baseline_fit.residual
    sig = report.sigma
    covs = report.covariates
    measured = report.measured
    if measured is None:
        raise RuntimeError("a loop report without its measured efficiencies (run_loop sets them)")
    out = ["## Each point against its measurement uncertainty", "",
           "| point | speed [rpm] | torque [N m] | measured [%] | model [%] | residual "
           "[points] | sensor sigma [points] |", "|---|---|---|---|---|---|---|"]
    for i in range(report.n_points):
        s_i = "–" if sig is None else f"{100 * sig[i]:.2f}"
        out.append(f"| {i + 1} | {covs['input_speed_rpm'][i]:g} | "
                   f"{covs['output_torque_Nm'][i]:g} | {100 * measured[i]:.2f} | "
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
    return out + ["", f"Unexplained: {report.unexplained_text()}", ""]
