"""Forward selection by BIC and held-out gain, with alias groups and a backward step.

:func:`select` adds effects one at a time while they help:

1. Every candidate not yet added (nor excluded as an earlier one's alias) is fitted with
   the effects already added (:attr:`Rules.scoring`) and scored: its change of BIC and its
   relative cut of the held-out error against the fit so far. It passes when BIC falls by
   at least :attr:`Settings.delta_bic` and the held-out error by at least
   :attr:`Settings.min_cv_gain`, unless a parameter of the fit sits at a bound (its own or
   an earlier effect's, pushed there by the joint fit): the at-bound rule (the data ask for
   more than the effects can physically give, so it is no explanation; such a candidate is
   "bounded").
2. Of the passing candidates the best by :attr:`Rules.rank` is added (of those within
   :attr:`Rules.tie_bic` of its BIC change, the first in the candidates' order).
   Pairs (:attr:`Rules.pairs`): where a bounded candidate's BIC beats every passing one's
   (or none passes), the best such is fitted together with each of the few other
   candidates that explain most alone (:data:`PAIR_PARTNERS`; a warm-up seen by a sensor
   that reads off needs the offset beside it: one at a time, neither explains the data);
   the best pair that passes, with no parameter at a bound, is added instead when
   it beats the single winner's BIC by :attr:`Settings.delta_bic` (the price of the second
   effect) or no single candidate passes.
3. Its aliases (:attr:`Rules.aliases`: by BIC, and by the rows' distance between the fits,
   :attr:`Rules.alias_separation`) form its alias group; the separating-measurement hook,
   where the loop has one, is asked how to tell the group apart.
4. Backward (:attr:`Rules.prune_fraction`): an earlier effect that the new one made
   redundant leaves again. Repeat from 1.

The at-bound rule holds for the model the selection ends with, not only for each candidate:
the joint refit of :attr:`Rules.scoring` "alone" and the backward step's refits are taken
only where no parameter ends at a bound.

It stops when no candidate passes, none is left, :attr:`Settings.max_effects` are in, too
few rows are left for another parameter (:attr:`Settings.min_points` beyond the
parameters), or the steps keep exchanging effects (:data:`STEPS_PER_CANDIDATE`). What was
scored, added, aliased and removed at each step is in its :class:`Step`; the loops phrase it.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import Protocol

from ....errors import ToothfemError
from .fitting import Engine
from .records import Fit

#: Selection steps allowed per candidate: each can be added once and removed once; more
#: steps than that means the selection keeps exchanging effects.
STEPS_PER_CANDIDATE = 2

#: Partners tried with a bounded candidate (:func:`pairs`): the candidates that explain
#: most of the data alone, by BIC (a partner takes the part the bounded one cannot, so it
#: must explain some of it itself). Four keep a step's pairs to four joint fits: a
#: million-row loop tries every effect in bounded pairs within its minute (issue 45); the
#: warm-up read by an offset sensor finds its partner second of them
#: (tests/test_loop_effects.py).
PAIR_PARTNERS = 4

#: Why a selection stopped (:attr:`Selection.stop`).
NO_CANDIDATES = "no candidates"          # none given
ALL_TRIED = "all tried"                  # every candidate added or excluded
MAX_EFFECTS = "max effects"              # Settings.max_effects added
TOO_FEW_ROWS = "too few rows"            # fewer than Settings.min_points rows per spare
NOTHING_PASSES = "nothing passes"        # no candidate passed: the last step adds none
EXCHANGING = "exchanging"                # STEPS_PER_CANDIDATE steps a candidate


@dataclass(frozen=True, kw_only=True)
class Score:
    """One candidate scored at one step, against the step's starting fit."""
    name: str
    fit: Fit | None                # None: its fit failed (``failure`` says why)
    delta_bic: float               # BIC change (inf where it failed)
    cv_gain: float                 # relative cut of the held-out error (nan where it failed)
    passed: bool
    bounded: bool = False          # would pass but for a parameter at its bound
    failure: str = ""
    partner: str = ""              # a pair's second effect (Rules.pairs); "" for one

    @property
    def at_bound(self) -> bool:
        """Whether a parameter of its fit sits at a bound (False where its fit failed)."""
        return self.fit is not None and any_at_bound(self.fit)

    @property
    def cv_wrmse(self) -> float:
        """Its held-out weighted RMS (inf where its fit failed)."""
        return float("inf") if self.fit is None else self.fit.cv_wrmse

    @property
    def bic(self) -> float:
        """Its BIC (inf where its fit failed)."""
        return float("inf") if self.fit is None else self.fit.bic


@dataclass(frozen=True, kw_only=True)
class Step:
    """One selection step: what was scored, what was added (None: nothing passed) with its
    aliases and alias group, and what left again."""
    index: int                     # 1-based
    before: Fit                    # the fit the step started from
    scores: tuple                  # Score, in the candidates' order
    after: Fit                     # the fit after the step
    added: str | None = None
    added_fit: Fit | None = None   # the fit with the added effect, before the backward step
    partner: str = ""              # added together with ``added`` (Rules.pairs)
    pairs: tuple = ()              # the pairs scored (Score with a partner)
    aliased: tuple = ()            # names, in the order of :attr:`Rules.rank`
    removed: tuple = ()            # names the backward step took out again
    group: object | None = None    # the separating-measurement hook's answer


@dataclass(frozen=True, kw_only=True)
class Selection:
    """The outcome of :func:`select`."""
    baseline: Fit
    final: Fit
    steps: tuple
    stop: str                      # one of the stop kinds (module constants)


class Separate(Protocol):
    """The separating-measurement hook: how to tell an alias group apart."""

    def __call__(self, step: int, fits: dict, /) -> object:
        """The loop's record of an alias group.

        Parameters
        ----------
        step : int
            The selection step (1-based).
        fits : dict of str to Fit
            Member name -> its fit (the effects before it plus the member), the added one
            first.

        Returns
        -------
        object
            Kept as :attr:`Step.group`.
        """


class Listener:
    """What a loop shows while the selection runs (each hook does nothing here)."""

    def scoring(self, step: int, names: tuple) -> contextlib.AbstractContextManager:
        """A context around one step's scoring; it yields ``tick(score)``, called after
        each candidate.

        Parameters
        ----------
        step : int
        names : tuple of str
            The candidates scored.

        Returns
        -------
        context manager yielding a callable
        """
        return contextlib.nullcontext(lambda score: None)

    def stepped(self, step: Step) -> None:
        """Told of each step when it is complete.

        Parameters
        ----------
        step : Step
        """


def any_at_bound(fit: Fit) -> bool:
    """Whether any parameter of a fit sits at a bound.

    Parameters
    ----------
    fit : Fit

    Returns
    -------
    bool
    """
    return any(any(flags) for flags in fit.at_bound.values())


def score(engine: Engine, current: Fit, name: str, partner: str = "",
          start: dict | None = None) -> Score:
    """A candidate (or a pair) fitted with the effects of ``current``
    (:attr:`Rules.scoring`) and scored against it (module docstring); a fit the model
    refuses (a ToothfemError) fails.

    Parameters
    ----------
    engine : Engine
    current : Fit
        The fit so far.
    name : str
        The candidate.
    partner : str, optional
        A second candidate fitted together with it (:attr:`Rules.pairs`).
    start : dict, optional
        {name: values} to start the new effects from (a pair: each one's fit alone), not
        screened again.

    Returns
    -------
    Score
    """
    s = engine.settings
    new = (name, partner) if partner else (name,)
    free = None if engine.rules.scoring == "joint" else new
    try:
        f = engine.fit(current.effects + new, {**current.values, **(start or {})},
                       free=free)
    except ToothfemError as exc:
        return Score(name=name, fit=None, delta_bic=float("inf"), cv_gain=float("nan"),
                     passed=False, failure=str(exc), partner=partner)
    dbic = f.bic - current.bic
    gain = 1 - f.cv_wrmse / current.cv_wrmse if current.cv_wrmse > 0 else 0.0
    helps = dbic <= -s.delta_bic * len(new) and gain >= s.min_cv_gain
    at = any_at_bound(f)
    return Score(name=name, fit=f, delta_bic=dbic, cv_gain=gain, passed=helps and not at,
                 bounded=helps and at, partner=partner)


def pairs(engine: Engine, current: Fit, scores, best: Score | None) -> tuple:
    """The pairs tried at a step (:attr:`Rules.pairs`; module docstring, 2): the bounded
    candidate with the lowest BIC, where it beats the best passing one's, with each of the
    :data:`PAIR_PARTNERS` other candidates of the lowest BIC alone.

    Parameters
    ----------
    engine : Engine
    current : Fit
    scores : sequence of Score
        The step's single scores (every candidate of the step).
    best : Score or None
        The single winner.

    Returns
    -------
    tuple of Score
        Every pair scored (empty where none was tried).
    """
    if not engine.rules.pairs:
        return ()
    bounded = [c for c in scores if c.bounded and (best is None or c.bic < best.bic)]
    if not bounded:
        return ()
    lead = min(bounded, key=lambda c: c.bic)
    fitted = sorted((c for c in scores if c.fit is not None and c.name != lead.name),
                    key=lambda c: c.bic)
    return tuple(score(engine, current, lead.name, c.name,
                       start={lead.name: lead.fit.values[lead.name],
                              c.name: c.fit.values[c.name]})
                 for c in fitted[:PAIR_PARTNERS] if lead.fit is not None and c.fit is not None)


def _pair_wins(pair_scores, best: Score | None, delta_bic: float) -> Score | None:
    """The pair to add instead of the single winner, or None."""
    passed = [p for p in pair_scores if p.passed]
    if not passed:
        return None
    top = min(passed, key=lambda p: p.bic)
    if best is None or top.bic <= best.bic - delta_bic:
        return top
    return None


def ranked(scores, rank: str) -> list:
    """The scores in the order of :attr:`Rules.rank`: passing ones first by held-out error,
    or every one by BIC (ties in the candidates' order).

    Parameters
    ----------
    scores : sequence of Score
    rank : {"held_out", "bic"}

    Returns
    -------
    list of Score
    """
    if rank == "held_out":
        return sorted(scores, key=lambda c: (not c.passed, c.cv_wrmse))
    return sorted(scores, key=lambda c: c.bic)


def winner(scores, rules) -> Score | None:
    """The passing candidate to add (module docstring, 2), or None.

    Parameters
    ----------
    scores : sequence of Score
        In the candidates' order.
    rules : Rules

    Returns
    -------
    Score or None
    """
    passed = [c for c in scores if c.passed]
    if not passed:
        return None
    top = ranked(passed, rules.rank)[0]
    return next(c for c in passed if abs(c.delta_bic - top.delta_bic) <= rules.tie_bic)


def aliases(engine: Engine, scores, added: str, fit: Fit, before: Fit) -> tuple:
    """The added candidate's aliases (:attr:`Rules.aliases`), in the order of
    :attr:`Rules.rank`.

    Parameters
    ----------
    engine : Engine
    scores : sequence of Score
        The step's scores.
    added : str
        The added candidate.
    fit : Fit
        The fit with it added (its joint refit where candidates are scored alone).
    before : Fit
        The step's starting fit.

    Returns
    -------
    tuple of Score
    """
    rules, s = engine.rules, engine.settings
    change = fit.bic - before.bic
    out = []
    for c in ranked(scores, rules.rank):
        if c.name == added or c.fit is None:
            continue
        if rules.aliases == "passing":
            alike = c.passed and abs(c.delta_bic - change) < s.alias_bic
        else:
            alike = not c.at_bound and c.fit.bic - fit.bic < s.alias_bic
        if alike or (not c.at_bound and rules.alias_separation > 0
                     and engine.separation(c.fit, fit) < rules.alias_separation):
            out.append(c)
    return tuple(out)


def prune(engine: Engine, fit: Fit, keep, threshold: float) -> tuple:
    """Backward step: drop, one at a time, an effect (other than ``keep``, the one(s) just
    added) whose removal raises BIC by less than ``threshold`` and leaves no parameter at a
    bound.

    Parameters
    ----------
    engine : Engine
    fit : Fit
    keep : str or tuple of str
    threshold : float

    Returns
    -------
    tuple
        (fit, tuple of the names removed).
    """
    keep = (keep,) if isinstance(keep, str) else tuple(keep)
    removed: list[str] = []
    while len(fit.effects) >= 2:
        trials = []
        for name in fit.effects:
            if name in keep:
                continue
            rest = tuple(n for n in fit.effects if n != name)
            f = engine.fit(rest, {n: fit.values[n] for n in rest})
            if not any_at_bound(f):
                trials.append((f.bic - fit.bic, name, f))
        if not trials:
            break
        cost, name, f = min(trials, key=lambda t: t[0])
        if cost >= threshold:
            break
        removed.append(name)
        fit = f
    return fit, tuple(removed)


def _scored(engine: Engine, current: Fit, pool: tuple, index: int,
            listener: Listener) -> tuple:
    """Every candidate of ``pool`` scored, the listener ticked after each."""
    out = []
    with listener.scoring(index, pool) as tick:
        for name in pool:
            out.append(score(engine, current, name))
            tick(out[-1])
    return tuple(out)


def _stop(engine: Engine, candidates: tuple, pool: tuple, current: Fit) -> str:
    """Why no step can be taken from ``current`` ("" when one can)."""
    s = engine.settings
    if not candidates:
        return NO_CANDIDATES
    if not pool:
        return ALL_TRIED
    if len(current.effects) >= s.max_effects:
        return MAX_EFFECTS
    if engine.n - current.n_params - 1 < s.min_points:
        return TOO_FEW_ROWS
    return ""


def select(engine: Engine, candidates, *, base: Fit | None = None,
           separate: Separate | None = None, listener: Listener | None = None) -> Selection:
    """Forward selection with alias groups and the backward step (module docstring).

    Parameters
    ----------
    engine : Engine
        The observations, effects, model and rules.
    candidates : sequence of str
        The effects that may be added, in the order that breaks ties.
    base : Fit, optional
        The fit of no effect (default: fitted here).
    separate : Separate, optional
        The separating-measurement hook, asked for each alias group.
    listener : Listener, optional
        Told of the scoring and of each step.

    Returns
    -------
    Selection
    """
    rules = engine.rules
    listener = listener or Listener()
    candidates = tuple(candidates)
    base = engine.fit(()) if base is None else base
    current = base
    steps: list[Step] = []
    excluded: set[str] = set()
    while True:
        pool = tuple(c for c in candidates if c not in current.effects and c not in excluded)
        stop = _stop(engine, candidates, pool, current)
        if stop:
            break
        index = len(steps) + 1
        scores = _scored(engine, current, pool, index, listener)
        best = winner(scores, rules)
        tried = pairs(engine, current, scores, best)
        pair = _pair_wins(tried, best, engine.settings.delta_bic)
        best = pair or best
        if best is None:
            steps.append(Step(index=index, before=current, scores=scores, after=current,
                              pairs=tried))
            listener.stepped(steps[-1])
            stop = NOTHING_PASSES
            break
        fit = best.fit
        assert fit is not None          # it passed
        if rules.scoring == "alone" and current.effects:
            joint = engine.fit(fit.effects, fit.values)      # every parameter refitted
            if joint.bic <= fit.bic and not any_at_bound(joint):
                fit = joint
        alike = () if pair else aliases(engine, scores, best.name, fit, current)
        group = None
        if alike and separate is not None:
            group = separate(index, {best.name: fit, **{c.name: c.fit for c in alike}})
        after, removed = fit, ()
        if rules.prune_fraction is not None:
            after, removed = prune(engine, fit, (best.name, best.partner),
                                   rules.prune_fraction * engine.settings.delta_bic)
        if rules.exclude_aliases:
            excluded.update(c.name for c in alike)
        steps.append(Step(index=index, before=current, scores=scores, after=after,
                          added=best.name, added_fit=fit, partner=best.partner, pairs=tried,
                          aliased=tuple(c.name for c in alike), removed=removed, group=group))
        listener.stepped(steps[-1])
        current = after
        if len(steps) >= STEPS_PER_CANDIDATE * len(candidates):
            stop = EXCHANGING
            break
    return Selection(baseline=base, final=current, steps=tuple(steps), stop=stop)

