"""The physically complete defaults of the efficiency model (issue 13, items 1-2): mixed
lubrication by load sharing, churning per gear stage in an oil bath, ISO/TR 14179-1 seals,
Palmgren's drag without a bath, the oil's temperature range; and the bar they must meet
(RV-40E at 412 N m inside the maker's 80-95 % and falling with speed; every case less
efficient at 10 % of its operating torque). Each law is checked against a number worked by
hand from its source's formula; the tolerance says why it is what it is."""
import dataclasses
import math

import numpy as np
import pytest

from toothfem import CaseError, load_case
from toothfem.case import Friction, Lubricant, Material
from toothfem.efficiency import evaluate, operating_point
from toothfem.efficiency import lubricant as lb
from toothfem.efficiency import mixed_film as mf
from toothfem.efficiency import no_load as nl
from toothfem.efficiency import palmgren as pg
from toothfem.efficiency.bearing_set import reducer_bearings

R = dataclasses.replace
#: 700 HV in Pa (HV is kgf/mm^2).
H_700HV = 700 * 9.80665e6


@pytest.fixture(scope="module")
def cases(cases_dir):
    return {n: load_case(cases_dir / f"{n}.toml")
            for n in ("sine_prototype", "cycloid_pinhousing", "rv40e")}


# ---------------------------------------------------------------------------------------
# Mixed lubrication


def test_bearing_ratio_is_the_gaussian_tail():
    """Abbott-Firestone bearing ratio of a Gaussian surface = P(Z > lambda): the standard
    normal table's 0.15866 above one sigma and 0.0013499 above three (table values to 5
    digits, hence the tolerance)."""
    assert mf.bearing_ratio(1.0) == pytest.approx(0.15866, abs=1e-5)
    assert mf.bearing_ratio(3.0) == pytest.approx(0.0013499, abs=1e-7)
    assert mf.bearing_ratio(0.0) == pytest.approx(0.5)


def test_asperity_share_solves_the_load_sharing():
    """Johnson, Greenwood & Poon's load sharing with plastic asperities (Bowden & Tabor:
    A_r = W_a/H): f = min(1, (H/p_m) BR(lambda (1 - f)^-0.1)), p_m = pi P_h/4. At
    P_h = 1 GPa and H = 700 HV, H/p_m = 8.741: by hand f(3) = 8.741 x 0.0013499 = 0.0118
    to first order, 0.01166 with the film's relief; the solution satisfies its own equation
    to the bisection's 1e-6."""
    lam = np.array([1.5, 2.0, 3.0])
    f = mf.asperity_load_share(lam, 1e9, H_700HV)
    k = H_700HV / (math.pi * 1e9 / 4)
    assert k == pytest.approx(8.741, abs=1e-3)
    np.testing.assert_allclose(f, np.minimum(1, k * mf.bearing_ratio(lam * (1 - f) ** -0.1)),
                               atol=2e-6)
    assert f[2] == pytest.approx(0.01166, abs=2e-5) and f[2] < k * mf.bearing_ratio(3.0)
    assert np.all(np.diff(f) < 0)                     # thicker film, fewer asperities
    # touching mean planes: half the area at the hardness carries 4.4 times the load
    assert mf.asperity_load_share(0.0, 1e9, H_700HV) == 1.0
    assert mf.asperity_load_share(np.inf, 1e9, H_700HV) == 0.0      # no film ratio known
    assert mf.asperity_load_share(2.0, 0.0, H_700HV) == 0.0          # unloaded contact
    # a lower nominal pressure: the same asperities carry a larger share
    assert mf.asperity_load_share(2.0, 0.3e9, H_700HV) > f[1]


def test_mixed_friction_and_its_default():
    """mu = (1 - f) mu_EHL + f mu_b; the default mu_b is 0.1 (lubricated steel, Bowden &
    Tabor 1950) and the default hardness 700 HV (60 HRC by ASTM E140)."""
    assert mf.mixed_friction(0.02, 0.25, 0.1) == pytest.approx(0.04)
    assert Friction().boundary_coefficient == 0.1
    assert Material(youngs_modulus_GPa=210.0, poisson_ratio=0.3).hardness_HV == 700.0


def test_rv_pins_are_in_boundary_lubrication(cases):
    """The RV-40E pins run at film ratios of 1e-4..1: the asperities carry the load and the
    disc contact rubs at the boundary friction (above the grooves' 0.05, so the pins turn
    in their grooves at every loaded contact)."""
    e = evaluate(cases["rv40e"], 1500.0, 412.0)
    assert any("asperities carry 100 %" in n for n in e.notes)
    assert any("grooves at 100 %" in n for n in e.notes)


# ---------------------------------------------------------------------------------------
# Load-independent losses


def test_seal_loss_iso_14179():
    """ISO/TR 14179-1: P = 7.69e-6 D^2 n W; a 50 mm shaft at 1500 rpm: 7.69e-6 x 2500 x
    1500 = 28.84 W (torque 0.184 N m). Exact arithmetic."""
    w = 1500 * 2 * math.pi / 60
    assert nl.seal_loss(0.050, w) == pytest.approx(28.8375, rel=1e-12)
    assert nl.seal_loss(0.050, w) / w == pytest.approx(0.1836, abs=1e-4)
    assert nl.seal_loss(0.0, w) == 0.0


def test_palmgren_no_load_moment():
    """Palmgren: M0 = 1e-7 f0 (nu n)^(2/3) d_m^3 N mm (nu n >= 2000), 160e-7 f0 d_m^3 below.
    A needle bearing in an oil bath (f0 = 12, Harris & Kotzalas' table), d_m = 20 mm, VG 68
    at 40 C (68 mm^2/s), 500 rpm: (34000)^(2/3) = 1049.5, M0 = 10.08 N mm. The branches meet
    at nu n = 2000 to Palmgren's rounding of 2000^(2/3) = 158.7 to 160 (0.8 %)."""
    w = 500 * 2 * math.pi / 60
    m0 = pg.palmgren_no_load_moment(pg.palmgren_f0("needle", "oil_bath"), 68e-6, w, 0.020)
    assert m0 * 1e3 == pytest.approx(1e-7 * 12 * 34000 ** (2 / 3) * 8000, rel=1e-12)
    assert m0 * 1e3 == pytest.approx(10.08, abs=0.01)
    w2000 = 2000 / 68 * 2 * math.pi / 60             # nu n = 2000 exactly
    hi = pg.palmgren_no_load_moment(2.0, 68e-6, w2000 * (1 + 1e-9), 0.05)
    lo = pg.palmgren_no_load_moment(2.0, 68e-6, w2000 * (1 - 1e-9), 0.05)
    assert hi / lo == pytest.approx(2000 ** (2 / 3) / 160, rel=1e-6)
    with pytest.raises(CaseError, match="bearing type 'plain' is not one of"):
        pg.palmgren_f0("plain", "oil_bath")


def test_churning_of_each_gear_stage(cases):
    """Lu & Xu Eq. 42 on the RV-40E's first stage: a0 = 1.5 (12 + 36)/2 = 36 mm at the sun's
    1500 (1 - 1/121) rpm relative to the carrier, 68 mm^2/s: by hand 1e-7 x 36 x
    (1487.6/60)^(4/3) x (68/1487.6)^0.1 x 158 kW = 36 x 72.29 x 0.7346 x 158 x 1e-4 = 30.20 W
    (4 digits of the hand product, hence 0.01 W); the
    K-H-V stage (a0 = 1.3 mm at the crank speed) adds 0.3 W."""
    grease = cases["rv40e"]                          # RV-E: grease-lubricated
    rv = R(grease, lubricant=R(grease.lubricant, lubrication="oil_bath"))
    e = evaluate(rv, 1500.0, 412.0)
    n_sun = 1500 * (1 - 1 / 121)
    first = lb.churning_lu_xu_2024(0.036, n_sun, 68e-6)
    assert float(first) == pytest.approx(30.20, abs=0.01)
    assert e.losses_W["churning"][0] == pytest.approx(30.48, abs=0.02)
    g = evaluate(grease, 1500.0, 412.0)
    assert "churning" not in g.losses_W and "bearing_drag" not in g.losses_W
    for name in ("crank_bearings", "crank_support_bearings", "main_bearings",
                 "input_bearings"):     # each bearing's viscous drag is in its own row
        assert g.losses_W[name][0] > 0


def test_sine_case_counts_its_seals_in_eq42(cases):
    """The sine paper's P0 (Eq. 42) includes its rig's seals: the case declares no separate
    seal, so the seal component is zero there and the churning share stays the paper's
    law."""
    e = evaluate(cases["sine_prototype"], 500.0, 28.0)
    assert e.losses_W["seals"][0] == 0.0
    assert e.shares()["churning"][0] == pytest.approx(0.0185, abs=0.003)   # paper 1.85 %


# ---------------------------------------------------------------------------------------
# The bar


def test_rv40e_inside_the_makers_range_and_falling_with_speed(cases):
    """The RV paper (Fig. 11, Nabtesco 2003): RV-40E efficiency between 80 and 95 % in the
    steady state, and a gear reducer's efficiency falls with speed at a fixed torque. At
    the rated 412 N m over 500-3000 rpm the model stays inside and falls at every step:
    the load-independent churning of the spur stage grows as n^1.23, faster than the
    output power."""
    rv = cases["rv40e"]
    lo, hi = rv.published["efficiency_range"]
    speeds = np.arange(500.0, 3001.0, 250.0)
    eta = evaluate(rv, speeds, 412.0).efficiency
    assert np.all((eta > lo) & (eta < hi)), eta
    assert np.all(np.diff(eta) < 0), eta


@pytest.mark.parametrize("name", ["sine_prototype", "cycloid_pinhousing", "rv40e"])
def test_part_load_is_less_efficient(cases, name):
    """Load-independent losses (churning, seals) weigh more at part load: every case's
    efficiency at 10 % of its operating torque is below that at the operating torque."""
    case = cases[name]
    speed, torque = operating_point(case)
    eta = evaluate(case, speed, [0.1 * torque, torque]).efficiency
    assert eta[0] < eta[1]


# ---------------------------------------------------------------------------------------
# Oil temperature


def test_viscosity_law_refuses_temperatures_outside_the_oil(cases):
    """Vogel's law only between the pour point (-15 C by default) and the mineral-oil limit
    (150 C), with one line naming the value and the range."""
    rv = cases["rv40e"]
    assert lb.temperature_range(rv.to_si().lubricant) == (-15.0, 150.0)
    for bad in (151.0, -20.0):
        with pytest.raises(CaseError) as err:
            evaluate(rv, 1500.0, 412.0, oil_temp_C=bad)
        msg = str(err.value)
        assert f"oil_temp_C = {bad!r} is outside the valid range [-15, 150]" in msg
        assert "\n" not in msg
    assert evaluate(rv, 1500.0, 412.0, oil_temp_C=150.0).efficiency[0] > 0


def test_lubricant_reference_inside_its_range():
    with pytest.raises(CaseError, match=r"lubricant.reference_temperature_C = 40.0 is outside "
                                        r"the valid range \(50, 150\)"):
        Lubricant(pour_point_C=50.0)


def test_every_new_key_is_in_the_schema_doc(cases_dir):
    """docs/case_schema.md names every key issue 13 added or whose default it changed, with
    its default's source."""
    from toothfem.case import Bearings, DutyPoint, Seals, Thermal

    text = (cases_dir.parent / "docs" / "case_schema.md").read_text()
    keys = [f.name for cls in (Seals, Bearings, Thermal, DutyPoint)
            for f in dataclasses.fields(cls)]
    keys += ["boundary_coefficient", "churning", "lubrication", "pour_point_C",
             "max_temperature_C", "hardness_HV", "allowable_contact_stress_MPa",
             "static_contact_stress_MPa", "yield_strength_MPa", "fatigue_limit_MPa"]
    missing = [k for k in keys if f"`{k}`" not in text]
    assert not missing, missing


def test_crank_support_bearings_carry_the_output_torque(cases):
    """Issue 22: each of the RV-40E's 2 crankshafts passes its discs' torque to the carrier
    (T (1 - 1/i)/(2 R_c), shared by its two tapered support bearings: 3.40 kN each at the
    rated 412 N m); each bearing's Palmgren moment M0 + mu F d_m/2 at the crank's speed
    against the carrier, by hand, exact arithmetic (1e-9). The discs' torque is the power flow's,
    T (1 - 1/i)(Za/Zb) (``Drive.member_torque``, the one torque rule); the system model's
    loads on a crank's two bearings (3.81 and 2.83 kN: the discs sit off-centre on the
    shaft) sum to it over k R_c (1e-4)."""
    from toothfem.fem.drives import drive_for

    rv = cases["rv40e"]
    si = rv.to_si()
    drive = drive_for(si)
    supports = drive.supports(si.supports)
    n_in, t = 1815.0, 412.0
    e = evaluate(rv, n_in, t)
    w = drive.speeds()
    w_rel = abs(n_in * math.pi / 30 * (w["crank"] - w["output"]))
    t_discs = drive.members_torque(t)                       # the power flow's
    r_c = si.cycloid.holes.crank_hole_circle_radius_m        # two cranks, two bearings each
    per_bearing = t_discs / (2 * r_c) / 2
    (b,) = [b for b in reducer_bearings(si, drive) if b.name == "crank_support_bearings"]
    assert b.bore_m >= supports.crankshaft_diameter_m         # it takes the shaft
    m0 = pg.palmgren_no_load_moment(pg.palmgren_f0("tapered", "grease"), 68e-6, w_rel,
                                    b.pitch_diameter_m)
    by_hand = 4 * (m0 + si.friction.bearing_coefficient * per_bearing
                   * b.pitch_diameter_m / 2) * w_rel
    assert e.losses_W["crank_support_bearings"][0] == pytest.approx(by_hand, rel=1e-9)
    # the order of a 25 mm tapered roller set's losses (four of them): tens of watts
    assert 10.0 < by_hand < 50.0
    system = drive.system_model(supports, 6)
    st = system.solve(t, 0)
    crank1 = sum(np.hypot(*st.bearing_force_N[f"support bearing 1{end}"]) for end in "ab")
    power_flow = t * (1 - 1 / 121) * (39 / 40) / (2 * r_c)
    assert crank1 == pytest.approx(power_flow, rel=1e-4)
    assert 2 * per_bearing == pytest.approx(power_flow, rel=1e-12)
