"""The accuracy life (issue 44): Archard's law on the pin-on-disc hand models, the
coefficient by regime and the run-in, and ``toothfem wear`` on the RV-40E (docs/wear.md)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from toothfem.errors import CaseError
from toothfem.efficiency import wear as w
from toothfem.efficiency.mixed_film import asperity_load_share

from tests.conftest import CASES, _command_output

#: The hand models' pin on its disc: a steel pin of 5 mm radius, 10 mm wide, 50 N, K 1e-6,
#: 700 HV; the Hertz half-width of the cylinder on the flat (E* 114 GPa).
K, F, B, R, H = 1e-6, 50.0, 0.010, 0.005, 700 * 9.80665e6
A_HERTZ = math.sqrt(4 * F / B * R / (math.pi * 114e9))


def test_archard_flat_pin_on_disc_is_the_closed_form():
    # a flat-ended pin of area A: depth K F s / (H A), linear in the sliding distance
    s, area = np.array([0.0, 1e3, 5e3, 2e4]), 12.5e-6
    depth = w.archard_volume(K, F, s, H) / area
    assert depth == pytest.approx(K * F * s / (H * area), rel=1e-14)
    assert depth[2] / depth[1] == pytest.approx(5.0, rel=1e-14)


def test_conforming_pin_runs_in_as_its_hand_model():
    """The cylindrical pin wears a flat: the depth from the worn volume in closed form
    (circular segment), the stepped run-in (dh = K p(h) ds / H with the pressure falling
    as the flat widens) on it, and its s^(2/3) law once past the Hertz band."""
    s = 2e4 * (np.arange(201) / 200) ** 3          # dense at the start, as the run-in is
    closed = w.conforming_depth(w.archard_volume(K, F, s, H), B, R, A_HERTZ)
    stepped = w.integrate_conforming(K, F, s, H, B, R, A_HERTZ)
    # midpoint steps: second order (50, 200, 800 steps: 2.5e-4, 1.5e-5, 9e-7 at the end;
    # 1e-3, 6e-5, 4e-6 over the second half): 200 steps within 2e-4 of the closed form
    assert stepped[100:] == pytest.approx(closed[100:], rel=2e-4)
    assert w.conforming_volume(closed, B, R, A_HERTZ) == pytest.approx(
        w.archard_volume(K, F, s, H), rel=1e-10)
    # far past the Hertz band: h = (3 K F s / (4 b H sqrt(2 R)))^(2/3)
    far = (3 * K * F * s[-1] / (4 * B * H * math.sqrt(2 * R))) ** (2 / 3)
    assert closed[-1] == pytest.approx(far, rel=0.02)      # h_a = a^2/2R is 1 % of it
    p = w.conforming_pressure(F, closed, B, R, A_HERTZ)
    assert np.all(np.diff(p) <= 0) and p[-1] < 0.2 * p[0]
    rate = np.diff(closed) / np.diff(s)
    assert rate[-1] < 0.5 * rate[len(rate) // 4]      # the run-in: slower as it conforms


def test_wear_coefficient_by_regime_and_run_in():
    # boundary: the asperities carry everything, K = K_b; full film: about 1 % at lambda 3
    # and 1 GPa (efficiency/mixed_film.py's own figure); mixed in between
    lam = np.array([0.2, 1.5, 3.0])
    k = w.wear_coefficient(1e-6, lam, 1e9, H)
    assert k[0] == pytest.approx(1e-6, rel=1e-12)
    assert k[2] == pytest.approx(1e-6 * asperity_load_share(3.0, 1e9, H), rel=1e-12)
    assert k[2] < 0.02e-6 < k[1] < k[0]
    assert list(w.regime(lam)) == ["boundary", "mixed", "full film"]
    sigma = 0.7e-6
    assert w.run_in_factor(0.0, sigma) == pytest.approx(w.RUN_IN_WEAR_RATIO)
    assert w.run_in_factor(20 * sigma, sigma) == pytest.approx(1.0, abs=1e-7)
    assert w.run_in_roughness(sigma, 20 * sigma) == pytest.approx(
        w.RUN_IN_ROUGHNESS_RATIO * sigma, rel=1e-7)


@pytest.mark.parametrize("argv, says", [
    (["--hours", "0"], "hours = 0"),
    (["--hours", "100", "--wear-coefficient=-1e-9"], "--wear-coefficient = -1e-09"),
    (["--hours", "100", "--steps", "0"], "steps = 0"),
])
def test_wear_refuses_bad_input_naming_it(argv, says, capsys):
    from toothfem import cli
    assert cli.main(["wear", str(CASES / "rv40e.toml"), *argv]) == 2
    assert says in capsys.readouterr().err


def test_wear_refuses_a_drive_without_a_cycloid_disc(capsys):
    from toothfem import cli
    assert cli.main(["wear", str(CASES / "sine_prototype.toml"), "--hours", "10"]) == 2
    assert "case.drive = 'sine'" in capsys.readouterr().err


@pytest.fixture(scope="module")
def rv40e_life():
    """The RV-40E's 2000 h at the default coefficient, on a short grid."""
    from toothfem.case import load_case
    from toothfem.wear import wear_analysis
    return wear_analysis(load_case(CASES / "rv40e.toml"), 2000.0, steps=4)


def test_rv40e_lost_motion_grows_from_the_datasheets(rv40e_life, tmp_path):
    from toothfem.case import load_case
    from toothfem.efficiency import rated_output_torque
    from toothfem.efficiency.no_load import path_friction
    from toothfem.fem.datasheet.sheet import lost_motion_arcmin
    from toothfem.fem.drives import drive_for
    from toothfem.fem.system.datasheet import SystemTwist
    case = load_case(CASES / "rv40e.toml")
    si, drive = case.to_si(), drive_for(case)
    # the datasheet's lost motion as `stiffness` computes it (36 positions, friction)
    sheet = lost_motion_arcmin(SystemTwist(drive.system_model(drive.supports(si.supports), 36),
                                           friction=path_friction(si, drive)),
                               rated_output_torque(si)[0])
    rows = rv40e_life.history
    lm = np.array([r["lost_motion_arcmin"] for r in rows])
    hours = np.array([r["hours"] for r in rows])
    assert lm[0] == pytest.approx(sheet, rel=0.02)
    assert np.all(np.diff(lm) > 0)
    # faster in the first quarter of the hours than in the last (the grid's rows at 500,
    # 1125 and 2000 h: the last quarter's rate from the last interval, a bound above it)
    first = (np.interp(500, hours, lm) - lm[0]) / 500
    last = (lm[-1] - lm[-2]) / (hours[-1] - hours[-2])
    assert first > 1.5 * last
    # the parts add up to the lost motion (the work balance); the support bearings open
    # more clearance than the crank bearings, as in the published test
    end = rows[-1]
    assert sum(end["lost_motion_parts_arcmin"].values()) == pytest.approx(lm[-1], rel=1e-6)
    assert end["clearance_um"]["support bearings"] > end["clearance_um"]["crank bearings"] > 0
    assert end["backlash_arcmin"] > rows[0]["backlash_arcmin"]
    summary = rv40e_life.write(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(summary["files"])
    hit = rv40e_life.hours_to_limit
    assert hit is not None and 0 < hit < 2000
    assert np.interp(hit, hours, lm) == pytest.approx(1.0, rel=1e-9)


def test_zero_coefficient_leaves_every_figure_unchanged():
    out = json.loads(_command_output(["wear", CASES / "rv40e.toml", "--hours", "5000",
                                      "--wear-coefficient", "0", "--steps", "2", "--json"]))
    rows = out["history"]
    assert [r["hours"] for r in rows] == [0.0, 1250.0, 5000.0]
    for r in rows[1:]:
        for key in ("lost_motion_arcmin", "backlash_arcmin", "te_mean_arcsec",
                    "te_peak_to_peak_arcsec", "efficiency"):
            assert r[key] == rows[0][key], key
        assert set(r["clearance_um"].values()) == {0.0}
    assert out["hours_to_lost_motion_limit"] is None


@pytest.mark.slow
def test_halving_the_steps_moves_the_end_lost_motion_below_1_percent():
    """The hours' steps, at 4 meshing positions (the steps' error does not depend on how
    many positions each step solves; 12 positions measured 0.18 %, docs/wear.md)."""
    from toothfem.case import load_case
    from toothfem.wear import DEFAULT_STEPS, wear_analysis
    case = load_case(CASES / "rv40e.toml")
    ends = [wear_analysis(case, 2000.0, steps=n, positions=4).history[-1]["lost_motion_arcmin"]
            for n in (DEFAULT_STEPS, 2 * DEFAULT_STEPS)]
    assert ends[0] == pytest.approx(ends[1], rel=0.01)


# -- the wear effect: a rig's long-run log fitted with the loops' engine -------------------

def _surrogate_curve(hours):
    """A wear curve of the shape the model's has (a run-in and a steady growth in K t):
    LM = 0.85 + 150 sqrt(K t) + 5e4 K t [arcmin], on geometric rows of K t."""
    from toothfem.wear_loop import WearCurve
    kt = np.concatenate([[0.0], np.geomspace(1e-12, 1e-4, 81)])
    return WearCurve(kt, 0.85 + 150 * np.sqrt(kt) + 5e4 * kt, hours)


def test_wear_effect_recovers_a_known_coefficient_on_a_surrogate_curve():
    from toothfem.wear_loop import fit_log
    hours = np.linspace(0.0, 2000.0, 21)
    curve = _surrogate_curve(hours)
    k_true, offset, sigma = 2e-9, 0.03, 0.005
    clean = curve.lost_motion(hours, k_true) + offset
    noisy = clean + np.random.default_rng(7).normal(0.0, sigma, hours.size)
    exact = fit_log(curve, hours, clean, sigma_arcmin=sigma)
    # the same curve made the rows: the fit's own tolerance (fit_tol 1e-10) is all
    assert exact.wear_coefficient == pytest.approx(k_true, rel=1e-5)
    assert exact.lost_motion_offset_arcmin == pytest.approx(offset, abs=1e-6)
    fit = fit_log(curve, hours, noisy, sigma_arcmin=sigma)
    # with the noise: within 3 of its standard errors, which are a few per cent
    assert abs(fit.wear_coefficient - k_true) < 3 * fit.wear_coefficient_stderr
    assert fit.wear_coefficient_stderr < 0.05 * k_true
    with pytest.raises(CaseError, match="hours and lost_motion_arcmin"):
        fit_log(curve, hours[:2], clean[:2])


@pytest.mark.slow
def test_wear_effect_recovers_the_coefficient_of_a_generated_rig_log():
    """Rows generated by the wear model at a known K_b (its own run, on the log's hours),
    fitted on the curve of one run at another K_b: the state's dependence on K_b t alone
    (docs/wear.md) is what the fit rests on."""
    from toothfem.case import load_case
    from toothfem.wear import wear_analysis
    from toothfem.wear_loop import fit_wear
    case = load_case(CASES / "rv40e.toml")
    hours = np.linspace(0.0, 2000.0, 11)
    run = wear_analysis(case, 2000.0, wear_coefficient=2e-9, positions=6, times=hours)
    lm = np.array([r["lost_motion_arcmin"] for r in run.history]) + 0.03
    fit = fit_wear(case, hours, lm, sigma_arcmin=0.005, positions=6)
    # the curve's 4 rows a decade interpolated linearly: measured 0.4 %
    assert fit.wear_coefficient == pytest.approx(2e-9, rel=0.02)
    assert fit.lost_motion_offset_arcmin == pytest.approx(0.03, abs=0.01)


def test_output_pin_and_bearing_wear_are_their_hand_formulas():
    """In boundary lubrication (a film-less oil: lambda 0, K = K_b) and past the run-in, a
    pin in its hole and a bearing's races wear as Archard's volume over the surface the
    contact sweeps (efficiency/wear_contacts.py's docstrings)."""
    import dataclasses
    from toothfem.case import load_case
    from toothfem.efficiency import wear_contacts as wc
    from toothfem.fem.drives import drive_for
    case = load_case(CASES / "cycloid_khv.toml")
    si, drive = case.to_si(), drive_for(case)
    si = dataclasses.replace(si, lubricant=dataclasses.replace(si.lubricant,
                                                               dynamic_viscosity_Pa_s=1e-12))
    om, k, run_in = si.output_mechanism, 1e-8, 1e-3          # 1 mm: the run-in long done
    q = np.full((4, 2, om.pin_count), 500.0)
    w = wc.output_pin_wear(si, drive, om, q, speed_rad_s=100.0, k_boundary=k,
                           worn_depth_m=run_in)
    v = k * 500.0 * 2 * drive.geometry.eccentricity_m * 100.0 / si.material.hardness_Pa * 3600
    # the sliding interface: the pin in its sleeve's bore (same radius), else in its hole
    r_out = om.pin_radius_m if om.roller_radius_m is not None else \
        (om.hole_radius_m or om.pin_radius_m + drive.geometry.eccentricity_m)
    b = drive.face_width_m
    assert w.volume_m3_per_h["pin"] == pytest.approx(v, rel=1e-9)
    assert w.clearance_m_per_h == pytest.approx(
        v / (2 * math.pi * om.pin_radius_m * b) + v / (2 * math.pi * r_out * b), rel=1e-9)
    assert w.regime_share["boundary"] == 1.0
    bearing = next(b for b in drive.layout.bearing_set(si, drive) if "eccentric" in b.name)
    bw = wc.bearing_wear(si, drive, bearing, [1000.0], speed_rad_s=100.0, k_boundary=k,
                         worn_depth_m=run_in, element="eccentric bearing")
    d_m, dia = bearing.pitch_diameter_m, bearing.element_diameter_m
    slide = wc.SLIP * 100.0 * (d_m ** 2 - dia ** 2) / (4 * d_m)
    vol = k * wc.Q_SUM_PER_FR * 1000.0 * slide / si.material.hardness_Pa * 3600
    length = bearing.element_length_m or bearing.width_m
    assert bw.clearance_m_per_h == pytest.approx(
        2 * vol / (math.pi * length) * (1 / (d_m - dia) + 1 / (d_m + dia)), rel=1e-9)
    # the roller set's load sum: int cos^(10/9) / int cos^(19/9) over the load zone, in
    # closed form (int cos^a over +-pi/2 = sqrt(pi) G((a+1)/2) / G(a/2+1)); the trapezoid's
    # 2001 points leave 1e-6
    def whole(a):
        return math.sqrt(math.pi) * math.gamma((a + 1) / 2) / math.gamma(a / 2 + 1)
    assert whole(10 / 9) / whole(19 / 9) == pytest.approx(wc.Q_SUM_PER_FR, rel=1e-5)
