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
def test_cad_profiles_read_back(cases_dir, tmp_path, capsys, name, profiles):
    """Every case with a disc or a sine pair writes DXF and SVG beside the CSV: in mm, one
    closed polyline each, the CSV's points. Tolerances: the DXF stores doubles (area to
    1e-9); the SVG writes 6 decimals of a mm (area to 1e-6)."""
    import ezdxf

    out = tmp_path / "geo"
    assert cli.main(["geometry", str(cases_dir / f"{name}.toml"), "--out", str(out)]) == 0
    assert f"to {out.resolve()}" in capsys.readouterr().out
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

    from toothfem.report.contact import robust_max

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
