"""Pins in contact and maximum pin force versus torque, unmodified and modified disc
(cycle mode, pin-housing drive). Writes docs/img/pins_vs_torque.png and prints the table.

Run: .venv/bin/python benchmarks/cycloid_modification_sweep.py
"""
from dataclasses import replace
from pathlib import Path

import numpy as np

from toothfem import load_case
from toothfem.fem import cycloid_fe as cf
from toothfem.report.contact import contacts_versus_torque
from toothfem.fem.drives import drive_for

ROOT = Path(__file__).resolve().parent.parent
PHI = np.array([0.05])                     # one generic crank angle
TORQUES = np.array([10, 25, 50, 91.85, 150, 250, 400])

if __name__ == "__main__":
    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    base = drive_for(case).fe_model()
    designs = {
        "unmodified": base.geometry,
        "equidistant +10 um, move -10 um": replace(base.geometry, equidistant_m=10e-6,
                                                   move_distance_m=-10e-6),
        "equidistant +20 um, move -10 um": replace(base.geometry, equidistant_m=20e-6,
                                                   move_distance_m=-10e-6),
    }
    counts, fmax = [], []
    print("| design | " + " | ".join(f"T = {t:g} N m" for t in TORQUES) + " |")
    print("|---|" + "---|" * len(TORQUES))
    for name, g in designs.items():
        solver = cf.CycleSolver(replace(base, geometry=g), PHI)
        res = [solver.solve(float(t)) for t in TORQUES]
        n = [int(r.contacts_per_position[0]) for r in res]
        f = [float(r.force.max()) for r in res]
        counts.append(n)
        fmax.append(f)
        print(f"| {name} | " + " | ".join(f"{a} pins, {b:.0f} N" for a, b in zip(n, f)) + " |")
    fig = contacts_versus_torque(TORQUES, counts, fmax, list(designs),
                                 title="pin-housing drive, one disc, crank angle 2.9 deg")
    out = ROOT / "docs" / "img" / "pins_vs_torque.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")
