"""The `toothfem` console script. Thin: parses arguments, calls the public API, and turns
toothfem's errors into one line on stderr and a non-zero exit code.

Exit codes: 0 done; 2 refused (bad input: the line names the parameter); 3 an internal
error (a bug: one line, the traceback with ``TOOTHFEM_DEBUG=1``); 4 a long run incomplete
(points failed, or the Dask cluster was lost: the line says how many points are kept);
130 / 143 interrupted by SIGINT / SIGTERM (the output folder is left as it was: commands
write through :func:`toothfem.output.atomic_dir`; a sweep or ensemble keeps its finished
points, :func:`toothfem.output.resumable_dir`, and the line says so). A closed stdout
(``toothfem check CASE | head -1``) ends the command quietly.
"""
from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
import threading
import warnings

from . import __version__
# each command module is light (NAME, HELP, add_parser, run); what a command needs is
# imported by its own add_parser and run, so `toothfem --help` imports neither numpy nor
# the FE (benchmarks/cli_startup.py times it)
from .commands import (check, contact, design, efficiency, geometry, loop, modes, run, size,
                       stiffness, sweep, te_loop, tolerance, new, wear)

COMMANDS = (check, geometry, contact, stiffness, modes, tolerance, design, size, efficiency,
            run, loop, te_loop, sweep, new, wear)
#: Environment variable that lets an internal error show its traceback.
DEBUG_ENV = "TOOTHFEM_DEBUG"
#: Exit codes (module docstring).
EXIT_REFUSED, EXIT_INTERNAL, EXIT_INCOMPLETE = 2, 3, 4


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand of COMMANDS.

    Parameters
    ----------
    only : str, optional
        Build the arguments of this subcommand alone; every other one is listed by its
        name and help line only (what ``toothfem --help`` shows), so that its add_parser,
        which may import the package's heavy parts, does not run. None: all of them.

    Returns
    -------
    argparse.ArgumentParser
        Each fully built subcommand sets ``func`` (its ``run``).
    """
    parser = argparse.ArgumentParser(
        prog="toothfem",
        description="Tooth-contact analysis and efficiency of precision robot reducers "
                    "(cycloid-pin, RV, sine-profile).",
        epilog="exit codes: 0 done; 2 refused (bad input, one line naming it); 3 internal "
               "error; 4 a sweep or ensemble incomplete (failed points or a lost Dask "
               "cluster; finished points kept, the same command resumes); 130 / 143 "
               "interrupted by Ctrl-C / SIGTERM")
    parser.add_argument("--version", action="version", version=f"toothfem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for cmd in COMMANDS:
        if only is None or only == cmd.NAME:
            cmd.add_parser(sub)
        else:
            sub.add_parser(cmd.NAME, help=cmd.HELP)
    return parser


def _command_named(argv) -> str:
    """The subcommand that ``argv`` names: its first word that is not an option (the
    top-level options, --help and --version, take no value); "" for none."""
    return next((a for a in argv if not a.startswith("-")), "")


def console() -> None:
    """The console script ``toothfem``: :func:`main` on ``sys.argv``, then exit with its
    code. A SIGINT or SIGTERM that arrives once the command has ended (its output in
    place, its exit code known) is ignored while the interpreter shuts down: it killed the
    process by the signal's default action (exit -15 with a complete result on disk; the
    fault probe, 1 in 20 instants)."""
    sys.exit(main(late_signals_ignored=True))


def main(argv=None, *, late_signals_ignored: bool = False) -> int:
    """Run one subcommand, turning toothfem's errors into a line on stderr.

    Parameters
    ----------
    argv : list of str, optional
        The arguments without the program name (None: ``sys.argv[1:]``).
    late_signals_ignored : bool
        After the command, ignore SIGINT and SIGTERM instead of restoring the handlers
        it found (the console script, which exits next).

    Returns
    -------
    int
        The exit code (module docstring): 0, EXIT_REFUSED, EXIT_INTERNAL, or 128 plus
        the signal's number.
    """
    _never_unencodable()
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(only=_command_named(argv)).parse_args(argv)
    from .errors import IncompleteRun, Terminated, ToothfemError   # after --help: numpy

    name = f"toothfem {args.command}"
    try:
        with _signals_raise(late_signals_ignored), _one_line_warnings(name):
            return args.func(args)
    except BrokenPipeError:
        return _quiet_broken_pipe()
    except IncompleteRun as exc:
        _say(f"{name}: incomplete: {exc}{_kept(exc, '')}")
        return EXIT_INCOMPLETE
    except (ToothfemError, OSError) as exc:
        _say(f"{name}: error: {exc}{_kept(exc, '')}")
        return EXIT_REFUSED
    except KeyboardInterrupt as exc:
        _say(f"{name}: interrupted{_kept(exc, '; no output written')}")
        return 128 + signal.SIGINT
    except Terminated as exc:
        _say(f"{name}: terminated{_kept(exc, '; no output written')}")
        return 128 + signal.SIGTERM
    except (Exception, MemoryError) as exc:     # noqa: BLE001 -- the last line of defence
        if os.environ.get(DEBUG_ENV):
            raise
        what = "out of memory" if isinstance(exc, MemoryError) else \
            f"internal error: {type(exc).__name__}: {exc}".splitlines()[0]
        _say(f"{name}: {what} (a bug: please report it with the case file; "
             f"{DEBUG_ENV}=1 shows the traceback)")
        return EXIT_INTERNAL


def _kept(exc: BaseException, otherwise: str) -> str:
    """What a stopped long run kept (toothfem.output.resumable_dir), or ``otherwise``."""
    kept = getattr(exc, "toothfem_kept", None)
    return f"; {kept}" if kept else otherwise


def _never_unencodable():
    """stdout and stderr replace a character their encoding lacks (PYTHONIOENCODING=ascii,
    a C locale) instead of raising: the tables and messages hold en dashes, degrees and
    Greek letters."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.reconfigure(errors="replace")  # type: ignore[union-attr]


def _say(line: str):
    """One line on stderr; a closed stderr is ignored."""
    with contextlib.suppress(OSError, ValueError):
        print(line, file=sys.stderr)


@contextlib.contextmanager
def _one_line_warnings(name: str):
    """Warnings (a cache that cannot be written, say) as one line each on stderr, the
    same message once, each also kept for the command's report.html
    (:func:`toothfem.report.html.warnings_kept`)."""
    from .report.html import warnings_kept

    said = set()

    def say_once(message, category, *rest, **kw):
        if str(message) not in said:      # a cache failing for every ring: one line
            said.add(str(message))
            _say(f"{name}: warning: {message}")

    with warnings.catch_warnings():
        warnings.showwarning = say_once
        with warnings_kept():       # and kept for the report.html of the command's folder
            yield


@contextlib.contextmanager
def _signals_raise(then_ignored: bool = False):
    """While the command runs, SIGINT raises KeyboardInterrupt and SIGTERM
    :class:`~toothfem.errors.Terminated`, and each is noted
    (:func:`toothfem.signals.note`): Python ignores an exception raised inside a
    finalizer or a weakref callback, so a signal whose exception lands there was lost (the
    run went on and wrote its result, exit 0); the output folder stops for a noted signal
    before it commits a result or keeps a point. Only the main thread can set a handler;
    elsewhere, as under a test runner's worker thread, nothing changes. Afterwards the
    handlers found are restored, or (``then_ignored``) both signals are ignored."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    from . import signals

    def handler(signum, frame):
        signals.note(signum)
        signals.stop_if_noted()

    previous = {s: signal.signal(s, handler) for s in signals.STOP_SIGNALS}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, signal.SIG_IGN if then_ignored else h)
        signals.note(None)


def _quiet_broken_pipe() -> int:
    """The reader of stdout has gone (``| head``): point stdout at /dev/null so that the
    interpreter's final flush does not complain, and end without a message (Python's
    documented recipe, https://docs.python.org/3/library/signal.html#note-on-sigpipe)."""
    with contextlib.suppress(AttributeError, OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    return 128 + signal.SIGPIPE


if __name__ == "__main__":  # pragma: no cover
    console()
