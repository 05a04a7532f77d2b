"""Bearing life (ISO 281), strength and heat (issue 13, items 3-6). Each law against a
number worked from its source's formula (the tolerance says why), the loads against the
efficiency model's own (two code paths), and bad input refused with one line."""
import dataclasses
import json
import math
import types

import numpy as np
import pytest

from toothfem import CaseError, cli, load_case, parse_case
from toothfem.case import case_to_dict
from toothfem.efficiency import bearings as br
from toothfem.efficiency import palmgren as pg
from toothfem.efficiency.bearing_set import reducer_bearings
from toothfem.efficiency import evaluate
from toothfem.efficiency import strength as st
from toothfem.efficiency import thermal as th
from toothfem.efficiency.loop import thermal_effect as te
from toothfem.efficiency.mesh_table import mesh_table
from toothfem.fem.drives import drive_for

R = dataclasses.replace


@pytest.fixture(scope="module")
def cases(cases_dir):
    return {n: load_case(cases_dir / f"{n}.toml")
            for n in ("sine_prototype", "cycloid_pinhousing", "rv40e")}


def _bearings(case, **kw):
    return R(case, bearings=R(case.bearings, **kw))


# ---------------------------------------------------------------------------------------
# ISO 281


def test_rating_life_and_duty_cycle_mean():
    """ISO 281: L10 = (C/P)^p 1e6 revolutions (C is the load for 1e6 revolutions): C/P = 2
    gives 2^(10/3) = 10.08e6 for rollers, 8e6 for balls. The mean equivalent load of a
    duty cycle weights P^p by revolutions: 1 and 2 kN at equal speed and time, p = 3:
    (4.5e9)^(1/3) = 1651 N; 2 kN at three times the speed: (6.25e9)^(1/3) = 1842 N. The set
    of four needle bearings lives 4^(-8/9) = 0.2916 of one (Weibull slope 9/8). Exact
    arithmetic."""
    assert br.rating_life_revolutions(2.0, 1.0, 10 / 3) == pytest.approx(2 ** (10 / 3) * 1e6)
    assert br.rating_life_revolutions(2.0, 1.0, 3.0) == pytest.approx(8e6)
    assert br.mean_equivalent_load([1e3, 2e3], [100, 100], [0.5, 0.5], 3) == pytest.approx(
        4.5e9 ** (1 / 3))
    assert br.mean_equivalent_load([1e3, 2e3], [100, 300], [0.5, 0.5], 3) == pytest.approx(
        6.25e9 ** (1 / 3))
    assert br.first_failure([1000.0] * 4, br.WEIBULL_SLOPE["needle"]) == pytest.approx(
        1000 * 4 ** (-8 / 9))
    assert br.first_failure([1000.0, math.inf], 9 / 8) == pytest.approx(1000.0)
    assert br.first_failure([math.inf], 9 / 8) == math.inf
    assert pytest.approx(0.2916, abs=1e-4) == 4 ** (-8 / 9)


def test_maker_rated_life_scaling():
    """Nabtesco's RV-E life L_h = K (N0/N_m)(T0/T_m)^(10/3): 6000 h at the rated 412 N m
    and 15 rpm; twice the torque 6000 x 2^(-10/3) = 595.3 h; half the speed 12000 h."""
    assert br.maker_rated_life_h(6000, 412, 15, [(412, 15, 1.0)]) == pytest.approx(6000)
    assert br.maker_rated_life_h(6000, 412, 15, [(824, 15, 1.0)]) == pytest.approx(595.28,
                                                                                    abs=0.01)
    assert br.maker_rated_life_h(6000, 412, 15, [(412, 7.5, 1.0)]) == pytest.approx(12000)


def test_crank_bearing_loads_match_the_loss_model(cases):
    """Two code paths: the crank-hole load over the relative angle, averaged (p = 1), is
    the load the crank-bearing loss takes (Palmgren: per bearing M0 + mu F d_m/2 at w_rel,
    efficiency/bearing_friction.py); the RV's disc load factor is 1, so peak and even shares
    agree. The loss model takes the period's mean resultant before the angle, the life each
    position's: they differ by the resultant's ripple (1.5e-7 here), hence 1e-5. Each hole
    carries at least the torque couple's T/(k R_c) at some angle."""
    rv = cases["rv40e"]
    si, drive = rv.to_si(), drive_for(rv)
    table = mesh_table(drive)
    loads = br.eccentric_loads(si, drive, table, 412.0)
    h = si.cycloid.holes
    k = h.crank_hole_count
    w = drive.speeds()
    rel = 1500 * 2 * math.pi / 60 * abs(w["crank"] - w["member"])
    loss = evaluate(rv, 1500.0, 412.0).losses_W["crank_bearings"][0]
    (b,) = [b for b in reducer_bearings(si, drive) if b.name == "crank_bearings"]
    m0 = pg.palmgren_no_load_moment(pg.palmgren_f0("needle", "grease"), 68e-6, rel,
                                    b.pitch_diameter_m)
    by_loads = drive.members * k * (m0 + si.friction.bearing_coefficient
                                    * np.mean(loads.load_N) * b.pitch_diameter_m / 2) * rel
    assert loss == pytest.approx(by_loads, rel=1e-5)
    couple = 412.0 / 2 / (k * h.crank_hole_circle_radius_m)
    assert loads.max_N >= couple
    assert np.all(np.linalg.norm(loads.force_N, axis=1) <= loads.max_N * (1 + 1e-12))
    assert (loads.count, loads.bearing_type) == (4, "needle")


def test_sine_eccentric_and_main_bearings(cases):
    """The planet's eccentric bearing carries |R - sum Q e| (the sine loss model's F_R1,
    2583 N at 28 N m, docs/efficiency.md); the output's main bearings share sum Q =
    4 T/(pi R_w) = 4 x 28/(pi x 0.0262) = 1360.7 N, 680.4 N per row."""
    sine = cases["sine_prototype"]
    si, drive = sine.to_si(), drive_for(sine)
    table = mesh_table(drive)
    ecc = br.eccentric_loads(si, drive, table, 28.0)
    assert np.mean(ecc.load_N) == pytest.approx(2583, abs=1)
    main = br.main_loads(si, drive, table, 28.0)
    assert main.equivalent_N == pytest.approx(4 * 28 / (math.pi * 0.0262) / 2, rel=1e-9)


def test_main_bearing_external_loads(cases):
    """RV: the two discs' resultants cancel at the carrier, so the main rows take only the
    external loads: 1000 N radial over two rows, 500 N each; a 100 N m moment over a 0.1 m
    span adds 1000 N to a row; 3000 N axial on a 40 deg angular contact row (F_a/F_r = 2
    > e = 1.14): P = 0.35 x 1500 + 0.57 x 3000 = 2235 N (ISO 281 Table 3)."""
    rv = cases["rv40e"]
    drive = drive_for(rv)
    table = mesh_table(drive)
    bare = br.main_loads(rv.to_si(), drive, table, 412.0)
    assert bare.max_N == pytest.approx(0.0, abs=1e-9)
    case = _bearings(rv, external_radial_load_N=1000.0)
    assert br.main_loads(case.to_si(), drive, table, 412.0).equivalent_N == pytest.approx(500)
    case = _bearings(rv, external_radial_load_N=1000.0, external_moment_Nm=100.0,
                     main_span_mm=100.0, external_axial_load_N=3000.0)
    assert br.main_loads(case.to_si(), drive, table, 412.0).equivalent_N == pytest.approx(2235)
    with pytest.raises(CaseError, match="needs bearings.main_span_mm"):
        br.main_loads(_bearings(rv, external_moment_Nm=1.0).to_si(), drive, table, 412.0)


def test_rv_life_at_the_makers_rating_point(cases):
    """The RV case's duty cycle is the maker's rating point (412 N m, 15 rpm output). Every
    bearing's load comes from the system model over the full period: a crank bearing's
    swings between |a - b| and a + b (the pin resultant and the torque couple); its C is
    ISO 281's for the rollers that fit the 35 mm hole of the 15 mm disc (33.9 kN: the
    case sized by toothfem size, docs/sizing.md). Each bearing: (C/P_m)^(10/3) 1e6 /
    (60 x 600 rpm) h (exact); the reducer fails with its first bearing at or above the
    maker's 6000 h (the sizing's target)."""
    rv = cases["rv40e"]
    res = br.reducer_life(rv)
    g = {x.name: x for x in res.groups}
    crank = g["crank_bearings"]
    assert crank.speed_rpm == pytest.approx(600.0)
    assert crank.dynamic_rating_N == pytest.approx(33.86e3, rel=1e-3)   # regression, ISO 281
    want = (crank.dynamic_rating_N / crank.equivalent_load_N) ** (10 / 3) * 1e6 / (60 * 600)
    assert crank.l10_h == pytest.approx(want, rel=1e-12)
    # the torque couple on one crank at one disc, T_disc / (k R_c), and the pin resultant
    # on top of it: the largest load lies between the couple and twice it
    drive = drive_for(rv)
    h = rv.cycloid.disc_holes
    couple = drive.members_torque(412.0) / rv.cycloid.disc_count / (
        h.crank_hole_count * h.crank_hole_circle_radius_mm * 1e-3)
    assert couple < crank.max_load_N < 2 * couple
    assert crank.l10_set_h < crank.l10_h
    assert res.l10_h < min(x.l10_set_h for x in res.groups)
    assert 6000 <= res.l10_h < 6600      # sized to the maker's 6000 h, a 0.5 mm hole step
    assert g["main_bearings"].l10_h == math.inf        # no external load on the output
    assert g["input_bearings"].equivalent_load_N == 0.0   # the planets balance the sun
    assert set(g) == {"crank_bearings", "crank_support_bearings", "main_bearings",
                      "input_bearings"}


def test_bad_bearing_and_duty_input(cases):
    """One line naming the key, its value and the valid range."""
    d = case_to_dict(cases["rv40e"])
    d["bearings"]["eccentric_dynamic_rating_kN"] = -14.0
    with pytest.raises(CaseError, match=r"bearings.eccentric_dynamic_rating_kN = -14.0 is "
                                        r"outside the valid range \(0, 100000\]"):
        parse_case(d)
    d = case_to_dict(cases["rv40e"])
    d["duty_cycle"] = [{"output_torque_Nm": 412.0, "input_speed_rpm": 1815.0,
                        "time_share": 0.6},
                       {"output_torque_Nm": 200.0, "input_speed_rpm": 1000.0,
                        "time_share": 0.3}]
    with pytest.raises(CaseError, match=r"duty_cycle time_share sum = 0.9 is outside the "
                                        r"valid range \[0.999, 1.001\]"):
        parse_case(d)
    with pytest.raises(CaseError, match="duty time share sum = 0.5"):
        br.reducer_life(cases["rv40e"], duty=[(412.0, 1815.0, 0.5)])


# ---------------------------------------------------------------------------------------
# Strength


def test_contact_safety_factor_and_warning(cases):
    """S = allowable / P_h,max; below 1 a one-line warning names the key and the values."""
    s = st.strength(cases["rv40e"].to_si(), 2219e6)
    assert s.contact_fatigue_safety == pytest.approx(1500 / 2219)
    assert s.contact_static_safety == pytest.approx(4000 / 2219)
    (w,) = s.warnings
    assert "material.allowable_contact_stress_MPa = 1500" in w and "\n" not in w
    assert st.strength(cases["rv40e"].to_si(), 1000e6).warnings == ()


def _annulus(a, b, nr=13, nt=96):
    from skfem import MeshTri

    r = np.linspace(a, b, nr)
    t = np.linspace(0, 2 * np.pi, nt, endpoint=False)
    rr, tt = np.meshgrid(r, t, indexing="ij")
    p = np.vstack([(rr * np.cos(tt)).ravel(), (rr * np.sin(tt)).ravel()])
    idx = np.arange(nr * nt).reshape(nr, nt)
    tri = []
    for i in range(nr - 1):
        for j in range(nt):
            j2 = (j + 1) % nt
            tri += [[idx[i, j], idx[i + 1, j], idx[i + 1, j2]],
                    [idx[i, j], idx[i + 1, j2], idx[i, j2]]]
    return MeshTri(p, np.array(tri).T)


def test_member_stress_at_a_hole_is_lames():
    """Lame's thick cylinder (Timoshenko & Goodier, Theory of Elasticity, Sec. 28) under
    100 MPa in a 40 mm bore of a 100 mm ring, plane strain: at the bore sigma_r = -100,
    sigma_t = 100 (b^2 + a^2)/(b^2 - a^2) = 138.1, sigma_z = 2 nu A = 11.4 MPa, von Mises
    206.3 MPa, the largest of the ring and found at its hole edge. The field is Lame's
    displacement in P2; the nodal stresses of the P1 projection fall short at the boundary
    by about 1 % on this 2.5 mm radial grid, hence 2 %."""
    from toothfem.fem.elastic import Body

    a, b, p, e, nu = 0.02, 0.05, 100e6, 210e9, 0.3
    mesh = _annulus(a, b)
    ca = p * a * a / (b * b - a * a)
    cb = p * a * a * b * b / (b * b - a * a)

    def lame(x):
        r = np.hypot(x[0], x[1])
        ur = (1 + nu) / e * ((1 - 2 * nu) * ca * r + cb / r)
        return np.array([ur * x[0] / r, ur * x[1] / r])

    body = Body(body_mesh=types.SimpleNamespace(mesh=mesh), youngs_modulus=e,
                poisson_ratio=nu, clamped_nodes=np.array([0]))
    vm_max, vm_holes = st.member_stress(body, body.basis.project(lame))
    sr, s_t, sz = -p, ca + cb / a ** 2, 2 * nu * ca
    exact = math.sqrt(0.5 * ((sr - s_t) ** 2 + (s_t - sz) ** 2 + (sz - sr) ** 2))
    assert exact / 1e6 == pytest.approx(206.3, abs=0.1)
    assert vm_holes == pytest.approx(exact, rel=0.02) and vm_max == vm_holes
    assert st.hole_edge_nodes(mesh).size == 96                    # the bore's nodes


# ---------------------------------------------------------------------------------------
# Heat


def test_heat_transfer_coefficient():
    """Holman's laminar natural convection of a horizontal cylinder, h = 1.32 (dT/d)^(1/4):
    40 K on a 0.158 m housing: 1.32 x 253.2^(1/4) = 5.26 W/(m^2 K); radiation at 60 C into
    20 C with eps = 0.9: 0.9 sigma (333.15^2 + 293.15^2)(626.3) = 6.29 W/(m^2 K) (hand
    arithmetic to 3 digits)."""
    assert float(th.convection_coefficient(40.0, 0.158)) == pytest.approx(5.26, abs=0.01)
    assert float(th.radiation_coefficient(60.0, 20.0, 0.9)) == pytest.approx(6.29, abs=0.01)


def test_heat_balance_closes(cases):
    """At the equilibrium the losses equal the heat the housing sheds within the fixed
    point's 0.1 K; with a declared h the balance is h A (T - T_a) exactly as declared."""
    rv = cases["rv40e"]
    hb = th.heat_balance(rv, [500.0, 1500.0, 3000.0], 412.0)
    shed = th.heat_flow(hb.housing, hb.temperature_C)
    per_k = hb.heat_transfer_W_m2K * hb.housing.area_m2
    assert np.all(np.abs(hb.losses_W - shed) < 0.1 * per_k * 1.5)
    assert np.all(np.diff(hb.temperature_C) > 0)          # faster, hotter
    declared = R(rv, thermal=R(rv.thermal, heat_transfer_W_m2K=20.0, housing_area_m2=0.2))
    hd = th.heat_balance(declared, 1500.0, 412.0)
    assert hd.losses_W[0] == pytest.approx(20 * 0.2 * (hd.temperature_C[0] - 20.0), abs=0.4)


def test_warm_up_reaches_the_equilibrium(cases):
    """C dT/dt = P(T) - h A (T - T_a) from the ambient: rising, and within 1 K of the
    equilibrium after five time constants (e^-5 of a 52 K rise is 0.35 K); the time
    constant C/(h A) at the equilibrium as measured (regression, 1 %: h with T). Bolted by
    a flange to a steel machine the housing sheds more per kelvin (conduction through the
    joint and into the machine), so the equilibrium is cooler and reached sooner."""
    rv = cases["rv40e"]
    hb = th.heat_balance(rv, 1500.0, 412.0)
    w = th.warm_up(rv, 1500.0, 412.0, 5 * 3666.0, samples=11)
    assert w.temperature_C[0] == 20.0 and np.all(np.diff(w.temperature_C) > 0)
    assert w.temperature_C[-1] == pytest.approx(hb.temperature_C[0], abs=1.0)
    assert w.time_constant_s == pytest.approx(3666, rel=0.01)
    bolted = dataclasses.replace(rv, thermal=dataclasses.replace(rv.thermal, mounting="flange"))
    h = th.housing(bolted.to_si())
    r = h.diameter_m / 2                     # joint and spreading in series, by hand
    face = math.pi * r ** 2
    assert h.flange_conductance_W_K == pytest.approx(
        1 / (1 / (1000.0 * face) + 1 / (2 * 2 * r * 50.0)), rel=1e-12)
    assert float(th.shed_per_kelvin(h, 60.0)) == pytest.approx(
        float(th.heat_transfer_coefficient(h, 60.0)) * (h.area_m2 - face)
        + h.flange_conductance_W_K, rel=1e-12)
    cool = th.heat_balance(bolted, 1500.0, 412.0)
    assert cool.temperature_C[0] < hb.temperature_C[0] - 5
    assert th.warm_up(bolted, 1500.0, 412.0, 3600.0, samples=3).time_constant_s < 3786


def test_ambient_above_the_oil_limit_is_refused(cases):
    d = case_to_dict(cases["rv40e"])
    d["lubricant"]["max_temperature_C"] = 80.0
    d["thermal"] = {"ambient_C": 90.0}
    with pytest.raises(CaseError, match=r"thermal.ambient_C = 90.0 is outside the valid range "
                                        r"\[-15, 80\)"):
        parse_case(d)


def test_thermal_rise_on_a_linear_loss():
    """The loop's fixed point dT = R phi P(dT) on a tabulated P = a + b dT is exact where the
    table is linear: dT = R a / (1 - R b); 2 K/W on 10 W + 0.05 W/K: 20/0.9 = 22.2 K."""
    grid = np.linspace(0.0, 100.0, 12)
    total = np.array([10.0 + 0.05 * grid, 10.0 + 0.05 * grid])
    dt = te.rise(total, grid, 2.0, np.array([1.0, 0.5]))
    assert dt == pytest.approx([20.0 / 0.9, 10.0 / 0.95])


def test_thermal_rise_is_the_first_crossing_of_each_row():
    """rise, one array operation for all rows (issue 45: a row-by-row loop on 4992 binned
    points in every least-squares call), gives each row's first crossing of R phi P - dT
    exactly as a row-by-row search does: none (the grid's end), at 0, or interpolated."""
    rng = np.random.default_rng(3)
    grid = np.concatenate([[0.0], np.geomspace(0.5, 60.0, 7)])
    total = rng.uniform(0.0, 200.0, (500, grid.size))
    factor = rng.uniform(0.0, 1.0, 500)
    for r in (0.0, 0.05, 0.5, 50.0):
        gap = r * factor[:, None] * total - grid
        want = []
        for row in gap:
            k = next((i for i, g in enumerate(row) if g <= 0), None)
            want.append(grid[-1] if k is None else 0.0 if k == 0 else
                        grid[k - 1] + (grid[k] - grid[k - 1]) * row[k - 1] / (row[k - 1] - row[k]))
        got = te.rise(total, grid, r, factor)
        np.testing.assert_array_equal(got, want)     # the same arithmetic: bit for bit


# ---------------------------------------------------------------------------------------
# CLI


def test_efficiency_thermal_command(cases_dir, capsys):
    assert cli.main(["efficiency", str(cases_dir / "rv40e.toml"), "--torque-Nm", "412",
                     "--speed-rpm", "1500", "--thermal", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    t = d["thermal"]["equilibrium_oil_temp_C"]
    assert 20 < t < 150 and d["oil_temp_C"] == t
    assert d["efficiency"] == pytest.approx(d["thermal"]["efficiency"], rel=1e-12)
    code = cli.main(["efficiency", str(cases_dir / "rv40e.toml"), "--thermal", "--oil-temp-C",
                     "40"])
    (line,) = capsys.readouterr().err.strip().splitlines()     # one line, exit code 2
    assert code == 2 and "exclude each other" in line


def test_run_reports_life_strength_and_heat(cases_dir, tmp_path, capsys):
    out = tmp_path / "run"
    assert cli.main(["run", str(cases_dir / "rv40e.toml"), "--out", str(out),
                     "--no-fem"]) == 0
    both = capsys.readouterr()
    printed = both.out
    assert "equilibrium oil" in printed and "L10" in printed
    # every stage of the run says when it is done and how long it took (issue 41: no stretch
    # of a run silent); --no-fem has no contact, datasheet or as-built stage
    stages = [ln.split(": done in")[0] for ln in both.err.splitlines() if ": done in " in ln]
    assert stages == ["progress: efficiency at the operating point",
                      "progress: heat balance, bearing life, contact strength",
                      "progress: efficiency maps over the operating range",
                      "progress: report files"]
    d = json.loads((out / "durability.json").read_text())
    assert set(d) == {"heat", "life", "strength", "as_built"}
    assert d["as_built"] == {}              # --no-fem: no built reducers solved
    assert d["life"]["maker"]["rated_life_h"] == 6000.0
    report = (out / "report.md").read_text()
    assert "## Life, strength and heat" in report and "z1 = 12, z2 = 36" in report
    assert "maker's rated life 6000 h" in report
