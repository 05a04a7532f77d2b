"""Sweep throughput with 1 and 2 Dask workers, and the cost of a repeated load case on the
same design: from the solver's memory, from the disk cache in a fresh solver, and cold.

Designs: the pin-housing drive with the eccentricity varied, two output torques each, the
cycle mode over --positions crank angles, no disk cache (every design is computed). The
clusters are started and warmed (imports) before the clock starts. The machine is shared:
the runs alternate 1, 2, 1, 2 ... workers (--repeat times) and the best of each counts; the
load average before each run and the workers' CPU time (busy = CPU / (workers x wall):
below 100 % means the workers waited, e.g. for other processes on the machine) are printed.

Run: .venv/bin/python benchmarks/sweep_throughput.py [--designs 8] [--positions 8] [--repeat 2]
Targets (issue 6): 2 workers >= 1.6x the throughput of 1 on this 2-core machine; a new
torque on a known design costs no factorisation (memory and disk: milliseconds).
"""
import argparse
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def _cpu_s():
    import resource

    u = resource.getrusage(resource.RUSAGE_SELF)
    return u.ru_utime + u.ru_stime


def _warm():
    import gmsh  # noqa: F401
    import skfem  # noqa: F401

    import toothfem.fem.cycloid_fe  # noqa: F401
    import toothfem.sweep  # noqa: F401


def throughput(case, designs, positions, pins, n_workers, out):
    from distributed import Client, LocalCluster

    from toothfem.sweep import sweep

    ecc = list(np.round(np.linspace(0.9, 1.05, designs), 4))
    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        client.run(_warm)
        cpu0 = sum(client.run(_cpu_s).values())
        t0 = time.perf_counter()
        res = sweep(case, {"cycloid.eccentricity_mm": [float(e) for e in ecc]},
                    torques_Nm=[100.0, 167.0], positions=positions, pins=pins,
                    scheduler=client, out=out, cache_dir=False, progress=False)
        wall = time.perf_counter() - t0
        cpu = sum(client.run(_cpu_s).values()) - cpu0
    if res.failed:
        raise SystemExit(f"{res.failed} points failed: see {res.table}")
    return designs / wall, len(res.rows) / wall, wall, cpu


def repeated_load(case, positions, pins):
    from toothfem.fem import cycloid_fe as cf
    from toothfem.fem.cache import DiskCache
    from toothfem.fem.drives import drive_for

    model = drive_for(case).fe_model(pin_structure=pins)
    phis = np.linspace(0, 2 * math.pi / model.geometry.pin_count, positions, endpoint=False)
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    with tempfile.TemporaryDirectory() as tmp:
        cache = DiskCache(Path(tmp))
        t0 = time.perf_counter()
        solver = cf.CycleSolver(model, phis, cache=cache)
        solver.solve(torque)
        t1 = time.perf_counter()
        solver.solve(1.5 * torque)
        t2 = time.perf_counter()
        cf.CycleSolver(model, phis, cache=cache).solve(1.5 * torque)
        t3 = time.perf_counter()
    return t1 - t0, t2 - t1, t3 - t2


def main(argv=None):
    from toothfem import load_case

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--designs", type=int, default=8)
    ap.add_argument("--positions", type=int, default=8)
    ap.add_argument("--pins", default=None, choices=("conventional", "integral", "rigid"),
                    help="pin structure (default: the case's, integral)")
    ap.add_argument("--repeat", type=int, default=2, help="runs per worker count (best counts)")
    ap.add_argument("--cache-positions", type=int, default=36,
                    help="positions of the repeated-load timing (default 36)")
    args = ap.parse_args(argv)
    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    pins = args.pins or case.cycloid.pin_structure
    rates = {1: 0.0, 2: 0.0}
    with tempfile.TemporaryDirectory() as tmp:
        for run in range(args.repeat):
            for n in (1, 2):
                load = os.getloadavg()[0]
                d, p, wall, cpu = throughput(case, args.designs, args.positions, pins, n,
                                             Path(tmp) / f"w{n}-{run}")
                rates[n] = max(rates[n], d)
                print(f"{n} worker{'s' if n > 1 else ' '}: {args.designs} designs x 2 torques, "
                      f"{args.positions} positions, {pins} pins: {wall:.1f} s -> "
                      f"{d:.3f} designs/s, {p:.3f} design points/s; worker CPU "
                      f"{cpu / args.designs:.1f} s/design, busy {cpu / (n * wall):.0%} "
                      f"(load average before: {load:.1f})")
    print(f"throughput ratio 2/1 workers (best runs): {rates[2] / rates[1]:.2f}x   "
          "target >= 1.6x")
    load = os.getloadavg()[0]
    cold, memory, disk = repeated_load(case, args.cache_positions, pins)
    print(f"(load average before: {load:.1f})")
    print(f"repeated load case, {args.cache_positions} positions, {pins} pins: cold "
          f"{cold:.2f} s; new torque from memory {memory * 1e3:.1f} ms; from the disk cache "
          f"in a fresh solver {disk * 1e3:.1f} ms ({cold / disk:.0f}x faster than cold)")


if __name__ == "__main__":
    main()
