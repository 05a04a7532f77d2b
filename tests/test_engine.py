"""The fitting engine (efficiency/loop/engine/) on millisecond surrogate models whose answer
is known: the effect behind the data is added with its value, noise alone adds nothing, an
exact alias joins the added one's group (and the separating-measurement hook is asked about
it), a near alias is grouped by the rows' distance, an effect that helps only at its bound
is not added, an effect made redundant leaves again, the k-fold held-out error is what
refits on each fold give, and a model that fails is a failed candidate.

Each selection test runs under the rules of both loops (the efficiency loop's
``problem.EFFICIENCY_RULES`` and the TE loop's ``te.problem.TE_RULES``), the thresholds of
``Settings()``. The rows: 10 fold groups (levels t) x 6 rows (x), each effect a shape
times its parameter, noise sigma 0.05 (the signals are 60 sigma: the tests check the
rules, not the limit of detection).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from toothfem.efficiency.loop import engine as en
from toothfem.efficiency.loop.problem import EFFICIENCY_RULES as EFFICIENCY
from toothfem.efficiency.loop.settings import Settings
from toothfem.efficiency.loop.te.problem import TE_RULES as TE
from toothfem.errors import ToothfemError

T = np.repeat(np.linspace(0.1, 1.0, 10), 6)          # 10 fold groups x 6 rows
X = np.tile(np.linspace(0, 1, 6), 10)
SIGMA = 0.05
SHAPES = {"play": np.exp(-5 * T), "ecc": np.sin(2 * np.pi * X) * T,
          "alias": np.exp(-5 * T), "stiff": T * X, "slope": T}
RULES = {"efficiency": EFFICIENCY, "te": TE}
SETTINGS = Settings()


@dataclass(frozen=True)
class Rows:
    """The engine's Observations."""
    values: np.ndarray
    weight: np.ndarray
    group: np.ndarray


@dataclass(frozen=True)
class Eff:
    """The engine's Effect."""
    name: str
    parameters: tuple


class Linear:
    """The engine's Model: the sum of each effect's shape times its value; ``fails(names,
    values)`` (optional) says where it raises as a model that does not settle."""

    def __init__(self, shapes=SHAPES, fails=None):
        self.shapes, self.fails, self.evaluations = shapes, fails, 0

    def predict(self, names, values):
        self.evaluations += 1
        if self.fails is not None and self.fails(names, values):
            raise ToothfemError("the system did not settle in 50 Newton steps")
        return sum((v * self.shapes[n] for n, v in zip(names, values)), np.zeros(T.size))


def effect(name, lo=0.0, hi=50.0):
    return Eff(name, (en.parameter(f"{name}_um", "um", lo, hi, 5.0, starts=(5.0, 20.0)),))


CATALOG = (effect("play"), effect("ecc"), effect("alias"), effect("stiff", hi=1.0))


def rows(truth: dict, seed: int, shapes=SHAPES) -> Rows:
    y = Linear(shapes).predict(tuple(truth), tuple(truth.values()))
    y = y + np.random.default_rng(seed).normal(0, SIGMA, T.size)
    return Rows(values=y, weight=np.full(T.size, 1 / SIGMA), group=np.round(T, 6))


def engine(obs, rules, catalog=CATALOG, model=None, settings=SETTINGS):
    return en.Engine(obs, catalog, model or Linear(), rules=RULES[rules], settings=settings)


# ---------------------------------------------------------------------------------------
# Selection


@pytest.mark.parametrize("rules", RULES)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_effect_behind_the_data_is_added_with_its_value(rules, seed):
    e = engine(rows({"ecc": 3.0}, seed), rules)
    sel = en.select(e, [c.name for c in CATALOG])
    assert sel.final.effects == ("ecc",) and sel.stop == en.NOTHING_PASSES
    assert sel.final.values["ecc"][0] == pytest.approx(3.0, rel=0.05)
    assert sel.baseline.cv_wrmse / sel.final.cv_wrmse > 3
    (step, last) = sel.steps
    assert step.added == "ecc" and step.aliased == () and last.added is None
    assert all(not c.passed for c in last.scores)
    # the standard error is the noise's: sigma / |shape| (weighted, 1 per row), ~1 %
    se = 1 / np.linalg.norm(SHAPES["ecc"] / SIGMA)
    assert sel.final.stderr["ecc"][0] == pytest.approx(se, rel=0.2)


@pytest.mark.parametrize("rules", RULES)
def test_two_effects_are_added(rules):
    e = engine(rows({"ecc": 3.0, "stiff": 0.5}, 1), rules)
    sel = en.select(e, ["play", "ecc", "stiff"])
    assert set(sel.final.effects) == {"ecc", "stiff"}
    assert sel.final.values["stiff"][0] == pytest.approx(0.5, rel=0.1)


@pytest.mark.parametrize("rules", RULES)
@pytest.mark.parametrize("seed", range(10))
def test_noise_alone_adds_nothing(rules, seed):
    sel = en.select(engine(rows({}, seed), rules), [c.name for c in CATALOG])
    assert sel.final.effects == () and sel.stop == en.NOTHING_PASSES
    (step,) = sel.steps
    assert max(c.delta_bic for c in step.scores) > -SETTINGS.delta_bic or \
        max(c.cv_gain for c in step.scores) < SETTINGS.min_cv_gain


@pytest.mark.parametrize("rules", RULES)
def test_an_exact_alias_is_grouped_and_the_hook_asked(rules):
    """'play' and 'alias' have one shape: the first in the candidates' order is added
    (their BIC ties), the other is its alias, and the separating-measurement hook is asked
    about the two, the added one first, with their fits."""
    asked = []

    def separate(step, fits):
        asked.append((step, {n: f.values[n] for n, f in fits.items()}))
        return "how to tell them apart"

    e = engine(rows({"play": 2.0}, 1), rules)
    sel = en.select(e, ["alias", "ecc", "play"], separate=separate)
    step = sel.steps[0]
    assert step.added == "alias" and step.aliased == ("play",)
    assert sel.final.values["alias"][0] == pytest.approx(2.0, rel=0.1)
    assert step.group == "how to tell them apart"
    ((index, values),) = asked
    assert index == 1 and list(values) == ["alias", "play"]
    assert values["play"] == pytest.approx(values["alias"])
    # the efficiency loop keeps an alias a candidate, the TE loop leaves it out
    later = {c.name for s in sel.steps[1:] for c in s.scores}
    assert ("play" in later) == (not RULES[rules].exclude_aliases)


@pytest.mark.parametrize("rules", RULES)
def test_a_near_alias_by_the_rows_distance(rules):
    """'mirror' is ecc's shape plus 0.01 t: fitted to data of ecc = 3 its rows lie D ~ 3
    sigma from ecc's (the weighted distance), and its BIC is about D^2 worse, beyond
    Settings.alias_bic. The TE loop's rows-distance rule (alias_separation 6) names it in
    ecc's group with its own fitted value; the efficiency loop's (BIC only) does not; 'play'
    (hundreds of sigma away) is no alias."""
    shapes = {**SHAPES, "mirror": SHAPES["ecc"] + 0.01 * T}
    obs = rows({"ecc": 3.0}, 4, shapes)
    catalog = (effect("ecc"), effect("mirror"), effect("play"))
    e = engine(obs, rules, catalog, Linear(shapes))
    sel = en.select(e, ["ecc", "mirror", "play"])
    step = sel.steps[0]
    assert step.added == "ecc"
    scores = {c.name: c for c in step.scores}
    d = e.separation(scores["mirror"].fit, step.added_fit)
    assert 1.5 < d < TE.alias_separation
    assert scores["mirror"].fit.bic - step.added_fit.bic > SETTINGS.alias_bic
    assert step.aliased == (("mirror",) if RULES[rules].alias_separation else ())
    assert scores["mirror"].fit.values["mirror"][0] == pytest.approx(3.0, rel=0.05)


@pytest.mark.parametrize("rules", RULES)
def test_an_effect_that_helps_only_at_its_bound_is_not_added(rules):
    """stiff = 3 where its bound is 1: it would pass, but only at its bound (the at-bound
    rule): not added, the step names it bounded."""
    e = engine(rows({"stiff": 3.0}, 0), rules)
    sel = en.select(e, ["stiff"])
    assert sel.final.effects == () and sel.stop == en.NOTHING_PASSES
    (c,) = sel.steps[0].scores
    assert c.bounded and not c.passed and c.at_bound
    assert c.fit.values["stiff"][0] == pytest.approx(1.0, abs=1e-3)
    assert c.fit.at_bound["stiff"] == (True,)


@pytest.mark.parametrize("rules", RULES)
def test_the_final_model_has_no_parameter_at_a_bound(rules):
    """cap (bound 1) is 0.6 and the rest is ecc's shape, offered only as neg = ecc - cap: a
    fit of neg with cap free takes neg = 1 and cap to its bound 1.6 -> 1. The at-bound rule
    holds for the model the selection ends with: the efficiency loop (joint scoring) calls
    neg bounded and keeps cap alone; the TE loop (scored alone, cap held at 0.6) adds neg
    but refuses the joint refit that would put cap at its bound."""
    shapes = {**SHAPES, "cap": T, "neg": SHAPES["ecc"] - T}
    obs = rows({"cap": 0.6, "ecc": 1.0}, 1, {**SHAPES, "cap": T})
    e = engine(obs, rules, (effect("cap", hi=1.0), effect("neg")), Linear(shapes))
    sel = en.select(e, ["cap", "neg"])
    assert not en.any_at_bound(sel.final)
    assert sel.final.values["cap"][0] == pytest.approx(0.6, abs=0.05)
    if rules == "efficiency":
        assert sel.final.effects == ("cap",)
        (neg,) = sel.steps[1].scores
        assert neg.bounded and neg.fit.at_bound["cap"] == (True,)
    else:
        assert sel.final.effects == ("cap", "neg")


@pytest.mark.parametrize("rules", RULES)
def test_a_pair_is_added_where_one_alone_stops_at_its_bound(rules):
    """cap (bound 1) is 0.95 and partner (cap's shape + 6 ecc's) 0.08: alone, cap wants
    1.05 and stops at its bound, though its bounded fit beats partner's; the efficiency loop
    (Rules.pairs) fits cap with each other candidate and adds cap with partner in one step,
    each to its true value; the TE loop tries no pair (each is a run of system solves)."""
    shapes = {**SHAPES, "cap": T, "partner": T + 6 * SHAPES["ecc"]}
    obs = rows({"cap": 0.95, "partner": 0.08}, 1, shapes)
    catalog = (effect("cap", hi=1.0), effect("partner"), effect("play"))
    e = engine(obs, rules, catalog, Linear(shapes))
    sel = en.select(e, ["cap", "partner", "play"])
    first = sel.steps[0]
    scores = {c.name: c for c in first.scores}
    assert scores["cap"].bounded and scores["cap"].bic < scores["partner"].bic
    assert set(sel.final.effects) == {"cap", "partner"}
    assert sel.final.values["cap"][0] == pytest.approx(0.95, abs=0.02)
    assert sel.final.values["partner"][0] == pytest.approx(0.08, abs=0.01)
    if rules == "efficiency":
        assert (first.added, first.partner) == ("cap", "partner")
        assert {p.partner for p in first.pairs} == {"partner", "play"}     # both (< 4)
    else:
        assert first.pairs == () and first.partner == ""


def test_an_effect_made_redundant_leaves_again():
    """'both' is play + slope + x: alone it explains data of play + slope best and is added
    first; slope and then play follow, each cutting what 'both' leaves, and with both of
    them in, 'both' only adds its x: the efficiency loop's backward step removes it again;
    the TE loop (no backward step, candidates scored alone) stops at 'both'."""
    shapes = {**SHAPES, "both": SHAPES["play"] + SHAPES["slope"] + X}
    obs = rows({"play": 1.0, "slope": 1.0}, 1, shapes)
    catalog = (effect("both"), effect("play"), effect("slope"))
    e = engine(obs, "efficiency", catalog, Linear(shapes))
    sel = en.select(e, ["both", "play", "slope"])
    assert [(s.added, s.removed) for s in sel.steps] == [
        ("both", ()), ("slope", ()), ("play", ("both",)), (None, ())]
    assert sel.final.effects == ("slope", "play")
    assert sel.final.values["play"][0] == pytest.approx(1.0, rel=0.05)
    kept = en.select(engine(obs, "te", catalog, Linear(shapes)), ["both", "play", "slope"])
    assert kept.final.effects == ("both",)


@pytest.mark.parametrize("rules", RULES)
def test_the_selection_stops_at_the_most_effects_and_the_fewest_rows(rules):
    obs = rows({"ecc": 3.0, "stiff": 0.5, "play": 2.0}, 1)
    sel = en.select(engine(obs, rules, settings=Settings(max_effects=1)), ["ecc", "stiff"])
    assert len(sel.final.effects) == 1 and sel.stop == en.MAX_EFFECTS
    few = Settings(min_points=59)    # 60 rows: after one parameter, 60 - 1 - 1 < 59 spare
    sel = en.select(engine(obs, rules, settings=few), ["ecc", "stiff", "play"])
    assert len(sel.final.effects) == 1 and sel.stop == en.TOO_FEW_ROWS
    sel = en.select(engine(obs, rules), [])
    assert sel.steps == () and sel.stop == en.NO_CANDIDATES


@pytest.mark.parametrize("rules", RULES)
def test_a_failing_model_is_a_failed_candidate(rules):
    """A model that raises (a contact that does not settle) wherever 'play' is set: the
    candidate fails with the model's words and the selection goes on (ecc is added)."""
    model = Linear(fails=lambda names, values: "play" in names)
    sel = en.select(engine(rows({"ecc": 3.0}, 1), rules, model=model), ["play", "ecc"])
    assert sel.final.effects == ("ecc",)
    failed = next(c for c in sel.steps[0].scores if c.name == "play")
    assert failed.fit is None and not failed.passed and "did not settle" in failed.failure
    assert failed.delta_bic == float("inf") and failed.cv_wrmse == float("inf")


# ---------------------------------------------------------------------------------------
# Fits, folds, the held-out error


def test_the_held_out_error_is_the_folds_refits():
    """On a model linear in its parameters, away from the bounds, the one-step held-out
    error of a fit equals the k-fold error of full refits, and both equal ordinary least
    squares on each fold's training rows; the folds hold out whole groups."""
    obs = rows({"ecc": 3.0, "stiff": 0.5}, 2)
    e = engine(obs, "efficiency")
    assert e.n_folds == SETTINGS.folds
    for g in np.unique(obs.group):
        assert len(set(e.fold[obs.group == g])) == 1          # a group in one fold
    assert sorted(np.bincount(e.fold)) == [12] * 5               # 2 groups of 6 per fold
    fit = e.fit(("ecc", "stiff"))
    held = e.held_out(fit)
    a = np.stack([SHAPES["ecc"], SHAPES["stiff"]], axis=1)
    want = np.empty(T.size)
    for f in range(e.n_folds):
        test = e.fold == f
        x = np.linalg.lstsq(a[~test], obs.values[~test], rcond=None)[0]
        want[test] = obs.values[test] - a[test] @ x
    np.testing.assert_allclose(held.residual, want, atol=1e-6)
    np.testing.assert_allclose(fit.cv_residual, want / SIGMA, atol=1e-4)
    assert held.folds == 5 and held.rmse == pytest.approx(np.sqrt(np.mean(want ** 2)))
    # BIC by its definition
    n = T.size
    assert fit.bic == pytest.approx(n * np.log(fit.wrss / n) + 2 * np.log(n))


def test_folds_of_both_schemes_are_balanced_and_seeded():
    group = np.repeat(np.arange(7), 3)
    for scheme in ("deal", "label"):
        fold, k = en.assign_folds(group, 5, 0, scheme)
        assert k == 5 and sorted(np.bincount(fold[::3])) == [1, 1, 1, 2, 2]
        np.testing.assert_array_equal(fold, en.assign_folds(group, 5, 0, scheme)[0])
    assert en.assign_folds(np.arange(3), 5, 0, "deal")[1] == 3
    assert en.assign_folds(np.zeros(4), 5, 0, "label")[1] == en.MIN_FOLDS


def test_starts_screened_or_restarted_where_a_fit_ends_at_a_bound():
    """A model (v - 1)^2 x shape fitted to data of v = 2.5: from the first start, 0.3,
    the fit runs into the lower bound (a local minimum there); "restart" runs again from
    the next start and finds 2.5, "screen" starts from the better start at once."""
    shape = np.exp(-T)

    class Wavy:
        def predict(self, names, values):
            v = values[0] if names else 0.0
            return (v - 1) ** 2 * shape

    obs = Rows(values=2.25 * shape, weight=np.ones(T.size), group=np.round(T, 6))
    eff = Eff("w", (en.parameter("w", "-", 0.0, 3.0, 1.0, starts=(0.3, 2.8)),))
    for rules in ("efficiency", "te"):
        fit = engine(obs, rules, (eff,), Wavy()).fit(("w",))
        assert fit.values["w"][0] == pytest.approx(2.5, rel=1e-3), rules
        assert fit.at_bound["w"] == (False,)


def test_a_held_parameter_stays_and_counts_in_bic():
    obs = rows({"ecc": 3.0, "stiff": 0.5}, 1)
    e = engine(obs, "te")
    fit = e.fit(("stiff", "ecc"), {"stiff": (0.25,)}, free=("ecc",))
    assert fit.values["stiff"] == (0.25,) and fit.n_params == 2
    assert np.isnan(fit.stderr["stiff"][0])                 # held: no standard error
    joint = e.fit(("stiff", "ecc"), fit.values)
    assert joint.values["stiff"][0] == pytest.approx(0.5, rel=0.1) and joint.bic < fit.bic


def test_the_at_bound_rule():
    p = en.parameter("c", "-", 0.0, 1.0, 0.5)
    assert en.at_bound(0.0, p) and en.at_bound(1.0 - 0.4 * en.AT_BOUND_REL, p)
    assert not en.at_bound(2 * en.AT_BOUND_REL * 0.5, p) and not en.at_bound(0.5, p)


def test_rules_refuse_what_the_engine_does_not_know():
    with pytest.raises(ValueError, match="rank"):
        en.Rules(**{**EFFICIENCY.__dict__, "rank": "aic"})
