"""`toothfem tolerance CASE --samples N --out DIR [--seed S] [--workers N] [--scheduler
ADDR]`: the tolerance Monte Carlo through the elastic contact model (docs/tolerance.md)."""
from __future__ import annotations

import json
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "tolerance"
HELP = ("distributions of pin force, Hertz pressure, contacts, lost motion, TE and efficiency "
        "over reducers built within the case's [tolerances], and where their scatter comes from")


def add_parser(sub):
    """Add ``toothfem tolerance`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML) with a [tolerances] section")
    p.add_argument("--out", required=True,
                   help="output folder: the tables and pictures at the end (the rings as "
                        "they finish in a hidden journal folder beside it); the same "
                        "command resumes an unfinished ensemble")
    p.add_argument("--samples", type=int, default=None,
                   help="built reducers to draw (default 40: the median and P90/P10 with "
                        "their 95 %% intervals; P99/P1 need 368)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--positions", type=int, default=36,
                   help="positions per reducer, spread over the pairing period (default 36)")
    p.add_argument("--share-samples", type=int, default=None, dest="share_samples",
                   help="reducers per one-tolerance run for the variance shares (default "
                        "a quarter of --samples where that is 20 or more, else none; 0: "
                        "none)")
    p.add_argument("--workers", type=int, default=1,
                   help="processes (a Dask LocalCluster above 1; default 1)")
    p.add_argument("--scheduler", default=None,
                   help="address of a running Dask scheduler to use instead")
    p.add_argument("--json", action="store_true",
                   help="print the key figures as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """The tolerance ensemble of a case into ``--out``, its percentiles on screen (JSON).

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out``, ``samples``, ``seed``, ``positions``, ``share_samples``,
        ``workers`` and ``scheduler``.

    Returns
    -------
    int
        0 once the ensemble's files are written (the limits its nominal design and
        percentiles pass printed as warnings: they are no error).

    Raises
    ------
    CaseError
        For an invalid case, no nonzero tolerance, or a count out of range.
    """
    from ..case import load_case
    from ..fem.cache import content_key
    from ..output import atomic_dir, reserved, resumable_dir
    from ..report import html as report_html, summary as report_summary
    from ..report import tolerance as report_tolerance
    from ..tolerance import DEFAULT_SAMPLES, tolerance_analysis
    case = load_case(args.case)
    if args.samples is None:
        args.samples = DEFAULT_SAMPLES
    key = content_key("tolerance", case, args.samples, args.seed, args.positions,
                      args.share_samples)
    with reserved(args.out):      # the name held for the run: a second run is refused
        with resumable_dir(args.out, key) as points:
            result = tolerance_analysis(case, samples=args.samples, seed=args.seed,
                                        positions=args.positions, workers=args.workers,
                                        scheduler=args.scheduler,
                                        share_samples=args.share_samples, points=points)
        with atomic_dir(args.out) as tmp:
            summary = result.write(tmp)
            report_html.write_report(tmp, case, command="tolerance", case_file=args.case)
    if args.json:
        print(json.dumps({"case": summary["case"], "samples": summary["samples"],
                          "outputs": summary["outputs"], "nominal": summary["nominal"],
                          "percentiles": summary["percentiles"],
                          "warnings": summary["warnings"]}, indent=2))
        return 0
    rows, legend, note = report_tolerance.screen_table(summary, result.outputs())
    print(report_summary.text(rows,
                              f"{case.name}: {summary['samples']} built reducers; "
                              f"{report_tolerance.operating_text(summary)}; "
                              f"{report_tolerance.model_text(summary)}", legend=legend))
    if note:
        print(report_summary.wrapped(note))
    if not summary.get("share_samples") and len(summary.get("tolerances_mm", {})) > 1:
        print(report_summary.wrapped(
            "variance shares: not run (--share-samples N: a run of N reducers for each "
            "tolerance alone; by default from --samples 80 on)"))
    for w in summary["warnings"]:
        print(f"warning: {w['message']}")
    print(f"wrote {Path(args.out).resolve()} (samples.csv, summary.json, report.html, "
          "pictures)")
    return 0
