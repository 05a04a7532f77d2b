"""One quantity, one number (issue 41): run every command on every shipped case, collect
every number each output prints (``--json``) or writes (the JSON files of its output
folder) under its quantity label, list each label with every value it has across the
outputs, and fail (exit 1) where one label carries two different values for one case.

A number's label is its key path in the output (toothfem/quantities.py names each
quantity once, its unit in the key's suffix), less the sections that only say which
command's part of a larger output it is (``WRAPPERS``: run's ``contact`` and
``stiffness``), with the variant its output declares beside it in brackets
(``VARIANT_FIELDS``: the efficiency's loads and method, the contact's mode and pin
structure, the model whose efficiency fixed the output torque of a case that declares
its input, a stated oil temperature; run's efficiency sections ``analytic``/``fem``
declare the same by name, ``SECTION_VARIANTS``). Any other section stays in the label
(``thermal.efficiency``: at the heat balance's oil; ``nominal.max_force_N``: the tolerance
ensemble's unbuilt reducer). Lists (values per position, per pin, per scenario) are not
one number and are left out; so are the run's own settings (``SETTINGS``: positions,
samples, seed) and the inputs echoed back (``ECHOED``).

Two values under one label agree within ``RTOL`` (and ``ATOL`` for clearances; below):
every command reads the same case and the same FE tables (the disk cache), so a quantity
computed twice the same way agrees to the printing's 10 significant figures (``check``
rounds to 10); 1e-6 leaves room for that rounding and for a sum taken in another order,
and is far below any difference between two variants of a quantity (the smallest the
issue lists: 88.62 against 88.51 %, 1.2e-3).

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
#: Absolute floors for clearances and the rotations that close them, which are exact
#: zeros in ``check`` (the profiles' closed form) and a few nanometres in the system model
#: (the rigid closing motion on the FE tables' discretised gaps: 1.3e-5 arcmin on the
#: K-H-V case, 0.25 nm at its 36 mm pin circle). 1e-4 arcmin is 1.0 nm there (up to 2 nm
#: on the shipped cases' 36-64 mm circles); a real difference of the backlash's variants
#: is 1e3 times that (1.763 against 1.706 arcmin, issue 41). Keyed by the label's unit
#: suffix; every other quantity has RTOL alone.
ATOL = {"_arcmin": 1e-4, "_arcsec": 6e-3, "_um": 2e-3}

#: Sections that only say which command's part of a larger output a number is (``run``
#: holds ``contact`` and ``stiffness``): left out of the label, so that the number meets
#: the same quantity of the command itself.
WRAPPERS = frozenset({"summary", "contact", "stiffness", "geometry", "check"})

#: Fields by which an output declares the variant of its numbers (the efficiency's loads
#: and method, the contact's mode and pin structure; the oil temperature where stated):
#: part of the label, in brackets.
VARIANT_FIELDS = ("loads", "method", "mode", "pin_structure", "operating_point_from")

#: Sections of run's efficiency.json named by their variant: the same declaration.
SECTION_VARIANTS = {"analytic": {"loads": "analytic", "method": "power_flow"},
                    "fem": {"loads": "fem", "method": "power_flow"},
                    "rv_split_power": {"method": "rv_split_power"}}

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


def numbers(obj, path: tuple = (), variant: tuple = ()) -> dict[str, tuple[str, float]]:
    """Every number of a JSON value under its label (module docstring).

    Parameters
    ----------
    obj : dict, list or scalar
    path : tuple of str
        The sections above ``obj``.
    variant : tuple of str
        The variant its sections and fields declared (``loads=fem``...).

    Returns
    -------
    dict
        label -> (its path in the output, value).
    """
    found: dict[str, tuple[str, float]] = {}
    if isinstance(obj, dict):
        here = dict(v.split("=", 1) for v in variant)
        if path and path[-1] in SECTION_VARIANTS:
            here.update(SECTION_VARIANTS[path[-1]])
        for f in VARIANT_FIELDS:
            if isinstance(obj.get(f), str):
                here[f] = obj[f]
        if "oil_temp_C" in obj and not isinstance(obj["oil_temp_C"], dict):
            oil = obj["oil_temp_C"]           # null: the lubricant's reference
            here["oil_temp_C"] = "reference" if oil is None else f"{oil:.4g}"
        var = tuple(f"{k}={v}" for k, v in sorted(here.items()))
        for k, v in obj.items():
            for label, got in numbers(v, path + (str(k),), var).items():
                found.setdefault(label, got)
                if found[label][1] != got[1]:       # twice in one output: both kept
                    found[f"{label} @{got[0]}"] = got
        return found
    if isinstance(obj, (list, bool)) or not isinstance(obj, (int, float)):
        return found
    if not path or path[-1] in SETTINGS or path[-1] in ECHOED:
        return found
    names = [p for p in path if p not in WRAPPERS and p not in SECTION_VARIANTS]
    label = ".".join(names) + (f"  [{', '.join(variant)}]" if variant else "")
    found[label] = (".".join(path), float(obj))
    return found


def _outputs(name: str, stdout: str, folder: str | None) -> dict:
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


def _split(label: str) -> tuple[str, dict]:
    """A label's name and its declared variant (``name  [k=v, ...]``)."""
    name, _, rest = label.partition("  [")
    rest, _, again = rest.partition("]")
    var = dict(x.split("=", 1) for x in rest.split(", ") if "=" in x)
    return name + again, var


def disagreements(values: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    """The quantities with two values that differ beyond RTOL/ATOL: under one label, or
    under one name where the variants declared do not tell them apart (an output that
    declares none, like ``check``'s, meets every variant of its name: ``check``'s disc
    torque is ``contact``'s, whatever mode the contact ran in).

    Parameters
    ----------
    values : dict
        label -> {output: value}.

    Returns
    -------
    dict
        name (with the variant that conflicts) -> {output: value}, the values compared.
    """
    by_name: dict[str, list] = {}
    for label, by in values.items():
        name, var = _split(label)
        by_name.setdefault(name, []).append((label, var, by))
    bad = {}
    for name, group in by_name.items():
        for label, var, by in group:
            merged = dict(by)
            for other, ovar, oby in group:
                if other != label and all(var.get(k, v) == v for k, v in ovar.items()) \
                        and all(ovar.get(k, v) == v for k, v in var.items()):
                    merged.update(oby)
            vs = [v for v in merged.values() if math.isfinite(v)]
            if len(vs) < 2:
                continue
            lo, hi = min(vs), max(vs)
            floor = max([a for u, a in ATOL.items() if name.endswith(u)], default=0.0)
            if hi - lo > max(floor, RTOL * max(abs(lo), abs(hi))):
                bad[label] = merged
    return bad


def main(argv=None) -> int:
    """Run the commands, print the table per case, exit 1 on a disagreement."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="*", default=sorted(glob.glob("cases/*.toml")))
    ap.add_argument("--samples", type=int, default=8,
                    help="tolerance ensemble size (small: only its nominal is compared)")
    ap.add_argument("--commands", nargs="*", help="only these (names as printed, e.g. "
                    "check contact); default every command")
    ap.add_argument("--json", help="write every label's values per case here")
    args = ap.parse_args(argv)
    report: dict = {}
    failed = False
    for case in args.cases:
        values: dict[str, dict[str, float]] = {}
        with tempfile.TemporaryDirectory(prefix="toothfem_q_") as tmp:
            for name, cmd, folder in _commands(case, tmp, args.samples):
                if args.commands and name not in args.commands:
                    continue
                t0 = time.perf_counter()
                code, out, err = _run(cmd)
                dt = time.perf_counter() - t0
                last = err.strip().splitlines()[-1] if err.strip() else ""
                print(f"# {case}: {name}: exit {code} in {dt:.1f} s"
                      + (f" ({last})" if code else ""), file=sys.stderr)
                if code:
                    continue
                for output, nums in _outputs(name, out, folder).items():
                    for label, (where, v) in nums.items():
                        values.setdefault(label, {})[f"{output}: {where}"] = v
        bad = disagreements(values)
        failed |= bool(bad)
        report[case] = {"values": values, "disagreements": sorted(bad)}
        print(f"\n== {case}: {len(values)} quantities, {len(bad)} with two values")
        for label in sorted(values):
            by = bad.get(label, values[label])
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
