import os
import tempfile
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# the FE disk cache (fem/cache.py) in a fresh folder per test session, not the user's
os.environ["TOOTHFEM_CACHE"] = tempfile.mkdtemp(prefix="toothfem-test-cache-")

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"

if os.environ.get("TOOTHFEM_TEST_WHEEL"):
    # `make test-wheel`: the suite must import the installed wheel, not the checkout
    import toothfem
    import toothfem.fem

    for mod in (toothfem, toothfem.fem):
        if Path(mod.__file__).resolve().is_relative_to(ROOT):
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
