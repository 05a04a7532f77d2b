"""Pictures and text of the modification search (``toothfem design``)."""
from __future__ import annotations

import csv
import json
from pathlib import Path

from typing import TYPE_CHECKING

from ..case import with_keys
from ..units import M_PER_MM, UM_PER_M
from . import pyplot, save, wrap

if TYPE_CHECKING:      # annotations only: the record's .write() calls this module
    from ..design import Candidate, DesignResult

#: Margin of the zoomed view around the candidates that meet every target, as a fraction
#: of their span on each axis.
ZOOM_MARGIN = 0.12


def _where(summary_or_result) -> str:
    """What a candidate's figures are: '(P90 of 8 built reducers: no 95 % interval ...)'
    or '(nominal design)'."""

    summary = summary_or_result if isinstance(summary_or_result, dict) else \
        summary_or_result.summary()
    iv = summary.get("percentile_interval")
    return iv["text"] if iv else "the design as drawn (no deviations)"


def tradeoff(result):
    """Backlash against the maximum Hertz pressure of every candidate evaluated, the
    feasible ones told apart, the trade-off front, the targets and the best design marked:
    left every candidate (the zoomed window outlined), right the window of the candidates
    that meet every target, the ones outside it marked at its edges with their count. With
    a percentile the candidates are that percentile of their built reducers (said, with
    whether it has a 95 % interval); the best design as drawn (nominal, its own FE tables)
    is marked beside it.

    Parameters
    ----------
    result : toothfem.design.DesignResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.patches import Rectangle

    plt = pyplot()
    t = result.targets
    fig, (full, zoom) = plt.subplots(1, 2, figsize=(15, 6.2),
                                     gridspec_kw={"width_ratios": [1, 1.25]})
    b, c = result.best, result.check
    at = t.get("percentile")
    how = _where(result)
    best_label = ((f"best, {how}:" if at else "best (nominal design):")
                  + f" backlash {b.backlash_arcmin:.3g} arcmin, P_h {b.max_ph_MPa:.4g} MPa, "
                  f"{b.contacts_min:g} pins; "
                  + ", ".join(_shown(k, v) for k, v in b.modification.items()))
    nominal_label = (f"the best as drawn (nominal, no deviations; its own FE tables): "
                     f"backlash {c['backlash_arcmin']:.3g} arcmin, P_h {c['max_ph_MPa']:.4g} "
                     f"MPa, {c['contacts_min']:g} pins")
    feasible = [x for x in result.candidates if x.feasible]
    allowable = next(iter((getattr(result, "limits", None) or {}).get("max_ph_MPa", [])), None)
    for ax in (full, zoom):
        for ok, colour, label in ((False, "tab:gray", "misses a target"),
                                  (True, "tab:blue", "meets every target")):
            pts = [x for x in result.candidates if x.feasible == ok]
            if pts:
                ax.scatter([x.backlash_arcmin for x in pts], [x.max_ph_MPa for x in pts],
                           s=14, color=colour, alpha=0.7, label=f"{label} ({len(pts)})")
        front = result.pareto()
        if front:
            ax.plot([x.backlash_arcmin for x in front], [x.max_ph_MPa for x in front], "-",
                    color="tab:orange", lw=1.5,
                    label=f"trade-off front (at least {t['min_contacts']} pins in contact)")
        ax.axvline(t["max_backlash_arcmin"], color="k", ls="--", lw=1,
                   label=f"max backlash {t['max_backlash_arcmin']:g} arcmin")
        if t.get("max_ph_MPa"):
            ax.axhline(t["max_ph_MPa"], color="k", ls=":", lw=1,
                       label=f"max P_h {t['max_ph_MPa']:g} MPa")
        if allowable:
            ax.axhline(allowable["value"], color="tab:purple", ls="-.", lw=1,
                       label=f"{allowable['name']} P_h {allowable['value']:.4g} MPa "
                             f"({allowable['source']})")
        ax.scatter([b.backlash_arcmin], [b.max_ph_MPa], s=150, marker="*", color="tab:red",
                   zorder=5, label=wrap(best_label, 60))
        if at:
            ax.scatter([c["backlash_arcmin"]], [c["max_ph_MPa"]], s=70, marker="D",
                       facecolor="none", edgecolor="tab:red", lw=1.5, zorder=5,
                       label=wrap(nominal_label, 60))
        ax.grid(alpha=0.3)
    if at:                             # the same design: as drawn -> at the percentile
        full.annotate("", xy=(b.backlash_arcmin, b.max_ph_MPa),
                      xytext=(c["backlash_arcmin"], c["max_ph_MPa"]),
                      arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 0.8,
                                  "ls": ":"})
    what = f", P{at:g} of {t['samples']} built reducers" if at else ", nominal design"
    for ax in (full, zoom):
        ax.set_xlabel(f"backlash [arcmin]{what} (system model)", fontsize=9)
    full.set_ylabel(wrap(f"maximum Hertz pressure P_h [MPa]{what} (one disc held at the peak "
                         "member torque)", 55), fontsize=9)
    full.set_title("every candidate (the window on the right outlined)", fontsize=9)
    if feasible:
        xs = [x.backlash_arcmin for x in feasible] + [t["max_backlash_arcmin"]]
        ys = [x.max_ph_MPa for x in feasible]
        dx = (max(xs) - min(xs)) or 1.0
        dy = (max(ys) - min(ys)) or max(1.0, 0.02 * max(ys))
        x0, x1 = min(xs) - ZOOM_MARGIN * dx, max(xs) + ZOOM_MARGIN * dx
        y0, y1 = min(ys) - ZOOM_MARGIN * dy, max(ys) + ZOOM_MARGIN * dy
        zoom.set_xlim(x0, x1)
        zoom.set_ylim(y0, y1)
        full.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ls="--", lw=1,
                                 ec="tab:blue"))
        out = _mark_out_of_view(zoom, result, x0, x1, y0, y1,
                                (c["backlash_arcmin"], c["max_ph_MPa"]) if at else None)
        if allowable and not y0 <= allowable["value"] <= y1:
            out += ("; " if out else "") + (
                f"the {allowable['name']} P_h {allowable['value']:.4g} MPa "
                + ("below" if allowable["value"] < y0 else "above"))
        zoom.set_title(f"the {len(feasible)} candidates that meet every target (zoomed)"
                       + (f"\n{wrap(out, 95)}" if out else ""), fontsize=9)
    handles, labels = zoom.get_legend_handles_labels()
    zoom.legend(handles, labels, fontsize=7.5, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    torque = ""
    if getattr(result, "output_torque_Nm", None):
        torque = (f" at {result.output_torque_Nm:.4g} N m output (P_h and pins: one disc "
                  f"held at the peak member torque {result.member_torque_Nm:.4g} N m)")
    fig.suptitle(wrap(result.case_name, 100) + "\n" + wrap(
        "modification search: backlash against contact pressure" + torque
        + (f"; every candidate at {how}" if at else ""), 130), fontsize=10)
    fig.tight_layout()
    return fig


def _side(bx, py, x0, x1, y0, y1):
    """Which edge of the window a point lies beyond (None: inside)."""
    if x0 <= bx <= x1 and y0 <= py <= y1:
        return None
    return "above" if py > y1 else "below" if py < y0 else "right" if bx > x1 else "left"


def _mark_out_of_view(ax, result, x0, x1, y0, y1,
                      nominal: tuple[float, float] | None = None) -> str:
    """Each candidate outside the window as a small triangle at the edge it lies beyond
    (pointing out); ``nominal`` (the best as drawn: backlash, P_h) as a hollow diamond at
    its edge. Returns the line that counts them with how far they reach ('' for none)."""
    marks: dict[str, list[Candidate]] = {"above": [], "below": [], "left": [], "right": []}
    for x in result.candidates:
        bx, py = x.backlash_arcmin, x.max_ph_MPa
        if x0 <= bx <= x1 and y0 <= py <= y1:
            continue
        side = ("above" if py > y1 else "below" if py < y0 else
                "right" if bx > x1 else "left")
        marks[side].append(x)
        ex = min(max(bx, x0), x1)
        ey = min(max(py, y0), y1)
        ax.scatter([ex], [ey], marker={"above": "^", "below": "v", "left": "<",
                                       "right": ">"}[side], s=30,
                   color="tab:blue" if x.feasible else "tab:gray", alpha=0.8,
                   clip_on=False, zorder=4)
    parts = []
    for side, pts in marks.items():
        if not pts:
            continue
        if side in ("above", "below"):
            far = max(pts, key=lambda x: abs(x.max_ph_MPa - (y1 if side == "above" else y0)))
            parts.append(f"{len(pts)} {side} (to {far.max_ph_MPa:.4g} MPa)")
        else:
            far = max(pts, key=lambda x: abs(x.backlash_arcmin
                                            - (x1 if side == "right" else x0)))
            parts.append(f"{len(pts)} {side} (to {far.backlash_arcmin:.3g} arcmin)")
    edge = None if nominal is None else _side(*nominal, x0, x1, y0, y1)
    if nominal is not None and edge is not None:       # an edge only where a nominal is
        ax.scatter([min(max(nominal[0], x0), x1)], [min(max(nominal[1], y0), y1)],
                   marker="D", s=60, facecolor="none", edgecolor="tab:red", lw=1.5,
                   clip_on=False, zorder=6)
        parts.append(f"the best as drawn {edge} ({nominal[1]:.4g} MPa, {nominal[0]:.3g} "
                     "arcmin)")
    return "out of view, marked at the edges: " + ", ".join(parts) if parts else ""


def _shown(key: str, value: float) -> str:
    """``equidistant_modification_mm`` 6.2e-05 -> 'equidistant 0.062 um'."""
    name = key.split("_modification")[0].replace("_", " ")
    if key.endswith("_mm"):
        return f"{name} {value * M_PER_MM * UM_PER_M:.3g} um"
    return f"{name} {value:.3g} deg"


def markdown(summary: dict) -> str:
    """report.md of the search: targets, the best modification at the search's percentile
    (said, with whether it has a 95 % interval), the same design as drawn with its own
    tables.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.design.DesignResult.summary`.

    Returns
    -------
    str
        Markdown.
    """
    t, b = summary["targets"], summary["best"]
    iv = summary.get("percentile_interval")
    how = _where(summary)
    torque = ""
    if summary.get("output_torque_Nm"):
        torque = (f" The pressure and the pins in contact are one disc held at the peak member "
                  f"torque {summary['member_torque_Nm']:.4g} N m (output "
                  f"{summary['output_torque_Nm']:.4g} N m); the backlash is the system "
                  "model's.")
    lines = [f"# Modification design: {summary['case']}", "",
             f"Targets: backlash <= {t['max_backlash_arcmin']:g} arcmin, at least "
             f"{t['min_contacts']} pins in contact"
             + (f", P_h <= {t['max_ph_MPa']:g} MPa" if t.get("max_ph_MPa") else
                ", the largest P_h minimised")
             + (f", at P{t['percentile']:g} of {t['samples']} reducers built within "
                "[tolerances] (the pins in contact at "
                f"P{100 - t['percentile']:g})" if t.get("percentile") else "") + "."
             + torque, ""]
    if iv is not None and not iv["has_interval"]:
        lines += [f"**The percentile has no 95 % confidence interval**: {iv['text']}. Each "
                  "candidate's percentile is read off its few reducers (interpolated between "
                  "the largest ones): a ranking of the candidates on the same draws, not a "
                  "value one in ten built reducers stays under.", ""]
    lines += [f"{summary['evaluations']} candidates evaluated with the case's own influence "
              "tables and each candidate's initial gaps.", "",
              "| | " + " | ".join(b["modification"]) + " | backlash [arcmin] | max P_h [MPa] "
              "| fewest pins |", "|---" * (len(b["modification"]) + 4) + "|",
              f"| best, {how} | " + " | ".join(f"{v:.4g}" for v in b["modification"].values())
              + f" | {b['backlash_arcmin']:.4g} | {b['max_ph_MPa']:.4g} | "
              f"{b['contacts_min']:g} |"]
    c, d = summary["check_with_own_tables"], summary["datasheet"]
    lines.append("| the same design as drawn (nominal, its own FE tables) | "
                 + " | ".join(f"{v:.4g}" for v in b["modification"].values())
                 + f" | {c['backlash_arcmin']:.4g} | {c['max_ph_MPa']:.4g} | "
                 f"{c['contacts_min']:g} |")
    lines += ["", "The best design as drawn (no deviations), with its own FE tables (in "
              "brackets: the case's tables with its gaps, as the search solved it):", ""]
    lines += [f"- maximum P_h {c['max_ph_MPa']:.4g} MPa ({c['search_tables_max_ph_MPa']:.4g}),"
              f" fewest pins {c['contacts_min']:g} ({c['search_tables_contacts_min']:g}), "
              f"backlash {c['backlash_arcmin']:.4g} arcmin "
              f"({c['search_tables_backlash_arcmin']:.4g});",
              f"- rigidity {d.get('torsional_rigidity_Nm_per_arcmin', float('nan')):.4g} "
              f"N m/arcmin, lost motion {d.get('lost_motion_arcmin', float('nan')):.4g} arcmin "
              f"at the rated {d.get('rated_torque_Nm', float('nan')):.4g} N m.", "",
              "Files: best_case.toml (the case with these modifications), candidates.csv, "
              "tradeoff.png, summary.json.", ""]
    if summary.get("warnings"):
        lines += ["## Warnings", ""] + [f"- {w['message']}" for w in summary["warnings"]] + [""]
    return "\n".join(lines)


#: The column of the printed table with the design as drawn.
NOMINAL_COLUMN = "as drawn (nominal)"


def summary_rows(summary: dict) -> list:
    """The search's best design as rows of :func:`toothfem.report.summary.text`: its
    modifications and what it gives as drawn (nominal, its own FE tables) and, with a
    percentile, at that percentile of its built reducers (the column says how many, and
    whether that has a 95 % interval).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.design.DesignResult.summary`.

    Returns
    -------
    list of (str, str, dict)
        (quantity, unit, {NOMINAL_COLUMN: value, and the percentile's column}).
    """
    b, c, d = summary["best"], summary["check_with_own_tables"], summary["datasheet"]
    iv = summary.get("percentile_interval")
    pc = None
    if iv is not None:
        pc = f"P{iv['percentile']:g} of {iv['samples']} reducers" + (
            f" (no 95 % interval: needs {iv['rings_needed']})" if not iv["has_interval"]
            else "")
    rows = [(k, k.rsplit("_", 1)[-1] if k.endswith(("_mm", "_deg")) else "",
             {NOMINAL_COLUMN: v, **({pc: v} if pc else {})})
            for k, v in b["modification"].items()]
    for what, unit, key in (("backlash", "arcmin", "backlash_arcmin"),
                            ("max P_h", "MPa", "max_ph_MPa"),
                            ("fewest pins in contact", "", "contacts_min")):
        rows.append((what, unit, {NOMINAL_COLUMN: c[key], **({pc: b[key]} if pc else {})}))
    rows += [("torsional rigidity", "N m/arcmin",
              {NOMINAL_COLUMN: d.get("torsional_rigidity_Nm_per_arcmin")}),
             ("lost motion", "arcmin", {NOMINAL_COLUMN: d.get("lost_motion_arcmin")})]
    return rows


def write_design(result: DesignResult, folder, source_text: str) -> dict:
    """Write the search's files.

    Parameters
    ----------
    result : DesignResult
    folder : str or pathlib.Path
        An existing folder; it receives candidates.csv, tradeoff.png, summary.json,
        report.md and the case file to use (``best_case.toml``).
    source_text : str
        The case file's text; ``best_case.toml`` is it with its [cycloid] modification
        keys set.

    Returns
    -------
    dict
        The summary, with the ``files`` written.

    Raises
    ------
    CaseError
        If ``source_text`` has no [cycloid] table.
    """
    folder = Path(folder)
    names = list(result.best.modification)
    with open(folder / "candidates.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([*names, "backlash_arcmin", "max_ph_MPa", "contacts_min", "feasible"])
        for c in result.candidates:
            w.writerow([*(f"{c.modification[k]:.6g}" for k in names),
                        f"{c.backlash_arcmin:.6g}", f"{c.max_ph_MPa:.6g}",
                        f"{c.contacts_min:g}", int(c.feasible)])
    save(tradeoff(result), folder / "tradeoff.png")
    section = result.case.layout.stage_section
    (folder / "best_case.toml").write_text(with_keys(source_text, section,
                                                     result.best.modification))
    summary = {**result.summary(), "files": ["candidates.csv", "tradeoff.png",
                                             "best_case.toml", "summary.json", "report.md"]}
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    (folder / "report.md").write_text(markdown(summary))
    return summary
