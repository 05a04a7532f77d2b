"""SIGINT and SIGTERM around toothfem's work, in one place: held back over a block that must
not be cut short, Python's handlers kept past a library that replaces them (gmsh), and a
signal noted so that it is not lost.

The CLI turns both signals into exceptions (KeyboardInterrupt, :class:`Terminated
<toothfem.errors.Terminated>`) so that ``with`` blocks unwind. Python ignores an exception
raised inside a finalizer or a weakref callback, so a handler's raise that lands there is
lost and the run goes on; the handler also notes the signal (:func:`note`), and the places
that commit a result or keep a point stop for it (:func:`stop_if_noted`).
"""
from __future__ import annotations

import contextlib
import signal
import threading

from .errors import Terminated

#: The signals that stop a command.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

#: The signal the running command was sent, if any (:func:`note`).
_NOTED: list = []


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def held():
    """Hold STOP_SIGNALS back for the block (delivered right after it); a no-op where
    signal masks are not available or off the main thread.

    Yields
    ------
    None
    """
    if not hasattr(signal, "pthread_sigmask") or not _main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextlib.contextmanager
def handlers_kept():
    """Python's handlers of STOP_SIGNALS as they were, put back after the block, with both
    signals held back during it (:func:`held`; delivered to those handlers right after):
    gmsh's C++ initialisation installs its own, so that a SIGTERM while meshing killed the
    process outright (exit -15, the temporary output folder left behind; issue 27). Only
    the main thread has handlers; elsewhere nothing changes.

    Yields
    ------
    None
    """
    if not _main_thread():
        yield
        return
    with held(), _handlers_restored():
        yield


@contextlib.contextmanager
def deferred():
    """STOP_SIGNALS only noted during the block, then Python's handlers put back and a
    noted signal raised (:func:`stop_if_noted`): for a C extension's initialisation, which
    fails its import as an ImportError ("initialization failed") when a handler raises
    inside it. Holding the signal back (:func:`held`) is not enough there: it masks the
    main thread only, and a signal that reaches another thread still runs the handler in
    the main thread. Only the main thread has handlers; elsewhere nothing changes.

    Yields
    ------
    None
    """
    if not _main_thread():
        yield
        return
    with _handlers_restored():
        for s in STOP_SIGNALS:
            signal.signal(s, lambda signum, frame: note(signum))
        yield
    stop_if_noted()


@contextlib.contextmanager
def _handlers_restored():
    """Python's handlers of STOP_SIGNALS as they were before the block, put back after it
    (main thread only)."""
    handlers = {s: signal.getsignal(s) for s in STOP_SIGNALS}
    try:
        yield
    finally:
        for s, handler in handlers.items():
            if handler is not None:
                signal.signal(s, handler)


def note(signum) -> None:
    """Note the signal the running command was sent (the CLI's handlers), or clear it.

    Parameters
    ----------
    signum : int or None
        SIGINT or SIGTERM; None clears it.
    """
    _NOTED[:] = [] if signum is None else [signum]


def noted():
    """The signal noted (:func:`note`), or None.

    Returns
    -------
    int or None
    """
    return _NOTED[0] if _NOTED else None


def stop_if_noted() -> None:
    """Raise what the CLI's handler raises for a noted signal (its own raise was lost).

    Raises
    ------
    KeyboardInterrupt
        For a noted SIGINT.
    toothfem.errors.Terminated
        For a noted SIGTERM.
    """
    signum = noted()
    if signum is not None:
        raise KeyboardInterrupt if signum == signal.SIGINT else Terminated(signum)
