"""The measured-data loop's physics and its adapter of the fitting engine: the effect
catalog (each effect's fields, bounds and model), the residual analysis, small data, the
report's JSON and the CLI.

The engine's rules (selection, aliases, the at-bound rule, held-out errors) are tested once
on surrogate models in tests/test_engine.py; the loop end to end on the README's demo in
tests/test_loop_demo.py. The loop's runs on synthetic data of each catalog effect (found,
recovered, the error cut) are benchmarks/loop_figures.py's (docs/loop.md's table).
"""
import dataclasses
import json
import math
import re

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency.loop import effects as fx
from toothfem.efficiency import loop as lp
from toothfem.layouts import layout_named
from toothfem.efficiency import lubricant as md
from toothfem.efficiency import predict
from toothfem.efficiency.loop import synthetic as sy
from toothfem.efficiency import drive_losses as dl
from toothfem.efficiency.mesh_table import table_from_records
from toothfem.fem.drives import drive_for

R = dataclasses.replace
#: Contact compliance [m per N/m] for the clearance effect in the fast tests (the FE value
#: of the pin-housing disc is about 3.6e-11; the slow test takes it from the FE).
FAST_COMPLIANCE = 5e-11
CATALOG = fx.catalog(clearance_compliance=FAST_COMPLIANCE)


def _friction(case, **kw):
    return R(case, friction=R(case.friction, **kw))


def _lubricant(case, **kw):
    return R(case, lubricant=R(case.lubricant, **kw))


@pytest.fixture(scope="module")
def cases(cases_dir):
    return {n: load_case(cases_dir / f"{n}.toml")
            for n in ("sine_prototype", "cycloid_pinhousing", "rv40e")}


# ---------------------------------------------------------------------------------------
# Catalog


def test_catalog_names_and_records():
    assert tuple(e.name for e in CATALOG) == fx.NAMES
    assert set(fx.NAMES) >= {"drag_torque", "churning", "viscosity_temperature",
                             "mixed_lubrication", "bearing_friction",
                             "output_mechanism_friction", "load_sharing_clearance",
                             "pin_sliding"}
    for e in CATALOG:
        # an effect of the rig (a sensor's misreading) sets no field of the reducer's case
        rig = e.true_points is not None or e.reading is not None
        assert e.citation and e.equation and (bool(e.case_fields) != rig)
        assert e.direct_test        # what tells it apart from an exact alias
        for p in e.parameters:
            assert p.unit and p.lo < p.hi and p.typical > 0
            assert all(p.lo <= s <= p.hi for s in p.starts)


#: The effects whose single value is the case field they set (viscosity_grade scales two
#: viscosities to its nu40: tests/test_loop_effects.py; the rig's effects set none).
FIELD_EFFECTS = tuple(e.name for e in CATALOG if len(e.case_fields) == 1)


@pytest.mark.parametrize("name", FIELD_EFFECTS)
def test_apply_sets_its_fields_by_copy(cases, name):
    eff = fx.by_name(name, CATALOG)
    case = cases["rv40e"] if eff.acts_on in (None, *layout_named("rv").components) \
        else cases["sine_prototype"]
    p = eff.parameters[0]
    value = 0.5 * (p.starts[0] + p.hi) if p.hi < 1e5 else 123.0
    new = eff.apply(case, (value,))
    assert new is not case
    section, field = eff.case_fields[-1].split(".")
    assert getattr(getattr(new, section), field) == pytest.approx(value)
    assert getattr(getattr(case, section), field) != pytest.approx(value)   # not mutated
    with pytest.raises(Exception, match="outside the valid range"):
        eff.apply(case, (p.hi * 2 + 1,))


def test_declared_and_applicable(cases):
    sine, cyc, rv = cases["sine_prototype"], cases["cycloid_pinhousing"], cases["rv40e"]
    pts = fx.Points(np.array([500.0]), np.array([20.0]))
    cands, skipped = lp.candidates_of(sine, pts, CATALOG)
    # churning and mixed lubrication are in the model by default: candidates as corrections
    # of their parameters (the churning law's factor, the boundary coefficient)
    assert cands == ["drag_torque", "churning", "mixed_lubrication", "viscosity_grade",
                     "windage", "viscous_drag", "input_torque_offset",
                     "output_torque_offset"]
    assert "declared" in skipped["bearing_friction"]
    assert "oil_temp_C" in skipped["viscosity_temperature"]
    assert "oil_temp_C" in skipped["thermal"]              # no sensor to be warmer than
    grease = _lubricant(sine, lubrication="grease")
    assert "no oil bath" in lp.candidates_of(grease, pts, CATALOG)[1]["churning"]
    assert "acts on the pins" in skipped["pin_sliding"] and "sine" in skipped["pin_sliding"]
    assert "acts on the pins" in skipped["load_sharing_clearance"]
    cands, skipped = lp.candidates_of(cyc, pts, CATALOG)
    assert "integral" in skipped["pin_sliding"]
    # a 2K-V train has no output pins (the effect acts on a K-H-V drive's and the sine's)
    assert "output mechanism, which an RV (2K-V)" in skipped["output_mechanism_friction"]
    assert "load_sharing_clearance" in cands and "bearing_friction" in cands
    cands, skipped = lp.candidates_of(rv, pts, CATALOG)
    assert "declared" in skipped["pin_sliding"]          # rv40e declares groove 0.05


def test_linear_components_are_exact(cases):
    """Scaling a linear effect's component equals evaluating the case with its value."""
    sine = _friction(cases["sine_prototype"], bearing_coefficient=0.0015,
                     output_pin_coefficient=0.05)
    cat = {e.name: e for e in CATALOG}
    pts = fx.Points(np.array([200.0, 800, 1400]), np.array([10.0, 20, 28]),
                    np.array([30.0, 50, 90]))
    a = {cat["drag_torque"]: (33.0,), cat["bearing_friction"]: (0.0042,),
         cat["output_mechanism_friction"]: (0.021,), cat["churning"]: (2.5,),
         cat["viscosity_temperature"]: (1400.0,)}
    direct = predict(fx.with_effects(sine, a), pts.speed_rpm, pts.torque_Nm, pts.oil_temp_C)
    np.testing.assert_allclose(fx.predict(sine, pts, a, cache={}).efficiency, direct,
                               rtol=1e-12)


def test_churning_on_a_cycloid_is_the_sine_law(cases):
    """Lu & Xu Eq. 42 on each gear stage of a 2K-V drive: the K-H-V stage with a0 = the
    eccentricity at the crank speed, and the spur first stage with a0 = m (z1 + z2)/2 =
    1.5 (9 + 27)/2 = 27 mm at the sun's speed relative to the carrier; the effect scales
    their sum."""
    cyc = cases["cycloid_pinhousing"]
    pts = fx.Points(np.array([1000.0]), np.array([100.0]))
    eff = fx.by_name("churning", CATALOG)
    p = fx.predict(cyc, pts, {eff: (2.0,)})
    n_crank = 1000.0 * fx.crank_speed_factor(cyc)
    n_sun = 1000.0 * (1 - 1 / 121)
    want = 2.0 * (md.churning_lu_xu_2024(1.0e-3, n_crank, 68.0e-6)
                  + md.churning_lu_xu_2024(27.0e-3, n_sun, 68.0e-6))
    assert p.losses_W["churning"][0] == pytest.approx(want)
    # 2K-V: planets (cranks) at w_c - (z_s/z_p)(1 - w_c) = (1 - 40)/121 of the input
    assert fx.crank_speed_factor(cyc) == pytest.approx(39 / 121)


def test_clearance_starts_at_the_analytic_split(cases):
    """At zero clearance the equal-springs split is F proportional to the moment arm (the
    analytic split), so the loss ratios are exactly 1; a clearance loads fewer pins."""
    cyc = cases["cycloid_pinhousing"]
    pts = fx.Points(np.array([500.0, 1500.0]), np.array([50.0, 167.0]))
    t = fx.clearance_tables(cyc, pts, FAST_COMPLIANCE, grid_mm=(0.0, 0.005))
    np.testing.assert_allclose(t.pin_ratio[0], 1.0)
    assert t.contacts_mean[0] == pytest.approx(20.0)
    assert t.contacts_mean[1] < 12
    assert np.all(t.pin_ratio[1] < 1.0)     # the pins near the pitch point slide least


def _pin_loss(case, c_mm, springs, torque=120.0, speed=1000.0, positions=12):
    """Cycle-mean sum mu F v_s of the pins at one operating point, load split from the FE
    cycle mode (springs None) or the equal-springs limit."""
    from toothfem.fem import cycloid_fe as cf
    from toothfem.geometry import cycloid_mesh as cym

    cc = R(case.cycloid, equidistant_modification_mm=c_mm)
    g = cc.geometry()
    phis = np.linspace(0, 2 * math.pi / g.pin_count, positions, endpoint=False)
    state = cym.meshing(g, phis, 1.0, pin_motion="fixed")
    model = drive_for(R(case, cycloid=cc)).fe_model()
    rec = cf.CycleSolver(model, phis, equal_springs=springs).solve(torque / cc.disc_count)
    tab = table_from_records(state, [rec], "check")
    t_disc = np.array([torque / cc.disc_count])
    crank = np.array([speed * 2 * math.pi / 60 * fx.crank_speed_factor(case)])
    loss = float(dl.disc_contact_losses(case, tab, t_disc, crank,
                                        case.lubricant.dynamic_viscosity_Pa_s)[0][0])
    return loss, float(np.mean(rec.contacts_per_position))


@pytest.mark.slow
def test_equal_springs_against_fe_cycle_mode(cases):
    """The clearance effect's contact model (equal contact springs, their compliance from
    the FE influence matrix) against the FE cycle mode (disc and housing elastic, coupled
    contacts): the pin loss relative to zero clearance agrees within 5 %
    at 5 um (observed 0.713 against 0.739 at 3 um, 0.640 against 0.659 at 10 um), and the
    pins in contact within one."""
    cyc = cases["cycloid_pinhousing"]
    comp = fx.contact_compliance(drive_for(cyc))
    assert 2e-11 < comp < 8e-11          # 3.8e-11 m per N/m: disc plus integral housing
    s0, _ = _pin_loss(cyc, 0.0, comp)
    f0, _ = _pin_loss(cyc, 0.0, None)
    s1, ns = _pin_loss(cyc, 0.005, comp)
    f1, nf = _pin_loss(cyc, 0.005, None)
    assert s1 / s0 == pytest.approx(f1 / f0, rel=0.05)
    assert abs(ns - nf) <= 1.0
    assert s1 / s0 < 0.8                     # the clearance effect is large here


# ---------------------------------------------------------------------------------------
# Residual analysis


def test_residual_trends_follow_the_right_covariate():
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, 1, 200), rng.uniform(0, 1, 200)
    runs = np.array([f"r{k % 4}" for k in range(200)], dtype=object)
    r = 0.01 * np.sin(3 * x) + rng.normal(0, 0.002, 200)
    trends = {t.covariate: t for t in lp.residual_trends(r, {"x": x, "y": y, "run": runs})}
    # signal std about 0.003 against noise 0.002: R^2 about 0.7
    assert trends["x"].follows and trends["x"].r2 > 0.5
    assert not trends["y"].follows and not trends["run"].follows
    assert trends["run"].kind == "levels" and trends["x"].kind == "numeric"


# ---------------------------------------------------------------------------------------
# The loop's adapter: what remains unexplained, small data


def test_effect_outside_the_catalog_is_unexplained(cases):
    """A running-in loss that decays with operating time: no effect offered depends on
    time, so the residual still follows time_h after the loop (an effect may take up its
    mean; the report says what remains). Three of the catalog's effects are offered: what
    remains unexplained is the loop's residual analysis, not the catalog's."""
    case = cases["sine_prototype"]
    data = sy.generate(case, {}, extra_loss=sy.running_in(0.05, 5.0), seed=3,
                       catalog=CATALOG)
    offered = tuple(fx.by_name(n, CATALOG) for n in ("drag_torque", "churning",
                                                     "mixed_lubrication"))
    rep = lp.run_loop(case, data, offered)
    assert "time_h" in rep.unexplained
    after = {t.covariate: t for t in rep.trends_after}
    assert after["time_h"].r2 > 0.5
    assert not after["input_speed_rpm"].follows and not after["output_torque_Nm"].follows


def test_small_data_reports_what_it_would_take(cases, cases_dir):
    """One point: no selection; each candidate's closing value is reported."""
    from toothfem.efficiency.loop.measured import load_measured

    case = cases["sine_prototype"]
    data = load_measured(cases_dir.parent / "data" / "sine_prototype_rig.csv",
                         ratio=case.ratio())
    rep = lp.run_loop(case, data, CATALOG)
    assert not rep.selection and rep.effects == ()
    assert rep.baseline.rmse == pytest.approx(0.0007, abs=0.0005)  # 82.54 % against 82.47 %
    drag = next(c for c in rep.closing if c.name == "drag_torque")
    assert drag.rmse < 1e-4 and 0.0 < drag.values[0] < 20.0
    assert rep.sigma[0] == pytest.approx(0.020, abs=0.001)          # the rig's 2 points


# ---------------------------------------------------------------------------------------
# Report and CLI


def _cli(argv):
    import argparse

    from toothfem import cli
    from toothfem.commands import loop as cmd

    if any(getattr(c, "__name__", "").endswith(".loop") for c in cli.COMMANDS):
        return cli.main(argv)
    parser = argparse.ArgumentParser()
    cmd.add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(argv)
    return args.func(args)


def test_cli_case_points_and_bad_file(cases_dir, tmp_path):
    case_file = cases_dir / "rv40e.toml"
    assert _cli(["loop", str(case_file), "--out", str(tmp_path / "a"),
                 "--effects", "drag_torque,bearing_friction"]) == 0
    rep = json.loads((tmp_path / "a" / "report.json").read_text())
    assert rep["selection"] is False and rep["n_points"] == 1
    assert {c["name"] for c in rep["closing"]} == {"drag_torque", "bearing_friction"}
    md_text = (tmp_path / "a" / "report.md").read_text()   # no held-out error of 1 point
    assert "| held-out RMSE [points] | – (none formed) | – (none formed) |" in md_text
    assert re.search(r"\| drag_torque \| drag_torque_Nmm = [\d.e+-]+ N mm \|", md_text)
    bad = tmp_path / "bad.csv"
    bad.write_text("input_speed_rpm,output_torque_furlong,efficiency\n1,2,0.5\n")
    from toothfem.errors import ToothfemError
    try:
        code = _cli(["loop", str(case_file), str(bad), "--out", str(tmp_path / "b")])
    except ToothfemError as exc:          # not registered in toothfem.cli yet
        assert "unknown unit 'furlong'" in str(exc)
    else:
        assert code == 2
    assert not (tmp_path / "b").exists()


def test_report_json_is_strict_json(cases):
    data = sy.generate(cases["sine_prototype"], {}, n_points=20, seed=5, catalog=CATALOG)
    rep = lp.run_loop(cases["sine_prototype"], data, CATALOG)
    text = json.dumps(rep.to_dict(), allow_nan=False)
    d = json.loads(text)
    assert set(d) >= {"baseline", "final", "effects", "unexplained"}
    assert math.isfinite(d["baseline"]["rmse"]) and math.isfinite(d["final"]["rmse"])


def test_a_residual_no_test_looked_at_is_never_nothing(cases_dir):
    """The RV case's one measured point sits 9.5 points below the model (regression: the
    sized RV-40E's losses): with one point nothing can be analysed, and the report says
    so with the residual, not 'nothing'."""
    from toothfem.efficiency.loop import measured
    from toothfem.report.loop import markdown

    case = load_case(cases_dir / "rv_paper_example.toml")
    report = lp.run_loop(case, measured.from_case(case), (fx.by_name("drag_torque"),))
    text = report.unexplained_text()
    assert text.startswith("not analysed: 1 point(s)") and "-9.53 points" in text
    assert f"Unexplained: {text}" in markdown(report)
    assert report.to_dict()["unexplained_text"] == text
