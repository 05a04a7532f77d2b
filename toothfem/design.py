"""Profile-modification design on the contact model (``toothfem design``).

The search varies the disc's equidistant, move-distance and rotation modifications within
the bounds of the case's ``[design]`` section. A candidate is solved with the influence
tables of the case's own disc and the candidate's initial gaps (a modification of a few
micrometres changes the gaps, not the compliance: docs/tolerance.md), so it costs three
complementarity solves per position: the backlash (the closing rotations of both flanks at
vanishing torque), the largest Hertz pressure and the fewest pins in contact at the peak
member torque. With ``percentile`` set, each candidate is solved for ``samples`` reducers
built within ``[tolerances]`` (the same draws for every candidate) and judged at that
percentile. A quasi-random design of experiments (scipy.stats.qmc Sobol) maps the space
and gives the trade-off between backlash and pressure; scipy.optimize.minimize (Powell,
bounded) refines the best feasible point. The winner is solved again with its own FE
tables (both flanks) for its datasheet figures.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from . import limits
from .case import Case, as_case
from .errors import CaseError, check_range
from .units import PA_PER_MPA
from .efficiency.no_load import path_friction
from .efficiency import rated_output_torque
from .fem.datasheet.sheet import datasheet
from .fem.drives import drive_for
from .fem.system.datasheet import SystemTwist, system_backlash_arcmin

#: Points of the design of experiments (a power of two: Sobol balance), the seed of its
#: scrambling, and the evaluations the refinement may add.
DOE_POINTS, DOE_SEED, REFINE_EVALUATIONS = 32, 0, 40
#: Penalty per unit of a target's relative violation, in units of the pressure objective.
PENALTY = 1e3


@dataclass(frozen=True, kw_only=True)
class Candidate:
    """One modification and what it gives (at the percentile, when one is set)."""
    modification: dict          # [cycloid] keys -> value (mm, deg)
    backlash_arcmin: float
    max_ph_MPa: float
    contacts_min: float
    feasible: bool


@dataclass(frozen=True, kw_only=True)
class DesignResult:
    """The search: every ``candidates`` evaluated (design of experiments, then the
    refinement), the ``best`` feasible one, its ``datasheet`` summary with its own FE
    tables, its ``case`` and the targets."""
    case_name: str
    targets: dict
    candidates: list
    best: Candidate
    datasheet: dict
    check: dict
    case: Case
    output_torque_Nm: float | None = None      # the declared output torque searched at
    member_torque_Nm: float | None = None      # its peak member torque (one disc held)
    warnings: tuple = ()                       # toothfem.limits.Exceeded: the best's
    limits: dict = dataclasses.field(default_factory=dict)   # {"max_ph_MPa": [...]} drawn

    def table(self) -> list:
        """The search's rows: the targets, the best modification and its figures.

        Returns
        -------
        list of (quantity, unit, {column: value})
            (:func:`toothfem.report.design.summary_rows`).
        """
        from .report.design import summary_rows
        return summary_rows(self.summary())

    def plot(self) -> dict:
        """The trade-off picture.

        Returns
        -------
        dict
            File name -> matplotlib Figure (:func:`toothfem.report.design.tradeoff`).
        """
        from .report.design import tradeoff
        return {"tradeoff.png": tradeoff(self)}

    def write(self, folder, source_text: str) -> dict:
        """The search's files into an existing ``folder``, with the case file to use.

        Parameters
        ----------
        folder : path
        source_text : str
            The case file's text; ``best_case.toml`` is it with the best modification.

        Returns
        -------
        dict
            The summary with the files written (:func:`toothfem.report.design.write_design`).
        """
        from .report.design import write_design
        return write_design(self, folder, source_text)

    def pareto(self) -> list:
        """The trade-off between backlash and pressure.

        Returns
        -------
        list of Candidate
            The candidates no other beats in both backlash and pressure (with the contacts
            target met), by increasing backlash.
        """
        ok = [c for c in self.candidates if c.contacts_min >= self.targets["min_contacts"]]
        ok.sort(key=lambda c: (c.backlash_arcmin, c.max_ph_MPa))
        front, best_ph = [], math.inf
        for c in ok:
            if c.max_ph_MPa < best_ph:
                front.append(c)
                best_ph = c.max_ph_MPa
        return front

    def summary(self) -> dict:
        """The search as summary.json holds it.

        Returns
        -------
        dict
            Targets, the best candidate, its datasheet and own-table check, the number of
            evaluations and the Pareto front.
        """
        return {"case": self.case_name, "targets": self.targets,
                "output_torque_Nm": self.output_torque_Nm,
                "member_torque_Nm": self.member_torque_Nm,
                "percentile_interval": percentile_interval(self.targets),
                "best": dataclasses.asdict(self.best), "datasheet": self.datasheet,
                "check_with_own_tables": self.check, "evaluations": len(self.candidates),
                "pareto": [dataclasses.asdict(c) for c in self.pareto()],
                "limits": self.limits, "warnings": [w.as_dict() for w in self.warnings]}


def check_limits(si, targets: dict, best: Candidate, check: dict,
                 output_torque_Nm: float) -> tuple:
    """The best design against the case's limits (:mod:`toothfem.limits`, each check done
    there): its largest Hertz pressure as drawn (its own FE tables) and at the search's
    percentile (:func:`toothfem.limits.contact_pressure`), and the output torque against
    the rating (:func:`toothfem.limits.rated_torque`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        The case: its material and ratings.
    targets : dict
        The [design] section as a dict (its ``percentile``, ``samples``).
    best : Candidate
        The best candidate (at the percentile, with one).
    check : dict
        Its figures as drawn with its own tables (``max_ph_MPa``).
    output_torque_Nm : float
        The output torque searched at [N m].

    Returns
    -------
    found : list of toothfem.limits.Exceeded
    drawn : dict
        {"max_ph_MPa": [{"name", "value", "unit", "source"}]}: the contact stress limits
        for the picture.
    """
    where = "the pin contacts of one disc held at the peak member torque, the best design"
    found = list(limits.rated_torque(si, output_torque_Nm))
    found += limits.contact_pressure(f"{where} as drawn (nominal)", check["max_ph_MPa"],
                                     si.material)
    iv = percentile_interval(targets)
    if iv is not None:
        at = f"P{iv['percentile']:g} of {iv['samples']} built reducers" + (
            "" if iv["has_interval"] else
            f" (no 95 % interval: a P{iv['percentile']:g} needs {iv['rings_needed']})")
        found += limits.contact_pressure(f"{where} at {at}", best.max_ph_MPa, si.material)
    return found, {"max_ph_MPa": limits.contact_pressure_lines(si.material)}


def percentile_interval(targets: dict) -> dict | None:
    """Whether the search's percentile, taken of ``samples`` reducers per candidate, has a
    95 % confidence interval (:func:`toothfem.tolerance_result.rings_needed`: a P90 needs 36
    reducers, as its contacts' P10), and the words that say so.

    Parameters
    ----------
    targets : dict
        The [design] section as a dict (``percentile``, ``samples``).

    Returns
    -------
    dict or None
        None without a percentile; else ``percentile``, ``samples``, ``rings_needed``,
        ``has_interval`` and ``text`` ("P90 of 8 built reducers: no 95 % interval (a P90
        needs 36)").
    """
    from .tolerance_result import rings_needed

    q = targets.get("percentile")
    if q is None:
        return None
    n = int(targets.get("samples") or 0)
    needed = max(rings_needed(q / 100), rings_needed(1 - q / 100))
    head = f"P{q:g} of {n} built reducers"
    text = (f"{head}: no 95 % interval (a P{q:g} needs {needed}; design.samples sets them)"
            if n < needed else f"{head} (a 95 % interval needs {needed}: met)")
    return {"percentile": q, "samples": n, "rings_needed": needed,
            "has_interval": n >= needed, "text": text}


def design_analysis(case: Case, *, positions: int = 18, progress: bool = True) -> DesignResult:
    """Search the modifications of a cycloid disc against the case's ``[design]`` targets.

    Parameters
    ----------
    case : toothfem.case.Case
        A cycloid or RV case with a ``[design]`` section (``[tolerances]`` too when its
        ``percentile`` is set).
    positions : int
        Meshing positions over one period for every candidate.
    progress : bool
        A tqdm bar on stderr (on a terminal only: toothfem.bars).

    Returns
    -------
    DesignResult

    Raises
    ------
    CaseError
        When no candidate within the bounds meets the targets (naming the target missed and
        by how much), or the case lacks [design], [cycloid] or, with a percentile, a
        nonzero tolerance.
    """
    case = as_case(case)
    from scipy.optimize import minimize
    from scipy.stats import qmc
    from .bars import bar as progress_bar

    if case.design is None:
        raise CaseError("[design] section is required (targets: max_backlash_arcmin, "
                        "min_contacts, max_ph_MPa, percentile)")
    layout = case.layout
    if not layout.design_keys or getattr(case, layout.stage_section, None) is None:
        raise CaseError(f"drive = {case.drive!r}: toothfem design searches the cycloid "
                        "disc's modifications; this case has no [cycloid] section")
    check_range("positions", positions, 2, 3600, error=CaseError)
    target = case.design
    drive = drive_for(case)
    si = case.to_si()
    solver = drive.cycle_solver(positions, solver_options=drive.both_flanks_options)
    solver.prepare()
    supports = drive.supports(si.supports)
    system = drive.system_model(supports, positions)   # on the search's tables
    t_out = si.declared_output_torque_Nm()
    if t_out is None:                # Case refuses it (every case declares a load)
        raise CaseError("[operating] needs an output torque for the modification search")
    torque = drive.member_torque(t_out)
    deviations = [None]
    if target.percentile is not None:
        if not si.tolerances.active():
            raise CaseError(f"design.percentile = {target.percentile!r} needs a "
                            "[tolerances] section with a nonzero zone")
        rng = np.random.default_rng(DOE_SEED)
        deviations = [drive.sample_deviation(si.tolerances, rng)
                      for _ in range(target.samples)]
    bounds = target.bounds()
    names = list(bounds)
    lo = np.array([bounds[k][0] for k in names])
    hi = np.array([bounds[k][1] for k in names])
    base = getattr(si, layout.stage_section).geometry      # the stage's SI geometry
    # a built reducer's positions spread over its pairing period (toothfem.tolerance)
    pitches = (np.arange(positions) * drive.pairing_period_pitches) // positions
    evaluated = []
    bar = progress_bar(total=DOE_POINTS + REFINE_EVALUATIONS, desc="design",
                       unit="candidate", enabled=progress)

    def evaluate(x, devs=None, record=True) -> Candidate:
        mod = {k: float(v) for k, v in zip(names, x)}
        keys = layout.design_keys
        geom = dataclasses.replace(base, **{keys[k][0]: v * keys[k][1]
                                            for k, v in mod.items()})
        backlash, ph, contacts = [], [], []
        for dev in deviations if devs is None else devs:
            opts = {"deviation": dev, "geometry": geom, "pitches": pitches}
            backlash.append(system_backlash_arcmin(system, deviation=dev, geometry=geom,
                                                   pitches=pitches))
            ls = solver.solve(torque, **opts)
            ph.append(float(np.max(ls.ph)) / PA_PER_MPA)
            contacts.append(float(np.min(ls.contacts_per_position)))
        q = target.percentile if target.percentile is not None else 50.0
        cand = Candidate(modification=mod,
                         backlash_arcmin=float(np.percentile(backlash, q)),
                         max_ph_MPa=float(np.percentile(ph, q)),
                         contacts_min=float(np.percentile(contacts, 100 - q)),
                         feasible=False)
        cand = dataclasses.replace(cand, feasible=not _violations(cand, target))
        if record:
            evaluated.append(cand)
            bar.update()
        return cand

    def objective(x):
        c = evaluate(np.clip(x, lo, hi))
        return _score(c, target)

    try:
        doe = qmc.scale(qmc.Sobol(len(names), seed=DOE_SEED).random(DOE_POINTS), lo, hi) \
            if np.any(hi > lo) else lo[None, :]
        for x in doe:
            evaluate(x)
        start = min(evaluated, key=lambda c: _score(c, target))
        x0 = np.array([start.modification[k] for k in names])
        free = hi > lo
        if np.any(free) and REFINE_EVALUATIONS > 0:
            minimize(objective, x0, method="Powell",
                     bounds=list(zip(lo, hi)), options={"maxfev": REFINE_EVALUATIONS,
                                                        "xtol": 1e-4, "ftol": 1e-4})
    finally:
        bar.close()
    feasible = [c for c in evaluated if c.feasible]
    if not feasible:
        closest = min(evaluated, key=lambda c: sum(_violations(c, target).values()))
        raise CaseError(_infeasible(closest, target))
    best = min(feasible, key=lambda c: c.max_ph_MPa)
    best_case = _with_modification(case, layout.stage_section, best.modification)
    nominal = evaluate([best.modification[k] for k in names], devs=[None], record=False)
    sheet, check = _verify(best_case, nominal, positions, torque)
    targets = dataclasses.asdict(target)
    found, drawn = check_limits(si, targets, best, check, t_out)
    return DesignResult(case_name=case.name, targets=targets,
                        candidates=evaluated, best=best, datasheet=sheet, check=check,
                        case=best_case, output_torque_Nm=t_out,
                        member_torque_Nm=float(torque), warnings=tuple(found), limits=drawn)


def _misses(c: Candidate, target) -> dict:
    """{target: (reached, limit, scale)} of the targets a candidate misses; the shortfall
    over ``scale`` is its relative violation."""
    out = {}
    backlash = target.max_backlash_arcmin
    if c.backlash_arcmin > backlash:
        out["design.max_backlash_arcmin"] = (c.backlash_arcmin, backlash, backlash)
    if c.backlash_arcmin < 0:          # interference: the stage cannot be assembled freely
        out["a backlash >= 0 (no interference)"] = (c.backlash_arcmin, 0.0, backlash)
    if c.contacts_min < target.min_contacts:
        out["design.min_contacts"] = (c.contacts_min, target.min_contacts,
                                      target.min_contacts)
    if target.max_ph_MPa is not None and c.max_ph_MPa > target.max_ph_MPa:
        out["design.max_ph_MPa"] = (c.max_ph_MPa, target.max_ph_MPa, target.max_ph_MPa)
    return out


def _violations(c: Candidate, target) -> dict:
    """{target: relative violation > 0} of a candidate."""
    return {k: abs(r - lim) / scale for k, (r, lim, scale) in _misses(c, target).items()}


def _score(c: Candidate, target) -> float:
    return c.max_ph_MPa + PENALTY * sum(_violations(c, target).values())


def _infeasible(c: Candidate, target) -> str:
    """One line: the targets the closest candidate misses, and by how much."""
    parts = [f"{k} = {lim:g} (reached {r:.4g}, off by {abs(r - lim):.3g})"
             for k, (r, lim, _) in _misses(c, target).items()]
    mod = ", ".join(f"{k} = {v:.4g}" for k, v in c.modification.items())
    return ("no modification within the [design] bounds meets the targets: the closest ("
            + mod + ") misses " + "; ".join(parts))


def _with_modification(case: Case, section: str, modification: dict) -> Case:
    """The case with the modification keys set in its stage's ``section`` (checked present
    by :func:`design_analysis`)."""
    stage = dataclasses.replace(getattr(case, section), **modification)
    return dataclasses.replace(case, **{section: stage})


def _verify(case: Case, nominal: Candidate, positions: int, torque: float):
    """The winner with its own FE tables: its datasheet (rigidity, lost motion, backlash)
    and its nominal pressure, contacts and backlash beside those the search's tables give
    for the same nominal geometry (the error of solving a candidate on the case's tables)."""
    drive = drive_for(case)
    si = case.to_si()
    rated, assumed = rated_output_torque(si)
    solver = drive.cycle_solver(positions, solver_options=drive.both_flanks_options)
    supports = drive.supports(si.supports)
    sheet = datasheet(SystemTwist(drive.system_model(supports, positions),
                                  friction=path_friction(si, drive)), rated,
                      rated_assumed=assumed)
    ls = solver.solve(torque)
    check = {"max_ph_MPa": float(np.max(ls.ph)) / PA_PER_MPA,
             "contacts_min": float(np.min(ls.contacts_per_position)),
             "backlash_arcmin": sheet.backlash_arcmin,
             "search_tables_max_ph_MPa": nominal.max_ph_MPa,
             "search_tables_contacts_min": nominal.contacts_min,
             "search_tables_backlash_arcmin": nominal.backlash_arcmin}
    summary = sheet.summary()
    return {k: summary[k] for k in ("rated_torque_Nm", "torsional_rigidity_Nm_per_arcmin",
                                    "lost_motion_arcmin", "backlash_arcmin")
            if k in summary}, check


