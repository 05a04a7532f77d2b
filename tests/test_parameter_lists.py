"""No parametrised test runs over an empty list.

pytest turns ``@pytest.mark.parametrize("x", [])`` into one test that is *skipped* ("got
empty parameter set"), so a list built by a filter or from another module that comes out
empty would pass the suite silently. Every test module's parametrize lists are checked
here, and the lists that are computed (not written out in the test file) are named once
more with what they are built from.
"""
import importlib
import importlib.util
from collections.abc import Sized
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent


def _parametrize_marks(obj):
    marks = getattr(obj, "pytestmark", [])
    return [m for m in (marks if isinstance(marks, list) else [marks])
            if m.name == "parametrize"]


def _test_functions(module):
    for name, obj in vars(module).items():
        if name.startswith("test") and callable(obj):
            yield f"{module.__name__}.{name}", obj
        if name.startswith("Test") and isinstance(obj, type):
            for meth, fn in vars(obj).items():
                if meth.startswith("test") and callable(fn):
                    yield f"{module.__name__}.{name}.{meth}", fn


def test_no_parametrize_list_is_empty():
    """Every ``pytest.mark.parametrize`` of every test module has at least one case (and is
    a sized collection, so this can tell)."""
    modules = sorted(p.stem for p in TESTS.glob("test_*.py"))
    assert len(modules) > 40, modules         # the glob itself found the suite
    checked, bad = 0, []
    for stem in modules:
        module = importlib.import_module(f"tests.{stem}")
        owners = [(stem, module)] + list(_test_functions(module))
        for where, obj in owners:
            for mark in _parametrize_marks(obj):
                values = mark.args[1] if len(mark.args) > 1 else mark.kwargs["argvalues"]
                checked += 1
                if not isinstance(values, Sized):
                    bad.append(f"{where}: parametrize over a {type(values).__name__}, "
                               "not a list: make it a list so its length can be checked")
                elif len(values) == 0:
                    bad.append(f"{where}: parametrize {mark.args[0]!r} over an empty list")
    assert checked > 80, checked               # the marks were found at all
    assert not bad, "\n".join(bad)


# The lists that are computed rather than written out, each with what it depends on.

def test_field_effects_of_the_catalog_are_found():
    """tests/test_loop.py's FIELD_EFFECTS: the catalog's effects with one case field."""
    from tests.test_loop import FIELD_EFFECTS
    assert len(FIELD_EFFECTS) >= 5, FIELD_EFFECTS


def test_linsolve_backends_are_found():
    """tests/test_linsolve.py's backends: ``linsolve.available_backends()`` (SuperLU is
    always there)."""
    from toothfem.fem import linsolve
    assert "superlu" in linsolve.available_backends()


def _load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _shipped_demo_sets():
    return {p.name.removesuffix("_synthetic.csv")
            for p in (ROOT / "data" / "demo").glob("*_synthetic.csv")}


def _shipped_te_sets():
    return {d.name for d in (ROOT / "data" / "demo" / "te").iterdir()
            if d.is_dir() and not d.name.startswith(("_", "."))}


@pytest.mark.parametrize("script, shipped", [("data/demo/generate.py", _shipped_demo_sets),
                                             ("data/demo/te/generate.py", _shipped_te_sets)])
def test_demo_generators_name_the_shipped_sets(script, shipped):
    """tests/test_loop_demo.py parametrises over data/demo/generate.py's SETS and
    tests/test_te_loop.py loops over data/demo/te/generate.py's SETS (a loop over an empty
    dict would pass): each names exactly the sets shipped beside it, and there are some."""
    gen = _load(ROOT / script, "sets_of_" + script.replace("/", "_").removesuffix(".py"))
    assert set(gen.SETS) == shipped() != set()
