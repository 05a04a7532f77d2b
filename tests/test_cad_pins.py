"""The drawings complete (issue 41, missing results): STEP holds the conventional pins, the
output pins and their rollers (one solid each, read back for their volume and extent), and
drawing.png draws the holes, the output pins and the housing the DXF and SVG hold."""
from __future__ import annotations

import math

import numpy as np
import pytest

from toothfem import cad, load_case
from toothfem.cad_parts import part_drawing
from toothfem.fem.drives import drive_for
from toothfem.geometry import cycloid_mesh as cym

#: Circles are exact in STEP: the volume read back by Gauss-Kronrod to 1e-9 (the reader's
#: own rule, tests/test_cad.py) against n pi r^2 L; 1e-6 leaves room for its integration.
CIRCLE_VOLUME_REL = 1e-6
#: The extent of exact circles [mm]: OCP's optimal box, to its own tolerance.
CIRCLE_EXTENT_ATOL_MM = 1e-4


def _read_step(path):
    from tests.test_cad import _read_step as read
    return read(path)


@pytest.fixture(scope="module")
def khv(cases_dir):
    case = load_case(cases_dir / "cycloid_khv.toml")
    return case, drive_for(case), part_drawing(case, 16)


def test_khv_step_holds_the_pins_the_output_pins_and_rollers(khv, tmp_path):
    """pins.step: 30 pins of r 3 mm over the discs' stack, on the pin circle; output_pins:
    8 of r 4 mm on r 30 mm; output_rollers: 8 sleeves 5.5 / 4 mm; each volume n pi r^2 L,
    each extent the ring's."""
    pytest.importorskip("OCP", reason="the optional extra [cad] (OCP) is not installed")
    case, drive, drawing = khv
    regions = {r.name: r for r in drawing.regions}
    assert set(regions) == {"disc", "housing", "pins", "output_pins", "output_rollers"}
    g, om = drive.geometry, case.output_mechanism
    length = case.cycloid.disc_count * case.cycloid.face_width_mm
    rz = g.pin_radius_m * 1e3
    expected = {"pins": (g.pin_count, rz, 0.0, g.pin_circle_radius_m * 1e3),
                "output_pins": (om.pin_count, om.pin_radius_mm, 0.0,
                                om.pin_hole_circle_radius_mm),
                "output_rollers": (om.pin_count, om.roller_radius_mm, om.pin_radius_mm,
                                   om.pin_hole_circle_radius_mm)}
    for name, (n, r, r_in, circle) in expected.items():
        volume, box, valid = _read_step(cad.write_step(tmp_path / f"{name}.step",
                                                       regions[name]))
        assert valid, name
        assert volume == pytest.approx(n * math.pi * (r ** 2 - r_in ** 2) * length,
                                       rel=CIRCLE_VOLUME_REL), name
        assert box[2] == pytest.approx(0.0, abs=CIRCLE_EXTENT_ATOL_MM)
        assert box[5] == pytest.approx(length, abs=CIRCLE_EXTENT_ATOL_MM)
        assert box[3] == pytest.approx(circle + r, abs=CIRCLE_EXTENT_ATOL_MM), name
    # the pins stand where the drawing's PINS layer has them
    pins = next(b for b in drawing.bodies if b.layer == "PINS")
    np.testing.assert_allclose(np.array(regions["pins"].at),
                               np.array([(x, y) for x, y, _ in pins.circles]), atol=1e-15)
    np.testing.assert_allclose(np.array(regions["pins"].at), cym.pin_centres(g).T, atol=1e-15)


def test_integral_pins_have_no_step_of_their_own(cases_dir):
    """Integral pins are the housing's teeth: no pins region (the housing holds them)."""
    drawing = part_drawing(load_case(cases_dir / "cycloid_pinhousing.toml"), 16)
    assert "pins" not in {r.name for r in drawing.regions}


def test_sine_step_holds_its_output_pins(cases_dir):
    """The sine pair's bare output pins: a region, no rollers."""
    drawing = part_drawing(load_case(cases_dir / "sine_prototype.toml"), 16)
    names = [r.name for r in drawing.regions]
    assert names == ["planet", "ring", "output_pins"]


@pytest.mark.parametrize("name, layers", [
    ("cycloid_khv", {"DISC_HOLES", "OUTPUT_PINS", "HOUSING"}),
    ("sine_prototype", {"PLANET_HOLES", "OUTPUT_PINS"})])
def test_drawing_png_draws_every_body(cases_dir, name, layers):
    """drawing.png's figure: a legend entry for each body the pair's own drawing leaves out,
    and on the whole-pair panel one filled patch per output pin or roller and per hole (the
    holes white, at their centres in the housing frame)."""
    from matplotlib.colors import to_rgba

    from toothfem.report import plots

    case = load_case(cases_dir / f"{name}.toml")
    drive = drive_for(case)
    parts = part_drawing(case, 16, drive=drive)
    fig = plots.drawing(drive, case_name=case.name, parts=parts)
    labels = {t.get_text().split(":")[0] for t in fig.legends[0].get_texts()}
    assert labels == layers
    ax = fig.axes[0]
    orange = to_rgba(plots.OVERLAY_COLOURS["OUTPUT_PINS"], 0.75)
    pins = [p for p in ax.patches if np.allclose(p.get_facecolor(), orange)]
    body = next(b for b in parts.bodies if b.layer == "OUTPUT_PINS")
    assert len(pins) == len(body.circles)
    holes = next(b for b in parts.bodies if b.layer.endswith("HOLES"))
    edge = to_rgba(plots.OVERLAY_COLOURS[holes.layer])
    white = [p for p in ax.patches if np.allclose(p.get_edgecolor(), edge)
             and np.allclose(p.get_facecolor(), to_rgba("white"))]
    assert len(white) == len(holes.circles)
    # a circle's centre the middle of its polygon's extent (90 points: an extreme falls
    # between two by r (1 - cos(pi/89)) at most, 0.01 mm on the 14 mm bore)
    drawn = np.array([(p.get_xy().min(axis=0) + p.get_xy().max(axis=0)) / 2 for p in white])
    for x, y, _ in holes.circles:
        assert np.min(np.hypot(*(drawn - [x * 1e3, y * 1e3]).T)) < 0.01
