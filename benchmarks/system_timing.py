"""Speed of the system model (issue 21, item 7), on this machine, cold against warm in the
same run (the chained load paths it replaced were removed at issue 38; their figures of
the last run that had them stay in benchmarks/results/system_timing_chained.json):

- the hysteresis loop (both flanks, friction on, ``--steps`` torque steps: 5 steps + 1
  points, 36 positions) cold (a fresh process with an empty FE cache: meshes,
  factorisations, the loop) and warm (the tables on disk);
- a tolerance ensemble through the system on 2 workers (``--rings``, default the target's
  1000; the tables already on disk): its wall time, Dask's start included.

Run: .venv/bin/python benchmarks/system_timing.py [--case cases/...toml] [--steps 8]
     [--rings 1000] [--workers 2]
Targets (issue 21): the loop under 15 s cold and 3 s warm; 1000 rings under 90 s on 2
workers.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

LOOP = r"""
import sys, time, json
t0 = time.perf_counter()
from toothfem import load_case
from toothfem.efficiency import rated_output_torque
from toothfem.efficiency.no_load import path_friction
from toothfem.fem.datasheet.sheet import datasheet
from toothfem.fem.drives import drive_for
from toothfem.fem.system.datasheet import SystemTwist
case = load_case(sys.argv[1]); steps = int(sys.argv[2])
drive = drive_for(case); si = case.to_si()
rated, _ = rated_output_torque(si); supports = drive.supports(si.supports)
t1 = time.perf_counter()
system = drive.system_model(supports, 36)
for s in system.slots:
    s.solver.prepare()
t2 = time.perf_counter()
sheet = datasheet(SystemTwist(system, friction=path_friction(si, drive)), rated, steps=steps)
t3 = time.perf_counter()
print(json.dumps({"import_s": t1 - t0, "tables_s": t2 - t1, "loop_s": t3 - t2,
                  "total_s": t3 - t0, "rigidity": sheet.rigidity_Nm_per_arcmin}))
"""


def loop(case, steps, cache):
    env = dict(os.environ, TOOTHFEM_CACHE=str(cache))
    out = subprocess.run([sys.executable, "-c", LOOP, str(case), str(steps)],
                         capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def ensemble(case, rings, workers):
    from toothfem import load_case
    from toothfem.tolerance import tolerance_analysis

    c = load_case(case)
    tolerance_analysis(c, samples=2, share_samples=0, workers=1, progress=False)  # tables
    t0 = time.perf_counter()
    tolerance_analysis(c, samples=rings, share_samples=0, workers=workers, progress=False)
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default=str(ROOT / "cases" / "cycloid_pinhousing.toml"))
    ap.add_argument("--steps", type=int, default=8)
    ap.add_argument("--rings", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    out = {}
    with tempfile.TemporaryDirectory() as cold:
        out["system_cold"] = loop(args.case, args.steps, Path(cold) / "system")
        out["system_warm"] = loop(args.case, args.steps, Path(cold) / "system")
    wall = ensemble(args.case, args.rings, args.workers)
    out["ensemble_s"], out["rings"] = wall, args.rings
    points = 5 * args.steps + 1
    print(f"case {Path(args.case).name}, loop of {points} points x 36 positions, friction on")
    print(f"{'':28s}{'cold':>10s}{'warm':>10s}{'ratio':>8s}{'target':>16s}")
    c, w = out["system_cold"]["total_s"], out["system_warm"]["total_s"]
    print(f"{'loop, total [s]':28s}{c:10.2f}{w:10.2f}{c / w:8.2f}{'15 cold, 3 warm':>16s}")
    rings = f"{args.rings} rings on {args.workers} workers [s]"
    print(f"{rings:28s}{wall:10.1f}"
          f"{'':18s}{90.0 * args.rings / 1000:9.1f}")
    res = ROOT / "benchmarks" / "results" / "system_timing.json"
    res.write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
