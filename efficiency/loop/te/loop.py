"""The TE/hysteresis loop (issue 24): recordings in, the effect the model lacks out, with
the error before and after (docs/te_rig.md, "The loop").

:func:`run_te_loop` reads the recordings (:mod:`.recordings`), takes their model-free
figures (:mod:`.figures`, :mod:`.hysteresis`), turns them into rows with their uncertainty
(:mod:`.observations`), and fits the catalog's effects (:mod:`.effects`) to them with the
fitting engine, by the TE loop's rules (:mod:`.problem`), on the case's system model
(:class:`~.model.RecordingModel`). Nothing here draws or writes: the reporting layer
(``toothfem.report.te``) renders a :class:`TeLoopResult`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..settings import DEFAULT_SETTINGS
from .effects import catalog, effects_of
from .figures import TeFigures, te_figures
from .hysteresis import HysteresisFigures, hysteresis_figures, read_hysteresis
from .problem import TeLoop, TeProblem
from .model import ModelRecordings, RecordingModel
from .observations import Layout, observations, model_rows
from .recordings import read_te_recordings, recording_paths
from .plausibility import check_scale, check_torques
from .running import RunningDatasheet, from_figures, running_datasheet
from ....errors import MeasuredDataError, ToothfemError

#: Named orders fitted: up to this multiple of the lowest named order above the output's
#: own (the crank's or the pins' passing): the model's TE resolves its period's first three
#: harmonics (docs/te_model.md, 7 sampled pitches); the mesh orders, Zb x the crank's, are
#: beyond what its positions sample.
MAX_ORDER_OVER_FIRST = 3.0
#: The spectra's window: rectangular. Over whole output revolutions an integer order (every
#: order of a reducer whose TE repeats each output turn) falls on its bin with no leakage;
#: a Hann window would read half of order 40 at 39 in a one-revolution sweep, an amplitude
#: the model (its exact harmonics) has no term for.
SPECTRUM_WINDOW = "rect"


@dataclass(frozen=True, kw_only=True)
class TeLoopResult:
    """The loop's outcome with what its report shows: the figures of the recordings, the
    model's recordings before and after, the fit."""
    case_name: str
    loop: TeLoop
    layout: Layout                     # what each row is
    te_figures: TeFigures | None
    hysteresis: HysteresisFigures | None
    before: ModelRecordings
    after: ModelRecordings
    rated_torque_Nm: float
    orders: dict                       # the named orders fitted
    refused: tuple                     # recordings.Refusal
    elapsed_s: float
    running: RunningDatasheet | None = None   # the widths' model-free reading
    running_note: str = ""             # why there is none

    def model_running(self, which: str = "before") -> RunningDatasheet | None:
        """The same reading of the model's widths at the measured torques (each weighed
        by the measured width's sigma), "before" or "after" the loop; None where the
        measured one could not be taken.

        Parameters
        ----------
        which : {"before", "after"}

        Returns
        -------
        RunningDatasheet or None
        """
        if self.running is None:
            return None
        model = self.before if which == "before" else self.after
        by_torque = {round(float(t.output_torque_Nm), 9): t.width_arcsec for t in model.te}
        sig = dict(zip(self.running.torques_Nm, self.running.sigmas_arcmin))
        torques = [t for t in self.running.torques_Nm if round(t, 9) in by_torque]
        try:
            return running_datasheet(torques, [by_torque[round(t, 9)] for t in torques],
                                     [60.0 * sig[t] for t in torques])
        except MeasuredDataError:
            return None

    @property
    def evaluations(self) -> int:
        """The model evaluations of the fit (:attr:`TeLoop.evaluations`)."""
        return self.loop.evaluations

    @property
    def not_considered(self) -> dict:
        """The catalog's effects left out of the candidates, each with why it costs most
        (:attr:`TeEffect.costly`; "" for one that was only not asked for).

        Returns
        -------
        dict of str to str
        """
        pool = {row[0] for step in self.loop.steps for row in step.scored} \
            | set(self.loop.added)
        return {n: e.costly for n, e in self.loop.catalog.items() if n not in pool}

    def summary(self) -> dict:
        """The loop's JSON (report.json).

        Returns
        -------
        dict
        """
        d = self.loop.to_dict()
        figs = {}
        if self.hysteresis is not None:
            figs = self.hysteresis.summary()
        running = {"measured": None if self.running is None else self.running.summary(),
                   "note": self.running_note}
        for which in ("before", "after"):
            m = self.model_running(which)
            running[f"model_{which}"] = None if m is None else m.summary()
        return {"case": self.case_name, "rated_torque_Nm": self.rated_torque_Nm,
                "named_orders": self.orders, "measured_figures": figs,
                "running_datasheet": running,
                "model_figures_before": (None if self.before.loop is None
                                         else self.before.loop.figures()),
                "model_figures_after": (None if self.after.loop is None
                                        else self.after.loop.figures()),
                "refused": [str(r) for r in self.refused],
                "not_considered": self.not_considered,
                "elapsed_s": self.elapsed_s, "model_evaluations": self.evaluations,
                "replayed_evaluations": self.loop.replayed, **d}


def fitted_orders(named: dict) -> dict:
    """The named orders whose amplitudes the loop fits: up to MAX_ORDER_OVER_FIRST times
    the first above the output's own (the mesh orders are beyond what the model's
    positions sample).

    Parameters
    ----------
    named : dict of str to float
        The drive's orders (:meth:`RecordingModel.te_orders`).

    Returns
    -------
    dict of str to float
    """
    first = min([q for q in named.values() if q >= 2] or [1.0])
    return {n: q for n, q in named.items() if q <= MAX_ORDER_OVER_FIRST * first}


def candidate_names(effects, candidates=None) -> list:
    """The effects a loop scores.

    Parameters
    ----------
    effects : sequence of TeEffect
        The catalog.
    candidates : sequence of str or "all", optional
        None: every effect but the costly ones (:attr:`TeEffect.costly`); "all": every one;
        else these names.

    Returns
    -------
    list of str
    """
    if candidates is None:
        return [e.name for e in effects if not e.costly]
    if isinstance(candidates, str):
        if candidates != "all":
            raise ToothfemError(f"candidates = {candidates!r}: effect names, or 'all'")
        return [e.name for e in effects]
    return list(candidates)


def run_te_loop(case, *, te=None, hysteresis=None, name_pattern=None, settings=DEFAULT_SETTINGS,
                candidates=None, model: RecordingModel | None = None, progress=False,
                on_step=None, replay=()):
    """Fit the effects a case's model lacks to its TE and hysteresis recordings.

    Parameters
    ----------
    case : toothfem.case.Case or path
    te : path or sequence of paths, optional
        TE recordings (files or folders; :func:`~.recordings.read_te_recordings`).
    hysteresis : path, optional
        A hysteresis staircase recording.
    name_pattern : str, optional
        File-name pattern of the TE files' conditions.
    settings : toothfem.efficiency.loop.settings.Settings
        The loop's thresholds (the efficiency loop's).
    candidates : sequence of str or "all", optional
        Effect names; default: the drive's catalog less its costly effects
        (:attr:`TeEffect.costly`, the pin ring's: each model evaluation some 40 times a
        drawn one's), which the result lists as not considered; "all": every effect.
    model : RecordingModel, optional
        The case's model already set up (default: one with ``warm_starts``, what a fit's
        many calls want).
    progress : bool
        Progress over the TE files and over each selection step's candidates.
    on_step : callable, optional
        ``on_step(index, record)`` as each selection step finishes
        (:meth:`TeProblem.run`).
    replay : iterable, optional
        The model evaluations of an earlier run's finished steps (their records'
        ``evaluations``): the loop resumes after them (:meth:`TeProblem.run`).

    Returns
    -------
    TeLoopResult

    Raises
    ------
    ToothfemError
        Where neither recording is given or none gives a row.
    """
    t0 = time.perf_counter()
    if te is None and hysteresis is None:
        raise ToothfemError("te, hysteresis: give TE recordings, a hysteresis recording, "
                            "or both")
    model = model or RecordingModel(case, warm_starts=True)
    rated = model.rated_torque_Nm
    orders = fitted_orders(model.te_orders())
    refused = []
    te_figs = loop_figs = running = None
    running_note = "no TE recordings"
    if te is not None:
        paths = recording_paths(te)
        if hysteresis is not None:      # a folder holding both: the staircase is not TE
            paths = [p for p in paths if p.resolve() != Path(hysteresis).resolve()]
        rec = read_te_recordings(paths, name_pattern=name_pattern, progress=progress,
                                 window=SPECTRUM_WINDOW)
        refused += list(rec.refused)
        te_figs = te_figures(rec, named_orders=orders)
        try:
            running, running_note = from_figures(te_figs), ""
        except MeasuredDataError as exc:
            running, running_note = None, str(exc)
    if hysteresis is not None:
        loop_figs = hysteresis_figures(read_hysteresis(hysteresis), rated)
    obs, layout = observations(rated, loop=loop_figs, te=te_figs, orders=orders)
    torque_max = None
    if loop_figs is not None:
        torque_max = max(float(np.max(np.abs(c.torque_Nm))) for c in loop_figs.curves)
    system = model.system(0)
    cranks, discs = system.cranks, system.discs

    def recordings(options: dict) -> ModelRecordings:
        eff = effects_of(options, cranks, discs)
        loop = model.hysteresis(eff, torque_max_Nm=torque_max) if layout.loop_rows.size \
            else None
        te_runs = model.te(eff, layout.te_torques_Nm) if layout.te_torques_Nm else ()
        return ModelRecordings(loop=loop, te=te_runs)

    check_torques(rated, _torques(te_figs, loop_figs))     # before the model meets them
    before = recordings({})
    _plausible(obs, layout, before)
    effects = catalog(model)
    problem = TeProblem(obs, lambda options: model_rows(layout, recordings(options)),
                        effects, settings)
    fitted = problem.run(candidate_names(effects, candidates), progress=progress,
                         on_step=on_step, replay=replay)
    final_options: dict = {}
    for name in fitted.final.effects:
        final_options.update(problem.catalog[name].model_options(fitted.final.values[name]))
    return TeLoopResult(case_name=model.case.name, loop=fitted, layout=layout,
                        te_figures=te_figs,
                        hysteresis=loop_figs, before=before,
                        after=recordings(final_options), rated_torque_Nm=rated,
                        orders=orders, refused=tuple(refused),
                        elapsed_s=time.perf_counter() - t0, running=running,
                        running_note=running_note)


def _torques(te_figs, loop_figs) -> list:
    """Every recorded output torque with where it comes from."""
    torques = []
    if te_figs is not None:
        torques += [(c.condition.output_torque_Nm, ", ".join(c.files))
                    for c in te_figs.conditions]
    if loop_figs is not None:
        torques += [(float(np.max(np.abs(c.torque_Nm))), "the hysteresis recording")
                    for c in loop_figs.curves]
    return torques


def _plausible(obs, layout, before) -> None:
    """Refuse recordings in the wrong unit before the fit (:mod:`.plausibility`): the width
    at the largest torque and the staircase's twist range against the case's model on the
    same rows."""
    model = model_rows(layout, before, centred=False)
    widths = [i for i, r in enumerate(layout.rows) if r.kind == "width"]
    if widths:
        top = max(widths, key=lambda i: layout.rows[i].torque_Nm)
        check_scale(abs(obs.values[top]), abs(model[top]),
                    "hysteresis width at the largest torque", "te (its unit suffix)")
    rows = layout.loop_rows
    if rows.size:
        check_scale(float(np.ptp(obs.values[rows])), float(np.ptp(model[rows])),
                    "twist range of the staircase", "twist (its unit suffix)")
