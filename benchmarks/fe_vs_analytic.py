"""Efficiency from the FE load sharing against the seeds' analytic split, side by side, for
the three cases (issue 4, item 6): a table (Markdown, printed) and a plot of efficiency
versus output torque (docs/img/fe_vs_analytic.png). The pin-housing drive is also run with
a clearance modification (equidistant +10 um, move distance -10 um), where the two splits
differ most.

    .venv/bin/python benchmarks/fe_vs_analytic.py            (about 1-2 min)
"""
from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from toothfem import load_case
from toothfem.efficiency import evaluation as m

ROOT = Path(__file__).resolve().parent.parent


def variants():
    ph = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    cyc = ph.cycloid
    yield "pin-housing, integral", ph
    yield "pin-housing, conventional", dataclasses.replace(
        ph, cycloid=dataclasses.replace(cyc, pin_structure="conventional"))
    yield "pin-housing, integral, +10/-10 um", dataclasses.replace(
        ph, cycloid=dataclasses.replace(cyc, equidistant_modification_mm=0.010,
                                        move_distance_modification_mm=-0.010))
    yield "RV-40E (assumed disc)", load_case(ROOT / "cases" / "rv40e.toml")
    yield "sine prototype (rig)", load_case(ROOT / "cases" / "sine_prototype.toml")


def main():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = []
    fig, axes = plt.subplots(1, 5, figsize=(22, 4.5))
    for ax, (label, case) in zip(axes, variants()):
        if case.drive == "sine":
            speed, torque = case.published["rig_input_speed_rpm"], \
                case.published["rig_output_torque_max_Nm"]
        else:
            speed, torque = m.operating_point(case)
        t0 = time.perf_counter()
        res = {s: m.evaluate(case, speed, torque, loads=s) for s in ("analytic", "fem")}
        dt = time.perf_counter() - t0
        a, f = res["analytic"], res["fem"]
        key = "mesh" if case.drive == "sine" else "pin_contacts"
        rows.append((label, speed, torque, 100 * a.efficiency[0], 100 * f.efficiency[0],
                     a.losses_W[key][0], f.losses_W[key][0], dt, f.notes))
        grid = np.linspace(0.1, 1.0, 19) * torque
        for s, style in (("analytic", "--"), ("fem", "-")):
            ax.plot(grid, 100 * m.evaluate(case, speed, grid, loads=s).efficiency, style,
                    label=f"{s} loads")
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("output torque [N m]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("efficiency [%]")
    axes[0].legend()
    fig.tight_layout()
    out = ROOT / "docs" / "img" / "fe_vs_analytic.png"
    fig.savefig(out, dpi=100)
    print("| case | speed [rpm] | torque [N m] | eta analytic [%] | eta FE [%] | contact loss "
          "analytic [W] | contact loss FE [W] | difference | time [s] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for label, n, t, ea, ef, la, lf, dt, _ in rows:
        print(f"| {label} | {n:g} | {t:.4g} | {ea:.2f} | {ef:.2f} | {la:.4g} | {lf:.4g} | "
              f"{100 * (lf / la - 1):+.1f} % | {dt:.1f} |")
    for label, *_, notes in rows:
        for note in notes:
            print(f"- {label} (FE): {note}")
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
