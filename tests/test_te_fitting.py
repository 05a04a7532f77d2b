"""The TE/hysteresis loop's adapter of the fitting engine (efficiency/loop/te/problem.py) on a
model whose answer is known: its report record (the alias group with each member's fitted
values and direct test, the steps' tables, the stop in words), its model evaluation (one per
set of options; a wall where the model does not settle, counted and named). The engine's
rules themselves are tests/test_engine.py's."""
from __future__ import annotations

import numpy as np
import pytest

from toothfem.efficiency.loop.te.problem import (Observations, TeEffect, TeProblem,
                                                 parameter)

T = np.repeat(np.linspace(0.1, 1.0, 10), 6)          # 10 torque levels x 6 rows
X = np.tile(np.linspace(0, 1, 6), 10)
SHAPES = {"play": np.exp(-5 * T), "ecc": np.sin(2 * np.pi * X) * T,
          "alias": np.exp(-5 * T), "stiff": T * X}


def catalog():
    def eff(name, hi=50.0):
        return TeEffect(name=name, parameters=(parameter(f"{name}_um", "um", 0.0, hi, 5.0,
                                                         starts=(5.0, 20.0)),),
                        options=lambda v, n=name: {n: v[0]}, summary=name, citation="test",
                        direct_test=f"measure {name}")
    return [eff("play"), eff("ecc"), eff("alias"), eff("stiff", hi=1.0)]


def model(options):
    return sum(options.get(k, 0.0) * f for k, f in SHAPES.items())


def data(truth, seed, sigma=0.05):
    rng = np.random.default_rng(seed)
    y = model(truth) + rng.normal(0, sigma, T.size)
    return Observations(values=y, sigma=np.full(T.size, sigma), group=np.round(T, 6),
                        labels=tuple(f"row {i}" for i in range(T.size)),
                        kinds=("twist_arcmin",) * T.size)


def test_the_report_names_the_alias_group_with_values_and_direct_tests():
    """'play' behind the data, 'alias' its exact twin: the one added names the other with
    its fitted value and the measurement that tells each apart; the steps' tables list the
    candidates by BIC; the loop stops in words when nothing more helps."""
    loop = TeProblem(data({"play": 2.0}, 1), model, catalog()).run()
    (name,) = loop.added
    (other,) = loop.alias_groups[name]
    assert {name, other} == {"play", "alias"}
    assert loop.final.values[name][0] == pytest.approx(2.0, rel=0.1)
    assert loop.group_values(name)[other][0] == pytest.approx(2.0, rel=0.1)
    d = loop.to_dict()
    assert [m["direct_test"] for m in d["added"][0]["alias_group"]] == \
        [f"measure {n}" for n in (name, other)]
    assert d["added"][0]["parameters"][f"{name}_um"]["bounds"] == [0.0, 50.0]
    first, last = d["steps"]
    bics = [c["bic"] for c in first["candidates"]]
    assert bics == sorted(bics) and first["added"] == name
    assert last["added"] is None and "alias" not in {c["name"] for c in last["candidates"]}
    assert "lowers BIC" in loop.stop_reason and d["held_out_error_cut"] > 3
    assert d["rows"] == T.size and d["model_failures"] == []


def test_an_effect_that_helps_only_at_its_bound_is_said_so():
    loop = TeProblem(data({"stiff": 3.0}, 0), model, catalog()).run(["stiff"])
    assert loop.added == () and loop.steps[0].bounded == ("stiff",)
    assert "only at a bound" in loop.stop_reason


def test_where_the_model_does_not_settle_the_report_says_so():
    """A model that raises (a contact that does not settle) for stiff > 0.5: a wall of
    FAILED_SIGMA on every row steers the fit away (ecc still found), and the loop counts
    and names those evaluations; each set of options is evaluated once."""
    from toothfem.fem.contact import ContactError

    calls = []

    def fragile(options):
        calls.append(tuple(sorted(options.items())))
        if options.get("stiff", 0.0) > 0.5:
            raise ContactError("the system did not settle in 50 Newton steps")
        return model(options)

    loop = TeProblem(data({"ecc": 3.0}, 1), fragile, catalog()).run()
    assert loop.added == ("ecc",)
    assert loop.failures and all("did not settle" in f for f in loop.failures)
    note = loop.failure_note()
    assert f"at {len(loop.failures)} of {loop.evaluations} evaluations" in note
    assert loop.to_dict()["model_failures"] == list(loop.failures)
    assert len(calls) == len(set(calls)) == loop.evaluations
