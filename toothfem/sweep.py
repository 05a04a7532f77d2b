"""Design sweeps: designs x load cases x meshing positions, run through Dask.

``sweep(case, vary, ...)`` varies case keys (``cycloid.eccentricity_mm``,
``material.youngs_modulus_GPa``, ``operating.output_torque_Nm`` ...). Keys of the
``[operating]`` section and ``torques_Nm`` make the load cases; every other key makes the
designs; the sweep runs the Cartesian product of each. Every design x load case gives one
row of ``sweep.csv``.

How the work is split (docs/architecture.md): one Dask task per design, which does the setup
its load cases share (cycloid disc: meshes, factorisation and the influence tables of the
cycle mode over ``positions`` crank angles, through
:class:`~toothfem.fem.cycloid_fe.CycleSolver`; sine: the FE cycle solver or the meshing
state) and then solves every load case on it. Designs that differ only in keys the contact
does not read (friction, lubricant ...) share one task. The influence tables also go to the
disk cache (:mod:`toothfem.fem.cache`) under a hash of their content, so a repeated sweep
costs no new factorisation. Independent tasks keep both workers busy without round trips
(Dask queues them and a worker starts its next design at once); a design's rows arrive
together when it finishes.

Every row is kept on disk as its task finishes: appended and synced to the journal in a
folder of its own beside ``out`` (:func:`toothfem.output.resumable_dir`; an earlier result
in ``out`` stays whole until the sweep completes), so a sweep stopped in
any way (Ctrl-C, SIGTERM, SIGKILL, a lost cluster: :mod:`toothfem.cluster`) keeps every
finished point, and the same command resumes it, computing only the rest. The tables
``sweep.csv`` and ``sweep.json`` are written when every point has run
(``toothfem.output.atomic_dir``). A point that fails (a design the case refuses, a solver
error, a worker that died on it) is a row with ``status = failed`` and its one-line error;
the sweep goes on, and a resumed sweep tries it again.

Sine drives: the FE cycle mode of ``toothfem.fem.sine_fe`` (``loads = fem``, default), or
with ``sine_loads = "analytic"`` the seeds' analytic load split on the geometry's meshing
state (``loads = analytic``). Rows of a cycloid disc (cycloid and RV drives) always say
``fem``.
"""
from __future__ import annotations

import copy
import csv
import dataclasses
import itertools
import json
import math
import threading
import time
import uuid
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from .case import Case, as_case, case_to_dict, parse_case
from .cluster import as_finished, dask_client
from .efficiency import operating_point
from .fem.cache import DiskCache, content_key
from .fem.drives import Drive, drive_for
from .fem.drives.sine import SINE_IN_MESH_GAP_M
from .errors import CaseError, ToothfemError, check_range
from .output import atomic_dir, reserved, resumable_dir, target
from .report import html as report_html
from .units import UM_PER_M


#: Columns after the design keys and load-case keys, in this order; ``{contacts}`` is the
#: drive's word (pins, teeth: :attr:`~toothfem.fem.drives.Drive.contacts_name`).
RESULT_COLUMNS = ("output_torque_Nm", "loads", "max_force_N", "{contacts}_in_contact_max",
                  "max_ph_MPa", "transmission_error_arcsec", "setup_s", "time_s", "status",
                  "error")


def result_columns(drive) -> list:
    """:data:`RESULT_COLUMNS` in the words of ``drive`` (a Drive).

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        Names its contacts.

    Returns
    -------
    list of str
        The column names of sweep.csv.
    """
    return [c.format(contacts=drive.contacts_name) for c in RESULT_COLUMNS]

#: Largest number of meshing positions per design.
MAX_POSITIONS = 3600

_LOAD_SECTION = "operating"


@dataclass(frozen=True)
class SweepResult:
    """What a sweep wrote: ``out`` (folder), ``table`` (its sweep.csv) and the rows, one
    mapping per design x load case in the order they arrived."""
    out: Path
    table: Path
    rows: tuple
    failed: int
    resumed: int
    wall_s: float


def sweep(case, vary: Mapping[str, Sequence], *, torques_Nm: Sequence[float] | None = None,
          positions: int = 36, pins: str | None = None, scheduler=None,
          n_workers: int | None = None, out, cache_dir=None, progress: bool = True,
          on_row: Callable[[dict], Any] | None = None,
          sine_loads: str = "fem") -> SweepResult:
    """Run designs x load cases x meshing positions through Dask; write ``out/sweep.csv``.

    Parameters
    ----------
    case : toothfem.case.Case or str or pathlib.Path
        The case or the path of a case file: a sine drive or any drive with a
        ``[cycloid]`` disc (cycloid, RV).
    vary : Mapping of str to sequence
        Dotted case key -> values; ``operating.*`` keys are load cases, all others designs.
    torques_Nm : sequence of float, optional
        Reducer output torques [N m] as further load cases (a cycloid disc carries
        disc_load_factor * T / disc_count, as in ``toothfem contact``). Without them the
        torque is the load case's ``operating.output_torque_Nm``, else the output torque its
        input torque or power gives through the efficiency model
        (``efficiency.operating_point``, as ``toothfem contact`` and ``run``).
    positions : int
        Meshing positions over one pin (cycloid disc) or ring-tooth (sine) pitch.
    pins : str, optional
        Cycloid pin structure override (conventional, integral, rigid).
    scheduler : str or distributed.Client, optional
        None for a LocalCluster of ``n_workers`` single-threaded processes, a scheduler
        address, or a ``distributed.Client``.
    n_workers : int, optional
        Processes of the local cluster (default: one per CPU).
    out : str or pathlib.Path
        The output folder: the tables at the end (the finished points as they arrive in
        a journal folder beside it, :func:`toothfem.output.journal_folder`); an unfinished
        sweep of the same case and settings into it is resumed. Held against other runs
        for the sweep's life: a second run into it is refused at once.
    cache_dir : str or pathlib.Path or None or False
        The disk cache of influence tables; None: ``$TOOTHFEM_CACHE`` or
        ``~/.cache/toothfem``; False: none.
    progress : bool
        Show a progress bar.
    on_row : callable, optional
        ``on_row(row)`` is called after each row is written and flushed.
    sine_loads : {"fem", "analytic"}
        The sine pair's load split.

    Returns
    -------
    SweepResult
        The folder, its sweep.csv, the rows (those of a resumed run first), the failed
        count, the points resumed and the wall time [s].

    Raises
    ------
    CaseError
        Before any work for an unknown key (naming the valid keys of its section), a value
        outside its key's own range, or a bad argument; a design refused only in
        combination (a looped profile, say) is a failed row.
    """
    from .bars import bar as progress_bar


    case_file = None if isinstance(case, Case) else case
    case = as_case(case)
    target(out)                                  # a bad out refused before any work
    plan = _plan(case, vary, torques_Nm, positions, pins, sine_loads)
    cache = _cache(cache_dir)
    if scheduler is not None and n_workers is not None:
        raise CaseError("n_workers applies to the local cluster; a scheduler brings its own "
                        "workers")
    if n_workers is not None:
        check_range("n_workers", n_workers, 1, 1024, error=CaseError)
    columns = (["design", "load_case"] + plan.design_keys + plan.load_keys
               + result_columns(drive_for(case)))
    key = content_key("sweep", case, plan.values,
                      None if torques_Nm is None else [float(t) for t in np.ravel(torques_Nm)],
                      plan.positions, pins, plan.loads)
    with reserved(out):      # the name held for the run: a second run is refused
        t0 = time.perf_counter()
        with resumable_dir(out, key) as points:
            rows = [r for r in points.done.values() if r["status"] == "ok"]
            finished = {_point(r["design"], r["load_case"]) for r in rows}
            with dask_client(scheduler, n_workers) as client, \
                    progress_bar(total=len(plan.designs) * len(plan.load_cases),
                                 initial=len(rows), desc="sweep", unit="point",
                                 enabled=progress) as bar:
                def emit(row):
                    points.record(_point(row["design"], row["load_case"]), row)
                    rows.append(row)
                    bar.update()
                    if on_row is not None:
                        on_row(row)

                _run(client, plan, cache, emit, finished)
                workers = len(client.nthreads())
                address = "local" if scheduler is None else client.scheduler.address
        # the final table is in design, load-case order, so that two runs give the same file
        # apart from the timing columns (issue 14)
        rows.sort(key=lambda r: (r["design"], r["load_case"]))
        failed = sum(r["status"] != "ok" for r in rows)
        summary = {
            "case": case.name, "drive": case.drive,
            "loads": plan.loads, "vary": plan.values,
            "torques_Nm": None if torques_Nm is None else [float(t) for t in
                                                           np.ravel(torques_Nm)],
            "positions": plan.positions, "pins": pins, "designs": len(plan.designs),
            "load_cases": len(plan.load_cases), "rows": len(rows), "failed": failed,
            "resumed": len(finished), "wall_s": time.perf_counter() - t0,
            # a local cluster's address changes from run to run (a free port)
            "scheduler": address, "workers": workers,
            "cache_dir": None if cache is None else str(cache.directory),
            "files": ["sweep.csv", "sweep.json"]}
        if plan.loads == "analytic":
            summary["sine_in_mesh_gap_um"] = SINE_IN_MESH_GAP_M * UM_PER_M
        with atomic_dir(out) as tmp:
            with open(tmp / "sweep.csv", "w", newline="") as fh:
                writer = csv.DictWriter(fh, columns)
                writer.writeheader()
                writer.writerows({k: _cell(v) for k, v in row.items()} for row in rows)
            (tmp / "sweep.json").write_text(json.dumps(summary, indent=2))
            report_html.write_report(tmp, case, command="sweep", case_file=case_file, tables=[
                report_html.Table.of_csv("one row per design and load case", tmp / "sweep.csv")])
    out = Path(out)
    return SweepResult(out, out / "sweep.csv", tuple(rows), failed, len(finished),
                       summary["wall_s"])


def _point(design: int, load_case: int) -> str:
    """A row's name in the journal."""
    return f"{design}/{load_case}"


# ---------------------------------------------------------------------------------------
# The plan: designs and load cases, validated on the driver

@dataclass(frozen=True)
class _Plan:
    case: Case
    design_keys: list
    load_keys: list
    designs: list            # [(values, Case or the CaseError that refused it)]
    load_cases: list         # [(values, output torque or None, operating changes)]
    positions: int
    pins: str | None
    values: dict             # key -> the checked values (plain Python numbers, strings)
    loads: str               # "fem" or "analytic"


def _plan(case: Case, vary, torques_Nm, positions, pins, sine_loads="fem") -> _Plan:
    try:
        drive = drive_for(case)
    except CaseError:
        raise CaseError(f"drive = {case.drive!r} without a [cycloid] disc: the sweep handles "
                        "sine drives and drives with a cycloid disc") from None
    if sine_loads not in ("fem", "analytic"):
        raise CaseError(f"sine_loads = {sine_loads!r} is not one of ['fem', 'analytic']")
    # the analytic split as a sweep's load source is offered where it sees the
    # modifications (the sine pair's in-mesh gap; the cycloid's seed split ignores them:
    # an infinite gap, no sweep needed)
    sees_gaps = math.isfinite(drive.analytic_in_mesh_gap_m)
    loads = "analytic" if sees_gaps and sine_loads == "analytic" else "fem"
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    if isinstance(positions, bool) or int(positions) != positions:
        raise CaseError(f"positions = {positions!r} must be an integer")
    if pins is not None:
        choices = drive.fe_options.get("pin_structure")
        if choices is None:
            raise CaseError(f"pins = {pins!r} applies to cycloid discs, not to drive = "
                            f"{case.drive!r}")
        if pins not in choices:
            raise CaseError(f"pins = {pins!r} is not one of {list(choices)}")
    if not isinstance(vary, Mapping):
        raise CaseError(f"vary must map case keys to lists of values, got "
                        f"{type(vary).__name__}")
    checked = {}
    for key, values in vary.items():
        if isinstance(values, np.ndarray):
            values = values.tolist()
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or not values:
            raise CaseError(f"{key}: give a non-empty list of values, got {values!r}")
        parts = _resolve(case, key)
        checked[key] = (parts, [_check_value(case, parts, v) for v in values])
    load_keys = [k for k, (parts, _) in checked.items() if parts[0] == _LOAD_SECTION]
    design_keys = [k for k in checked if k not in load_keys]
    torque_keys = {"operating.output_torque_Nm", "operating.input_torque_Nm",
                   "operating.input_power_kW"} & set(load_keys)
    if isinstance(torques_Nm, np.ndarray):
        torques_Nm = torques_Nm.tolist()
    if torques_Nm is not None:
        if isinstance(torques_Nm, (str, bytes)) or not isinstance(torques_Nm, Sequence) \
                or not torques_Nm:
            raise CaseError(f"torques_Nm: give a non-empty list, got {torques_Nm!r}")
        for t in torques_Nm:
            check_range("torques_Nm", t, 0, None, lo_open=True, error=CaseError)
        if torque_keys:
            raise CaseError(f"give the torque one way: torques_Nm or {sorted(torque_keys)[0]}")
    base = case_to_dict(case)
    designs = []
    for combo in itertools.product(*(checked[k][1] for k in design_keys)):
        changes = {checked[k][0]: v for k, v in zip(design_keys, combo)}
        designs.append((dict(zip(design_keys, combo)), _design(base, case, changes)))
    load_cases = []
    for combo in itertools.product(torques_Nm or [None],
                                   *(checked[k][1] for k in load_keys)):
        ops = {checked[k][0][1]: v for k, v in zip(load_keys, combo[1:])}
        load_cases.append((dict(zip(load_keys, combo[1:])), combo[0], ops))
    return _Plan(case, design_keys, load_keys, designs, load_cases, int(positions), pins,
                 {k: v for k, (_, v) in checked.items()}, loads)


def _sections(case: Case) -> list:
    return [f.name for f in dataclasses.fields(case)
            if dataclasses.is_dataclass(getattr(case, f.name))]


def _leaf_keys(obj, prefix="") -> list:
    out = []
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if dataclasses.is_dataclass(v):
            out += _leaf_keys(v, f"{prefix}{f.name}.")
        else:
            out.append(prefix + f.name)
    return out


def _resolve(case: Case, key: str) -> tuple:
    """The path of a dotted case key, e.g. ('cycloid', 'disc_holes', 'crank_hole_count')."""
    if not isinstance(key, str):
        raise CaseError(f"{key!r}: case keys are dotted strings like 'cycloid.eccentricity_mm'")
    parts = tuple(key.split("."))
    sections = _sections(case)
    if len(parts) < 2 or parts[0] not in sections:
        raise CaseError(f"{key} is not a key of a section of this case "
                        f"(drive = {case.drive!r}); sections: {sections}")
    section = getattr(case, parts[0])
    valid = _leaf_keys(section)
    if ".".join(parts[1:]) not in valid:
        raise CaseError(f"{key} is not a known key; valid keys of [{parts[0]}]: {valid}")
    return parts


def _check_value(case: Case, parts: tuple, value):
    """``value`` checked against its key's own type and range (the case's metadata and
    message); int -> float for float keys. Cross-key rules wait for the whole design."""
    obj = case
    for name in parts[:-1]:
        obj = getattr(obj, name)
    f = {f.name: f for f in dataclasses.fields(obj)}[parts[-1]]
    md, key = f.metadata, ".".join(parts)
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise CaseError(f"{key} = {value!r} must be a number or a string")
    if md.get("choices") is not None:
        if value not in md["choices"]:
            raise CaseError(f"{key} = {value!r} is not one of {list(md['choices'])}")
        return value
    if md.get("integer") and not isinstance(value, int):
        raise CaseError(f"{key} = {value!r} must be an integer")
    if f.type in ("float", "float | None", "int"):
        check_range(key, value, md.get("lo"), md.get("hi"), lo_open=md.get("lo_open", False),
                    hi_open=md.get("hi_open", False), error=CaseError, why=md.get("doc", ""))
        if f.type != "int":
            value = float(value)
    return value


def _design(base: dict, case: Case, changes: dict):
    """The case with ``changes`` ({path: value}) applied and validated, or the CaseError
    that refuses it. ``stated_ratio`` is dropped (a design may change tooth numbers); a
    housing radius that follows the default rule (Rz + 5 rz) keeps following it."""
    if not changes:
        return case
    d = copy.deepcopy(base)
    d["case"].pop("stated_ratio", None)
    st = case.cycloid
    if st is not None and st.housing_outer_radius_mm == st.pin_circle_radius_mm + \
            5 * st.pin_radius_mm:
        d["cycloid"].pop("housing_outer_radius_mm", None)
    for parts, value in changes.items():
        t = d
        for name in parts[:-1]:
            t = t.setdefault(name, {})
        t[parts[-1]] = value
    try:
        return parse_case(d)
    except CaseError as exc:
        return exc


def _cache(cache_dir):

    if cache_dir is False:
        return None
    return DiskCache() if cache_dir is None else DiskCache(Path(cache_dir))


# ---------------------------------------------------------------------------------------
# Submitting, and the tasks

def _run(client, plan: _Plan, cache, emit, finished=frozenset()) -> None:
    """Run the plan on ``client`` but the ``finished`` points, calling ``emit(row)`` as
    each row is known: first the rows refused on the driver, then those of each design
    task as it finishes."""
    prefix = f"toothfem-sweep-{uuid.uuid4().hex[:8]}"
    cache_dir = None if cache is None else str(cache.directory)
    pending = {}
    for key, design, jobs in _groups(plan, emit, finished):
        fut = client.submit(_design_task, design, plan.pins, plan.positions, cache_dir,
                            [member for _, member in jobs], plan.loads,
                            key=f"{prefix}-{key}", pure=False)
        pending[fut] = [base for base, _ in jobs]
    said = set()
    for fut in as_finished(client, list(pending)):
        bases = pending.pop(fut)
        try:
            results = fut.result()
        except Exception as exc:             # noqa: BLE001 -- recorded, the sweep goes on
            results = [{"status": "failed", "error": _message(exc)}] * len(bases)
        for base, result in zip(bases, results):
            for message, category in result.pop(_WARNINGS, ()):
                if message not in said:      # each once, on the driver (one line each)
                    said.add(message)
                    warnings.warn(message, category, stacklevel=1)
            emit({**base, **result})
        fut.release()


def _groups(plan: _Plan, emit, finished=frozenset()) -> list:
    """[(task key, design case, [(row base, member torque)])], one per setup key in the
    order of the designs, without the ``finished`` points; the rows refused on the driver
    are emitted here."""
    groups: dict[tuple[Drive, str | None], tuple[str, Case, list[tuple[dict, float]]]] = {}
    for d, (dvalues, design) in enumerate(plan.designs):
        for lc, (lvalues, torque, ops) in enumerate(plan.load_cases):
            if _point(d, lc) in finished:
                continue
            base = {"design": d, "load_case": lc, **dvalues, **lvalues, "loads": plan.loads,
                    "output_torque_Nm": math.nan if torque is None else float(torque)}
            try:
                if isinstance(design, Exception):
                    raise design
                loaded = dataclasses.replace(design, operating=dataclasses.replace(
                    design.operating, **ops))
                t_out = _output_torque(loaded, torque, set(ops))
                base["output_torque_Nm"] = t_out
                member = drive_for(loaded).member_torque(t_out)
            except ToothfemError as exc:
                emit(_failed(base, exc))
                continue
            skey = (drive_for(design), plan.pins)   # what the FE models read
            if skey not in groups:
                groups[skey] = (f"design-{d}", design, [])
            groups[skey][2].append((base, member))
    return list(groups.values())


def _output_torque(case: Case, torque, varied) -> float:
    """Reducer output torque of a load case [N m]: ``torque`` if given, else the output
    torque of its [operating] table (efficiency.operating_point); a varied input
    torque or power overrides a stated output torque."""
    if torque is not None:
        return float(torque)
    if varied & {"input_torque_Nm", "input_power_kW"} and "output_torque_Nm" not in varied:
        case = dataclasses.replace(case, operating=dataclasses.replace(
            case.operating, output_torque_Nm=None))
    return float(operating_point(case)[1])


_SETUP_LOCK = threading.Lock()
#: The key under which a task's result carries the warnings its setup gave (not a column).
_WARNINGS = "_warnings"


def _design_task(case: Case, pins, positions: int, cache_dir, member_torques,
                 loads: str) -> list:
    """Worker task: one design (or designs with one setup key) and all its load cases.

    The setup its load cases share comes first (cycloid disc: meshes, factorisation and
    influence tables through CycleSolver, from the disk cache when there; sine: the FE
    cycle solver, or the meshing state for the analytic split), then each load case on
    it. One result per torque on the moving member; a ToothfemError fails the rows it
    concerns, other exceptions propagate (Dask logs them, the driver records them)."""
    t0 = time.perf_counter()
    try:
        # gmsh keeps one model per process: one setup at a time; its warnings (a cache
        # that cannot be written) go back to the driver, which says each in one line
        with _SETUP_LOCK, warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            solve = _prepare(case, pins, positions, cache_dir, loads)
    except ToothfemError as exc:
        failed = {"setup_s": time.perf_counter() - t0, "status": "failed",
                  "error": _message(exc)}
        return [failed] * len(member_torques)
    told = [(str(w.message), w.category) for w in said]
    setup_s = time.perf_counter() - t0
    out = []
    for torque in member_torques:
        t1 = time.perf_counter()
        try:
            res = {**solve(torque), "status": "ok", "error": ""}
        except ToothfemError as exc:
            res = {"status": "failed", "error": _message(exc)}
        out.append({**res, "setup_s": setup_s, "time_s": time.perf_counter() - t1,
                    _WARNINGS: told})
    return out


def _prepare(case: Case, pins, positions: int, cache_dir, loads: str):
    """Do the work the load cases of a design share (the FE cycle solver's meshes,
    factorisations and influence tables, or the cache's; for the analytic split the
    meshing state); returns solve(member torque) -> the summary columns."""
    drive = drive_for(case)
    if loads == "analytic":
        state = drive.meshing(drive.positions(positions))
        return lambda torque: _summary(drive, drive.analytic_split(state, torque),
                                       transmission=False)
    overrides = {} if pins is None else {"pin_structure": pins}
    cache = False if cache_dir is None else DiskCache(Path(cache_dir))
    solver = drive.cycle_solver(positions, cache=cache, **overrides)
    solver.prepare()
    return lambda torque: _summary(drive, solver.solve(torque))


def _summary(drive, ls, transmission=True) -> dict:
    """The result columns of a LoadSharing; the analytic split has no transmission error."""
    out = ls.figures(drive.contacts_name)
    if not transmission:
        out["transmission_error_arcsec"] = math.nan
    return out


# ---------------------------------------------------------------------------------------
# Rows

def _failed(base: dict, exc: BaseException) -> dict:
    return {**base, "status": "failed", "error": _message(exc)}


def _message(exc: BaseException) -> str:
    """One line: toothfem's own errors as they read, others with their type."""
    msg = str(exc) if isinstance(exc, ToothfemError) else f"{type(exc).__name__}: {exc}"
    return " ".join(msg.split())


def _cell(v):
    if isinstance(v, float):
        return "" if not math.isfinite(v) else f"{v:.9g}"
    return v
