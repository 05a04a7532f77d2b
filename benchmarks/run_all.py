"""One command for the speed figures of issues 6 and 16, measured in one run on this machine:

* cold solves (issue 16), each in a fresh process (imports, meshes, factorisations, tables)
  with the chosen sparse backend (fem.linsolve) and with SciPy's SuperLU beside it: the
  full cycle (36 positions) of the pin-housing drive with conventional pins, the detailed
  mode at one position, the sine pair's cycle; and the peak memory of each process;
* ``toothfem efficiency CASE --loads fem`` for every shipped case, cold (a fresh process,
  an empty disk cache);
* cycle mode: full cycle (36 positions) of the pin-housing drive, a repeated load case on
  the same design (memory cache) and from the disk cache in a fresh solver;
* cycle mode against detailed mode (time per position, maximum pin force ratio) and against
  the CalculiX peer (recorded per-position time of benchmarks/calculix/results, or rerun);
* a 100 x 100 efficiency map of the sine case;
* the measured-data loop on 200 synthetic points;
* sweep throughput with 1 and 2 Dask workers;
* peak memory (this process and its children).

    .venv/bin/python benchmarks/run_all.py [--quick] [--run-peer] [--only-cold]

Targets (issue 6): cycle < 30 s, repeated load < 3 s, map < 1 s, loop (200 points) < 60 s,
2-worker sweep >= 1.6 x the 1-worker throughput. Issue 16: cold cycle < 4 s, detailed mode
< 3 s per position, sine cold cycle < 6 s, peak memory of the cycle < 1 GB, the efficiency
command with FE loads cold < 30 s per case. The machine's load average (1 min) is printed
beside every figure: on a shared machine it explains more of a time than the code does.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402

RESULTS = []


def report(name, value, unit, target=None, ok=None):
    RESULTS.append((name, value, unit, target, ok))
    mark = "" if ok is None else ("  [met]" if ok else "  [MISSED]")
    tgt = f"  (target {target})" if target else ""
    load = os.getloadavg()[0]
    print(f"{name:<58s} {value:>10.3f} {unit}{tgt}{mark}  [load {load:.1f}]", flush=True)


#: Cold runs, each timed in a fresh process: name -> what it computes.
COLD_RUNS = ("cycle", "detailed", "sine")


def cold_run(what: str) -> dict:
    """One cold design in this fresh process: seconds of the solve (the modules, gmsh and
    scikit-fem imported before, as in a sweep; meshes, factorisations and tables inside,
    no disk cache), and the process's peak memory (MB)."""
    import gmsh  # noqa: F401
    import skfem  # noqa: F401
    from toothfem.fem.drives import drive_for

    t0, c0 = time.perf_counter(), time.process_time()
    name = "sine_prototype" if what == "sine" else "cycloid_pinhousing"
    case = load_case(ROOT / "cases" / f"{name}.toml")
    drive = drive_for(case)
    torque = drive.member_torque(case.to_si().declared_output_torque_Nm())
    overrides = {} if what == "sine" else {"pin_structure": "conventional"}
    if what == "detailed":
        drive.solve_detailed(drive.fe_model(**overrides), drive.positions(36)[0], torque)
    else:                      # cold: no disk cache
        drive.cycle_solver(36, cache=False, **overrides).solve(torque)
    return dict(seconds=time.perf_counter() - t0, cpu_seconds=time.process_time() - c0,
                peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def cold_in_child(what: str, backend: str) -> dict:
    env = dict(os.environ, TOOTHFEM_SOLVER=backend)
    out = subprocess.run([sys.executable, __file__, "--cold", what], env=env, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def cold_solves(args):
    """Issue 16: cold cycle, detailed mode and sine cycle with the chosen backend and with
    SciPy's SuperLU, each in a fresh process (no disk cache)."""
    from toothfem.fem import linsolve

    chosen = linsolve.choose_backend()
    backends = [chosen] + (["superlu"] if chosen != "superlu" else [])
    print(f"sparse backends available: {list(linsolve.available_backends())}; "
          f"chosen: {chosen}")
    targets = dict(cycle=("cold full cycle, 36 positions, pin-housing", 4),
                   detailed=("detailed mode, cold, one position", 3),
                   sine=("sine pair cold cycle, 36 positions", 6))
    peak = {}
    for what in COLD_RUNS:
        label, limit = targets[what]
        for backend in backends:
            r = cold_in_child(what, backend)
            peak[what, backend] = r["peak_mb"]
            mine = backend == chosen
            report(f"{label} [{backend}]", r["seconds"], "s", f"< {limit} s" if mine else None,
                   r["seconds"] < limit if mine else None)
            # CPU time of the process (all its threads): near the wall time of an idle
            # machine for these mostly single-threaded solves; on a loaded one, far below it
            report(f"  the same, CPU time [{backend}]", r["cpu_seconds"], "s")
    for backend in backends:
        mb = peak["cycle", backend]
        mine = backend == chosen
        report(f"peak memory of the cold cycle [{backend}]", mb, "MB",
               "< 1024 MB" if mine else None, mb < 1024 if mine else None)


def efficiency_fem_cold():
    """Issue 16: ``toothfem efficiency CASE --loads fem`` for every shipped case, each in a
    fresh process with an empty disk cache ($TOOTHFEM_CACHE a new folder): imports, meshes,
    factorisations, influence tables and the FE load table at every tabulated torque."""
    for path in sorted((ROOT / "cases").glob("*.toml")):
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, TOOTHFEM_CACHE=cache)
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "toothfem.cli", "efficiency", str(path),
                            "--loads", "fem"], env=env, check=True, capture_output=True)
            seconds = time.perf_counter() - t0
        report(f"efficiency --loads fem, cold, {path.stem}", seconds, "s", "< 30 s",
               seconds < 30)


def cycle_and_detailed(args):
    from toothfem.fem import cycloid_fe as cf
    from toothfem.fem.drives import drive_for

    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    model = drive_for(case).fe_model(pin_structure="conventional")
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    phis = np.linspace(0, 2 * math.pi / model.geometry.pin_count, 36, endpoint=False)
    from toothfem.fem.cache import DiskCache

    with tempfile.TemporaryDirectory() as folder:
        cache = DiskCache(Path(folder))
        t0 = time.perf_counter()
        solver = cf.CycleSolver(model, phis, cache=cache)
        ls = solver.solve(torque)
        cycle = time.perf_counter() - t0
        report("cycle mode, full cycle of 36 positions", cycle, "s", "< 30 s", cycle < 30)
        t0 = time.perf_counter()
        solver.solve(1.5 * torque)
        rep = time.perf_counter() - t0
        report("repeated load case, same solver (memory)", rep, "s", "< 3 s", rep < 3)
        t0 = time.perf_counter()
        cf.CycleSolver(model, phis, cache=cache).solve(0.5 * torque)
        disk = time.perf_counter() - t0
        report("repeated load case, fresh solver (disk cache)", disk, "s", "< 3 s", disk < 3)
    per_pos = cycle / len(phis)
    picks = [0] if args.quick else [0, 12, 25]
    ratios, times = [], []
    for p in picks:
        t0 = time.perf_counter()
        det = cf.solve_detailed(model, phis[p], torque)
        times.append(time.perf_counter() - t0)
        ratios.append(float(det.load_sharing.force.max() / ls.force[p].max()))
    report("detailed mode, time per position", float(np.mean(times)), "s")
    report("detailed / cycle time per position", float(np.mean(times)) / per_pos, "x")
    report("detailed / cycle max pin force (worst of positions)",
           max(ratios, key=lambda r: abs(r - 1)), "-", "within 2 %",
           all(abs(r - 1) < 0.02 for r in ratios))
    if args.run_peer:
        out = Path(tempfile.mkdtemp(prefix="toothfem_peer_"))
        subprocess.run([sys.executable, str(ROOT / "benchmarks" / "calculix" / "run_peer.py"),
                        "--positions", "0", "--mesh-size-mm", "0.004", "--out", str(out)],
                       check=True)
        folder, how = out, "this run"
    else:
        folder, how = ROOT / "benchmarks" / "calculix" / "results", "recorded"
    with open(folder / "positions.csv") as fh:
        rows = [r for r in csv.DictReader(fh) if float(r["mesh_size_mm"]) == 0.004]
    peer = float(np.mean([float(r["ccx_wall_s"]) for r in rows]))
    report(f"CalculiX per position ({how}, 4 um contact mesh)", peer, "s")
    report("CalculiX / cycle mode time per position", peer / per_pos, "x", ">= 10 x",
           peer / per_pos >= 10)


def efficiency_map():
    from toothfem.efficiency import evaluation as m

    case = load_case(ROOT / "cases" / "sine_prototype.toml")
    speed, torque = m.operating_point(case)
    tt, nn = np.meshgrid(np.linspace(0.05, 1.2, 100) * torque,
                         np.linspace(0.1, 2.0, 100) * speed)
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        m.predict(case, nn, tt)
        best = min(best, time.perf_counter() - t0)
    report("efficiency map 100 x 100 (sine case, best of 3)", best, "s", "< 1 s", best < 1)


def loop_time():
    """The loop on 200 synthetic points: the slowest catalog case (pin sliding on the
    cycloid: FE clearance springs and EHL friction re-evaluated per step)."""
    from toothfem.efficiency.loop import effects as fx
    from toothfem.efficiency import loop as lp
    from toothfem.efficiency.loop import synthetic as sy

    sine = load_case(ROOT / "cases" / "sine_prototype.toml")
    cyc = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    cat = fx.catalog()
    worst = 0.0
    for name, (case, truth, kw) in sy.reference_scenarios(sine, cyc).items():
        data = sy.generate(case, {name: truth}, n_points=200, seed=1, catalog=cat, **kw)
        t0 = time.perf_counter()
        lp.run_loop(case, data, cat)
        dt = time.perf_counter() - t0
        worst = max(worst, dt)
        report(f"loop on 200 points, {name} ({case.drive})", dt, "s")
    report("loop on 200 points, slowest catalog effect", worst, "s", "< 60 s", worst < 60)


def sweep_throughput(args):
    """Design points per second through Dask with 1 and 2 workers (8 designs x 2 torques,
    8 positions each, no disk cache), best of alternating runs (benchmarks/sweep_throughput.py)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from sweep_throughput import throughput

    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    best = {1: 0.0, 2: 0.0}
    for _ in range(1 if args.quick else 2):
        for workers in (1, 2):
            with tempfile.TemporaryDirectory() as tmp:
                _, points_per_s, _, _ = throughput(case, 8, 8, None, workers,
                                                   Path(tmp) / "sweep")
            best[workers] = max(best[workers], points_per_s)
    report("sweep throughput, 1 worker", best[1], "points/s")
    report("sweep throughput, 2 workers", best[2], "points/s")
    ratio = best[2] / best[1]
    report("sweep throughput ratio 2 / 1 workers", ratio, "x", ">= 1.6 x", ratio >= 1.6)


def peak_memory():
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    report("peak memory, this process", own, "MB")
    report("peak memory, largest child process", kids, "MB")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="one detailed position, one sweep run per worker count")
    ap.add_argument("--run-peer", action="store_true",
                    help="rerun CalculiX at one position instead of reading its recorded time")
    ap.add_argument("--cold", choices=COLD_RUNS,
                    help="(internal) time one cold run in this process, print it as JSON")
    ap.add_argument("--only-cold", action="store_true",
                    help="the issue-16 cold runs only (solves and the efficiency command)")
    args = ap.parse_args()
    if args.cold:
        print(json.dumps(cold_run(args.cold)))
        return
    print(f"toothfem benchmarks on {os.cpu_count()} cores, load average "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())} (1, 5, 15 min)")
    cold_solves(args)
    efficiency_fem_cold()
    if args.only_cold:
        return
    cycle_and_detailed(args)
    efficiency_map()
    loop_time()
    sweep_throughput(args)
    peak_memory()
    missed = [r[0] for r in RESULTS if r[4] is False]
    print("all targets met" if not missed else f"targets missed: {missed}")


if __name__ == "__main__":
    main()
