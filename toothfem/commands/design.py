"""`toothfem design CASE --out DIR`: the profile modification that meets the case's
[design] targets, searched on the contact model (docs/tolerance.md)."""
from __future__ import annotations

import json
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "design"
HELP = ("search the disc's equidistant, move-distance and rotation modifications for the "
        "[design] targets (backlash, contacts, Hertz pressure, optionally at a tolerance "
        "percentile)")


def add_parser(sub):
    """Add ``toothfem design`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML) with a [design] section")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--positions", type=int, default=18,
                   help="meshing positions over one period per candidate (default 18)")
    p.add_argument("--json", action="store_true",
                   help="print the key figures as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """The modification search of a case into ``--out``, the best design on screen (JSON).

    Parameters
    ----------
    args : argparse.Namespace
        ``case`` (a TOML path whose text best_case.toml copies), ``out`` and
        ``positions`` per candidate.

    Returns
    -------
    int
        0 once best_case.toml and the search's files are written.

    Raises
    ------
    CaseError
        For an invalid case, one without [design] or [cycloid], or targets no candidate
        meets.
    """
    from ..case import load_case
    from ..design import design_analysis
    from ..errors import decode_text
    from ..output import atomic_dir
    from ..report import html as report_html
    from ..report import summary as report_summary
    case = load_case(args.case)
    source = decode_text(Path(args.case).read_bytes(), args.case)
    with atomic_dir(args.out) as tmp:     # open from the start: a bad --out refused at once
        result = design_analysis(case, positions=args.positions)
        summary = result.write(tmp, source)
        report_html.write_report(tmp, case, command="design", case_file=args.case)
    if args.json:
        print(json.dumps({"case": summary["case"], "best": summary["best"],
                          "check_with_own_tables": summary["check_with_own_tables"],
                          "percentile_interval": summary["percentile_interval"],
                          "datasheet": summary["datasheet"],
                          "warnings": summary["warnings"]}, indent=2))
        return 0
    print(report_summary.text(result.table(),
                              f"{case.name}: the best modification"))
    iv = summary.get("percentile_interval")
    if iv is not None and not iv["has_interval"]:
        print(f"note: the search judged each candidate at {iv['text']}")
    for w in summary["warnings"]:
        print(f"warning: {w['message']}")
    print(f"wrote {Path(args.out).resolve()} (best_case.toml, candidates.csv, report.html, "
          "pictures)")
    return 0
