"""The TE/hysteresis loop's selection rules on a model whose answer is known (issue 24 item
4): the effect behind the data is added with its value, an exact alias joins its group, a
noise-only control adds nothing, an effect that helps only at its bound is not added."""
from __future__ import annotations

import numpy as np
import pytest

from toothfem.efficiency.loop.te.fitting import (Observations, TeEffect, TeProblem,
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


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_effect_behind_the_data_is_added_with_its_alias(seed):
    loop = TeProblem(data({"ecc": 3.0}, seed), model, catalog()).run()
    assert loop.added == ("ecc",)
    assert loop.final.values["ecc"][0] == pytest.approx(3.0, rel=0.05)
    assert loop.baseline.cv_wrmse / loop.final.cv_wrmse > 3
    loop = TeProblem(data({"play": 2.0}, seed), model, catalog()).run()
    (name,) = loop.added
    assert {name, *loop.alias_groups[name]} == {"play", "alias"}     # exact aliases
    assert loop.final.values[name][0] == pytest.approx(2.0, rel=0.1)
    d = loop.to_dict()
    assert [m["direct_test"] for m in d["added"][0]["alias_group"]] == \
        [f"measure {n}" for n in (name, *loop.alias_groups[name])]


@pytest.mark.parametrize("seed", range(10))
def test_noise_alone_adds_nothing(seed):
    loop = TeProblem(data({}, seed), model, catalog()).run()
    assert loop.added == () and "lowers BIC" in loop.stop_reason


def test_an_effect_that_helps_only_at_its_bound_is_not_added():
    loop = TeProblem(data({"stiff": 3.0}, 0), model, catalog(), ).run(["stiff"])
    assert loop.added == ()
    assert loop.steps[0].bounded == ("stiff",) and "bound" in loop.stop_reason
