"""A new file written whole, never over an existing one unless asked (``toothfem new``)."""
from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path

from . import signals
from .errors import ToothfemError
from .leftovers import left_by_dead_runs, owner


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
