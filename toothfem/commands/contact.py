"""`toothfem contact CASE --positions N [--torque-Nm T] [--mode cycle|detailed] --out DIR
[--json]`: a summary table on screen (the case's published figures beside), the files in DIR."""
from __future__ import annotations

import json
from pathlib import Path


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "contact"
HELP = ("FE load sharing, Hertz or FE pressure and transmission error over one meshing period "
        "(cycloid discs, sine pair)")


def add_parser(sub):
    """Add ``toothfem contact`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pin pitch (default 36)")
    p.add_argument("--torque-Nm", type=float, default=None, dest="torque",
                   help="reducer output torque [N m] (default: the case's); one disc carries "
                        "disc_load_factor * T / disc_count")
    p.add_argument("--mode", choices=("cycle", "detailed"), default="cycle",
                   help="cycle: influence coefficients + Hertz (fast, default); detailed: "
                        "two-body FE contact at each position (slow)")
    p.add_argument("--pins", choices=("conventional", "integral", "rigid"), default=None,
                   help="pin structure: conventional (pins in housing grooves), integral "
                        "(pins one piece with the housing) or rigid (fixed rigid pins, cycle "
                        "mode only: the CalculiX peer's model); default: the case's")
    p.add_argument("--field", choices=("detailed", "structural", "none"), default="detailed",
                   help="stress field at the worst position: detailed (two-body FE with the "
                        "contact zones resolved, ~1-2 min; default), structural (cycloid: the "
                        "cycle mode's loads smeared over b_ref, no contact-zone stress; the "
                        "sine pair always uses detailed) or none")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--json", action="store_true",
                   help="print the summary as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """FE load sharing of a case over one meshing period: the files in ``--out``, a summary on
    screen.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``positions``, ``torque`` [N m] or None, ``mode``, ``pins``, ``field``,
        ``out`` and ``json``.

    Returns
    -------
    int
        0 when the load sharing and its files are written.

    Raises
    ------
    CaseError
        If ``--positions`` or ``--torque-Nm`` is outside its range, or the case is invalid.
    """
    from ..case import load_case
    from ..case_checks import TORQUE_NM
    from ..errors import CaseError, check_range
    from ..output import atomic_dir
    from ..pipeline import contact_analysis
    from ..bars import bar
    from ..report import html as report_html, summary as report_summary


    check_range("--positions", args.positions, 1, 3600, error=CaseError)
    if args.torque is not None:         # the case's plausibility bounds (issue 14)
        check_range("--torque-Nm", args.torque, *TORQUE_NM, error=CaseError)
    case = load_case(args.case)
    progress = lambda it: bar(it, desc=f"{args.mode} mode", unit="position")  # noqa: E731
    with atomic_dir(args.out) as tmp:     # open from the start: an interrupt leaves none
        result = contact_analysis(case, positions=args.positions, torque_Nm=args.torque,
                                  mode=args.mode, pins=args.pins, field=args.field,
                                  progress=progress)
        summary = result.write(tmp)
        report_html.write_report(tmp, case, command="contact", case_file=args.case, tables=[
            report_html.Table.of_summary(f"{result.mode} mode, {summary['positions']} "
                                         "positions over one period",
                                         result.table(case.published))])
    if args.json:
        print(json.dumps({k: v for k, v in summary.items() if k != "files"}, indent=2))
        return 0
    print(report_summary.text(result.table(case.published), title=f"{case.name}: {result.mode} mode, "
                                          f"{summary['positions']} positions over one period"))
    for w in summary.get("warnings", ()):
        print(f"warning: {w['message']}")
    print(f"wrote {', '.join(summary['files'])} to {Path(args.out).resolve()}")
    return 0
