"""How long the console script takes to answer ``toothfem --help`` (issue: the suite in
three minutes, part 7, item 5), against an interpreter that does nothing, in the same run.

Each round runs ``python -c pass`` and ``toothfem --help`` once, in turn, as whole processes
(wall time from ``time.perf_counter`` around ``subprocess.run``); the ratio is taken round
by round, so that a machine whose speed drifts (another job starting) moves both figures
together. Printed: each command's minimum, median and maximum and the median ratio. A
warm-up round is not counted (it compiles the byte code and fills the file cache). The
target: ``--help`` under 0.5 s on the 2-core development machine; the commands' modules
import their heavy parts inside their functions (toothfem/cli.py), so what remains is
the interpreter, argparse and the command modules.

Run: .venv/bin/python benchmarks/cli_startup.py [--rounds 20] [--json FILE]
Also: ``/usr/bin/time -v .venv/bin/toothfem --help`` for one run with its peak memory.
"""
import argparse
import json
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

BIN = Path(sys.executable).parent


def wall(cmd) -> float:
    """Seconds of one run of ``cmd`` (its output discarded); it must exit 0."""
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=20, help="counted rounds (default 20)")
    ap.add_argument("--json", default=None, help="also write the figures here")
    args = ap.parse_args(argv)
    script = shutil.which("toothfem", path=str(BIN)) or shutil.which("toothfem")
    if script is None:
        sys.exit("no toothfem console script beside this interpreter or on PATH")
    commands = {"python -c pass": [sys.executable, "-c", "pass"],
                "toothfem --help": [script, "--help"]}
    for cmd in commands.values():                   # warm-up, not counted
        wall(cmd)
    times = {k: [] for k in commands}
    for _ in range(args.rounds):
        for k, cmd in commands.items():
            times[k].append(wall(cmd))
    ratios = [h / p for h, p in zip(times["toothfem --help"], times["python -c pass"])]
    out = {k: {"min_s": min(v), "median_s": statistics.median(v), "max_s": max(v)}
           for k, v in times.items()}
    out["ratio_median"] = statistics.median(ratios)
    out["rounds"] = args.rounds
    for k in commands:
        f = out[k]
        print(f"{k:<16} min {f['min_s']:.3f} s  median {f['median_s']:.3f} s  "
              f"max {f['max_s']:.3f} s")
    print(f"toothfem --help / python -c pass: median ratio {out['ratio_median']:.1f} "
          f"over {args.rounds} rounds")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
