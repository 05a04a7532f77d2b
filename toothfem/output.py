"""Atomic output folders: write into a temporary sibling, then rename into place.

A run that fails, is interrupted (SIGINT, or SIGTERM, which the CLI turns into an
exception) or is killed never leaves a half-written result under the output name: the work
happens in a hidden sibling ``.<name>~<digest>.tmp-<host>-<pid>-<random>`` (the name cut to
64 characters and told apart by a digest, so that a legal 255-character name stays legal),
renamed to ``<name>`` only when complete. A sibling left by a run that was killed outright
(SIGKILL, power loss) names its process; the next run into the same folder removes it once
that process is gone. The previous result is moved aside (``.old-``) only for the instant of
the swap; a run killed inside that instant leaves it there, and the next run puts it back
under its name (and says so) before anything else. A symbolic link ``out`` is followed: the
result is written where it points.

Only a folder toothfem wrote is ever replaced: every result folder holds the marker file
MARKER, which lists what the run wrote, and an ``out`` that is a file, a folder that is
neither empty nor marked (a user's folder, the case's own folder), or a marked folder
holding something the run did not write (a user's note put beside the results), is
refused before anything is written. The marker names the toothfem version and the command
line that wrote the folder.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import secrets
import shutil
import sys
import tempfile
import warnings
from pathlib import Path
from typing import TextIO

from . import __version__, signals
from .errors import ToothfemError, short_repr
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
        For an ``out`` that is not a path (None, a number), or an empty one.
    """
    if not isinstance(out, (str, os.PathLike)) or not str(out):
        raise ToothfemError(f"out = {short_repr(out)} is not a folder path; valid: a path "
                            "such as 'out/run'")
    out = Path(out)
    return Path(os.path.realpath(out)) if out.is_symlink() else out


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
        E.g. ``toothfem run cases/rv40e.toml --out out/rv``.
    """
    argv = sys.argv or ["python"]
    return " ".join(" ".join([Path(argv[0]).name, *argv[1:]]).split())


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


@contextlib.contextmanager
def atomic_dir(out, *, unfinished: str | None = None):
    """Yield a temporary folder that becomes ``out`` only if the block succeeds.

    On an exception (KeyboardInterrupt and the CLI's SIGTERM included) the temporary folder
    is removed and ``out`` is left as it was, so a failed run never leaves a half-written
    result folder. Stale temporary folders of killed runs are removed first
    (:func:`clean_stale`).

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
    out = target(out)
    clean_stale(out)
    check_replaceable(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=_tag(out, "tmp"), dir=out.parent))
    try:
        tmp.chmod(0o777 & ~_UMASK)          # as a folder made by mkdir (mkdtemp: 0700)
        (tmp / MARKER).write_text(_marker_head() + "\n", encoding="utf-8")
        yield tmp
        signals.stop_if_noted()
        (tmp / MARKER).write_text("\n".join([_marker_head(unfinished) + ":"] + sorted(
            p.name for p in tmp.iterdir() if p.name != MARKER)) + "\n", encoding="utf-8")
    except BaseException:
        with signals.held():          # a second Ctrl-C does not cut the clean-up short
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = None
    try:
        with signals.held():
            if out.exists():
                old = Path(tempfile.mkdtemp(prefix=_tag(out, "old"), dir=out.parent))
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


#: A long run's finished points, one JSON object per line, kept under its output folder
#: while the run is unfinished (resumable_dir).
JOURNAL = "finished_points.jsonl"
#: The attribute resumable_dir sets on an exception leaving its block: what is kept
#: (toothfem.cli reads it).
KEPT_ATTRIBUTE = "toothfem_kept"


class Points:
    """The finished points of a long run: ``done`` {point: record}, those read back from
    the journal of an earlier, unfinished run of the same key and those recorded since.
    The folder is made (replacing an earlier result) when the first point is recorded, so
    a run that finishes none leaves everything as it was.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder.
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
        """The journal, opened to append (kept as ``_fh`` and returned): a new unfinished
        folder, or the resumed one's journal rewritten without a line cut short by a kill."""
        if not self.done:
            with atomic_dir(self.folder, unfinished=self.key) as tmp:
                (tmp / JOURNAL).touch()
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
    """The output folder of a long run of many points, kept on disk as they finish.

    From the first finished point on, ``out`` holds the run's marker (unfinished, with
    ``key``) and the journal JOURNAL: each finished point is appended and synced as it
    arrives (:meth:`Points.record`), so a run stopped in any way (an interrupt, SIGKILL, a
    lost cluster, power loss) keeps every finished point, and the same command (the same
    ``key``) resumes: the points read back are in ``done``. The finished result is written
    afterwards with :func:`atomic_dir`, which replaces the unfinished folder. ``out`` is
    refused at once as by :func:`atomic_dir` (a folder of the user's is never written
    into); an earlier result there stays until the first point is recorded.

    Parameters
    ----------
    out : str or pathlib.Path
        The output folder.
    key : str
        What identifies the run (hex digits: a hash of the case and the settings); an
        unfinished folder of another key is an earlier result, replaced.

    Yields
    ------
    Points
        ``done`` and ``record``. An exception leaving the block carries
        ``toothfem_kept``: a line saying how many points are kept and where.
    """
    out = target(out)
    clean_stale(out)
    for _, left in left_by_dead_runs(out, f".{JOURNAL}."):    # a rewrite cut short
        with contextlib.suppress(OSError):
            left.unlink()
    done = _journal(out, key)
    if done is None:
        check_replaceable(out)
    points = Points(out, key, done or {})
    try:
        yield points
    except BaseException as exc:
        # what the journal on disk holds: a signal between a point's sync and its entry
        # in ``done`` left the line saying "no output written" with a point kept
        kept = _journal(out, key) or points.done
        if kept:
            setattr(exc, KEPT_ATTRIBUTE, f"{len(kept)} finished points kept in {out} "
                                         "(the same command resumes)")
        raise
    finally:
        points.close()


def write_new_file(text: str, out, *, force: bool = False) -> Path:
    """Write a text to a file atomically: a temporary sibling named by its writer
    (:mod:`toothfem.leftovers`), renamed into place whole. Never over an existing file
    unless ``force`` (the check and the placing are one step: a hard link, which fails
    when the name exists).

    Parameters
    ----------
    text : str
        The file's text (UTF-8).
    out : str or os.PathLike
        The file; a symbolic link is followed. Its folder is created.
    force : bool
        Replace an existing file.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ToothfemError
        For a path that is a folder, or an existing file without ``force`` (one line
        naming ``--out``).
    """
    out = check_new_file(out, force=force)
    out.parent.mkdir(parents=True, exist_ok=True)
    for _, stale in left_by_dead_runs(out.parent, f".{out.name}.", ("tmp",)):
        with contextlib.suppress(OSError):
            stale.unlink()
    tmp = out.parent / f".{out.name}.tmp-{owner()}{secrets.token_hex(4)}"
    try:
        with open(tmp, "x", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        signals.stop_if_noted()
        with signals.held():
            if force:
                os.replace(tmp, out)
            else:
                _place_new(tmp, out)
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()
    return out


def _place_new(tmp: Path, out: Path) -> None:
    """``tmp`` under the name ``out`` only if that name is free, in one step."""
    try:
        os.link(tmp, out)
    except FileExistsError:
        raise ToothfemError(_exists(out)) from None
    except OSError:                  # a file system without hard links: check, then rename
        if out.exists():
            raise ToothfemError(_exists(out)) from None
        os.replace(tmp, out)


def _exists(out: Path) -> str:
    return (f"--out {out} exists: toothfem does not overwrite a file (choose a new name, "
            "or --force to replace it)")


def check_new_file(out, *, force: bool = False) -> Path:
    """Refuse a ``--out`` that cannot take a new file, before any work.

    Parameters
    ----------
    out : str or os.PathLike
        The file asked for.
    force : bool
        An existing file may be replaced.

    Returns
    -------
    pathlib.Path
        The file (a symbolic link followed to its target).

    Raises
    ------
    ToothfemError
        For a path that is not a file name, a folder, or an existing file without
        ``force``.
    """
    if not isinstance(out, (str, os.PathLike)) or not str(out):
        raise ToothfemError(f"--out = {out!r} is not a file path; valid: a name such as "
                            "my_reducer.toml")
    out = Path(out)
    if out.is_symlink():
        out = Path(os.path.realpath(out))
    if out.is_dir():
        raise ToothfemError(f"--out {out} is a folder: give a file name such as "
                            f"{out / 'my_reducer.toml'}")
    if out.exists() and not force:
        raise ToothfemError(_exists(out))
    return out
