"""FE load sharing of the pin-housing cycloid drive (conventional pins).

Analytic facts: torque equilibrium sum F_i l_i = T; the rigid-body limit with equal
contact springs gives the seed's F_i = F_max l_i / r_a on 20 of 40 pins; a clearance
modification loads fewer pins harder; cycle and detailed modes agree (docs/fem.md).
"""
import math

import numpy as np
import pytest

from toothfem import load_case
from toothfem.fem import cycloid_fe as cf
from toothfem.fem.load_sharing import analytic_split
from toothfem.geometry import cycloid_mesh as cym
from toothfem.fem.drives import drive_for


@pytest.fixture(scope="module")
def case(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


@pytest.fixture(scope="module")
def model(case):
    return drive_for(case).fe_model(pin_structure="conventional")


PHIS = np.array([0.013, 0.061, 0.117])      # generic crank angles within one pin pitch


@pytest.fixture(scope="module")
def cycle(model, case, fe_cache):
    return cf.CycleSolver(model, PHIS, cache=fe_cache).solve(
        drive_for(case).member_torque(case.operating.output_torque_Nm))


def test_torque_equilibrium_every_position(cycle, case):
    """sum F_i l_i = T to 1e-8 relative (the solver imposes it as a constraint)."""
    assert np.all(np.abs(cycle.torque_residual()) < 1e-8)
    assert cycle.torque == pytest.approx(drive_for(case).member_torque(case.operating.output_torque_Nm))


def test_cycle_mode_physics(cycle):
    """19-20 pins carry load (20 in the rigid limit; with elastic bodies the pin whose arm
    tends to zero at the end of the zone may lift off); none on the unloaded side; the
    transmission error is a small positive lag; Hertz pressure and half-width agree."""
    assert np.all((cycle.contacts_per_position >= 19) & (cycle.contacts_per_position <= 20))
    assert np.all(cycle.force[cycle.moment_arm > 0] == 0)
    assert np.all((cycle.transmission_error > 0) & (cycle.transmission_error < 1e-3))
    loaded = cycle.force > 0
    w = cycle.force[loaded] / cycle.face_width
    assert np.allclose(cycle.ph[loaded], 2 * w / (math.pi * cycle.half_width[loaded]),
                       rtol=1e-12)
    assert np.all(cycle.gap[loaded] == 0) and np.all(cycle.gap[~loaded] >= 0)


def test_rigid_body_limit_reproduces_seed(model, case):
    """Stiff bodies, equal springs: F_i = F_max l_i / r_a (pin-housing paper Eq. 10) on the
    20 pins with 0 < theta_b < pi; F_max from the exact sum of l_i^2 (Eq. 13 within 1e-4)."""
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    ls = cf.CycleSolver(model, PHIS, equal_springs=1e-11).solve(torque)
    state = cym.meshing(model.geometry, PHIS)
    seed = analytic_split(state, torque, model.face_width, model.e_star, weight="moment_arm")
    assert np.all(ls.contacts_per_position == 20)
    assert np.allclose(ls.force, seed.force, rtol=1e-9, atol=1e-9)
    r_a = model.geometry.disc_pitch_radius_m
    f_max = 4 * torque / (r_a * model.geometry.pin_count)         # Eq. 13
    assert np.allclose(ls.force, f_max * np.where(ls.force > 0, -ls.moment_arm, 0) / r_a,
                       rtol=2e-4, atol=1e-6)


def test_clearance_modification_loads_fewer_pins_harder(case, cycle, fe_cache):
    from dataclasses import replace

    g = replace(case.cycloid.geometry(), equidistant_m=10e-6, move_distance_m=-10e-6)
    model = replace(drive_for(case).fe_model(pin_structure="conventional"), geometry=g)
    mod = cf.CycleSolver(model, PHIS, cache=fe_cache).solve(
        drive_for(case).member_torque(case.operating.output_torque_Nm))
    assert np.all(mod.contacts_per_position < cycle.contacts_per_position)
    assert np.all(mod.force.max(axis=1) > 1.2 * cycle.force.max(axis=1))
    assert np.all(np.abs(mod.torque_residual()) < 1e-8)
    # more torque closes more clearance: the count rises with the load
    more = cf.CycleSolver(model, PHIS[:1], cache=fe_cache).solve(
        3 * drive_for(case).member_torque(case.operating.output_torque_Nm))
    assert more.contacts_per_position[0] > mod.contacts_per_position[0]


def test_new_torque_reuses_influence(model, case, fe_cache):
    s = cf.CycleSolver(model, PHIS[:1], cache=fe_cache)
    a = s.solve(drive_for(case).member_torque(case.operating.output_torque_Nm))
    infl = s._influence[0]
    b = s.solve(2 * drive_for(case).member_torque(case.operating.output_torque_Nm))
    assert s._influence[0] is infl
    assert b.force.max() > 1.9 * a.force.max()    # nearly linear (Hertz adds a log)


@pytest.mark.slow
@pytest.mark.parametrize("phi", [0.0, 0.05, 0.11])
def test_cycle_and_detailed_modes_agree(model, case, phi, fe_cache):
    """Maximum pin force within 2 % (measured 0.2 %, docs/fem.md); the detailed mode's
    nodal forces balance the torque exactly with their own moment arms."""
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    det = cf.solve_detailed(model, phi, torque, elements_per_halfwidth=5)
    cyc = cf.CycleSolver(model, np.array([phi]), cache=fe_cache).solve(torque)
    fd, fc = det.load_sharing.force[0], cyc.force[0]
    assert abs(fd.max() / fc.max() - 1) < 0.02
    assert np.sum(fd > 0) == np.sum(fc > 0)
    assert abs(det.load_sharing.torque_residual()[0]) < 1e-8
    assert abs(det.load_sharing.ph[0].max() / cyc.ph[0].max() - 1) < 0.03
    # the FE pressure of the most loaded pin against Hertz on its FE force: within 3 %
    # (P2 with 5 elements per half-width: 0.4 % on the Hertz cases; docs/fem.md)
    k = int(np.argmax(fd[det.pins]))
    assert abs(np.max(det.pressure[k]) / det.load_sharing.ph[0, det.pins[k]] - 1) < 0.03


def test_integral_housing_against_conventional(case, fe_cache):
    """The integral structure (pins one piece with a housing clamped at r = 112 mm) shares
    the load like the conventional pins within a few per cent and balances the torque."""
    integral = cf.CycleSolver(drive_for(case).fe_model(pin_structure="integral"), PHIS[:2],
                              cache=fe_cache).solve(
        drive_for(case).member_torque(case.operating.output_torque_Nm))
    conventional = cf.CycleSolver(drive_for(case).fe_model(pin_structure="conventional"),
                                  PHIS[:2], cache=fe_cache).solve(
        drive_for(case).member_torque(case.operating.output_torque_Nm))
    assert np.all(np.abs(integral.torque_residual()) < 1e-8)
    assert np.all(integral.contacts_per_position >= 19)
    ratio = integral.force.max(axis=1) / conventional.force.max(axis=1)
    assert np.all(np.abs(ratio - 1) < 0.05)


@pytest.mark.slow
def test_integral_cycle_and_detailed_agree(case, fe_cache):
    model = drive_for(case).fe_model(pin_structure="integral")
    torque = drive_for(case).member_torque(case.operating.output_torque_Nm)
    det = cf.solve_detailed(model, 0.05, torque, elements_per_halfwidth=4)
    cyc = cf.CycleSolver(model, np.array([0.05]), cache=fe_cache).solve(torque)
    assert abs(det.load_sharing.force.max() / cyc.force.max() - 1) < 0.02
    assert abs(det.load_sharing.torque_residual()[0]) < 1e-8


def test_integral_housing_outline(case):
    """The housing's bore: the circle Rz with the inner part of every pin circle protruding;
    a valid polygon whose area is the annulus plus 40 pin segments (exact to the outline's
    chord sag, < 1e-4 relative)."""
    from shapely.geometry import Polygon

    model = drive_for(case).fe_model(pin_structure="integral")
    inner, outer = cf.housing_rings(model, {})
    poly = Polygon(outer.T, [inner.T])
    assert poly.is_valid
    rz, big_r, r_out = 0.002, 0.100, model.housing_outer_radius
    alpha = math.acos(-rz / (2 * big_r))
    # segment of the pin circle inside radius Rz (angle 2 pi - 2 alpha) minus the lens of
    # the Rz circle cut off by the pin's chord: area of the circular segments
    seg_pin = 0.5 * rz**2 * ((2 * math.pi - 2 * alpha) - math.sin(2 * math.pi - 2 * alpha))
    beta = 2 * math.asin(rz * math.sin(alpha) / big_r)
    seg_bore = 0.5 * big_r**2 * (beta - math.sin(beta))
    n_out = outer.shape[1]
    annulus = 0.5 * n_out * r_out**2 * math.sin(2 * math.pi / n_out) - math.pi * big_r**2
    expected = annulus + 40 * (seg_pin + seg_bore)
    assert poly.area == pytest.approx(expected, rel=1e-4)
