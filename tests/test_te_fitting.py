"""The TE/hysteresis loop's selection rules on a model whose answer is known (issue 24 item
4): the effect behind the data is added with its value, an exact alias joins its group, a
noise-only control adds nothing, an effect that helps only at its bound is not added."""
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


def test_a_candidate_the_rows_cannot_tell_apart_is_an_alias_whatever_its_bic():
    """A near-alias: 'mirror' is ecc's shape plus 0.01 T, so fitted to data of ecc = 3 its
    rows lie D ~ 3 sigma from ecc's (the weighted distance; BIC about D^2 worse, beyond
    the 6 of the BIC rule): the separation rule (D < 6) names it in ecc's group with its
    own fitted value; 'play' (far: hundreds of sigma) stays out."""
    from toothfem.efficiency.loop.te.problem import RULES

    shapes = {"ecc": SHAPES["ecc"], "mirror": SHAPES["ecc"] + 0.01 * T, "play": SHAPES["play"]}

    def near(options):
        return sum(options.get(k, 0.0) * f for k, f in shapes.items())

    cat = [e for e in catalog() if e.name in ("ecc", "play")] + [TeEffect(
        name="mirror", parameters=(parameter("mirror_um", "um", 0.0, 50.0, 5.0),),
        options=lambda v: {"mirror": v[0]}, summary="mirror", citation="test",
        direct_test="measure mirror")]
    obs = data({}, 4)
    obs = Observations(values=near({"ecc": 3.0}) + (obs.values - model({})),
                       sigma=obs.sigma, group=obs.group, labels=obs.labels, kinds=obs.kinds)
    problem = TeProblem(obs, near, cat)
    loop = problem.run()
    assert loop.added == ("ecc",)
    step = loop.steps[0]
    fits = {n: problem.fit(("ecc",) if n == "ecc" else (n,)) for n in ("ecc", "mirror")}
    d = problem.separation(fits["ecc"], fits["mirror"])
    assert 1.5 < d < RULES.alias_separation
    scored = {row[0]: row[1] for row in step.scored}
    assert scored["mirror"] - scored["ecc"] > 6          # the BIC rule alone would miss it
    assert loop.alias_groups["ecc"] == ("mirror",)
    assert loop.group_values("ecc")["mirror"][0] == pytest.approx(3.0, rel=0.05)


def test_where_the_model_does_not_settle_the_report_says_so():
    """A model that raises (a contact that does not settle) for stiff > 0.5: the fit is
    steered away (ecc still found), and the loop counts and names those evaluations."""
    from toothfem.fem.contact import ContactError

    def fragile(options):
        if options.get("stiff", 0.0) > 0.5:
            raise ContactError("the system did not settle in 50 Newton steps")
        return model(options)

    loop = TeProblem(data({"ecc": 3.0}, 1), fragile, catalog()).run()
    assert loop.added == ("ecc",)
    assert loop.failures and all("did not settle" in f for f in loop.failures)
    note = loop.failure_note()
    assert f"at {len(loop.failures)} of {loop.evaluations} evaluations" in note
    assert loop.to_dict()["model_failures"] == list(loop.failures)
