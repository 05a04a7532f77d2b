"""One quantity, one number (issue 41): run every command on every shipped case, collect
every number each output prints (``--json``) or writes (the JSON files of its output
folder) under its quantity label, list each label with every value it has across the
outputs, and fail (exit 1) where one label carries two different values for one case.

A number's label is its key (toothfem/quantities.py names each quantity once, its unit in
the key's suffix). Where a key sits in a section of an output, the section is part of the
label only where the section says which variant the number is (``VARIANT_SECTIONS``:
``thermal`` is the efficiency at the heat balance's oil, ``nominal`` the tolerance
ensemble's unbuilt reducer at its positions over the pairing period); any other nesting
(``losses``, ``loss_shares``...) keeps the key with its section's name, as the table
shows it. Lists (values per position, per pin, per scenario) are not one number and are
left out; so are counts of the run's own settings (``SETTINGS``: positions, samples,
seed), which the command line chose.

Two values under one label agree within ``RTOL`` (below): every command reads the same
case and the same FE tables (the disk cache), so a quantity computed twice the same way
agrees to the printing's 10 significant figures (``check`` rounds to 10); 1e-6 leaves
room for that rounding and for a sum taken in another order, and is far below any
difference between two variants of a quantity (the smallest the issue lists: 88.62 against
88.51 %, 1.2e-3).

Run:  .venv/bin/python benchmarks/quantity_consistency.py [--cases cases/rv40e.toml ...]
      [--samples 8] [--json out.json]
"""
from __future__ import annotations

import argparse
import contextlib
import glob
import io
import json
import math
import os
import sys
import tempfile
import time

#: Relative tolerance of two values under one label (module docstring: rounding to 10
#: significant figures and summation order, far below any two variants' difference).
RTOL = 1e-6
#: Absolute floor for quantities that are zero in one output (a backlash of 0 against
#: 5.9e-6 arcmin from the system model's solve: its Newton tolerance, 1e-5 arcmin).
ATOL = 1e-5

#: Sections whose name says which variant a number is: kept in the label.
VARIANT_SECTIONS = ("thermal", "nominal", "warm_up", "at_bound", "percentiles")

#: The run's own settings (the command line chose them), not results.
SETTINGS = frozenset({"positions", "samples", "seed", "share_samples", "workers",
                      "iterations", "te_samples", "te_positions", "steps", "files",
                      "elapsed_s", "ensemble_size"})

#: Keys that are inputs echoed back, not results (the operating point differs between
#: commands by design: ``efficiency --thermal`` states its oil).
ECHOED = frozenset({"oil_temp_C"})


def _commands(case: str, out: str, samples: int) -> list[tuple[str, list[str], str | None]]:
    """(name, argv, output folder or None) of every command on one case."""
    def folder(name):
        return os.path.join(out, name)
    return [
        ("check", ["check", case, "--json"], None),
        ("contact", ["contact", case, "--field", "none", "--json",
                     "--out", folder("contact")], folder("contact")),
        ("contact --pins conventional", ["contact", case, "--field", "none", "--json",
                                         "--pins", "conventional",
                                         "--out", folder("contact_conv")], None),
        ("stiffness", ["stiffness", case, "--json", "--out", folder("stiffness")],
         folder("stiffness")),
        ("efficiency", ["efficiency", case, "--json"], None),
        ("efficiency --loads fem", ["efficiency", case, "--json", "--loads", "fem"], None),
        ("efficiency --thermal", ["efficiency", case, "--json", "--thermal"], None),
        ("tolerance", ["tolerance", case, "--json", "--samples", str(samples),
                       "--share-samples", "0", "--out", folder("tolerance")],
         folder("tolerance")),
        ("run", ["run", case, "--json", "--field", "none", "--out", folder("run")],
         folder("run")),
    ]


def _run(argv: list[str]) -> tuple[int, str, str]:
    """One command in this process: its exit code, stdout and stderr."""
    from toothfem.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:          # argparse: a refused option
            code = int(exc.code or 0)
    return code, out.getvalue(), err.getvalue()


def numbers(obj, path: tuple = ()) -> dict[str, float]:
    """Every number of a JSON value under its label (module docstring).

    Parameters
    ----------
    obj : dict, list or scalar
    path : tuple of str
        The sections above ``obj``.

    Returns
    -------
    dict
        label -> value.
    """
    found: dict[str, float] = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            found.update(numbers(v, path + (str(k),)))
        return found
    if isinstance(obj, list) or isinstance(obj, bool) or not isinstance(obj, (int, float)):
        return found
    if not path or path[-1] in SETTINGS or path[-1] in ECHOED:
        return found
    keep = [p for p in path[:-1] if p in VARIANT_SECTIONS]
    # a key inside a plain section (losses, loss_shares, compliance_shares, ...) keeps the
    # section's name: "losses.seals" is one quantity, "seals" alone is not
    plain = [p for p in path[:-1] if p not in VARIANT_SECTIONS and p != "summary"]
    label = ".".join(keep + plain[-1:] + [path[-1]])
    found[label] = float(obj)
    return found


def _outputs(name: str, stdout: str, folder: str | None) -> dict[str, dict[str, float]]:
    """Each output of one command (its printed JSON, its folder's JSON files) -> numbers."""
    outs: dict[str, dict[str, float]] = {}
    try:
        outs[f"{name} (printed)"] = numbers(json.loads(stdout))
    except json.JSONDecodeError:
        outs[f"{name} (printed)"] = {}
    if folder and os.path.isdir(folder):
        for f in sorted(glob.glob(os.path.join(folder, "**", "*.json"), recursive=True)):
            with open(f) as fh:
                try:
                    data = json.load(fh)
                except json.JSONDecodeError:
                    continue
            outs[f"{name}: {os.path.relpath(f, folder)}"] = numbers(data)
    return outs


def disagreements(values: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    """The labels with two values that differ beyond RTOL/ATOL.

    Parameters
    ----------
    values : dict
        label -> {output: value}.

    Returns
    -------
    dict
        The subset of ``values`` that disagrees.
    """
    bad = {}
    for label, by in values.items():
        vs = [v for v in by.values() if math.isfinite(v)]
        if len(vs) < 2:
            continue
        lo, hi = min(vs), max(vs)
        if hi - lo > max(ATOL, RTOL * max(abs(lo), abs(hi))):
            bad[label] = by
    return bad


def main(argv=None) -> int:
    """Run the commands, print the table per case, exit 1 on a disagreement."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="*", default=sorted(glob.glob("cases/*.toml")))
    ap.add_argument("--samples", type=int, default=8,
                    help="tolerance ensemble size (small: only its nominal is compared)")
    ap.add_argument("--json", help="write every label's values per case here")
    args = ap.parse_args(argv)
    report: dict = {}
    failed = False
    for case in args.cases:
        values: dict[str, dict[str, float]] = {}
        with tempfile.TemporaryDirectory(prefix="toothfem_q_") as tmp:
            for name, cmd, folder in _commands(case, tmp, args.samples):
                t0 = time.perf_counter()
                code, out, err = _run(cmd)
                dt = time.perf_counter() - t0
                last = err.strip().splitlines()[-1] if err.strip() else ""
                print(f"# {case}: {name}: exit {code} in {dt:.1f} s"
                      + (f" ({last})" if code else ""), file=sys.stderr)
                if code:
                    continue
                for output, nums in _outputs(name, out, folder).items():
                    for label, v in nums.items():
                        values.setdefault(label, {})[output] = v
        bad = disagreements(values)
        failed |= bool(bad)
        report[case] = {"values": values, "disagreements": sorted(bad)}
        print(f"\n== {case}: {len(values)} quantities, {len(bad)} with two values")
        for label in sorted(values):
            by = values[label]
            mark = "DIFFER" if label in bad else "  ok  "
            if label in bad or len(by) > 1:
                print(f"{mark} {label}")
                for output, v in by.items():
                    print(f"         {v:<14.7g} {output}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)
    print("\nFAIL: a label with two values (above: DIFFER)" if failed
          else "\nOK: one value per label on every case")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
