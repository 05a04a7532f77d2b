"""Measured data at scale (issue 14, item 5): time and peak memory of parsing a large CSV
and of the loop on many points. A benchmark, not a test (no timed asserts in tests/).

    python benchmarks/measured_scale.py parse --rows 1000000     # target: < 1 GB
    python benchmarks/measured_scale.py loop --rows 100000       # target: < 2 GB, minutes
    python benchmarks/measured_scale.py                          # both, each in its own
                                                                 # process (peak RSS apart)

Parse: a CSV written by numpy with the three required columns, oil temperature, time,
a run label and one further covariate. Loop: points of the sine prototype from
``efficiency.synthetic`` (its analytic model plus noise), through ``efficiency.loop`` with
the default catalog and analytic loads. Peak memory is the process's maximum resident set
(``ru_maxrss``), the interpreter and imports included.
"""
from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024     # Linux: kB


def write_csv(path: Path, rows: int, seed: int = 0) -> None:
    """A measured-data CSV of ``rows`` good rows (written in chunks)."""
    rng = np.random.default_rng(seed)
    with open(path, "w") as fh:
        fh.write("# source: synthetic benchmark\n"
                 "input_speed_rpm,output_torque_Nm,efficiency,oil_temp_C,time_h,run_id,"
                 "vibration_mm_s\n")
        for start in range(0, rows, 100_000):
            n = min(100_000, rows - start)
            cols = [rng.uniform(100, 3000, n), rng.uniform(1, 200, n),
                    rng.uniform(0.5, 0.95, n), rng.uniform(20, 90, n),
                    (start + np.arange(n)) / 3600.0]
            body = np.column_stack(cols)
            lines = [f"{a:.6g},{b:.6g},{c:.6g},{d:.4g},{e:.6g},r{(start + i) // 10000},"
                     f"{0.1 * i % 7:.3g}" for i, (a, b, c, d, e) in enumerate(body)]
            fh.write("\n".join(lines) + "\n")


def bench_parse(rows: int) -> dict:
    from toothfem.efficiency.loop import measured as ms

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.csv"
        write_csv(path, rows)
        size_mb = path.stat().st_size / 2**20
        base = _peak_mb()
        t0 = time.perf_counter()
        data = ms.load_measured(path)
        wall = time.perf_counter() - t0
    return {"what": "parse", "rows": len(data), "file_MB": round(size_mb, 1),
            "wall_s": round(wall, 2), "peak_rss_MB": round(_peak_mb(), 1),
            "peak_rss_before_parse_MB": round(base, 1), "rejected": len(data.rejected)}


def bench_loop(rows: int) -> dict:
    from toothfem import load_case
    from toothfem.efficiency import loop as lp
    from toothfem.efficiency.loop import synthetic as sy

    case = load_case(ROOT / "cases" / "sine_prototype.toml")
    t0 = time.perf_counter()
    data = sy.generate(case, {}, n_points=rows, seed=1)
    t_gen = time.perf_counter() - t0
    t1 = time.perf_counter()
    report = lp.run_loop(case, data)
    wall = time.perf_counter() - t1
    return {"what": "loop", "rows": len(data), "generate_s": round(t_gen, 2),
            "wall_s": round(wall, 2), "peak_rss_MB": round(_peak_mb(), 1),
            "n_points_used": report.n_points, "stop": report.stop_reason,
            "model_evaluations": report.evaluations}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", nargs="?", choices=("parse", "loop", "all"), default="all")
    ap.add_argument("--rows", type=int, default=None)
    args = ap.parse_args(argv)
    if args.what == "all":
        for what, rows in (("parse", 1_000_000), ("loop", 100_000)):
            subprocess.run([sys.executable, __file__, what, "--rows", str(rows)], check=False)
        return 0
    rows = args.rows or (1_000_000 if args.what == "parse" else 100_000)
    out = bench_parse(rows) if args.what == "parse" else bench_loop(rows)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
