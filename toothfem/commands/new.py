"""`toothfem new DRIVE --KEY-NUMBERS ... --out FILE.toml [--force]`: a case file from a drive
type and its key numbers, every other value derived or marked ASSUMPTION with its reason."""
from __future__ import annotations

import argparse
import json
import textwrap

from ..case_new import DRIVE_LABELS, KEY_NUMBERS, OPTIONS, SINE_SIZE, new_case
from ..output import check_new_file, write_new_file


def add_parser(sub):
    """Add ``toothfem new`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    def needs(d):
        size = ["one of " + " / ".join(OPTIONS[k] for k in SINE_SIZE)] if d == "sine" else []
        return ", ".join([OPTIONS[k] for k in KEY_NUMBERS[d][0]] + size)

    drives = "; ".join(f"{d}: {label} ({needs(d)})" for d, label in DRIVE_LABELS.items())
    p = sub.add_parser(
        "new", help="write a case file from a drive type and its key numbers (every other "
        "value derived or marked ASSUMPTION); it passes `check` and runs `run` as written",
        description=textwrap.fill(f"Drives and their required key numbers: {drives}.", 79,
                                  break_on_hyphens=False),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("drive", choices=tuple(DRIVE_LABELS), help="the case's drive type")
    num = p.add_argument_group("key numbers (units in the names)")
    for option, metavar, kind, text in (
            ("--pins", "N", int, "cycloid, rv: pins Zb in the housing"),
            ("--lobes", "N", int, "cycloid, rv: lobes Za of a disc (default pins - 1)"),
            ("--pin-circle-radius-mm", "MM", float, "cycloid, rv: pin circle radius Rz [mm]"),
            ("--eccentricity-mm", "MM", float, "cycloid, rv: the crank's eccentricity [mm]; "
             "sine: the centre distance a0 (one way to give its size)"),
            ("--sun-teeth", "N", int, "rv: the first stage's sun teeth"),
            ("--planet-teeth", "N", int, "rv: the first stage's planet teeth"),
            ("--teeth", "N", int, "sine: the planet's teeth z1"),
            ("--ring-teeth", "N", int, "sine: the ring's teeth (default z1 + 1)"),
            ("--module-mm", "MM", float, "sine: the module [mm]"),
            ("--ring-pitch-radius-mm", "MM", float, "sine: the ring's pitch radius [mm]"),
            ("--torque-Nm", "NM", float, "output torque [N m]: the operating point and the "
             "rated torque the size is for"),
            ("--input-speed-rpm", "RPM", float, "input speed [rpm]")):
        num.add_argument(option, metavar=metavar, type=kind, help=text)
    p.add_argument("--name", help="the case's name (default: from the key numbers)")
    p.add_argument("--out", required=True, metavar="FILE.toml",
                   help="the case file to write (TOML); an existing file is not replaced")
    p.add_argument("--force", action="store_true", help="replace an existing --out file")
    p.add_argument("--json", action="store_true", help="print JSON instead of lines")
    p.set_defaults(func=run)


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
    print(f"wrote {path}: {DRIVE_LABELS[new.drive]}, ratio {new.ratio:.6g} (signed), "
          f"{len(new.key_numbers)} key numbers, {len(new.assumptions)} values marked "
          "ASSUMPTION with their reasons")
    print(f"  at {new.case.operating.output_torque_Nm:g} N m (analytic split): peak Hertz "
          f"pressure {new.peak_ph_MPa:.4g} MPa, efficiency {100 * new.efficiency:.4g} %")
    for w in new.warnings:
        print(f"warning: {w}")
    print(f"next: toothfem check {args.out}; toothfem run {args.out} --out DIR")
    return 0
