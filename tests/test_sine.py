"""Sine gear pair: conjugacy, validity, kinematics, and the seed's closed forms.

Analytic facts checked here (docs/derivations.md, section 3, S1-S9):
- the ring is the envelope of the planet's positions: at every crank angle the planet
  touches it (normal gap 0, normals opposite) and nowhere enters it;
- the contact normal passes through the pitch point P = r2 u(chi), the planet's instant
  centre, so the sliding speed is |omega_planet| |K - P|;
- the planet turns by -(z2 - z1)/z1 of a turn per crank turn, and the mesh repeats after a
  crank angle 2 pi/z2 with the planet tooth index advanced by one.
"""
import math

import numpy as np
import pytest
from shapely import affinity

from toothfem.errors import GeometryError
from toothfem.geometry import sine, train

# Table 2 of the seed: z1 = 79, z2 = 80, m = 0.9 mm, a = 0.4 mm, L = 8 mm
PROTO = sine.SineGearPair(79, 80, 0.9e-3, 0.4e-3, 8e-3)
# a second pair with a larger tooth difference and fewer teeth, so no result hinges on one
OTHER = sine.SineGearPair(30, 32, 1.0e-3, 0.3e-3, 5e-3)
PAIRS = [PROTO, OTHER]
IDS = ["79/80", "30/32"]
PITCH = 2 * math.pi / PROTO.ring_teeth
# 16 generic crank angles over a revolution: every phase of the tooth mesh is visited
CRANK = np.linspace(0.0, 2 * math.pi, 17)[:-1] + 0.0123


def _conj_columns(m):
    conj = m.gap == 0.0
    assert np.all(conj.sum(axis=1) == 1)
    return np.arange(m.gap.shape[0]), np.argmax(conj, axis=1)


# ---------------------------------------------------------------------------------------
# profiles
@pytest.mark.parametrize("pair", PAIRS, ids=IDS)
def test_derivatives_match_finite_differences(pair):
    """Analytic d/dphi and d2/dphi2 of both profiles against central differences, h=1e-6.
    Tolerance 1e-7 relative: truncation h^2|p'''|/6 and rounding eps|p|/h are both
    ~1e-9 relative here."""
    phi = np.linspace(-0.1, 0.1, 13) + 0.0123
    h = 1e-6
    for fn in (sine.planet_curve, sine.ring_curve):
        c, cp, cm = fn(pair, phi), fn(pair, phi + h), fn(pair, phi - h)
        d1 = (cp.point - cm.point) / (2 * h)
        d2 = (cp.d1 - cm.d1) / (2 * h)
        assert np.max(np.abs(d1 - c.d1)) < 1e-7 * np.max(np.abs(c.d1))
        assert np.max(np.abs(d2 - c.d2)) < 1e-7 * np.max(np.abs(c.d2))


def test_curvature_eq6_against_finite_differences_and_mirror():
    """Eq. (6) in the paper's own parametrisation (x, y) = r (sin phi, cos phi) equals our
    convex-positive curvature (the mirror flips the sign of the standard formula, Eq. 6
    carries a minus); and the curvature of points differenced with h=1e-5 agrees to 1e-5
    relative (second differences: rounding eps|p|/h^2 ~ 1e-7 relative)."""
    phi = np.linspace(-math.pi / 79, math.pi / 79, 41) + 2 * math.pi * 5 / 79
    c = sine.planet_curve(PROTO, phi)
    # paper frame from r, r', r'' (the swap x <-> y of our points)
    d1p, d2p = c.d1[::-1], c.d2[::-1]
    assert np.allclose(sine.curvature_eq6(d1p, d2p), c.curvature, rtol=1e-12, atol=0)
    assert np.allclose(sine.curvature_eq6(c.d1, c.d2), -c.curvature, rtol=1e-12, atol=0)
    h = 1e-5
    p0, pp, pm = (sine.planet_profile(PROTO, phi + s) for s in (0, h, -h))
    d1, d2 = (pp - pm) / (2 * h), (pp - 2 * p0 + pm) / h**2
    k_fd = (d1[0] * d2[1] - d1[1] * d2[0]) / np.hypot(*d1) ** 3
    scale = np.max(np.abs(c.curvature))
    assert np.max(np.abs(k_fd - c.curvature)) < 1e-5 * scale
    # tip convex (radius m^2/(4a)(1+O(a/r1))), root concave
    tip = sine.planet_curve(PROTO, np.array([0.0, math.pi / 79]))
    assert tip.curvature[0] > 0 > tip.curvature[1]
    assert math.isclose(tip.radius[0], 0.9e-3**2 / (4 * 0.4e-3), rel_tol=0.01)


def test_ring_is_the_envelope_not_the_family():
    """Eq. (2) (mirrored) is the family of planet positions; the ring is its envelope:
    each planet point, followed over the crank angle, stays outside the ring material
    (normal gap >= -1e-15 m: rounding of 0.036 m coordinates) and touches it exactly at
    chi(phi), where the meshing equation (p - P1(psi)) . p' = 0 holds."""
    phi = np.linspace(-0.3, 0.3, 9) + 0.0071
    chi_c = sine.contact_crank_angle(PROTO, phi)
    d = np.linspace(-0.05, 0.05, 201)
    chi = chi_c[:, None] + d[None, :]
    centre, th = sine.planet_pose(PROTO, chi.ravel())
    p = sine.planet_profile(PROTO, np.repeat(phi, d.size))
    c, s = np.cos(th), np.sin(th)
    K = np.stack([c * p[0] - s * p[1], s * p[0] + c * p[1]]) + centre
    # Eq. (2) with (x1, y1) = r (sin phi, cos phi), phi2 = chi, phi1 = chi z2/z1
    r = np.hypot(*p)
    ph = np.repeat(phi, d.size)
    x1, y1 = r * np.sin(ph), r * np.cos(ph)
    f2 = chi.ravel()
    f1 = f2 * 80 / 79
    x2 = x1 * np.cos(f1 - f2) - y1 * np.sin(f1 - f2) + 0.45e-3 * np.sin(f2)
    y2 = x1 * np.sin(f1 - f2) + y1 * np.cos(f1 - f2) + 0.45e-3 * np.cos(f2)
    assert np.max(np.abs(K - np.stack([y2, x2]))) < 1e-15   # mirror x <-> y, rounding
    gap = sine.distance_to_ring(PROTO, K).reshape(phi.size, d.size)
    assert gap.min() > -1e-15
    assert np.all(np.argmin(gap, axis=1) == d.size // 2)
    assert np.max(np.abs(gap[:, d.size // 2])) < 1e-15
    X = sine.ring_profile(PROTO, phi)
    assert np.max(np.abs(X - K.reshape(2, phi.size, d.size)[:, :, d.size // 2])) < 1e-15


# ---------------------------------------------------------------------------------------
# conjugacy and interference
@pytest.mark.parametrize("pair", PAIRS, ids=IDS)
def test_profiles_tangent_at_contact(pair):
    """At 16 crank angles the closest approach of the contacting flank, found by Newton on
    the parametric curves, has normal gap < 1e-6 mm (in fact ~1e-17 m: rounding), lies at
    the conjugate point phi* (1e-9 rad: Newton tolerance 1e-12 rad), and the planet's
    outward normal there is opposite the ring's (1e-9: a parameter error of 1e-12 rad turns
    the normal by 1e-12 |p'| kappa, |p'| kappa < 100)."""
    chi = CRANK
    fs = sine.conjugate_contact(pair, chi)
    z1 = pair.planet_teeth
    tooth = np.round(fs * z1 / (2 * math.pi)).astype(int)
    flank = np.where(fs >= 2 * math.pi * tooth / z1, 1, -1)
    ap = sine.closest_approach(pair, chi, tooth, flank)
    assert np.all(ap.own)
    assert np.max(np.abs(ap.gap)) < 1e-9
    assert np.max(np.abs(ap.gap)) < 1e-15
    assert np.max(np.abs(ap.phi_planet - fs)) < 1e-9
    assert np.max(np.hypot(*(ap.planet_point - ap.ring_point))) < 1e-15
    c = sine.planet_curve(pair, fs)
    _, th = sine.planet_pose(pair, chi)
    t = np.stack([np.cos(th) * c.d1[0] - np.sin(th) * c.d1[1],
                  np.sin(th) * c.d1[0] + np.cos(th) * c.d1[1]])
    n_out = np.stack([t[1], -t[0]]) / np.hypot(*t)
    assert np.max(np.abs(n_out + ap.normal)) < 1e-9


def test_no_interference_over_a_tooth_pitch():
    """shapely: the planet placed at 36 crank angles over one tooth pitch overlaps the ring
    by less than the area of ONE chord sliver, h^3 kappa_max/12 (h the chord, kappa_max
    the tip curvature; sag h^2 kappa/8 = 0.48 um at 64 points per tooth). The overlap is a
    discretisation artefact: 4x finer polylines shrink it more than 8x, whereas turning the
    planet 1e-5 rad into the ring (0.2 um at the flanks) gives far more than the sliver."""
    n = 64
    h = 2 * math.pi * PROTO.planet_pitch_radius_m / (PROTO.planet_teeth * n)
    kmax = np.max(np.abs(sine.planet_curve(PROTO, np.linspace(0, 2 * math.pi / 79, 257))
                         .curvature))
    sliver = h**3 * kmax / 12
    chi = np.linspace(0, PITCH, 36, endpoint=False)

    def overlaps(points):
        ring = sine.ring_polygon(PROTO, points_per_tooth=points)
        return np.array([sine.planet_polygon(PROTO, points, c).intersection(ring).area
                         for c in chi]), ring

    coarse, ring = overlaps(n)
    assert coarse.max() < sliver                 # measured 5.7e-16 m^2 vs 1.4e-11 m^2
    fine, _ = overlaps(4 * n)
    assert fine.max() < coarse.max() / 8
    centre = tuple(sine.planet_pose(PROTO, chi[5])[0][:, 0])
    turned = affinity.rotate(sine.planet_polygon(PROTO, n, chi[5]), 1e-5, origin=centre,
                             use_radians=True)
    assert turned.intersection(ring).area > 10 * sliver


def test_closest_approach_matches_dense_sampling():
    """The candidates' own gaps are the local minima of the gap along the planet profile:
    a dense scan (200 points per tooth over the same 9 teeth) finds the same minima to 1e-8 m
    (grid spacing 14 um along the profile, relative curvature radius >= ~10 mm: error
    s^2/(2R) <= 1e-8 m) and never a smaller one (Newton finds the true minimum)."""
    for chi in (0.0, 0.3 * PITCH, 0.77 * PITCH):
        m = sine.meshing(PROTO, chi, candidates=4)
        own = np.sort(m.gap[0][np.isfinite(m.gap[0])])
        j0 = round(chi * 80 / (2 * math.pi))            # tooth nearest the pitch point
        # the candidates' windows: teeth j0-4 .. j0+4, both flanks
        f = (j0 + np.linspace(-4.5, 4.5, 9 * 200 + 1)) * 2 * math.pi / 79
        centre, th = sine.planet_pose(PROTO, chi)
        p = sine.planet_profile(PROTO, f)
        K = np.stack([math.cos(th[0]) * p[0] - math.sin(th[0]) * p[1],
                      math.sin(th[0]) * p[0] + math.cos(th[0]) * p[1]]) + centre
        g = sine.distance_to_ring(PROTO, K)
        i = np.where((g[1:-1] < g[:-2]) & (g[1:-1] <= g[2:]))[0] + 1
        sampled = np.sort(g[i])
        assert sampled.size == own.size
        assert np.max(np.abs(sampled - own)) < 1e-8
        assert np.all(own <= sampled + 1e-15)


@pytest.mark.parametrize("gap_um", [1.0, 5.0, 10.0, 20.0])
def test_contact_count_monotone_and_periodic(gap_um):
    """Tooth pairs within a gap: at least the conjugate one, never fewer for a larger gap,
    the same one tooth pitch (2 pi/z2 of crank) later, and symmetric about the pitch
    midpoint (the profile is symmetric). Prototype: 1-3 pairs within 1 um, 13-16 within
    20 um."""
    chi = np.linspace(0, PITCH, 24, endpoint=False)
    n = sine.contact_count(PROTO, np.r_[chi, chi + 3 * PITCH], gap_um * 1e-6)
    a, b = n[:24], n[24:]
    assert np.array_equal(a, b)
    assert np.all(a >= 1)
    assert np.array_equal(a[1:], a[1:][::-1])
    smaller = sine.contact_count(PROTO, chi, 0.5 * gap_um * 1e-6)
    assert np.all(smaller <= a) and np.any(smaller < a)
    expected = {1.0: (1, 3), 5.0: (5, 7), 10.0: (9, 11), 20.0: (13, 16)}[gap_um]
    assert (a.min(), a.max()) == expected


# ---------------------------------------------------------------------------------------
# kinematics
@pytest.mark.parametrize("pair", PAIRS, ids=IDS)
def test_conjugate_kinematics(pair):
    """At the conjugate contact: the normal passes through P (1e-15 m, rounding); the
    sliding speed is |omega_planet| |K - P| (relative motion is a rotation about P; 1e-12
    relative); the moment arm is r1 u(chi) x n (same identity); the equivalent radius is
    positive. Entrainment against central differences of the contact point over the crank
    angle (h = 1e-7 rad, 1e-6 relative)."""
    om = 3.0
    m = sine.meshing(pair, CRANK, crank_speed_rad_s=om)
    r, c = _conj_columns(m)
    K, n = m.point[r, c], m.normal[r, c]
    P = sine.pitch_point(pair, CRANK).T
    KP = K - P
    assert np.max(np.abs(KP[:, 0] * n[:, 1] - KP[:, 1] * n[:, 0])) < 1e-15
    w = om * pair.tooth_difference / pair.planet_teeth
    assert np.allclose(np.abs(m.sliding_velocity[r, c]), w * np.hypot(*KP.T), rtol=1e-12,
                       atol=1e-18)
    e = np.stack([np.cos(CRANK), np.sin(CRANK)], axis=1)
    arm = pair.planet_pitch_radius_m * (e[:, 0] * n[:, 1] - e[:, 1] * n[:, 0])
    assert np.allclose(m.moment_arm[r, c], arm, rtol=1e-12, atol=1e-15)
    assert np.all(m.equivalent_radius[r, c] > 0)
    assert np.allclose(1 / m.equivalent_radius[r, c],
                       1 / m.radius_moving[r, c] + 1 / m.radius_fixed[r, c], rtol=1e-9)
    h = 1e-7
    kp = sine.meshing(pair, CRANK + h).point[r, c]
    km = sine.meshing(pair, CRANK - h).point[r, c]
    vc = (kp - km) / (2 * h) * om
    v1 = -w * np.stack([-KP[:, 1], KP[:, 0]], axis=1)     # planet turns at -w about P
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    u1 = np.sum((vc - v1) * t, axis=1)
    u2 = np.sum(vc * t, axis=1)
    U = m.entrainment_velocity[r, c]
    assert np.allclose(U, 0.5 * (u1 + u2), rtol=1e-6, atol=1e-6 * np.max(np.abs(U)))
    assert np.allclose(m.sliding_velocity[r, c], u2 - u1, rtol=1e-6,
                       atol=1e-6 * np.max(np.abs(U)))


def test_near_contact_kinematics_against_finite_differences():
    """For the non-conjugate candidates with a minimum of their own, the rolling speeds from
    implicit differentiation of the closest-approach equations agree with central
    differences of the closest points over the crank angle (h = 1e-7 rad; 1e-5 relative:
    the points move with the Newton tolerance 1e-12 rad)."""
    chi = np.array([0.1, 0.45, 0.8]) * PITCH
    m = sine.meshing(PROTO, chi)
    r, c = np.where(np.isfinite(m.gap) & (m.gap > 0))
    tooth = (np.round(chi * 80 / (2 * math.pi))[:, None]
             + np.repeat(np.arange(-4, 5), 2)[None, :])[r, c]
    flank = np.tile([-1, 1], 9)[c]
    h = 1e-7
    ap, am = (sine.closest_approach(PROTO, chi[r] + s, tooth, flank) for s in (h, -h))
    assert np.all(ap.own & am.own)
    v_pl = (ap.planet_point - am.planet_point) / (2 * h)   # closest point on the planet
    v_ring = (ap.ring_point - am.ring_point) / (2 * h)
    P = sine.pitch_point(PROTO, chi[r])
    K = m.point[r, c].T
    v_mat = -(1 / 79) * np.stack([-(K - P)[1], (K - P)[0]])
    n = m.normal[r, c].T
    t = np.stack([-n[1], n[0]])
    u1 = np.sum((v_pl - v_mat) * t, axis=0)
    u2 = np.sum(v_ring * t, axis=0)
    U = m.entrainment_velocity[r, c]
    scale = np.max(np.abs(U))
    assert np.allclose(U, 0.5 * (u1 + u2), rtol=1e-5, atol=1e-5 * scale)
    assert np.allclose(m.sliding_velocity[r, c], np.sum(v_mat * t, axis=0), rtol=1e-12,
                       atol=1e-18)


@pytest.mark.parametrize("pair", PAIRS, ids=IDS)
def test_kinematics_at_reduces_to_meshing(pair):
    """kinematics_at is meshing's column where the contact points coincide: the conjugate
    contact followed at its own rate d phi*/d chi = (z2/z1)/psi' (psi' by central
    differences, h = 1e-6: 1e-8 relative, rounding eps |psi|/h with |psi| up to 6.4 rad),
    and a flank without a minimum of its own at its end point, held there (rate 0: the
    same formulas, 1e-12 relative). The sliding speed is the same number either way
    (1e-12 relative)."""
    om = 3.0
    m = sine.meshing(pair, CRANK, crank_speed_rad_s=om)
    r, c = _conj_columns(m)
    fs = sine.conjugate_contact(pair, CRANK)
    h = 1e-6
    psid = (sine.pitch_point_angle(pair, fs + h) - sine.pitch_point_angle(pair, fs - h)) / (2 * h)
    k = sine.kinematics_at(pair, CRANK, fs, om, pair.ring_teeth / pair.planet_teeth / psid)
    U, vs = m.entrainment_velocity[r, c], m.sliding_velocity[r, c]
    assert np.allclose(k.sliding_velocity, vs, rtol=1e-12, atol=1e-12 * np.max(np.abs(vs)))
    assert np.allclose(k.entrainment_velocity, U, rtol=1e-8, atol=1e-8 * np.max(np.abs(U)))
    assert np.allclose(k.planet_point.T, m.point[r, c], rtol=0, atol=1e-15)
    rr, cc = np.where(~np.isfinite(m.gap))
    j0 = np.round(CRANK * pair.ring_teeth / (2 * math.pi)).astype(int)
    tooth = j0[rr] - sine.DEFAULT_CANDIDATES + cc // 2
    ap = sine.closest_approach(pair, CRANK[rr], tooth, np.where(cc % 2, 1, -1))
    assert not np.any(ap.own)
    k = sine.kinematics_at(pair, CRANK[rr], ap.phi_planet, om)
    U, vs = m.entrainment_velocity[rr, cc], m.sliding_velocity[rr, cc]
    assert np.allclose(k.sliding_velocity, vs, rtol=1e-12, atol=1e-12 * np.max(np.abs(vs)))
    assert np.allclose(k.entrainment_velocity, U, rtol=1e-12, atol=1e-12 * np.max(np.abs(U)))


@pytest.mark.parametrize("pair", PAIRS, ids=IDS)
def test_kinematics_at_arbitrary_point_against_finite_differences(pair):
    """Off the conjugate contact, moving along the planet at chosen rates (0, 0.5, -1.3
    per unit crank angle): the rolling speeds agree with central differences of the planet
    point and of its foot on the ring over the crank angle (h = 1e-7 rad; 1e-5 relative:
    the foot points move with the Newton tolerance 1e-12 rad), and the sliding speed is
    that of a rotation about the pitch point P, omega_planet k x (K - P) (1e-12
    relative)."""
    om = 3.0
    pitch = 2 * math.pi / pair.ring_teeth
    chi = np.array([0.1, 0.45, 0.8]) * pitch
    phi = (sine.conjugate_contact(pair, chi)
           + np.array([0.3, -0.5, 0.7]) * math.pi / pair.planet_teeth)
    rate = np.array([0.0, 0.5, -1.3])
    h = 1e-7
    k = sine.kinematics_at(pair, chi, phi, om, rate)
    kp, km = (sine.kinematics_at(pair, chi + s, phi + rate * s, om, rate) for s in (h, -h))
    assert np.all(k.gap > 0)
    v_pl = (kp.planet_point - km.planet_point) / (2 * h) * om
    v_ring = (kp.ring_point - km.ring_point) / (2 * h) * om
    KP = k.planet_point - sine.pitch_point(pair, chi)
    v_mat = om * sine.planet_rotation(pair, 1.0) * np.stack([-KP[1], KP[0]])
    t = np.stack([-k.normal[1], k.normal[0]])
    u1 = np.sum((v_pl - v_mat) * t, axis=0)
    u2 = np.sum(v_ring * t, axis=0)
    U = k.entrainment_velocity
    assert np.allclose(U, 0.5 * (u1 + u2), rtol=1e-5, atol=1e-5 * np.max(np.abs(U)))
    vs = np.sum(v_mat * t, axis=0)
    assert np.allclose(k.sliding_velocity, vs, rtol=1e-12, atol=1e-12 * np.max(np.abs(vs)))


def test_foot_point_is_the_foot_of_the_perpendicular():
    """foot_point: K - X(phi_ring) is along the ring normal (1e-15 m, rounding) and its
    length is |gap|; inside the ring's material the gap is negative."""
    phi = np.linspace(-0.2, 0.3, 9)
    c = sine.ring_curve(PROTO, phi)
    n = np.stack([-c.d1[1], c.d1[0]]) / np.hypot(*c.d1)
    off = np.linspace(-20e-6, 20e-6, 9)
    K = c.point + off * n
    f2, gap = sine.foot_point(PROTO, K)
    X = sine.ring_profile(PROTO, f2)
    assert np.max(np.abs(K - X - gap * n)) < 1e-15
    assert np.allclose(gap, off, rtol=1e-9, atol=1e-15)


def test_mesh_repeats_after_one_tooth_pitch():
    """meshing(chi + 2 pi/z2) is meshing(chi) turned by 2 pi/z2 with the planet tooth index
    advanced by one (exact symmetry: gaps to 1e-15 m, rounding; points to 1e-13 m, the
    Newton tolerance 1e-12 rad times |p'| = 0.036 m; other fields 1e-9 relative)."""
    chi = np.linspace(0, PITCH, 7)[:-1] + 0.001
    a, b = sine.meshing(PROTO, chi), sine.meshing(PROTO, chi + PITCH)
    assert np.array_equal(b.contact_id, (a.contact_id + 1) % 79)
    fin = np.isfinite(a.gap)
    assert np.array_equal(fin, np.isfinite(b.gap))
    assert np.max(np.abs(a.gap[fin] - b.gap[fin])) < 1e-15
    c, s = math.cos(PITCH), math.sin(PITCH)
    turned = np.stack([c * a.point[..., 0] - s * a.point[..., 1],
                       s * a.point[..., 0] + c * a.point[..., 1]], axis=-1)
    assert np.max(np.abs(turned - b.point)) < 1e-13
    for f in ("moment_arm", "pressure_angle", "sliding_velocity", "entrainment_velocity"):
        x, y = getattr(a, f)[fin], getattr(b, f)[fin]
        assert np.allclose(x, y, rtol=1e-9, atol=1e-12 * np.max(np.abs(x))), f


def test_transmission_ratio():
    """Rigid-body ratio: the planet turns -(z2 - z1)/z1 of a turn per crank turn (-1/79:
    ratio -79, as train.khv_ratio). The sign is the rolling condition: the planet's
    velocity at the pitch point, by central differences of its pose (h = 1e-6 rad), is
    zero (1e-12 m/s per rad/s: truncation h^2); the opposite sign would give 2 a0."""
    assert math.isclose(sine.planet_rotation(PROTO, 2 * math.pi), -2 * math.pi / 79,
                        rel_tol=1e-15)
    ratio = 2 * math.pi / sine.planet_rotation(PROTO, 2 * math.pi)
    assert math.isclose(ratio, -79, rel_tol=1e-14)
    assert math.isclose(ratio, train.khv_ratio(79, 80), rel_tol=1e-12)
    chi, h = 0.7, 1e-6
    P = sine.pitch_point(PROTO, chi)[:, 0]
    c0, t0 = sine.planet_pose(PROTO, chi)
    local = np.array([[math.cos(-t0[0]), -math.sin(-t0[0])],
                      [math.sin(-t0[0]), math.cos(-t0[0])]]) @ (P - c0[:, 0])

    def where(x):
        c, t = sine.planet_pose(PROTO, x)
        rot = np.array([[math.cos(t[0]), -math.sin(t[0])], [math.sin(t[0]), math.cos(t[0])]])
        return c[:, 0] + rot @ local

    v = (where(chi + h) - where(chi - h)) / (2 * h)
    assert np.hypot(*v) < 1e-12
    # and the conjugate contact crosses exactly z2 planet teeth per crank turn
    f = sine.conjugate_contact(PROTO, np.array([0.3, 0.3 + 2 * math.pi]))
    assert math.isclose(f[1] - f[0], 2 * math.pi * 80 / 79, rel_tol=1e-12)


# ---------------------------------------------------------------------------------------
# the seed's closed forms
def test_seed_pressure_angles_eqs_8_to_14():
    """Eqs. (8)-(10) give the numerical alpha_k1 (angle between the contact normal and the
    perpendicular to O1K) to 1e-12 rad (rounding). Eq. (13) with arccos gives zeta; the
    corrected Eq. (14), alpha_k1 - s zeta (s = +1 where angle O1-K-P is acute), matches the
    numerical alpha_k2 to 1e-7 rad (arccos near 1 keeps only ~sqrt(eps) = 1.5e-8 rad when
    zeta -> 0); as printed (s = +1 everywhere) it is off by up to 2 zeta = 1.1e-4 rad."""
    chi = np.linspace(0, PITCH, 201)
    phi = sine.conjugate_contact(PROTO, chi)
    a1, a2 = sine.pressure_angles(PROTO, phi)
    seed = sine.seed_pressure_angles(PROTO, phi)
    m = sine.meshing(PROTO, chi)
    r, c = _conj_columns(m)
    assert np.max(np.abs(seed.alpha_k1 - a1)) < 1e-12
    assert np.max(np.abs(m.pressure_angle[r, c] - a1)) < 1e-12
    assert np.allclose(seed.r_k1, np.hypot(*(m.point[r, c] - m.centre).T), rtol=1e-14)
    assert np.max(np.abs(seed.alpha_k2 - a2)) < 1e-7
    printed_err = np.abs(seed.alpha_k2_printed - a2)
    assert printed_err.max() > 1e-4
    assert np.max(printed_err[seed.sign > 0]) < 1e-7
    # s = +1 is the addendum side of the planet (r_k1 > r1) apart from a sliver
    agree = (seed.sign > 0) == (seed.r_k1 > PROTO.planet_pitch_radius_m)
    assert agree.mean() > 0.9
    # the pressure angle at the contact runs from 90 deg (tip/root) down to ~48.9 deg
    assert math.isclose(math.degrees(a1.max()), 90.0, abs_tol=0.01)
    assert 48.0 < math.degrees(a1.min()) < 50.0


def test_tooth_height_limits_match_closed_forms():
    """For z2 - z1 = 1 the planet tips meet the ring tips opposite the pitch point at
    a = a0 = m/2 (radial clearance 2(a0 - a)), and the contact path stops advancing at the
    tip when a = m/2: d psi/d phi = 1 - (2a/m)^2 there. Bisection tolerance 1e-9 m plus
    the interference threshold 1e-11 m (half of it in a)."""
    lim = sine.tooth_height_limits(79, 80, 0.9e-3)
    assert abs(lim.contact - 0.45e-3) < 2e-12
    assert abs(lim.interference - 0.45e-3) < 1e-11
    assert lim.envelope > 4 * lim.max
    assert sine.max_tooth_height_m(PROTO) == lim.max
    psid_tip = 80 / 79 * (sine.contact_crank_angle(PROTO, 1e-7)
                                - sine.contact_crank_angle(PROTO, -1e-7)) / 2e-7
    assert math.isclose(psid_tip, 1 - (0.8 / 0.9) ** 2, rel_tol=1e-7)


# ---------------------------------------------------------------------------------------
# refusals: each rule names the parameter, the value and the bound
BASE = dict(planet_teeth=79, ring_teeth=80, module_m=0.9e-3, tooth_height_m=0.4e-3,
            face_width_m=8e-3)
RULES = [
    ({"planet_teeth": 79.5}, "planet_teeth = 79.5 must be an integer"),
    ({"planet_teeth": 9, "ring_teeth": 10},
     "planet_teeth = 9 is outside the valid range [10, inf)"),
    ({"ring_teeth": 79}, "ring_teeth = 79 is outside the valid range [80, inf)"),
    ({"module_m": 0.0}, "module_m = 0.0 is outside the valid range (0, inf)"),
    ({"face_width_m": -0.008}, "face_width_m = -0.008 is outside the valid range (0, inf)"),
    ({"tooth_height_m": 0.0}, "tooth_height_m = 0.0 is outside the valid range (0, 0.03555)"),
    ({"tooth_height_m": 0.04}, "tooth_height_m = 0.04 is outside the valid range (0, 0.03555)"),
]


@pytest.mark.parametrize("change, message", RULES,
                         ids=[m.split(" ")[0] + "-" + str(i) for i, (_, m) in enumerate(RULES)])
def test_simple_rules_refused(change, message):
    with pytest.raises(GeometryError) as info:
        sine.SineGearPair(**{**BASE, **change})
    assert message in str(info.value)


@pytest.mark.parametrize("change, which, words", [
    ({"tooth_height_m": 0.0025}, "envelope", "cusped or self-intersecting"),
    ({"tooth_height_m": 0.0005}, "interference", "interfere with the ring"),
    ({"ring_teeth": 80, "planet_teeth": 78, "tooth_height_m": 0.0005}, "contact",
     "contact path would reverse"),
], ids=["cusp", "interference", "contact-reversal"])
def test_tooth_height_rules_refused_with_numerical_bound(change, which, words):
    """Each numerical rule on the tooth height fires on its own (the others hold below their
    bounds): a = 2.5 mm cusps the 79/80 ring (bound 2.117 mm), a = 0.5 mm makes the 79/80
    tips collide opposite the pitch point (bound a0 = 0.45 mm), and for 78/80 a = 0.5 mm
    lies below the interference bound (0.716 mm) but reverses the contact path (m/2)."""
    kw = {**BASE, **change}
    lim = sine.tooth_height_limits(kw["planet_teeth"], kw["ring_teeth"], kw["module_m"])
    bound = getattr(lim, which)
    with pytest.raises(GeometryError) as info:
        sine.SineGearPair(**kw)
    msg = str(info.value)
    assert f"tooth_height_m = {kw['tooth_height_m']:g} is outside the valid range" in msg
    assert f"(0, {bound:.6g})" in msg
    assert words in msg
    # just below the bound the same pair is accepted, except where an earlier rule binds
    if which != "envelope":
        sine.SineGearPair(**{**kw, "tooth_height_m": 0.999 * bound})
