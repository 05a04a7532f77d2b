"""The `toothfem` console script. Thin: parses arguments, calls the public API, and turns
toothfem's errors into one line on stderr and a non-zero exit code."""
from __future__ import annotations

import argparse
import sys

from . import __version__
from .commands import check, contact, efficiency, geometry, loop, run, stiffness, sweep

COMMANDS = (check, geometry, contact, stiffness, efficiency, run, loop, sweep)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="toothfem",
        description="Tooth-contact analysis and efficiency of precision robot reducers "
                    "(cycloid-pin, RV, sine-profile).")
    parser.add_argument("--version", action="version", version=f"toothfem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for cmd in COMMANDS:
        cmd.add_parser(sub)
    return parser


def main(argv=None) -> int:
    from .errors import ToothfemError

    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except ToothfemError as exc:
        print(f"toothfem {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"toothfem {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
