"""One fitting engine for the loops that compare a model with measurements (installed as
``toothfem.efficiency.loop.engine``): bounded least squares of a set of effects, BIC,
the k-fold held-out error, forward selection with alias groups (by BIC and by the rows'
distance between the fits), the separating-measurement hook and the at-bound rule.

A loop is an adapter: its rows (:class:`Observations`), its effects (:class:`Effect`), its
model evaluation (:class:`Model`), its :class:`Rules` and its report records. The
efficiency loop (:mod:`toothfem.efficiency.loop.problem`, :mod:`~toothfem.efficiency.loop.run`)
and the TE/hysteresis loop (:mod:`toothfem.efficiency.loop.te.problem`) are the two.

* :mod:`.records`: the Protocols, :class:`Parameter`, :class:`Rules`, :class:`Fit`,
  :class:`HeldOut`, the at-bound rule and the folds;
* :mod:`.fitting`: :class:`Engine`, fits and held-out errors;
* :mod:`.selection`: :func:`select`, the forward selection.
"""
from .fitting import Engine, Solution  # noqa: F401
from .records import (AT_BOUND_REL, EXACT_TOL, MIN_FOLDS, STEP_BOUND_EPS,  # noqa: F401
                      WRSS_FLOOR, Effect, Fit, HeldOut, Model, Observations, Parameter, Rules,
                      assign_folds, at_bound, fold_count, parameter)
from .selection import (ALL_TRIED, EXCHANGING, MAX_EFFECTS, NO_CANDIDATES,  # noqa: F401
                        NOTHING_PASSES, STEPS_PER_CANDIDATE, TOO_FEW_ROWS, Listener, Score,
                        Selection, Separate, Step, aliases, any_at_bound, pairs, prune, ranked,
                        score, select, winner)

__all__ = ["ALL_TRIED", "AT_BOUND_REL", "EXACT_TOL", "EXCHANGING", "MAX_EFFECTS", "MIN_FOLDS",
           "NOTHING_PASSES", "NO_CANDIDATES", "STEPS_PER_CANDIDATE", "STEP_BOUND_EPS",
           "TOO_FEW_ROWS", "WRSS_FLOOR", "Effect", "Engine", "Fit", "HeldOut", "Listener",
           "Model", "Observations", "Parameter", "Rules", "Score", "Selection", "Separate",
           "Solution", "Step", "aliases", "any_at_bound", "assign_folds", "at_bound",
           "fold_count", "pairs", "parameter", "prune", "ranked", "score", "select", "winner"]
