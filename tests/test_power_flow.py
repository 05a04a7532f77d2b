"""Power flow of reducer trains: the RV paper's split-power method and the general
virtual-power method (Chen & Angeles 2007; the test oracle tests/oracles/power_flow.py).
Derivations: docs/derivations.md, section 5."""
import math
import tomllib

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from tests.oracles import power_flow as pf
from toothfem.efficiency import rv_paper as rp
from toothfem.errors import ToothfemError

#: Solver checks: a 5x5 least-squares speed solve and a 5x5 torque solve in double
#: precision; observed errors are below 1e-13.
REL = 1e-11
#: Energy balance (brief): input - output = sum of mesh losses.
BALANCE_REL = 1e-9

RV40E = (12, 36, 39, 40)


@pytest.fixture
def rv40e_case(cases_dir):
    with open(cases_dir / "rv_paper_example.toml", "rb") as f:
        return tomllib.load(f)


# --- 1. The RV paper's method ----------------------------------------------------------

def test_rv40e_paper_example_from_its_inputs(rv40e_case):
    """RV paper Eqs. 16-20 from Table 1 inputs. The paper prints rounded numbers, so each
    is checked to half a unit of its last printed digit: V 2211.8 (+-0.05 W), U 58.2051
    (+-5e-5 W), L1 136.2 (+-0.05 W), L2 131.52 (+-0.005 W), eta 88.2 % (+-0.05 %)."""
    rv, pub, op = rv40e_case["rv"], rv40e_case["published"], rv40e_case["operating"]
    r = rp.rv_split_power(rv["sun_teeth"], rv["planet_teeth"], rv["disc_teeth"],
                          rv["pin_count"], op["input_power_kW"] * 1e3,
                          rv["mesh_efficiency"], rv["mesh_efficiency"])
    assert abs(r.split_power_V_W - pub["split_power_V_W"]) <= 0.05
    assert abs(r.virtual_power_U_W - pub["virtual_power_U_W"]) <= 5e-5
    assert abs(r.loss_L1_W - pub["loss_L1_W"]) <= 0.05
    assert abs(r.loss_L2_W - pub["loss_L2_W"]) <= 0.005
    assert abs(r.efficiency - pub["efficiency"]) <= 0.0005
    # the same numbers, written out: Eq. 20 unrounded is 88.206 %
    assert r.efficiency == pytest.approx(0.8820615384615385, rel=REL)


def test_rv_paper_eqs_4_5_8_9_11_12_are_consistent():
    """Eq. 4 w3/w4 = z4/(z4 - z5) = -39; Eq. 5 i24 = (z1 + z2 - z1 i16)/z2 = -39;
    Eq. 8 beta = P/(P - V) = -w2/w4 = 39; Eq. 9 V = (2 z4 - z5)/z4 P;
    Eq. 10/11 U = (z4 - z5)/z4 P; Eq. 12 U = (z5 - z4)/z4 P; alpha = z5/(z5 - z4) = 40."""
    z1, z2, z4, z5 = RV40E
    p = 2270.0
    r12 = rp.rv_split_power(z1, z2, z4, z5, p, 0.94, 0.94)
    r11 = rp.rv_split_power(z1, z2, z4, z5, p, 0.94, 0.94, u_equation=11)
    assert r12.ratio == pytest.approx(121, rel=REL)
    assert r12.crank_disc_ratio == pytest.approx(z4 / (z4 - z5), rel=REL)
    assert (z1 + z2 - z1 * r12.ratio) / z2 == pytest.approx(r12.crank_disc_ratio, rel=REL)
    assert r12.beta == pytest.approx(39, rel=REL)
    assert p / (p - r12.split_power_V_W) == pytest.approx(r12.beta, rel=REL)
    assert r12.split_power_V_W == pytest.approx((2 * z4 - z5) / z4 * p, rel=REL)
    assert r12.alpha == pytest.approx(z5 / (z5 - z4), rel=REL)
    assert r12.virtual_power_U_W == pytest.approx((z5 - z4) / z4 * p, rel=1e-9)
    assert r11.virtual_power_U_W == pytest.approx((z4 - z5) / z4 * p, rel=1e-9)
    # U = P - V in magnitude: the paper's "virtual power" is its own split remainder
    assert r12.virtual_power_U_W == pytest.approx(p - r12.split_power_V_W, rel=1e-9)
    # its output power is P - L1 - L2 (Eq. 15)
    assert r12.output_power_W == pytest.approx(p - r12.loss_L1_W - r12.loss_L2_W, rel=REL)


def test_fig12_trend_efficiency_rises_with_pair_efficiency():
    """Fig. 12: the reducer efficiency rises with the single-pair mesh efficiency (same
    value on both pairs), for the paper's method and for the general method."""
    etas = np.linspace(0.90, 1.0, 21)
    paper = [rp.rv_split_power(*RV40E, 2270.0, e, e).efficiency for e in etas]
    general = [pf.rv_power_flow(*RV40E, 2270.0, e, e).efficiency for e in etas]
    assert np.all(np.diff(paper) > 0) and np.all(np.diff(general) > 0)
    assert paper[-1] == pytest.approx(1.0, rel=REL)
    assert general[-1] == pytest.approx(1.0, rel=REL)


def test_fig13_trend_paper_method_depends_only_on_cycloid_teeth():
    """The paper's eta depends on the tooth numbers only through (z5 - z4)/z4, so Fig. 13's
    ratio must come from the cycloid stage (z4, z5 = z4 + 1). Changing z2/z1 (the way the
    RV-40E catalogue ratios 57..153 are made) leaves it unchanged; with U of Eq. 12 it RISES
    with the ratio, contrary to Fig. 13; with U of Eq. 11 (negative) it falls, as Fig. 13."""
    first_stage = [(15, 21), (12, 24), (10, 26), (12, 36), (10, 38)]     # i = 57 .. 153
    flat = [rp.rv_split_power(z1, z2, 39, 40, 2270.0, .94, .94).efficiency
            for z1, z2 in first_stage]
    assert max(flat) - min(flat) < 1e-12
    z4s = [19, 29, 39, 49, 59]                                             # i = 61 .. 181
    eq12 = [rp.rv_split_power(12, 36, z, z + 1, 2270.0, .94, .94) for z in z4s]
    eq11 = [rp.rv_split_power(12, 36, z, z + 1, 2270.0, .94, .94, u_equation=11)
            for z in z4s]
    assert np.all(np.diff([r.ratio for r in eq12]) > 0)
    assert np.all(np.diff([r.efficiency for r in eq12]) > 0)               # printed: rises
    assert np.all(np.diff([r.efficiency for r in eq11]) < 0)               # Fig. 13: falls


@pytest.mark.parametrize("etas", [(0.94, 0.94), (0.98, 0.995)])
def test_fig13_trend_general_method_efficiency_falls_with_ratio(etas):
    """General method: efficiency falls with the ratio whichever stage makes it, strongly
    through the cycloid stage (z4, z5 = z4 + 1), weakly through z2/z1."""
    by_z4 = [pf.rv_power_flow(12, 36, z, z + 1, 2270.0, *etas).efficiency
             for z in (19, 29, 39, 49, 59)]
    by_z2z1 = [pf.rv_power_flow(z1, z2, 39, 40, 2270.0, *etas).efficiency
               for z1, z2 in [(15, 21), (12, 24), (10, 26), (12, 36), (10, 38)]]
    assert np.all(np.diff(by_z4) < 0) and np.all(np.diff(by_z2z1) < 0)


# --- 2. General virtual-power method -----------------------------------------------------

def test_rv40e_general_method_numbers_and_closed_form():
    """RV-40E by the general method (measured numbers quoted in the docs), against the
    closed form eta = (1 + r e1 z5/(z5 - z4 e2))/i, r = z2/z1, i = 121."""
    z1, z2, z4, z5 = RV40E
    r, i = z2 / z1, 1 + (z2 / z1) * z5 / (z5 - z4)
    for e1, e2 in [(0.94, 0.94), (0.98, 0.99), (0.98, 0.995), (0.999, 0.9)]:
        res = pf.rv_power_flow(*RV40E, 2270.0, e1, e2)
        assert res.efficiency == pytest.approx((1 + r * e1 * z5 / (z5 - z4 * e2)) / i, rel=REL)
    res = pf.rv_power_flow(*RV40E, 2270.0, 0.94, 0.94)
    assert res.efficiency == pytest.approx(0.28738, abs=5e-6)
    sp, dp = res.mesh("sun-planet"), res.mesh("disc-pins")
    assert (sp.driver, dp.driver) == ("sun", "pins")     # pins drive in the crank frame
    # sun-planet: virtual power (1 - 1/i) P exactly (the sun torque is set by the input)
    assert sp.virtual_power_W == pytest.approx(2270.0 * 120 / 121, rel=REL)
    # lossless: disc-pins virtual power = r z4 z5/(z5 - z4)^2 / i * P = 38.68 P
    ideal = pf.rv_power_flow(*RV40E, 2270.0, 1.0, 1.0)
    assert ideal.mesh("disc-pins").virtual_power_W == pytest.approx(
        3 * 39 * 40 / 121 * 2270.0, rel=REL)


def test_rv_back_drive_closed_form():
    """Back-driving (carrier in, sun out): planet drives the sun-planet mesh, disc drives the
    pins; eta = i / (1 + (r/e1) z5 e2/(z5 e2 - z4)) while z5 e2 > z4."""
    z1, z2, z4, z5 = RV40E
    r, i = z2 / z1, 1 + (z2 / z1) * z5 / (z5 - z4)
    for e1, e2 in [(0.98, 0.995), (0.98, 0.999), (0.94, 0.99)]:
        res = pf.rv_power_flow(*RV40E, 2270.0, e1, e2, back_drive=True)
        assert (res.mesh("sun-planet").driver, res.mesh("disc-pins").driver) == \
            ("planet", "disc")
        closed = i / (1 + (r / e1) * z5 * e2 / (z5 * e2 - z4))
        assert res.efficiency == pytest.approx(closed, rel=REL)
        assert not res.self_locking
    assert pf.rv_power_flow(*RV40E, 2270.0, 0.94, 0.94, back_drive=True).self_locking


@pytest.mark.parametrize("z_moving, z_fixed", [(39, 40), (79, 80)])
@pytest.mark.parametrize("eta", [0.9, 0.99, 0.995, 0.999, 1.0])
def test_khv_general_solver_matches_closed_form_both_directions(z_moving, z_fixed, eta):
    """K-H-V, c = z_f/(z_f - z_m): crank driving eta = 1/(1 + c (1/eta_m - 1)) (the ring
    drives in the crank frame); back-driving eta = 1 - c (1 - eta_m) (the moving member
    drives; <= 0 is self-locking). Cycloid 39/40 (c = 40) and sine 79/80 (c = 80)."""
    fwd = pf.khv_power_flow(z_moving, z_fixed, 1000.0, eta)
    back = pf.khv_power_flow(z_moving, z_fixed, 1000.0, eta, back_drive=True)
    assert fwd.efficiency == pytest.approx(pf.khv_efficiency(z_moving, z_fixed, eta), rel=REL)
    assert back.efficiency == pytest.approx(
        pf.khv_efficiency(z_moving, z_fixed, eta, back_drive=True), rel=REL, abs=1e-13)
    c = z_fixed / (z_fixed - z_moving)
    assert pf.khv_efficiency(z_moving, z_fixed, eta) == pytest.approx(
        1 / (1 + c * (1 / eta - 1)), rel=REL)
    if eta < 1:
        assert fwd.meshes[0].driver == "fixed" and back.meshes[0].driver == "moving"
    assert back.self_locking == (1 - c * (1 - eta) <= 0)


def test_khv_closed_form_values():
    """Hand values: 39/40 at 0.99 -> 1/(1 + 40/99) = 99/139; back 1 - 0.4 = 0.6;
    79/80 at 0.999 back 1 - 0.08 = 0.92; 39/40 at 0.9 back -3 (self-locking)."""
    assert pf.khv_efficiency(39, 40, 0.99) == pytest.approx(99 / 139, rel=REL)
    assert pf.khv_efficiency(39, 40, 0.99, back_drive=True) == pytest.approx(0.6, rel=REL)
    assert pf.khv_efficiency(79, 80, 0.999, back_drive=True) == pytest.approx(0.92, rel=REL)
    assert pf.khv_power_flow(39, 40, 1.0, 0.9, back_drive=True).efficiency == \
        pytest.approx(-3.0, rel=REL)


def test_simple_planetary_2kh_and_fixed_axis_pair():
    """Other trains through the same generic solver. 2K-H, sun in, ring held, carrier out:
    eta = (1 + e_sp e_pr z_r/z_s)/(1 + z_r/z_s) (sun drives planet drives ring in the
    carrier frame). Fixed-axis pair (housing as carrier): eta = e."""
    zs, zp, zr = 20, 31, 82
    train = pf.GearTrain(
        members=("sun", "planet", "ring", "carrier"),
        meshes=(pf.Mesh("sun", "planet", "carrier", zs, zp, internal=False, efficiency=0.98),
                pf.Mesh("planet", "ring", "carrier", zp, zr, internal=True, efficiency=0.99)))
    res = pf.power_flow(train, input_member="sun", output_member="carrier",
                        fixed=("ring",), input_power_W=500.0, input_speed_rad_s=150.0)
    u = zr / zs
    assert res.efficiency == pytest.approx((1 + 0.98 * 0.99 * u) / (1 + u), rel=REL)
    pair = pf.GearTrain(members=("pinion", "wheel", "housing"),
                        meshes=(pf.Mesh("pinion", "wheel", "housing", 17, 53, False, 0.97),))
    res = pf.power_flow(pair, input_member="pinion", output_member="wheel",
                        fixed="housing", input_power_W=10.0, input_speed_rad_s=-3.0)
    assert res.efficiency == pytest.approx(0.97, rel=REL)
    assert res.speeds["wheel"] == pytest.approx(3.0 * 17 / 53, rel=REL)


@settings(max_examples=60, deadline=None)
@given(z1=st.integers(8, 30), ratio=st.integers(1, 5), z4=st.integers(11, 79),
       e1=st.floats(0.9, 1.0), e2=st.floats(0.995, 1.0), back=st.booleans(),
       w=st.floats(0.1, 500.0), p=st.floats(1.0, 1e4))
def test_energy_balance_rv(z1, ratio, z4, e1, e2, back, w, p):
    """Input power - output power = sum of mesh losses (1e-9 relative), each loss >= 0,
    torques on every member balance (sum of external torques = 0)."""
    res = pf.rv_power_flow(z1, z1 * ratio, z4, z4 + 1, p, e1, e2, back_drive=back,
                           input_speed_rad_s=w)
    assert res.input_power_W - res.output_power_W == pytest.approx(
        res.loss_W, rel=BALANCE_REL, abs=BALANCE_REL * p)
    assert all(m.loss_W >= 0 for m in res.meshes)
    assert abs(sum(res.external_torques_Nm.values())) <= 1e-9 * max(
        abs(t) for t in res.external_torques_Nm.values())


@pytest.mark.parametrize("back", [False, True])
@pytest.mark.parametrize("zm, zf", [(39, 40), (79, 80)])
def test_energy_balance_khv(zm, zf, back):
    res = pf.khv_power_flow(zm, zf, 750.0, 0.997, back_drive=back, input_speed_rad_s=157.0)
    assert (res.input_power_W - res.output_power_W) / res.input_power_W == pytest.approx(
        res.loss_W / res.input_power_W, abs=BALANCE_REL)


def test_efficiency_tends_to_one_when_meshes_are_lossless():
    """eta -> 1 as every mesh efficiency -> 1; the deficit is first order in (1 - eta_m)."""
    for d in (1e-3, 1e-5, 1e-7):
        e = 1 - d
        for res in (pf.rv_power_flow(*RV40E, 2270.0, e, e),
                    pf.rv_power_flow(*RV40E, 2270.0, e, e, back_drive=True),
                    pf.khv_power_flow(79, 80, 100.0, e),
                    pf.khv_power_flow(39, 40, 100.0, e, back_drive=True)):
            assert 0 < 1 - res.efficiency < 200 * d
    assert pf.rv_power_flow(*RV40E, 2270.0, 1.0, 1.0).efficiency == pytest.approx(1, rel=REL)
    assert rp.rv_split_power(*RV40E, 2270.0, 1.0, 1.0).efficiency == 1.0


def test_callable_mesh_efficiency():
    """A callable efficiency returning a constant gives the float result; a load-dependent
    one (losses partly load-independent: eta = 1 - 0.002 - 5 W / P_v) converges, keeps the
    energy balance, and is evaluated at the converged virtual power."""
    const = pf.rv_power_flow(*RV40E, 2270.0, lambda s: 0.98, lambda s: 0.995)
    assert const.efficiency == pytest.approx(
        pf.rv_power_flow(*RV40E, 2270.0, 0.98, 0.995).efficiency, rel=REL)

    def eta(state):
        return 1.0 - 0.002 - 5.0 / max(state.virtual_power_W, 1e3)

    res = pf.rv_power_flow(*RV40E, 2270.0, eta, eta)
    assert res.input_power_W - res.output_power_W == pytest.approx(res.loss_W, rel=BALANCE_REL)
    for m in res.meshes:
        assert m.efficiency == pytest.approx(1 - 0.002 - 5.0 / max(m.virtual_power_W, 1e3),
                                             abs=1e-10)


# --- 3. Bad input ------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [0.0, -0.1, 1.2, math.nan, math.inf])
def test_efficiency_outside_unit_interval_is_refused(bad):
    for call, name in [
        (lambda: rp.rv_split_power(*RV40E, 2270.0, bad, 0.94), "mesh_efficiency_1"),
        (lambda: rp.rv_split_power(*RV40E, 2270.0, 0.94, bad), "mesh_efficiency_2"),
        (lambda: pf.rv_power_flow(*RV40E, 2270.0, 0.94, bad), "mesh_efficiency_2"),
        (lambda: pf.khv_efficiency(39, 40, bad), "mesh_efficiency"),
        (lambda: pf.khv_power_flow(39, 40, 1.0, bad), "mesh_efficiency"),
        (lambda: pf.Mesh("a", "b", "h", 10, 20, False, bad), "efficiency"),
    ]:
        with pytest.raises(ToothfemError) as err:
            call()
        msg = str(err.value)
        assert f"{name} = " in msg and "(0, 1]" in msg
        if math.isfinite(bad):
            assert repr(bad) in msg or f"{bad:g}" in msg


def test_callable_efficiency_outside_range_is_refused():
    with pytest.raises(ToothfemError, match=r"efficiency of mesh 'disc-pins' = 1\.5 .*\(0, 1\]"):
        pf.rv_power_flow(*RV40E, 2270.0, 0.98, lambda s: 1.5)


@pytest.mark.parametrize("call", [
    lambda: rp.rv_split_power(12, 36, 40, 40, 2270.0, 0.94, 0.94),
    lambda: pf.rv_power_flow(12, 36, 40, 40, 2270.0, 0.94, 0.94),
])
def test_equal_disc_and_pin_teeth_are_refused(call):
    with pytest.raises(ToothfemError, match=r"z_pins = 40 is outside the valid range \[41, inf\)"):
        call()


def test_other_bad_inputs_are_refused():
    with pytest.raises(ToothfemError,
                       match=r"z_fixed = 80 is outside the valid range \[81, inf\)"):
        pf.khv_efficiency(80, 80, 0.99)
    with pytest.raises(ToothfemError, match=r"z_b = 30 is outside the valid range z_b != z_a"):
        pf.Mesh("p", "r", "h", 30, 30, internal=True)
    with pytest.raises(ToothfemError,
                       match=r"input_power_W = 0.0 is outside the valid range \(0, inf\)"):
        rp.rv_split_power(*RV40E, 0.0, 0.94, 0.94)
    with pytest.raises(ToothfemError, match=r"z_sun = 12\.5 must be an integer"):
        rp.rv_split_power(12.5, 36, 39, 40, 2270.0, 0.94, 0.94)
    with pytest.raises(ToothfemError, match="input_speed_rad_s = 0.0"):
        pf.khv_power_flow(39, 40, 1.0, 0.99, input_speed_rad_s=0.0)
    with pytest.raises(ToothfemError, match="not determined"):   # nothing held: 2 dof
        pf.power_flow(pf.khv_train(39, 40, 0.99), input_member="crank",
                      output_member="moving", input_power_W=1.0)


def test_results_are_frozen():
    r = rp.rv_split_power(*RV40E, 2270.0, 0.94, 0.94)
    g = pf.rv_power_flow(*RV40E, 2270.0, 0.94, 0.94)
    with pytest.raises(AttributeError):
        r.efficiency = 1.0
    with pytest.raises(TypeError):
        g.speeds["sun"] = 2.0
