"""Determinism (issue 14, item 6): two runs of a command give identical CSV and JSON,
apart from the fields named as timings; sweep rows come sorted by design and load case."""
import csv
import json

import pytest

from toothfem import cli, load_case
from toothfem.sweep import sweep

#: Fields that are wall-clock times (the only ones allowed to differ between two runs).
TIMINGS = {"elapsed_s", "wall_s", "setup_s", "time_s"}


def _without_timings(x):
    if isinstance(x, dict):
        return {k: _without_timings(v) for k, v in x.items() if k not in TIMINGS}
    if isinstance(x, list):
        return [_without_timings(v) for v in x]
    return x


def _table(path):
    with open(path, newline="") as fh:
        return [_without_timings(r) for r in csv.DictReader(fh)]


def _twice(argv, capsys):
    outs = []
    for _ in range(2):
        assert cli.main(argv) == 0
        outs.append(capsys.readouterr().out)
    return outs


@pytest.mark.parametrize("command", ["check", "efficiency"])
@pytest.mark.parametrize("name", ["cycloid_pinhousing.toml", "sine_prototype.toml",
                                  "rv40e.toml"])
def test_json_commands_repeat_exactly(cases_dir, capsys, command, name):
    a, b = _twice([command, str(cases_dir / name), "--json"], capsys)
    assert a == b and json.loads(a)


def test_geometry_files_repeat_exactly(cases_dir, tmp_path, geometry_of):
    """A second run writes the same bytes as the session's first (conftest's shared run)."""
    first, _ = geometry_of("sine_prototype")
    assert cli.main(["geometry", str(cases_dir / "sine_prototype.toml"), "--out",
                     str(tmp_path / "g1")]) == 0
    for name in ("planet.csv", "ring.csv", "check.json"):
        assert (first / name).read_bytes() == (tmp_path / "g1" / name).read_bytes()


def test_loop_report_repeats_apart_from_timings(cases_dir, tmp_path, capsys):
    reports = []
    for k in range(2):
        out = tmp_path / f"l{k}"
        assert cli.main(["loop", str(cases_dir / "rv40e.toml"), "--out", str(out),
                         "--effects", "drag_torque"]) == 0
        reports.append(json.loads((out / "report.json").read_text()))
    capsys.readouterr()
    assert set(reports[0]) & TIMINGS
    assert _without_timings(reports[0]) == _without_timings(reports[1])


@pytest.fixture(scope="module")
def scheduler():
    """One single-process worker for the module's sweeps (as tests/test_sweep.py)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster:
        yield cluster.scheduler_address


def test_sweep_rows_sorted_and_repeat(cases_dir, scheduler, tmp_path):
    """The refused design (module 1 mm with the case's centre distance of 0.45 mm) is known
    on the driver and emitted first; the final table is still in design, load-case
    order."""
    case = load_case(cases_dir / "sine_prototype.toml")
    tables, sums = [], []
    for k in range(2):
        res = sweep(case, {"sine.module_mm": [0.9, 1.0],
                           "operating.input_torque_Nm": [0.2, 0.4]}, positions=4,
                    scheduler=scheduler, out=tmp_path / f"s{k}", cache_dir=False,
                    progress=False, sine_loads="analytic")
        rows = _table(res.table)
        assert [(int(r["design"]), int(r["load_case"])) for r in rows] == [
            (0, 0), (0, 1), (1, 0), (1, 1)]
        assert [r["status"] for r in rows] == ["ok", "ok", "failed", "failed"]
        assert [(r["design"], r["load_case"]) for r in res.rows] == [
            (0, 0), (0, 1), (1, 0), (1, 1)]
        tables.append(rows)
        sums.append(_without_timings(json.loads((res.out / "sweep.json").read_text())))
    assert tables[0] == tables[1]
    assert sums[0] == sums[1]


@pytest.mark.slow
def test_contact_repeats_exactly(cases_dir, tmp_path, capsys):
    for k in range(2):
        assert cli.main(["contact", str(cases_dir / "cycloid_pinhousing.toml"), "--positions",
                         "2", "--field", "none", "--out", str(tmp_path / f"c{k}")]) == 0
    capsys.readouterr()
    for name in ("load_sharing.csv", "summary.json"):
        assert (tmp_path / "c0" / name).read_bytes() == (tmp_path / "c1" / name).read_bytes()
