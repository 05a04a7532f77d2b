"""`toothfem check CASE`: validate a case and print its derived quantities."""
from __future__ import annotations

import json


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "check"
HELP = "validate a case file and print derived quantities"


def add_parser(sub):
    """Add ``toothfem check`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


def run(args) -> int:
    """Validate a case and print its derived quantities (a table, or JSON with ``--json``).

    Parameters
    ----------
    args : argparse.Namespace
        ``case`` (path) and ``json``.

    Returns
    -------
    int
        0 once the case has been read and shown.

    Raises
    ------
    CaseError
        A case that cannot be read or holds an invalid value (the CLI prints the message).
    """
    from ..case import load_case
    from ..derived import derived

    case = load_case(args.case)
    d = derived(case)
    if args.json:
        print(json.dumps(d, indent=2))
        return 0
    from ..report.summary import wrapped
    print(f"{args.case}: OK")
    print(wrapped(f"  ({d['ratio_sign_convention']})", indent="   "))
    rows = {k: v for k, v in d.items() if k not in ("ratio_sign_convention", "warnings")}
    if case.stated_ratio is not None:
        rows["ratio"] = f"{d['ratio']:g}  (the case states {case.stated_ratio:g})"
    width = max(len(k) for k in rows)
    for k, v in rows.items():          # a long value (a list) wrapped under its own column
        print(wrapped(f"  {k:<{width}}  {v}", indent=" " * (width + 4)))
    for w in d["warnings"]:
        print(f"warning: {w}")
    return 0
