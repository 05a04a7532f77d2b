"""The rotation modification and the disc's two flanks (issue 28): exact and first-order gaps
of every pin, the disc before load (backlash, interference), and the cycle and detailed
modes on every modification.

The physics the tests hold to: a rotation modification Delta delta turns each flank by
Delta delta about the disc centre (toward its tooth centre for Delta delta > 0: the disc is
the intersection of the two turned profiles; away for < 0: their union). On the loaded
flank that is a rigid turn, so the load sharing equals the unmodified disc's, the
transmission error shifts by Delta delta and the backlash grows by both flanks' closing
rotations, 2 Delta delta (docs/derivations.md 8).
"""
import dataclasses
import math

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from toothfem.geometry.vectors import rotate
from toothfem import load_case
from toothfem.fem import cycloid_fe as cf
from toothfem.fem.deviations import CycloidDeviation
from toothfem.fem.drives import drive_for
from toothfem.geometry import cycloid as cy, cycloid_backlash as cyb, cycloid_mesh as cym
from toothfem.geometry import cycloid_distance as cyd
from toothfem.derived import derived

ARCSEC = math.pi / (180 * 3600)


@pytest.fixture(scope="module")
def case(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


@pytest.fixture(scope="module")
def drive(case):
    return drive_for(case)


@pytest.fixture(scope="module")
def base(drive):
    return drive.fe_model(pin_structure="conventional")


def _with(model, **mods):
    return dataclasses.replace(model, geometry=dataclasses.replace(model.geometry, **mods))


def _geometry(**mods):
    return cy.CycloidGeometry(40, 0.100, 0.001, 0.002, **mods)


# ---------------------------------------------------------------------------------------
# Geometry: gaps of every pin on both flanks

@pytest.mark.parametrize("deg", [0.05, 0.1, -0.05, -0.1])
def test_loaded_flank_gap_is_the_rigid_turn(deg):
    """The flank that carries a torque of sign s is the unmodified profile turned by
    -s Delta delta: linearised about the pose where it is turned back, every pin on it has
    g0 = Delta delta |l| exactly (unmodified pins touch the theoretical profile), except
    near the tooth tip and root (|l| < r_a/4 here), where the other turned flank cuts the
    corner off (Delta delta > 0: the gap is larger, by 1.2 um at the tip for 0.05 deg) or
    covers it (< 0: smaller)."""
    d = math.radians(deg)
    g = _geometry(rotation_rad=d)
    phi = np.linspace(0, 2 * math.pi / 40, 5, endpoint=False)
    arm = cym.meshing(g, phi).moment_arm
    for s in (1, -1):
        g0 = cym.clearance_exact(g, phi, s)
        own = s * arm < -0.25 * g.disc_pitch_radius_m
        np.testing.assert_allclose(g0[own], d * np.abs(arm[own]), rtol=0, atol=1e-12)
        tip = (s * arm < 0) & ~own
        assert np.all(math.copysign(1, d) * (g0[tip] - d * np.abs(arm[tip])) >= -1e-12)


def _polygon_distance(g, points, samples_per_lobe=4000):
    """Brute force: the disc as a densely sampled polygon, the turned profiles intersected
    (Delta delta > 0) or united (< 0); distance of each point from its boundary."""
    psi = np.linspace(0, 2 * math.pi, g.lobe_count * samples_per_lobe, endpoint=False)
    w = cy.working_profile(g.generating(), psi)
    turned = [Polygon(rotate(w, a).T) for a in (g.rotation_rad, -g.rotation_rad)]
    disc = turned[0].intersection(turned[1]) if g.rotation_rad > 0 else \
        turned[0].union(turned[1])
    return np.array([disc.exterior.distance(Point(*p)) for p in points.T])


@pytest.mark.parametrize("deg", [0.05, -0.05, 0.5])
def test_distance_from_the_modified_disc_against_a_polygon(deg):
    """Exact distance from the intersection (union) of the turned profiles, corners at the
    tooth tips and roots included, against a polygon of 4000 samples per lobe (chord sag
    ds^2/(8 rho) ~ 2 nm on the 4.4 mm root: tolerance 5 nm), at the nominal pose and
    turned either way."""
    g = _geometry(equidistant_m=5e-6, rotation_rad=math.radians(deg))
    phi = np.array([0.0, 0.07])
    for turn in (0.0, g.rotation_rad, -g.rotation_rad):
        exact = cym.clearance_at(g, phi, turn) + g.pin_radius_m
        c = np.broadcast_to(cym.pin_centres(g)[:, None, :], (2, 2, 40))
        local = rotate(cym.to_disc_frame(g, phi, c).reshape(2, -1), -turn)
        ref = _polygon_distance(g, local).reshape(2, 40)
        assert np.max(np.abs(exact - ref)) < 5e-9, (deg, turn)


MODS = [dict(equidistant_m=10e-6), dict(move_distance_m=-10e-6),
        dict(equidistant_m=-5e-6, move_distance_m=-10e-6),
        dict(rotation_rad=2e-4), dict(rotation_rad=-2e-4),
        dict(equidistant_m=10e-6, move_distance_m=-5e-6, rotation_rad=1e-4),
        dict(equidistant_m=20e-6, rotation_rad=-2e-4),
        dict(equidistant_m=10e-6, move_distance_m=5e-6, rotation_rad=-1e-4)]


def _ids(m):
    return ",".join(f"{k.split('_')[0]}={v:g}" for k, v in m.items())


@pytest.mark.parametrize("mods", MODS, ids=_ids)
def test_exact_gaps_of_every_pin_against_the_first_order(mods):
    """Every pin on both flanks (own-flank linearisation, ``side=0``) against the
    first-order D0 = Delta rz - Delta Rz (1 - K1 cos theta)/sqrt(S) + Delta delta |l|
    (docs/derivations.md C6): the difference is second order, a quarter of the
    modification leaves 1/16 of it (measured 1/13-1/19 across the pins' worst; the tip and
    root corners are second order by themselves)."""
    phi = np.linspace(0, 2 * math.pi / 40, 4, endpoint=False)
    errs = []
    for scale in (1.0, 0.25):
        g = _geometry(**{k: v * scale for k, v in mods.items()})
        theta = np.mod(2 * math.pi * np.arange(40)[None, :] / 40 - phi[:, None], 2 * math.pi)
        d0 = cyb.clearance_closed_form(g, theta)[0]
        exact = cym.clearance_exact(g, phi, 0)
        errs.append(np.max(np.abs(exact - d0)))
        assert errs[-1] < 0.05 * np.max(np.abs(d0)) + 1e-12
    if errs[0] > 1e-12:            # an equidistant modification alone is exact
        assert 10 < errs[0] / errs[1] < 22


def test_before_load_backlash_and_interference():
    """Rotation alone: backlash 2 Delta delta exactly (both flanks' closing rotations), no
    interference; a negative rotation beyond the equidistant clearance: both flanks
    closed, the interference and its pins named on both flanks."""
    phi = np.linspace(0, 2 * math.pi / 40, 12, endpoint=False)
    d = math.radians(0.05)
    b = cyb.before_load(_geometry(rotation_rad=d), phi)
    assert b["backlash_min_arcmin"] == pytest.approx(2 * 0.05 * 60, rel=1e-9)
    assert b["interference_before_load_um"] == 0 and not b["interference_pins"]
    none = cyb.before_load(_geometry(), phi)
    assert none["backlash_max_arcmin"] == 0 and none["clearance_before_load_um"] == 0
    b = cyb.before_load(_geometry(equidistant_m=5e-6, rotation_rad=-math.radians(0.02)), phi)
    assert b["backlash_min_arcmin"] is None
    # first order: 5 um - 0.02 deg x the largest arm (about 34 mm) = -6.9 um
    assert 5 < b["interference_before_load_um"] < 10
    assert set(b["interference_flanks"]) == {"+", "-"}


def test_check_reports_the_clearance_before_load(cases_dir):
    """``toothfem check`` (derived): the backlash of both flanks from the exact gaps, its
    first-order value beside, and interference named with a warning."""
    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    c = dataclasses.replace(case, cycloid=dataclasses.replace(
        case.cycloid, rotation_modification_deg=0.05))
    d = derived(c)
    assert d["disc_backlash_min_arcmin"] == pytest.approx(6.0, rel=1e-6)
    # the reducer's, input held: the cranks turn (1 + 9/27) times the output angle
    assert d["backlash_min_arcmin"] == pytest.approx(6.0 * 39 / (40 + 1 / 3), rel=1e-6)
    assert d["backlash_first_order_arcmin"] == pytest.approx(6.0 * 39 / (40 + 1 / 3),
                                                             rel=1e-9)
    assert d["interference_before_load_um"] == 0
    bad = dataclasses.replace(case, cycloid=dataclasses.replace(
        case.cycloid, equidistant_modification_mm=0.005, rotation_modification_deg=-0.02))
    d = derived(bad)
    assert d["interference_before_load_um"] > 5 and "(+)" in d["interference_pins"]
    assert any("interferes" in w for w in d["warnings"])


# ---------------------------------------------------------------------------------------
# Cycle mode

@pytest.fixture(scope="module")
def unmodified_cycle(base, drive, fe_cache):
    """The unmodified disc at two positions, per flank layout (both sides' tables, one set
    of both flanks): its tables and its solutions at +-T, the reference of every rotation
    below (built once for them all)."""
    phis = drive.positions(36)[[0, 13]]
    torque = drive.member_torque(167.0)
    ref = {}
    for sides in ((1, -1), (0,)):
        solver = cf.CycleSolver(base, phis, sides=sides, cache=fe_cache)
        tables = solver.tables()
        ref[sides] = tables, {t: solver.solve(t) for t in (torque, -torque)}
    return phis, torque, ref


@pytest.mark.parametrize("deg", [0.05, 0.1])
def test_cycle_mode_rotation_is_a_rigid_turn(base, unmodified_cycle, deg):
    """Rotation alone: the unmodified load sharing and the transmission error shifted by
    Delta delta, for both torque signs and for the solver of both flanks at once. The
    tables are the same; the forces differ only through the pin at the tooth tip (3-4 N
    unmodified), which the corner of the two turned flanks leaves 1.2 um (0.05 deg) or
    4.8 um (0.1 deg) off: the other pins within 1e-3 of the largest force, the TE within
    0.01 arcsec."""
    phis, torque, ref = unmodified_cycle
    mod = _with(base, rotation_rad=math.radians(deg))
    for sides in ((1, -1), (0,)):
        tables, solved = ref[sides]
        new = cf.CycleSolver(mod, phis, sides=sides)
        new.adopt(tables)
        for t in (torque, -torque):
            a, b = solved[t], new.solve(t)
            flank = np.abs(a.moment_arm) > 0.1 * base.geometry.disc_pitch_radius_m
            np.testing.assert_allclose(b.force[flank], a.force[flank], rtol=0,
                                       atol=1e-3 * a.force.max())
            assert b.force.max() == pytest.approx(a.force.max(), rel=1e-3)
            np.testing.assert_allclose(b.transmission_error - a.transmission_error,
                                       math.copysign(math.radians(deg), t),
                                       atol=0.01 * ARCSEC)


def test_the_derivations_result_line_is_computed(base, drive, fe_cache):
    """docs/derivations.md 8's result line (pins, F_max and the TE at 0.05 and 0.1 deg, at
    the seed's 91.85 N m on the disc) computed here, so the doc cannot drift from the code:
    to its printed digits."""
    import re
    from pathlib import Path
    text = (Path(__file__).resolve().parents[1] / "docs" / "derivations.md").read_text()
    m = re.search(r"give the unmodified (\d+)\s+pins and F_max ([\d.]+) N, TE ([\d.]+) and "
                  r"([\d.]+) arcsec \(unmodified ([\d.]+) \+ 180 and 360\)", text)
    assert m, "docs/derivations.md 8: the result line moved"
    # one position (its own disc mesh: a solver of more positions meshes their zones too
    # and moves F_max by 0.2 %, docs/fem.md's known sensitivity)
    phis = drive.positions(36)[:1]
    tables = cf.CycleSolver(base, phis, sides=(0,), cache=fe_cache).tables()
    for deg, te_doc in ((0.0, m[5]), (0.05, m[3]), (0.1, m[4])):
        solver = cf.CycleSolver(_with(base, rotation_rad=math.radians(deg)), phis,
                                sides=(0,))
        solver.adopt(tables)
        r = solver.solve(91.85)
        assert int(np.sum(r.force[0] > 0)) == int(m[1])
        assert round(float(r.force[0].max()), 2) == float(m[2])
        assert round(float(r.transmission_error[0]) / ARCSEC, 3) == float(te_doc)


# ---------------------------------------------------------------------------------------
# Detailed mode against the cycle mode

#: The cycle and detailed modes agree on the largest pin force within 2 % (docs/fem.md:
#: 0.7 % measured on the unmodified disc; issue 28 measured 0.0-1.3 % over MODS_FE) and on
#: the transmission error within 0.3 arcsec.
MODES_RTOL, TE_ATOL = 0.02, 0.3 * ARCSEC

#: Each kind of modification alone and all three together (the suite's time: the pairs
#: equidistant + move-distance and equidistant + rotation, and the 0.05 deg rotation, agreed
#: as well when issue 28 landed and are covered by the exact-gap tests above).
MODS_FE = [dict(), dict(rotation_rad=math.radians(0.1)), dict(equidistant_m=10e-6),
           dict(move_distance_m=-10e-6),
           dict(equidistant_m=10e-6, move_distance_m=-5e-6, rotation_rad=math.radians(0.02))]


@pytest.mark.slow
@pytest.mark.parametrize("mods", MODS_FE, ids=_ids)
def test_cycle_and_detailed_agree_on_every_modification(base, drive, mods, fe_cache):
    """One position, both torque signs: the same pins carry load, the largest force within
    MODES_RTOL, the TE within TE_ATOL; with a rotation the TE is the unmodified one shifted
    by the rotation in both modes (the must-show of issue 28). At the seed's disc torque
    1.1 x 167/2 = 91.85 N m, where issue 28 measured: at the power flow's 88.81 N m the
    detailed mode's largest force at the 0.1 deg rotation jumps to 251.6 N (250.4 N at
    91.85 N m, against the cycle mode's 242.4 N: +3.8 %), the detailed mode's known
    sensitivity of one pin's force to its meshing of the turned flank (issue 28's note),
    left open."""
    phi = drive.positions(36)[13]
    torque = 1.1 * 167.0 / 2
    model = _with(base, **mods)
    solver = cf.CycleSolver(model, np.array([phi]), sides=(1, -1), cache=fe_cache)
    for t in (torque, -torque):
        c = solver.solve(t)
        d = cf.solve_detailed(model, phi, t).load_sharing
        assert np.array_equal(c.force[0] > 0, d.force[0] > 0) or \
            np.sum(np.abs((c.force[0] > 0).astype(int) - (d.force[0] > 0))) <= 1
        assert d.force.max() == pytest.approx(c.force.max(), rel=MODES_RTOL)
        assert abs(d.transmission_error[0] - c.transmission_error[0]) < TE_ATOL


@pytest.mark.slow
def test_detailed_rotation_keeps_the_unmodified_load_sharing(base, drive):
    """The issue's must-show in the detailed mode: 0.05 and 0.1 deg, largest pin force and
    pins in contact equal to the unmodified design's within 2 %, TE shifted by the
    rotation (within 0.3 arcsec)."""
    phi = drive.positions(36)[0]
    torque = drive.member_torque(167.0)
    ref = cf.solve_detailed(base, phi, torque).load_sharing
    for deg in (0.05, 0.1):
        d = cf.solve_detailed(_with(base, rotation_rad=math.radians(deg)), phi,
                              torque).load_sharing
        assert d.force.max() == pytest.approx(ref.force.max(), rel=0.02)
        assert np.sum(d.force > 0) == np.sum(ref.force > 0)
        assert (d.transmission_error[0] - ref.transmission_error[0]) == pytest.approx(
            math.radians(deg), abs=0.3 * ARCSEC)


@pytest.mark.slow
def test_both_flanks_with_idle_flank_interference(base, drive, fe_cache):
    """A built stage whose idle flank interferes (two idle pins grown by 2 um, the rest
    moved in a 5 um zone): the cycle mode with every pin a candidate (sides=(0,)) and the
    detailed mode on both flanks load the same pins, idle ones included, and agree on the
    largest force within MODES_RTOL."""
    phi = drive.positions(36)[0]
    torque = drive.member_torque(167.0)
    rng = np.random.default_rng(5)
    radius = np.zeros(40)
    radius[[28, 31]] = 2e-6                       # idle flank at this position (arm > 0)
    dev = CycloidDeviation(pin_offset=rng.normal(0, 5e-6 / 6, (2, 40)), pin_radius=radius,
                           profile=np.zeros((39, 2)), member_offset=np.zeros(2))
    c = cf.CycleSolver(base, np.array([phi]), sides=(0,), cache=fe_cache).solve(
        torque, deviation=dev)
    d = cf.solve_detailed(base, phi, torque, deviation=dev, flanks="both",
                          force_margin=8).load_sharing
    arm = c.moment_arm[0]
    assert np.all(c.force[0][[28, 31]] > 0) and np.all(arm[[28, 31]] > 0)
    assert np.array_equal(c.force[0] > 0, d.force[0] > 0)
    assert d.force.max() == pytest.approx(c.force.max(), rel=MODES_RTOL)


@pytest.mark.slow
def test_contact_names_the_preload_and_refuses_what_cannot_be_assembled(cases_dir):
    """Issue 28 item 3: an interfering disc's preload before any load (the system model at
    a vanishing torque, every pin of both flanks a candidate) is in the contact summary; a
    P_h above the contact-fatigue limit (ISO 281, 1500 MPa) is a warning, above the static
    limit (ISO 76, 4000 MPa) a refusal naming the limit and its key. Pin-housing drive,
    rotation modification -0.01 deg (6.8 um of interference): 1322 N, 1698 MPa;
    -0.05 deg: P_h above 4000 MPa."""
    import warnings as w

    from toothfem.errors import CaseError
    from toothfem.pipeline import contact_analysis

    case = load_case(cases_dir / "cycloid_pinhousing.toml")

    def rotated(deg):
        return dataclasses.replace(case, cycloid=dataclasses.replace(
            case.cycloid, rotation_modification_deg=deg))
    with w.catch_warnings(record=True) as caught:
        w.simplefilter("always")
        res = contact_analysis(rotated(-0.01), positions=12, field="none")
    s = res.summary
    assert s["interference_before_load_um"] == pytest.approx(6.806, abs=0.01)
    assert 1000 < s["preload_force_max_N"] < 2000
    assert 1500 < s["preload_ph_max_MPa"] < 4000
    assert any("contact-fatigue limit 1500 MPa (ISO 281" in str(c.message) for c in caught)
    with pytest.raises(CaseError, match=r"static limit 4000 MPa \(ISO 76:2006, "
                                        r"material.static_contact_stress_MPa\)"):
        contact_analysis(rotated(-0.05), positions=12, field="none")


@pytest.mark.slow
@pytest.mark.parametrize("sign", [1, -1])
def test_detailed_large_rotation_leaves_the_tip_corner_pins_unloaded(base, drive, fe_cache,
                                                                     sign):
    """Issue 41: at a 1 deg rotation modification the detailed mode loaded pins 17-19
    (62/43/19 N at crank angle 0) that face the tip corner where the two turned flanks
    meet, 36-319 um clear of the exact intersection; their contact points were projected
    on the whole turned profile. Now only the part that bounds the disc is searched
    (flanks.bounds_disc): the same pins carry load as in the cycle mode (exact gaps),
    the largest force within MODES_RTOL, the TE within TE_ATOL."""
    phi = drive.positions(36)[0]
    torque = sign * drive.member_torque(167.0)
    model = _with(base, rotation_rad=math.radians(1.0))
    c = cf.CycleSolver(model, np.array([phi]), sides=(1, -1), cache=fe_cache).solve(torque)
    d = cf.solve_detailed(model, phi, torque).load_sharing
    assert np.array_equal(c.force[0] > 0, d.force[0] > 0)
    assert d.force.max() == pytest.approx(c.force.max(), rel=MODES_RTOL)
    assert abs(d.transmission_error[0] - c.transmission_error[0]) < TE_ATOL


def test_bounds_disc_marks_the_corner_side_of_each_turned_flank():
    """flanks.bounds_disc: on a disc turned by +-1 deg (intersection), a foot point just
    past a half-lobe's symmetry line on the profile that does not bound that half-lobe is
    off the disc; at the middle of the half-lobe, on the profile that bounds it, on it.
    Without a rotation every foot point bounds the disc."""
    from toothfem.fem.cycloid_fe import flanks as fl

    g = _geometry(rotation_rad=math.radians(1.0))
    alpha, own = fl.half_lobe_turns(g)
    assert set(np.round(own / g.rotation_rad).astype(int)) == {-1, 1}
    step = alpha[1]
    for k in (0, 1):
        a = float(own[k])
        mid = cyd.polar_parameter(g.generating(), np.array([alpha[k] + 0.5 * step - a]))
        wrong = cyd.polar_parameter(g.generating(), np.array([alpha[k] + 0.5 * step + a]))
        for side in (1, -1):
            pose = fl.frame_turn(g, side)
            assert fl.bounds_disc(g, side, mid, [a + pose])[0]
            assert not fl.bounds_disc(g, side, wrong, [-a + pose])[0]
    plain = _geometry()
    assert fl.bounds_disc(plain, 1, np.linspace(0, 6, 7), np.zeros(7)).all()
