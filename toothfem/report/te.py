"""Pictures and text of the TE/hysteresis loop (``toothfem te-loop``): the measured loop
beside the model before and after, the TE amplitudes at the named orders measured and
modelled, and report.md (docs/te_rig.md, "The loop")."""
from __future__ import annotations

import math

import numpy as np

from ..efficiency.loop.te.observations import model_rows
from ..efficiency.loop.te.running import misses
from . import pyplot, wrap

#: The figures compared, summary key -> (label, unit).
FIGURES = {"torsional_rigidity_Nm_per_arcmin": ("torsional rigidity 50-100 %", "N m/arcmin"),
           "lost_motion_arcmin": ("lost motion ±3 %", "arcmin"),
           "hysteresis_loss_arcmin": ("hysteresis loss", "arcmin"),
           "backlash_arcmin": ("backlash", "arcmin")}


def _effects_text(result) -> str:
    loop = result.loop
    if not loop.added:
        return "no effect added"
    parts = []
    for name in loop.added:
        eff = loop.catalog[name]
        vals = ", ".join(f"{p.name} = {v:.3g} {p.unit}"
                         for p, v in zip(eff.parameters, loop.final.values[name]))
        parts.append(f"{name} ({vals})")
    return "added: " + "; ".join(parts)


def hysteresis(result):
    """The measured hysteresis loop (its binned branches) with the model's before and
    after, the whole loop and the window of ±10 % of the rated torque.

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 5.4), layout="constrained",
                             gridspec_kw={"width_ratios": [1.2, 1]})
    rated = result.rated_torque_Nm
    meas = result.hysteresis
    shift = _offset(result)
    for ax in axes:
        for c in meas.curves:
            ax.plot(c.torque_Nm, c.twist_arcmin - shift, "o", ms=4, mfc="none",
                    color="tab:green" if c.branch > 0 else "tab:red",
                    label=(f"measured, torque {'rising' if c.branch > 0 else 'falling'}"
                           if c.flank > 0 else None))
        for rec, style, label in ((result.before, "--", "model as declared"),
                                  (result.after, "-", "model after the loop")):
            lp = rec.loop
            ax.plot(lp.rising_torque_Nm, lp.rising_twist_arcmin, style, color="k", lw=1.2,
                    label=label)
            ax.plot(lp.falling_torque_Nm, lp.falling_twist_arcmin, style, color="k", lw=1.2)
        ax.axhline(0, color="0.5", lw=0.5)
        ax.axvline(0, color="0.5", lw=0.5)
        ax.set_xlabel("output torque [N m]")
        ax.set_ylabel("output twist [arcmin]")
        ax.grid(alpha=0.3)
    window = 0.1 * rated
    zoom = axes[1]
    zoom.set_xlim(-window, window)
    parts = [c.twist_arcmin[np.abs(c.torque_Nm) <= window] - shift for c in meas.curves]
    near = np.concatenate([n for n in parts if n.size] or [np.zeros(1)])
    pad = 0.15 * max(float(np.ptp(near)), 1e-3)
    zoom.set_ylim(float(near.min()) - pad, float(near.max()) + pad)
    zoom.set_title("near zero torque (±10 % of rated)", fontsize=10)
    axes[0].set_title("the loop", fontsize=10)
    axes[0].legend(fontsize=8, loc="upper left")
    m = meas.summary()
    b, a = result.before.loop.figures(), result.after.loop.figures()
    lm = "lost_motion_arcmin"
    fig.suptitle(wrap(f"{result.case_name}\nhysteresis measured (binned) against the model, "
                      f"input held; rated {rated:.4g} N m\nlost motion ±3 %: measured "
                      f"{m[lm]:.3g} arcmin, model {b[lm]:.3g} as declared, {a[lm]:.3g} after "
                      f"the loop\n{_effects_text(result)}", 120), fontsize=10)
    return fig


def _offset(result) -> float:
    """The measured loop's zero against the model after the loop [arcmin]: the measured
    twist rows' mean less the model's on the same rows (an encoder's zero is arbitrary)."""
    layout = result.layout
    if not layout.loop_rows.size:
        return 0.0
    model = model_rows(layout, result.after, centred=False)[layout.loop_rows]
    return layout.loop_mean_arcmin - float(model.mean())


def spectrum(result):
    """TE amplitudes at the named orders fitted: measured (bars, forward and backward) and
    the model before and after (markers), one panel per torque level.

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    obs = result.loop.observations
    rows = _amplitude_rows(result)
    torques = sorted({r[0] for r in rows})
    fig, axes = plt.subplots(len(torques), 1, figsize=(11, 2.8 * len(torques) + 1.2),
                             layout="constrained", squeeze=False)
    before = result.loop.baseline.prediction
    after = result.loop.final.prediction
    for ax, t in zip(axes[:, 0], torques):
        mine = [r for r in rows if r[0] == t]
        orders = sorted({r[1] for r in mine})
        x = np.arange(len(orders))
        for d, dx, colour in ((1, -0.2, "tab:blue"), (-1, 0.2, "tab:orange")):
            vals = [next((obs.values[r[3]] for r in mine if r[1] == o and r[2] == d),
                         np.nan) for o in orders]
            ax.bar(x + dx, vals, width=0.38, color=colour, alpha=0.6,
                   label=f"measured, {'forward' if d > 0 else 'backward'}")
            for pred, marker, label in ((before, "x", "model as declared"),
                                        (after, "o", "model after the loop")):
                pv = [next((pred[r[3]] for r in mine if r[1] == o and r[2] == d), np.nan)
                      for o in orders]
                ax.plot(x + dx, pv, marker, color="k", mfc="none" if marker == "o" else None,
                        ms=6, ls="none", label=label if d > 0 else None)
        noise = [r[4] for r in mine]
        ax.axhline(float(np.median(noise)) * math.sqrt(math.pi / 2), color="0.4", ls=":",
                   lw=1, label="the spectrum's noise floor (mean amplitude of noise)")
        ax.set_xticks(x, [f"{o:g}" for o in orders], fontsize=8)
        ax.set_xlabel("order per output revolution", fontsize=8)
        ax.set_ylabel("TE amplitude [arcsec]")
        ax.set_title(f"at {t:.4g} N m output", fontsize=9, loc="left")
        ax.grid(alpha=0.3, axis="y")
        ax.set_ylim(bottom=0)
    axes[0, 0].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    named = "\n".join(f"{q:g}: {n}" for n, q in sorted(result.orders.items(),
                                                        key=lambda nq: nq[1]))
    axes[-1, 0].text(1.01, 0.0, "the drive's orders (and their doubles):\n" + named,
                     transform=axes[-1, 0].transAxes, fontsize=8, va="bottom", ha="left")
    fig.suptitle(wrap(f"{result.case_name}\nTE amplitude at the drive's named orders, "
                      f"measured against the model\n{_effects_text(result)}", 120),
                 fontsize=10)
    return fig


def widths(result):
    """The hysteresis widths of the running TE against the output torque: measured (with
    each width's sigma), the model before and after the loop, and the line w = 2 T / k + LM
    of the measured widths' reading (:mod:`~toothfem.efficiency.loop.te.running`).

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult

    Returns
    -------
    matplotlib.figure.Figure or None
        None where the recordings hold no width.
    """
    rows = [(r.torque_Nm, i) for i, r in enumerate(result.layout.rows) if r.kind == "width"]
    if not rows:
        return None
    plt = pyplot()
    obs = result.loop.observations
    t = np.array([r[0] for r in rows])
    idx = [r[1] for r in rows]
    fig, ax = plt.subplots(figsize=(9, 5.5), layout="constrained")
    ax.errorbar(t, obs.values[idx] / 60, yerr=np.asarray(obs.sigma)[idx] / 60, fmt="o",
                color="tab:blue", capsize=3, label="measured (forward less backward mean "
                "TE), +-1 sigma")
    for pred, marker, label in ((result.loop.baseline.prediction, "x", "model as declared"),
                                (result.loop.final.prediction, "s", "model after the loop")):
        ax.plot(t, np.asarray(pred)[idx] / 60, marker, color="k",
                mfc="none" if marker == "s" else None, ls="none", label=label)
    ds = result.running
    if ds is not None:
        tt = np.linspace(0, t.max(), 50)
        ax.plot(tt, ds.width_arcmin(tt), "--", color="tab:red",
                label=f"measured: 2 T / k + LM, k = {ds.rigidity_Nm_per_arcmin:.4g} N m/arcmin, "
                      f"LM = {ds.lost_motion_intercept_arcmin:.3g} arcmin (from "
                      f"{ds.linear_from_Nm:.4g} N m)")
    ax.set_xlabel("output torque (brake opposing the motion) [N m]")
    ax.set_ylabel("hysteresis width [arcmin]")
    ax.set_title(wrap(f"{result.case_name}: the running TE's hysteresis width against the "
                      "torque", 90), fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    return fig


def width_errors_arcsec(result) -> tuple | None:
    """RMS of measured less model over the width rows [arcsec], before and after the
    loop; None without width rows.

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult

    Returns
    -------
    (float, float) or None
    """
    idx = [i for i, r in enumerate(result.layout.rows) if r.kind == "width"]
    if not idx:
        return None
    y = result.loop.observations.values[idx]
    return tuple(float(np.sqrt(np.mean((y - np.asarray(p)[idx]) ** 2)))
                 for p in (result.loop.baseline.prediction, result.loop.final.prediction))


def _running_md(result) -> list:
    """report.md's section on the running widths."""
    if result.te_figures is None:
        return []
    out = ["## The running widths (model-free reading)", ""]
    ds = result.running
    if ds is None:
        return out + [f"No rigidity from the widths: {result.running_note}.", ""]
    out += ["| | rigidity [N m/arcmin] | lost-motion intercept [arcmin] |", "|---|---|---|",
            f"| measured (w = 2 T / k + LM from {ds.linear_from_Nm:.4g} N m) | "
            f"{ds.rigidity_Nm_per_arcmin:.4g} +- {ds.rigidity_sigma_Nm_per_arcmin:.2g} | "
            f"{ds.lost_motion_intercept_arcmin:.4g} +- "
            f"{ds.lost_motion_intercept_sigma_arcmin:.2g} |"]
    for which in ("before", "after"):
        m = result.model_running(which)
        if m is not None:
            out.append(f"| model {which} the loop | {m.rigidity_Nm_per_arcmin:.4g} | "
                       f"{m.lost_motion_intercept_arcmin:.4g} |")
    after = result.model_running("after")
    gaps = [] if after is None else misses(ds, after)
    err = width_errors_arcsec(result)
    out += [""] + [f"**The model cannot reach the widths:** {g}." for g in gaps]
    out += ["", f"Measured width at {ds.torques_Nm[0]:.4g} N m: {ds.lowest_width_arcmin:.4g} "
            f"arcmin, {ds.softening_arcmin:.3g} arcmin below the line (softer near zero). "
            "The model's running TE carries its running losses (docs/te_model.md): its "
            "width at zero torque is friction and play."]
    if err is not None:
        out.append(f"Widths' RMS error {err[0]:.3g} arcsec before the loop, {err[1]:.3g} "
                   "arcsec after.")
    return out + [""]


def _amplitude_rows(result) -> list:
    """(torque, order, direction, row index, noise) of the amplitude rows (the loop's
    layout of its observations)."""
    out = []
    for i, row in enumerate(result.layout.rows):
        if row.kind == "amplitude":
            out.append((row.torque_Nm, row.order, row.direction, i, row.noise_arcsec))
    return out


def markdown(result, *, files=()) -> str:
    """report.md of the TE/hysteresis loop.

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult
    files : sequence of str
        The pictures beside it.

    Returns
    -------
    str
    """
    loop = result.loop
    b, f = loop.baseline, loop.final
    lines = [f"# TE and hysteresis loop: {result.case_name}", "",
             f"Rated torque {result.rated_torque_Nm:.4g} N m; {len(loop.observations.values)} "
             f"observed figures; {result.evaluations} model evaluations in "
             f"{result.elapsed_s:.1f} s.", "",
             "## Error before and after", "",
             "| | model as declared | after the loop |", "|---|---|---|",
             f"| held-out error, weighted RMS [sigma] | {b.cv_wrmse:.3g} | {f.cv_wrmse:.3g} |",
             f"| fit error, weighted RMS [sigma] | {b.wrmse:.3g} | {f.wrmse:.3g} |", "",
             f"Held-out error cut {b.cv_wrmse / max(f.cv_wrmse, 1e-300):.3g}x (k-fold over "
             "the torque levels: a fold holds out whole torques). sigma: each row's own "
             "uncertainty from the recordings (the spectrum's noise floor, the binned loop's "
             "scatter, the widths' scatter between or within windows).", ""]
    lines += _running_md(result)
    lines += ["## Effects added", ""]
    if loop.added:
        lines += ["| effect | value | standard error | meaning | source |",
                  "|---|---|---|---|---|"]
        for name in loop.added:
            eff = loop.catalog[name]
            for p, v, s in zip(eff.parameters, f.values[name], f.stderr[name]):
                lines.append(f"| {name} | {p.name} = {v:.4g} {p.unit} | "
                             f"{s:.2g} {p.unit} | {eff.summary} | {eff.citation} |")
        for name in loop.added:
            group = loop.alias_groups.get(name, ())
            if group:
                lines += ["", f"**{name} cannot be told apart by these recordings from:** "
                          + ", ".join(group) + ". The measurement that tells each apart:", ""]
                for n, values in loop.group_values(name).items():
                    fitted = ", ".join(f"{p.name} = {v:.4g} {p.unit}" for p, v in
                                       zip(loop.catalog[n].parameters, values))
                    lines.append(f"- {n} ({fitted}): {loop.catalog[n].direct_test}")
    else:
        lines.append("None.")
    lines += ["", f"Stop: {loop.stop_reason}", ""]
    if loop.failures:
        lines += [f"Note: {loop.failure_note()}.", ""]
    if result.not_considered:
        lines += ["Not considered: " + "; ".join(
            f"{n} ({why or 'not asked for'})" for n, why in result.not_considered.items())
            + ". `--effects` names any of them, `--effects all` takes every effect.", ""]
    lines += ["## Steps", ""]
    for s in loop.steps:
        lines += [f"Step {s.index}: {s.added or 'nothing added'} ({s.reason})", "",
                  "| candidate | BIC | held-out [sigma] | values | at a bound |",
                  "|---|---|---|---|---|"]
        for name, bic, cv, values, bound in s.scored:
            lines.append(f"| {name} | {bic:.1f} | {cv:.3g} | "
                         + ", ".join(f"{v:.4g}" for v in values)
                         + f" | {'yes' if bound else 'no'} |")
        lines.append("")
    if result.hysteresis is not None:
        m = result.hysteresis.summary()
        before, after = result.before.loop.figures(), result.after.loop.figures()
        lines += ["## The loop's figures (catalogue definitions, docs/stiffness.md)", "",
                  "| figure | measured | model as declared | after the loop |",
                  "|---|---|---|---|"]
        for key, (label, unit) in FIGURES.items():
            lines.append(f"| {label} [{unit}] | {m[key]:.4g} | {before[key]:.4g} | "
                         f"{after[key]:.4g} |")
        lines.append("")
        if m["notes"]:
            lines += ["Notes on the recording: " + "; ".join(m["notes"]), ""]
    if result.te_figures is not None:
        lines += ["## The TE recordings (model-free)", "",
                  "| torque [N m] | forward mean [arcsec] | backward mean [arcsec] | "
                  "width [arcsec] | named peaks (forward) |", "|---|---|---|---|---|"]
        for c in result.te_figures.conditions:
            peaks = "" if c.forward is None else ", ".join(
                f"{p.order:.4g}: {p.amplitude_arcsec:.3g} arcsec"
                + (f" ({p.name})" if p.names else "") for p in c.forward.peaks[:6])
            lines.append(f"| {c.condition.output_torque_Nm:.4g} | "
                         f"{_num(c.forward.mean_arcsec if c.forward else math.nan)} | "
                         f"{_num(c.backward.mean_arcsec if c.backward else math.nan)} | "
                         f"{_num(c.width_arcsec)} | {peaks} |")
        lines += ["", "TE levels are relative (each file's zero offset fitted out, "
                  "docs/te_rig.md)."]
    obs = loop.observations
    lines += ["", "## Every observed figure beside the model", "",
              "Residual = measured - model, in the row's unit; sigma its uncertainty (the "
              "twist rows are centred on their mean, an encoder's zero being arbitrary).", "",
              "| figure | measured | model as declared | after the loop | sigma |",
              "|---|---|---|---|---|"]
    for i, label in enumerate(obs.labels):
        lines.append(f"| {label} | {obs.values[i]:.4g} | {b.prediction[i]:.4g} | "
                     f"{f.prediction[i]:.4g} | {obs.sigma[i]:.2g} |")
    if result.refused:
        lines += ["", "## Refused files", ""] + [f"- {r}" for r in result.refused]
    lines += [""] + [f"![{n}]({n})" for n in files] + [""]
    return "\n".join(lines)


def _num(x) -> str:
    return "–" if not math.isfinite(x) else f"{x:.4g}"
