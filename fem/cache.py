"""Disk cache of the torque-independent arrays of an FE solve, keyed by content.

A cycle-mode solve spends nearly all its time on what does not depend on the load: the
meshes, the sparse factorisations and the influence matrices they give. Those arrays are
kept here as numpy ``.npz`` files named by a hash of everything that determines them
(:func:`content_key`), so a new torque on a known design, in this process or a later one,
costs no mesh and no factorisation.

Location: ``$TOOTHFEM_CACHE`` if set, else ``~/.cache/toothfem``. Writes are atomic (a
temporary file in the same folder, then ``os.replace``), so a reader never sees half a
file; a file that cannot be read back (truncated, corrupt, other format) or whose stored
key is not the one its name promises (a renamed or copied file) counts as a miss and is
recomputed and overwritten by the caller. A temporary file names its writer
(:mod:`toothfem.leftovers`): one left by a killed write is removed by the next store once its
process is gone. A cache that cannot be written (read-only, full
disk, a file where the folder should be) costs only the saving: :meth:`DiskCache.store`
warns (:class:`CacheWarning`) and the caller's result stands.
"""
from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import os
import tempfile
import warnings
import zipfile
from dataclasses import dataclass
from pathlib import Path
from collections.abc import Mapping

import numpy as np

from ..leftovers import left_by_dead_runs, owner

#: Environment variable naming the cache folder.
CACHE_ENV = "TOOTHFEM_CACHE"
#: Folder used when CACHE_ENV is not set.
DEFAULT_DIR = Path("~/.cache/toothfem")
#: Name of the array in each file that holds the file's own key.
KEY_ARRAY = "__key__"


class CacheWarning(UserWarning):
    """The disk cache could not be written; the result was computed and is used anyway."""


def default_dir() -> Path:
    """``$TOOTHFEM_CACHE`` if set and non-empty, else ``~/.cache/toothfem`` (expanded).

    Returns
    -------
    pathlib.Path
        The cache folder (not created here).
    """
    env = os.environ.get(CACHE_ENV, "")
    return Path(env or DEFAULT_DIR).expanduser()


def content_key(*parts) -> str:
    """SHA-256 (hex) of a canonical encoding of ``parts``.

    Handles dataclasses (class name and fields by name), numpy arrays (dtype, shape, bytes),
    numbers (as exact binary floats, so 40 and 40.0 agree), strings, None, and sequences
    and mappings of these. Equal content gives an equal key in any process and session.

    Parameters
    ----------
    *parts
        The content.

    Returns
    -------
    str
        64 hex digits.

    Raises
    ------
    TypeError
        If a part (at any depth) is of another type.
    """
    h = hashlib.sha256()
    _feed(h, parts)
    return h.hexdigest()


def _feed(h, x):
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        h.update(b"D" + type(x).__name__.encode() + b"(")
        for f in dataclasses.fields(x):
            h.update(f.name.encode() + b"=")
            _feed(h, getattr(x, f.name))
        h.update(b")")
    elif isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        h.update(b"A" + a.dtype.str.encode() + repr(a.shape).encode())
        h.update(a.tobytes())
    elif x is None or isinstance(x, (bool, np.bool_)):
        h.update(b"N" if x is None else (b"T" if x else b"F"))
    elif isinstance(x, (int, float, np.integer, np.floating)):
        h.update(b"f" + float(x).hex().encode())
    elif isinstance(x, str):
        h.update(b"s" + str(len(x)).encode() + b":" + x.encode())
    elif isinstance(x, Mapping):
        h.update(b"M" + str(len(x)).encode())
        for k in sorted(x, key=str):
            _feed(h, str(k))
            _feed(h, x[k])
    elif isinstance(x, (tuple, list)):
        h.update(b"L" + str(len(x)).encode())
        for v in x:
            _feed(h, v)
    else:
        raise TypeError(f"content_key: cannot encode {type(x).__name__}")


@dataclass(frozen=True)
class DiskCache:
    """A folder of ``<key>.npz`` files, each a mapping of names to numpy arrays."""
    directory: Path = dataclasses.field(default_factory=default_dir)

    def __post_init__(self):
        object.__setattr__(self, "directory", Path(self.directory).expanduser())

    def path(self, key: str) -> Path:
        """The file that holds (or would hold) the arrays of ``key``.

        Parameters
        ----------
        key : str
            Names the file (64 hex digits of :func:`content_key`).

        Returns
        -------
        pathlib.Path
            ``<directory>/<key>.npz``.
        """
        return self.directory / f"{key}.npz"

    def load(self, key: str) -> dict[str, np.ndarray] | None:
        """The arrays stored under ``key``, or None when absent, unreadable, or stored
        under another key (the file's name and its content disagree).

        Parameters
        ----------
        key : str
            A :func:`content_key`.

        Returns
        -------
        dict of str to numpy.ndarray or None
            The arrays by name; None for a miss.
        """
        path = self.path(key)
        try:
            with np.load(path, allow_pickle=False) as data:
                if KEY_ARRAY not in data.files or str(data[KEY_ARRAY]) != key:
                    return None    # renamed, copied or foreign: recomputed and replaced
                return {name: data[name] for name in data.files if name != KEY_ARRAY}
        except FileNotFoundError:
            return None
        except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
            return None        # corrupt or foreign: a miss; the caller's store replaces it

    def store(self, key: str, arrays: Mapping[str, np.ndarray]) -> Path | None:
        """Write ``arrays`` under ``key`` atomically (with the key itself, checked by
        :meth:`load`).

        Parameters
        ----------
        key : str
            The key the arrays are stored under (:func:`content_key`).
        arrays : Mapping of str to numpy.ndarray
            The arrays by name.

        Returns
        -------
        pathlib.Path or None
            The file's path, or None with a :class:`CacheWarning` when the cache cannot be
            written (the caller goes on with its result).

        Raises
        ------
        ValueError
            If a name in ``arrays`` is the reserved KEY_ARRAY.
        """
        if KEY_ARRAY in arrays:
            raise ValueError(f"{KEY_ARRAY!r} is reserved for the cache key")
        path = self.path(key)
        tmp = None
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            for _, left in left_by_dead_runs(self.directory, "."):
                with contextlib.suppress(OSError):
                    left.unlink(missing_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".tmp-{owner()}{key[:16]}.", suffix=".tmp",
                                       dir=self.directory)
            with os.fdopen(fd, "wb") as fh:
                payload = {KEY_ARRAY: np.asarray(key),
                           **{k: np.asarray(v) for k, v in arrays.items()}}
                # numpy's stub maps **names onto allow_pickle: bool too; no array is named so
                np.savez(fh, **payload)  # type: ignore[arg-type]  # no name is "allow_pickle"
            os.replace(tmp, path)
        except OSError as exc:
            if tmp is not None:
                with contextlib.suppress(OSError):
                    Path(tmp).unlink(missing_ok=True)
            warnings.warn(f"the FE cache {self.directory} cannot be written "
                          f"({exc.strerror or exc}); the result is kept but not cached",
                          CacheWarning, stacklevel=2)
            return None
        except BaseException:
            if tmp is not None:
                Path(tmp).unlink(missing_ok=True)
            raise
        return path


#: Cycle solvers kept in memory per process (each holds its influence tables, tens of MB):
#: enough for the designs of one command or one sweep task group.
SOLVERS_KEPT = 4
_SOLVERS: dict = {}


def kept_solver(key, build):
    """The cycle solver kept under ``key``, else ``build()``'s, kept (the oldest dropped
    beyond :data:`SOLVERS_KEPT`).

    Parameters
    ----------
    key : hashable
        The drive, its positions, options, cache folder and pitch.
    build : callable
        Makes the solver.

    Returns
    -------
    object
        The solver.
    """
    solver = _SOLVERS.get(key)
    if solver is None:
        solver = build()
        if len(_SOLVERS) >= SOLVERS_KEPT:
            _SOLVERS.pop(next(iter(_SOLVERS)))
        _SOLVERS[key] = solver
    return solver


def release_solvers() -> None:
    """Drop the cycle solvers kept in memory (a search over many designs calls it between
    designs: each holds its influence tables)."""
    _SOLVERS.clear()
