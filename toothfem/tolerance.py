"""Tolerance Monte Carlo through the elastic contact model (``toothfem tolerance``).

Each sample is one reducer as built: its deviations are drawn from the case's
``[tolerances]`` (:meth:`toothfem.fem.drives.Drive.sample_deviation`), turned into shifts of
the candidates' initial gaps and solved with the nominal design's influence tables (no
mesh, no factorisation: docs/tolerance.md). The positions of one meshing period are put
over the stage's whole pairing period (``pitches``), so that every pin and lobe of the
built stage takes part. Each ring is solved through the drive's system model (the whole
reducer at the operating torque: every disc free on its pins and bearings, the split
between the discs solved); the labels
(:func:`~toothfem.tolerance_result.output_labels`) say so. Per sample: the largest pin
(tooth) force, the largest Hertz pressure and the fewest contacts on one member at a
position; lost motion (+-3 % of the rated torque); the loaded transmission error and the
mesh and total efficiency at the operating point (with the first member's loads), and the
lowest film ratio the efficiency model finds. The share of each tolerance in each output's
variance comes from runs with that tolerance alone (normalised over the tolerances: a
ranking; the model is not additive, so the one-tolerance variances need not sum to the
whole ensemble's). The result, its percentiles and the limits it is checked against:
:mod:`toothfem.tolerance_result`.
"""
from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import math
import os
import pickle
from pathlib import Path
from dataclasses import dataclass

import numpy as np

from .case import Case, as_case
from .case_checks import check_type
from .cluster import as_finished, dask_client
from .efficiency import evaluate, operating_point, rated_output_torque
from .efficiency.mesh_table import table_from_records
from .errors import CaseError, IncompleteRun, check_range
from .fem.cache import DiskCache
from .fem.datasheet.sheet import lost_motion_arcmin
from .units import ARCSEC
from .fem.deviations import only
from .fem.drives import drive_for
from .fem.linsolve import one_blas_thread
from .datasheet import TE_DEFINITION
from .fem.system.datasheet import SystemTwist, system_backlash_arcmin
from .quantities import ALONE_OVER_ALL
from .tolerance_result import MAX_SAMPLES, OUTPUTS, ToleranceResult, check_limits
from .units import MPA_PER_PA

#: What a ring's forces and TE are (the summary says it).
LOADS_SYSTEM = {"te_definition": TE_DEFINITION,
                "loads": "the system model at the operating torque: every disc on its pins "
                         "and bearings, the split between the discs solved (no load factor)"}
#: Sampled pitches of the system model's tables over the full period (each position of a
#: ring is solved with the tables of its own pitch, filled from these: within 0.7 % of
#: the exact tables on the largest pin force at 13 samples of the pin-housing drive's 39
#: pitches, 3.6 % at 6; docs/stiffness.md).
PITCH_SAMPLES = 13
#: Samples per Dask task: a worker reads the tables and solves the nominal design once for
#: all its tasks (``_models``), so a task costs little more than its rings, and small tasks
#: keep the last worker's tail short (20 rings: 3 s on the pin-housing drive).
CHUNK = 20
#: The default ensemble [built reducers]: enough for the median and the P90/P10 with
#: their 95 % intervals (36, tolerance_result.rings_needed), a margin above it, and
#: within a minute on RV-40E (docs/tolerance.md, measured); P99/P1 need 368 (--samples).
DEFAULT_SAMPLES = 40
#: The one-tolerance runs' default size: a quarter of the ensemble where that is at least
#: this many reducers a tolerance (fewer give a share of little meaning), else none.
SHARE_SAMPLES_MIN = 20


@dataclass(frozen=True, kw_only=True)
class _Setup:
    """What every sample of a case reads (picklable: sent to each Dask task)."""
    case: Case
    positions: int
    pitches: np.ndarray
    speed_rpm: float
    output_torque_Nm: float
    rated_torque_Nm: float
    cache_dir: str | None
    pitch_samples: int = 0          # the system's sampled pitches (PITCH_SAMPLES when made)


def default_share_samples(samples: int) -> int:
    """The one-tolerance runs' size when none is given: a quarter of ``samples`` where that
    is at least :data:`SHARE_SAMPLES_MIN`, else 0 (none).

    Parameters
    ----------
    samples : int
        The ensemble's size.

    Returns
    -------
    int
    """
    quarter = int(samples) // 4
    return quarter if quarter >= SHARE_SAMPLES_MIN else 0


def tolerance_analysis(case: Case | str | os.PathLike, *, samples: int = DEFAULT_SAMPLES,
                       seed: int = 0,
                       positions: int = 36,
                       workers: int = 1, scheduler=None, share_samples: int | None = None,
                       overrides: dict | None = None, progress: bool = True,
                       cache=True, points=None) -> ToleranceResult:
    """The tolerance ensemble of a case.

    Parameters
    ----------
    case : toothfem.case.Case or str or os.PathLike
        With a ``[tolerances]`` section (at least one nonzero zone); a path is the case
        file, loaded and validated (as every analysis of the API takes it:
        :func:`toothfem.case.as_case`).
    samples : int
        Built reducers drawn (1 to MAX_SAMPLES).
    seed : int
        Seed of the generator: the same seed gives the same samples and results.
    positions : int
        Positions per sample, one per meshing period spread over the pairing period.
    workers : int
        Processes (a Dask LocalCluster when above 1, or with ``scheduler``).
    scheduler : str or distributed.Client, optional
        A Dask scheduler to run on.
    share_samples : int, optional
        Samples of each one-tolerance run for the variance shares (default a quarter of
        ``samples`` where that is at least SHARE_SAMPLES_MIN, else none: from 80
        samples on); 0 for none.
    overrides : dict, optional
        [tolerances] keys (mm) to use instead of the case's.
    progress : bool
        A tqdm bar on stderr (on a terminal only: toothfem.bars).
    cache : bool or toothfem.fem.cache.DiskCache
        Where the nominal influence tables are kept (True: the user's cache).
    points : toothfem.output.Points, optional
        Where each finished ring is kept as it arrives (``record``), and the rings of an
        unfinished run of the same settings (``done``), which are not solved again.

    Returns
    -------
    ToleranceResult

    Raises
    ------
    CaseError
        For a count that is not an integer or out of range, or tolerances without a
        nonzero zone.
    """
    case = as_case(case)
    for name, value, lo, hi in (("samples", samples, 1, MAX_SAMPLES),
                                ("workers", workers, 1, 256), ("positions", positions, 2, 3600),
                                ("seed", seed, 0, 2**63 - 1)):      # numpy's seeds: >= 0
        check_type(name, value, "integer")
        check_range(name, value, lo, hi, error=CaseError)
    if overrides:
        known = {f.name for f in dataclasses.fields(case.tolerances)}
        for key in overrides:
            if key not in known:
                raise CaseError(f"tolerances.{key} is not a known key; known: {sorted(known)}")
        case = dataclasses.replace(case, tolerances=dataclasses.replace(case.tolerances,
                                                                        **overrides))
    si = case.to_si()
    tol = si.tolerances
    active = tol.active()
    if not active:
        raise CaseError("[tolerances] has no nonzero zone: nothing to sample (e.g. "
                        "pin_position_mm = 0.005)")
    drive = drive_for(case)
    speed, t_out = operating_point(case)
    rated, _ = rated_output_torque(si)
    n = int(positions)
    cache_obj = DiskCache() if cache is True else (cache or None)
    setup = _Setup(case=case, positions=n,
                   pitches=(np.arange(n) * drive.pairing_period_pitches) // n,
                   speed_rpm=float(speed), output_torque_Nm=float(t_out),
                   rated_torque_Nm=float(rated),
                   cache_dir=None if cache_obj is None else str(cache_obj.directory),
                   pitch_samples=PITCH_SAMPLES)
    rng = np.random.default_rng(seed)
    runs = [("all", tol, int(samples))]
    n_share = default_share_samples(int(samples)) if share_samples is None \
        else int(share_samples)
    if n_share and len(active) > 1:
        runs += [(name, only(tol, name), n_share) for name in active]
    plan = [(label, drive.sample_deviation(t, rng)) for label, t, count in runs
            for _ in range(count)]
    # the cluster first: a scheduler that cannot run the rings is found before the tables
    remote = int(workers) > 1 or scheduler is not None
    with dask_client(scheduler, int(workers)) if remote else \
            contextlib.nullcontext() as client:
        _system(setup, prepare=True)              # tables once, here (and on disk)
        # the nominal design (None) first, where the samples run
        nominal, *rows = _run_all(setup, [None] + [d for _, d in plan], client, progress,
                                  points)
    labels = np.array([label for label, _ in plan])
    table = {k: np.array([r[k] for r in rows], float) for k in OUTPUTS}
    ensemble = {k: v[labels == "all"] for k, v in table.items()}
    shares = _shares(table, labels, active) if n_share else {}
    film = _film_ratios(nominal, [r for r, label in zip(rows, labels) if label == "all"])
    settings = {"samples": int(samples), "seed": int(seed), "positions": n,
                "pairing_period_pitches": int(drive.pairing_period_pitches),
                "share_samples": n_share if len(active) > 1 else 0,
                "distribution": tol.distribution,
                "distributions": dict(tol.distributions),
                "tolerances_mm": {k: v for k, v in dataclasses.asdict(case.tolerances).items()
                                  if k.endswith("_mm") and v},
                "operating_speed_rpm": setup.speed_rpm,
                "operating_output_torque_Nm": setup.output_torque_Nm,
                "rated_torque_Nm": setup.rated_torque_Nm,
                **LOADS_SYSTEM,
                # the same operating point with the loads `toothfem run` takes (the
                # analytic split): what the nominal's efficiency is told apart from
                "nominal_total_efficiency_analytic_loads_pct": 100 * float(
                    evaluate(si, setup.speed_rpm, setup.output_torque_Nm).efficiency[0])}
    result = ToleranceResult(case_name=case.name, drive=drive.kind,
                             contact_name=drive.contact_name,
                             contacts_name=drive.contacts_name, member_name=drive.member_name,
                             members=int(drive.members),
                             samples=ensemble, nominal={k: nominal[k] for k in OUTPUTS},
                             shares=shares, settings=settings, film_ratio=film)
    result = dataclasses.replace(result, maker={
        k: float(case.published[k]) for k in ("backlash_arcmin", "lost_motion_arcmin")
        if k in case.published})
    found, drawn = check_limits(result, si)
    return dataclasses.replace(result, limits=drawn, warnings=tuple(found))


def _film_ratios(nominal: dict, rows: list) -> dict:
    """{contacts: {"nominal": lowest or None, "samples": (N,) with inf where not below
    FILM_RATIO_BOUNDARY}} over every contact set the nominal or a ring names; NaN for a
    ring kept by an older run (no film ratio recorded)."""
    names = dict.fromkeys(w for r in [nominal, *rows] for w in r.get("film_ratio", {}))
    return {w: {"nominal": nominal.get("film_ratio", {}).get(w),
                "samples": np.array([r["film_ratio"].get(w, math.inf) if "film_ratio" in r
                                     else math.nan for r in rows], float)}
            for w in names}


def _shares(table, labels, active) -> dict:
    """{tolerance: {output: Var(one tolerance) / sum over tolerances}} and, per output,
    ALONE_OVER_ALL = sum Var(one) / Var(all) (sampling noise included)."""
    if len(active) < 2:
        return {active[0]: {k: 1.0 for k in OUTPUTS}} if active else {}
    parts = {name: {k: float(np.var(table[k][labels == name])) for k in OUTPUTS}
             for name in active}
    out: dict[str, dict[str, float]] = {name: {} for name in active}
    out[ALONE_OVER_ALL] = {}
    for k in OUTPUTS:
        total = sum(parts[m][k] for m in active)
        for name in active:
            out[name][k] = parts[name][k] / total if total > 0 else 0.0
        v_all = float(np.var(table[k][labels == "all"]))
        out[ALONE_OVER_ALL][k] = total / v_all if v_all > 0 else 0.0
    return out


#: The quantity of :func:`toothfem.limits.film_ratio`'s records: "film ratio of <contacts>".
_FILM = "film ratio of "


def _film_ratio(eff) -> dict:
    """{contacts: lowest film ratio} of the efficiency model's film-ratio records (those
    below FILM_RATIO_BOUNDARY; contacts not named were not below it)."""
    return {w.quantity[len(_FILM):]: float(w.value) for w in eff.warnings
            if w.quantity.startswith(_FILM)}


def _outputs(setup: _Setup, system, deviation, state, reference=None) -> dict:
    """One built reducer (``deviation`` None: the nominal design) through the system model
    at the operating torque: every disc on
    its pins and bearings, the deviation's gaps at each position's pitch; the largest
    force, Hertz pressure and fewest contacts over every disc (the split between them
    solved, so no load factor), the elastic lost motion, the reducer's TE, and the
    efficiency with the first disc's loads; ``reference``: the nominal design's
    SystemTwist on these positions, each solve's start."""
    si, drive = setup.case.to_si(), system.drive
    twist = SystemTwist(system, deviation=deviation, pitches=setup.pitches,
                        reference=reference)
    t = setup.output_torque_Nm
    sts = twist.states(t)
    records = [system.member_record(j, sts, state) for j in range(system.discs)]
    eff = evaluate(si, setup.speed_rpm, t, table=table_from_records(state, records[:1], "fem"))
    total = np.array([s.twist_rad for s in sts])
    return {"max_force_N": float(max(np.max(r.force) for r in records)),
            "max_ph_MPa": float(max(np.max(r.ph) for r in records)) * MPA_PER_PA,
            "contacts_min": float(min(np.min(s.contacts) for s in sts)),
            "lost_motion_arcmin": lost_motion_arcmin(twist, setup.rated_torque_Nm),
            "backlash_arcmin": system_backlash_arcmin(system, deviation=deviation,
                                                      pitches=setup.pitches),
            "te_mean_arcsec": float(np.mean(total) / ARCSEC),
            "te_pp_arcsec": float(np.ptp(total) / ARCSEC),
            "mesh_efficiency_pct": 100 * float(eff.mesh_efficiency[drive.kind][0]),
            "total_efficiency_pct": 100 * float(eff.efficiency[0]),
            "film_ratio": _film_ratio(eff)}


def _system(setup: _Setup, prepare: bool = False):
    """The drive's system model with its tables at every pitch (PITCH_SAMPLES sampled),
    from the disk cache; ``prepare``: build every table now."""
    drive = drive_for(setup.case)
    system = drive.system_model(
        drive.supports(setup.case.to_si().supports), setup.positions,
        cache=False if setup.cache_dir is None else DiskCache(Path(setup.cache_dir)),
        pitch_samples=setup.pitch_samples)
    if prepare:
        for tables in {id(t): t for t in system.pitch_tables or ()}.values():
            tables.prepare()
        for s in system.slots:
            s.solver.prepare()
    return system


#: The last setup's models in this process ({key: (state, system, reference)}): the Dask
#: tasks of one run on a worker read the tables and solve the nominal design once.
_MODELS: dict[str, tuple] = {}


def release_models() -> None:
    """Drop the last setup's models kept for the process's next task (a search over many
    designs calls it between designs: the system model holds every pitch's tables)."""
    _MODELS.clear()


def _models(setup: _Setup):
    """(meshing state, system model, the nominal design's SystemTwist) of a setup, kept for
    the process's next task of the same run."""
    key = hashlib.sha256(pickle.dumps(setup)).hexdigest()
    if key not in _MODELS:
        system = _system(setup)
        state = system.drive.meshing(system.slots[0].solver.positions_rad)
        reference = SystemTwist(system, pitches=setup.pitches)
        _MODELS.clear()
        _MODELS[key] = (state, system, reference)
    return _MODELS[key]


def _run_chunk(setup: _Setup, deviations: list, done=None) -> list:
    """The outputs of each deviation, in order (a Dask task, or the whole run in one
    process); ``done(k, output)`` after the k-th, if given."""
    state, system, reference = _models(setup)
    out = []
    # small dense systems: BLAS on one thread (beside the other workers), the limit set
    # once for the task rather than per solve
    with one_blas_thread():
        for k, d in enumerate(deviations):
            out.append(_outputs(setup, system, d, state, reference))
            if done is not None:
                done(k, out[-1])
    return out


def _run_all(setup, deviations, client, progress, points=None) -> list:
    """Outputs of every deviation, in order: here (``client`` None), or in Dask tasks of
    CHUNK samples; those in ``points.done`` (by index) are taken from there, the others
    kept there as they finish."""
    from .bars import bar as progress_bar

    results = {} if points is None else {int(k): v for k, v in points.done.items()}
    todo = [i for i in range(len(deviations)) if i not in results]

    def keep(i, output):
        results[i] = output
        if points is not None:
            points.record(str(i), output)
        bar.update()

    bar = progress_bar(total=len(deviations), initial=len(results), desc="tolerance",
                       unit="ring", enabled=progress, every_s=15.0)
    try:
        if client is None:
            _run_chunk(setup, [deviations[i] for i in todo],
                       lambda k, output: keep(todo[k], output))
        elif todo:
            chunks = [todo[i:i + CHUNK] for i in range(0, len(todo), CHUNK)]
            futures = {client.submit(_run_chunk, setup, [deviations[i] for i in c],
                                     pure=False): c for c in chunks}
            for fut in as_finished(client, list(futures)):
                chunk = futures[fut]
                try:
                    outputs = fut.result()
                except Exception as exc:        # noqa: BLE001 -- a worker died on it
                    raise IncompleteRun(f"rings {chunk[0]}-{chunk[-1]} failed on the "
                                        f"cluster ({type(exc).__name__}: {exc})"
                                        .splitlines()[0]) from None
                for i, output in zip(chunk, outputs):
                    keep(i, output)
        return [results[i] for i in range(len(deviations))]
    finally:
        bar.close()
