"""The efficiency loop's side of the fitting engine (:mod:`.engine`): measured efficiencies
as the engine's rows, the catalog's effects bound to the case and data, the model with
those effects at the measured points (:class:`Problem`), and the rules it fits and selects
by (:data:`EFFICIENCY_RULES`).

Weights: the residual r = eta_measured - eta_model at every point is weighted by 1/sigma
where the data give an uncertainty (the rig's torque sensors), else unweighted; the weights
are relative (mean square 1), so the weighted RMS is in efficiency units. Each point is its
own fold group.

Effects whose loss is proportional to their parameter (drag, bearing and output-pin friction,
churning) are evaluated once at a reference value and scaled (effects.predict's cache), so
fitting them costs almost no model evaluations, and the held-out error of a candidate (one
bounded Gauss-Newton step from its all-data fit for each fold) is exact for them and close
for the others. The held-out errors reported before and after the loop are from full refits
on each fold's training points (:meth:`.engine.Engine.held_out`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..evaluation import Efficiency
from ..mesh_table import LoadsMemo
from . import effects as fx
from .engine import Engine, Rules
from .settings import Settings

#: The efficiency loop's rules (:class:`.engine.Rules`), the reason beside each.
EFFICIENCY_RULES = Rules(
    fd_step=1e-3,           # on parameters scaled by their typical value: the model is
                            # smooth there (the clearance tables are PCHIP-interpolated)
    fit_tol=1e-6,           # the parameters' standard errors are percents, so a relative
                            # change of 1e-6 is converged; 1e-10 took 28 % more model
                            # evaluations for the same values to 4 digits (four scenarios
                            # of tests/test_loop*.py)
    starts="screen",        # a start costs one evaluation (a linear effect's none), so
                            # each is tried and the fit runs once, from the best
    folds="deal",           # each point its own group, dealt round the folds
    scoring="joint",        # a candidate's fit costs few evaluations: every parameter is
                            # refitted with it, and a later effect may take over an earlier
                            # one's share (then the backward step removes it)
    rank="held_out",        # the loop's aim: the error at points it did not fit
    tie_bic=0.1,            # a likelihood ratio of 1.05: no preference; exact aliases (a
                            # drag on the input and the input meter's offset) tie up to the
                            # fit's rounding, near ones such as the two torque meters'
                            # offsets by about 1e-3: the one first in the catalog, the
                            # reducer's before the rig's, is added
    aliases="passing",      # the candidates that pass as well, BIC within
                            # Settings.alias_bic either side
    alias_separation=0.0,   # none by the rows' distance: each group's search for a
                            # separating operating point (separation.py) says which pairs
                            # no point separates
    exclude_aliases=False,  # an alias stays a candidate: the points it was aliased at may
                            # not hold once another effect is in
    prune_fraction=0.5,     # below the entry threshold, so an effect just added does not
                            # leave at once
    pairs=True,             # a pair costs one joint fit of a few evaluations; a warm-up the
                            # log does not show, read by a sensor that is also off, is met
                            # only by the two together (tests/test_loop_effects.py)
)

#: Parameter values equal to this many decimals are one prediction: the optimiser revisits
#: a point up to rounding in its steps.
VALUE_DECIMALS = 12
#: Predictions kept, each an (M,) array (1.6 kB at M = 200: at most 6.5 MB; 40 kB at
#: Settings.max_points = 5000: at most 164 MB), more than one least-squares fit asks for
#: (max_nfev = 60 steps, each with its finite-difference columns).
PREDICTION_CACHE_SIZE = 4096
#: Model evaluations kept (effects.predict's cache, each a few (M,) loss arrays): bounds the
#: memory while keeping the evaluations the fits of one selection step share.
MODEL_CACHE_SIZE = 512


@dataclass(frozen=True)
class Rows:
    """The measured points as the engine's :class:`~.engine.Observations`."""
    values: np.ndarray             # (M,) measured efficiency, a fraction
    weight: np.ndarray             # (M,) relative weights (mean square 1)
    group: np.ndarray              # (M,) each point its own fold group


class Problem:
    """Measured efficiencies, the case and the catalog: the model at the measured points
    and the engine that fits it (:attr:`engine`).

    Parameters
    ----------
    case : toothfem.Case
        The reducer case the effects are added to.
    data : measured.MeasuredData
        Measured points, M of them.
    effects : sequence of effects.Effect
        The catalog effects that may be fitted.
    settings : Settings
        Folds, fold seed, function evaluations per fit and the selection's thresholds.
    loads : str
        Load sharing of the model, ``"analytic"`` or ``"fem"``.
    """

    def __init__(self, *, case, data, effects, settings: Settings, loads):
        self.case = case
        self.data = data
        self.settings = settings
        self.loads = loads
        self.points = fx.Points.of(data)
        self.eta = np.asarray(data.efficiency, float)
        self.n = self.eta.size
        if data.sigma is not None and np.all(np.isfinite(data.sigma)) and np.all(data.sigma > 0):
            w = 1.0 / np.asarray(data.sigma, float)
            self.w = w / np.sqrt(np.mean(w ** 2))       # relative weights, mean square 1
            self.weighted = True
        else:
            self.w = np.ones(self.n)
            self.weighted = False
        # each applicable effect with the bounds of this case and data (Effect.bound_to)
        self.effects = {e.name: e.bound_to(case, self.points)
                        if e.applicable(case, self.points) is None else e for e in effects}
        self.prepared: dict[str, object] = {}   # effect name -> its prepared tables
        self.evaluations = 0
        # (names, values) -> efficiency
        self._cache: dict[tuple[tuple[str, ...], tuple[float, ...]], np.ndarray] = {}
        self._evals: dict[tuple, Efficiency] = {}   # model evaluations (effects.predict's cache)
        self.memo = LoadsMemo()        # each drive's load tables, computed once for this fit
        self.engine = Engine(Rows(self.eta, self.w, np.arange(self.n)), self.effects.values(),
                             self, rules=EFFICIENCY_RULES, settings=settings)

    def predict(self, names, values) -> np.ndarray:
        """Efficiency at the measured points with the effects ``names`` set
        (:class:`.engine.Model`).

        Parameters
        ----------
        names : sequence of str
            Effect names, in the order of ``values``.
        values : array_like
            Their parameter values, one after the other, in the parameters' units.

        Returns
        -------
        numpy.ndarray
            (M,) efficiency, a fraction.
        """
        key = (tuple(names), tuple(np.round(values, VALUE_DECIMALS)))
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        assignment, k = {}, 0
        for name in names:
            eff = self.effects[name]
            m = len(eff.parameters)
            assignment[eff] = tuple(values[k:k + m])
            k += m
            if eff.route(self.case) == "loss" and eff.prepare is not None \
                    and name not in self.prepared:
                self.prepared[name] = eff.prepare(self.case, self.points)
        before = len(self._evals)
        eta = fx.predict(self.case, self.points, assignment, self.prepared,
                         loads=self.loads, cache=self._evals, memo=self.memo).efficiency
        self.evaluations += len(self._evals) - before
        if len(self._cache) > PREDICTION_CACHE_SIZE:
            self._cache.clear()
        if len(self._evals) > MODEL_CACHE_SIZE:
            self._evals.clear()
        self._cache[key] = eta
        return eta
