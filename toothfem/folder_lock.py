"""An output name held by one run at a time, and a swap of two folders in one step.

:func:`held` locks an output name for a run's life: an advisory lock (``flock``) on a
hidden file beside the final name, ``.<name cut to 64>~<digest>.lock``. A second run into
the same name, in this or another process, is refused at once in one line; the lock is
released when the run ends, and a process that dies in any way (SIGKILL included) releases
it with its open files, so a dead run's lock never blocks. The lock file is removed by the
run that holds it (a run that finds the file it locked already replaced locks again).
Within one process the lock is re-entrant: a long run holds the name and its writers
take it again.

:func:`exchange` swaps two names in one step (``renameat2`` with ``RENAME_EXCHANGE`` on
Linux), so that a finished result's name never points at nothing; where the platform or
the file system has no such call it says so (False) and the caller renames twice.
"""
from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import sys
import threading
from pathlib import Path

from .errors import ToothfemError, shown

try:
    import fcntl
except ImportError:          # pragma: no cover -- Windows: no advisory lock
    fcntl = None  # type: ignore[assignment]

#: Lock files this process holds: path -> [file descriptor, depth].
_HELD: dict[str, list[int]] = {}
_GUARD = threading.Lock()


@contextlib.contextmanager
def held(lock: Path, out: Path):
    """Hold ``lock`` (the lock file of the output name ``out``) while the block runs.

    Parameters
    ----------
    lock : pathlib.Path
        The lock file (its folder exists).
    out : pathlib.Path
        The output name, for the message.

    Yields
    ------
    None
        While the name is held.

    Raises
    ------
    ToothfemError
        When another run holds it (one line naming ``--out`` and that run's process), or
        the lock file cannot be made (naming ``--out`` and why).
    """
    key = os.fspath(lock)
    with _GUARD:
        mine = _HELD.get(key)
        if mine is not None:
            mine[1] += 1
    if mine is not None:
        try:
            yield
        finally:
            with _GUARD:
                mine[1] -= 1
        return
    fd = _acquire(lock, out)
    with _GUARD:
        _HELD[key] = [fd, 1]
    try:
        yield
    finally:
        with _GUARD:
            entry = _HELD.pop(key)
        if entry[1] > 1:             # pragma: no cover -- a thread still inside: keep it
            with _GUARD:
                _HELD[key] = [fd, entry[1] - 1]
        else:
            with contextlib.suppress(OSError):
                lock.unlink()        # while still locked: a waiting run locks again
            os.close(fd)


def _acquire(lock: Path, out: Path) -> int:
    """The locked file descriptor of ``lock`` (the file made if missing)."""
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        except OSError as exc:
            raise ToothfemError(f"--out {shown(out)}: its folder cannot be written "
                                f"({exc.strerror or exc})") from None
        if fcntl is None:            # pragma: no cover
            return fd
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise ToothfemError(f"--out {shown(out)}: cannot be locked "
                                    f"({exc.strerror or exc})") from None
            raise ToothfemError(f"--out {shown(out)} is being written by another toothfem "
                                f"run{_holder(lock)}: wait for it to end, or choose "
                                "another folder") from None
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(lock))
        except FileNotFoundError:
            same = False
        if same:
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode())
            return fd
        os.close(fd)                 # removed by the run that held it: lock the new one


def _holder(lock: Path) -> str:
    """`` (process N)`` of the run holding ``lock``, or "" if it cannot be read."""
    with contextlib.suppress(OSError, ValueError):
        return f" (process {int(lock.read_text().strip())})"
    return ""


#: renameat2's flag that swaps the two names (linux/fs.h) and "relative to the working
#: folder" (fcntl.h).
_RENAME_EXCHANGE, _AT_FDCWD = 2, -100


def _renameat2():
    if not sys.platform.startswith("linux"):
        return None
    with contextlib.suppress(OSError, AttributeError):
        return ctypes.CDLL(None, use_errno=True).renameat2
    return None


_CALL = _renameat2()


def exchange(a: Path, b: Path) -> bool:
    """Swap the names ``a`` and ``b`` (both exist) in one step.

    Parameters
    ----------
    a, b : pathlib.Path
        Two entries of one file system.

    Returns
    -------
    bool
        True when swapped; False when the platform or the file system has no such call
        (nothing changed: the caller renames twice).

    Raises
    ------
    OSError
        For another failure (nothing changed).
    """
    if _CALL is None:
        return False
    rc = _CALL(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV):
        return False
    raise OSError(err, os.strerror(err), os.fspath(b))
