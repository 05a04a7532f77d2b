"""Property test (issue 14, item 2): random values through `check`, then the analyses on
every case it accepts. Zero tracebacks, zero NaN/inf in the outputs, every refusal one line
naming a case key, and nothing `check` accepts refused later in other terms (an internal
variable).

Hypothesis runs derandomized (a fixed sequence of examples, the same in CI as on a laptop);
``TOOTHFEM_FUZZ_EXAMPLES`` raises the number of examples for a longer local search.
"""
import copy
import dataclasses
import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from toothfem import CaseError, parse_case
from toothfem.case import _NESTED, _SECTIONS, MeasuredPoint
from toothfem.derived import derived
from toothfem.efficiency import evaluate, operating_point
from toothfem.errors import ToothfemError

try:
    import tomllib
except ImportError:  # pragma: no cover
    import tomli as tomllib

from tests.conftest import CASES

BASES = {name: tomllib.loads((CASES / f"{name}.toml").read_text())
         for name in ("cycloid_pinhousing", "sine_prototype", "rv40e")}


def _leaves(d, path=()):
    """Dotted paths of the numeric leaves of a case mapping (not [published])."""
    for k, v in d.items():
        if k in ("published", "measured", "stated_ratio"):
            continue
        if isinstance(v, dict):
            yield from _leaves(v, path + (k,))
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            yield path + (k,)


LEAVES = {name: sorted(_leaves(raw)) for name, raw in BASES.items()}


def _case_keys():
    """Every name a refusal may use for a key: section.key, [section], case.*."""
    keys = {"case.name", "case.drive", "case.source", "case.stated_ratio", "[case]"}
    for sec, cls in _SECTIONS.items():
        keys.add(f"[{sec}]")
        keys.update(f"{sec}.{f.name}" for f in dataclasses.fields(cls))
        for sub, scls in _NESTED.get(cls, {}).items():
            keys.update(f"{sec}.{sub}.{f.name}" for f in dataclasses.fields(scls))
    keys.update(f"measured[0].{f.name}" for f in dataclasses.fields(MeasuredPoint))
    return keys


CASE_KEYS = _case_keys()

_WRONG_TYPES = st.sampled_from(["1.0", "abc", True, [1.0], {"x": 1.0}])


@st.composite
def mutated_case(draw):
    """A seed case with one to three numeric keys changed: a scale of the value (mostly
    plausible), any float (NaN, inf, 1e308 ...), an integer, or a wrong type."""
    name = draw(st.sampled_from(sorted(BASES)))
    raw = copy.deepcopy(BASES[name])
    raw["case"].pop("stated_ratio", None)         # tooth numbers may change
    paths = draw(st.lists(st.sampled_from(LEAVES[name]), min_size=1, max_size=3,
                          unique=True))
    for path in paths:
        node = raw
        for k in path[:-1]:
            node = node[k]
        old = node[path[-1]]
        new = draw(st.one_of(
            st.floats(0.2, 5.0).map(lambda f, old=old: old * f if isinstance(old, float)
                                    else max(1, round(old * f))),
            st.floats(allow_nan=True, allow_infinity=True),
            st.integers(-10, 10**7),
            _WRONG_TYPES))
        node[path[-1]] = new
    return name, raw


def _finite(x) -> bool:
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, dict):
        return all(_finite(v) for v in x.values())
    return True


def _accepted_or_refused(raw):
    """The Case, or None after checking the refusal is one line naming a case key."""
    try:
        return parse_case(raw)
    except CaseError as exc:
        msg = str(exc)
        assert "\n" not in msg
        assert any(k in msg for k in CASE_KEYS), f"refusal names no case key: {msg}"
        return None


EXAMPLES = int(os.environ.get("TOOTHFEM_FUZZ_EXAMPLES", "30"))
CI = settings(derandomize=True, database=None, deadline=None, max_examples=EXAMPLES,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@CI
@given(mutated_case())
def test_check_then_every_analytic_analysis(drawn):
    """What `check` accepts, `check` prints finite and `efficiency` evaluates in (0, 1]."""
    _, raw = drawn
    case = _accepted_or_refused(raw)
    if case is None:
        return
    assert _finite(derived(case))
    try:
        speed, torque = operating_point(case)
        e = evaluate(case, speed, torque)
    except ToothfemError as exc:
        # the physics may still say no (the declared input cannot overcome the no-load
        # losses), but in the case's own terms: a refusal naming a case key, one line
        msg = str(exc)
        assert "\n" not in msg and any(k in msg for k in CASE_KEYS), \
            f"check accepted a case that efficiency refuses naming no case key: {msg}"
        return
    assert 0 < float(e.efficiency[0]) <= 1
    for name, loss in e.losses_W.items():
        assert np.all(np.isfinite(loss)) and np.all(np.asarray(loss) >= 0), name


@pytest.mark.slow
@settings(CI, max_examples=max(4, EXAMPLES // 6))
@given(drawn=mutated_case())
def test_check_then_a_small_fe_run(drawn, tmp_path_factory):
    """The FE contact (cycle mode, two positions, no stress field) on accepted cycloid and
    sine cases: finite forces and pressures, or one line naming a key."""
    from toothfem import cli

    name, raw = drawn
    case = _accepted_or_refused(raw)
    if case is None or (case.cycloid is None and case.drive != "sine"):
        return
    path = tmp_path_factory.mktemp("fe") / "case.toml"
    path.write_text(_dumps(raw))
    out = path.parent / "out"
    code = cli.main(["contact", str(path), "--positions", "2", "--field", "none",
                     "--out", str(out)])
    assert code == 0
    import json
    summary = json.loads((out / "summary.json").read_text())
    assert _finite(summary) and summary["max_force_N"] > 0


def _dumps(raw) -> str:
    """TOML text of a case mapping (tables of scalars, one level of nesting)."""
    import json

    def value(v):
        return json.dumps(v) if not isinstance(v, float) or math.isfinite(v) else \
            ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))

    lines = []
    for sec, body in raw.items():
        if sec == "measured":
            for m in body:
                lines.append("[[measured]]")
                lines += [f"{k} = {value(v)}" for k, v in m.items()]
            continue
        lines.append(f"[{sec}]")
        subs = {k: v for k, v in body.items() if isinstance(v, dict)}
        lines += [f"{k} = {value(v)}" for k, v in body.items() if k not in subs]
        for k, v in subs.items():
            lines.append(f"[{sec}.{k}]")
            lines += [f"{kk} = {value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"
