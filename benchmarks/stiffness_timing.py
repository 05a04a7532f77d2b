"""Speed of the hysteresis loop (issue 11, item 8): 41 torque steps x 36 positions of the
pin-housing drive through the system model reuse its discs' influence tables, so the loop
factorises nothing beyond the tables' own and takes seconds once the tables exist.

Run: .venv/bin/python benchmarks/stiffness_timing.py [--case cases/...toml] [--positions 36]
     [--steps 8]
Target: the loop under 5 s once the tables exist; no factorisation during the loop.
"""
import argparse
import sys
import time
from pathlib import Path

import scipy.sparse.linalg as sla

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402
from toothfem.efficiency import rated_output_torque  # noqa: E402
from toothfem.fem.datasheet.sheet import datasheet, loop_torques  # noqa: E402
from toothfem.fem.drives import drive_for  # noqa: E402
from toothfem.fem.system.datasheet import SystemTwist  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default=str(ROOT / "cases" / "cycloid_pinhousing.toml"))
    ap.add_argument("--positions", type=int, default=36)
    ap.add_argument("--steps", type=int, default=8)
    args = ap.parse_args(argv)
    case = load_case(args.case)
    drive = drive_for(case)
    rated, _ = rated_output_torque(case)
    supports = drive.supports(case.to_si().supports)
    t0 = time.perf_counter()
    system = drive.system_model(supports, args.positions)
    for slot in system.slots:            # meshes and factorises, or reads the disk cache
        slot.solver.prepare()
    t1 = time.perf_counter()
    count = {"n": 0}
    original = sla.splu

    def counting(*a, **kw):              # every sparse LU during the loop is counted
        count["n"] += 1
        return original(*a, **kw)

    sla.splu = counting
    try:
        t2 = time.perf_counter()
        sheet = datasheet(SystemTwist(system), rated, steps=args.steps)
        t3 = time.perf_counter()
    finally:
        sla.splu = original
    n_torques = len(loop_torques(rated, args.steps))
    print(f"case {case.name}: {args.positions} positions, both flanks, system model")
    print(f"tables (mesh + factorisation, or the disk cache): {t1 - t0:.1f} s")
    print(f"hysteresis loop, {n_torques} torque steps x {args.positions} positions and the "
          f"catalogue points: {t3 - t2:.2f} s   target < 5 s")
    print(f"factorisations during the loop: {count['n']}   target 0")
    print(f"rigidity {sheet.rigidity_Nm_per_arcmin:.4g} N m/arcmin, lost motion "
          f"{sheet.lost_motion_arcmin:.4g} arcmin, backlash {sheet.backlash_arcmin:.4g} "
          "arcmin")


if __name__ == "__main__":
    main()
