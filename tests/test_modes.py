"""The dynamics on the system model (docs/dynamics.md): the bodies' inertias against closed
forms, the eigenproblem against hand-solved chains, the tangent stiffness against the
datasheet's twist, the two-inertia limit of RV-40E (issue 42), the free input's rigid
motion against the train's ratio, the Campbell crossings' formula and the command."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from toothfem import cli
from toothfem.case import load_case
from toothfem.dynamics import find_crossings, modes_analysis, te_orders
from toothfem.fem.drives import drive_for
from toothfem.fem.system import inertia as fi, modes as fm
from toothfem.fem.system.datasheet import SystemTwist

ROOT = Path(__file__).resolve().parents[1]
RV40E = ROOT / "cases" / "rv40e.toml"


# -- inertias -------------------------------------------------------------------------
def test_polygon_moments_of_a_circle_and_a_square():
    # a 2000-gon: its area and polar moment fall short of the circle's by O(1/N^2)
    # (2.1e-6 relative for N = 2000: 1 - sin(2 pi/N) N / (2 pi)); the square is exact
    a = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    area, j = fi.polygon_moments(0.05 * np.stack([np.cos(a), np.sin(a)]))
    assert area == pytest.approx(math.pi * 0.05 ** 2, rel=1e-5)
    assert j == pytest.approx(math.pi * 0.05 ** 4 / 2, rel=1e-5)
    sq = np.array([[-1, 1, 1, -1], [-1, -1, 1, 1]], float)
    assert fi.polygon_moments(sq) == pytest.approx((4.0, 8.0 / 3.0), rel=1e-12)


def test_plane_body_with_a_hole_equals_the_hollow_cylinder_and_steiner():
    rho, t = 7850.0, 0.015
    ring = fi.plane_body("ring", (0.0, 0.0, 0.05), [(0.0, 0.0, 0.02)], t, rho)
    cyl = fi.cylinder("ring", 0.05, t, rho, inner_m=0.02)
    assert ring.mass_kg == pytest.approx(cyl.mass_kg, rel=1e-12)
    assert ring.inertia_kgm2 == pytest.approx(cyl.inertia_kgm2, rel=1e-12)
    off = fi.cylinder("pin", 0.003, 0.03, rho, offset_m=0.04, count=8)
    one = fi.cylinder("pin", 0.003, 0.03, rho)
    assert off.mass_kg == pytest.approx(8 * one.mass_kg)
    assert off.inertia_kgm2 == pytest.approx(8 * (one.inertia_kgm2 + one.mass_kg * 0.04 ** 2))


# -- the eigenproblem ---------------------------------------------------------------
def _chain(k1, k2, m1, m2, massless_middle=False):
    """ground -k1- x1 -k2- x2 (x1 massless: the springs in series)."""
    b1 = np.array([[1.0, 0.0]])
    b2 = np.array([[-1.0, 1.0]])
    parts = (("a", b1, np.array([[k1]])), ("b", b2, np.array([[k2]])))
    k = b1.T * k1 @ b1 + b2.T * k2 @ b2
    lin = fm.Linearised(k=k, parts=parts, names=("x1", "x2"), assumed={})
    return lin, np.diag([0.0 if massless_middle else m1, m2])


def test_two_mass_chain_frequencies_and_energy_shares():
    k1, k2, m1, m2 = 3e6, 1e6, 2.0, 1.0
    lin, m = _chain(k1, k2, m1, m2)
    found = fm.modes(lin, m)
    # det(K - w^2 M) = 0: m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0
    a, b, c = m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2
    w2 = np.sort([(-b - math.sqrt(b * b - 4 * a * c)) / (2 * a),
                  (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)])
    assert found.frequency_Hz == pytest.approx(np.sqrt(w2) / (2 * math.pi), rel=1e-10)
    for i in range(2):
        v = found.shapes[:, i]
        ea, eb = 0.5 * k1 * v[0] ** 2, 0.5 * k2 * (v[1] - v[0]) ** 2
        assert found.shares[i]["a"] == pytest.approx(ea / (ea + eb), rel=1e-9)
        assert sum(found.shares[i].values()) == pytest.approx(1.0, rel=1e-12)


def test_a_massless_coordinate_is_condensed_exactly():
    k1, k2, m2 = 3e6, 1e6, 1.0
    lin, m = _chain(k1, k2, 0.0, m2, massless_middle=True)
    found = fm.modes(lin, m)
    series = k1 * k2 / (k1 + k2)
    assert found.frequency_Hz == pytest.approx([math.sqrt(series / m2) / (2 * math.pi)],
                                               rel=1e-12)
    # the springs in series share the energy inversely to their stiffness
    assert found.shares[0]["a"] == pytest.approx(k2 / (k1 + k2), rel=1e-10)


# -- the system model ---------------------------------------------------------------
@pytest.fixture(scope="module")
def rv():
    si = load_case(RV40E).to_si()
    drive = drive_for(si)
    supports = drive.supports(si.supports)
    return si, drive, supports, drive.system_model(supports, 4)


def test_tangent_compliance_is_the_solvers_rate(rv):
    """The condensed tangent's output compliance is the solve's own tangent (the carrying
    contacts held): one linear algebra, two routes (tolerance: the solve's RTOL 1e-8 on
    the state and the contacts' forward-difference approach tangent, 1e-6 of the force)."""
    from toothfem.efficiency.no_load import path_friction
    si, drive, _, system = rv
    st = system.solve(412.0, 1, friction=path_friction(si, drive))
    lin = fm.linearise(system, st)
    rate = st.equilibrium.rate[system.coords.index["out"]][0]
    assert fm.output_compliance(lin, 0) == pytest.approx(rate, rel=1e-5)


def test_free_input_column_is_the_spur_mesh_ratio(rv):
    """With the sun free, each spur mesh deforms by r_b,planet (psi_g + (z_s/z_p)(sun -
    carrier)) (fem/system/paths.py, Cranks): the rigid motion gives the sun's coefficient
    r_b z_s/z_p (round-off of an SVD's null vector: 1e-9)."""
    _, drive, _, system = rv
    lin = fm.linearise(system, system.solve(412.0, 0), input_free=True)
    path = drive.path
    r_b = system.planet_base_radius
    cols = [b[0, -1] for g, b, _ in lin.parts if g == "spur mesh"]
    assert len(cols) == system.cranks
    assert cols == pytest.approx([r_b * path.sun_over_planet] * system.cranks, rel=1e-9)


def test_rigid_motion_turns_the_train_by_its_ratios(rv):
    """The train's rigid motion found from the elements and contacts (a null space) turns
    the cranks and discs by geometry.train's speeds per output turn (rv_speeds: the crank
    is the carrier's turn plus psi_e; round-off of an SVD, 1e-8)."""
    _, drive, _, system = rv
    r, _ = fm.rigid_motion(system, system.solve(412.0, 0))
    c, w = system.coords.index, drive.speeds()
    per_out = 1.0 / r[c["out"]][0]
    crank = (r[c["carrier"]][0] + r[c["psi_e0"]][0]) * per_out
    assert crank == pytest.approx(w["crank"] / w["output"], rel=1e-8)
    assert r[c["disc0"]][2] * per_out == pytest.approx(w["member"] / w["output"], rel=1e-8)


def test_two_inertia_limit_against_the_datasheet_twist(rv):
    """Issue 42: a load of 200 kg m^2 (1e4 times the reducer's own output), input held:
    the first mode is sqrt(k/J)/(2 pi), k the tangent rigidity at that torque from the
    stiffness command's own twist (SystemTwist, a central difference of +-2 % about
    412 N m, its curvature's error ~1e-4), within 2 % (the reducer's own inertias couple
    at 1e-4 of the load: the rest is the difference of the mean of the compliance over
    the positions against the mean of the stiffness)."""
    _, _, _, system = rv
    twist = SystemTwist(system)
    dt = 0.02 * 412.0
    up, down = twist.at(412.0 + dt).total.mean(), twist.at(412.0 - dt).total.mean()
    k = 2 * dt / (up - down)
    res = modes_analysis(load_case(RV40E), load_kgm2=200.0, input_free=False,
                         positions=4, campbell=False)
    j = 200.0 + res.bodies.carrier.inertia_kgm2 / 2 + res.bodies.output.inertia_kgm2
    expected = math.sqrt(k / j) / (2 * math.pi)
    assert res.modes.frequency_Hz[0] == pytest.approx(expected, rel=0.02)
    assert res.modes.kinetic[0]["out"] > 0.99


def test_free_input_has_the_rigid_mode_and_every_share_sums_to_one(rv):
    res = modes_analysis(load_case(RV40E), load_kgm2=1.0, motor_kgm2=1e-4, input_free=True,
                         positions=2, count=6, campbell=False)
    assert res.modes.frequency_Hz[0] == 0.0
    assert res.modes.frequency_Hz[1] > 1.0
    for s in res.modes.shares[1:]:
        assert sum(s.values()) == pytest.approx(1.0, rel=1e-9)


# -- Campbell -----------------------------------------------------------------------
def test_crossing_speed_formula_and_the_warned_lines():
    orders = te_orders({"pin passing": 40.0, "mesh": 1560.0}, [40.0, 80.0, 1560.0, 1640.0],
                       [0.1, 2.0, 1e-9, 0.5])
    assert [o["order"] for o in orders] == [40.0, 80.0, 120.0, 1560.0, 1640.0, 3120.0, 4680.0]
    assert orders[4]["name"] == "TE line"                 # a sideband, 25 % of the largest
    assert orders[2]["amplitude_arcsec"] == 0.0          # no line at 120
    assert orders[3]["amplitude_arcsec"] == 0.0          # round-off: below 1e-6 of 2.0
    ratio = 1 / 121
    cross = find_crossings(orders, [7.0, 3000.0], ratio, (0.0, 1815.0))
    # n_in = 60 f / (order |w_out/w_in|): 60 * 7 * 121 / 80 = 635.25 rpm
    by = {(c["order"], c["mode"]): c for c in cross}
    assert by[(80.0, 1)]["speed_rpm"] == pytest.approx(60 * 7.0 * 121 / 80.0, rel=1e-12)
    assert by[(80.0, 1)]["warned"] and by[(40.0, 1)]["warned"]
    assert not by[(120.0, 1)]["warned"]
    assert (80.0, 2) not in by                             # 544500 rpm: outside the range


def test_modes_command_json_and_campbell_file(tmp_path, capsys):
    out = tmp_path / "m"
    assert cli.main(["modes", str(RV40E), "--load-inertia-kgm2", "200", "--input", "held",
                     "--json", "--positions", "4", "--out", str(out)]) == 0
    data = json.loads(capsys.readouterr().out)
    first = data["modes"][0]
    assert first["frequency_Hz"] == pytest.approx(data["two_inertia_frequency_Hz"], rel=0.02)
    assert set(first) >= {"frequency_Hz", "strain_energy_shares", "shape"}
    assert any("campbell" in f for f in data["files"])
    assert (out / "campbell.png").is_file() and (out / "modes.png").is_file()
    assert cli.main(["modes", str(RV40E), "--load-inertia-kgm2", "-1"]) == 2
    err = capsys.readouterr().err
    assert "load_inertia_kgm2" in err and len(err.strip().splitlines()) == 1


def test_the_lumped_crank_chain_of_our_own_meets_the_system_modes():
    """benchmarks/lumped_rv_torsion.py: RV-40E's planets on the spur mesh and eccentrics on
    the shafts' torsion, a two-degree-of-freedom chain per crank from the drawing alone
    (ISO 6336-1's mesh stiffness, G I_p / L, solid-cylinder inertias), against the system
    model's modes of the same motion within 5 % (measured -1.3 % and -0.7 %: the chain leaves
    the eccentrics free, the system holds them by the crank bearings)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "lumped_rv_torsion", ROOT / "benchmarks" / "lumped_rv_torsion.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    rows = mod.compare(load_case(ROOT / "cases" / "rv40e.toml"))
    assert len(rows) == 2
    for motion, _lumped, _system, gap in rows:
        assert abs(gap) < mod.RTOL, motion


def test_a_summary_that_is_not_finite_is_written_as_strict_json():
    """A self-locking train's backdrive torque is infinite: the summary is strict JSON with
    null there (the self_locking flag beside it), never Infinity or NaN."""
    import json

    from toothfem.report.modes import finite_json

    text = finite_json({"backdrive": {"positive": {"backdrive_torque_Nm": math.inf,
                                                   "fit_residual_Nm": math.nan,
                                                   "self_locking": True}},
                        "range_Hz": [1.0, math.inf], "count": 3})
    assert "Infinity" not in text and "NaN" not in text
    back = json.loads(text)
    assert back["backdrive"]["positive"]["backdrive_torque_Nm"] is None
    assert back["range_Hz"] == [1.0, None] and back["count"] == 3
