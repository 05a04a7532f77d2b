"""Measured-data loader: units in column names, bad rows refused with line and reason, no
good row lost, provenance from header comments and sidecar."""
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from toothfem import load_case
from toothfem.efficiency.loop import measured as ms
from toothfem.efficiency.loop.measured import MeasuredDataError, load_measured, parse_measured

HEADER = "input_speed_rpm,output_torque_Nm,efficiency,oil_temp_C,time_h,run_id"


def test_good_file_all_columns():
    text = "\n".join(["# source: rig A", "# operator: me", HEADER,
                      "500,28,0.8247,50,0.0,r1",
                      "1000,20,0.80,60,0.5,r1",
                      "1500,10,0.75,70,1.0,r2"])
    d = parse_measured(text)
    assert len(d) == 3 and d.rejected == ()
    np.testing.assert_allclose(d.speed_rpm, [500, 1000, 1500])
    np.testing.assert_allclose(d.efficiency, [0.8247, 0.80, 0.75])
    assert list(d.run_id) == ["r1", "r1", "r2"]
    assert d.provenance == {"source": "rig A", "operator": "me"}
    assert list(d.lines) == [4, 5, 6]
    assert set(d.covariates()) == {"input_speed_rpm", "output_torque_Nm", "oil_temp_C",
                                   "time_h", "run_id"}


def test_unit_conversions():
    """rad/s, N mm, percent, kelvin and minutes convert to rpm, N m, fraction, deg C, h."""
    text = ("input_speed_rad_s,output_torque_Nmm,efficiency_pct,oil_temp_K,time_min\n"
            f"{2 * math.pi * 500 / 60},28000,82.47,323.15,30\n")
    d = parse_measured(text)
    np.testing.assert_allclose([d.speed_rpm[0], d.torque_Nm[0], d.efficiency[0],
                                d.oil_temp_C[0], d.time_h[0]], [500, 28, 0.8247, 50, 0.5])


@pytest.mark.parametrize("row, reason", [
    ("500,,0.8", "output_torque_Nm is empty"),
    ("nan,28,0.8", "input_speed_rpm is NaN"),
    ("500,28,abc", "efficiency = 'abc' is not a number"),
    ("500,28,0", "efficiency = 0 is outside (0, 1]"),
    ("500,28,1.2", "efficiency = 1.2 is outside (0, 1]"),
    ("-5,28,0.8", "input_speed_rpm = -5 is negative"),
    ("0,28,0.8", "input_speed_rpm = 0"),
    ("500,-1,0.8", "output_torque_Nm = -1 must be > 0"),
    ("500,28", "has 2 fields, the header has 3"),
    ("500,28,0.8,9", "has 4 fields, the header has 3"),
])
def test_bad_row_refused_with_line_and_reason(row, reason):
    text = "input_speed_rpm,output_torque_Nm,efficiency\n500,28,0.82\n" + row + "\n600,20,0.8\n"
    d = parse_measured(text)
    assert len(d) == 2, "both good rows are kept"
    assert len(d.rejected) == 1
    assert d.rejected[0].line == 3
    assert reason in d.rejected[0].reason
    with pytest.raises(MeasuredDataError, match="line 3: "):
        parse_measured(text, strict=True)


@pytest.mark.parametrize("header, message", [
    ("output_torque_Nm,efficiency", "missing column input_speed_rpm"),
    ("input_speed_rpm,efficiency", "missing column output_torque_Nm"),
    ("input_speed_rpm,output_torque_Nm", "missing column efficiency"),
    ("input_speed_rpm,output_torque_lbft,efficiency", "unknown unit 'lbft' for output_torque"),
    ("input_speed_rpm,output_torque_Nm,efficiency,oil_temp_R", "unknown unit 'R' for oil_temp"),
    ("input_speed_rpm,output_torque_Nm,efficiency,efficiency_pct", "efficiency appears twice"),
])
def test_bad_header_refuses_file(header, message):
    with pytest.raises(MeasuredDataError, match=message):
        parse_measured(header + "\n1,2,0.5\n")


def test_no_good_row_is_an_error():
    with pytest.raises(MeasuredDataError, match="no good row.*line 2"):
        parse_measured("input_speed_rpm,output_torque_Nm,efficiency\n500,28,2\n")


def test_input_torque_needs_ratio_and_is_checked():
    text = "input_speed_rpm,output_torque_Nm,input_torque_Nm\n500,28,0.43\n"
    with pytest.raises(MeasuredDataError, match="needs the reducer ratio"):
        parse_measured(text)
    d = parse_measured(text, ratio=-79.0)
    assert d.efficiency[0] == pytest.approx(28 / (79 * 0.43))
    both = ("input_speed_rpm,output_torque_Nm,input_torque_Nm,efficiency\n"
            "500,28,0.43,0.8243\n500,28,0.43,0.70\n")
    d = parse_measured(both, ratio=79)
    assert len(d) == 1 and "disagrees with T2/(|i| T1)" in d.rejected[0].reason


def test_sensor_sigma_from_sidecar(tmp_path):
    """sigma = eta sqrt((a1 R1/T1)^2 + (a2 R2/T2)^2) with the sine rig's sensors."""
    csv = tmp_path / "rig.csv"
    csv.write_text("# source: header\ninput_speed_rpm,output_torque_Nm,input_torque_Nm\n"
                   "500,28,0.43\n")
    sensors = {"input_torque": {"range_Nm": 10, "accuracy": 0.001},
               "output_torque": {"range_Nm": 100, "accuracy": 0.002}}
    (tmp_path / "rig.json").write_text(json.dumps({"source": "sidecar", "sensors": sensors}))
    d = load_measured(csv, ratio=79)
    eta = 28 / (79 * 0.43)
    assert d.provenance["source"] == "sidecar"          # the sidecar wins
    assert d.sigma[0] == pytest.approx(eta * math.hypot(0.01 / 0.43, 0.2 / 28))


def test_missing_file():
    with pytest.raises(MeasuredDataError, match="no such measured-data file"):
        load_measured("/nonexistent/x.csv")


def test_round_trip():
    d = parse_measured("\n".join([HEADER, "500,28,0.8247,50,0.0,r1", "1000,20,0.8,60,0.5,r2"]))
    d2 = parse_measured(ms.to_csv(d))
    for a, b in ((d.speed_rpm, d2.speed_rpm), (d.efficiency, d2.efficiency),
                 (d.oil_temp_C, d2.oil_temp_C)):
        np.testing.assert_allclose(a, b)
    assert list(d2.run_id) == ["r1", "r2"]


def test_case_points(cases_dir):
    d = ms.from_case(load_case(cases_dir / "sine_prototype.toml"))
    assert len(d) == 1 and d.efficiency[0] == pytest.approx(0.8247)


@pytest.mark.parametrize("name, case, eta", [("sine_prototype_rig", "sine_prototype", 0.8247),
                                             ("rv40e_rig", "rv40e", 0.7323)])
def test_real_data_files_load_with_provenance(cases_dir, name, case, eta):
    c = load_case(cases_dir / f"{case}.toml")
    d = load_measured(cases_dir.parent / "data" / f"{name}.csv", ratio=c.ratio())
    assert len(d) == 1 and d.efficiency[0] == pytest.approx(eta)
    assert d.provenance["source"] and d.provenance["how_obtained"]


_GOOD = st.tuples(st.floats(1, 5000), st.floats(0.1, 500), st.floats(0.01, 1.0))
_BAD = st.sampled_from(["-1,10,0.5", "100,10,1.5", "100,10,0", "100,,0.5", "x,10,0.5",
                        "100,10,nan", "100,10"])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(_GOOD, _BAD), min_size=1, max_size=30))
def test_no_good_row_lost(rows):
    """Invariant: every good row is kept, in order, and every bad row is refused with its
    own line number."""
    lines, good, bad_lines = [], [], []
    for k, r in enumerate(rows):
        if isinstance(r, tuple):
            lines.append(",".join(repr(v) for v in r))
            good.append(r)
        else:
            lines.append(r)
            bad_lines.append(k + 2)
    text = "input_speed_rpm,output_torque_Nm,efficiency\n" + "\n".join(lines) + "\n"
    if not good:
        with pytest.raises(MeasuredDataError):
            parse_measured(text)
        return
    d = parse_measured(text)
    np.testing.assert_array_equal(d.speed_rpm, [g[0] for g in good])
    np.testing.assert_array_equal(d.efficiency, [g[2] for g in good])
    assert [r.line for r in d.rejected] == bad_lines


@pytest.mark.parametrize("bad", [None, "1000,-5,0.8,0.5,40,0.1,r1,x",
                                 '1000,5,"0.8",0.5,40,0.1,r1,x', "",
                                 "1000,5,0.8,0.5,40,0.1,r1,x,"])
def test_a_plain_file_read_at_once_gives_the_row_loop_s_record(monkeypatch, bad):
    """A plain comma-separated file of good rows is read column by column (clean_rows);
    the record is the row loop's, value for value; a file with a bad row, a quoted cell, a
    blank line or a trailing comma is read by the row loop (its refusals and line numbers)."""
    from toothfem.efficiency.loop import measured_columns as mc

    rng = np.random.default_rng(5)
    rows = [f"{a:.6g},{t:.6g},{e:.6g},{t / (51 * e):.9g},{c:.4g},{h:.6g},r{k % 3}, {v:.3g}"
            for k, (a, t, e, c, h, v) in enumerate(zip(
                rng.uniform(100, 3000, 300), rng.uniform(1, 200, 300),
                rng.uniform(0.5, 0.95, 300), rng.uniform(20, 90, 300),
                np.arange(300) / 60, rng.normal(size=300)))]
    if bad is not None:
        rows.insert(150, bad)
    text = "\n".join(["# source: rig", "input_speed_rpm,output_torque_Nm,efficiency,"
                      "input_torque_Nm,oil_temp_C,time_h,run_id,vibration_mm_s"] + rows)
    seen = []
    monkeypatch.setattr(ms, "clean_rows", lambda *a: seen.append(mc.clean_rows(*a)) or seen[-1])
    at_once = parse_measured(text, ratio=51)
    monkeypatch.setattr(ms, "clean_rows", lambda *a: None)
    by_rows = parse_measured(text, ratio=51)
    assert (seen[0] is None) == (bad is not None)
    for f in ("speed_rpm", "torque_Nm", "efficiency", "oil_temp_C", "time_h", "run_id",
              "input_torque_Nm", "lines"):
        a, b = getattr(at_once, f), getattr(by_rows, f)
        assert np.array_equal(a, b) and np.asarray(a).dtype == np.asarray(b).dtype, f
    assert at_once.extra.keys() == by_rows.extra.keys() == {"vibration_mm_s"}
    assert np.array_equal(at_once.extra["vibration_mm_s"], by_rows.extra["vibration_mm_s"])
    assert (at_once.rejected, at_once.notes, at_once.provenance) == \
        (by_rows.rejected, by_rows.notes, by_rows.provenance)
    assert len(at_once) == 300          # the good rows; the bad one refused or skipped
