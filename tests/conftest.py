import hashlib
import os
import sys
import tempfile
from importlib import metadata
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"

#: Where the suite keeps its FE disk cache: a path, or "fresh" for a new temporary folder
#: (every table built again, as on a fresh machine; the cold timing).
TEST_CACHE_ENV = "TOOTHFEM_TEST_CACHE"
#: The folders whose Python sources build the FE tables, and the libraries that do so too.
FE_SOURCES = ("geometry", "fem")
FE_LIBRARIES = ("numpy", "scipy", "scikit-fem", "gmsh", "shapely")


def fe_source_hash() -> str:
    """16 hex digits of SHA-256 over every .py file of FE_SOURCES (path and bytes), the
    versions of FE_LIBRARIES and Python's: the name of the suite's cache folder.

    Why a stale cache cannot serve wrong tables: fem/cache.py keys each file by the
    solver's inputs (geometry, material, positions, mesh density, TABLES_VERSION), not by
    the code that turns them into tables; a change to that code under an unchanged key
    would read old tables. Here any change to a file of geometry/ or fem/ (or to a library
    that meshes, factorises or intersects) names another folder, which starts empty; the
    tables of the old sources stay in the old folder, which no later session reads.
    """
    h = hashlib.sha256()
    for folder in FE_SOURCES:
        for path in sorted((ROOT / folder).rglob("*.py")):
            h.update(path.relative_to(ROOT).as_posix().encode() + b"\0")
            h.update(path.read_bytes() + b"\0")
    for lib in FE_LIBRARIES:
        try:
            version = metadata.version(lib)
        except metadata.PackageNotFoundError:
            version = "-"
        h.update(f"{lib}={version}\0".encode())
    h.update(sys.version.encode())
    return h.hexdigest()[:16]


def suite_cache_dir() -> str:
    """The FE disk cache (fem/cache.py) of this session: ``$TOOTHFEM_TEST_CACHE``; a new
    temporary folder if that is "fresh"; else ``<XDG cache>/toothfem-tests/<hash>``, kept
    between sessions so that tables are built once per source state, not once per run.

    Never the user's own cache. pytest-xdist's workers inherit the controller's
    TOOTHFEM_CACHE and keep it (one folder per session, "fresh" included). Workers that
    build the same table at once are safe: DiskCache.store writes a temporary file named
    by its process and renames it over the key's file (os.replace, atomic on one file
    system), so a reader sees a whole file or none, and the last of two equal writes
    wins. Tests about the cache itself (cold against warm, corrupt, unwritable) give their
    solver or $TOOTHFEM_CACHE a folder of their own (tmp_path).
    """
    if os.environ.get("PYTEST_XDIST_WORKER") and os.environ.get("TOOTHFEM_CACHE"):
        return os.environ["TOOTHFEM_CACHE"]           # the controller's choice
    chosen = os.environ.get(TEST_CACHE_ENV, "")
    if chosen == "fresh":
        return tempfile.mkdtemp(prefix="toothfem-test-cache-")
    if chosen:
        return chosen
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = base / "toothfem-tests" / fe_source_hash()
    folder.mkdir(parents=True, exist_ok=True)
    os.utime(folder)                    # in use: not pruned by another checkout's session
    _prune(folder.parent, keep=folder)
    return str(folder)


#: A cache folder of other sources (another checkout or an older commit) that no session
#: has used for this long is removed at the start of a session [days].
PRUNE_AFTER_DAYS = 14


def _prune(parent: Path, keep: Path):
    """Remove the folders of ``parent`` named like a source hash (16 hex digits), other
    than ``keep``, whose last use is more than PRUNE_AFTER_DAYS ago (each holds ~10-20 MB
    of tables that only those sources read)."""
    import re
    import shutil
    import time

    limit = time.time() - PRUNE_AFTER_DAYS * 86400
    for entry in parent.iterdir():
        if (entry != keep and re.fullmatch(r"[0-9a-f]{16}", entry.name) and entry.is_dir()
                and entry.stat().st_mtime < limit):
            shutil.rmtree(entry, ignore_errors=True)


os.environ["TOOTHFEM_CACHE"] = suite_cache_dir()

if os.environ.get("TOOTHFEM_TEST_WHEEL"):
    # `make test-wheel`: the suite must import the installed wheel, not the checkout
    import toothfem
    import toothfem.fem

    # the checkout's own folders (the wheel's environment, .venv-wheel, may sit inside
    # the clone: a path under ROOT alone does not tell them apart)
    for mod, folder in ((toothfem, ROOT / "toothfem"), (toothfem.fem, ROOT / "fem")):
        if Path(mod.__file__).resolve().is_relative_to(folder):
            raise RuntimeError(f"TOOTHFEM_TEST_WHEEL is set but {mod.__name__} is the "
                               f"checkout's ({mod.__file__}), not the installed wheel's")


@pytest.fixture(scope="session")
def cases_dir():
    return CASES


@pytest.fixture(scope="session")
def small_khv():
    """cases/cycloid_khv.toml with 12 pins and 11 lobes (e 2 mm, the output pins' holes
    opened by the eccentricity's change): a drive whose pin errors repeat over 132
    pitches (30 pins: 870), for fast runs of what stretches the period."""
    from toothfem.case import parse_case_text

    text = (CASES / "cycloid_khv.toml").read_text()
    for old, new in (("stated_ratio = 29 ", "stated_ratio = 11 "),
                     ("pin_count = 30\nlobe_count = 29", "pin_count = 12\nlobe_count = 11"),
                     ("eccentricity_mm = 1.2 ", "eccentricity_mm = 2.0 "),
                     ("hole_radius_mm = 6.7 ", "hole_radius_mm = 7.5 ")):
        assert old in text, old
        text = text.replace(old, new)
    return parse_case_text(text)


@pytest.fixture(scope="session")
def fe_cache():
    """The suite's FE disk cache (suite_cache_dir) for the cycle solvers a test builds
    itself (``CycleSolver(..., cache=fe_cache)``; ``drive.cycle_solver`` and the commands
    take it from TOOTHFEM_CACHE). The tables read back are the arrays these sources
    computed when the folder was filled (its name is their hash), so such a test checks
    the same numbers warm or cold; building them is checked in every session that starts
    cold (a changed source, a fresh machine, TOOTHFEM_TEST_CACHE=fresh) and by the tests
    about the cache, which keep their own folder (``DiskCache(tmp_path)``)."""
    from toothfem.fem.cache import DiskCache

    return DiskCache()


def pytest_collection_modifyitems(config, items):
    """The slow tests first, each group in its own order (a stable sort): under
    pytest-xdist (``make test``: ``-n auto --dist worksteal``) the long ones then start
    while the short ones are left to balance the workers, instead of one beginning near
    the end and running alone."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)


def _command_output(argv, argv0="toothfem"):
    """``toothfem ARGV`` in this process (toothfem.cli.main), with ``sys.argv`` as the
    console script has it (report.html shows the command line); what it printed."""
    import contextlib
    import io

    from toothfem import cli

    printed = io.StringIO()
    with pytest.MonkeyPatch.context() as mp, contextlib.redirect_stdout(printed):
        mp.setattr(sys, "argv", [argv0, *map(str, argv)])
        code = cli.main([str(a) for a in argv])
    assert code == 0, (argv, printed.getvalue()[-2000:])
    return printed.getvalue()


@pytest.fixture(scope="session")
def geometry_of(tmp_path_factory):
    """``toothfem geometry CASE --out DIR`` of a shipped case by name, run once per session
    (per xdist worker) for the tests that only read what it wrote: name -> (DIR, what it
    printed). Those tests read the folder and never change it."""
    runs = {}

    def run(name):
        if name not in runs:
            out = tmp_path_factory.mktemp(f"geometry_{name}") / "geo"
            runs[name] = out, _command_output(["geometry", CASES / f"{name}.toml",
                                               "--out", out])
        return runs[name]
    return run


@pytest.fixture(scope="session")
def sine_run(tmp_path_factory):
    """``toothfem run cases/sine_prototype.toml --no-fem --out DIR``, once per session for
    the tests that read its folder (tests/test_cli.py, tests/test_report_html.py): (DIR,
    what it printed), the command line as the installed console script has it."""
    out = tmp_path_factory.mktemp("sine_run") / "run"
    printed = _command_output(["run", CASES / "sine_prototype.toml", "--no-fem", "--out", out],
                              argv0="/usr/bin/toothfem")
    return out, printed
