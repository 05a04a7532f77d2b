"""The loop's effects of issue 23 (the rig's sensors, the oil's grade, windage, bearing
preload, a warm-up along time), alias groups with the measurement that separates them, and
the rule that an effect at its parameter's bound is not an explanation.

Synthetic data (efficiency/loop/synthetic.py): the case plus one effect it does not declare,
torques read with the sine rig's sensor classes (ranges matched to the reducer). Effect sizes
are several times the noise, so a found effect must cut the held-out error at least 3x (the
issue's figure). An effect that another explains exactly (a drag on the input and the input
meter's zero offset) cannot be named by efficiency data: the truth must then be in the alias
group of the effect that was added, and the group must say how to tell them apart.
"""
import dataclasses

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency import evaluate
from toothfem.efficiency import loop as lp
from toothfem.efficiency.bearing_set import main_pair
from toothfem.efficiency.main_bearing import main_tilt
from toothfem.efficiency.loop import effects as fx
from toothfem.efficiency.loop import synthetic as sy
from toothfem.efficiency.loop.loss_effects import grade_viscosity_mm2_s
from toothfem.fem.drives import drive_for
from toothfem.report.loop import markdown

R = dataclasses.replace
CATALOG = fx.catalog(clearance_compliance=5e-11)   # the fast tests' contact springs
#: Held-out RMSE must fall at least this many times (the issue).
RMSE_CUT = 3.0
#: Relative error of a fitted value where the truth itself is named: the sensor offsets and
#: the warm-up are recovered to a few percent with these seeds; the oil's grade to about
#: 10 % (the efficiency changes slowly with the viscosity of so thick an oil).
VALUE_TOLERANCE = 0.25
#: Rows of each synthetic data set (fewer than the 200 of tests/test_loop.py: each loop
#: here weighs 16 candidates; 120 rows keep the effects several times the noise).
N_POINTS = 120
SEEDS = (1, 2)
#: name -> (truth, generator keywords) on the sine prototype. The sine case's oil is a
#: VG 680 (nu40 738 mm^2/s); the rig runs a VG 220. The warm-up is the issue's: the oil
#: warms by 25 K over the 8 h run (a 2 h time constant, inside the 0.2-3.0 h the housing's
#: heat balance allows), logged at a constant 30 C.
SCENARIOS = {
    "input_torque_offset": ((0.05,), {}),
    "output_torque_offset": ((0.6,), {}),
    "oil_temp_offset": ((8.0,), {"oil_temp_C": (30.0, 80.0)}),
    "viscosity_grade": ((220.0,), {"oil_temp_C": (30.0, 80.0)}),
    "windage": ((26.7,), {"oil_temp_C": (30.0, 80.0)}),     # 2.8 W at 1000 rpm
    "warm_up": ((25.0, 2.0), {"oil_temp_C": (30.0, 30.0), "hours": 8.0}),
}


@pytest.fixture(scope="module")
def sine(cases_dir):
    return load_case(cases_dir / "sine_prototype.toml")


@pytest.fixture(scope="module")
def cycloid(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


_RUNS = {}


def run(case, truth: dict, seed, effects=CATALOG, **kw):
    """(data, report) of one synthetic scenario, computed once per module."""
    key = (case.name, tuple(sorted((k, v) for k, v in truth.items())), seed,
           tuple(e.name for e in effects), tuple(sorted((k, str(v)) for k, v in kw.items())))
    if key not in _RUNS:
        data = sy.generate(case, truth, n_points=kw.pop("n_points", N_POINTS), seed=seed,
                           catalog=CATALOG, **kw)
        _RUNS[key] = data, lp.run_loop(case, data, effects)
    return _RUNS[key]


def named_or_aliased(report, name):
    """Whether ``name`` is an added effect or in the alias group of the step that added one
    still in the final model; returns the group (None when named itself)."""
    added = {e.name for e in report.effects}
    if name in added:
        return None
    for g in report.alias_groups:
        members = {m.name for m in g.members}
        if name in members and members & added:
            return g
    raise AssertionError(f"{name} neither added nor aliased: {report.stop_reason}")


# ---------------------------------------------------------------------------------------
# The new effects' laws


def test_windage_loss_is_its_law(sine):
    """P = T_w (n / 1000 rpm)^2 omega_in, exactly."""
    case = R(sine, friction=R(sine.friction, windage_torque_Nmm=30.0))
    n = np.array([500.0, 1000.0, 2000.0])
    ev = evaluate(case, n, np.full(3, 20.0))
    w = n * 2 * np.pi / 60
    np.testing.assert_allclose(ev.losses_W["windage"], 0.030 * (n / 1000) ** 2 * w, rtol=1e-12)
    assert "windage" not in evaluate(sine, n, np.full(3, 20.0)).losses_W


def test_viscosity_grade_keeps_the_vogel_law(sine):
    eff = fx.by_name("viscosity_grade", CATALOG)
    new = eff.apply(sine, (220.0,))
    assert grade_viscosity_mm2_s(new.lubricant) == pytest.approx(220.0, rel=1e-12)
    assert grade_viscosity_mm2_s(sine.lubricant) == pytest.approx(738.4, rel=1e-3)
    a, b = sine.lubricant, new.lubricant
    assert (b.vogel_B_C, b.vogel_C_C) == (a.vogel_B_C, a.vogel_C_C)
    assert b.dynamic_viscosity_Pa_s / b.kinematic_viscosity_mm2_s == pytest.approx(
        a.dynamic_viscosity_Pa_s / a.kinematic_viscosity_mm2_s, rel=1e-12)
    assert eff.declared(sine) is None          # the rig may run another oil than the case's


def test_main_preload_is_one_number_for_tilt_and_friction(cycloid):
    """The declared preload loads each main row's Palmgren term mu F d_m / 2 at the output
    speed, and stiffens the tilt model; by default both take 2 % of C0."""
    si = cycloid.to_si()
    drive = drive_for(si)
    c0 = main_pair(si, drive).static_rating_N
    assert main_tilt(si, drive)["preload_N"] == pytest.approx(0.02 * c0)
    n, t = np.array([1000.0]), np.array([100.0])
    with_p = R(cycloid, bearings=R(cycloid.bearings, main_preload_N=3000.0))
    none = R(cycloid, bearings=R(cycloid.bearings, main_preload_N=0.0))
    d = evaluate(with_p, n, t).losses_W["main_bearings"] - evaluate(none, n, t).losses_W[
        "main_bearings"]
    pair = main_pair(si, drive)
    w_out = 1000.0 * 2 * np.pi / 60 * pair.speed_per_input
    want = cycloid.friction.bearing_coefficient * pair.count * 3000.0 * pair.pitch_diameter_m / 2
    assert d[0] == pytest.approx(want * w_out, rel=1e-9)
    assert main_tilt(with_p.to_si(), drive)["preload_N"] == 3000.0
    assert "preload" not in main_tilt(with_p.to_si(), drive)["assumed"]


def test_torque_meter_offsets_read_as_a_rig_reads(sine):
    """eta_read = T2_read / (|i| T1_read): the input meter adds d1 to T1; the output meter
    reads T2 + d2 while the reducer ran at T2."""
    pts = fx.Points(np.array([300.0, 1200.0]), np.array([10.0, 25.0]))
    i = abs(sine.ratio())
    inp, out = fx.by_name("input_torque_offset"), fx.by_name("output_torque_offset")
    eta = fx.predict(sine, pts).efficiency
    got = fx.predict(sine, pts, {inp: (0.02,)}).efficiency
    np.testing.assert_allclose(got, pts.torque_Nm / (pts.torque_Nm / eta + i * 0.02),
                               rtol=1e-12)
    ran = fx.Points(pts.speed_rpm, pts.torque_Nm - 0.5)
    eta_ran = fx.predict(sine, ran).efficiency
    got = fx.predict(sine, pts, {out: (0.5,)}).efficiency
    np.testing.assert_allclose(got, eta_ran * pts.torque_Nm / ran.torque_Nm, rtol=1e-12)
    # bounds: half the smallest reading (T2 / |i| for the input meter)
    (p,) = inp.bound_to(sine, pts).parameters
    assert (p.lo, p.hi) == pytest.approx((-5.0 / i, 5.0 / i))
    (p,) = out.bound_to(sine, pts).parameters
    assert (p.lo, p.hi) == pytest.approx((-5.0, 5.0))


def test_warm_up_is_bounded_by_the_heat_balance(sine):
    from toothfem.efficiency.loop.rig_effects import WARM_RISE_MARGIN, heat_balance_scales

    pts = fx.Points(np.array([500.0, 1500.0]), np.array([10.0, 28.0]),
                    np.array([30.0, 30.0]), np.array([0.0, 8.0]))
    rise, tau = heat_balance_scales(sine, pts)
    assert 10.0 < rise < 100.0 and 0.2 < tau < 5.0      # a small housing, tens of W
    rise_p, tau_p = fx.by_name("warm_up").bound_to(sine, pts).parameters
    assert rise_p.hi == pytest.approx(WARM_RISE_MARGIN * rise)
    assert tau_p.lo < tau < tau_p.hi
    ran = fx.true_points(sine, pts, {fx.by_name("warm_up"): (20.0, 2.0)})
    np.testing.assert_allclose(ran.oil_temp_C, 30.0 + 20.0 * (1 - np.exp(-pts.time_h / 2.0)))


# ---------------------------------------------------------------------------------------
# Each new effect on synthetic data: named or in its alias group, error cut 3x


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", SCENARIOS)
def test_each_new_effect_is_named_or_its_alias_group(sine, name, seed):
    truth, kw = SCENARIOS[name]
    _, rep = run(sine, {name: truth}, seed, **kw)
    group = named_or_aliased(rep, name)
    assert rep.baseline.rmse >= RMSE_CUT * rep.final.rmse, rep.stop_reason
    if group is None:
        got = next(e for e in rep.effects if e.name == name).parameters.values()
        for value, want in zip((p["value"] for p in got), truth):
            assert value == pytest.approx(want, rel=VALUE_TOLERANCE)
    else:           # the group says how to tell its members apart
        assert group.points or all(m.direct_test for m in group.members)
        assert "measure" in group.note


def test_bearing_preload_on_a_cycloid(cycloid):
    """A preload near the top of its range (6000 N of the rows' 65 kN C0) at low torque
    and a rig of class 0.05 (the effect is a few tenths of a point: a preload at the output
    speed is a small loss): named, or in its alias group with the drag and the meters'
    offsets (constant torques all, which no operating point separates)."""
    effects = tuple(fx.by_name(n, CATALOG) for n in (
        "drag_torque", "bearing_friction", "mixed_lubrication", "bearing_preload",
        "input_torque_offset", "output_torque_offset"))
    rig = sy.Rig(input_range_Nm=2.0, input_accuracy=5e-4, output_range_Nm=100.0,
                 output_accuracy=5e-4)
    _, rep = run(cycloid, {"bearing_preload": (6000.0,)}, 1, effects=effects,
                 torque_Nm=(10.0, 60.0), rig=rig)
    group = named_or_aliased(rep, "bearing_preload")
    assert rep.baseline.rmse >= RMSE_CUT * rep.final.rmse
    if group is not None:
        assert not group.separable and "rolling torque" in group.note


def test_exact_aliases_name_their_direct_tests(sine):
    """A drag on the input and the input meter's offset are one number to efficiency data:
    the drag (first in the catalog) is added, the group says no operating point separates
    them and how each is measured directly."""
    _, rep = run(sine, {"input_torque_offset": SCENARIOS["input_torque_offset"][0]}, 1)
    assert [e.name for e in rep.effects] == ["drag_torque"]
    drag = rep.effects[0].parameters["drag_torque_Nmm"]["value"]
    assert drag == pytest.approx(50.0, rel=0.05)         # 0.05 N m, the offset
    (g,) = rep.alias_groups
    assert not g.separable and g.points == ()
    assert ("drag_torque", "input_torque_offset") in g.exact_pairs
    assert "shaft uncoupled" in g.note and "both directions" in g.note


def _joined(a, b):
    """Two MeasuredData records, one after the other."""
    kw = {f.name: np.concatenate([getattr(a, f.name), getattr(b, f.name)])
          for f in dataclasses.fields(a)
          if isinstance(getattr(a, f.name), np.ndarray)
          and isinstance(getattr(b, f.name), np.ndarray)}
    return R(a, **kw)


def test_proposed_points_separate_the_group(sine):
    """A VG 320 in the rig (seed 2): the oil's grade is added, and a sensor offset explains
    the data nearly as well (BIC within 6); measuring at the proposed points (each its
    proposed number of readings, at least 3) separates them: the grade is added again and
    the offset falls out of its group."""
    truth, kw = (320.0,), SCENARIOS["viscosity_grade"][1]
    data, rep = run(sine, {"viscosity_grade": truth}, 2, **kw)
    assert [e.name for e in rep.effects] == ["viscosity_grade"]
    (g,) = rep.alias_groups
    assert {m.name for m in g.members} == {"viscosity_grade", "oil_temp_offset"}
    assert g.separable and g.points[0].repeats <= 3
    n = [max(p.repeats, 3) for p in g.points]
    at = fx.Points(*(np.repeat([getattr(p, k) for p in g.points], n).astype(float)
                     for k in ("input_speed_rpm", "output_torque_Nm", "oil_temp_C",
                               "time_h")))
    more = sy.generate(sine, {"viscosity_grade": truth}, seed=11, at=at, catalog=CATALOG,
                       rig=sy.Rig.matched(sine, 28.0))
    after = lp.run_loop(sine, _joined(data, more), CATALOG)
    assert [e.name for e in after.effects] == ["viscosity_grade"]
    assert not any("oil_temp_offset" in {m.name for m in x.members}
                   for x in after.alias_groups)
    # the report carries the group and the proposal, in Markdown and JSON
    text = markdown(rep, effects=CATALOG)
    assert "Effects the data cannot tell apart" in text and "Proposed measurements" in text
    (jg,) = rep.to_dict()["alias_groups"]
    assert jg["separable"] and jg["proposed_points"][0]["repeats"] >= 1
    assert set(jg["proposed_points"][0]["efficiency"]) == {"oil_temp_offset",
                                                            "viscosity_grade"}


# ---------------------------------------------------------------------------------------
# Bounds and trends


def test_an_effect_at_its_bound_is_not_an_explanation(sine):
    """A VG 68 in the rig where the case says VG 680: a sensor offset would need more than
    its 15 K to mimic so thin an oil; offered alone, it is not added, the report says the
    data ask for more than it can give, and the residual trend stays reported."""
    truth = {"viscosity_grade": (68.0,)}
    _, rep = run(sine, truth, 1, effects=(fx.by_name("oil_temp_offset", CATALOG),),
                 oil_temp_C=(30.0, 80.0))
    assert rep.effects == ()
    (step,) = rep.steps
    assert step.bounded == ("oil_temp_offset",) and not step.candidates[0].passed
    assert "only at the bound" in rep.stop_reason and "physically" in rep.stop_reason
    assert rep.unexplained and step.trend.follows
    assert "no, at its bound" in markdown(rep, effects=CATALOG)


def test_each_step_names_the_covariate_the_residual_follows_most(sine):
    """After each step the report names the covariate the residual follows most (the
    windage run: the step that adds it and the step that stops), the last one as the final
    trends say, in the JSON and the Markdown."""
    truth, kw = SCENARIOS["windage"]
    _, rep = run(sine, {"windage": truth}, 1, **kw)
    assert len(rep.steps) >= 2 and all(s.trend is not None for s in rep.steps)
    assert rep.steps[-1].trend == lp.most_followed(rep.trends_after)
    assert rep.steps[-1].trend.follows == bool(rep.unexplained)
    steps = rep.to_dict()["steps"]
    assert all(s["residual_follows_most"]["covariate"] for s in steps)
    assert "After this step the residual" in markdown(rep, effects=CATALOG)
