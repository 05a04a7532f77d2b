"""Every number the shipped cases print, captured and compared.

``python benchmarks/output_snapshot.py capture DIR`` runs each command of the CLI on each
shipped case (``--json`` where the command has it) and keeps, per run, what it printed and
the JSON and CSV files of its output folder. ``python benchmarks/output_snapshot.py compare
OLD NEW [--rtol 1e-9]`` lists every number that differs between two captures by more than
``rtol`` relative (and every file or key that one of them lacks), and exits 1 if any does.
A restructuring that must leave the results alone is checked by a capture before and
after it.

Timestamps, folder names, durations and the version line are not results: the keys in
``IGNORED_KEYS`` and any text are compared as text only when ``--text`` is given.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASES = ("cycloid_pinhousing", "cycloid_khv", "rv40e", "rv_paper_example", "sine_prototype")
#: Keys whose values are run metadata, not results.
IGNORED_KEYS = {"elapsed_s", "seconds", "time_s", "date", "created", "command", "version",
                "out", "output", "folder", "path", "report", "command_line", "duration_s",
                "wall_s", "toothfem_version", "written", "files", "cache_dir", "setup_s"}


def runs() -> list[tuple[str, list[str]]]:
    """(name, argv) of every run; ``{out}`` stands for the run's output folder."""
    out: list[tuple[str, list[str]]] = []
    for c in CASES:
        case = f"cases/{c}.toml"
        demo = f"data/demo/{c}_synthetic.csv"
        out += [
            (f"{c}.check", ["check", case, "--json"]),
            (f"{c}.geometry", ["geometry", case, "--out", "{out}"]),
            (f"{c}.contact", ["contact", case, "--out", "{out}", "--field", "none",
                              "--json"]),
            (f"{c}.stiffness", ["stiffness", case, "--out", "{out}", "--json"]),
            (f"{c}.tolerance", ["tolerance", case, "--out", "{out}", "--samples", "16",
                                "--share-samples", "0", "--positions", "12", "--json"]),
            (f"{c}.efficiency", ["efficiency", case, "--json"]),
            (f"{c}.efficiency_fem", ["efficiency", case, "--loads", "fem", "--json"]),
            (f"{c}.efficiency_thermal", ["efficiency", case, "--thermal", "--json"]),
            (f"{c}.run", ["run", case, "--out", "{out}", "--field", "none", "--json"]),
            (f"{c}.loop", ["loop", case, demo, "--out", "{out}", "--json"]),
        ]
    out += [("cycloid_pinhousing.design", ["design", "cases/cycloid_pinhousing.toml", "--out",
                                          "{out}", "--positions", "12", "--json"]),
            ("cycloid_pinhousing.contact_detailed",
             ["contact", "cases/cycloid_pinhousing.toml", "--out", "{out}", "--positions",
              "4", "--mode", "detailed", "--json"]),
            ("rv40e.te_loop", ["te-loop", "cases/rv40e.toml", "--te",
                               "data/demo/te/rv40e_crank_play/", "--hysteresis",
                               "data/demo/te/rv40e_crank_play/hysteresis.csv", "--effects",
                               "crank_bearing_play,friction", "--out", "{out}", "--json"]),
            ("sine_prototype.sweep", ["sweep", "cases/sine_prototype.toml", "--vary",
                                      "operating.output_torque_Nm=14,28", "--positions", "6",
                                      "--workers", "1", "--out", "{out}", "--json"])]
    return out


def capture(folder: Path, only: str | None) -> int:
    """Run every command into ``folder/<run>/``: stdout.txt, rc, and the output's files."""
    folder.mkdir(parents=True, exist_ok=True)
    exe = Path(sys.executable).with_name("toothfem")
    failed = 0
    for name, argv in runs():
        if only and only not in name:
            continue
        dest = folder / name
        dest.mkdir(exist_ok=True)
        out = dest / "out"
        argv = [a.replace("{out}", str(out)) for a in argv]
        t0 = time.perf_counter()
        proc = subprocess.run([str(exe), *argv], cwd=ROOT, capture_output=True, text=True,
                              env={**os.environ, "TOOTHFEM_PROGRESS": "0"})
        (dest / "stdout.txt").write_text(proc.stdout)
        (dest / "stderr.txt").write_text(proc.stderr)
        (dest / "rc").write_text(str(proc.returncode))
        failed += proc.returncode != 0
        print(f"{name}: exit {proc.returncode} in {time.perf_counter() - t0:.1f} s",
              flush=True)
    return 1 if failed else 0


def _numbers(obj, prefix=""):
    """(path, value) of every leaf of a JSON value."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k in IGNORED_KEYS:
                continue
            yield from _numbers(v, f"{prefix}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _numbers(v, f"{prefix}[{i}]")
    else:
        yield prefix, obj


def _leaves(path: Path) -> dict:
    """Every leaf of a captured file: JSON by key path, CSV by row and column, stdout as
    JSON when it parses, else its numbers by line."""
    text = path.read_text(errors="replace")
    if path.suffix == ".csv":
        rows = [r for r in csv.reader(line for line in text.splitlines()
                                       if not line.startswith("#"))]
        if not rows:
            return {}
        head = rows[0]
        return {f"[{i}].{head[j] if j < len(head) else j}": _num(c)
                for i, r in enumerate(rows[1:], 1) for j, c in enumerate(r)
                if j >= len(head) or head[j] not in IGNORED_KEYS}
    try:
        return dict(_numbers(json.loads(text)))
    except json.JSONDecodeError:
        if path.suffix == ".json":
            return {"<unparsable>": text}
    # text: its numbers by line (the table a command prints)
    import re
    out = {}
    for i, line in enumerate(text.splitlines()):
        if "wrote" in line or " in " in line and " s" in line:
            continue
        for j, tok in enumerate(re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?", line)):
            out[f"line{i}#{j}"] = float(tok)
    return out


def _num(cell: str):
    try:
        return float(cell)
    except ValueError:
        return cell


def _differ(a, b, rtol: float) -> bool:
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) \
            or not isinstance(b, (int, float)):
        return a != b and (isinstance(a, (int, float)) or isinstance(b, (int, float)))
    if math.isnan(a) and math.isnan(b):
        return False
    return abs(a - b) > rtol * max(abs(a), abs(b), 1e-300)


def compare(old: Path, new: Path, rtol: float, text: bool) -> int:
    """Print every difference; 1 if any."""
    bad = 0
    for run_dir in sorted(p for p in old.iterdir() if p.is_dir()):
        other = new / run_dir.name
        if not other.exists():
            print(f"{run_dir.name}: missing in {new}")
            bad += 1
            continue
        files = sorted(p.relative_to(run_dir) for p in run_dir.rglob("*")
                       if p.is_file() and (p.suffix in (".json", ".csv") or p.name in
                                           ("stdout.txt", "rc")))
        for rel in files:
            if "finished_points" in str(rel) or rel.name == ".toothfem-result":
                continue
            b_path = other / rel
            if not b_path.exists():
                print(f"{run_dir.name}/{rel}: missing in new")
                bad += 1
                continue
            a, b = _leaves(run_dir / rel), _leaves(b_path)
            for key in sorted(set(a) | set(b)):
                if key not in a or key not in b:
                    print(f"{run_dir.name}/{rel}{key}: only in {'old' if key in a else 'new'}")
                    bad += 1
                elif _differ(a[key], b[key], rtol) or text and a[key] != b[key]:
                    print(f"{run_dir.name}/{rel}{key}: {a[key]!r} -> {b[key]!r}")
                    bad += 1
    print(f"{bad} difference(s) beyond rtol {rtol:g}")
    return 1 if bad else 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="verb", required=True)
    c = sub.add_parser("capture")
    c.add_argument("folder", type=Path)
    c.add_argument("--only", help="runs whose name holds this text")
    d = sub.add_parser("compare")
    d.add_argument("old", type=Path)
    d.add_argument("new", type=Path)
    d.add_argument("--rtol", type=float, default=1e-9)
    d.add_argument("--text", action="store_true", help="also compare text leaves")
    args = p.parse_args(argv)
    if args.verb == "capture":
        return capture(args.folder, args.only)
    return compare(args.old, args.new, args.rtol, args.text)


if __name__ == "__main__":
    sys.exit(main())
