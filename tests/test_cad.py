"""The full CAD of a drive (issue 25, item 5): the disc or planet with every hole, the pins
and the housing or ring body in DXF (one layer each) and SVG (one group each), STEP through
the optional extra ``[cad]`` read back for its volume and extent, and VTU fields that state
their units.

Must show: the DXF of the RV-40E disc holds the profile and every hole; the STEP (with the
extra) reads back with the disc's volume within 1 % of the profile area minus the holes
times the face width.
"""
import json
import math
import xml.etree.ElementTree as ET
from collections import Counter
from types import SimpleNamespace

import numpy as np
import pytest

from toothfem import cad, load_case
from toothfem.cad_parts import part_drawing
from toothfem.errors import MissingExtra
from toothfem.fem.drives import drive_for
from toothfem.geometry import cycloid_mesh as cym

SVG = "{http://www.w3.org/2000/svg}"
#: Hole centres and radii in the DXF against the drive's numbers [mm]: the DXF stores
#: doubles, the only error the m -> mm product's round-off.
DXF_ATOL_MM = 1e-9
#: The housing's bore against Rz and Rz + rz [mm]: a polygon (shapely's union of the pin
#: circle and the pins), whose chords of 0.1 mm on the 64 mm circle sag by 2e-5 mm.
BORE_ATOL_MM = 1e-4
#: The issue's bound on the STEP disc's volume against area x face width.
VOLUME_REL = 0.01
#: STEP extent against the profile's points [mm]: the writer's splines pass through the
#: points and bulge between them by less than the chord sagitta of the coarsest spacing
#: (0.8 mm chords on the RV-40E disc's flanks, sagitta below 0.03 mm).
EXTENT_ATOL_MM = 0.05

#: Profile points per tooth where the test counts bodies, not shapes (a quick drawing).
FEW_POINTS = 16

CASES = ["rv40e", "rv_paper_example", "cycloid_pinhousing", "cycloid_khv", "sine_prototype"]


@pytest.fixture(scope="module")
def rv40e(cases_dir):
    case = load_case(cases_dir / "rv40e.toml")
    return case, drive_for(case), part_drawing(case)


def _by_layer(doc) -> dict:
    """Layer -> Counter of the entity types on it."""
    out = {}
    for e in doc.modelspace():
        out.setdefault(e.dxf.layer, Counter())[e.dxftype()] += 1
    return out


def _sorted_circles(circles) -> np.ndarray:
    return np.array(sorted((round(x, 6), round(y, 6), round(r, 6)) for x, y, r in circles))


def test_rv40e_disc_dxf_holds_the_profile_and_every_hole(rv40e, tmp_path):
    """Each layer holds its bodies: the profile of profile.csv on the disc at crank angle
    0 (centre (e, 0)), its centre bore, 2 crank and 2 pillar holes at the case's radii and
    angles, the 40 pins, the housing's grooved bore and outer circle, nothing else."""
    import ezdxf
    from shapely.geometry import Point, Polygon

    case, drive, drawing = rv40e
    doc = ezdxf.readfile(cad.write_drawing_dxf(tmp_path / "drawing.dxf", drawing))
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    assert _by_layer(doc) == {"DISC_PROFILE": {"LWPOLYLINE": 1}, "DISC_HOLES": {"CIRCLE": 5},
                              "PINS": {"CIRCLE": 40},
                              "HOUSING": {"LWPOLYLINE": 1, "CIRCLE": 1}}
    msp = doc.modelspace()
    g, h = drive.geometry, drive.stage.holes
    (ex, ey), = (cym.disc_pose(g, 0.0)[0].T * 1e3).tolist()
    assert (ex, ey) == pytest.approx((1.3, 0.0))                # the case's eccentricity
    # the profile: profile.csv's points, moved to the disc's centre
    (poly,) = msp.query('LWPOLYLINE[layer=="DISC_PROFILE"]')
    own = drive.profiles(96)[0]["profile"].T * 1e3
    assert poly.closed
    np.testing.assert_allclose(np.array(poly.get_points("xy")), own + [ex, ey],
                               atol=DXF_ATOL_MM)
    # every hole at the drive's centre and radius, and the case's numbers
    holes = [(c.dxf.center.x, c.dxf.center.y, c.dxf.radius)
             for c in msp.query('CIRCLE[layer=="DISC_HOLES"]')]
    drives = [(x * 1e3 + ex, y * 1e3 + ey, r * 1e3) for x, y, r, _ in h.circles()]
    np.testing.assert_allclose(_sorted_circles(holes), _sorted_circles(drives),
                               atol=DXF_ATOL_MM)
    by_diameter = Counter(round(2 * r, 6) for _, _, r in holes)
    expected = Counter()
    for count, radius in ((1, h.centre_bore_radius_m),
                          (h.crank_hole_count, h.crank_hole_radius_m),
                          (h.pillar_hole_count, h.pillar_hole_radius_m)):
        expected[round(2e3 * radius, 6)] += count
    # cases/rv40e.toml: bore 16 mm, 2 crank holes of 35 mm, 2 pillar holes of 15 mm
    assert by_diameter == expected == Counter({16.0: 1, 35.0: 2, 15.0: 2})
    angles = {round(2 * r, 6): [] for _, _, r in holes}
    for x, y, r in holes:
        if math.hypot(x - ex, y - ey) > 1e-6:
            assert math.hypot(x - ex, y - ey) == pytest.approx(36.0, abs=DXF_ATOL_MM)
            angles[round(2 * r, 6)].append(round(math.degrees(math.atan2(y - ey, x - ex))))
    assert sorted(angles[35.0]) == [0, 180]           # crank holes from +x
    assert sorted(angles[15.0]) == [-90, 90]          # pillars halfway between
    # every hole inside the profile, apart from the others
    disc = Polygon(np.array(poly.get_points("xy")))
    discs = [Point(x, y).buffer(r, 64) for x, y, r in holes]
    assert all(disc.contains(d) for d in discs)
    assert all(a.disjoint(b) for i, a in enumerate(discs) for b in discs[i + 1:])
    # the pins on the pin circle, the housing's bore between Rz and Rz + rz (the grooves)
    pins = [(c.dxf.center.x, c.dxf.center.y, c.dxf.radius)
            for c in msp.query('CIRCLE[layer=="PINS"]')]
    np.testing.assert_allclose([math.hypot(x, y) for x, y, _ in pins], 64.0, atol=DXF_ATOL_MM)
    assert {round(r, 9) for *_, r in pins} == {3.0}
    (bore,) = msp.query('LWPOLYLINE[layer=="HOUSING"]')
    radii = np.hypot(*np.array(bore.get_points("xy")).T)
    assert radii.min() == pytest.approx(64.0, abs=BORE_ATOL_MM)
    assert radii.max() == pytest.approx(67.0, abs=BORE_ATOL_MM)
    (rim,) = msp.query('CIRCLE[layer=="HOUSING"]')
    assert rim.dxf.radius == pytest.approx(79.0) and tuple(rim.dxf.center) == (0, 0, 0)
    # the housing's outer radius is not in the case: marked as assumed, with its reason
    assert "housing_outer_radius_mm" in drawing.assumed
    assert "not in the case" in drawing.assumed["housing_outer_radius_mm"]


@pytest.mark.parametrize("name", CASES)
def test_each_shipped_case_writes_its_drawing(cases_dir, tmp_path, name):
    """DXF and SVG of every shipped case: the same bodies, one DXF layer and one SVG group
    each (its id the layer, a title, its own colour), in mm; the SVG parses as XML."""
    import ezdxf

    drawing = part_drawing(load_case(cases_dir / f"{name}.toml"), FEW_POINTS)
    doc = ezdxf.readfile(cad.write_drawing_dxf(tmp_path / "d.dxf", drawing))
    root = ET.parse(cad.write_drawing_svg(tmp_path / "d.svg", drawing)).getroot()
    assert doc.header["$INSUNITS"] == 4
    layers = _by_layer(doc)
    groups = root.findall(f"{SVG}g")
    assert [g.get("id") for g in groups] == [b.layer for b in drawing.bodies]
    assert set(layers) == {b.layer for b in drawing.bodies}
    assert len({g.get("stroke") for g in groups}) == len(groups)       # told apart
    for g in groups:
        assert g.find(f"{SVG}title").text
        assert len(g.findall(f"{SVG}path")) == layers[g.get("id")]["LWPOLYLINE"]
        assert len(g.findall(f"{SVG}circle")) == layers[g.get("id")]["CIRCLE"]
    assert root.get("width").endswith("mm")
    sine = name == "sine_prototype"
    member = "PLANET" if sine else "DISC"
    assert layers[f"{member}_PROFILE"] == {"LWPOLYLINE": 1}
    assert layers["RING" if sine else "HOUSING"] == {"LWPOLYLINE": 1, "CIRCLE": 1}
    if sine:               # the bore and the 8 output pins' holes; the pins in them
        assert layers["PLANET_HOLES"] == {"CIRCLE": 9} and layers["OUTPUT_PINS"] == {
            "CIRCLE": 8}
    if name == "cycloid_khv":    # bore and 8 output holes; 8 pins with 8 roller sleeves
        assert layers["DISC_HOLES"] == {"CIRCLE": 9} and layers["OUTPUT_PINS"] == {
            "CIRCLE": 16}
    # a STEP part each; the conventional pins and the output pins (with their rollers)
    # one solid each (tests/test_cad_pins.py), integral pins the housing's own teeth
    expected = {"planet", "ring", "output_pins"} if sine else {"disc", "housing"}
    if not sine and load_case(cases_dir / f"{name}.toml").cycloid.pin_structure \
            != "integral":
        expected.add("pins")
    if name == "cycloid_khv":
        expected |= {"output_pins", "output_rollers"}
    assert {r.name for r in drawing.regions} == expected


def test_sine_planet_holes_are_the_drives(cases_dir):
    """The planet's bore is the eccentric bearing's outer raceway r_p + d_w and its holes
    sit at R_w with radius r_x + a0; the pins at R_w about the ring's centre; the ring's
    rim (not in the case) is assumed, as drawing.png takes it."""
    case = load_case(cases_dir / "sine_prototype.toml")
    drive, drawing = drive_for(case), part_drawing(case)
    om, pair = drive.output_mechanism, drive.pair
    d_w = drive.supports(case.to_si().supports).bearing_roller_diameter_m
    planet = {b.layer: b for b in drawing.bodies}
    a0 = pair.centre_distance_m
    circles = sorted(planet["PLANET_HOLES"].circles, key=lambda c: c[2])
    *holes, bore = circles
    assert bore == pytest.approx((a0, 0.0, om.eccentric_bearing_inner_radius_m + d_w))
    assert len(holes) == om.pin_count
    for x, y, r in holes:
        assert math.hypot(x - a0, y) == pytest.approx(om.pin_hole_circle_radius_m)
        assert r == pytest.approx(om.pin_radius_m + a0)
    for x, y, r in planet["OUTPUT_PINS"].circles:
        assert (math.hypot(x, y), r) == pytest.approx((om.pin_hole_circle_radius_m,
                                                       om.pin_radius_m))
    assert planet["RING"].circles[0][2] == pytest.approx(
        pair.ring_pitch_radius_m + 5 * pair.module_m)
    assert {"ring_outer_radius_mm", "planet_bore_radius_mm"} <= set(drawing.assumed)


def test_integral_pins_stand_out_of_the_housing(cases_dir):
    """Integral pins (the pin-housing paper) are teeth of the housing: its bore runs
    between Rz - rz and Rz; its outer radius is the case's, not assumed."""
    drawing = part_drawing(load_case(cases_dir / "cycloid_pinhousing.toml"))
    housing = next(b for b in drawing.bodies if b.layer == "HOUSING")
    radii = np.hypot(*housing.polylines[0])
    assert (radii.min(), radii.max()) == pytest.approx((98e-3, 100e-3), abs=1e-9)
    assert housing.circles == ((0.0, 0.0, 112e-3),)
    assert "housing_outer_radius_mm" not in drawing.assumed


def test_geometry_writes_the_drawing_beside_the_profiles(cases_dir, tmp_path, monkeypatch):
    """write_geometry lists drawing.dxf and drawing.svg with the profiles; without the
    extra it writes no STEP and says why in check.json."""
    from toothfem.report.files import write_geometry

    monkeypatch.setattr(cad, "step_available", lambda: False)
    summary = write_geometry(load_case(cases_dir / "cycloid_khv.toml"), tmp_path, FEW_POINTS)
    assert summary["files"][:5] == ["profile.csv", "profile.dxf", "profile.svg",
                                    "drawing.dxf", "drawing.svg"]
    assert all((tmp_path / f).is_file() for f in summary["files"])
    saved = json.loads((tmp_path / "check.json").read_text())["cad"]
    assert "[cad]" in saved["step"] and not list(tmp_path.glob("*.step"))
    assert set(saved["layers"]) == {"DISC_PROFILE", "DISC_HOLES", "PINS", "OUTPUT_PINS",
                                    "HOUSING"}
    assert saved["dimensions_mm"]["disc_centre_mm"] == [1.2, 0.0]


def test_step_without_the_extra_names_it(rv40e, monkeypatch, tmp_path):
    """One line naming the extra and its install command (OCP hidden as if absent)."""
    import sys

    monkeypatch.setitem(sys.modules, "OCP", None)
    with pytest.raises(MissingExtra) as err:
        cad.write_step(tmp_path / "disc.step", rv40e[2].regions[0])
    assert "[cad]" in str(err.value) and "pip install" in str(err.value)
    assert "\n" not in str(err.value) and isinstance(err.value, ImportError)
    assert not (tmp_path / "disc.step").exists()


def _read_step(path):
    """(volume [mm^3], (xmin, ymin, zmin, xmax, ymax, zmax) [mm], valid) of a STEP file,
    read with OCP itself (not the writer's code). Volume by Gauss-Kronrod integration to
    1e-9: OCP's default volume rule misses the splines' many spans (5 % off)."""
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.Bnd import Bnd_Box
    from OCP.GProp import GProp_GProps
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    assert reader.ReadFile(str(path)) == IFSelect_RetDone
    reader.TransferRoots()
    shape = reader.OneShape()
    props = GProp_GProps()
    BRepGProp.VolumePropertiesGK_s(shape, props, 1e-9)
    box = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, box, False, False)
    lo, hi = box.CornerMin(), box.CornerMax()
    return (props.Mass(), (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z()),
            BRepCheck_Analyzer(shape).IsValid())


def test_step_of_the_rv40e_disc_and_housing_read_back(rv40e, tmp_path):
    """The must-show: the disc's STEP volume is within 1 % of (profile area - holes) x face
    width, the area from shapely on the drive's own profile and holes; its extent is the
    profile's, its thickness the face width. The housing likewise (pi R^2 less the grooved
    bore, over disc_count x face width)."""
    pytest.importorskip("OCP", reason="the optional extra [cad] (OCP) is not installed: "
                                      "pip install 'toothfem[cad]'")
    from shapely.geometry import Point, Polygon
    from shapely.ops import unary_union

    case, drive, drawing = rv40e
    regions = {r.name: r for r in drawing.regions}
    profile = drive.profiles(96)[0]["profile"] * 1e3                      # (2, N) mm
    holes = sum(math.pi * (r * 1e3) ** 2 for *_, r, _ in drive.stage.holes.circles())
    w = drive.face_width_m * 1e3
    expected = (Polygon(profile.T).area - holes) * w
    volume, box, valid = _read_step(cad.write_step(tmp_path / "disc.step", regions["disc"]))
    assert valid
    assert volume == pytest.approx(expected, rel=VOLUME_REL)
    print(f"RV-40E disc: STEP {volume:.1f} mm3, shapely {expected:.1f} mm3, "
          f"{100 * (volume / expected - 1):+.4f} %")
    np.testing.assert_allclose(box, [*profile.min(axis=1), 0.0, *profile.max(axis=1), w],
                               atol=EXTENT_ATOL_MM)
    # the housing: its bore from shapely's own union of the pin circle and the pins
    g = drive.geometry
    bore = unary_union([Point(0, 0).buffer(64.0, 2048)] + [
        Point(x * 1e3, y * 1e3).buffer(3.0, 256) for x, y in cym.pin_centres(g).T])
    length = drive.stage.disc_count * w
    expected = (math.pi * 79.0 ** 2 - bore.area) * length
    volume, box, valid = _read_step(cad.write_step(tmp_path / "housing.step",
                                                   regions["housing"]))
    assert valid and volume == pytest.approx(expected, rel=VOLUME_REL)
    print(f"RV-40E housing: STEP {volume:.1f} mm3, shapely {expected:.1f} mm3, "
          f"{100 * (volume / expected - 1):+.4f} %")
    np.testing.assert_allclose(box, [-79, -79, 0, 79, 79, length], atol=1e-6)


def test_vtu_fields_state_their_units(tmp_path):
    """A uniform strain exx on a plane-strain square: the VTU holds points and
    displacement in mm and the stresses in MPa, each name with its unit, and the field
    picture reads it."""
    import meshio
    from skfem import MeshTri

    from toothfem.fem import export
    from toothfem.fem.elastic import Body, lame_parameters
    from toothfem.report.field import field_png

    mesh = MeshTri().refined(2).scaled(0.01)                     # a 10 mm square [m]
    body = Body(SimpleNamespace(mesh=mesh), 2e11, 0.3, np.array([0]))
    strain = 1e-3
    u = body.basis.project(lambda x: np.array([strain * x[0], 0.0 * x[1]]))   # exact: P2
    vtu = meshio.read(export.write_vtu(tmp_path / "square.vtu", body, u))
    assert set(vtu.point_data) == {"displacement_mm", "sxx_MPa", "syy_MPa", "sxy_MPa",
                                   "szz_MPa", "von_mises_MPa"}
    np.testing.assert_allclose(vtu.points[:, :2], mesh.p.T * 1e3)          # mm
    np.testing.assert_allclose(vtu.point_data["displacement_mm"][:, 0], strain * mesh.p[0]
                               * 1e3, atol=1e-12)
    lam, mu = lame_parameters(2e11, 0.3, "strain")
    np.testing.assert_allclose(vtu.point_data["sxx_MPa"], (lam + 2 * mu) * strain / 1e6,
                               rtol=1e-6)
    s, t = (lam + 2 * mu) * strain / 1e6, lam * strain / 1e6
    np.testing.assert_allclose(vtu.point_data["von_mises_MPa"], abs(s - t), rtol=1e-6)
    png = field_png(tmp_path / "square.vtu", tmp_path / "square.png", title="uniform strain")
    assert png.stat().st_size > 5_000
