"""`toothfem size CASE --out DIR`: a 2K-V reducer sized to its maker's datasheet inside the
catalogue envelope (docs/sizing.md)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "size"
HELP = ("size an RV reducer to its [published] datasheet inside its [envelope]: crank "
        "circle, crank bearings, disc width, crankshafts, pillars and the modification, "
        "each with its rule, verified on the system model")


def add_parser(sub):
    """Add ``toothfem size`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML) with [envelope] and the [published] "
                                "rated torque, speed, life and rigidity")
    p.add_argument("--out", required=True, help="output folder (written atomically): "
                   "sized_case.toml, sizing.json, report.md")
    p.add_argument("--json", action="store_true",
                   help="print the summary as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """Size the case into ``--out``; the datasheet beside the maker's on screen.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out``, ``json``.

    Returns
    -------
    int
        0 when every target is met inside the envelope; 1 when one binds (the files are
        written, the binding figures printed).

    Raises
    ------
    CaseError
        For a case that is not a 2K-V reducer with [envelope] and the published figures.
    """
    from ..case import load_case
    from ..errors import decode_text
    from ..output import atomic_dir
    from ..report import summary as report_summary
    from ..sizing import size_reducer
    case = load_case(args.case)
    source = decode_text(Path(args.case).read_bytes(), args.case)
    with atomic_dir(args.out) as tmp:     # open from the start: a bad --out refused at once
        result = size_reducer(case, source,
                              progress=lambda line: print(line, file=sys.stderr, flush=True))
        summary = result.write(tmp)
    if args.json:
        print(json.dumps({k: summary[k] for k in ("case", "feasible", "binding", "figures",
                                                  "choices")}, indent=2))
    else:
        print(report_summary.text(result.table(), f"{case.name}: sized to the datasheet"))
        for b in summary["binding"]:
            print(f"binding: {b}")
        print(f"wrote {Path(args.out).resolve()} (sized_case.toml, sizing.json, report.md)")
    return 0 if result.feasible else 1
