"""Tolerance Monte Carlo through the elastic contact model (``toothfem tolerance``).

Each sample is one reducer as built: its deviations are drawn from the case's
``[tolerances]`` (:meth:`toothfem.fem.drives.Drive.sample_deviation`), turned into shifts of
the candidates' initial gaps and solved with the nominal design's influence tables (no
mesh, no factorisation: docs/tolerance.md). The positions of one meshing period are put
over the stage's whole pairing period (``pitches``), so that every pin and lobe of the
built stage takes part. Each ring is solved through the drive's system model (the whole
reducer at the operating torque: every disc free on its pins and bearings, the split
between the discs solved); the labels (:func:`output_labels`) say so. Per sample:
the largest pin (tooth) force, the largest Hertz pressure and the fewest contacts on one
member at a position; lost motion (+-3 % of the rated torque); the loaded transmission
error and the mesh and total efficiency at the operating point (with the first member's
loads), and the lowest film ratio the efficiency model finds. The nominal design and the
percentiles are checked against the case's limits (:func:`check_limits`, through
:mod:`toothfem.limits`). The share of each tolerance in each output's variance comes from runs
with that tolerance alone (normalised over the tolerances: a ranking; the model is not
additive, so the one-tolerance variances need not sum to the whole ensemble's).
"""
from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import math
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
from . import limits
from .datasheet import TE_DEFINITION
from .fem.system.datasheet import SystemTwist, system_backlash_arcmin
from .units import MPA_PER_PA

#: Where the outputs come from (the labels say it: the nominal design's figures differ from
#: ``toothfem contact``'s, whose counts and forces are one disc held at its bearing seats
#: over one pitch, and from ``toothfem run``'s efficiency, whose loads are the analytic
#: split or that held disc's).
SYSTEM_WHERE = "system model, positions over the pairing period"


def output_labels(contact: str = "contact", contacts: str = "contacts", member: str = "disc",
                  members: int = 2) -> dict:
    """The outputs of a ring, column -> (label, unit), each label naming the model and the
    positions that gave it.

    Parameters
    ----------
    contact, contacts, member : str
        The drive's words for a contact, several, and the moving member ("pin", "pins",
        "disc"; "tooth", "teeth", "planet").
    members : int
        Moving members sharing the torque (one planet: no "any" or "first" of them).

    Returns
    -------
    dict
        {column: (label, unit)} in the order of the tables and pictures.
    """
    where, model = SYSTEM_WHERE, "system model"
    several = members > 1
    loads = (f"the system model's loads of the first {member}, every {member} taken alike"
             if several else f"the system model's loads of the {member}")
    on = f"any {member}" if several else f"the {member}"
    one = f"one {member}" if several else f"the {member}"
    return {
        "max_force_N": (f"largest {contact} force on {on} ({where})", "N"),
        "max_ph_MPa": (f"largest Hertz pressure P_h on {on} ({where})", "MPa"),
        "contacts_min": (f"fewest {contacts} in contact on {one} at a position "
                         f"({where})", "-"),
        "lost_motion_arcmin": (f"lost motion, elastic curve at +-3 % of the rated torque "
                               f"({model}, no friction)", "arcmin"),
        "backlash_arcmin": (f"backlash ({model}; < 0: the flanks interfere, preloaded; both "
                            "tails: P10 the interference side, P90 the play side)", "arcmin"),
        "te_mean_arcsec": (f"transmission error of the reducer at the operating torque, "
                           f"mean ({where})", "arcsec"),
        "te_pp_arcsec": (f"transmission error of the reducer, peak to peak ({where})",
                         "arcsec"),
        "mesh_efficiency_pct": (f"mesh efficiency ({loads})", "%"),
        "total_efficiency_pct": (f"total efficiency ({loads})", "%"),
    }


#: The outputs of a sample: column -> (label, unit) for tables and pictures (the system
#: model's words; :func:`output_labels` gives a drive's own).
OUTPUTS = output_labels()
#: Outputs where low is worse (the rest: high is worse); their tail percentiles are taken
#: on that side: P10/P1 of the fewest contacts and the efficiencies, P90/P99 of forces,
#: pressures, lost motion and TE.
LOW_IS_WORSE = frozenset({"contacts_min", "mesh_efficiency_pct", "total_efficiency_pct"})
#: Outputs bad on both sides, with both tails given: the backlash (above: play, lost
#: motion at the output; below zero: the flanks interfere, the stage is preloaded, its
#: friction and heat rise and it may not assemble). One tail alone would hide the other.
TWO_SIDED = frozenset({"backlash_arcmin"})
#: Outputs that are counts: their percentiles are sample values (an order statistic on the
#: unfavourable side, COUNT_METHOD), never between two counts ("7.5 pins").
COUNTS = frozenset({"contacts_min"})
COUNT_METHOD = "lower"
#: Percentiles of each output, the median and the unfavourable tail (1 in 10 and 1 in
#: 100 of the built reducers worse than it), by the side that is worse; both sides for
#: TWO_SIDED.
PERCENTILES = {"high": (50, 90, 99), "low": (50, 10, 1), "both": (50, 10, 90, 1, 99)}


def side_of(output: str) -> str:
    """Which side of an output is worse: "high", "low" or "both" (PERCENTILES' keys).

    Parameters
    ----------
    output : str
        A column of OUTPUTS.

    Returns
    -------
    str
    """
    return "both" if output in TWO_SIDED else "low" if output in LOW_IS_WORSE else "high"


#: Confidence of a percentile's interval (distribution-free, from the order statistics:
#: the ranks a binomial(n, q) count of samples below the q-quantile reaches at its
#: (1 - c)/2 and (1 + c)/2 quantiles). A percentile whose interval runs past the sample
#: (too few reducers for it: P99 needs 368) is not given; the summary says how many it needs.
CONFIDENCE = 0.95
#: Most samples one run takes (1e5 rings x 36 positions: about an hour on 2 cores).
MAX_SAMPLES = 100_000
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


@dataclass(frozen=True, kw_only=True)
class ToleranceResult:
    """The ensemble: ``samples`` {output: (N,)}, the ``nominal`` design's outputs on the
    same positions, ``shares`` {tolerance: {output: share of the variance}} from the runs
    with one tolerance at a time (and ALONE_OVER_ALL: their variances summed over the
    whole ensemble's), ``settings`` (samples, seed, positions, tolerances in mm);
    ``film_ratio`` {contacts: {"nominal": lowest or None, "samples": (N,)}}: the efficiency
    model's lowest film ratio where it is below FILM_RATIO_BOUNDARY (inf in ``samples``,
    None for the nominal: not below it); ``limits`` the limits the outputs are drawn
    against ({output: [{name, value, unit, source}]}); ``warnings`` the limits passed
    (:class:`toothfem.limits.Exceeded`, :func:`check_limits`)."""
    case_name: str
    drive: str
    contact_name: str
    contacts_name: str
    samples: dict
    nominal: dict
    shares: dict
    settings: dict
    member_name: str = "disc"
    members: int = 2
    film_ratio: dict = dataclasses.field(default_factory=dict)
    limits: dict = dataclasses.field(default_factory=dict)
    warnings: tuple = ()

    def percentiles(self) -> dict:
        """The ensemble's percentiles of each output on its unfavourable side
        (PERCENTILES, LOW_IS_WORSE; both tails of TWO_SIDED), each with its CONFIDENCE
        interval.

        Returns
        -------
        dict
            {output: {"P50": {"value", "ci", "rings_needed"}, "P90" or "P10": ..,
            "P99" or "P1": ..}} in the output's unit (OUTPUTS): ``value`` and ``ci``
            ([low, high]) None where the sample is too small for the percentile, which
            then needs ``rings_needed`` reducers.
        """
        return {k: {f"P{q}": percentile_ci(v, q / 100, method=COUNT_METHOD if k in COUNTS
                                           else "linear")
                    for q in PERCENTILES[side_of(k)]}
                for k, v in self.samples.items()}

    def outputs(self) -> dict:
        """The outputs in the drive's own words, each label naming its model and positions
        (:func:`output_labels`).

        Returns
        -------
        dict
            {column: (label, unit)}.
        """
        return output_labels(self.contact_name, self.contacts_name, self.member_name,
                             self.members)

    def film_ratio_percentiles(self) -> dict:
        """The lowest film ratio's low-side percentiles over the ensemble (P50, P10, P1)
        that the sample is large enough for (``rings_needed``, as the outputs'), each
        ``value`` None where it is not below FILM_RATIO_BOUNDARY.

        Returns
        -------
        dict
            {contacts: {"P50": {"value", "rings_needed"}, ...}}.
        """
        out: dict[str, dict] = {}
        for where, rec in self.film_ratio.items():
            x = np.asarray(rec["samples"], float)
            if x.size == 0 or np.any(np.isnan(x)):        # rings of an older run: not known
                continue
            out[where] = {}
            for q in PERCENTILES["low"]:
                needed = rings_needed(q / 100)
                if x.size < needed:
                    continue
                # a ring not below the limit stands in as a huge value: a percentile that
                # reaches one is not below the limit either
                v = float(np.percentile(np.where(np.isfinite(x), x, _NOT_BELOW), q))
                out[where][f"P{q}"] = {"value": v if v < limits.FILM_RATIO_BOUNDARY
                                       else None, "rings_needed": needed}
        return out

    def summary(self) -> dict:
        """The result as summary.json holds it.

        Returns
        -------
        dict
            Case, drive, the settings, the outputs' labels, the nominal outputs,
            percentiles, means, the variance shares, the film ratio, the limits and the
            ``warnings`` (the limits passed, :meth:`toothfem.limits.Exceeded.as_dict`).
        """
        return {"case": self.case_name, "drive": self.drive, "member": self.member_name,
                "members": self.members, **self.settings,
                "outputs": {k: list(v) for k, v in self.outputs().items()},
                "nominal": self.nominal, "percentiles": self.percentiles(),
                "mean": {k: float(np.mean(v)) for k, v in self.samples.items()},
                "variance_shares": self.shares,
                "film_ratio_lowest": {
                    where: {"nominal": rec["nominal"], **{
                        q: p["value"] for q, p in
                        self.film_ratio_percentiles().get(where, {}).items()}}
                    for where, rec in self.film_ratio.items()},
                "limits": self.limits,
                "warnings": [w.as_dict() for w in self.warnings]}


#: What a ring whose film ratio is not below the limit stands in as for the percentiles.
_NOT_BELOW = 1e300


def percentile_ci(values, q: float, confidence: float = CONFIDENCE,
                  method: str = "linear") -> dict:
    """A percentile of a sample with its distribution-free confidence interval.

    The interval is [x_(l), x_(u)] of the sorted sample (1-based ranks), l and u - 1 the
    binomial(n, q) count's (1 - c)/2 and (1 + c)/2 quantiles: it holds the true
    q-quantile with probability at least about c whatever the distribution.

    Parameters
    ----------
    values : array_like
        The sample, (n,).
    q : float
        The quantile, in (0, 1).
    confidence : float
        c, in (0, 1).
    method : str
        numpy's percentile method: "linear" interpolates, "lower" takes the sample value
        at or below (a count's, on its low side).

    Returns
    -------
    dict
        ``value`` (numpy's percentile by ``method``) and ``ci`` ([low, high]), both None
        when the interval's ranks pass the sample's ends; ``rings_needed``: the fewest
        samples whose interval stays inside.
    """
    from scipy.stats import binom

    x = np.sort(np.asarray(values, float))
    n = x.size
    needed = rings_needed(q, confidence)
    if n < needed:
        return {"value": None, "ci": None, "rings_needed": needed}
    lo = int(binom.ppf((1 - confidence) / 2, n, q))
    hi = int(binom.ppf((1 + confidence) / 2, n, q)) + 1
    return {"value": float(np.percentile(x, 100 * q, method=method)),  # type: ignore[call-overload]  # method: a str of numpy's Literal
            "ci": [float(x[lo - 1]), float(x[hi - 1])], "rings_needed": needed}


@functools.cache
def rings_needed(q: float, confidence: float = CONFIDENCE) -> int:
    """The fewest samples whose :func:`percentile_ci` interval of the q-quantile lies
    inside the sample (rank 1 to n): 6 for the median, 36 for P90 or P10, 368 for P99 or
    P1 at 95 %.

    Parameters
    ----------
    q, confidence : float
        As :func:`percentile_ci`.

    Returns
    -------
    int
    """
    from scipy.stats import binom

    n = np.arange(1, MAX_SAMPLES + 1)
    ok = ((binom.ppf((1 - confidence) / 2, n, q) >= 1)
          & (binom.ppf((1 + confidence) / 2, n, q) + 1 <= n))
    return int(n[np.argmax(ok)]) if ok.any() else MAX_SAMPLES + 1


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


def tolerance_analysis(case: Case, *, samples: int = 200, seed: int = 0, positions: int = 36,
                       workers: int = 1, scheduler=None, share_samples: int | None = None,
                       overrides: dict | None = None, progress: bool = True,
                       cache=True, points=None) -> ToleranceResult:
    """The tolerance ensemble of a case.

    Parameters
    ----------
    case : toothfem.case.Case
        With a ``[tolerances]`` section (at least one nonzero zone).
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
        ``samples``, at least 20); 0 for none.
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
    n_share = max(20, int(samples) // 4) if share_samples is None else int(share_samples)
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


def check_limits(result: ToleranceResult, si) -> tuple:
    """The ensemble against the case's limits (:mod:`toothfem.limits`, each check done
    there): the largest Hertz pressure of the nominal design and of each percentile given
    (:func:`toothfem.limits.contact_pressure`), the lowest film ratio likewise
    (:func:`toothfem.limits.film_ratio`, low side), and the operating output torque
    against the rating (:func:`toothfem.limits.rated_torque`).

    Parameters
    ----------
    result : ToleranceResult
        Its nominal, samples and film ratios.
    si : toothfem.si.CaseSI
        The case: its material and operating limits.

    Returns
    -------
    found : list of toothfem.limits.Exceeded
        Each limit passed, its quantity naming the contacts, the model and which figure
        (the nominal design, or "P90 of 200 built reducers" with its 95 % interval).
    drawn : dict
        {output: [{"name", "value", "unit", "source"}]}: the limits to mark on the
        outputs' pictures (the allowable and static contact stress on the pressure's).
    """
    n = next((v.size for v in result.samples.values()), 0)
    where = f"the {result.contact_name} contacts in the reducer (system model)"

    def at(q, p=None, unit=""):
        if q is None:
            return "the nominal design"
        ci = "" if p is None or p.get("ci") is None else \
            f" (95 % interval {p['ci'][0]:.4g} to {p['ci'][1]:.4g} {unit})"
        return f"{q} of {n} built reducers{ci}"

    found = list(limits.rated_torque(si, result.settings.get(
        "operating_output_torque_Nm", 0.0)))
    found += limits.contact_pressure(f"{where}, {at(None)}", result.nominal["max_ph_MPa"],
                                     si.material)
    for q, p in result.percentiles().get("max_ph_MPa", {}).items():
        if p["value"] is not None:
            found += limits.contact_pressure(f"{where}, {at(q, p, 'MPa')}", p["value"],
                                             si.material)
    pct = result.film_ratio_percentiles()
    for contacts, rec in result.film_ratio.items():
        if rec["nominal"] is not None:
            found += limits.film_ratio(f"{contacts}, {at(None)}", rec["nominal"])
        for q, p in pct.get(contacts, {}).items():
            if p["value"] is not None:
                found += limits.film_ratio(f"{contacts}, {at(q)}", p["value"])
    return found, {"max_ph_MPa": limits.contact_pressure_lines(si.material)}


#: Key of the shares' last row: the one-tolerance variances summed, over the whole
#: ensemble's (1: the tolerances add up; above 1 they mask each other, as when one
#: tolerance's interference already decides which pins carry; below 1 they compound).
ALONE_OVER_ALL = "sum_alone_over_all"


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
                       unit="ring", enabled=progress)
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
