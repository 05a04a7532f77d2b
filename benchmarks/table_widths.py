"""How wide each command's terminal output is (issue 41: tables that fit 100 columns, the
full names in a legend): every command that prints a table, on every shipped case, in
this process; for each, the widest line of what it prints (its title, table and legend;
the ``warning:``, ``wrote`` and ``progress:`` lines are prose, not the table, and are
left out) and whether it fits ``WIDTH``.

Run:  .venv/bin/python benchmarks/table_widths.py [--cases cases/x.toml ...] [--json F]
      exit 1 where a table is wider than WIDTH.
"""
from __future__ import annotations

import argparse
import contextlib
import glob
import io
import json
import os
import sys
import tempfile

#: The terminal width every table fits (issue 41).
WIDTH = 100
#: Lines that are not the table: prose the commands print around it.
PROSE = ("warning:", "wrote ", "progress:", "note:")


def _commands(case: str, out: str) -> list:
    """(name, argv) of every command that prints a table, on one case."""
    with open(case, encoding="utf-8") as f:
        text = f.read()
    cmds = [("check", ["check", case]),
            ("contact", ["contact", case, "--field", "none", "--out", f"{out}/contact"]),
            ("stiffness", ["stiffness", case, "--out", f"{out}/stiffness"]),
            ("efficiency", ["efficiency", case]),
            ("efficiency --thermal", ["efficiency", case, "--thermal"]),
            ("tolerance --samples 8", ["tolerance", case, "--samples", "8",
                                       "--share-samples", "0", "--out", f"{out}/tol"]),
            ("run --as-built 8", ["run", case, "--field", "none", "--as-built", "8",
                                  "--out", f"{out}/run"])]
    if "\n[design]" in text:
        cmds.append(("design", ["design", case, "--out", f"{out}/design"]))
    return cmds


def _run(argv: list) -> tuple:
    from toothfem.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = int(exc.code or 0)
    return code, out.getvalue()


def widest(text: str) -> int:
    """The widest line of a command's output that is not prose (:data:`PROSE`)."""
    return max((len(line) for line in text.splitlines()
                if not line.startswith(PROSE)), default=0)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", nargs="*", default=sorted(glob.glob("cases/*.toml")))
    parser.add_argument("--json", default=None, help="write the widths here")
    args = parser.parse_args(argv)
    found, over = {}, 0
    for case in args.cases:
        with tempfile.TemporaryDirectory(prefix="toothfem-widths-") as out:
            for name, cmd in _commands(case, out):
                code, text = _run(cmd)
                w = widest(text)
                key = f"{os.path.basename(case)} | {name}"
                found[key] = {"width": w, "exit": code}
                over += w > WIDTH
                print(f"{key:55s} {w:4d}{'' if w <= WIDTH else '  > ' + str(WIDTH)}"
                      f"{'' if code == 0 else f'  (exit {code})'}", flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(found, f, indent=2)
    print(f"{over} of {len(found)} outputs wider than {WIDTH} columns")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
