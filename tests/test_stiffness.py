"""The datasheet's parts (docs/stiffness.md): supports in closed form, mirror symmetry of
the two flanks, mesh convergence of the rigidity, the TE's full period and harmonics, a
clearance the loop does not close, bad input. The datasheet through the system model is
tested in tests/test_system*.py (rigid limits, the closing rotation, the hand model)."""
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
from toothfem.fem.drives import drive_for
from toothfem.fem.system.datasheet import SystemTwist


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


def test_assumed_supports_are_marked(case, drive):
    d = case_to_dict(case)
    d["supports"] = {"bearing_roller_count": 20, "carrier_stiffness_Nm_per_arcmin": 400.0}
    s = drive.supports(parse_case(d).to_si().supports).describe()
    assert s["bearing_roller_count"] == {"value": 20, "assumed": False}
    assert s["bearing_roller_length_mm"]["assumed"]
    assert s["carrier_stiffness_Nm_per_arcmin"]["value"] == pytest.approx(400.0)
    assert not s["carrier_stiffness_Nm_per_arcmin"]["assumed"]


SPRING = 1e-11      # m per N/m: an equal contact spring (rigid bodies, the seed's limit)


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
    position (the next pin's clearance is microns away), the curve would be backlash.
    The system model on equal pin springs (no FE)."""
    g = replace(drive.geometry, equidistant_m=50e-6)
    d = replace(drive, stage=replace(drive.stage, geometry=g))
    system = d.system_model(supports, 3, cache=False, pin_spring_m_per_N=SPRING)
    with pytest.raises(CaseError, match="torque_max_Nm = 0.01 .*backlash"):
        datasheet(SystemTwist(system), 167.0, torque_max_Nm=0.01)


def test_cli_refuses_few_steps(cases_dir, tmp_path, capsys):
    from toothfem.cli import main

    rc = main(["stiffness", str(cases_dir / "cycloid_pinhousing.toml"), "--out",
               str(tmp_path / "out"), "--steps", "3"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "steps = 3" in err[0]
    assert not (tmp_path / "out").exists()
