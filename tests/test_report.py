"""What an engineer sees (issue 15): CAD profiles that read back, `check` with its sign
convention and rating warning, summary tables with the published figures beside ours, and
contact pictures that name the user's torque and the drive's own words."""
import json
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from toothfem import cli, load_case
from toothfem.fem.drives import drive_for


def _area(xy) -> float:
    """Shoelace area of a closed polygon (N, 2), the closing point not repeated."""
    x, y = np.asarray(xy, float).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _svg_points(path) -> np.ndarray:
    """The (N, 2) points [mm] of the one closed path of an SVG, y back to up."""
    d = ET.parse(path).getroot().find("{http://www.w3.org/2000/svg}path").get("d")
    assert d.startswith("M ") and d.endswith(" Z")
    pts = np.array([[float(v) for v in p.split(",")] for p in re.findall(r"[-\d.]+,[-\d.]+", d)])
    return pts * [1.0, -1.0]


@pytest.mark.parametrize("name, profiles", [("cycloid_pinhousing", ("profile",)),
                                            ("rv40e", ("profile",)),
                                            ("sine_prototype", ("planet", "ring"))])
def test_cad_profiles_read_back(geometry_of, name, profiles):
    """Every case with a disc or a sine pair writes DXF and SVG beside the CSV: in mm, one
    closed polyline each, the CSV's points. Tolerances: the DXF stores doubles (area to
    1e-9); the SVG writes 6 decimals of a mm (area to 1e-6). (`toothfem geometry` of the
    case, shared: conftest.)"""
    import ezdxf

    out, printed = geometry_of(name)
    assert f"to {out.resolve()}" in printed
    for p in profiles:
        csv = np.loadtxt(out / f"{p}.csv", delimiter=",", skiprows=1)
        doc = ezdxf.readfile(out / f"{p}.dxf")
        assert doc.header["$INSUNITS"] == 4                     # millimetres
        (poly,) = doc.modelspace().query("LWPOLYLINE")
        assert poly.closed and poly.dxf.layer == p.upper()
        dxf = np.array(poly.get_points("xy"))
        assert dxf.shape == csv.shape
        assert _area(dxf) == pytest.approx(_area(csv), rel=1e-9)
        np.testing.assert_allclose(dxf, csv, atol=1e-8)
        svg = _svg_points(out / f"{p}.svg")
        assert svg.shape == csv.shape
        assert _area(svg) == pytest.approx(_area(csv), rel=1e-6)


def test_check_states_the_convention_once_and_warns_above_the_rating(cases_dir, capsys):
    assert cli.main(["check", str(cases_dir / "rv_paper_example.toml")]) == 0
    out = capsys.readouterr().out
    assert out.count("i = n_input / n_output") == 1
    assert "operating_output_torque_Nm" in out and "operating_input_power_W" in out
    warning = [line for line in out.splitlines() if line.startswith("warning:")]
    assert len(warning) == 1 and "x the rated 412 N m" in warning[0]
    assert cli.main(["check", str(cases_dir / "sine_prototype.toml"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["ratio"] == -79 and d["warnings"] == []       # signed: the output turns back
    assert d["operating_input_torque_Nm"] == pytest.approx(0.4, rel=1e-6)
    # P_in = T_in omega_in: 0.4 N m at 300 rpm
    assert d["operating_input_power_W"] == pytest.approx(0.4 * 300 * np.pi / 30, rel=1e-6)
    assert d["operating_output_power_W"] == pytest.approx(
        d["operating_efficiency_analytic"] * d["operating_input_power_W"], rel=1e-5)


def test_efficiency_table_with_the_published_figures(cases_dir, capsys):
    assert cli.main(["efficiency", str(cases_dir / "rv_paper_example.toml"), "--method",
                     "rv_split_power"]) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("loss: cycloid_mesh"))
    assert row.split()[-2:] == ["131.5", "131.5"]          # ours, the RV paper's L2
    assert "published: the paper's figure" in out


def test_summary_rows_name_contacts_by_the_drive(cases_dir):
    from toothfem.report.contact import ContactLabels
    from toothfem.report import summary as rs

    labels = ContactLabels(case_name="c", contact="tooth", contacts="teeth", member="planet",
                           members=1, output_torque_Nm=28.0, member_torque_Nm=28.0,
                           mode="cycle")
    rows = rs.contact_rows({"teeth_in_contact_max": 3, "max_ph_MPa": 120.0}, labels,
                           {"teeth_in_contact": 2, "max_contact_stress_MPa": 110.0})
    by = {what: vals for what, _, vals in rows}
    assert by["teeth in contact, most"] == {"ours": 3, "published": 2}
    assert by["largest Hertz pressure P_h, one planet held at its bearing seats"] == {
        "ours": 120.0, "published": 110.0}
    assert by["torque on the planet"] == {"ours": 28.0}
    text = rs.text(rows)
    assert text.splitlines()[0].split() == ["quantity", "unit", "ours", "published"]
    assert "| teeth in contact, most |  | 3 | 2 |" in rs.markdown(rows)


@pytest.mark.parametrize("name", ["cycloid_pinhousing", "sine_prototype"])
def test_contact_pictures_name_the_users_torque(cases_dir, name):
    """Titles carry the output torque the user asked for and the member's share, axes
    their units, series the drive's words; legends sit outside the axes."""
    from matplotlib.transforms import Bbox

    from toothfem.report import contact as rc, pyplot

    case = load_case(cases_dir / f"{name}.toml")
    drive = drive_for(case)
    torque = 167.0 if drive.kind == "cycloid" else 28.0
    ls = drive.analytic_split(drive.meshing(drive.positions(8)), drive.member_torque(torque))
    labels = rc.ContactLabels(case_name=case.name, contact=drive.contact_name,
                              contacts=drive.contacts_name, member=drive.member_name,
                              members=drive.members, output_torque_Nm=torque,
                              member_torque_Nm=drive.member_torque(torque), mode="analytic")
    # 1.1 x 167 (1 - 1/121)(39/40)/2: the power flow's share with the disc load factor
    share = {"cycloid": "88.81 N m on each of 2 discs", "sine": "28 N m on the planet"}
    for draw in (rc.load_per_contact, rc.load_around_ring, rc.transmission_error):
        fig = draw(ls, labels)
        texts = [a.get_title(loc="left") for a in fig.axes] + [
            fig._suptitle.get_text() if fig._suptitle else ""]
        title = next(t for t in texts if "N m output" in t)
        assert f"{torque:g} N m output" in title and share[drive.kind] in title
        fig.canvas.draw()
        legends = fig.legends + [a.get_legend() for a in fig.axes if a.get_legend()]
        assert legends
        for leg in legends:                  # beside or below the axes, not on the data
            box = leg.get_window_extent()
            for ax in fig.axes:
                inter = Bbox.intersection(box, ax.get_window_extent())
                assert inter is None or inter.width * inter.height < 1.0, draw.__name__
        labels_y = " ".join(a.get_ylabel() for a in fig.axes)
        assert re.search(r"\[(N|MPa|arcsec)\]", labels_y)
        assert drive.contact_name in labels_y or draw is rc.transmission_error
        pyplot().close(fig)


def test_titles_never_break_a_quantity():
    from toothfem.report import wrap

    title = ("von Mises stress of the disc, structural field (contact loads spread over "
             "strips: the Hertz stress, P_h 623.3 MPa at pin 2, is not resolved); 1524 N m "
             "output, 736.6 N m on each of 2 discs")
    for width in range(30, 120, 7):
        lines = wrap(title, width).splitlines()
        text = "\n".join(lines)
        for quantity in ("P_h 623.3 MPa", "1524 N m", "736.6 N m"):
            assert quantity in text, (width, lines)
        assert "\u00a0" not in text


def test_a_field_scale_ends_at_its_99th_percentile_by_area():
    """A field of 1 MPa with a 1000 MPa spike on a few small triangles: the colour scale
    ends near 1 MPa (the body readable), not at the spike."""
    from matplotlib.tri import Triangulation

    from toothfem.report.field import robust_max

    x, y = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    tri = Triangulation(x.ravel(), y.ravel())
    value = np.ones(x.size)
    value[np.argmin(np.hypot(x.ravel() - 0.5, y.ravel() - 0.5))] = 1000.0
    assert robust_max(tri, value) < 2.0
    assert robust_max(tri, np.zeros(x.size)) == 0.0


def test_marked_points_lie_inside_the_axes():
    from toothfem.report import plots

    marked = [plots.Marked(x=1500.0, y=0.87, kind="operating", label="operating"),
              plots.Marked(x=412.0, y=0.40, label="measured")]
    fig = plots.efficiency_vs_torque(np.linspace(30, 1500, 20), {"a": np.full(20, 0.8)},
                                     marked)
    ax = fig.axes[0]
    for m in marked:
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        assert x0 < m.x < x1 and x1 - m.x > 0.03 * (x1 - x0)
        assert y0 < 100 * m.y < y1 and 100 * m.y - y0 > 0.03 * (y1 - y0)


def test_the_loaded_contacts_are_told_apart():
    """The contacts named in a per-contact picture have distinct colours, none grey; the
    rest are grey; the largest force's contact is named."""
    from toothfem.report.contact import MAX_LEGEND_SERIES, OTHER_CONTACTS, _highlighted

    rng = np.random.default_rng(1)
    numbers = np.arange(20)
    force = rng.uniform(0, 100, size=(36, 20))
    force[:, 17] = 500.0
    colour = _highlighted(numbers, force, force)
    named = [n for n in numbers if colour[n] != OTHER_CONTACTS]
    assert len(named) == MAX_LEGEND_SERIES and 17 in named
    assert len({colour[n] for n in named}) == len(named)
    assert all(len(set(colour[n][:3])) > 1 for n in named)       # no grey among them


def test_a_case_without_a_rating_is_rated_at_its_operating_output_torque(cases_dir):
    """The sine prototype declares an input torque: its datasheet's rating is the output
    torque `run` reports (|i| T1 eta), not the lossless |i| T1; a declared rating wins."""
    from toothfem.efficiency import operating_point, rated_output_torque

    sine = load_case(cases_dir / "sine_prototype.toml")
    rated, assumed = rated_output_torque(sine)
    assert assumed and rated == pytest.approx(operating_point(sine)[1], rel=1e-12)
    assert rated < 0.9 * 0.4 * 79
    rv = load_case(cases_dir / "rv_paper_example.toml")
    assert rated_output_torque(rv) == (412.0, False)


# --- picture faults of the audit: titles, named series, markers, sectors, labels ---------


def test_wrap_keeps_peak_to_peak_and_the_mode_whole():
    """A ripple's "1.89 arcsec peak to peak" and "(cycle mode)" are never broken, at any
    width; a glued phrase longer than the width stays whole."""
    from toothfem.report import wrap

    title = ("The mesh's part of the TE (one disc held at its bearing seats): mean 48.5 "
             "arcsec, ripple 0.0582 arcsec peak to peak; the reducer's TE is the summary's "
             "system-model row\nRV-40E, the RV paper's worked example (Wang, 2.27 kW): 1524 N "
             "m output, 736.6 N m on each of 2 discs (cycle mode)")
    for width in range(10, 130, 3):
        text = wrap(title, width)
        for phrase in ("0.0582 arcsec peak to peak", "(cycle mode)", "1524 N m"):
            assert phrase in text, (width, text)
        assert "\u00a0" not in text


def _labels(**kw):
    from toothfem.report.contact import ContactLabels

    return ContactLabels(**{**dict(case_name="c", contact="pin", contacts="pins",
                                   member="disc", members=2, output_torque_Nm=100.0,
                                   member_torque_Nm=55.0, mode="cycle"), **kw})


def test_contact_titles_say_the_model_and_the_reducers_figures():
    """Titles of the contact pictures say they show one member held at its bearing seats
    and, where the summary has them, the reducer-wide figures for comparison."""
    from types import SimpleNamespace

    from toothfem.report.files import contact_labels

    summary = {"output_torque_Nm": 100.0, "disc_torque_Nm": 55.0,
               "max_force_reducer_N": 2648.5, "max_ph_reducer_MPa": 2483.46}
    result = SimpleNamespace(case_name="c", contact_name="pin", contacts_name="pins",
                             member_name="disc", members=2, mode="cycle", summary=summary)
    labels = contact_labels(result)
    assert labels.reducer_max_force_N == 2648.5 and labels.reducer_max_ph_MPa == 2483.46
    title = labels.title(f"Load per pin: {labels.model_text}", reducer=True)
    assert "one disc held at its bearing seats" in title
    assert "every disc free on its supports" in title
    assert "largest force 2648 N" in title and "P_h 2483 MPa" in title
    assert "force" not in labels.reducer(force=False).split(":")[-1]
    assert _labels().reducer_text == "" and len(_labels().title("x", reducer=True)
                                                .splitlines()) == 2
    assert "the planet free" in _labels(member="planet", members=1,
                                        reducer_max_ph_MPa=1.0).reducer_text


def test_the_named_pins_include_the_largest_ph():
    """Force and P_h peak on different pins (a pin's curvature, not its force): the pins
    named in colour are the union of the top ones by force and by P_h."""
    from toothfem.report.contact import MAX_LEGEND_SERIES, OTHER_CONTACTS, _highlighted

    numbers = np.arange(20)
    position = np.linspace(0, 1, 12)[:, None]
    force = np.tile(np.linspace(1000, 50, 20), (12, 1)) * (1 + 0.01 * position)
    ph = np.tile(np.r_[np.linspace(100, 400, 12), np.linspace(2000, 1500, 8)], (12, 1))
    colour = _highlighted(numbers, force, ph)
    named = {n for n in numbers if colour[n] != OTHER_CONTACTS}
    assert len(named) == MAX_LEGEND_SERIES
    assert {0, 1, 2} <= named                 # the top ones by force
    assert {12, 13, 14} <= named              # the top ones by P_h


def test_the_envelope_is_drawn_behind_the_series():
    from toothfem.report import contact as rc, pyplot
    from toothfem.fem.load_sharing import LoadSharing

    p, c = 6, 3
    force = np.array([[300.0, 200.0, 0.0]] * p)
    ls = LoadSharing(method="cycle", position_rad=np.linspace(0, 0.1, p),
                     contact_id=np.tile(np.arange(c), (p, 1)), force=force,
                     point=np.tile([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]], (p, 1, 1)),
                     moment_arm=np.full((p, c), -0.01), half_width=np.full((p, c), 1e-4),
                     ph=force * 1e6, gap=np.zeros((p, c)), transmission_error=np.zeros(p),
                     torque=5.0, face_width=0.01, pressure_from_fe=np.zeros((p, c), bool),
                     equivalent_radius=np.full((p, c), 0.01),
                     hertz_invalid=np.zeros((p, c), bool))
    fig = rc.load_per_contact(ls, _labels())
    ax = fig.axes[0]
    band = next(li for li in ax.lines if "largest over" in li.get_label())
    series = [li for li in ax.lines if li.get_label().startswith("pin ")]
    assert series and all(band.get_zorder() < li.get_zorder() for li in series)
    assert band.get_linestyle() == "-" and band.get_linewidth() > series[0].get_linewidth()
    assert "one disc held at its bearing seats" in ax.get_title(loc="left")
    pyplot().close(fig)
    fig = rc.load_around_ring(ls, _labels())           # a point at 0 N above the frame
    assert all(a.get_ylim()[0] < 0 for a in fig.axes[1:3])
    pyplot().close(fig)


def test_a_polar_sector_is_just_wider_than_the_loaded_span():
    """The sine pair's teeth at -5.1..6.8 deg: the sector is their span and one pitch
    either side on whole degrees, with round ticks; a half-ring load gets the circle."""
    from toothfem.report.contact import POLAR_MAX_TICKS, polar_sector

    start, end, ticks = polar_sector([-5.1, 0.0, 4.1, 6.8])
    assert (start, end) == (-10.0, 11.0)
    assert start <= -5.1 - 4.1 and end >= 6.8 + 4.1 and end - start < 25
    inner = ticks[(ticks > start) & (ticks < end)]
    assert np.allclose(np.diff(inner), inner[1] - inner[0]) and inner[1] - inner[0] in (
        1, 2, 5, 10, 15, 20, 30, 45) and len(ticks) <= POLAR_MAX_TICKS + 2
    assert polar_sector(np.arange(0.0, 181.0, 12.0)) is None


def test_a_marked_points_colour_differs_from_every_lines():
    """The operating star, a published square and a measured dot in colours no curve has;
    a curve lying on an earlier one is dashed over it (both seen)."""
    from matplotlib.colors import to_rgba

    from toothfem.report import plots, pyplot

    t = np.linspace(1, 40, 30)
    base = 0.8 - 0.3 / t
    curves = {f"curve {i}": base + 0.02 * i for i in range(5)}
    curves["on curve 0"] = base + 1e-5
    marked = [plots.Marked(x=20.0, y=0.79, kind=k, label=k)
              for k in ("operating", "published", "measured")]
    fig = plots.efficiency_vs_torque(t, curves, marked)
    ax = fig.axes[0]
    lines = [li for li in ax.lines if li.get_label() in curves]
    points = [li for li in ax.lines if li.get_label() in ("operating", "published",
                                                           "measured")]
    line_colours = {to_rgba(li.get_color()) for li in lines}
    for p in points:
        for c in (p.get_markerfacecolor(), p.get_markeredgecolor()):
            if to_rgba(c)[3] > 0 and to_rgba(c) != to_rgba("k"):
                assert to_rgba(c) not in line_colours, p.get_label()
    assert to_rgba(points[0].get_markerfacecolor()) not in line_colours
    style = {li.get_label(): li.get_linestyle() for li in lines}
    assert style["curve 0"] == "-" and style["on curve 0"] == "--"
    assert style["curve 1"] == "-"
    pyplot().close(fig)


def test_loss_share_labels_are_exact_enough_and_never_overlap():
    """11.49 and 11.51 % read alike (not 11 and 12), 20.5 and 19.9 apart; the value
    labels of neighbouring bars do not overlap; published shares are one more group."""
    from toothfem.report import plots, pyplot

    text = plots.share_text
    assert text(11.49) == text(11.51) == "11.5"
    assert (text(20.5), text(19.9)) == ("20.5", "19.9")
    assert (text(0.0503), text(0.0510), text(3.55), text(0.0), text(np.nan)) == (
        "0.0503", "0.0510", "3.55", "0", "")
    names = ["mesh", "main_bearings", "seals"]
    shares = {"analytic": {"mesh": 0.1149, "main_bearings": 0.000503, "seals": 0.0074},
              "fem": {"mesh": 0.1151, "main_bearings": 0.000510, "seals": 0.0075}}
    fig = plots.loss_shares(names, shares, published={"mesh": 0.0355, "bearings": 0.0227})
    ax = fig.axes[0]
    fig.canvas.draw()
    boxes = [t.get_window_extent() for t in ax.texts if t.get_text()]
    assert len(boxes) == 8                        # 3 x 2 of ours, 2 published
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    assert any("published" in t.get_text() for t in ax.get_legend().get_texts())
    assert "bearings\n(published only)" in [t.get_text() for t in ax.get_xticklabels()]
    pyplot().close(fig)


def test_the_whole_members_view_takes_in_the_outlines_and_a_close_up_its_own_max():
    from matplotlib.tri import Triangulation

    from toothfem.report.field import field_limits, view_max

    x, y = np.meshgrid(np.linspace(-10, 10, 21), np.linspace(-10, 10, 21))
    tri = Triangulation(x.ravel(), y.ravel())
    pin = np.array([[-0.012, -0.011, -0.012, -0.013], [0.0, 0.001, 0.002, 0.001]])  # [m]
    (x0, x1), (y0, y1) = field_limits(tri, [pin])
    assert x0 < -13.0 and x1 > 10.0 and y0 < -10.0 and y1 > 10.0
    value = np.hypot(x.ravel(), y.ravel())
    top, at = view_max(tri, value, (-2.0, 2.0), (-2.0, 2.0))
    assert top == pytest.approx(np.hypot(2, 2)) and abs(at[0]) == 2.0
    assert view_max(tri, value, (50, 60), (50, 60)) == (None, None)


def test_the_largest_ph_contact_is_found_in_the_members_frame():
    """The member frame from the largest-force contact and the fixed member's outlines
    (pins evenly about the housing's centre): any housing point maps as the rigid
    motion does."""
    from types import SimpleNamespace

    from toothfem.report.files import member_frame

    turn, shift = 0.3, np.array([0.001, -0.002])
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    to_member = lambda p: (np.asarray(p) - shift) @ rot.T          # noqa: E731
    t = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    pins = [0.05 * np.array([np.cos(a), np.sin(a)])[:, None]
            + 0.003 * np.array([np.cos(t), np.sin(t)]) for a in np.linspace(0, 2 * np.pi, 12,
                                                                              endpoint=False)]
    outlines = tuple(to_member(o.T).T for o in pins)
    point = np.array([[[0.047, 0.0], [0.0, 0.047]]])               # (P, C, 2) housing
    ls = SimpleNamespace(force=np.array([[900.0, 100.0]]), point=point)
    result = SimpleNamespace(outlines=outlines, load_sharing=ls, worst=0,
                             member_point=to_member(point[0, 0]))
    assert np.allclose(member_frame(result, point[0, 1]), to_member(point[0, 1]), atol=1e-12)
    assert member_frame(SimpleNamespace(outlines=()), point[0, 1]) is None


def test_the_oil_temperature_map_takes_in_the_operating_oil():
    from types import SimpleNamespace

    from toothfem.maps import OIL_TEMPERATURE_GRID_C, oil_temperature_grid

    oil = SimpleNamespace(pour_point_C=-30.0, max_temperature_C=150.0)
    assert oil_temperature_grid(60.0, oil) is OIL_TEMPERATURE_GRID_C
    hot = oil_temperature_grid(145.7, oil)
    assert hot[0] == 20.0 and 145.7 < hot[-1] <= 150.0
    cold = oil_temperature_grid(5.0, oil)
    assert cold[0] < 5.0 and cold[-1] == 100.0


def test_the_drawing_shows_the_pitch_point_it_names(cases_dir):
    """The pitch point (+) lies inside the panel that marks it; the close-up's title does
    not promise it."""
    from toothfem.report import plots, pyplot

    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    fig = plots.drawing(drive_for(case), case_name=case.name)
    left, right = fig.axes
    plus = [li for ax in fig.axes for li in ax.lines if li.get_marker() == "+"]
    assert len(plus) == 1 and plus[0].axes is left
    (x,), (y,) = plus[0].get_data()
    assert left.get_xlim()[0] < x < left.get_xlim()[1]
    assert left.get_ylim()[0] < y < left.get_ylim()[1]
    assert "outside" not in left.get_title() and "left" in right.get_title()
    pyplot().close(fig)
