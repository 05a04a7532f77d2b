"""The accuracy life's files (``toothfem wear``): history.csv, lost_motion.png (the lost
motion against the hours with the parts' contributions) and summary.json."""
from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..quantities import WEAR
from . import pyplot, save

if TYPE_CHECKING:      # annotations only: the record's .write() calls this module
    from ..wear import WearResult

#: history.csv's columns of each row's figures (the clearances follow, in um).
COLUMNS = tuple(WEAR)


def wear_rows(result: WearResult) -> list:
    """The table's rows: each figure at 0 h and at the end, the hours to the limit.

    Parameters
    ----------
    result : WearResult

    Returns
    -------
    list of (str, str)
        Quantity with its unit, and "start -> end".
    """
    first, last = result.history[0], result.history[-1]
    rows = []
    for key, q in WEAR.items():
        if key == "hours":
            continue
        unit = q.unit_symbol()
        rows.append((f"{q.label}" + (f" [{unit}]" if unit else ""),
                     f"{first[key]:.4g} at 0 h -> {last[key]:.4g} at {last['hours']:g} h"))
    for part in first["clearance_um"]:
        rows.append((f"clearance worn, {part} [um]", f"{last['clearance_um'][part]:.3g}"))
    lim, t = result.lost_motion_limit_arcmin, result.hours_to_limit
    if lim is not None:
        rows.append((f"hours to the lost-motion limit {lim:g} arcmin [h]",
                     f"{t:.4g}" if t is not None else f"not reached in {result.hours:g}"))
    rows.append(("wear coefficient K_b (boundary)", f"{result.wear_coefficient:.3g} "
                                                   f"({result.coefficient_source})"))
    return rows


def lost_motion_figure(result: WearResult):
    """The lost motion against the hours, its parts stacked (each part's share of the
    twist between -3 % and +3 % of the rated torque), the backlash beside it.

    Parameters
    ----------
    result : WearResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    rows = result.history
    hours = np.array([r["hours"] for r in rows])
    parts = list(rows[0]["lost_motion_parts_arcmin"])
    stack = np.array([[r["lost_motion_parts_arcmin"].get(p, 0.0) for r in rows]
                      for p in parts])
    fig, ax = plt.subplots(figsize=(9, 5.4))
    ax.stackplot(hours, stack, labels=parts, alpha=0.55)
    ax.plot(hours, [r["lost_motion_arcmin"] for r in rows], "k.-",
            label="lost motion ±3 % of the rated torque")
    ax.plot(hours, [r["backlash_arcmin"] for r in rows], "--", color="tab:red",
            label="backlash")
    lim = result.lost_motion_limit_arcmin
    if lim is not None:
        t = result.hours_to_limit
        ax.axhline(lim, color="tab:purple", lw=1, ls=":",
                   label=f"limit {lim:g} arcmin" + (f": reached at {t:.0f} h"
                                                    if t is not None else ": not reached"))
    ax.set_xlabel("hours of the duty cycle [h]")
    ax.set_ylabel("lost motion [arcmin]")
    ax.set_title(f"{result.case_name}\nwear K_b = {result.wear_coefficient:.2g}: lost "
                 "motion and its parts against the hours", fontsize=10)
    ax.set_xlim(0, hours[-1])
    ax.set_ylim(0, None)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    return fig


def wear_figures(result: WearResult) -> dict:
    """File name -> figure.

    Parameters
    ----------
    result : WearResult

    Returns
    -------
    dict
    """
    return {"lost_motion.png": lost_motion_figure(result)}


def write_wear(result: WearResult, folder) -> dict:
    """history.csv, lost_motion.png and summary.json into ``folder`` (it must exist).

    Parameters
    ----------
    result : WearResult
    folder : path

    Returns
    -------
    dict
        The summary with the names of the files written.
    """
    folder = Path(folder)
    rows = result.history
    parts = list(rows[0]["lost_motion_parts_arcmin"])
    clear = list(rows[0]["clearance_um"])
    with open(folder / "history.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(COLUMNS) + [f"lost_motion_{p.replace(' ', '_')}_arcmin" for p in parts]
                   + [f"clearance_{c.replace(' ', '_')}_um" for c in clear])
        for r in rows:
            w.writerow([f"{r[k]:.9g}" for k in COLUMNS]
                       + [f"{r['lost_motion_parts_arcmin'].get(p, 0.0):.9g}" for p in parts]
                       + [f"{r['clearance_um'][c]:.9g}" for c in clear])
    for name, fig in wear_figures(result).items():
        save(fig, folder / name)
    summary = result.summary()
    summary["files"] = ["history.csv", "lost_motion.png", "summary.json"]
    with open(folder / "summary.json", "w") as fh:
        json.dump(summary, fh, indent=2)
    return summary
