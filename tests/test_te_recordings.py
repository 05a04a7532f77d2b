"""TE and hysteresis rig recordings (issue 24, items 1 and 2): both file shapes read and
reduced file by file, the catalogue figures of a hysteresis recording against a hand
computation and the analytic truth, the ripple's orders recovered and named by the drive's
orders, per-file re-zeroing offsets out of the width, bad files refused in one line."""
import math
import time

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency.loop.te import (hysteresis_figures, read_hysteresis,
                                         read_hysteresis_recordings, read_te_file,
                                         read_te_recordings, te_figures, te_spectrum)
from toothfem.efficiency.loop.te import synthetic as sy
from toothfem.efficiency.loop.te.columns import ANGLE_UNITS, name_pattern, values_from_name
from toothfem.efficiency.loop.te.spectrum import combine_spectra, find_peaks
from toothfem.errors import MeasuredDataError
from toothfem.fem.datasheet.sheet import LOST_MOTION_FRACTION, RIGIDITY_FRACTIONS
from toothfem.fem.drives import drive_for

RATED = 1000.0
LOOP = sy.Loop(rated_torque_Nm=RATED, rigidity_Nm_per_arcmin=200.0,
               low_rigidity_Nm_per_arcmin=80.0, backlash_arcmin=0.6,
               friction_width_arcmin=0.4)
PER_STEP = 40
#: Agreement asked of the model-free figures with the hand computation and the truth.
RTOL = 0.02
ARCSEC = ANGLE_UNITS["arcsec"]


@pytest.fixture(scope="module")
def rv_orders(cases_dir):
    return drive_for(load_case(cases_dir / "rv40e.toml")).te_orders()


def _loop_samples(seed=1):
    return LOOP.samples(samples_per_step=PER_STEP, torque_noise_Nm=0.5,
                        twist_noise_arcmin=0.005, rng=np.random.default_rng(seed))


def _hand_figures(path):
    """The catalogue figures computed by hand from the file: the rows grouped by the
    staircase's steps (the test plan: PER_STEP rows a step), each step's mean torque and
    twist, the steps of the closed loop picked by their set torque and branch."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    torque = data["output_torque_Nm"].reshape(-1, PER_STEP).mean(axis=1)
    twist = data["twist_arcmin"].reshape(-1, PER_STEP).mean(axis=1)
    set_torque, branch, _ = LOOP.path()
    virgin = len(sy.STAIRCASE)

    def step(fraction, b):
        k = [i for i in range(virgin, set_torque.size)
             if math.isclose(set_torque[i], fraction * RATED, abs_tol=1e-9) and branch[i] == b]
        assert len(k) == 1
        return k[0]

    f50, f100 = RIGIDITY_FRACTIONS
    r50, r100 = step(f50, 1), step(f100, 1)
    fm50, fm100 = step(-f50, -1), step(-f100, -1)
    pos = (torque[r100] - torque[r50]) / (twist[r100] - twist[r50])
    neg = (torque[fm50] - torque[fm100]) / (twist[fm50] - twist[fm100])
    lm = LOST_MOTION_FRACTION

    def mid(fraction):
        return 0.5 * (twist[step(fraction, 1)] + twist[step(fraction, -1)])

    def mid_torque(fraction):
        return 0.5 * (torque[step(fraction, 1)] + torque[step(fraction, -1)])

    ends = []
    for s in (1, -1):
        fr = [s * f for f in (0.03, 0.06, 0.1)]
        ends.append(np.polyfit([mid_torque(f) for f in fr], [mid(f) for f in fr], 1)[1])
    return {"rigidity_pos": pos, "rigidity_neg": neg, "rigidity": 0.5 * (pos + neg),
            "lost_motion": mid(lm) - mid(-lm),
            "hysteresis_loss": twist[step(0.0, -1)] - twist[step(0.0, 1)],
            "backlash": ends[0] - ends[1]}


def _module_figures(f):
    pos, neg = f.rigidity_by_direction_Nm_per_arcmin
    return {"rigidity_pos": pos, "rigidity_neg": neg, "rigidity": f.rigidity_Nm_per_arcmin,
            "lost_motion": f.lost_motion_arcmin, "hysteresis_loss": f.hysteresis_loss_arcmin,
            "backlash": f.backlash_arcmin}


def test_hysteresis_figures_agree_with_hand_and_truth(tmp_path):
    """Rigidity, lost motion, hysteresis loss and backlash of a recording agree within 2 %
    with the same figures computed by hand from the recording's steps, and with the
    analytic loop's own figures."""
    path = sy.write_hysteresis(tmp_path / "loop.csv", _loop_samples())
    rec = read_hysteresis(path)
    assert rec.branch is None and len(rec) == PER_STEP * LOOP.path()[0].size
    fig = hysteresis_figures(rec, RATED)
    assert fig.notes == ()
    got, hand = _module_figures(fig), _hand_figures(path)
    truth = {"rigidity_pos": LOOP.rigidity_Nm_per_arcmin,
             "rigidity_neg": LOOP.rigidity_Nm_per_arcmin,
             "rigidity": LOOP.rigidity_Nm_per_arcmin, "lost_motion": LOOP.lost_motion_arcmin,
             "hysteresis_loss": LOOP.hysteresis_loss_arcmin, "backlash": LOOP.backlash_arcmin}
    for key in got:
        assert got[key] == pytest.approx(hand[key], rel=RTOL), key
        assert got[key] == pytest.approx(truth[key], rel=RTOL), key
    # the datasheet's window: rising and falling at -3 %, 0, +3 %
    np.testing.assert_allclose(fig.window["torque_Nm"], [-30.0, 0.0, 30.0])
    assert fig.window["falling_arcmin"][1] - fig.window["rising_arcmin"][1] == \
        pytest.approx(fig.hysteresis_loss_arcmin)
    assert set(fig.summary()) >= {"torsional_rigidity_Nm_per_arcmin", "lost_motion_arcmin",
                                  "backlash_arcmin", "hysteresis_loss_arcmin"}


def test_hysteresis_branch_column_units_offset_delimiter(tmp_path):
    """A branch column, the twist in arcsec, semicolons with decimal commas and a large zero
    offset of the file give the same figures as the plain file."""
    s = _loop_samples()
    plain = hysteresis_figures(read_hysteresis(sy.write_hysteresis(tmp_path / "a.csv", s)),
                               RATED)
    other = sy.write_hysteresis(tmp_path / "b.csv", s, twist_unit="arcsec", with_branch=True,
                                delimiter=";", offset_arcmin=250.0,
                                comments={"oil_temp_C": "40,5", "rig": "B"})
    rec = read_hysteresis(other)
    assert rec.branch is not None and rec.condition.oil_temp_C == pytest.approx(40.5)
    assert rec.provenance["rig"] == "B"
    fig = hysteresis_figures(rec, RATED)
    for key, v in _module_figures(plain).items():
        assert _module_figures(fig)[key] == pytest.approx(v, rel=1e-6, abs=1e-6), key


def test_hysteresis_set_and_missing_torque(tmp_path):
    """Several files: figures per file, a bad file refused; a loop short of the rated
    torque gives NaN rigidity with a note, not a refusal."""
    sy.write_hysteresis(tmp_path / "h1.csv", _loop_samples(1))
    sy.write_hysteresis(tmp_path / "h2.csv", _loop_samples(2))
    (tmp_path / "h3.csv").write_text("output_torque_Nm,angle_arcmin\n1,2\n", encoding="utf-8")
    hs = read_hysteresis_recordings(tmp_path, RATED, progress=False)
    assert len(hs.figures) == 2 and len(hs.refused) == 1
    msg = str(hs.refused[0])
    assert "h3.csv" in msg and "twist_" in msg and "\n" not in msg
    assert hs.mean()["torsional_rigidity_Nm_per_arcmin"] == pytest.approx(200.0, rel=RTOL)
    fig = hysteresis_figures(read_hysteresis(tmp_path / "h1.csv"), 2 * RATED)
    assert math.isnan(fig.rigidity_Nm_per_arcmin)
    assert any("rigidity" in n and "N m" in n for n in fig.notes)


def test_ripple_orders_recovered_and_named(tmp_path, rv_orders):
    """Known orders and amplitudes of an RV-40E TE come back from a long table with uneven
    angle steps and encoder noise, each named by the drive's orders (2x multiples too)."""
    assert rv_orders["crank revolution = lobe passing (Zc)"] == 39.0
    assert rv_orders["pin passing (Zp) = eccentric against the disc"] == 40.0
    assert rv_orders["input revolution"] == 121.0
    amps = {1: 6.0, 39: 8.0, 40: 5.0, 80: 2.0, 121: 3.0}
    rip = sy.Ripple(amplitudes_arcsec=amps, phases_rad={39: 1.0, 121: -0.5},
                    width_arcsec=24.0)
    sy.write_te_long(tmp_path / "te.csv", [(rip, 1, None), (rip, -1, None)], revolutions=4,
                     samples_per_revolution=2048, noise_arcsec=0.3, jitter=0.6,
                     direction_words=True, comments={"output_torque_Nm": 500})
    figs = te_figures(read_te_recordings(tmp_path, progress=False), named_orders=rv_orders)
    (cond,) = figs.conditions
    assert cond.condition.output_torque_Nm == 500.0
    names = {1: "output revolution", 39: "crank revolution = lobe passing (Zc)",
             40: "pin passing (Zp) = eccentric against the disc",
             80: "2x pin passing (Zp) = eccentric against the disc", 121: "input revolution"}
    for d in (cond.forward, cond.backward):
        assert d.spectrum.resolution_orders == 0.25
        found = {round(p.order): p for p in d.peaks}
        assert set(found) == set(amps)                   # nothing else above the noise
        for q, a in amps.items():
            assert found[q].amplitude_arcsec == pytest.approx(a, rel=RTOL), q
            assert abs(found[q].order - q) < 0.05
            assert found[q].names[0] == names[q]
    assert cond.width_arcsec == pytest.approx(24.0, abs=0.1)


def test_order_off_the_grid_named_and_resolution(tmp_path):
    """An order between the bins (a 2K-V input order i = 36.57) keeps its amplitude with
    the Hann window and is named within the tolerance; one revolution with the rectangular
    window tells orders 39 and 40 apart at a resolution of one order."""
    rng = np.random.default_rng(3)
    a = sy.sweep_angles(3, 1024, jitter=0.5, rng=rng)
    rip = sy.Ripple(amplitudes_arcsec={36.57: 4.0, 39: 2.0})
    spec = te_spectrum(a, rip.te_arcsec(a, 1) * ARCSEC)
    assert spec.revolutions == 3 and spec.resolution_orders == pytest.approx(1 / 3)
    from toothfem.efficiency.loop.te import named_peaks
    peaks = {round(p.order): p for p in named_peaks(spec, {"input revolution": 36.57,
                                                           "crank revolution": 39.0})}
    assert peaks[37].amplitude_arcsec == pytest.approx(4.0, rel=RTOL)
    assert peaks[37].names == ("input revolution",)
    assert peaks[39].names == ("crank revolution",)
    b = sy.sweep_angles(1, 1024)
    noise = 0.02 * ARCSEC * rng.standard_normal(b.size)
    one = te_spectrum(b, sy.Ripple(amplitudes_arcsec={39: 2.0, 40: 1.0}).te_arcsec(b, 1)
                      * ARCSEC + noise, window="rect")
    assert one.resolution_orders == 1.0
    got = {round(p.order): p.amplitude_arcsec for p in find_peaks(one)}
    assert got == pytest.approx({39: 2.0, 40: 1.0}, rel=RTOL)
    # spectra of different lengths combine on the coarser grid, keeping a tone's amplitude
    c = combine_spectra([spec, te_spectrum(b, rip.te_arcsec(b, 1) * ARCSEC)])
    assert c.revolutions == 1 and c.sweeps == 2


def _offset_files(folder, offset):
    """Shape (a) files named by their condition: two repeats at 100 N m, one at 300 N m; the
    first repeat re-zeroed by ``offset``."""
    folder.mkdir()
    plan = [("te_100Nm_15rpm_run1.csv", 100.0, 20.0, offset, 11),
            ("te_100Nm_15rpm_run2.csv", 100.0, 20.0, 0.0, 12),
            ("te_300Nm_15rpm_run1.csv", 300.0, 36.0, 0.0, 13)]
    for name, _, width, off, seed in plan:
        rip = sy.Ripple(amplitudes_arcsec={39: 5.0, 40: 3.0}, width_arcsec=width)
        sy.write_te_sides(folder / name, rip, revolutions=2, samples_per_revolution=1024,
                          offset_arcsec=off, noise_arcsec=0.5, jitter=0.5,
                          rng=np.random.default_rng(seed))
    return read_te_recordings(folder, progress=False,
                              name_pattern="te_{output_torque_Nm}Nm_{input_speed_rpm}rpm_*.csv")


def test_rezeroing_offset_does_not_change_the_width(tmp_path):
    """A file re-zeroed by 900 arcsec: the widths are those of the same files without it
    (to rounding), the fit finds the offset, the levels are unchanged."""
    clean = te_figures(_offset_files(tmp_path / "clean", 0.0))
    shifted = te_figures(_offset_files(tmp_path / "shifted", 900.0))
    assert [c.condition.output_torque_Nm for c in shifted.conditions] == [100.0, 300.0]
    assert shifted.conditions[0].condition.input_speed_rad_s == pytest.approx(
        15 * 2 * math.pi / 60)
    for a, b, width in zip(clean.conditions, shifted.conditions, (20.0, 36.0)):
        assert b.width_arcsec == pytest.approx(a.width_arcsec, abs=1e-6)
        assert b.width_arcsec == pytest.approx(width, abs=0.1)
        assert b.forward.mean_arcsec == pytest.approx(a.forward.mean_arcsec, abs=1e-6)
        assert len(b.files) == (2 if b.condition.output_torque_Nm == 100 else 1)
    off = {k.rsplit("/", 1)[-1]: v for k, v in shifted.offsets_arcsec.items()}
    assert off["te_100Nm_15rpm_run1.csv"] - off["te_100Nm_15rpm_run2.csv"] == \
        pytest.approx(900.0, abs=0.1)
    # the offset would have biased a plain pooled mean of the forward runs by 450 arcsec
    runs = [r for r in _offset_files(tmp_path / "again", 900.0).runs
            if r.direction == 1 and r.condition.output_torque_Nm == 100]
    assert np.mean([r.mean_te_rad for r in runs]) / ARCSEC > 400


def test_width_needs_both_directions_in_one_file(tmp_path):
    """Forward in one file, backward in another: each file's offset hides the width
    (NaN, with a note); the levels of a file stepping through two torques keep their
    difference (the joint fit)."""
    rip = sy.Ripple(amplitudes_arcsec={39: 5.0}, width_arcsec=20.0)
    sy.write_te_long(tmp_path / "f.csv", [(rip, 1, None)], revolutions=2,
                     samples_per_revolution=512, comments={"output_torque_Nm": 100})
    sy.write_te_long(tmp_path / "b.csv", [(rip, -1, None)], revolutions=2,
                     samples_per_revolution=512, offset_arcsec=50.0,
                     comments={"output_torque_Nm": 100})
    (cond,) = te_figures(read_te_recordings(tmp_path, progress=False)).conditions
    assert math.isnan(cond.width_arcsec) and "never in one file" in cond.notes[0]
    # one long table: 100 N m (level 0) then 200 N m (level +50 arcsec), torque logged
    # with noise; the fit keeps the 50 arcsec between the levels, and both widths
    low = sy.Ripple(amplitudes_arcsec={39: 5.0}, width_arcsec=20.0)
    high = sy.Ripple(amplitudes_arcsec={39: 5.0}, width_arcsec=30.0, level_arcsec=50.0)
    sub = tmp_path / "long"
    sub.mkdir()
    sy.write_te_long(sub / "stair.csv", [(low, 1, 100.0), (low, -1, 100.0), (high, 1, 200.0),
                                         (high, -1, 200.0)], revolutions=2,
                     samples_per_revolution=512, offset_arcsec=-300.0, noise_arcsec=0.2,
                     torque_noise_Nm=0.3)
    a, b = te_figures(read_te_recordings(sub, progress=False)).conditions
    assert (a.condition.output_torque_Nm, b.condition.output_torque_Nm) == \
        pytest.approx((100.0, 200.0), abs=0.05)
    mid = [0.5 * (c.forward.mean_arcsec + c.backward.mean_arcsec) for c in (a, b)]
    assert mid[1] - mid[0] == pytest.approx(50.0, abs=0.1)
    assert (a.width_arcsec, b.width_arcsec) == pytest.approx((20.0, 30.0), abs=0.1)


def test_bad_files_refused_in_one_line_good_files_read(tmp_path):
    """A missing column, an unknown unit, a non-numeric cell, non-UTF-8 bytes and an unknown
    direction word each refuse their file in one line naming it and the column (or the
    byte's place); the good files are read."""
    rip = sy.Ripple(amplitudes_arcsec={39: 5.0}, width_arcsec=10.0)

    def good(name):
        # each file its own provenance line: two files of the same bytes are one recording
        # read twice (refused as such, test_te_running.py)
        return sy.write_te_sides(tmp_path / name, rip, revolutions=2,
                                 samples_per_revolution=256, comments={"file": name})

    good("good1.csv")
    good("good2.csv")
    p = good("missing.csv")
    p.write_text("\n".join(line.rsplit(",", 1)[0] for line in p.read_text().splitlines()))
    p = good("unit.csv")
    p.write_text(p.read_text().replace("te_backward_arcsec", "te_backward_urad"))
    p = good("cell.csv")
    lines = p.read_text().splitlines()
    cells = lines[57].split(",")
    cells[1] = "12.3x"
    lines[57] = ",".join(cells)
    p.write_text("\n".join(lines))
    p = sy.write_te_sides(tmp_path / "latin.csv", rip, revolutions=2,
                          samples_per_revolution=256, comments={"rig": "A"})
    p.write_bytes(p.read_bytes().replace(b"rig: A", "rig: 20 \u00b0C".encode("latin-1")))
    p = sy.write_te_long(tmp_path / "word.csv", [(rip, 1, None), (rip, -1, None)],
                         revolutions=2, samples_per_revolution=256)
    lines = p.read_text().splitlines()
    lines[40] = lines[40].rsplit(",", 1)[0] + ",sideways"
    p.write_text("\n".join(lines))
    rec = read_te_recordings(tmp_path)          # the progress bar: silent off a terminal
    assert sorted(f.rsplit("/", 1)[-1] for f in rec.files) == ["good1.csv", "good2.csv"]
    assert len(rec.runs) == 4
    why = {r.source.rsplit("/", 1)[-1]: str(r) for r in rec.refused}
    assert set(why) == {"missing.csv", "unit.csv", "cell.csv", "latin.csv", "word.csv"}
    for name, text in why.items():
        assert "\n" not in text and text.startswith(str(tmp_path / name)), text
    assert "missing column te_backward_" in why["missing.csv"]
    assert "'te_backward_urad'" in why["unit.csv"] and "unknown unit 'urad'" in why["unit.csv"]
    assert "line 58" in why["cell.csv"] and "'te_forward_arcsec'" in why["cell.csv"] \
        and "'12.3x' is not a number" in why["cell.csv"]
    assert "not UTF-8" in why["latin.csv"] and "line 1, column 11" in why["latin.csv"]
    assert "line 41" in why["word.csv"] and "'direction'" in why["word.csv"]
    with pytest.raises(MeasuredDataError, match="no TE run"):
        te_figures(read_te_recordings(tmp_path / "latin.csv", progress=False))


def test_condition_sources_units_and_pattern(tmp_path):
    """The condition from a column, a comment or the file name (which must agree);
    angles in rad, TE in arcmin; a semicolon file with decimal commas."""
    rip = sy.Ripple(amplitudes_arcsec={39: 5.0}, width_arcsec=12.0)
    p = sy.write_te_sides(tmp_path / "te_250Nm_2p5rpm.csv", rip, revolutions=2,
                          samples_per_revolution=512, angle_unit="rad", te_unit="arcmin",
                          delimiter=";", comments={"oil_temp_K": "313,15", "operator": "X"},
                          extra_columns={"output_torque_Nm": 250.0, "note": "x"})
    runs, notes = read_te_file(p, name_pattern="te_{output_torque_Nm}Nm_{input_speed_rpm}rpm.csv")
    assert len(runs) == 2 and any("'note' not used" in n for n in notes)
    c = runs[0].condition
    assert (c.output_torque_Nm, c.oil_temp_C) == pytest.approx((250.0, 40.0))
    assert c.input_speed_rad_s == pytest.approx(2.5 * 2 * math.pi / 60)
    assert runs[0].revolutions == pytest.approx(2.0)
    fwd, bwd = sorted(runs, key=lambda r: -r.direction)
    assert (fwd.mean_te_rad - bwd.mean_te_rad) / ARCSEC == pytest.approx(12.0, abs=0.01)
    # the name says 300 N m, the column 250: refused naming the line and column
    q = tmp_path / "te_300Nm_2p5rpm.csv"
    q.write_bytes(p.read_bytes())
    with pytest.raises(MeasuredDataError, match=r"line \d+: column 'output_torque_Nm'"):
        read_te_file(q, name_pattern="te_{output_torque_Nm}Nm_{input_speed_rpm}rpm.csv")
    pat = name_pattern("te_{output_torque_Nm}Nm_{direction}.csv")
    assert values_from_name(pat, "te_1,5Nm_bwd.csv", "f") == \
        {"output_torque_Nm": 1.5, "direction": -1}
    with pytest.raises(MeasuredDataError, match="does not match the pattern"):
        values_from_name(pat, "other.csv", "other.csv")
    with pytest.raises(MeasuredDataError, match="not a condition column"):
        name_pattern("te_{torque}.csv")
    with pytest.raises(MeasuredDataError, match="unknown unit 'lbft'"):
        name_pattern("te_{output_torque_lbft}.csv")


def test_drive_te_orders(cases_dir):
    """The orders of the three drives from their trains."""
    khv = drive_for(load_case(cases_dir / "cycloid_khv.toml")).te_orders()
    assert khv == {"output revolution": 1.0,
                   "input revolution = crank revolution = lobe passing (Zc)": 29.0,
                   "pin passing (Zp) = eccentric against the disc": 30.0,
                   "pin mesh": 870.0}
    rv = drive_for(load_case(cases_dir / "rv40e.toml")).te_orders()
    assert rv["input revolution"] == 121.0 and rv["pin mesh"] == 40 * 39
    assert rv["first-stage mesh"] == 12 * (121 - 1)
    sine = drive_for(load_case(cases_dir / "sine_prototype.toml")).te_orders()
    assert sine["ring-tooth passing (Z2)"] == 80.0 and sine["tooth mesh"] == 80 * 79
    assert sine["input revolution = crank revolution = planet-tooth passing (Z1)"] == 79.0


def test_large_file_streamed(tmp_path):
    """A 100,000-row shape (a) file is read and reduced (the time is printed, not asserted)."""
    rip = sy.Ripple(amplitudes_arcsec={39: 5.0, 121: 2.0}, width_arcsec=10.0)
    p = sy.write_te_sides(tmp_path / "big.csv", rip, revolutions=4,
                          samples_per_revolution=25_000, noise_arcsec=0.3, jitter=0.5)
    t0 = time.perf_counter()
    rec = read_te_recordings([p], progress=False)
    took = time.perf_counter() - t0
    print(f"\n100,001-row TE file read and reduced in {took:.2f} s")
    assert [r.samples for r in rec.runs] == [100_001, 100_001]
    assert rec.runs[0].binned_te_rad.dtype == np.float32
    (cond,) = te_figures(rec).conditions
    assert cond.width_arcsec == pytest.approx(10.0, abs=0.05)
