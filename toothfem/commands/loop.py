"""`toothfem loop CASE [MEASURED.csv] --out DIR`: compare the model with measured efficiency,
add the physical effects the data ask for, and report the error before and after
(DIR/report.md, DIR/report.json, DIR/residuals_before.png, DIR/residuals_after.png)."""
from __future__ import annotations

import json
import sys
from pathlib import Path


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "loop"
HELP = ("fit physical effects to measured efficiency and report the error before and after "
        "(report.md, report.json, PNGs)")


def add_parser(sub):
    """Add ``toothfem loop`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    from ..efficiency.loop import effects as fx
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("measured", nargs="?", default=None,
                   help="measured data CSV (units in the column names; provenance in "
                        "<name>.json beside it); default: the case's [[measured]] points")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--effects", default=None,
                   help="comma-separated catalog effects to consider (default: all: "
                        + ", ".join(fx.NAMES) + ")")
    p.add_argument("--folds", type=int, default=5, help="k of the k-fold held-out error")
    p.add_argument("--json", action="store_true",
                   help="print report.json's content (errors, effects, alias groups with "
                        "their proposed measurements, steps, trends) instead of the summary "
                        "lines")
    p.add_argument("--loads", choices=("analytic", "fem"), default="analytic",
                   help="load sharing of the model (fem: FE cycle mode, slow)")
    p.add_argument("--strict", action="store_true",
                   help="refuse the whole file on the first bad row")
    p.set_defaults(func=run)


def run(args) -> int:
    """Compare the model with measured efficiency, add the effects the data ask for and write
    the report into ``--out``.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``measured`` (CSV path or None: the case's points), ``out``, ``effects``,
        ``folds``, ``loads`` and ``strict``.

    Returns
    -------
    int
        0 when the report is written.

    Raises
    ------
    ToothfemError
        If ``--folds`` is below 2, an effect is unknown, or the case or data are refused.
    """
    from ..case import load_case
    from ..efficiency import loop as lp
    from ..efficiency.loop import effects as fx, measured as ms
    from ..errors import ToothfemError
    from ..output import atomic_dir
    from . import json_default
    from ..report import html as report_html, loop as rl, save

    case = load_case(args.case)
    if args.measured:
        data = ms.load_measured(args.measured, ratio=case.ratio(), strict=args.strict)
    else:
        data = ms.from_case(case)
    say = (lambda msg: print(msg, file=sys.stderr)) if args.json else print
    for r in data.rejected:
        say(f"refused {args.measured}: {r}")
    for note in data.notes:
        say(f"note {args.measured}: {note}")
    effects = fx.catalog()
    if args.effects:
        names = [n.strip() for n in args.effects.split(",") if n.strip()]
        effects = tuple(fx.by_name(n, effects) for n in names)
    if args.folds < 2:
        raise ToothfemError(f"--folds = {args.folds} is outside the valid range [2, inf)")
    settings = lp.Settings(folds=args.folds)
    with atomic_dir(args.out) as tmp:     # open from the start: a bad --out refused at once
        report = lp.run_loop(case, data, effects, settings=settings, loads=args.loads,
                             progress=lambda msg: say(f"  {msg}"))
        out = report.to_dict()
        out["case_file"] = str(args.case)
        out["measured_file"] = args.measured
        final = lp.final_case(case, report, effects)
        out["final_case_fields"] = {
            f: _field(final, f) for e in report.effects for f in e.case_fields}
        (tmp / "report.json").write_text(json.dumps(out, indent=2, default=json_default) + "\n")
        for stage in ("before", "after"):
            save(rl.plot_residuals(report, stage), tmp / f"residuals_{stage}.png", dpi=110)
        (tmp / "report.md").write_text(rl.markdown(report, effects=effects))
        report_html.write_report(tmp, case, command="loop", case_file=args.case)
    if args.json:
        print(json.dumps(out, indent=2, default=json_default))
        return 0
    b, f = report.baseline, report.final
    error = (f"held-out RMSE {100 * b.rmse:.3f} -> {100 * f.rmse:.3f} points"
             if report.selection else
             f"fit RMSE {100 * report.baseline_fit.rmse:.3f} points (too few points for a "
             "held-out error)")
    size = (f"{report.n_rows} rows binned onto {report.n_points} points"
            if report.n_rows != report.n_points else f"{report.n_points} points")
    print(f"{case.name}: {size}; {error}; effects: "
          f"{', '.join(e.name for e in report.effects) or 'none'}; unexplained: "
          f"{report.unexplained_text()}")
    print(f"  {report.stop_reason}")
    for g in report.alias_groups:
        print(f"  step {g.step}: {g.note}")
    print(f"wrote {(Path(args.out) / 'report.md').resolve()}")
    return 0


def _field(case, dotted):
    section, name = dotted.split(".")
    return getattr(getattr(case, section), name)

