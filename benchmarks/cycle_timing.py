"""Wall time of a full meshing cycle (36 positions) of the pin-housing drive in cycle mode,
a repeated load case on the same design, and the CalculiX peer's time per position on a
comparable mesh (read from benchmarks/calculix/results, or rerun with --run-peer).

Run: .venv/bin/python benchmarks/cycle_timing.py [--pins conventional|integral|rigid]
Targets (issue 3): full cycle under 30 s; per position at least 10x faster than the peer.
"""
import argparse
import csv
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402
from toothfem.fem import cycloid_fe as cf  # noqa: E402
from toothfem.fem.drives import drive_for  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pins", default="conventional",
                    choices=("conventional", "integral", "rigid"))
    ap.add_argument("--positions", type=int, default=36)
    ap.add_argument("--peer-mesh-mm", type=float, default=0.004,
                    help="peer element size at the contacts (comparable mesh)")
    ap.add_argument("--run-peer", action="store_true",
                    help="run the peer at one position now instead of reading its results")
    args = ap.parse_args(argv)
    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    model = drive_for(case).fe_model(pin_structure=args.pins)
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    phis = np.linspace(0, 2 * math.pi / model.geometry.pin_count, args.positions,
                       endpoint=False)
    t0 = time.perf_counter()
    solver = cf.CycleSolver(model, phis)
    _ = solver._setup                               # meshes, factorisation, pin/housing model
    t1 = time.perf_counter()
    ls = solver.solve(torque)
    t2 = time.perf_counter()
    solver.solve(1.5 * torque)                      # same design, new load case
    t3 = time.perf_counter()
    cycle = t2 - t0
    if args.run_peer:
        out = Path("/tmp/toothfem_timing_peer")
        subprocess.run([sys.executable, str(ROOT / "benchmarks" / "calculix" / "run_peer.py"),
                        "--positions", "0", "--mesh-size-mm", str(args.peer_mesh_mm),
                        "--out", str(out)], check=True)
        folder = out
    else:
        folder = ROOT / "benchmarks" / "calculix" / "results"
    with open(folder / "positions.csv") as fh:
        rows = [r for r in csv.DictReader(fh) if float(r["mesh_size_mm"]) == args.peer_mesh_mm]
    peer = float(np.mean([float(r["ccx_wall_s"]) for r in rows]))
    per_position = cycle / args.positions
    print(f"pins: {args.pins}; F_max over the cycle {ls.force.max():.1f} N; "
          f"disc dofs {solver._setup[2].basis.N}")
    print(f"full cycle, {args.positions} positions: {cycle:.1f} s "
          f"(setup {t1 - t0:.1f} s + solves {t2 - t1:.1f} s)   target < 30 s")
    print(f"repeated load case on the same design: {t3 - t2:.3f} s   target < 3 s")
    print(f"per position: toothfem {per_position:.2f} s, CalculiX {peer:.1f} s "
          f"(h_c = {args.peer_mesh_mm} mm, {'this run' if args.run_peer else 'recorded'}) "
          f"-> ratio {peer / per_position:.0f}x   target >= 10x")


if __name__ == "__main__":
    main()
