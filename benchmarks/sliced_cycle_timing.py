"""A sliced cycle (issue 43): the pin-housing drive (its integral housing, or --pins), 36
positions, the face width in 9 slices under a 3 arcmin tilt and an 8 um crown, cold (no
disk cache: meshes, factorisations, influence tables and the sliced solves), in one
process; prints the planar and sliced figures and the time of each stage.

Run (cold, the whole process): .venv/bin/python benchmarks/sliced_cycle_timing.py
Target (issue 43): a sliced cycle (9 slices, 36 positions) under 5 s cold.
"""
import argparse
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402
from toothfem.fem.cycloid_fe.slices import FaceSpec, solve_sliced  # noqa: E402
from toothfem.fem.drives import drive_for  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pins", default=None, choices=("conventional", "integral"))
    ap.add_argument("--positions", type=int, default=36)
    ap.add_argument("--slices", type=int, default=9)
    ap.add_argument("--tilt-arcmin", type=float, default=3.0)
    ap.add_argument("--crown-um", type=float, default=8.0)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    drive = drive_for(case)
    solver = drive.cycle_solver(args.positions, cache=None,
                                **({} if args.pins is None else {"pin_structure": args.pins}))
    torque = drive.member_torque(case.operating.output_torque_Nm)
    planar = solver.solve(torque)
    t1 = time.perf_counter()
    face = FaceSpec(args.slices, tilt_rad=math.radians(args.tilt_arcmin / 60),
                    crown_m=args.crown_um * 1e-6)
    sliced = solve_sliced(solver, face, torque)
    t2 = time.perf_counter()
    print(f"pins {solver.model.pin_structure}, {args.positions} positions, torque "
          f"{torque:.2f} N m")
    print(f"planar: F_max {planar.force.max():.2f} N, P_h {planar.ph.max() / 1e6:.1f} MPa; "
          f"set-up and planar cycle {t1 - t0:.2f} s")
    print(f"{args.slices} slices, tilt {args.tilt_arcmin:g} arcmin, crown {args.crown_um:g} um: "
          f"F_max {sliced.load_sharing.force.max():.2f} N, P_h "
          f"{sliced.load_sharing.ph.max() / 1e6:.1f} MPa; sliced solve {t2 - t1:.2f} s")
    print(f"total in the process {t2 - t0:.2f} s")


if __name__ == "__main__":
    main()
