"""Atomic output folders: write into a temporary sibling, then rename into place.

A run that fails, is interrupted (SIGINT, or SIGTERM, which the CLI turns into an
exception) or is killed never leaves a half-written result under the output name: the work
happens in a hidden sibling ``.<name>.tmp-<host>-<pid>-<random>``, renamed to ``<name>``
only when complete. A sibling left by a run that was killed outright (SIGKILL, power loss)
names its process; the next run into the same folder removes it once that process is gone.

Only a folder toothfem wrote is ever replaced: every result folder holds the marker file
MARKER, which lists what the run wrote, and an ``out`` that is a file, a folder that is
neither empty nor marked (a user's folder, the case's own folder), or a marked folder
holding something the run did not write (a user's note put beside the results), is
refused before anything is written.
"""
from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import socket
import tempfile
import threading
from pathlib import Path

from .errors import ToothfemError

#: The file that marks a folder as a toothfem result (what a later run may replace).
MARKER = ".toothfem-result"

#: The signals that are held back while the finished folder replaces the old one, so that
#: an interrupt cannot fall between the two renames (and leave neither under the name).
_SWAP_SIGNALS = {signal.SIGINT, signal.SIGTERM}


def _host() -> str:
    """This machine's name as it may appear in a folder name."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"


def _tag(kind: str) -> str:
    return f"{kind}-{_host()}-{os.getpid()}-"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:       # another user's live process
        return True
    return True


def clean_stale(out) -> list[Path]:
    """Remove the temporary siblings of ``out`` left by runs on this machine whose process
    has ended. Siblings of live processes, of other machines and of other names are left
    alone (a hidden folder is ignored by everything else).

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.

    Returns
    -------
    list of pathlib.Path
        What was removed.
    """
    out = Path(out)
    pattern = re.compile(rf"^\.{re.escape(out.name)}\.(tmp|old)-{re.escape(_host())}-"
                         r"(\d+)-[^/]*$")
    removed = []
    with contextlib.suppress(OSError):
        for sib in out.parent.iterdir():
            m = pattern.match(sib.name)
            if m and int(m.group(2)) != os.getpid() and not _alive(int(m.group(2))):
                shutil.rmtree(sib, ignore_errors=True)
                removed.append(sib)
    return removed


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT/SIGTERM back for the block (delivered right after it); a no-op where
    signal masks are not available or off the main thread."""
    if not hasattr(signal, "pthread_sigmask") or \
            threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _SWAP_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def check_replaceable(out) -> None:
    """Refuse an output path that toothfem did not write: a file, or a folder that is
    neither empty nor marked as a toothfem result (MARKER).

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.

    Raises
    ------
    ToothfemError
        Naming the path and why it is not replaced.
    """
    out = Path(out)
    if not out.exists():
        return
    if not out.is_dir():
        raise ToothfemError(f"--out {out} is a file: toothfem writes a folder and does not "
                            "replace what it did not write (choose a new folder)")
    marker = out / MARKER
    if any(out.iterdir()) and not marker.is_file():
        raise ToothfemError(f"--out {out} holds files toothfem did not write: it is not "
                            "replaced (choose a new or empty folder, or an earlier result)")
    written = _listed(marker)
    if written is not None:
        extra = sorted(p.name for p in out.iterdir() if p.name != MARKER
                       and p.name not in written)
        if extra:
            raise ToothfemError(f"--out {out} is an earlier result with files toothfem did "
                                f"not write ({', '.join(extra[:3])}"
                                f"{', ...' if len(extra) > 3 else ''}): it is not replaced "
                                "(move them, or choose a new folder)")


#: The marker's first line; the names the run wrote follow, one per line.
_MARKER_HEAD = "written by toothfem; a later run may replace this folder"


def _listed(marker: Path):
    """The names a marked folder's run wrote, or None (no marker, or one written before
    the marker listed them)."""
    try:
        lines = marker.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    if len(lines) < 2 or lines[0] != _MARKER_HEAD + ":":
        return None
    return set(lines[1:])


@contextlib.contextmanager
def atomic_dir(out):
    """Yield a temporary folder that becomes ``out`` only if the block succeeds.

    On an exception (KeyboardInterrupt and the CLI's SIGTERM included) the temporary folder
    is removed and ``out`` is left as it was, so a failed run never leaves a half-written
    result folder. Stale temporary folders of killed runs are removed first
    (:func:`clean_stale`).

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder (its parent is created).

    Yields
    ------
    pathlib.Path
        The temporary folder to write into.
    """
    out = Path(out)
    check_replaceable(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    clean_stale(out)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.{_tag('tmp')}", dir=out.parent))
    try:
        (tmp / MARKER).write_text(_MARKER_HEAD + "\n")
        yield tmp
        (tmp / MARKER).write_text("\n".join([_MARKER_HEAD + ":"] + sorted(
            p.name for p in tmp.iterdir() if p.name != MARKER)) + "\n", encoding="utf-8")
    except BaseException:
        with _signals_held():          # a second Ctrl-C does not cut the clean-up short
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = None
    try:
        with _signals_held():
            if out.exists():
                old = Path(tempfile.mkdtemp(prefix=f".{out.name}.{_tag('old')}",
                                            dir=out.parent))
                out.replace(old / out.name)
            try:
                tmp.replace(out)
            except BaseException:
                if old is not None:            # put the previous result back
                    (old / out.name).replace(out)
                raise
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    finally:
        if old is not None and out.exists():   # else it holds the only copy: keep it
            shutil.rmtree(old, ignore_errors=True)
