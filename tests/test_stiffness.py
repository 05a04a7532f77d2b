"""The datasheet from the contact model (docs/stiffness.md): supports in closed form, the
equal-springs rigid limit, mirror symmetry of the two flanks, backlash = the closing
rotation of the modification, mesh convergence of the rigidity, the twist against the
cycle solver's TE, the TE's full period and harmonics, bad input."""
import math
from dataclasses import replace

import numpy as np
import pytest

from toothfem import load_case
from toothfem.case import case_to_dict, parse_case
from toothfem.errors import CaseError
from toothfem.fem import cycloid_fe as cf
from toothfem.fem.datasheet import supports as sp
from toothfem.fem.datasheet.sheet import datasheet, loop_torques
from toothfem.fem.datasheet.transmission import (fourier_fill, harmonic_amplitudes,
                                                  sampled_pitches)
from toothfem.fem.datasheet.twist import ARCMIN, TwistModel, closing_rotation
from toothfem.fem.drives import drive_for
from toothfem.geometry import cycloid_mesh as cym


@pytest.fixture(scope="module")
def case(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


@pytest.fixture(scope="module")
def drive(case):
    return drive_for(case)


@pytest.fixture(scope="module")
def supports(case, drive):
    return drive.supports(case.to_si().supports)


# -- supports: closed forms ----------------------------------------------------------------

def test_roller_and_shaft_closed_forms():
    """Palmgren: 1 kN on a 10 mm roller approaches 3.84e-5 * 1000^0.9 / 10^0.8 mm; the
    most loaded of 10 rollers carries 4.08 F/10 on two raceways; a shaft's mid-span
    deflection is L^3/(48 EI) + L/(4 k G A) (Roark; Timoshenko). Exact formulas: 1e-12."""
    assert sp.roller_approach(1000.0, 0.01) == pytest.approx(
        3.84e-5 * 1000 ** 0.9 / 10 ** 0.8 * 1e-3, rel=1e-12)
    assert sp.radial_bearing_deflection(2000.0, 10, 0.01) == pytest.approx(
        2 * sp.roller_approach(4.08 * 200.0, 0.01), rel=1e-12)
    e, nu, d, span = 208e9, 0.3, 0.015, 0.04
    inertia, area = math.pi * d ** 4 / 64, math.pi * d ** 2 / 4
    mid = span ** 3 / (48 * e * inertia) + span / (4 * 0.9 * e / (2 * (1 + nu)) * area)
    assert sp.simply_supported_influence(span / 2, span / 2, span, d, e, nu) == \
        pytest.approx(mid, rel=1e-12)
    # Maxwell's reciprocity
    a = sp.simply_supported_influence(0.01, 0.03, span, d, e, nu)
    assert a == pytest.approx(sp.simply_supported_influence(0.03, 0.01, span, d, e, nu))


def test_crank_bearings_without_resultant(drive, supports):
    """With no contact resultant each of the n crank holes carries T/(n R_c) tangentially:
    the output turns by the bearing's deflection under it over R_c."""
    h = drive.stage.holes
    t = 80.0
    out = drive.member_support_twists(supports, np.full(3, t), np.zeros((3, 2)),
                                      np.array([0.0, 0.05, 0.1]))["crank bearings"]
    f = t / (h.crank_hole_count * h.crank_hole_circle_radius_m)
    want = sp.radial_bearing_deflection(f, supports.bearing_roller_count,
                                        supports.bearing_roller_length_m)
    assert np.allclose(out, want / h.crank_hole_circle_radius_m, rtol=1e-12)


def test_assumed_supports_are_marked(case, drive):
    d = case_to_dict(case)
    d["supports"] = {"bearing_roller_count": 20, "carrier_stiffness_Nm_per_arcmin": 400.0}
    s = drive.supports(parse_case(d).to_si().supports).describe()
    assert s["bearing_roller_count"] == {"value": 20, "assumed": False}
    assert s["bearing_roller_length_mm"]["assumed"]
    assert s["carrier_stiffness_Nm_per_arcmin"]["value"] == pytest.approx(400.0)
    assert not s["carrier_stiffness_Nm_per_arcmin"]["assumed"]


# -- the rigid limit, the closing rotation ------------------------------------------------

SPRING = 1e-11      # m per N/m: an equal contact spring (rigid bodies, the seed's limit)


def test_equal_springs_twist_is_the_closed_form(drive, supports):
    """Rigid bodies on equal springs k: beta = (T_m / w) k / sum l_i^2 over the pins of the
    loaded flank (docs/stiffness.md), either sign, T_m the member torque (the power flow's
    share); the datasheet's mesh compliance is its mean slope (T_m/T) k / (w sum l^2).
    Linear algebra only: 1e-9."""
    phis = drive.positions(4)
    solver = cf.CycleSolver(drive.fe_model(), phis, equal_springs=SPRING, sides=(1, -1))
    model = TwistModel(drive, supports, solver)
    arm = drive.meshing(phis).moment_arm
    w, m = drive.face_width_m, drive.members
    for side in (1, -1):
        t = side * 120.0
        sum_l2 = np.sum(np.where(side * arm < 0, arm ** 2, 0.0), axis=1)
        want = (side * drive.member_torque(abs(t), peak=False) / w) * SPRING / sum_l2
        assert np.allclose(model.at(t).paths["mesh"], want, rtol=1e-9)
    sheet = datasheet(model, 167.0)
    sum_l2 = np.sum(np.where(arm < 0, arm ** 2, 0.0), axis=1)
    per_nm = drive.member_torque(1.0, peak=False)
    slope = np.mean(per_nm * SPRING / (w * sum_l2)) / ARCMIN
    assert sheet.compliance_arcmin_per_Nm["mesh"] == pytest.approx(slope, rel=1e-9)
    # unmodified: both flanks touch at rest; the springs' part at ZERO_TORQUE_NM remains
    assert abs(sheet.backlash_arcmin) < 1e-6


def test_backlash_is_the_closing_rotation(drive, supports):
    """A 10 um equidistant modification: the zero-torque twist of each flank is the rigid
    rotation that closes the first pin's clearance, min D0/|l| over the pins of the flank
    with the first-order clearance D0 = Delta_rz of docs C4 (clearance_closed_form), the
    backlash twice it. The exact clearances differ at second order, (Delta/r_a) = 2.6e-4
    relative: tolerance 1e-3. The springs' part at the zero-torque limit is ~1e-8 of it."""
    g = replace(drive.geometry, equidistant_m=10e-6)
    d = replace(drive, stage=replace(drive.stage, geometry=g))
    phis = d.positions(6)
    solver = cf.CycleSolver(d.fe_model(), phis, equal_springs=SPRING, sides=(1, -1))
    model = TwistModel(d, supports, solver)
    theta_b = np.mod(2 * np.pi * np.arange(40)[None, :] / 40 - phis[:, None], 2 * np.pi)
    d0, _, _ = cym.clearance_closed_form(g, theta_b)
    arm = np.abs(cym.seed_moment_arm(g, theta_b))
    for side, flank in ((1, theta_b < np.pi), (-1, theta_b > np.pi)):
        want = np.min(np.where(flank & (arm > 0), d0 / np.where(arm > 0, arm, 1), np.inf),
                      axis=1)
        assert np.allclose(closing_rotation(model.state, side), side * want, rtol=1e-3)
        assert np.allclose(model.at(0.0, side).total, side * want, rtol=1e-3)
    sheet = datasheet(model, 167.0)
    backlash = np.mean(model.at(0.0, 1).total - model.at(0.0, -1).total) / ARCMIN
    assert sheet.backlash_arcmin == pytest.approx(backlash, rel=1e-12)
    assert backlash == pytest.approx(2 * cym.closing_rotation(g) / ARCMIN, rel=1e-2)


# -- FE: mirror symmetry and the cycle solver's TE ------------------------------------------

PHI0 = 0.3 * 2 * math.pi / 40      # a generic crank angle, and its mirror image -PHI0


@pytest.fixture(scope="module")
def both_sides(drive, fe_cache):
    """Conventional pins (the lighter model), both flanks, at PHI0, -PHI0 and 0."""
    return cf.CycleSolver(drive.fe_model(pin_structure="conventional"),
                          np.array([PHI0, -PHI0, 0.0]), sides=(1, -1), cache=fe_cache)


def test_two_flanks_mirror_each_other(both_sides):
    """The drive is symmetric about the x-axis (pins, lobes, holes): -T at phi is +T at -phi
    mirrored, so beta(-T, phi) = -beta(T, -phi) and the pin counts agree. The meshes of the
    two flanks are not mirror images (gmsh): measured 0.2 %, tolerance 1 %."""
    t = 90.0
    pos, neg = both_sides.solve(t), both_sides.solve(-t)
    te_p, te_n = pos.transmission_error, neg.transmission_error
    assert te_n[1] == pytest.approx(-te_p[0], rel=1e-2)
    assert te_n[0] == pytest.approx(-te_p[1], rel=1e-2)
    assert te_n[2] == pytest.approx(-te_p[2], rel=1e-2)
    assert np.array_equal(neg.contacts_per_position[[1, 0, 2]], pos.contacts_per_position)
    assert np.all(np.abs(neg.torque_residual()) < 1e-8)


def test_twist_is_the_cycle_solvers_te(drive, supports, both_sides):
    """The datasheet's mesh twist at a torque is the cycle solver's transmission error at
    the member torque (the same solve: 1e-12)."""
    model = TwistModel(drive, supports, both_sides)
    tm = drive.member_torque(167.0, peak=False)
    assert np.allclose(model.at(167.0).paths["mesh"],
                       both_sides.solve(tm).transmission_error, rtol=1e-12)


@pytest.mark.slow
def test_both_flank_mesh_agrees_with_one_flank_mesh(drive, supports, both_sides, fe_cache):
    """The one-flank solver (the cycle mode of `toothfem contact`, its mesh refined on one
    flank only) gives the same TE within the two meshes' difference (tolerance 1 %)."""
    tm = drive.member_torque(167.0, peak=False)
    one = cf.CycleSolver(both_sides.model, both_sides.positions_rad, cache=fe_cache)
    assert np.allclose(both_sides.solve(tm).transmission_error,
                       one.solve(tm).transmission_error, rtol=1e-2)


@pytest.mark.slow
def test_rigidity_converges_with_the_mesh(drive, fe_cache):
    """The mesh's rigidity (50-100 % slope of beta) on three meshes of 3, 5 and 8 elements
    per reference strip: the change from the middle to the finest below 2 %."""
    phis = drive.positions(2)
    tm = drive.member_torque(167.0, peak=False)
    slopes = []
    for n in (3, 5, 8):
        s = cf.CycleSolver(drive.fe_model(pin_structure="conventional"), phis,
                           elements_per_bref=n, cache=fe_cache)
        d_beta = s.solve(tm).transmission_error - s.solve(0.5 * tm).transmission_error
        slopes.append(0.5 * tm / np.mean(d_beta))
    assert abs(slopes[2] / slopes[1] - 1) < 0.02


# -- the full period and its harmonics ----------------------------------------------------

def test_full_period_and_member_offsets(case, drive):
    """40 pins, 39 lobes, holes of two-fold symmetry: the model repeats after 39 pitches;
    the second disc (the same part turned by pi) sits at the first's configuration (the
    whole assembly turned by pi about the axis maps one disc onto the other)."""
    assert drive.full_period_pitches == 39
    assert drive.member_offsets(12) == (0, 0)
    three = replace(drive, stage=replace(drive.stage, holes=replace(
        drive.stage.holes, pillar_hole_count=3, crank_hole_count=3)))
    assert three.full_period_pitches == 13
    with pytest.raises(CaseError, match="crank holes"):
        three.member_offsets(12)


def test_fourier_fill_and_harmonics():
    """A pitch-wise signal of order <= (Q-1)/2 is refilled exactly from Q samples; a pure
    cosine of h cycles per period has amplitude 1 at order h * 2 pi / (period's angle)."""
    k, n = 39, 4
    m = np.arange(k)[:, None] + np.arange(n)[None, :] / n
    f = 2 + np.cos(2 * np.pi * 2 * m / k) + 0.3 * np.sin(2 * np.pi * m / k)
    q = sampled_pitches(k, 6)
    assert len(q) == 6
    assert np.allclose(fourier_fill(q, f[list(q)], k), f, atol=1e-12)
    x = np.cos(2 * np.pi * 3 * np.arange(64) / 64)
    orders, amp = harmonic_amplitudes(x, 2 * np.pi / 40)
    assert orders[np.argmax(amp)] == pytest.approx(3 * 40)
    assert amp.max() == pytest.approx(1.0, rel=1e-12)


# -- bad input ----------------------------------------------------------------------------

def test_bad_input_names_the_key(case):
    with pytest.raises(CaseError, match="steps = 3"):
        loop_torques(100.0, 3)
    with pytest.raises(CaseError, match="torque_max_Nm = -1"):
        loop_torques(-1.0, 8)
    d = case_to_dict(case)
    d["operating"]["rated_torque_Nm"] = -5.0
    with pytest.raises(CaseError, match="operating.rated_torque_Nm = -5"):
        parse_case(d)
    d = case_to_dict(case)
    d["supports"] = {"bearing_roller_count": 1}
    with pytest.raises(CaseError, match="supports.bearing_roller_count = 1"):
        parse_case(d)
    assert len(loop_torques(167.0, 8)) == 41


def test_unclosed_clearance_is_refused(drive, supports):
    """A 50 um equidistant modification and a loop to 0.01 N m: one pin carries at every
    position (the next pin's clearance is microns away), the curve would be backlash."""
    g = replace(drive.geometry, equidistant_m=50e-6)
    d = replace(drive, stage=replace(drive.stage, geometry=g))
    solver = cf.CycleSolver(d.fe_model(), d.positions(3), equal_springs=SPRING,
                            sides=(1, -1))
    with pytest.raises(CaseError, match="torque_max_Nm = 0.01 .*backlash"):
        datasheet(TwistModel(d, supports, solver), 167.0, torque_max_Nm=0.01)


def test_cli_refuses_few_steps(cases_dir, tmp_path, capsys):
    from toothfem.cli import main

    rc = main(["stiffness", str(cases_dir / "cycloid_pinhousing.toml"), "--out",
               str(tmp_path / "out"), "--steps", "3"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "steps = 3" in err[0]
    assert not (tmp_path / "out").exists()
