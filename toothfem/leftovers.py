"""Temporary files and folders of killed runs: named by machine and process, removed by a
later run once that process is gone.

A run writes its temporary output under a name holding :func:`owner` (``<host>-<pid>-``),
so that a run killed outright (SIGKILL, power loss), which cannot clean up, leaves a name
that tells a later run whether its writer is still alive (:func:`left_by_dead_runs`).
Names of live processes, of other machines and of other patterns are never touched.
"""
from __future__ import annotations

import contextlib
import os
import re
import socket
from pathlib import Path


def host() -> str:
    """This machine's name as it may appear in a file name.

    Returns
    -------
    str
        The host name, characters other than letters, digits, ``_`` and ``-`` as ``_``,
        at most 32 of them.
    """
    return (re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host")[:32]


def owner() -> str:
    """The part of a temporary name that names its writer.

    Returns
    -------
    str
        ``<host>-<pid>-``.
    """
    return f"{host()}-{os.getpid()}-"


def alive(pid: int) -> bool:
    """Whether a process of this machine is running.

    Parameters
    ----------
    pid : int
        Its process id.

    Returns
    -------
    bool
        True while it runs (another user's process counts).
    """
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def left_by_dead_runs(folder, start: str, kinds=("tmp",)):
    """The entries of ``folder`` named ``<start><kind>-<host>-<pid>-...`` whose process
    (on this machine, not this one) has ended.

    Parameters
    ----------
    folder : str or pathlib.Path
        Where to look (a folder that cannot be read has none).
    start : str
        The names' fixed start (matched literally).
    kinds : sequence of str
        The words allowed between ``start`` and the owner (``tmp``, ``old``).

    Returns
    -------
    list of (str, pathlib.Path)
        ``(kind, path)`` of each.
    """
    pattern = re.compile(rf"^{re.escape(start)}({'|'.join(map(re.escape, kinds))})-"
                         rf"{re.escape(host())}-(\d+)-")
    found = []
    with contextlib.suppress(OSError):
        for entry in Path(folder).iterdir():
            m = pattern.match(entry.name)
            if m and int(m.group(2)) != os.getpid() and not alive(int(m.group(2))):
                found.append((m.group(1), entry))
    return found
