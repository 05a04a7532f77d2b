"""Design sweeps through Dask (toothfem.sweep, `toothfem sweep`) and the disk cache of
influence tables (toothfem.fem.cache, CycleSolver.cache).

Facts checked: a sweep row is the cycle solver's own result for that design and load case;
load cases of a design share one setup; rows reach the journal beside the output folder one
by one and the tables appear only when the sweep ends; a sweep stopped by a crash of the
driver keeps its finished points and the same call resumes it; a failed point is a row, not
the end of the sweep (the command's exit says how many); a new torque on a known design costs no
factorisation, from memory or from disk; the cache key follows the geometry, not the torque.
"""
import argparse
import contextlib
import csv
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from toothfem import CaseError, load_case
from toothfem.errors import IncompleteRun
from toothfem.output import JOURNAL
from toothfem.commands import sweep as sweep_cmd
from toothfem.fem import cycloid_fe as cf
from toothfem.fem import linsolve
from toothfem.fem.cache import DiskCache, content_key
from toothfem.fem.load_sharing import analytic_split
from toothfem.sweep import SINE_IN_MESH_GAP_M, result_columns, sweep
from toothfem.fem.drives import drive_for

ECC = "cycloid.eccentricity_mm"
FAST = dict(positions=2, pins="rigid", progress=False)     # one small factorisation a design


@pytest.fixture(scope="module")
def cycloid(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


@pytest.fixture(scope="module")
def scheduler():
    """One single-process, single-thread worker for the module's sweeps."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster:
        yield cluster.scheduler_address


@pytest.fixture(scope="module")
def cache_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("influence_cache")


def _read(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _temp_tables(out):
    """The tables in hidden siblings of ``out`` (none may be left)."""
    return list(out.parent.glob(f".{out.name}~*/sweep.csv"))


def _journal_files(out):
    """The journals of unfinished runs into ``out``: in folders of their own beside it."""
    return list(out.parent.glob(f".{out.name}~*.journal-*/{JOURNAL}"))


def _journal(out):
    (journal,) = _journal_files(out)
    return [json.loads(line) for line in journal.read_text().splitlines()]


def test_sweep_rows_are_the_solvers_and_arrive_one_by_one(cycloid, scheduler, cache_dir,
                                                          tmp_path):
    out = tmp_path / "sw"
    seen = []

    def on_row(row):
        seen.append(len(_journal(out)))       # on disk row by row ...
        assert not (out / "sweep.csv").exists()      # ... the table at the end

    res = sweep(cycloid, {ECC: [1.0, 0.9]}, torques_Nm=[100, 200], scheduler=scheduler,
                out=out, cache_dir=cache_dir, on_row=on_row, **FAST)
    assert seen == [1, 2, 3, 4]
    assert res.failed == 0 and res.table == out / "sweep.csv" and not _temp_tables(out)
    assert not _journal_files(out) and not (out / JOURNAL).exists()   # only its tables
    rows = _read(res.table)
    assert list(rows[0]) == ["design", "load_case", ECC] + result_columns(drive_for(cycloid))
    assert "pins_in_contact_max" in rows[0]                # a cycloid sweep counts pins
    assert sorted((float(r[ECC]), float(r["output_torque_Nm"])) for r in rows) == [
        (0.9, 100), (0.9, 200), (1.0, 100), (1.0, 200)]
    by = {(float(r[ECC]), float(r["output_torque_Nm"])): r for r in rows}
    for r in rows:
        assert r["status"] == "ok" and r["error"] == "" and r["loads"] == "fem"
        assert int(r["pins_in_contact_max"]) == 20          # half the pins carry (seed)
        assert float(r["transmission_error_arcsec"]) > 0
    # load cases of a design share one setup task
    assert by[(1.0, 100)]["setup_s"] == by[(1.0, 200)]["setup_s"]
    assert len(list(cache_dir.glob("*.npz"))) == 2
    # the row is the cycle solver's own result (disc torque 1.1 x the power flow's share
    # of 100 N m)
    model = drive_for(cycloid).fe_model(pin_structure="rigid")
    phis = np.linspace(0, 2 * math.pi / 40, 2, endpoint=False)
    ls = cf.CycleSolver(model, phis, cache=DiskCache(cache_dir)).solve(
        drive_for(cycloid).member_torque(100.0))
    assert float(by[(1.0, 100)]["max_force_N"]) == pytest.approx(ls.force.max(), rel=1e-8)
    assert float(by[(1.0, 100)]["max_ph_MPa"]) == pytest.approx(ls.ph.max() / 1e6, rel=1e-8)
    # nearly linear in the torque (Hertz adds a log); the smaller eccentricity loads harder
    assert float(by[(1.0, 200)]["max_force_N"]) > 1.9 * float(by[(1.0, 100)]["max_force_N"])
    assert float(by[(0.9, 100)]["max_force_N"]) > float(by[(1.0, 100)]["max_force_N"])
    summary = json.loads((out / "sweep.json").read_text())
    assert (summary["designs"], summary["load_cases"], summary["rows"]) == (2, 2, 4)


def test_failed_points_are_rows_not_the_end(cycloid, scheduler, cache_dir, tmp_path):
    """A design the case refuses (K1 = 1.2: looped profile) fails on the driver with the
    case's own message; one the solver refuses (no crank holes to hold the disc) fails in
    the worker; the valid design still runs."""
    res = sweep(cycloid, {ECC: [1.0, 3.0], "cycloid.disc_holes.crank_hole_count": [2, 0]},
                torques_Nm=[100], scheduler=scheduler, out=tmp_path / "sw",
                cache_dir=cache_dir, **FAST)
    rows = {(float(r[ECC]), int(r["cycloid.disc_holes.crank_hole_count"])): r
            for r in _read(res.table)}
    assert len(rows) == 4 and res.failed == 3
    assert rows[(1.0, 2)]["status"] == "ok"
    for holes in (2, 0):
        r = rows[(3.0, holes)]
        assert r["status"] == "failed" and r["max_force_N"] == ""
        assert r["error"].startswith("cycloid.eccentricity_mm = 3.0 is outside the valid "
                                     "range (0, 2.5)")
    assert rows[(1.0, 0)]["status"] == "failed"
    assert "crank holes" in rows[(1.0, 0)]["error"]


def test_keys_and_values_checked_before_any_work(cycloid, tmp_path):
    out = tmp_path / "sw"
    with pytest.raises(CaseError, match=r"cycloid\.eccentricty_mm is not a known key; valid "
                                        r"keys of \[cycloid\]: \[.*'eccentricity_mm'.*"
                                        r"'disc_holes\.crank_hole_count'"):
        sweep(cycloid, {"cycloid.eccentricty_mm": [1.0]}, out=out, progress=False)
    with pytest.raises(CaseError, match=r"sine\.module_mm is not a key of a section of this "
                                        r"case.*sections: \[.*'cycloid'"):
        sweep(cycloid, {"sine.module_mm": [1.0]}, out=out, progress=False)
    with pytest.raises(CaseError, match=r"^cycloid\.eccentricity_mm = -1\.0 is outside the "
                                        r"valid range \[0\.01, 100\]$"):
        sweep(cycloid, {ECC: [1.0, -1.0]}, out=out, progress=False)
    with pytest.raises(CaseError, match=r"cycloid\.pin_count = 40\.5 must be an integer"):
        sweep(cycloid, {"cycloid.pin_count": [40.5]}, out=out, progress=False)
    with pytest.raises(CaseError, match="one way"):
        sweep(cycloid, {"operating.output_torque_Nm": [50.0]}, torques_Nm=[10], out=out,
              progress=False)
    with pytest.raises(CaseError, match="torques_Nm = -5 is outside"):
        sweep(cycloid, {}, torques_Nm=[-5], out=out, progress=False)
    assert not out.exists() and not _temp_tables(out)


def test_a_stopped_sweep_keeps_its_points_and_the_same_call_resumes(cycloid, scheduler,
                                                                     cache_dir, tmp_path):
    """The driver dies after the first row: that row is on disk beside the output folder
    (the exception says so); the same call computes only the other row; another call (other
    torques) into the folder starts afresh."""
    out = tmp_path / "sw"

    def crash(row):
        raise RuntimeError("driver died")

    with pytest.raises(RuntimeError, match="driver died") as stopped:
        sweep(cycloid, {}, torques_Nm=[100, 200], scheduler=scheduler, out=out,
              cache_dir=cache_dir, on_row=crash, **FAST)
    assert stopped.value.toothfem_kept.startswith(f"1 finished points kept beside {out}")
    (kept,) = _journal(out)
    assert kept["record"]["status"] == "ok" and not (out / "sweep.csv").exists()
    computed = []
    res = sweep(cycloid, {}, torques_Nm=[100, 200], scheduler=scheduler, out=out,
                cache_dir=cache_dir, on_row=computed.append, **FAST)
    assert res.resumed == 1 and len(computed) == 1 and len(_read(res.table)) == 2
    assert computed[0]["load_case"] != kept["record"]["load_case"]
    assert float(_read(res.table)[kept["record"]["load_case"]]["max_force_N"]) == \
        pytest.approx(kept["record"]["max_force_N"], rel=1e-9)
    res = sweep(cycloid, {}, torques_Nm=[300], scheduler=scheduler, out=out,
                cache_dir=cache_dir, **FAST)
    assert res.resumed == 0 and len(_read(res.table)) == 1 and not _temp_tables(out)


def test_sine_sweep_with_the_analytic_split(cases_dir, scheduler, tmp_path):
    """The seeds' split on the meshing state (loads = analytic), linear in the torque; the
    load case's output torque is what its input torque gives through the efficiency
    model (as in `toothfem contact` and `run`)."""
    from dataclasses import replace

    from toothfem.efficiency import operating_point

    case = load_case(cases_dir / "sine_prototype.toml")
    res = sweep(case, {"operating.input_torque_Nm": [0.2, 0.4]}, positions=6,
                scheduler=scheduler, out=tmp_path / "sw", cache_dir=False, progress=False,
                sine_loads="analytic")
    rows = sorted(_read(res.table), key=lambda r: float(r["output_torque_Nm"]))
    assert [r["status"] for r in rows] == ["ok", "ok"]
    t_out = [float(operating_point(replace(case, operating=replace(
        case.operating, input_torque_Nm=t)))[1]) for t in (0.2, 0.4)]
    assert [float(r["output_torque_Nm"]) for r in rows] == pytest.approx(t_out, rel=1e-8)
    assert 0.8 * 79 * 0.2 < t_out[0] < 79 * 0.2
    assert all(r["loads"] == "analytic" and r["transmission_error_arcsec"] == ""
               for r in rows)
    assert all(int(r["teeth_in_contact_max"]) >= 2 for r in rows)   # a sine sweep counts teeth
    f = [float(r["max_force_N"]) for r in rows]
    assert f[1] / f[0] == pytest.approx(t_out[1] / t_out[0], rel=1e-7)
    from toothfem.fem.hertz import reduced_modulus
    from toothfem.geometry import sine

    state = sine.meshing(case.sine.geometry(), np.linspace(0, 2 * math.pi / 80, 6,
                                                           endpoint=False))
    ls = analytic_split(state, t_out[1], 8e-3, reduced_modulus(212e9, 0.28, 212e9, 0.28),
                        SINE_IN_MESH_GAP_M, weight="cos_pressure_angle")
    assert f[1] == pytest.approx(ls.force.max(), rel=1e-8)


@pytest.mark.slow
def test_sine_sweep_with_the_fe_model(cases_dir, scheduler, tmp_path):
    """Sine rows use the FE model (loads = fem) by default, both load cases of the design
    in one task on one factorisation."""
    case = load_case(cases_dir / "sine_prototype.toml")
    res = sweep(case, {}, torques_Nm=[15.8, 31.6], positions=2, scheduler=scheduler,
                out=tmp_path / "sw", cache_dir=False, progress=False)
    rows = sorted(_read(res.table), key=lambda r: float(r["output_torque_Nm"]))
    assert [(r["status"], r["loads"]) for r in rows] == [("ok", "fem")] * 2, rows
    assert rows[0]["setup_s"] == rows[1]["setup_s"]
    assert float(rows[1]["max_force_N"]) > float(rows[0]["max_force_N"]) > 0
    assert float(rows[0]["transmission_error_arcsec"]) > 0


def test_cli_sweep(cases_dir, scheduler, cache_dir, tmp_path, capsys):
    ap = argparse.ArgumentParser(prog="toothfem")
    sweep_cmd.add_parser(ap.add_subparsers(dest="command"))
    out = tmp_path / "cli"
    args = ap.parse_args(["sweep", str(cases_dir / "cycloid_pinhousing.toml"), "--vary",
                          f"{ECC}=1.0", "--torque-Nm", "100,200", "--positions", "2",
                          "--pins", "rigid", "--scheduler", scheduler, "--cache-dir",
                          str(cache_dir), "--out", str(out), "--json"])
    assert args.func(args) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["rows"] == 2 and printed["failed"] == 0
    args.json = False                   # without --json: a table and the folder's name
    assert args.func(args) == 0
    table = capsys.readouterr().out
    assert "points resumed" in table and f"wrote {out.resolve()}" in table
    assert [r["status"] for r in _read(out / "sweep.csv")] == ["ok", "ok"]
    assert sweep_cmd.parse_vary("cycloid.pin_structure=integral,conventional") == (
        "cycloid.pin_structure", ["integral", "conventional"])
    assert sweep_cmd.parse_vary("material.poisson_ratio=0.3, 0.29") == (
        "material.poisson_ratio", [0.3, 0.29])
    # a failed point: the tables are written, and the command says how many failed
    args = ap.parse_args(["sweep", str(cases_dir / "cycloid_pinhousing.toml"), "--vary",
                          f"{ECC}=3.0,1.0", "--torque-Nm", "100", "--positions", "2",
                          "--pins", "rigid", "--scheduler", scheduler, "--cache-dir",
                          str(cache_dir), "--out", str(tmp_path / "failed")])
    with pytest.raises(IncompleteRun, match=r"^1 of 2 points failed"):
        args.func(args)
    assert len(_read(tmp_path / "failed" / "sweep.csv")) == 2
    for bad in ("cycloid.eccentricity_mm", "=1,2", "cycloid.eccentricity_mm=1,,2"):
        with pytest.raises(CaseError):
            sweep_cmd.parse_vary(bad)


@pytest.mark.parametrize("fault", ["no worker", "worker lost", "scheduler lost"])
def test_dask_faults_end_in_one_line_and_keep_the_finished_points(cycloid, fault, tmp_path,
                                                                  monkeypatch):
    """A scheduler without workers, the only worker lost after the first row, the
    scheduler closed after it: each ends within seconds (the no-worker wait shortened to
    1.5 s here, 30 s by default) in a ClusterError of one line, with the finished row kept."""
    from distributed import LocalCluster

    from toothfem import cluster

    monkeypatch.setattr(cluster, "NO_WORKER_TIMEOUT_S", 1.5)
    out = tmp_path / "sw"
    with LocalCluster(n_workers=0 if fault == "no worker" else 1, threads_per_worker=1,
                      processes=True, dashboard_address=":0") as local:
        def on_row(row):
            if fault == "worker lost":
                local.scale(0)
            elif fault == "scheduler lost":
                local.close()

        t0 = time.monotonic()
        with pytest.raises(cluster.ClusterError) as stopped:
            sweep(cycloid, {ECC: [1.0, 0.95, 0.9]}, torques_Nm=[100], positions=2,
                  pins="rigid", scheduler=local.scheduler_address, out=out, cache_dir=False,
                  progress=False, on_row=on_row)
    assert time.monotonic() - t0 < 30
    message = str(stopped.value)
    assert "\n" not in message and local.scheduler_address in message
    assert ("no worker for 2 s" if fault != "scheduler lost" else "stopped answering") \
        in message
    if fault == "no worker":
        assert not out.exists()
    else:
        assert len(_journal(out)) == 1
        assert stopped.value.toothfem_kept.startswith("1 finished points kept")


def test_a_silent_scheduler_address_is_refused_in_bounded_time(cycloid, tmp_path,
                                                               monkeypatch):
    """Something that accepts the connection and never answers: Dask's own timeout does not
    bound the handshake (it waited for ever); ours does (shortened to 2 s here)."""
    import socket

    from toothfem import cluster
    from toothfem.errors import ToothfemError

    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 2.0)
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen(4)
        address = f"tcp://127.0.0.1:{silent.getsockname()[1]}"
        t0 = time.monotonic()
        with pytest.raises(ToothfemError, match=f"scheduler = '{address}': no Dask scheduler "
                                                r"there \(no answer within 2 s\)"):
            sweep(cycloid, {}, torques_Nm=[100], scheduler=address, out=tmp_path / "sw",
                  **FAST)
    assert time.monotonic() - t0 < 15 and not (tmp_path / "sw").exists()


@pytest.mark.slow
def test_a_killed_sweep_keeps_its_points_and_a_rerun_finishes_only_the_rest(cases_dir,
                                                                            tmp_path):
    """`toothfem sweep` on a local cluster, its whole process group signalled once points
    are on disk: Ctrl-C exits 130 with one line saying they are kept, no traceback; the
    same command resumes and, killed with SIGKILL (nothing could be cleaned up), keeps
    them all and more; run once more, it computes only the rest."""
    out = tmp_path / "sw"
    cmd = [sys.executable, "-c", "import sys; from toothfem.cli import main; "
           "sys.exit(main())", "sweep", str(cases_dir / "cycloid_pinhousing.toml"),
           "--vary", f"{ECC}=1.0,0.98,0.96,0.94,0.92,0.9", "--torque-Nm", "100",
           "--positions", "2", "--workers", "1", "--no-cache", "--out", str(out)]

    def stop_after(points, signum):
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             start_new_session=True)
        try:
            while p.poll() is None and not (_journal_files(out) and
                                            len(_journal(out)) >= points):
                time.sleep(0.02)
            os.killpg(p.pid, signum)
            p.wait(timeout=60)
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGKILL)
        return p.returncode, p.stderr.read().decode()

    code, err = stop_after(1, signal.SIGINT)
    kept = len(_journal(out))
    assert code == 130 and 1 <= kept < 6, err[-800:]
    assert "Traceback" not in err, err[-800:]
    assert err.strip().splitlines()[-1].startswith(
        f"toothfem sweep: interrupted; {kept} finished points kept beside"), err[-800:]
    code, err = stop_after(kept + 1, signal.SIGKILL)
    killed = len(_journal(out))
    assert code == -signal.SIGKILL and kept < killed < 6, err[-800:]
    done = subprocess.run(cmd, capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr.decode()[-800:]
    summary = json.loads((out / "sweep.json").read_text())
    assert summary["resumed"] == killed and summary["rows"] == 6 and summary["failed"] == 0


@pytest.mark.slow
def test_local_cluster_two_workers_conventional_pins(cycloid, tmp_path):
    """The default path: a LocalCluster of two worker processes, the case's own pins, the
    default disk cache ($TOOTHFEM_CACHE: the suite's, tests/conftest.py)."""
    res = sweep(cycloid, {ECC: [1.0, 0.95, 0.9]}, torques_Nm=[100, 167], positions=4,
                pins="conventional", n_workers=2, out=tmp_path / "sw", progress=False)
    rows = _read(res.table)
    assert len(rows) == 6 and res.failed == 0
    summary = json.loads((res.out / "sweep.json").read_text())
    assert summary["workers"] == 2
    assert all(int(r["pins_in_contact_max"]) == 20 for r in rows)


# ---------------------------------------------------------------------------------------
# Disk cache of influence tables

@pytest.fixture
def splu_count(monkeypatch):
    """Counts sparse factorisations (Body.factor calls fem.linsolve.factorize, whatever
    the backend)."""
    calls = []
    real = linsolve.factorize

    def counting(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(linsolve, "factorize", counting)
    return calls


def test_new_torque_costs_no_factorisation_in_memory_or_from_disk(cycloid, splu_count,
                                                                  tmp_path):
    """Conventional pins: the disc and the pin table are factorised once; a new torque on
    the same solver, or on a fresh solver reading the disk cache, factorises nothing.
    (A coarse patch, b_ref = 0.4 mm, keeps the pin's mesh small.)"""
    model = drive_for(cycloid).fe_model(pin_structure="conventional")
    phis = np.array([0.061])
    cache = DiskCache(tmp_path)
    coarse = dict(b_ref=4e-4)
    first = cf.CycleSolver(model, phis, cache=cache, **coarse)
    first.solve(55.0)
    assert len(splu_count) == 2                   # disc + pin
    again = first.solve(91.85)
    assert len(splu_count) == 2                   # in memory
    fresh = cf.CycleSolver(model, phis, cache=cache, **coarse)
    from_disk = fresh.solve(91.85)
    assert len(splu_count) == 2                   # from disk: no mesh, no factorisation
    assert "_setup" not in vars(fresh)
    assert np.array_equal(from_disk.force, again.force)


def test_cache_key_follows_geometry_not_torque(cycloid):
    from dataclasses import replace

    model = drive_for(cycloid).fe_model(pin_structure="rigid")
    phis = np.array([0.0, 0.05])

    def key(m=model, p=phis, **kw):
        return cf.CycleSolver(m, p, **kw).cache_key()

    base = key()
    assert key() == base                                        # stable
    assert key(replace(model, face_width=0.02)) == base         # tables are per unit length
    g = model.geometry
    for other in (replace(model, geometry=replace(g, eccentricity_m=0.9e-3)),
                  replace(model, geometry=replace(g, equidistant_m=1e-5)),
                  replace(model, youngs_modulus=200e9),
                  replace(model, pin_structure="conventional")):
        assert key(other) != base
    assert key(p=phis[:1]) != base and key(b_ref=2e-4) != base
    assert content_key(40) == content_key(40.0) != content_key("40")


def test_corrupt_cache_file_is_recomputed(cycloid, splu_count, tmp_path):
    model = drive_for(cycloid).fe_model(pin_structure="rigid")
    phis = np.array([0.061])
    cache = DiskCache(tmp_path)
    solver = cf.CycleSolver(model, phis, cache=cache)
    path = cache.path(solver.cache_key())
    path.write_bytes(b"not an npz file")
    ls = solver.solve(55.0)
    assert len(splu_count) == 1
    assert set(cache.load(solver.cache_key())) == {"influence_0"}     # rewritten, readable
    cf.CycleSolver(model, phis, cache=cache).solve(55.0)
    assert len(splu_count) == 1
    # a stale file that does not fit these positions is refused and overwritten too
    cache.store(solver.cache_key(), {"influence_0": np.eye(3)})
    again = cf.CycleSolver(model, phis, cache=cache).solve(55.0)
    assert len(splu_count) == 2 and np.array_equal(again.force, ls.force)
    assert not list(tmp_path.glob("*.tmp"))                           # atomic writes
    # without a cache: the same numbers (the hook changes nothing else)
    uncached = cf.CycleSolver(model, phis).solve(55.0)
    assert len(splu_count) == 3 and np.array_equal(uncached.force, ls.force)


def test_default_cache_dir_from_environment(monkeypatch, tmp_path):
    from toothfem.fem.cache import default_dir

    monkeypatch.setenv("TOOTHFEM_CACHE", str(tmp_path / "c"))
    assert DiskCache().directory == tmp_path / "c" == default_dir()
    monkeypatch.delenv("TOOTHFEM_CACHE")
    assert default_dir().parts[-2:] == (".cache", "toothfem")
    assert DiskCache(tmp_path).load("0" * 64) is None
