"""Design sweeps: designs x load cases x meshing positions, run through Dask.

``sweep(case, vary, ...)`` varies case keys (``cycloid.eccentricity_mm``,
``material.youngs_modulus_GPa``, ``operating.output_torque_Nm`` ...). Keys of the
``[operating]`` section and ``torques_Nm`` make the load cases; every other key makes the
designs; the sweep runs the Cartesian product of each. Every design x load case gives one
row of ``sweep.csv``.

How the work is split (DESIGN.md, Scale): per design one setup task (cycloid: meshes,
factorisation and the influence tables of the cycle mode over ``positions`` crank angles,
through :class:`~toothfem.fem.cycloid_fe.CycleSolver`; sine: the meshing state), and per
load case one small task that takes the setup's result, so the load cases of a design reuse
its factorisation wherever they run. The influence tables also go to the disk cache
(:mod:`toothfem.fem.cache`) under a hash of the design's content, so a repeated sweep, or a
design that differs only in keys the contact does not see (friction, lubricant ...), costs
no new factorisation.

Rows are written as the tasks finish (``as_completed``) and flushed one by one into a
temporary folder that becomes ``out`` only when the sweep ends (``toothfem.output.atomic_dir``):
a crash of the driver never leaves a half-written ``out``. A point that fails (a design the
case refuses, a solver error, a lost worker) is a row with ``status = failed`` and its one-line
error; the sweep goes on.

Sine drives have no FE contact model yet: their rows use the seeds' analytic load split on
the geometry's meshing state (``loads = analytic``; cycloid rows say ``fem``).
"""
from __future__ import annotations

import copy
import csv
import dataclasses
import functools
import itertools
import json
import math
import os
import threading
import time
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from .case import Case, case_to_dict, load_case, parse_case
from .errors import CaseError, ToothfemError, check_range

#: Sine pair, analytic split: the tooth pairs within this normal gap carry load. The sine
#: paper's Eqs. 16-19 sum over the z_s pairs "in mesh" without saying which; over a pitch of
#: the prototype 2 to 5 load-carrying pairs lie within 5 um, the order of the elastic approach
#: at the rated load (docs/derivations.md, S8). ASSUMPTION until the sine FE model exists.
SINE_IN_MESH_GAP_M = 5e-6

#: Columns after the design keys and load-case keys, in this order.
RESULT_COLUMNS = ("output_torque_Nm", "loads", "max_force_N", "pins_in_contact_max",
                  "max_ph_MPa", "transmission_error_arcsec", "setup_s", "time_s", "status",
                  "error")

#: Largest number of meshing positions per design.
MAX_POSITIONS = 3600

_LOAD_SECTION = "operating"
_DRIVES = ("cycloid", "sine")


@dataclass(frozen=True)
class SweepResult:
    """What a sweep wrote: ``out`` (folder), ``table`` (its sweep.csv) and the rows, one
    mapping per design x load case in the order they arrived."""
    out: Path
    table: Path
    rows: tuple
    failed: int
    wall_s: float


def sweep(case, vary: Mapping[str, Sequence], *, torques_Nm: Sequence[float] | None = None,
          positions: int = 36, pins: str | None = None, scheduler=None,
          n_workers: int | None = None, out, cache_dir=None, progress: bool = True,
          on_row: Callable[[dict], Any] | None = None) -> SweepResult:
    """Run designs x load cases x meshing positions through Dask; write ``out/sweep.csv``.

    ``case``: a :class:`~toothfem.case.Case` or the path of a case file (cycloid or sine).
    ``vary``: dotted case key -> values; ``operating.*`` keys are load cases, all others
    designs. ``torques_Nm``: reducer output torques [N m] as further load cases (a cycloid
    disc carries disc_load_factor * T / disc_count, as in ``toothfem contact``). Without
    them the torque is the case's ``operating.output_torque_Nm``, else its input torque
    times the ratio (lossless).
    ``positions``: meshing positions over one pin (cycloid) or ring-tooth (sine) pitch.
    ``pins``: cycloid pin structure override (conventional, integral, rigid).
    ``scheduler``: None for a LocalCluster of ``n_workers`` single-threaded processes
    (default: one per CPU), a scheduler address, or a ``distributed.Client``.
    ``cache_dir``: the disk cache of influence tables; None: ``$TOOTHFEM_CACHE`` or
    ``~/.cache/toothfem``; False: none.
    ``on_row(row)`` is called after each row is written and flushed.

    Raises CaseError before any work for an unknown key (naming the valid keys of its
    section), a value outside its key's own range, or a bad argument; a design refused only
    in combination (a looped profile, say) is a failed row.
    """
    from tqdm import tqdm

    from .output import atomic_dir

    if not isinstance(case, Case):
        case = load_case(case)
    plan = _plan(case, vary, torques_Nm, positions, pins)
    cache = _cache(cache_dir)
    if scheduler is not None and n_workers is not None:
        raise CaseError("n_workers applies to the local cluster; a scheduler brings its own "
                        "workers")
    if n_workers is not None:
        check_range("n_workers", n_workers, 1, 1024, error=CaseError)
    columns = (["design", "load_case"] + plan.design_keys + plan.load_keys
               + list(RESULT_COLUMNS))
    rows: list[dict] = []
    t0 = time.perf_counter()
    with atomic_dir(out) as tmp, _client(scheduler, n_workers) as client, \
            open(tmp / "sweep.csv", "w", newline="") as fh, \
            tqdm(total=len(plan.designs) * len(plan.load_cases), desc="sweep", unit="point",
                 disable=not progress) as bar:
        writer = csv.DictWriter(fh, columns)
        writer.writeheader()
        fh.flush()

        def emit(row):
            writer.writerow({k: _cell(v) for k, v in row.items()})
            fh.flush()
            rows.append(row)
            bar.update()
            if on_row is not None:
                on_row(row)

        pending = _submit(client, plan, cache, emit)
        from distributed import as_completed

        for fut in as_completed(list(pending)):
            base = pending.pop(fut)
            try:
                result = fut.result()
            except Exception as exc:             # noqa: BLE001 -- recorded, the sweep goes on
                emit(_failed(base, exc))
            else:
                emit({**base, **result, "status": "ok", "error": ""})
            fut.release()
        wall = time.perf_counter() - t0
        failed = sum(r["status"] != "ok" for r in rows)
        summary = {
            "case": case.name, "drive": case.drive,
            "loads": "fem" if case.drive == "cycloid" else "analytic",
            "vary": {k: list(v) for k, v in vary.items()},
            "torques_Nm": None if torques_Nm is None else list(torques_Nm),
            "positions": positions, "pins": pins, "designs": len(plan.designs),
            "load_cases": len(plan.load_cases), "rows": len(rows), "failed": failed,
            "wall_s": wall, "scheduler": client.scheduler.address,
            "workers": len(client.nthreads()),
            "cache_dir": None if cache is None else str(cache.directory),
            "files": ["sweep.csv", "sweep.json"]}
        if case.drive == "sine":
            summary["sine_in_mesh_gap_um"] = SINE_IN_MESH_GAP_M * 1e6
        (tmp / "sweep.json").write_text(json.dumps(summary, indent=2))
    out = Path(out)
    return SweepResult(out, out / "sweep.csv", tuple(rows), failed, wall)


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


def _plan(case: Case, vary, torques_Nm, positions, pins) -> _Plan:
    if case.drive not in _DRIVES:
        raise CaseError(f"drive = {case.drive!r}: the sweep handles {list(_DRIVES)} drives")
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    if isinstance(positions, bool) or int(positions) != positions:
        raise CaseError(f"positions = {positions!r} must be an integer")
    if pins is not None:
        from .fem.cycloid_fe import PIN_STRUCTURES

        if case.drive != "cycloid":
            raise CaseError(f"pins = {pins!r} applies to cycloid drives, not {case.drive!r}")
        if pins not in PIN_STRUCTURES:
            raise CaseError(f"pins = {pins!r} is not one of {list(PIN_STRUCTURES)}")
    if not isinstance(vary, Mapping):
        raise CaseError(f"vary must map case keys to lists of values, got "
                        f"{type(vary).__name__}")
    checked = {}
    for key, values in vary.items():
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or not values:
            raise CaseError(f"{key}: give a non-empty list of values, got {values!r}")
        parts = _resolve(case, key)
        checked[key] = (parts, [_check_value(case, parts, v) for v in values])
    load_keys = [k for k, (parts, _) in checked.items() if parts[0] == _LOAD_SECTION]
    design_keys = [k for k in checked if k not in load_keys]
    torque_keys = {"operating.output_torque_Nm", "operating.input_torque_Nm"} & set(load_keys)
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
    return _Plan(case, design_keys, load_keys, designs, load_cases, int(positions), pins)


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
    from .fem.cache import DiskCache

    if cache_dir is False:
        return None
    return DiskCache() if cache_dir is None else DiskCache(Path(cache_dir))


# ---------------------------------------------------------------------------------------
# Submitting, and the tasks

def _client(scheduler, n_workers):
    """A context manager giving a distributed Client (and the LocalCluster it owns)."""
    import contextlib

    from distributed import Client, LocalCluster

    @contextlib.contextmanager
    def owned():
        if scheduler is None:
            with LocalCluster(n_workers=n_workers or os.cpu_count() or 1,
                              threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                yield client
        elif isinstance(scheduler, Client):
            yield scheduler
        else:
            with Client(scheduler) as client:
                yield client
    return owned()


def _submit(client, plan: _Plan, cache, emit) -> dict:
    """Submit the setup and load-case tasks; rows of designs refused on the driver are
    emitted at once. Returns {load-case future: its row's fixed part}."""
    prefix = f"toothfem-sweep-{uuid.uuid4().hex[:8]}"
    cache_dir = None if cache is None else str(cache.directory)
    loads = "fem" if plan.case.drive == "cycloid" else "analytic"
    setups, pending = {}, {}
    for d, (dvalues, design) in enumerate(plan.designs):
        for lc, (lvalues, torque, ops) in enumerate(plan.load_cases):
            base = {"design": d, "load_case": lc, **dvalues, **lvalues, "loads": loads,
                    "output_torque_Nm": math.nan if torque is None else float(torque)}
            try:
                if isinstance(design, Exception):
                    raise design
                loaded = dataclasses.replace(design, operating=dataclasses.replace(
                    design.operating, **ops))
                t_out = _output_torque(loaded, torque, set(ops))
                base["output_torque_Nm"] = t_out
                member = _member_torque(loaded, t_out)
            except ToothfemError as exc:
                emit(_failed(base, exc))
                continue
            skey = _setup_key(design, plan.pins)
            if skey not in setups:
                setups[skey] = client.submit(_setup, design, plan.pins, plan.positions,
                                             cache_dir, key=f"{prefix}-setup-{d}", pure=False)
            fut = client.submit(_load, setups[skey], member, key=f"{prefix}-load-{d}-{lc}",
                                pure=False)
            pending[fut] = base
    return pending


def _output_torque(case: Case, torque, varied) -> float:
    """Reducer output torque of a load case [N m]: ``torque`` if given, else the varied or
    stated output torque, else the input torque times the ratio (lossless)."""
    if torque is not None:
        return float(torque)
    op = case.operating
    if op.output_torque_Nm is not None and "input_torque_Nm" not in varied:
        return float(op.output_torque_Nm)
    if op.input_torque_Nm is not None:
        return float(op.input_torque_Nm * abs(case.ratio()))
    raise CaseError("no torque: give torques_Nm, operating.output_torque_Nm or "
                    "operating.input_torque_Nm")


def _member_torque(case: Case, output_torque: float) -> float:
    """Torque on the moving member: one cycloid disc (disc_load_factor T / disc_count,
    seed Eq. 6) or the sine planet (T)."""
    check_range("output_torque_Nm", output_torque, 0, None, lo_open=True, error=CaseError)
    if case.drive == "cycloid":
        st = case.cycloid
        return st.disc_load_factor * output_torque / st.disc_count
    return output_torque


def _setup_key(case: Case, pins):
    """Designs with equal keys share one setup task (equal contact geometry and material)."""
    return (case.cycloid if case.drive == "cycloid" else case.sine, case.material, pins)


_SETUP_LOCK = threading.Lock()


def _setup(case: Case, pins, positions: int, cache_dir):
    """Worker task: what every load case of the design shares (a dict, picklable)."""
    t0 = time.perf_counter()
    with _SETUP_LOCK:            # gmsh keeps one model per process: one setup at a time
        if case.drive == "sine":
            from .efficiency.friction import reduced_modulus
            from .geometry import sine

            pair = case.sine.geometry()
            chis = np.linspace(0, 2 * math.pi / pair.ring_teeth, positions, endpoint=False)
            e, nu = case.material.youngs_modulus_GPa * 1e9, case.material.poisson_ratio
            out = {"drive": "sine", "state": sine.meshing(pair, chis),
                   "face_width": case.sine.face_width_mm * 1e-3,
                   "e_star": float(reduced_modulus(e, nu, e, nu))}
        else:
            from .fem import cycloid_fe as cf
            from .fem.cache import DiskCache

            _gmsh_off_main_thread()
            model = cf.model_from_case(case, pins)
            phis = np.linspace(0, 2 * math.pi / model.geometry.pin_count, positions,
                               endpoint=False)
            cache = None if cache_dir is None else DiskCache(Path(cache_dir))
            solver = cf.CycleSolver(model, phis, cache=cache)
            out = {"drive": "cycloid", "model": model, "phis": phis,
                   "tables": solver.tables()}
    out["setup_s"] = time.perf_counter() - t0
    return out


def _load(setup: dict, member_torque: float) -> dict:
    """Worker task: one load case of a design from its setup; the summary columns."""
    t0 = time.perf_counter()
    if setup["drive"] == "sine":
        from .fem.load_sharing import analytic_split

        ls = analytic_split(setup["state"], member_torque, setup["face_width"],
                            setup["e_star"], SINE_IN_MESH_GAP_M)
        te = math.nan                       # the analytic split has no transmission error
    else:
        from .fem import cycloid_fe as cf

        solver = cf.CycleSolver(setup["model"], setup["phis"])
        solver.adopt(setup["tables"])
        ls = solver.solve(member_torque)
        te = float(np.degrees(ls.transmission_error.mean()) * 3600)
    return {"max_force_N": float(ls.force.max()),
            "pins_in_contact_max": int(ls.contacts_per_position.max()),
            "max_ph_MPa": float(ls.ph.max() / 1e6), "transmission_error_arcsec": te,
            "setup_s": setup["setup_s"], "time_s": time.perf_counter() - t0}


def _gmsh_off_main_thread():
    """Let gmsh run in a Dask worker thread (once per process).

    ``gmsh.initialize()`` installs a SIGINT handler unless told ``interruptible=False``,
    and Python allows that only in the main thread; Dask runs tasks in worker threads.
    Default ``interruptible`` to whether the caller is the main thread. (If
    ``fem.mesh.mesh_rings`` passes it itself, this shim can go.)"""
    import gmsh

    init = gmsh.initialize
    if getattr(init, "_toothfem_thread_aware", False):
        return

    @functools.wraps(init)
    def initialize(*args, **kwargs):
        if len(args) < 4:
            kwargs.setdefault("interruptible",
                              threading.current_thread() is threading.main_thread())
        return init(*args, **kwargs)

    initialize._toothfem_thread_aware = True
    gmsh.initialize = initialize


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
