"""Pictures and text of the modification search (``toothfem design``)."""
from __future__ import annotations

from . import pyplot, wrap


def tradeoff(result):
    """Backlash against the maximum Hertz pressure of every candidate evaluated, the
    feasible ones told apart, the trade-off front, the targets and the best design marked.

    Parameters
    ----------
    result : toothfem.design.DesignResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    t = result.targets
    fig, ax = plt.subplots(figsize=(9, 6))
    for feasible, colour, label in ((False, "tab:gray", "misses a target"),
                                    (True, "tab:blue", "meets every target")):
        pts = [c for c in result.candidates if c.feasible == feasible]
        if pts:
            ax.scatter([c.backlash_arcmin for c in pts], [c.max_ph_MPa for c in pts], s=14,
                       color=colour, alpha=0.7, label=f"{label} ({len(pts)})")
    front = result.pareto()
    if front:
        ax.plot([c.backlash_arcmin for c in front], [c.max_ph_MPa for c in front], "-",
                color="tab:orange", lw=1.5,
                label=f"trade-off front (at least {t['min_contacts']} pins in contact)")
    b = result.best
    ax.scatter([b.backlash_arcmin], [b.max_ph_MPa], s=120, marker="*", color="tab:red",
               zorder=5, label="best: " + ", ".join(_shown(k, v)
                                                   for k, v in b.modification.items()))
    ax.axvline(t["max_backlash_arcmin"], color="k", ls="--", lw=1,
               label=f"max backlash {t['max_backlash_arcmin']:g} arcmin")
    if t.get("max_ph_MPa"):
        ax.axhline(t["max_ph_MPa"], color="k", ls=":", lw=1,
                   label=f"max P_h {t['max_ph_MPa']:g} MPa")
    at = (f" (P{t['percentile']:g} of {t['samples']} built reducers)"
          if t.get("percentile") else "")
    ax.set_xlabel(f"backlash [arcmin]{at}")
    ax.set_ylabel(f"maximum Hertz pressure [MPa]{at}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(wrap(result.case_name, 70) + "\nmodification search: backlash against "
                 "contact pressure", fontsize=10)
    return fig


def _shown(key: str, value: float) -> str:
    """``equidistant_modification_mm`` 6.2e-05 -> 'equidistant 0.062 um'."""
    name = key.split("_modification")[0].replace("_", " ")
    if key.endswith("_mm"):
        return f"{name} {value * 1e3:.3g} um"
    return f"{name} {value:.3g} deg"


def markdown(summary: dict) -> str:
    """report.md of the search: targets, the best modification, its own-table check.

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
    lines = [f"# Modification design: {summary['case']}", "",
             f"Targets: backlash <= {t['max_backlash_arcmin']:g} arcmin, at least "
             f"{t['min_contacts']} pins in contact"
             + (f", P_h <= {t['max_ph_MPa']:g} MPa" if t.get("max_ph_MPa") else
                ", the largest P_h minimised")
             + (f", at P{t['percentile']:g} of {t['samples']} reducers built within "
                "[tolerances]" if t.get("percentile") else "") + ".", "",
             f"{summary['evaluations']} candidates evaluated with the case's own influence "
             "tables and each candidate's initial gaps.", "",
             "| | " + " | ".join(b["modification"]) + " | backlash [arcmin] | max P_h [MPa] "
             "| fewest pins |", "|---" * (len(b["modification"]) + 4) + "|",
             "| best | " + " | ".join(f"{v:.4g}" for v in b["modification"].values())
             + f" | {b['backlash_arcmin']:.4g} | {b['max_ph_MPa']:.4g} | "
             f"{b['contacts_min']:g} |", "",
             "The best design as drawn (no deviations), with its own FE tables (in brackets: "
             "the case's tables with its gaps, as the search solved it):", ""]
    c, d = summary["check_with_own_tables"], summary["datasheet"]
    lines += [f"- maximum P_h {c['max_ph_MPa']:.4g} MPa ({c['search_tables_max_ph_MPa']:.4g}),"
              f" fewest pins {c['contacts_min']:g} ({c['search_tables_contacts_min']:g}), "
              f"backlash {c['backlash_arcmin']:.4g} arcmin "
              f"({c['search_tables_backlash_arcmin']:.4g});",
              f"- rigidity {d.get('torsional_rigidity_Nm_per_arcmin', float('nan')):.4g} "
              f"N m/arcmin, lost motion {d.get('lost_motion_arcmin', float('nan')):.4g} arcmin "
              f"at the rated {d.get('rated_torque_Nm', float('nan')):.4g} N m.", "",
              "Files: best_case.toml (the case with these modifications), candidates.csv, "
              "tradeoff.png, summary.json.", ""]
    return "\n".join(lines)


def summary_rows(summary: dict) -> list:
    """The search's best design as rows of :func:`toothfem.report.summary.text`: its
    modifications and what it gives (with its own FE tables).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.design.DesignResult.summary`.

    Returns
    -------
    list of (str, str, dict)
        (quantity, unit, {"best": value}).
    """
    b, c, d = summary["best"], summary["check_with_own_tables"], summary["datasheet"]
    rows = [(k, k.rsplit("_", 1)[-1] if k.endswith(("_mm", "_deg")) else "", {"best": v})
            for k, v in b["modification"].items()]
    rows += [("backlash", "arcmin", {"best": c["backlash_arcmin"]}),
             ("max P_h", "MPa", {"best": c["max_ph_MPa"]}),
             ("fewest contacts", "", {"best": c["contacts_min"]}),
             ("torsional rigidity", "N m/arcmin",
              {"best": d.get("torsional_rigidity_Nm_per_arcmin")}),
             ("lost motion", "arcmin", {"best": d.get("lost_motion_arcmin")})]
    return rows
