"""Measured data at scale (issue 14, item 5): time and peak memory of parsing a large CSV
and of the loop on many rows. A benchmark, not a test (no timed asserts in tests/).

    python benchmarks/measured_scale.py parse --rows 1000000     # target: < 1 GB
    python benchmarks/measured_scale.py loop --rows 100000       # target: < 2 GB, minutes
    python benchmarks/measured_scale.py loop --rows 1000000 --random   # target: < 60 s
    python benchmarks/measured_scale.py                          # both, each in its own
                                                                 # process (peak RSS apart)

Parse: a CSV written by numpy with the three required columns, oil temperature, time,
a run label and one further covariate; the loader alone. Loop: rig data of the sine
prototype from ``efficiency.loop.synthetic`` (its analytic model, the rig's torque sensors
with their noise; made in chunks of :data:`CHUNK` rows, since the model's evaluation takes
about 26 kB a point) written as a CSV with its sidecar, then ``toothfem loop CASE CSV``
in a child process: the loader, the loop (which bins the rows above
``Settings.max_points``), the report and its pictures. ``--random``: the parse benchmark's
CSV (:func:`write_csv`: efficiencies uniform in 0.5 to 0.95, which no model meets, so the
selection tries every effect) through the same command instead. Peak memory is the process's
maximum resident set (``ru_maxrss``; for the loop the child's), the interpreter and imports
included.
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


#: Rows of synthetic rig data made at a time (the model's evaluation takes about 26 kB a
#: point: 0.26 GB a chunk).
CHUNK = 10_000


def write_rig_csv(path: Path, case, rows: int) -> None:
    """``rows`` rows of synthetic rig data of ``case``, one a second (chunks of
    :data:`CHUNK`, each with its own seed and runs) as a CSV with its sidecar."""
    from dataclasses import replace

    from toothfem.efficiency.loop import synthetic as sy
    from toothfem.efficiency.loop.measured import to_csv

    with open(path, "w") as fh:
        for k, start in enumerate(range(0, rows, CHUNK)):
            n = min(CHUNK, rows - start)
            data = sy.generate(case, {"drag_torque": (20.0,)}, n_points=n, seed=1 + k,
                               oil_temp_C=(30.0, 80.0), hours=(n - 1) / 3600.0)
            data = replace(data, time_h=data.time_h + start / 3600.0,
                           run_id=np.array([f"c{k}-{r}" for r in data.run_id], dtype=object))
            if k == 0:
                sy.write(data, path)            # the sidecar: the rig's sensors
                fh.write(path.read_text())
            else:
                fh.write(to_csv(data).split("\n", 1)[1])


def bench_loop(rows: int, random: bool = False) -> dict:
    from toothfem import load_case

    case_file = ROOT / "cases" / "sine_prototype.toml"
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "rig.csv"
        t0 = time.perf_counter()
        if random:
            write_csv(csv, rows)
        else:
            write_rig_csv(csv, load_case(case_file), rows)
        t_gen = time.perf_counter() - t0
        t1 = time.perf_counter()
        p = subprocess.run([sys.executable, "-c", "import sys; from toothfem.cli import main; "
                            "sys.exit(main(sys.argv[1:]))", "loop", str(case_file), str(csv),
                            "--out", str(Path(tmp) / "loop")], capture_output=True, text=True)
        wall = time.perf_counter() - t1
        if p.returncode:
            raise SystemExit(p.stderr)
        rep = json.loads((Path(tmp) / "loop" / "report.json").read_text())
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return {"what": "loop", "rows": rep["n_rows"], "points": rep["n_points"],
            "generate_s": round(t_gen, 2), "wall_s": round(wall, 2),
            "loop_s": round(rep["elapsed_s"], 2), "peak_rss_MB": round(peak, 1),
            "effects": [e["name"] for e in rep["effects"]], "notes": rep["notes"],
            "model_evaluations": rep["model_evaluations"]}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", nargs="?", choices=("parse", "loop", "all"), default="all")
    ap.add_argument("--rows", type=int, default=None)
    ap.add_argument("--random", action="store_true",
                    help="loop: write_csv's random rows instead of the sine prototype's rig data")
    args = ap.parse_args(argv)
    if args.what == "all":
        for what, rows in (("parse", 1_000_000), ("loop", 100_000)):
            subprocess.run([sys.executable, __file__, what, "--rows", str(rows)], check=False)
        return 0
    rows = args.rows or (1_000_000 if args.what == "parse" else 100_000)
    out = bench_parse(rows) if args.what == "parse" else bench_loop(rows, args.random)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
