"""`toothfem geometry CASE --out DIR`: profiles as CSV, DXF and SVG (mm), the parts' drawing
as DXF and SVG (mm; STEP with the extra [cad]), a drawing (PNG) and a check summary."""
from __future__ import annotations

from pathlib import Path


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "geometry"
HELP = ("write the tooth profiles (CSV, DXF, SVG in mm), the parts' drawing (drawing.dxf, "
        "drawing.svg in mm: the disc or planet with its holes, the pins, the housing or ring; "
        "STEP of each part with the extra [cad]), a drawing (PNG) and a check summary (JSON)")


def add_parser(sub):
    """Add ``toothfem geometry`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--points-per-tooth", type=int, default=96,
                   help="profile points per lobe or tooth (default 96)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Write the profiles, the drawing and the check summary of a case into ``--out``.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out`` and ``points_per_tooth``.

    Returns
    -------
    int
        0 once the profiles are in the folder.

    Raises
    ------
    CaseError
        If ``--points-per-tooth`` is outside [8, 10000] or the case is invalid.
    """
    from ..case import load_case
    from ..errors import CaseError, check_range
    from ..output import atomic_dir
    from ..report.files import write_geometry
    from ..report import html as report_html

    check_range("--points-per-tooth", args.points_per_tooth, 8, 10000, error=CaseError)
    case = load_case(args.case)
    with atomic_dir(args.out) as tmp:
        summary = write_geometry(case, tmp, args.points_per_tooth)
        report_html.write_report(tmp, case, command="geometry", case_file=args.case, tables=[
            report_html.Table.of_mapping("derived quantities and checks (check.json)", {
                k: v for k, v in summary.items() if k not in ("cad", "files", "warnings")})])
    print(f"wrote {', '.join(summary['files'])} to {Path(args.out).resolve()}")
    for w in summary.get("warnings", ()):
        print(f"warning: {w}")
    return 0
