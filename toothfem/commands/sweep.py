"""`toothfem sweep CASE --vary KEY=V1,V2,... [--vary ...] [--torque-Nm T1,T2] [--positions N]
[--pins P] [--sine-loads fem|analytic] [--scheduler ADDRESS] [--workers N]
[--cache-dir DIR | --no-cache] --out DIR`."""
from __future__ import annotations

import json


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "sweep"
HELP = ("designs x load cases x meshing positions through Dask; one CSV row per design and "
        "load case")


def add_parser(sub):
    """Add ``toothfem sweep`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a dotted case key and its values, e.g. cycloid.eccentricity_mm=0.9,1.0;"
                        " operating.* keys are load cases, the others designs (repeatable)")
    p.add_argument("--torque-Nm", default=None, dest="torques", metavar="T1,T2,...",
                   help="reducer output torques [N m] as load cases (default: the case's)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pin or tooth pitch (default 36)")
    p.add_argument("--pins", choices=("conventional", "integral", "rigid"), default=None,
                   help="cycloid pin structure (default: the case's)")
    p.add_argument("--sine-loads", choices=("fem", "analytic"), default="fem",
                   help="sine drives: FE cycle mode (fem, default) or the seeds' analytic "
                        "split")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address (default: a local cluster)")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of the local cluster (default: one per CPU)")
    cache = p.add_mutually_exclusive_group()
    cache.add_argument("--cache-dir", default=None,
                       help="disk cache of influence tables (default: $TOOTHFEM_CACHE or "
                            "~/.cache/toothfem)")
    cache.add_argument("--no-cache", action="store_true", help="no disk cache")
    p.add_argument("--out", required=True,
                   help="output folder: sweep.csv and sweep.json at the end (the points "
                        "as they finish in a hidden journal folder beside it); the same "
                        "command resumes an unfinished sweep")
    p.add_argument("--json", action="store_true",
                   help="print the key figures as JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run a design and load-case sweep (:func:`toothfem.sweep.sweep`) and print its summary.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``vary`` (list of KEY=V1,V2), ``torques`` [N m] or None, ``positions``,
        ``pins``, ``scheduler``, ``workers``, ``cache_dir``, ``no_cache``, ``sine_loads``
        and ``out``.

    Returns
    -------
    int
        0 after every design and load case has run.

    Raises
    ------
    CaseError
        If a key is given twice, a value cannot be read, or as :func:`toothfem.sweep.sweep`.
    IncompleteRun
        When a point failed (after the tables are written), or the cluster was lost
        (:class:`toothfem.cluster.ClusterError`; the finished points are kept).
    """
    from ..errors import CaseError, IncompleteRun
    from ..report import summary as report_summary
    from ..sweep import sweep

    vary = {}
    for item in args.vary:
        key, values = parse_vary(item)
        if key in vary:

            raise CaseError(f"--vary {key} is given twice")
        vary[key] = values
    torques = None
    if args.torques is not None:
        torques = parse_values("--torque-Nm", args.torques)
    result = sweep(args.case, vary, torques_Nm=torques, positions=args.positions,
                   pins=args.pins, scheduler=args.scheduler, n_workers=args.workers,
                   out=args.out, cache_dir=False if args.no_cache else args.cache_dir,
                   sine_loads=args.sine_loads, progress=True)
    summary = json.loads((result.out / "sweep.json").read_text())
    if args.json:
        print(json.dumps({k: v for k, v in summary.items() if k != "files"}, indent=2))
    else:
        print(report_summary.text([
            ("designs x load cases", "",
             {"value": summary["designs"] * summary["load_cases"]}),
            ("points computed", "", {"value": summary["rows"] - summary["resumed"]}),
            ("points resumed", "", {"value": summary["resumed"]}),
            ("points failed", "", {"value": summary["failed"]}),
            ("wall time", "s", {"value": summary["wall_s"]})], f"{summary['case']}: sweep"))
        print(f"wrote {result.out.resolve()} (sweep.csv, sweep.json, report.html)")
    if result.failed:
        raise IncompleteRun(f"{result.failed} of {len(result.rows)} points failed (the "
                            f"error column of {result.table} says why)")
    return 0


def parse_vary(item: str):
    """'KEY=V1,V2' -> (KEY, [V1, V2]) with each value an int, float or string.

    Parameters
    ----------
    item : str
        One ``--vary`` argument.

    Returns
    -------
    tuple of (str, list)
        The key and its values.

    Raises
    ------
    CaseError
        If there is no ``=``, no key, or an empty value.
    """
    from ..errors import CaseError

    key, sep, values = item.partition("=")
    if not sep or not key.strip():
        raise CaseError(f"--vary {item!r}: expected KEY=V1,V2,...")
    return key.strip(), parse_values(f"--vary {key.strip()}", values)


def parse_values(name: str, text: str) -> list:
    """Comma-separated values, each an int, float or string.

    Parameters
    ----------
    name : str
        The option, for the message.
    text : str
        "V1,V2,...".

    Returns
    -------
    list
        The values.

    Raises
    ------
    CaseError
        If a value is empty.
    """
    from ..errors import CaseError

    out = []
    for token in text.split(","):
        token = token.strip()
        if not token:
            raise CaseError(f"{name}: empty value in {text!r}")
        out.append(_number(token))
    return out


def _number(token: str):
    for kind in (int, float):
        try:
            return kind(token)
        except ValueError:
            pass
    return token
