"""The data the measured-data loop fits (issue 14, item 5): many rows binned onto fewer
operating points and the report saying so; identical points, or fewer distinct points than
folds, refused by the library in one line; the data's notes in the report.

Time and memory of the loop on 1e5 rows are a benchmark (benchmarks/measured_scale.py),
not a test.
"""
import json

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency import loop as lp
from toothfem.efficiency.loop import effects as fx
from toothfem.efficiency.loop import measured as ms
from toothfem.efficiency.loop import synthetic as sy
from toothfem.efficiency.loop.binning import MIXED_RUNS, bin_rows
from toothfem.errors import MeasuredDataError, ToothfemError
from toothfem.report import loop as rl

GOOD = "input_speed_rpm,output_torque_Nm,efficiency"
#: Drag alone keeps these loops fast; the binning and the checks do not depend on the
#: catalog.
DRAG = (fx.by_name("drag_torque"),)


@pytest.fixture(scope="module")
def sine(cases_dir):
    return load_case(cases_dir / "sine_prototype.toml")


def _record(speed, torque, eta, *, sigma=None, run=None, extra=None):
    return ms.MeasuredData(speed_rpm=np.array(speed, float), torque_Nm=np.array(torque, float),
                           efficiency=np.array(eta, float),
                           sigma=None if sigma is None else np.array(sigma, float),
                           run_id=None if run is None else np.array(run, dtype=object),
                           extra=extra or {}, lines=np.arange(2, 2 + len(speed)),
                           notes=("column 'operator' dropped (text)",))


def test_bin_rows_keeps_the_mean_and_count_of_each_cell():
    """Two rows at each of four operating points, four points kept: each point is the mean
    of its two rows, its sigma that of a mean, sqrt(s1^2 + s2^2) / 2; a cell of two runs
    is 'mixed'; a record small enough is returned as it is."""
    speed = [100, 101, 1000, 1001, 100, 101, 1000, 1001]
    torque = [10, 10, 10, 10, 20, 20, 20, 20]
    eta = [0.70, 0.72, 0.80, 0.82, 0.75, 0.77, 0.85, 0.87]
    sigma = [0.03, 0.04, 0.03, 0.04, 0.03, 0.04, 0.03, 0.04]
    run = ["a", "a", "a", "b", "b", "b", "b", "b"]
    data = _record(speed, torque, eta, sigma=sigma, run=run,
                   extra={"vibration_mm_s": np.arange(8.0)})
    assert bin_rows(data, 8) == (data, None)
    binned, info = bin_rows(data, 4)
    assert (info.rows, info.points, info.rows_per_point) == (8, 4, (2, 2.0, 2))
    order = np.lexsort((binned.speed_rpm, binned.torque_Nm))
    np.testing.assert_allclose(binned.speed_rpm[order], [100.5, 1000.5] * 2)
    np.testing.assert_allclose(binned.efficiency[order], [0.71, 0.81, 0.76, 0.86])
    np.testing.assert_allclose(binned.sigma, np.hypot(0.03, 0.04) / 2)
    np.testing.assert_allclose(binned.extra["vibration_mm_s"][order], [0.5, 2.5, 4.5, 6.5])
    assert list(binned.run_id[order]) == ["a", MIXED_RUNS, "b", "b"]
    assert info.mixed_runs == 1 and "1 of the points mix runs (run_id 'mixed')" in info.note()
    assert list(binned.lines[order]) == [2, 4, 6, 8]         # the first row of each cell
    assert binned.notes[0] == data.notes[0]
    assert binned.notes[-1].startswith("8 rows binned onto 4 operating points (more rows "
                                       "than max_points = 4)")


def test_bin_rows_without_sigma_weights_by_the_rows_of_each_point():
    """Without the rows' sigma a point's sigma is s / sqrt(n), s the pooled scatter within
    the cells: s^2 = (2 + 4) x 1e-4 / (7 rows - 2 cells)."""
    data = _record([100, 100, 100, 1000, 1000, 1000, 1000],
                   [10, 10, 10, 10, 10, 10, 10],
                   [0.70, 0.72, 0.71, 0.80, 0.82, 0.80, 0.82])
    binned, info = bin_rows(data, 2)
    assert info.rows_per_point == (3, 3.5, 4)
    s = np.sqrt((0.0001 + 0.0001 + 0.0 + 4 * 0.0001) / (7 - 2))
    np.testing.assert_allclose(sorted(binned.sigma), [s / 2, s / np.sqrt(3)])
    assert "pooled scatter" in info.sigma


def test_many_rows_are_binned_and_the_report_says_so(sine):
    """More rows than Settings.max_points: the loop fits the bins, finds the effect all the
    same (drag of 20 N mm, within 10 %) and says in its notes, JSON
    and Markdown how many rows, how many points and how."""
    data = sy.generate(sine, {"drag_torque": (20.0,)}, n_points=600, seed=3)
    rep = lp.run_loop(sine, data, DRAG, settings=lp.Settings(max_points=60))
    assert rep.n_rows == 600 and 8 <= rep.n_points <= 60
    assert rep.binning["rows"] == 600 and rep.binning["points"] == rep.n_points
    assert rep.effects[0].parameters["drag_torque_Nmm"]["value"] == pytest.approx(20.0,
                                                                                rel=0.1)
    note = f"600 rows binned onto {rep.n_points} operating points"
    assert rep.notes[-1].startswith(note)
    out = json.loads(json.dumps(rep.to_dict(), allow_nan=False))
    assert out["n_rows"] == 600 and out["notes"][-1].startswith(note)
    assert out["binning"]["cells_per_axis"] == rep.binning["cells_per_axis"]
    md = rl.markdown(rep, effects=DRAG)
    assert f"600 rows binned onto {rep.n_points} points" in md
    assert "## What was done to the data" in md and note in md


def test_identical_points_refused_by_the_library_in_one_line(sine):
    """The loop itself (not only the CLI) refuses identical points, and a selection with
    fewer distinct points than folds, in one line naming the problem."""
    same = ms.parse_measured(GOOD + "\n" + "1500,20,0.8\n" * 12, source="same.csv")
    with pytest.raises(MeasuredDataError) as exc:
        lp.run_loop(sine, same, DRAG)
    msg = str(exc.value)
    assert "\n" not in msg
    assert msg.startswith("same.csv: 12 good rows but only 1 distinct operating point ")
    three = ms.parse_measured(GOOD + "\n" + "1500,20,0.8\n1000,20,0.79\n500,20,0.78\n" * 4)
    with pytest.raises(MeasuredDataError, match=r"12 good rows but only 3 distinct operating "
                                                r"points .*5-fold held-out error .* needs "
                                                r"at least 5$"):
        lp.run_loop(sine, three, DRAG)
    assert lp.loop_data(three, lp.Settings(folds=3)) == (three, None)
    assert lp.loop_data(three, lp.Settings(min_points=13)) == (three, None)   # no folds


def test_settings_refuse_what_the_loop_cannot_use():
    with pytest.raises(ToothfemError, match=r"folds = 1 is outside the valid range \[2, inf\)"):
        lp.Settings(folds=1)
    with pytest.raises(ToothfemError, match=r"max_points = 4 is outside the valid range "
                                            r"\[8, inf\)"):
        lp.Settings(max_points=4)


def test_report_carries_the_datas_notes(sine):
    """A column the loader dropped is in the report's notes, its JSON and its Markdown."""
    rows = "".join(f"{500 + 100 * k},{10 + k},{0.80 + 0.005 * k:.3f},op{k}\n" for k in range(10))
    data = ms.parse_measured(GOOD + ",operator\n" + rows)
    rep = lp.run_loop(sine, data, DRAG)
    assert rep.binning is None and rep.n_rows == rep.n_points == 10
    assert rep.notes == data.notes and "'operator' dropped (text)" in rep.notes[0]
    assert rep.to_dict()["notes"] == list(data.notes)
    md = rl.markdown(rep, effects=DRAG)
    assert f"- {data.notes[0]}" in md and "10 points" in md
