"""The face width in slices (issue 43; fem/cycloid_fe/slices.py, docs/face_width.md).

Facts: with no tilt and no crown every slice carries the planar problem per unit length,
so n slices give the planar forces and P_h on every cycloid layout and pin structure; a
tilt moves the load to one edge (the peak P_h rises), a crown under it brings it back
towards the middle; a tilt of the opposite sign mirrors the slices; the slices' forces
keep the torque balance; the crown's forms have their drop at the edges.
"""
import math

import numpy as np
import pytest

from toothfem.case import parse_case_text
from toothfem.errors import CaseError, ToothfemError
from toothfem.face_width import face_of, sliced_contact
from toothfem.fem.cycloid_fe.slices import FaceSpec, solve_sliced
from toothfem.fem.drives import drive_for

ARCMIN = math.pi / 180 / 60
#: The pin-housing case at 36 positions: the issue's "must show" figures.
POSITIONS = 36


def _case(cases_dir, name, **keys):
    """A shipped case with [cycloid] keys added."""
    text = (cases_dir / name).read_text()
    extra = "".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in keys.items())
    text = text.replace("[cycloid]\n", "[cycloid]\n" + extra, 1)
    return parse_case_text(text)


@pytest.fixture(scope="module")
def pinhousing(cases_dir):
    case = _case(cases_dir, "cycloid_pinhousing.toml")
    drive = drive_for(case)
    solver = drive.cycle_solver(POSITIONS)
    torque = drive.member_torque(case.operating.output_torque_Nm)
    return solver, torque, solver.solve(torque)


@pytest.mark.parametrize("name, pins", [("cycloid_pinhousing.toml", None),
                                        ("cycloid_pinhousing.toml", "conventional"),
                                        ("cycloid_khv.toml", None)])
def test_nine_straight_slices_are_the_planar_model(cases_dir, name, pins):
    """RV (integral housing, conventional pins) and K-H-V: 9 slices without tilt or crown
    give the planar F_max and P_h. The issue asks for 1 %; the slices solve the planar
    problem per length in one system, so they agree to the Hertz iteration's tolerance
    (1e-9): 1e-7 is asserted."""
    case = _case(cases_dir, name)
    drive = drive_for(case)
    solver = drive.cycle_solver(4, **({} if pins is None else {"pin_structure": pins}))
    torque = drive.member_torque(case.operating.output_torque_Nm)
    planar = solver.solve(torque)
    sliced = solve_sliced(solver, FaceSpec(9), torque)
    ls = sliced.load_sharing
    assert ls.force == pytest.approx(planar.force, rel=1e-7, abs=1e-9 * planar.force.max())
    assert ls.ph.max() == pytest.approx(planar.ph.max(), rel=1e-7)
    assert ls.transmission_error == pytest.approx(planar.transmission_error, rel=1e-7)
    assert sliced.edge_figures()["peak_ph_z_mm"] == 0.0      # uniform: the middle named
    # each slice carries a ninth of each pin's force
    assert sliced.force == pytest.approx(np.broadcast_to(planar.force / 9, sliced.force.shape),
                                         rel=1e-7, abs=1e-9 * planar.force.max())


def test_tilt_raises_the_peak_and_a_crown_lowers_it(pinhousing):
    """The issue's must-show on the pin-housing case, 9 slices, 36 positions: 3 arcmin of
    tilt raise the straight disc's peak P_h by more than 10 % (measured +69 %: 658 ->
    1113 MPa, the peak at the loaded edge); an 8 um circular crown under the same tilt
    lowers it (1007 MPa) and moves the peak off the edge."""
    solver, torque, planar = pinhousing
    tilt = solve_sliced(solver, FaceSpec(9, tilt_rad=3 * ARCMIN), torque)
    crown = solve_sliced(solver, FaceSpec(9, tilt_rad=3 * ARCMIN, crown_m=8e-6), torque)
    p0, p1, p2 = planar.ph.max(), tilt.load_sharing.ph.max(), crown.load_sharing.ph.max()
    assert p1 > 1.10 * p0
    assert p2 < p1
    assert tilt.edge_figures()["peak_ph_z_mm"] == pytest.approx(tilt.z[-1] * 1e3)
    assert abs(crown.edge_figures()["peak_ph_z_mm"]) < abs(tilt.z[-1]) * 1e3
    assert crown.edge_figures()["edge_to_centre_ph"] < 1 < tilt.edge_figures()["edge_to_centre_ph"]
    for r in (tilt, crown):     # the torque balance holds with the slices' forces
        assert np.max(np.abs(r.load_sharing.torque_residual())) < 1e-9


def test_opposite_tilt_mirrors_the_slices(pinhousing):
    """-theta gives the slices of +theta in reverse order (the tilt's gap is odd in z)."""
    solver, torque, _ = pinhousing
    plus = solve_sliced(solver, FaceSpec(5, tilt_rad=2 * ARCMIN), torque)
    minus = solve_sliced(solver, FaceSpec(5, tilt_rad=-2 * ARCMIN), torque)
    f = plus.force.max()
    assert minus.force == pytest.approx(plus.force[::-1], abs=1e-8 * f)
    assert minus.tilt_moment == pytest.approx(-plus.tilt_moment, abs=1e-8 * f * 1e-2)


def test_logarithmic_crown_has_no_edge_peak_at_its_design_load(pinhousing):
    """Lundberg's profile for the planar F_max, at that load and no tilt: along the width
    the pressure of every contact falls from the middle to the edges (no edge peak), and
    the profile's drop at the edges is the one asked for."""
    solver, torque, planar = pinhousing
    width = solver.model.face_width
    face = FaceSpec(9, crown_m=5e-6, form="logarithmic",
                    crown_load_N_per_m=planar.force.max() / width)
    edge = face.drop(np.array([-width / 2, width / 2]), width, solver.model.e_star)
    assert edge == pytest.approx([5e-6, 5e-6], rel=1e-12)
    r = solve_sliced(solver, face, torque)
    mid = r.ph[4]
    assert np.all(r.ph[0] <= mid) and np.all(r.ph[-1] <= mid)
    assert np.all(np.diff(r.ph[4:], axis=0) <= 0)


@pytest.mark.parametrize("form", ["circular", "partial", "logarithmic"])
def test_crown_forms_drop(form):
    """Each form: 0 at the middle, c at the edges, symmetric and growing outwards; the
    partial crown flat over its middle fraction."""
    face = FaceSpec(3, crown_m=8e-6, form=form, flat_fraction=0.4, crown_load_N_per_m=2e4)
    z = np.linspace(-5e-3, 5e-3, 101)
    d = face.drop(z, 10e-3, 1.1e11)
    assert d[50] == 0 and d[0] == pytest.approx(8e-6) and d[-1] == pytest.approx(8e-6)
    assert d == pytest.approx(d[::-1], abs=1e-15)
    assert np.all(np.diff(d[50:]) >= 0)
    if form == "partial":
        assert np.all(d[np.abs(z) <= 0.2 * 10e-3] == 0)


def test_case_keys_and_their_refusals(cases_dir):
    """The [cycloid] keys reach the drive; a tilt or crown with one slice, a logarithmic
    crown without its design load and slices in the detailed mode are refused naming
    the key and its range."""
    case = _case(cases_dir, "cycloid_pinhousing.toml", face_slices=7, disc_tilt_arcmin=2.0,
                 face_crowning_um=4.0, face_crowning_form="partial")
    face = face_of(drive_for(case))
    assert (face.slices, face.form, face.crown_m) == (7, "partial", pytest.approx(4e-6))
    assert face.tilt_rad == pytest.approx(2 * ARCMIN)
    with pytest.raises(CaseError, match=r"face_slices = 1 .*valid range"):
        _case(cases_dir, "cycloid_pinhousing.toml", disc_tilt_arcmin=3.0)
    with pytest.raises(CaseError, match=r"face_crowning_load_N = None .*valid range"):
        _case(cases_dir, "cycloid_pinhousing.toml", face_slices=9, face_crowning_um=4.0,
              face_crowning_form="logarithmic")
    with pytest.raises(CaseError, match=r"face_slices = 100"):
        _case(cases_dir, "cycloid_pinhousing.toml", face_slices=100)
    with pytest.raises(CaseError, match=r"face_slices = 7 .*--mode detailed"):
        sliced_contact(drive_for(case), None, 80.0, "detailed")
    assert sliced_contact(drive_for(_case(cases_dir, "cycloid_pinhousing.toml")), None, 80.0,
                          "detailed") is None
    with pytest.raises(ToothfemError, match="face_crowning_form"):
        FaceSpec(3, form="elliptic")


def test_face_width_files(pinhousing, tmp_path):
    """face_width.csv has every slice of every loaded contact, its slice forces summing to
    the contact's force and its line loads the force over the slice width; the picture
    is written."""
    from toothfem.report.face_width import FACE_COLUMNS, write_face

    solver, torque, _ = pinhousing
    r = solve_sliced(solver, FaceSpec(9, tilt_rad=3 * ARCMIN, crown_m=8e-6), torque)
    files = write_face(r, tmp_path, "pin-housing")
    assert files == ["face_width.csv", "face_width.png"]
    rows = np.genfromtxt(tmp_path / "face_width.csv", delimiter=",", names=True)
    assert tuple(rows.dtype.names) == FACE_COLUMNS
    ls = r.load_sharing
    assert rows.size == 9 * int(np.sum(ls.force > 0))
    first = rows[rows["position_deg"] == rows["position_deg"][0]]
    pin = int(first["contact_id"][0])
    c = int(np.flatnonzero(ls.contact_id[0] == pin)[0])
    mine = first[first["contact_id"] == pin]
    assert mine["slice_force_N"].sum() == pytest.approx(ls.force[0, c], rel=1e-8)
    assert mine["line_load_N_per_mm"] == pytest.approx(mine["slice_force_N"]
                                                       / (r.slice_width * 1e3), rel=1e-8)
    assert (tmp_path / "face_width.png").stat().st_size > 10_000


def test_edge_crown_is_the_least_that_keeps_the_edges_below_the_middle(cases_dir):
    """The design crown at 3 arcmin (4 positions of the pin-housing drive): with it the
    edges' P_h is at most the middle's, with one resolution step less it is above; a
    crown is refused for fewer than 3 slices. (36 positions: 5.27 um circular, 6.88 um
    partial, docs/face_width.md.)"""
    from toothfem.fem.cycloid_fe.slices import CROWN_RESOLUTION_M, edge_crown

    case = _case(cases_dir, "cycloid_pinhousing.toml")
    drive = drive_for(case)
    solver = drive.cycle_solver(4)
    torque = drive.member_torque(case.operating.output_torque_Nm)
    face = FaceSpec(9, tilt_rad=3 * ARCMIN)
    c, r = edge_crown(solver, torque, face)
    assert 1e-6 < c < 20e-6
    assert r.edge_figures()["edge_to_centre_ph"] <= 1.0
    less = solve_sliced(solver, FaceSpec(9, tilt_rad=3 * ARCMIN,
                                         crown_m=c - 1.01 * CROWN_RESOLUTION_M), torque)
    assert less.edge_figures()["edge_to_centre_ph"] > 1.0
    with pytest.raises(ToothfemError, match="face_slices = 2"):
        edge_crown(solver, torque, FaceSpec(2, tilt_rad=3 * ARCMIN))


def test_pin_bending_against_beam_theory():
    """A pin on two supports at the face's edges under a uniform load over the face, as
    S equal slice forces: its deflection at the middle against Euler-Bernoulli and
    Timoshenko's shear, 5 q L^4/(384 E I) + q L^2/(8 k G A). The slices' point loads are
    the midpoint rule of the uniform load: the error falls as 1/S^2 (measured +0.66 % at 9
    slices, +0.022 % at 49)."""
    from toothfem.fem.datasheet.supports import SHEAR_COEFFICIENT_CIRCLE

    e, nu, r, span, force = 208e9, 0.295, 2e-3, 10e-3, 100.0
    inertia, area, g = math.pi * (2 * r) ** 4 / 64, math.pi * (2 * r) ** 2, e / (2 + 2 * nu)
    q = force / span
    exact = (5 * q * span ** 4 / (384 * e * inertia)
             + q * span ** 2 / (8 * SHEAR_COEFFICIENT_CIRCLE * g * area / 4))
    errors = []
    for n in (9, 49):
        w = FaceSpec(n, pin_span_m=span).pin_bending(span, r, e, nu) @ np.full(n, force / n)
        errors.append(w[n // 2] / exact - 1)
    assert 0 < errors[1] < errors[0] < 0.01
    assert errors[0] / errors[1] == pytest.approx((49 / 9) ** 2, rel=0.05)
    assert not FaceSpec(9).pin_bending(span, r, e, nu).any()   # held in grooves


def test_pins_on_end_supports_load_the_edges(cases_dir):
    """Conventional pins held at their ends (span 12 mm over the 10 mm face), no tilt or
    crown: the pins bend away at the middle, the slices' loads are symmetric about it and
    the edges carry more (measured at 36 positions: edge 804 MPa, middle 538 MPa); the
    torque balance holds; a span with the integral housing and a span inside the face
    are refused."""
    case = _case(cases_dir, "cycloid_pinhousing.toml")
    drive = drive_for(case)
    solver = drive.cycle_solver(4, pin_structure="conventional")
    torque = drive.member_torque(case.operating.output_torque_Nm)
    r = solve_sliced(solver, FaceSpec(9, pin_span_m=12e-3), torque)
    f = r.force.max()
    assert r.force == pytest.approx(r.force[::-1], abs=1e-8 * f)
    assert r.edge_figures()["edge_to_centre_ph"] > 1.3
    assert np.max(np.abs(r.load_sharing.torque_residual())) < 1e-9
    with pytest.raises(ToothfemError, match="pin_span"):
        solve_sliced(drive.cycle_solver(4), FaceSpec(9, pin_span_m=12e-3), torque)
    with pytest.raises(ToothfemError, match="pin_span"):
        solve_sliced(solver, FaceSpec(9, pin_span_m=8e-3), torque)
    with pytest.raises(CaseError, match=r"pin_span_mm = 8.0 .*valid range"):
        _case(cases_dir, "cycloid_pinhousing.toml", face_slices=9, pin_span_mm=8.0)


def test_crowned_roller_under_tilt_against_hertz_and_the_halfspace():
    """A 2 mm roller, 10 mm long, 8 um circular crown, 3 arcmin tilt, 240 N (the pin-housing
    pin's radius and line load), both steel. Closed form: Hertz's ellipse with R_y =
    L^2/(8c) (Johnson 1985, Sec. 4.2), p_max 1163.3 MPa, moved along the length by
    theta L^2/(8c) = 1.364 mm (a tilt only moves the crown's parabola). The 3-D
    half-space on a 16 x 40 grid gives it within 1 % (measured -0.55 %, -0.27 % at
    24 x 60). The disc's slice solver with independent slices (9 slices, each the
    half-space's per-length law) puts the load's centre there within 2 % (+0.9 %) and
    reads the peak 6.9 % low (-6.1 % at 60 slices): the coupling between slices it
    neglects (docs/face_width.md); asserted within 8 %."""
    from toothfem.fem.datasheet.hertz_point import hertz_point_contact
    from toothfem.fem.slice_check import halfspace_roller, sliced_roller

    r, length, e_star, load, tilt, crown = 2e-3, 10e-3, 113.9e9, 240.0, 3 * ARCMIN, 8e-6
    hertz = hertz_point_contact(load, r, length ** 2 / (8 * crown), e_star)
    shift = -tilt * length ** 2 / (8 * crown)
    assert hertz.semi_major_m + abs(shift) < length / 2        # the ellipse on the roller
    x, y, p = halfspace_roller(r, length, e_star, load, tilt, crown, nx=16, ny=40)
    assert p.max() == pytest.approx(hertz.p_max_Pa, rel=0.01)
    at = y[np.unravel_index(int(np.argmax(p)), p.shape)[1]]
    assert abs(at - shift) <= length / 40
    ys, w, ph = sliced_roller(r, length, e_star, load, tilt, crown, 9)
    assert np.sum(w) * length / 9 == pytest.approx(load, rel=1e-9)
    assert np.sum(ys * w) / np.sum(w) == pytest.approx(shift, rel=0.02)
    assert ph.max() == pytest.approx(hertz.p_max_Pa, rel=0.08)
    assert ph.max() < hertz.p_max_Pa
