"""`toothfem stiffness CASE --out DIR [--torque-max-Nm T] [--steps N] [--positions N]`: the
datasheet (hysteresis curve, torsional rigidity, lost motion, backlash, compliances in
series), the loaded transmission error over the full period and the split between the
discs (docs/stiffness.md)."""
from __future__ import annotations

import json
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "stiffness"
HELP = ("torsional stiffness, hysteresis, lost motion, backlash, loaded transmission error and "
        "disc split from the FE contact and the supports in series")


def add_parser(sub):
    """Add ``toothfem stiffness`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--torque-max-Nm", type=float, default=None, dest="torque_max",
                   help="largest output torque of the loop [N m] (default: the case's "
                        "rated_torque_Nm, else its operating torque)")
    p.add_argument("--steps", type=int, default=8,
                   help="torque steps from 0 to the largest torque (>= 4; the loop "
                        "0 -> +T -> -T -> +T has 5 steps + 1 points; default 8: 41)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pitch of the loop (default 36)")
    p.add_argument("--te-torque-Nm", type=float, default=None, dest="te_torque",
                   help="output torque of the loaded TE and the split (default: rated)")
    p.add_argument("--te-samples", type=int, default=6,
                   help="cycle solvers over the drive's full period for the TE (default 6)")
    p.add_argument("--te-positions", type=int, default=12,
                   help="positions per pitch of each TE solver (default 12)")
    p.add_argument("--no-friction", action="store_false", dest="friction",
                   help="leave friction out of the quasi-static path: the elastic curve "
                        "(the loop's only width is then the backlash)")
    p.add_argument("--json", action="store_true",
                   help="print the key figures as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """The stiffness data sheet of a case into ``--out``, its key figures on screen (JSON).

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out``, ``torque_max`` [N m], ``steps``, ``positions``, ``te_torque``
        [N m], ``te_samples``, ``te_positions`` and ``friction``.

    Returns
    -------
    int
        0 once the data sheet is written.
    """
    from ..case import load_case
    from ..output import atomic_dir
    from ..datasheet import stiffness_analysis
    from ..report import html as report_html, summary as report_summary
    case = load_case(args.case)
    with atomic_dir(args.out) as tmp:     # open from the start: a bad --out refused at once
        result = stiffness_analysis(case, torque_max_Nm=args.torque_max, steps=args.steps,
                                    positions=args.positions, te_torque_Nm=args.te_torque,
                                    te_samples=args.te_samples,
                                    te_positions=args.te_positions, friction=args.friction)
        summary = result.write(tmp)
        report_html.write_report(tmp, case, command="stiffness", case_file=args.case, tables=[
            report_html.Table.of_summary("datasheet", result.table())])
    keep = ("rated_torque_Nm", "rated_torque_assumed", "torsional_rigidity_Nm_per_arcmin",
            "lost_motion_arcmin", "backlash_arcmin", "hysteresis_loss_arcmin",
            "compliance_shares", "te_mean_arcsec", "te_peak_to_peak_arcsec", "te_rms_arcsec",
            "te_definition", "member_share_max",
            "member_load_factor_fe")
    if args.json:
        print(json.dumps({k: summary[k] for k in keep if k in summary}, indent=2))
        return 0
    print(report_summary.text([_with_unit(what, value) for what, value in result.table()],
                              f"{case.name}: datasheet"))
    print(f"wrote {Path(args.out).resolve()} (summary.json, report.html, pictures)")
    return 0


def _with_unit(what: str, value: str) -> tuple:
    """A datasheet row (quantity with its unit in brackets, value) as the terminal table's
    (quantity, unit, {"value": value}): the unit in its column, a share's % with it."""
    if what.endswith("]") and " [" in what:
        what, unit = what[:-1].rsplit(" [", 1)
        return what, unit, {"value": value}
    if value.endswith(" %"):
        return what, "%", {"value": value[:-2]}
    return what, "", {"value": value}
