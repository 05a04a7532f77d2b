"""Atomic output folders: write into a temporary sibling, then swap it into place.

A run that fails, is interrupted (SIGINT, or SIGTERM, which the CLI turns into an
exception) or is killed never leaves a half-written result under the output name: the work
happens in a hidden sibling ``.<name>~<digest>.tmp-<host>-<pid>-<random>`` (the name cut to
64 characters and told apart by a digest, so that a legal 255-character name stays legal),
put under ``<name>`` only when complete. A sibling left by a run that was killed outright
(SIGKILL, power loss) names its process; the next run into the same folder removes it once
that process is gone. An earlier result is exchanged for the new one in one step where the
platform has one (``renameat2`` with ``RENAME_EXCHANGE`` on Linux), so the name never
points at nothing; elsewhere it is moved aside (``.old-``) for the instant of two renames,
and a run killed inside that instant leaves it there, put back under its name by the next
run (which says so). A symbolic link ``out`` is followed: the result is written where it
points. The name is held by one run at a time (a lock file beside it,
:mod:`toothfem.folder_lock`): a second run into the same folder is refused at once.

A long run keeps its finished points in a journal folder of its own beside the output
(:func:`resumable_dir`), so an unfinished run never takes the place of a finished result.

Only a folder toothfem wrote is ever replaced: every result folder holds the marker file
MARKER, which lists what the run wrote, and an ``out`` that is a file, a folder that is
neither empty nor marked (a user's folder, the case's own folder), or a marked folder
holding something the run did not write (a user's note put beside the results), is
refused before anything is written. The marker names the toothfem version and the command
line that wrote the folder.
"""
from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path
from typing import TextIO

from . import __version__, signals
from .errors import ToothfemError, short_repr, shown
from .folder_lock import exchange, held
from .leftovers import left_by_dead_runs, owner

#: The file that marks a folder as a toothfem result (what a later run may replace).
MARKER = ".toothfem-result"

def _stem(out: Path) -> str:
    """The hidden siblings' common start: ``.<name cut to 64>~<digest of the name>``."""
    digest = hashlib.sha1(out.name.encode("utf-8", "surrogateescape")).hexdigest()[:8]
    return f".{out.name[:64]}~{digest}"


def _tag(out: Path, kind: str) -> str:
    return f"{_stem(out)}.{kind}-{owner()}"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: The process's umask (read once, at import: setting it to read it is not thread-safe).
_UMASK = _umask()


def target(out) -> Path:
    """The folder a result named ``out`` goes to.

    Parameters
    ----------
    out : str or os.PathLike
        The output folder as given.

    Returns
    -------
    pathlib.Path
        ``out``, or where it points when it is a symbolic link (followed through every
        link; a dangling link gives its target).

    Raises
    ------
    ToothfemError
        For an ``out`` that is not a path (None, a number), an empty one, or a link that
        loops.
    """
    if not isinstance(out, (str, os.PathLike)) or not str(out):
        raise ToothfemError(f"out = {short_repr(out)} is not a folder path; valid: a path "
                            "such as 'out/run'")
    out = Path(out)
    if not out.is_symlink():
        return out
    try:
        return Path(os.path.realpath(out, strict=True))
    except FileNotFoundError:           # dangling: its target
        return Path(os.path.realpath(out))
    except OSError as exc:              # a loop of links
        raise ToothfemError(f"--out {shown(out)} is a symbolic link that cannot be followed "
                            f"({exc.strerror or exc}); valid: a folder path") from None


def clean_stale(out) -> list[Path]:
    """Tidy the hidden siblings of ``out`` left by runs on this machine whose process has
    ended: a previous result left aside by a run killed during the swap is put back under
    ``out`` when nothing is there (with a warning); every other leftover is removed.
    Siblings of live processes, of other machines and of other names are left alone.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.

    Returns
    -------
    list of pathlib.Path
        What was removed.
    """
    out = target(out)
    removed = []
    for kind, sib in sorted(left_by_dead_runs(out.parent, _stem(out) + ".", ("tmp", "old")),
                            key=lambda k: k[0] != "old"):
        kept = sib / out.name
        if kind == "old" and kept.is_dir() and not out.exists():
            with contextlib.suppress(OSError):
                kept.replace(out)
                warnings.warn(f"--out {out}: the earlier result, left aside by a run that "
                              f"was killed while replacing it, is back under its name",
                              RuntimeWarning, stacklevel=2)
            if kept.exists():           # not put back: the only copy stays where it is
                continue
        shutil.rmtree(sib, ignore_errors=True)
        removed.append(sib)
    return removed


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
    out = target(out)
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


#: The marker's first line starts so; the version and command line follow, then ":" and
#: the names the run wrote, one per line.
_MARKER_HEAD = "written by toothfem"
#: What an unfinished long run's marker says, with its key (resumable_dir).
_UNFINISHED = re.compile(r"; unfinished run ([0-9a-f]+)")


def command_line() -> str:
    """The command line of this process as the marker and report.html name it: the
    program's name (not its path) and its arguments, on one line.

    Returns
    -------
    str
        E.g. ``toothfem run cases/rv40e.toml --out out/rv``; bytes of another locale in
        a path as ``\\xNN``.
    """
    argv = sys.argv or ["python"]
    return shown(" ".join(" ".join([Path(argv[0]).name, *argv[1:]]).split()))


def _marker_head(unfinished: str | None = None) -> str:
    command = command_line()[:200]
    state = (f"; unfinished run {unfinished}: the same command resumes it"
             if unfinished else "")
    return (f"{_MARKER_HEAD} {__version__} ({command}){state}; a later "
            "run may replace this folder")


def _listed(marker: Path):
    """The names a marked folder's run wrote, or None (no marker, or one written before
    the marker listed them)."""
    try:
        lines = marker.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    if len(lines) < 2 or not (lines[0].startswith(_MARKER_HEAD) and lines[0].endswith(":")):
        return None
    return set(lines[1:])


def _lock_file(out: Path) -> Path:
    return out.parent / f"{_stem(out)}.lock"


@contextlib.contextmanager
def reserved(out):
    """Hold the output name ``out`` for the block: checked, and locked against every other
    run (:func:`toothfem.folder_lock.held`), so that a second run into the same folder is
    refused at once in one line instead of both computing and one result silently
    replacing the other. Re-entrant within a process; a dead process's lock never blocks.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder (its parent is created).

    Yields
    ------
    pathlib.Path
        The folder the result goes to (:func:`target`).

    Raises
    ------
    ToothfemError
        Before any work: another run holds the name, its folder cannot be written, or it
        holds what toothfem did not write (:func:`check_replaceable`).
    """
    out = target(out)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise ToothfemError(f"--out {shown(out)}: a part of its folder is a file; valid: "
                            "a path of folders") from None
    except OSError as exc:
        raise ToothfemError(f"--out {shown(out)}: its folder cannot be made "
                            f"({exc.strerror or exc})") from None
    with held(_lock_file(out), out):
        clean_stale(out)
        check_replaceable(out)
        try:
            yield out
        except BaseException as exc:
            kept = _kept_beside(out)
            if kept and not getattr(exc, KEPT_ATTRIBUTE, None):
                setattr(exc, KEPT_ATTRIBUTE, f"{kept} finished points kept beside "
                                             f"{shown(out)} (the same command resumes)")
            raise


def _kept_beside(out: Path) -> int:
    """How many finished points the journals of unfinished runs into ``out`` hold."""
    count = 0
    for folder in _journal_folders(out):
        with contextlib.suppress(OSError, UnicodeDecodeError):
            count += sum(line.endswith("}") for line in     # not a line cut short
                         (folder / JOURNAL).read_text(encoding="utf-8").splitlines())
    return count


#: Failures of a write itself (a file-size limit, a full disk, a quota): an OSError of
#: these while the result is written is the output's, whatever file it names.
_WRITE_FAILURES = (errno.EFBIG, errno.ENOSPC, errno.EDQUOT)


def _named_for_user(exc: OSError, tmp: Path, out: Path) -> ToothfemError | None:
    """A failure to write the result into the hidden folder ``tmp`` as one line naming
    ``out`` (the path the user gave), or None for another error."""
    names = [os.fsdecode(f) for f in (exc.filename, exc.filename2) if f is not None]
    if exc.errno in _WRITE_FAILURES or any(n.startswith(os.fspath(tmp)) for n in names):
        return ToothfemError(f"--out {shown(out)} cannot be written "
                             f"({exc.strerror or exc}); nothing was written under it")
    return None


@contextlib.contextmanager
def atomic_dir(out, *, unfinished: str | None = None):
    """Yield a temporary folder that becomes ``out`` only if the block succeeds.

    On an exception (KeyboardInterrupt and the CLI's SIGTERM included) the temporary folder
    is removed and ``out`` is left as it was, so a failed run never leaves a half-written
    result folder. Stale temporary folders of killed runs are removed first
    (:func:`clean_stale`); the name is held against other runs (:func:`reserved`). An
    earlier result is swapped for the new one in one step where the platform can
    (:func:`toothfem.folder_lock.exchange`), so the name never points at nothing.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder (its parent is created).
    unfinished : str, optional
        The key of a long run that goes on writing into the folder (its marker says so:
        :func:`resumable_dir`).

    Yields
    ------
    pathlib.Path
        The temporary folder to write into.
    """
    with reserved(out) as out:
        try:
            tmp = Path(tempfile.mkdtemp(prefix=_tag(out, "tmp"), dir=out.parent))
        except OSError as exc:
            raise ToothfemError(f"--out {shown(out)}: its folder cannot be written "
                                f"({exc.strerror or exc})") from None
        try:
            tmp.chmod(0o777 & ~_UMASK)          # as a folder made by mkdir (mkdtemp: 0700)
            (tmp / MARKER).write_text(_marker_head() + "\n", encoding="utf-8")
            yield tmp
            signals.stop_if_noted()
            (tmp / MARKER).write_text("\n".join([_marker_head(unfinished) + ":"] + sorted(
                p.name for p in tmp.iterdir() if p.name != MARKER)) + "\n", encoding="utf-8")
        except BaseException as exc:
            with signals.held():          # a second Ctrl-C does not cut the clean-up short
                shutil.rmtree(tmp, ignore_errors=True)
            said = _named_for_user(exc, tmp, out) if isinstance(exc, OSError) else None
            if said is not None:
                raise said from None
            raise
        try:
            _swap_in(tmp, out)
        except OSError as exc:
            raise ToothfemError(f"--out {shown(out)} cannot be written "
                                f"({exc.strerror or exc}); nothing was written under it") \
                from None
        for journal in _journal_folders(out):   # unfinished runs into out: superseded
            shutil.rmtree(journal, ignore_errors=True)


def _swap_in(tmp: Path, out: Path) -> None:
    """Put the finished folder ``tmp`` under the name ``out``: the earlier result there is
    exchanged for it in one step (and then removed from ``tmp``'s name, where a kill leaves
    it as a dead run's leftover), or, where the platform has no exchange, moved aside for
    the instant of two renames."""
    old = None
    try:
        with signals.held():
            if out.exists() and exchange(tmp, out):
                pass                           # tmp now holds the earlier result
            elif out.exists():
                old = Path(tempfile.mkdtemp(prefix=_tag(out, "old"), dir=out.parent))
                out.replace(old / out.name)
                try:
                    tmp.replace(out)
                except BaseException:
                    (old / out.name).replace(out)   # put the previous result back
                    raise
            else:
                tmp.replace(out)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and out.exists():   # else it holds the only copy: keep it
            shutil.rmtree(old, ignore_errors=True)


#: A long run's finished points, one JSON object per line, kept while the run is
#: unfinished in a hidden folder of its own beside the output folder (resumable_dir).
JOURNAL = "finished_points.jsonl"
#: The attribute resumable_dir sets on an exception leaving its block: what is kept
#: (toothfem.cli reads it).
KEPT_ATTRIBUTE = "toothfem_kept"


def journal_folder(out, key: str) -> Path:
    """Where an unfinished long run of ``key`` into ``out`` keeps its finished points:
    the hidden sibling ``.<name cut to 64>~<digest>.journal-<key>``, never ``out`` itself,
    so that an unfinished run never takes the place of a finished result.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.
    key : str
        The run's key.

    Returns
    -------
    pathlib.Path
        The folder (it holds MARKER and JOURNAL once the first point is kept).
    """
    out = target(out)
    return out.parent / f"{_stem(out)}.journal-{key}"


def _journal_folders(out: Path) -> list[Path]:
    """The journal folders of unfinished runs into ``out``, of any key."""
    start = f"{_stem(out)}.journal-"
    with contextlib.suppress(OSError):
        return [p for p in out.parent.iterdir() if p.name.startswith(start)]
    return []


class Points:
    """The finished points of a long run: ``done`` {point: record}, those read back from
    the journal of an earlier, unfinished run of the same key and those recorded since.
    The journal folder (:func:`journal_folder`) is made when the first point is recorded;
    the output folder is left as it was until the finished result replaces it.

    Parameters
    ----------
    folder : pathlib.Path
        The journal folder.
    key : str
        The run's key (its marker says it).
    done : dict
        The points read back.
    """

    def __init__(self, folder: Path, key: str, done: dict):
        self.folder, self.key, self.done = folder, key, done
        self._fh: TextIO | None = None

    def record(self, point: str, record: dict) -> None:
        """Keep one finished point: appended to the journal and on disk (flushed and
        synced) before this returns.

        Parameters
        ----------
        point : str
            The point's name within the run (a later record of the same name replaces
            the earlier one).
        record : dict
            Its result (JSON: numbers, strings, None, lists and dicts of these).
        """
        signals.stop_if_noted()
        fh = self._fh
        if fh is None:
            fh = self._open()
        fh.write(_line(point, record))
        fh.flush()
        os.fsync(fh.fileno())
        self.done[point] = record

    def _open(self) -> TextIO:
        """The journal, opened to append (kept as ``_fh`` and returned): a new journal
        folder holding the points read back, or the resumed one's journal rewritten
        without a line cut short by a kill."""
        if _journal(self.folder, self.key) is None:
            with atomic_dir(self.folder, unfinished=self.key) as tmp:
                (tmp / JOURNAL).write_text("".join(_line(p, r) for p, r in self.done.items()),
                                           encoding="utf-8")
        else:
            with tempfile.NamedTemporaryFile("w", encoding="utf-8", dir=self.folder,
                                             delete=False,
                                             prefix=f".{JOURNAL}.tmp-{owner()}") as fh:
                fh.writelines(_line(p, r) for p, r in self.done.items())
            os.replace(fh.name, self.folder / JOURNAL)
        self._fh = open(self.folder / JOURNAL, "a", encoding="utf-8")  # noqa: SIM115 -- every record() appends; close() closes
        return self._fh

    def close(self):
        if self._fh is not None:
            # a write that failed (a file-size limit, a full disk) fails its flush again
            # here: the exception already raised says so, this one would hide it
            with contextlib.suppress(OSError):
                self._fh.close()


def _line(point: str, record: dict) -> str:
    """One journal line (numpy scalars as Python numbers)."""
    return json.dumps({"point": point, "record": record}, default=_plain) + "\n"


def _plain(x):
    """numpy scalars as Python numbers (json's ``default``)."""
    if hasattr(x, "item"):
        return x.item()
    raise TypeError(f"{type(x).__name__} is not JSON")


def _journal(out: Path, key: str):
    """The finished points of an unfinished run of ``key`` in ``out``, or None (no such
    run there). A line cut short by a kill is skipped."""
    marker = out / MARKER
    try:
        head = marker.read_text(encoding="utf-8").split("\n", 1)[0]
        lines = (out / JOURNAL).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    m = _UNFINISHED.search(head)
    if not (head.startswith(_MARKER_HEAD) and m and m.group(1) == key):
        return None
    done = {}
    for line in lines:
        try:
            entry = json.loads(line)
            done[str(entry["point"])] = entry["record"]
        except (ValueError, KeyError, TypeError):
            continue
    return done


@contextlib.contextmanager
def resumable_dir(out, key: str):
    """The finished points of a long run of many points, kept on disk as they finish.

    From the first finished point on, the run's journal folder (:func:`journal_folder`,
    beside ``out``) holds its marker (unfinished, with ``key``) and the journal JOURNAL:
    each finished point is appended and synced as it arrives (:meth:`Points.record`), so a
    run stopped in any way (an interrupt, SIGKILL, a lost cluster, power loss) keeps every
    finished point, and the same command (the same ``key``) resumes: the points read back
    are in ``done``. ``out`` itself is not touched: an earlier result there stays whole
    until the finished result is written with :func:`atomic_dir`, which then removes the
    journal. ``out`` is refused at once as by :func:`atomic_dir` (a folder of the user's
    is never written into) and held against other runs for the block (:func:`reserved`).
    An unfinished folder of an earlier version (the journal inside ``out``) is resumed.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.
    key : str
        What identifies the run (hex digits: a hash of the case and the settings).

    Yields
    ------
    Points
        ``done`` and ``record``. An exception leaving the block carries
        ``toothfem_kept``: a line saying how many points are kept and where.
    """
    with reserved(out) as out:
        folder = journal_folder(out, key)
        for place in (folder, out):
            for _, left in left_by_dead_runs(place, f".{JOURNAL}."):  # a rewrite cut short
                with contextlib.suppress(OSError):
                    left.unlink()
        clean_stale(folder)
        done = _journal(folder, key)
        if done is None:
            done = _journal(out, key)
        points = Points(folder, key, done or {})
        try:
            yield points
        except BaseException as exc:
            # what the journal on disk holds: a signal between a point's sync and its
            # entry in ``done`` left the line saying "no output written" with a point kept
            kept = _journal(folder, key) or points.done
            said = exc
            if isinstance(exc, OSError) and exc.errno in _WRITE_FAILURES:
                said = ToothfemError(f"--out {shown(out)}: its finished points cannot be "
                                     f"kept beside it ({exc.strerror or exc})")
            if kept:
                setattr(said, KEPT_ATTRIBUTE, f"{len(kept)} finished points kept beside "
                                              f"{shown(out)} (the same command resumes)")
            if said is not exc:
                raise said from None
            raise
        finally:
            points.close()
