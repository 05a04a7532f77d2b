"""Atomic output folders: write into a temporary sibling, then rename into place."""
from __future__ import annotations

import contextlib
import shutil
import tempfile
from pathlib import Path


@contextlib.contextmanager
def atomic_dir(out):
    """Yield a temporary folder that becomes ``out`` only if the block succeeds.

    On an exception the temporary folder is removed and ``out`` is left as it was, so a
    failed run never leaves a half-written result folder.
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=out.parent))
        out.replace(old / out.name)
    tmp.replace(out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
