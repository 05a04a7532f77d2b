import os
import tempfile
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# the FE disk cache (fem/cache.py) in a fresh folder per test session, not the user's
os.environ["TOOTHFEM_CACHE"] = tempfile.mkdtemp(prefix="toothfem-test-cache-")

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"


@pytest.fixture(scope="session")
def cases_dir():
    return CASES
