"""Cycloid disc: conjugacy, validity, modifications, kinematics against the seed's closed forms.

Analytic facts checked here (docs/derivations.md, C1-C5):
- every pin centre lies on the theoretical profile at every crank angle, so the working
  profile is tangent to every pin circle;
- the normal at each contact passes through the pitch point P = r_b u(phi);
- the moment arm equals the seed's Eq. (14); sum of l_i^2 over the loaded half = Zb r_a^2/4.
"""
import math

import numpy as np
import pytest
from shapely import affinity

from toothfem.errors import GeometryError
from toothfem.geometry import (cycloid as cy, cycloid_backlash as cyb, cycloid_distance as cyd,
                               cycloid_mesh as cym)
from toothfem.geometry.disc import DiscHolesSI, disc_polygon

PIN_HOUSING = cy.CycloidGeometry(40, 0.100, 0.001, 0.002)
# a second, more strongly shortened drive (K1 = 0.72) so no result hinges on one K1
SMALL = cy.CycloidGeometry(12, 0.030, 0.0018, 0.003)
GEOMS = [PIN_HOUSING, SMALL]
CRANK = np.linspace(0.0, 2 * math.pi, 13)[:-1] + 0.123  # 12 generic crank angles


def _pins_in_disc_frame(g, phi):
    c = np.broadcast_to(cym.pin_centres(g)[:, None, :], (2, phi.size, g.pin_count))
    return cym.to_disc_frame(g, phi, c).reshape(2, -1)


@pytest.mark.parametrize("g", GEOMS, ids=["pin-housing", "K1=0.72"])
def test_unmodified_profile_tangent_to_every_pin(g):
    """|distance(pin centre, working profile) - rz| < 1e-6 Rz at 12 crank angles, every pin,
    measured by a Newton foot point on the parametric curve started from a global search."""
    d = cyd.distance_to_profile(g, _pins_in_disc_frame(g, CRANK))
    err = np.max(np.abs(d - g.pin_radius_m))
    assert err < 1e-6 * g.pin_circle_radius_m
    assert err < 1e-12  # in fact exact to rounding: the pins lie on the theoretical curve


@pytest.mark.parametrize("g", GEOMS, ids=["pin-housing", "K1=0.72"])
def test_polygon_valid_with_lobe_symmetry(g):
    poly = disc_polygon(g, points_per_lobe=64)
    assert poly.is_valid and poly.geom_type == "Polygon"
    turned = affinity.rotate(poly, 2 * math.pi / g.lobe_count, origin=(0, 0), use_radians=True)
    # samples are equally spaced in psi and psi -> psi + 2pi/Za maps the curve onto itself
    # turned by 2pi/Za, so the only mismatch is rounding
    assert poly.symmetric_difference(turned).area < 1e-9 * poly.area
    # and turning by half a lobe is NOT a symmetry (the test can fail)
    half = affinity.rotate(poly, math.pi / g.lobe_count, origin=(0, 0), use_radians=True)
    assert poly.symmetric_difference(half).area > 1e-4 * poly.area


def test_disc_with_holes_is_valid_and_holes_are_checked():
    holes = DiscHolesSI(0.010, 2, 0.027, 0.011, 2, 0.027, 0.009)
    poly = disc_polygon(PIN_HOUSING, holes)
    assert poly.is_valid and len(poly.interiors) == 5
    hole_area = math.pi * (0.010**2 + 2 * 0.011**2 + 2 * 0.009**2)
    assert math.isclose(disc_polygon(PIN_HOUSING).area - poly.area, hole_area, rel_tol=1e-3)
    with pytest.raises(GeometryError, match=r"crank_0 hole reaches radius 100 mm, "
                       r"outside the valid range \(0, 96.5\) mm"):
        disc_polygon(PIN_HOUSING, DiscHolesSI(0, 2, 0.090, 0.010))
    with pytest.raises(GeometryError, match="closer than the minimum ligament"):
        disc_polygon(PIN_HOUSING, DiscHolesSI(0.020, 2, 0.027, 0.008))


MODS = [
    dict(equidistant_m=10e-6),
    dict(move_distance_m=-10e-6),
    dict(equidistant_m=10e-6, move_distance_m=-10e-6),
    dict(equidistant_m=20e-6, move_distance_m=-10e-6, rotation_rad=5e-5),
    dict(equidistant_m=-10e-6, move_distance_m=-20e-6, rotation_rad=1e-4),
]


@pytest.mark.parametrize("mods", MODS, ids=lambda m: ",".join(f"{k}={v:g}" for k, v in m.items()))
def test_clearance_closed_form_matches_exact_geometry(mods):
    """Clearance per pin versus pin angle: first-order closed form (docs C4) against the exact
    distance between each pin centre and the modified parametric profile, with the disc
    turned by the closing rotation found from the exact gaps. The closed form is first order
    in the modification, so the tolerance is 2 % of the largest clearance (the measured
    error is second order: see the next test)."""
    g = cy.CycloidGeometry(40, 0.100, 0.001, 0.002, **mods)
    theta = np.linspace(0.02, math.pi - 0.02, 90)
    exact0 = cym.clearance_exact(g, -theta)[:, 0]    # pin 0 at angle theta from the centres' line
    d0, d, beta0 = cyb.clearance_closed_form(g, theta)
    scale = np.max(np.abs(d0))
    assert np.max(np.abs(exact0 - d0)) < 0.02 * scale
    arm = np.abs(cym.seed_moment_arm(g, theta))
    beta_exact = np.min(exact0 / arm)
    exact = exact0 - beta_exact * arm
    assert np.max(np.abs(exact - d)) < 0.02 * scale
    assert abs(beta_exact - beta0) < 0.02 * abs(beta0) + 1e-9
    assert np.min(d) > -0.02 * scale          # clearance, not interference, after closing


def test_clearance_error_is_second_order():
    """Halving... dividing the modification by 10 divides the closed-form error by ~100."""
    theta = np.linspace(0.1, math.pi - 0.1, 40)
    errs = []
    for s in (1.0, 0.1):
        g = cy.CycloidGeometry(40, 0.100, 0.001, 0.002, equidistant_m=40e-6 * s,
                               move_distance_m=-40e-6 * s, rotation_rad=2e-4 * s)
        errs.append(np.max(np.abs(cym.clearance_exact(g, -theta)[:, 0]
                                  - cyb.clearance_closed_form(g, theta)[0])))
    assert 50 < errs[0] / errs[1] < 200


def test_textbook_form_for_positive_equidistant_negative_move():
    g = cy.CycloidGeometry(40, 0.100, 0.001, 0.002, equidistant_m=15e-6, move_distance_m=-8e-6)
    theta = np.linspace(0.05, math.pi - 0.05, 50)
    k1 = g.k1
    s = np.sqrt(1 + k1**2 - 2 * k1 * np.cos(theta))
    book = (15e-6 * (1 - np.sin(theta) / s)
            + 8e-6 * (1 - k1 * np.cos(theta) - math.sqrt(1 - k1**2) * np.sin(theta)) / s)
    assert np.allclose(cyb.clearance_closed_form(g, theta)[1], book, rtol=0, atol=1e-15)


@pytest.mark.parametrize("kwargs, match", [
    (dict(eccentricity_m=0.0026), r"eccentricity_m = 0.0026 is outside the valid range "
                                  r"\(0, 0.0025\): K1 = A\*Zb/Rz must be below 1"),
    (dict(eccentricity_m=0.0), r"eccentricity_m = 0.0 is outside the valid range \(0,"),
    (dict(pin_count=12, pin_circle_radius_m=0.030, eccentricity_m=0.0018, pin_radius_m=0.0077),
     r"pin_radius_m = 0.0077 is outside the valid range \(0, 0.00765469\): the working "
     r"profile would be undercut"),
    (dict(equidistant_m=-1e-5), r"equidistant_m - move_distance_m = -1e-05 is outside the "
                                r"valid range \[0, inf\): the disc would interfere"),
    (dict(pin_radius_m=0.0079, eccentricity_m=0.0005),
     r"pin_radius_m = 0.0079 is outside the valid range \(0, 0.00784591\): neighbouring pins"),
    (dict(pin_count=3), r"pin_count = 3 is outside the valid range \[4,"),
    (dict(equidistant_m=0.002), r"equidistant_m = 0.002 is outside the valid range"),
    (dict(rotation_rad=0.1), r"rotation_rad = 0.1 is outside the valid range"),
])
def test_looped_cusped_undercut_refused_with_bound(kwargs, match):
    base = dict(pin_count=40, pin_circle_radius_m=0.1, eccentricity_m=0.001, pin_radius_m=0.002)
    base.update(kwargs)
    with pytest.raises(GeometryError, match=match):
        cy.CycloidGeometry(**base)


def test_curvature_radius_formula_matches_derivatives():
    g = SMALL.generating()
    psi = np.linspace(0, 2 * math.pi, 997)
    p1, p2 = cy.theoretical_profile(g, psi, 1), cy.theoretical_profile(g, psi, 2)
    rho = np.hypot(*p1) ** 3 / (p1[0] * p2[1] - p1[1] * p2[0])
    assert np.allclose(cy.curvature_radius(g, psi), rho, rtol=1e-10)
    # and the undercut bound is that radius at its convex minimum
    assert math.isclose(cy.min_convex_curvature_radius(g), np.min(rho[rho > 0]), rel_tol=1e-4)


@pytest.mark.parametrize("g", GEOMS, ids=["pin-housing", "K1=0.72"])
def test_kinematics_against_profile_and_seed(g):
    """Moment arm and pressure angle from the closed forms (seed Eq. 14; normals through P)
    against the same quantities computed from the parametric profile; velocities against
    finite differences of the disc pose."""
    phi = CRANK
    m = cym.meshing(g, phi, crank_speed_rad_s=2.0)
    # -- from the profile: foot point of each pin centre, normal of the working curve there
    gg = g.generating()
    local = _pins_in_disc_frame(g, phi)
    psi, _ = cyd.foot_point(gg, local, cyd._nearest_psi(gg, local))
    n_loc = -cy.inward_normal(gg, psi)                 # outward normal of the disc
    k_loc = cy.working_profile(gg, psi)
    centre, rot = cym.disc_pose(g, phi)
    rot = np.repeat(rot, g.pin_count)
    c, s = np.cos(rot), np.sin(rot)
    k = np.stack([c * k_loc[0] - s * k_loc[1], s * k_loc[0] + c * k_loc[1]])
    k = k + np.repeat(centre, g.pin_count, axis=1)
    n = -np.stack([c * n_loc[0] - s * n_loc[1], s * n_loc[0] + c * n_loc[1]])  # into disc
    rel = k - np.repeat(centre, g.pin_count, axis=1)
    arm = (rel[0] * n[1] - rel[1] * n[0]).reshape(m.shape)
    assert np.allclose(m.point, np.moveaxis(k, 0, -1).reshape(m.point.shape), atol=1e-12)
    assert np.allclose(m.moment_arm, arm, atol=1e-12)
    theta_b = np.mod(2 * math.pi * np.arange(g.pin_count) / g.pin_count - phi[:, None],
                     2 * math.pi)
    assert np.allclose(m.moment_arm, -cym.seed_moment_arm(g, theta_b), atol=1e-12)
    alpha = np.arccos(np.abs(arm) / np.hypot(*rel).reshape(m.shape))
    assert np.allclose(m.pressure_angle, alpha, atol=1e-9)
    # -- velocities: disc material point and contact point by central differences in time
    omega, h = 2.0, 1e-6
    def pose_point(dphi, local_pts):
        cc, rr = cym.disc_pose(g, phi + dphi)
        rr = np.repeat(rr, g.pin_count)
        p = np.stack([np.cos(rr) * local_pts[0] - np.sin(rr) * local_pts[1],
                      np.sin(rr) * local_pts[0] + np.cos(rr) * local_pts[1]])
        return p + np.repeat(cc, g.pin_count, axis=1)
    v_mat = (pose_point(h, k_loc) - pose_point(-h, k_loc)) / (2 * h) * omega
    t = np.moveaxis(np.stack([-m.normal[..., 1], m.normal[..., 0]]), 0, 0).reshape(2, -1)
    assert np.allclose(m.sliding_velocity.ravel(), np.sum(v_mat * t, axis=0), atol=1e-9)
    k_next = cym.meshing(g, phi + h).point
    k_prev = cym.meshing(g, phi - h).point
    dk = (np.moveaxis(k_next - k_prev, -1, 0) / (2 * h) * omega).reshape(2, -1)
    u_pin = np.sum(dk * t, axis=0)
    u_disc = u_pin - np.sum(v_mat * t, axis=0)
    assert np.allclose(m.entrainment_velocity.ravel(), 0.5 * (u_pin + u_disc), atol=1e-8)


def test_normals_pass_through_pitch_point_and_disc_turns_back():
    m = cym.meshing(PIN_HOUSING, CRANK)
    pitch = PIN_HOUSING.pin_pitch_radius_m * np.stack([np.cos(CRANK), np.sin(CRANK)], -1)
    d = pitch[:, None, :] - m.point
    cross = d[..., 0] * m.normal[..., 1] - d[..., 1] * m.normal[..., 0]
    assert np.max(np.abs(cross)) < 1e-14
    _, rot = cym.disc_pose(PIN_HOUSING, [0.0, 2 * math.pi])
    assert math.isclose(rot[1] - rot[0], -2 * math.pi / 39, rel_tol=1e-14)


def test_seed_sum_of_squared_moment_arms():
    """Seed Eqs. 11-12: sum over the loaded pins of l_i^2 = Zb r_a^2 / 4.

    Over all Zb pins the sum is Zb r_a^2/2 exactly (up to aliasing of order K1^Zb); the
    half-sum is exact when the pin set is symmetric about the line of centres
    (phi = k pi/Zb) and otherwise carries an O(h^3) truncation error (h = 2 pi/Zb) from the
    kink of sin^2 at theta = 0, pi: measured below 1e-4 relative for Zb = 40 (docs C3)."""
    g = PIN_HOUSING
    target = g.pin_count * g.disc_pitch_radius_m**2 / 4
    sym = np.arange(6) * math.pi / g.pin_count
    for phi, rtol in ((sym, 1e-12), (CRANK, 1e-4)):
        m = cym.meshing(g, phi)
        s = np.sum(np.where(m.moment_arm < 0, m.moment_arm**2, 0.0), axis=1)
        assert np.allclose(s, target, rtol=rtol)
        assert np.allclose(np.sum(m.moment_arm**2, axis=1), 2 * target, rtol=1e-12)
    assert np.all(np.sum(m.moment_arm < 0, axis=1) == 20)


def test_rolling_pins_do_not_slide_on_the_disc():
    m_fixed = cym.meshing(PIN_HOUSING, CRANK, pin_motion="fixed")
    m_roll = cym.meshing(PIN_HOUSING, CRANK, pin_motion="rolling")
    assert np.all(m_roll.sliding_velocity == 0)
    assert np.max(np.abs(m_fixed.sliding_velocity)) > 0
    assert np.all(np.isfinite(m_fixed.slide_to_roll))
    assert np.all(m_fixed.equivalent_radius > 0)
    with pytest.raises(GeometryError, match="pin_motion = 'sliding' is not one of"):
        cym.meshing(PIN_HOUSING, CRANK, pin_motion="sliding")


def test_modified_meshing_gap_is_exact_clearance():
    g = cy.CycloidGeometry(40, 0.100, 0.001, 0.002, equidistant_m=10e-6)
    m = cym.meshing(g, CRANK)
    assert np.allclose(m.gap, 10e-6, atol=1e-12)  # equidistant: uniform normal clearance
