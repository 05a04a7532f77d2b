"""Efficiency map timing: a 100 x 100 map (output torque x input speed) of the sine case in
one vectorised call, against the same points evaluated one at a time (the baseline,
measured on a subset in the same run and scaled). Target (issue 6): the map under 1 s.

    .venv/bin/python benchmarks/efficiency_map.py [--case cases/sine_prototype.toml]
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from toothfem import load_case
from toothfem.efficiency import evaluation as m

ROOT = Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default=str(ROOT / "cases" / "sine_prototype.toml"))
    ap.add_argument("--size", type=int, default=100)
    args = ap.parse_args()
    case = load_case(args.case)
    speed, torque = m.operating_point(case)            # also warms the geometry cache
    t = np.linspace(0.05, 1.2, args.size) * torque
    n = np.linspace(0.1, 2.0, args.size) * speed
    tt, nn = np.meshgrid(t, n)
    best = []
    for _ in range(3):
        t0 = time.perf_counter()
        eta = m.predict(case, nn, tt)
        best.append(time.perf_counter() - t0)
    temps = np.linspace(20, 100, args.size)
    tt2, th = np.meshgrid(t, temps)
    t0 = time.perf_counter()
    m.predict(case, speed, tt2, th)
    t_temp = time.perf_counter() - t0
    k = 50
    idx = np.linspace(0, tt.size - 1, k).astype(int)
    t0 = time.perf_counter()
    for i in idx:
        m.predict(case, nn.flat[i], tt.flat[i])
    per_point = (time.perf_counter() - t0) / k
    one = min(best)
    print(f"case: {case.name}")
    print(f"{args.size} x {args.size} map (torque x speed): {one:.3f} s (best of 3; "
          f"target < 1 s), efficiency {100 * eta.min():.1f}..{100 * eta.max():.1f} %")
    print(f"{args.size} x {args.size} map (torque x oil temperature): {t_temp:.3f} s")
    print(f"baseline, one point per call: {per_point * 1e3:.2f} ms/point -> "
          f"{per_point * tt.size:.1f} s for the map; vectorised speed-up {per_point * tt.size / one:.0f}x")


if __name__ == "__main__":
    main()
