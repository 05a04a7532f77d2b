"""Close the loop with measured data: residuals, effect selection, report
(installed as ``toothfem.efficiency.loop``).

``run_loop(case, data)`` compares the model with measured efficiencies and adds physical
effects from the catalog one at a time while they help. One job per module:

* :mod:`.measured`: measured efficiency data (CSV with units in the column names, provenance
  beside it) as a :class:`~.measured.MeasuredData` record; :mod:`.measured_columns`: the
  columns' units and the checks of the header, cells and rows;
* :mod:`.effects`: the catalog of physical effects, each a parameter of the model with its
  bounds, case fields, equation, source and the measurement that shows it directly
  (:mod:`.effect_base` the records; :mod:`.loss_effects` the oil's grade, windage and
  bearing preload; :mod:`.rig_effects` the rig's sensors: torque meters' offsets, the oil
  sensor's offset, a warm-up it did not log; :mod:`.thermal_effect`);
* :mod:`.separation`: effects the data cannot tell apart, and the operating points (or the
  direct measurement) that would;
* :mod:`.binning`: many rows onto fewer operating points (the mean of each cell of a grid);
* :mod:`.synthetic`: synthetic rig data (the model plus effects the case does not declare,
  plus sensor noise) for the tests and the figures;
* :mod:`.engine` (a subpackage): the fitting engine both loops adapt: bounded least
  squares, BIC, k-fold held-out errors, forward selection with alias groups and the
  separating-measurement hook, the at-bound rule;
* :mod:`.problem`: the efficiency loop's side of it: the measured points as rows, the
  model with effects at them, and the loop's :data:`~.problem.EFFICIENCY_RULES`;
* :mod:`.trends`: residual trends against the covariates, and each effect's signature;
* :mod:`.run`: the data checked and binned (:func:`loop_data`), the loop itself
  (:func:`run_loop`); an effect that helps only at its parameter's physical bound is not
  added;
* :mod:`.report`: the :class:`LoopReport` record and its JSON;
* :mod:`.settings`: the thresholds of all of the above (both loops');
* :mod:`.te` (a subpackage, imported on its own): TE and hysteresis rig recordings read
  file by file, the TE spectrum in orders named by the drive's orders, and the model-free
  rigidity, lost motion, hysteresis loss and width (docs/te_rig.md).

Pictures and the Markdown text of a report are the reporting layer's
(``toothfem.report.loop``): this package computes, it does not draw.
"""
from .engine import AT_BOUND_REL, Fit, HeldOut, at_bound  # noqa: F401
from .binning import Binning, bin_rows  # noqa: F401
from .problem import EFFICIENCY_RULES, Problem  # noqa: F401
from .report import Candidate, Closing, EffectFit, LoopReport, Step  # noqa: F401
from .run import candidates_of, final_case, loop_data, run_loop  # noqa: F401
from .settings import Settings  # noqa: F401
from .separation import AliasGroup, alias_group  # noqa: F401
from .trends import Trend, most_followed, residual_trends, signatures  # noqa: F401

__all__ = ["AT_BOUND_REL", "EFFICIENCY_RULES", "Binning", "Candidate", "Closing", "EffectFit", "Fit",
           "HeldOut", "LoopReport", "Problem", "Settings", "Step", "Trend", "at_bound",
           "bin_rows", "candidates_of", "final_case", "loop_data", "residual_trends",
           "run_loop", "signatures", "AliasGroup", "alias_group", "most_followed"]
