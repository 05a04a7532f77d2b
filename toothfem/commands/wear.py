"""`toothfem wear CASE --hours H [--wear-coefficient K] [--steps N] [--positions N] [--json]
[--out DIR]`: the accuracy life: lost motion, backlash, TE and efficiency against the hours
of the duty cycle as the contacts wear, and the hours to the case's lost-motion limit
(docs/wear.md)."""
from __future__ import annotations

import json
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help``.
NAME = "wear"
HELP = ("accuracy life: lost motion, backlash, TE and efficiency against the hours as the pins, "
        "discs and bearings wear (Archard)")


def add_parser(sub):
    """Add ``toothfem wear`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    from ..wear import DEFAULT_POSITIONS, DEFAULT_STEPS
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--hours", type=float, required=True,
                   help="running time of the duty cycle [h] (the case's [[duty_cycle]], else "
                        "its operating point)")
    p.add_argument("--wear-coefficient", type=float, default=None, dest="wear_coefficient",
                   help="Archard's dimensionless K_b in boundary lubrication, 0 to 1e-3 (the "
                        "film ratio's regime scales it); default [wear] wear_coefficient, "
                        "else 1e-8 (docs/wear.md)")
    p.add_argument("--steps", type=int, default=DEFAULT_STEPS,
                   help=f"steps over the hours, denser at the start (default {DEFAULT_STEPS})")
    p.add_argument("--positions", type=int, default=DEFAULT_POSITIONS,
                   help=f"positions per pin pitch of the system model (default "
                        f"{DEFAULT_POSITIONS})")
    p.add_argument("--out", default=None,
                   help="output folder (written atomically): history.csv, lost_motion.png, "
                        "summary.json")
    p.add_argument("--json", action="store_true",
                   help="print the summary with its history rows as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """The accuracy life of a case on screen, and into ``--out`` if given.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``hours``, ``wear_coefficient``, ``steps``, ``positions``, ``out``,
        ``json``.

    Returns
    -------
    int
        0 once done.
    """
    import contextlib

    from ..case import load_case
    from ..output import atomic_dir
    from ..report import summary as report_summary
    from ..wear import wear_analysis
    case = load_case(args.case)
    out = atomic_dir(args.out) if args.out else contextlib.nullcontext(None)
    with out as tmp:                   # a bad --out refused before the run
        result = wear_analysis(case, args.hours, wear_coefficient=args.wear_coefficient,
                               steps=args.steps, positions=args.positions)
        summary = result.write(tmp) if tmp is not None else result.summary()
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(report_summary.text([_with_unit(what, value) for what, value in result.table()],
                              f"{case.name}: accuracy life"))
    lim, t = result.lost_motion_limit_arcmin, result.hours_to_limit
    if lim is None:
        print("no lost-motion limit: set [wear] lost_motion_limit_arcmin for the hours to it")
    elif t is None:
        print(f"lost motion stays below {lim:g} arcmin over {result.hours:g} h")
    else:
        print(f"lost motion reaches {lim:g} arcmin at {t:.0f} h")
    if args.out:
        print(f"wrote {Path(args.out).resolve()} (history.csv, lost_motion.png, summary.json)")
    return 0


def _with_unit(what: str, value: str) -> tuple:
    """A row (quantity with its unit in brackets, value) as the terminal table's."""
    if what.endswith("]") and " [" in what:
        what, unit = what[:-1].rsplit(" [", 1)
        return what, unit, {"value": value}
    return what, "", {"value": value}
