"""`toothfem new DRIVE --KEY-NUMBERS ... --out FILE.toml [--force]`: a case file from a drive
type and its key numbers, every other value derived or marked ASSUMPTION with its reason."""
from __future__ import annotations

import argparse
import json
import textwrap
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..case_new import NewCaseTemplate


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "new"
HELP = ("write a case file from a drive type and its key numbers (every other value derived or "
        "marked ASSUMPTION); it passes `check` and runs `run` as written")


def add_parser(sub):
    """Add ``toothfem new`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    from ..case_new import FLOAT_KEY_NUMBERS, OPTIONS, templates
    from ..layouts import layout_named
    drives = templates()
    listed = "; ".join(f"{d}: {layout_named(d).label} ({_needs(t)})" for d, t in drives.items())
    p = sub.add_parser(
        NAME, help=HELP,
        description=textwrap.fill(f"Drives and their required key numbers: {listed}.", 79,
                                  break_on_hyphens=False),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("drive", choices=tuple(drives), help="the case's drive type")
    num = p.add_argument_group("key numbers (units in the names)")
    for kw, option in OPTIONS.items():
        floats = kw in FLOAT_KEY_NUMBERS      # a length, torque or speed: its unit names it
        num.add_argument(option, metavar=kw.rsplit("_", 1)[1].upper() if floats else "N",
                         type=float if floats else int, help=_meaning(kw, drives))
    p.add_argument("--name", help="the case's name (default: from the key numbers)")
    p.add_argument("--out", required=True, metavar="FILE.toml",
                   help="the case file to write (TOML); an existing file is not replaced")
    p.add_argument("--force", action="store_true", help="replace an existing --out file")
    p.add_argument("--json", action="store_true", help="print JSON instead of lines")
    p.set_defaults(func=run)


def _needs(template: NewCaseTemplate) -> str:
    """A layout's required key numbers, and its size options where it has them."""
    from ..case_new import OPTIONS
    size = ["one of " + " / ".join(OPTIONS[k] for k in template.sizes)] if template.sizes \
        else []
    return ", ".join([OPTIONS[k] for k in template.required] + size)


def _meaning(kw: str, drives: dict) -> str:
    """What a key number is, once where every layout means the same by it, else per the
    layouts that take it ("cycloid, rv: ...; sine: ...")."""
    by_text: dict[str, list[str]] = {}
    for d, template in drives.items():
        if kw in template.key_help:
            by_text.setdefault(template.key_help[kw], []).append(d)
    if [list(drives)] == list(by_text.values()):
        return next(iter(by_text))
    return "; ".join(f"{', '.join(ds)}: {text}" for text, ds in by_text.items())


def run(args) -> int:
    """Write the new case file and say what it holds.

    Parameters
    ----------
    args : argparse.Namespace
        ``drive``, the key numbers (None where not given), ``name``, ``out``, ``force``
        and ``json``.

    Returns
    -------
    int
        0 once the file is in place.

    Raises
    ------
    CaseError
        A missing, inapplicable or bad key number (one line naming its option, its value
        and the valid range), or an ``--out`` that exists (without ``--force``) or is a
        folder; nothing is written then.
    """
    from ..case_new import OPTIONS, new_case
    from ..layouts import layout_named
    from ..output_file import check_new_file, write_new_file
    check_new_file(args.out, force=args.force)      # refused before any work
    new = new_case(args.drive, name=args.name, **{k: getattr(args, k) for k in OPTIONS})
    path = write_new_file(new.text, args.out, force=args.force).resolve()
    if args.json:
        print(json.dumps({"file": str(path), "drive": new.drive, "ratio": new.ratio,
                          "peak_ph_MPa": new.peak_ph_MPa, "efficiency": new.efficiency,
                          "warnings": list(new.warnings), "key_numbers": new.key_numbers,
                          "assumptions": [{"key": k, "value": v, "reason": r}
                                          for k, v, r in new.assumptions]}, indent=2))
        return 0
    print(f"wrote {path}: {layout_named(new.drive).label}, ratio {new.ratio:.6g} (signed), "
          f"{len(new.key_numbers)} key numbers, {len(new.assumptions)} values marked "
          "ASSUMPTION with their reasons")
    print(f"  at {new.case.operating.output_torque_Nm:g} N m (analytic split): peak Hertz "
          f"pressure {new.peak_ph_MPa:.4g} MPa, efficiency {100 * new.efficiency:.4g} %")
    for w in new.warnings:
        print(f"warning: {w}")
    print(f"next: toothfem check {args.out}; toothfem run {args.out} --out DIR")
    return 0
