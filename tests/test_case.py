"""Case files: the three seed reducers load; each rule refuses an impossible value with one
line naming the key, the value and the valid range."""
import copy
import dataclasses
import math

import pytest

from toothfem import CaseError, load_case, parse_case
from toothfem.case import case_to_dict

try:
    import tomllib
except ImportError:  # pragma: no cover
    import tomli as tomllib


def _raw(cases_dir, name):
    with open(cases_dir / name, "rb") as fh:
        return tomllib.load(fh)


def test_pin_housing_case(cases_dir):
    c = load_case(cases_dir / "cycloid_pinhousing.toml")
    assert c.drive == "cycloid" and c.cycloid.pin_count == 40 and c.cycloid.lobe_count == 39
    assert c.cycloid.pin_circle_radius_mm == 100 and c.cycloid.eccentricity_mm == 1
    assert c.cycloid.pin_radius_mm == 2 and c.cycloid.disc_count == 2
    assert (c.first_stage.sun_teeth, c.first_stage.planet_teeth) == (9, 27)
    assert c.first_stage.module_mm == 1.5 and c.first_stage.pressure_angle_deg == 20
    assert c.operating.input_speed_rpm == 1815 and c.operating.output_torque_Nm == 167
    assert c.material.youngs_modulus_GPa == 208 and c.material.poisson_ratio == 0.295
    assert c.friction.coefficient == 0.05
    assert math.isclose(c.ratio(), 121, rel_tol=1e-12)
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.name = "x"


def test_sine_case(cases_dir):
    c = load_case(cases_dir / "sine_prototype.toml")
    assert (c.sine.planet_teeth, c.sine.ring_teeth) == (79, 80)
    assert c.sine.module_mm == 0.9 and c.sine.tooth_height_mm == 0.4
    assert math.isclose(c.ratio(), -79, rel_tol=1e-12)
    (m,) = c.measured
    assert (m.input_speed_rpm, m.output_torque_Nm, m.efficiency) == (500, 28, 0.8247)
    assert c.lubricant.kinematic_viscosity_mm2_s == 400
    assert c.output_mechanism.pin_hole_circle_radius_mm == 26.2


def test_rv40e_case(cases_dir):
    """The unit at its maker's rated point (412 N m at 15 rpm output), one planet per
    crankshaft; the paper's 2.27 kW example is a case of its own with the same train."""
    c = load_case(cases_dir / "rv40e.toml")
    assert (c.rv.sun_teeth, c.rv.planet_teeth, c.rv.disc_teeth, c.rv.pin_count) == (12, 36, 39, 40)
    assert c.operating.output_torque_Nm == 412.0 and c.operating.input_speed_rpm == 1815.0
    assert c.first_stage.planet_count == c.cycloid.disc_holes.crank_hole_count == 2
    assert math.isclose(c.ratio(), 121, rel_tol=1e-12)
    paper = load_case(cases_dir / "rv_paper_example.toml")
    assert paper.operating.input_power_kW == 2.27 and paper.rv.mesh_efficiency == 0.94
    assert paper.rv == c.rv and paper.cycloid == c.cycloid


@pytest.mark.parametrize("name", ["cycloid_pinhousing.toml", "sine_prototype.toml", "rv40e.toml"])
def test_round_trip(cases_dir, name):
    c = load_case(cases_dir / name)
    assert parse_case(case_to_dict(c)) == c


# (case file, dotted key, bad value, text the one-line message must contain)
RULES = [
    ("cycloid_pinhousing.toml", "cycloid.eccentricity_mm", -1.0,
     "cycloid.eccentricity_mm = -1.0 is outside the valid range [0.01, 100]"),
    ("cycloid_pinhousing.toml", "cycloid.eccentricity_mm", 2.6,
     "cycloid.eccentricity_mm = 2.6 is outside the valid range (0, 2.5): K1 = A*Zb/Rz must "
     "be below 1"),
    ("cycloid_pinhousing.toml", "cycloid.pin_radius_mm", 0.0,
     "cycloid.pin_radius_mm = 0.0 is outside the valid range [0.1, 200]"),
    ("cycloid_pinhousing.toml", "cycloid.pin_radius_mm", 8.0,
     "cycloid.pin_radius_mm = 8.0 is outside the valid range (0, 7.84591): neighbouring pins"),
    ("cycloid_pinhousing.toml", "cycloid.pin_count", 3,
     "cycloid.pin_count = 3 is outside the valid range [4, 400]"),
    ("cycloid_pinhousing.toml", "cycloid.pin_count", 40.5,
     "cycloid.pin_count = 40.5 must be an integer"),
    ("cycloid_pinhousing.toml", "cycloid.lobe_count", 38,
     "cycloid.lobe_count = 38 must equal pin_count - 1 = 39"),
    ("cycloid_pinhousing.toml", "cycloid.disc_count", 0,
     "cycloid.disc_count = 0 is outside the valid range [1, 4]"),
    ("cycloid_pinhousing.toml", "cycloid.pin_structure", "floating",
     "cycloid.pin_structure = 'floating' is not one of ['conventional', 'integral']"),
    ("cycloid_pinhousing.toml", "cycloid.equidistant_modification_mm", -0.01,
     "cycloid.equidistant_modification_mm - move_distance_modification_mm = -0.01 is outside "
     "the valid range [0, inf): the disc would interfere"),
    ("cycloid_pinhousing.toml", "cycloid.disc_holes.crank_hole_circle_radius_mm", 90.0,
     "cycloid: crank_0 hole reaches radius 101 mm, outside the valid range (0, 96.5) mm"),
    ("cycloid_pinhousing.toml", "cycloid.face_width_mm", float("nan"),
     "cycloid.face_width_mm = nan is outside the valid range [0.1, 1000]"),
    ("cycloid_pinhousing.toml", "material.poisson_ratio", 0.5,
     "material.poisson_ratio = 0.5 is outside the valid range [0, 0.5)"),
    ("cycloid_pinhousing.toml", "material.youngs_modulus_GPa", -208.0,
     "material.youngs_modulus_GPa = -208.0 is outside the valid range [1, 1000]"),
    ("cycloid_pinhousing.toml", "operating.input_speed_rpm", -10.0,
     "operating.input_speed_rpm = -10.0 is outside the valid range [0.01, 20000]"),
    ("cycloid_pinhousing.toml", "operating.output_torque_Nm", -1.0,
     "operating.output_torque_Nm = -1.0 is outside the valid range [0.001, 1e+06]"),
    ("cycloid_pinhousing.toml", "friction.coefficient", 1.5,
     "friction.coefficient = 1.5 is outside the valid range [0, 1]"),
    ("cycloid_pinhousing.toml", "first_stage.pressure_angle_deg", 45.0,
     "first_stage.pressure_angle_deg = 45.0 is outside the valid range [10, 35]"),
    ("cycloid_pinhousing.toml", "case.stated_ratio", 120,
     "case.stated_ratio = 120 disagrees with the ratio 121 computed from the tooth numbers"),
    ("cycloid_pinhousing.toml", "case.drive", "harmonic",
     "case.drive = 'harmonic' is not one of ['cycloid', 'rv', 'sine']"),
    ("cycloid_pinhousing.toml", "cycloid.pin_circle_radius", 100.0,
     "cycloid.pin_circle_radius is not a known key"),
    ("cycloid_pinhousing.toml", "cycloid.eccentricity_mm", "one",
     "eccentricity_mm = 'one' is not a number"),
    ("sine_prototype.toml", "sine.ring_teeth", 79,
     "sine.ring_teeth = 79 must exceed planet_teeth = 79"),
    ("sine_prototype.toml", "sine.centre_distance_mm", 0.5,
     "sine.centre_distance_mm = 0.5 is not module*(ring_teeth-planet_teeth)/2 = 0.45"),
    ("sine_prototype.toml", "sine.tooth_height_mm", -0.4,
     "sine.tooth_height_mm = -0.4 is outside the valid range (0, 100]"),
    ("sine_prototype.toml", "lubricant.dynamic_viscosity_Pa_s", 0.0,
     "lubricant.dynamic_viscosity_Pa_s = 0.0 is outside the valid range [0.0001, 10]"),
    ("sine_prototype.toml", "lubricant.roughness_Ra_um", -0.1,
     "lubricant.roughness_Ra_um = -0.1 is outside the valid range [0, 10]"),
    ("sine_prototype.toml", "measured.0.efficiency", 1.2,
     "measured[0].efficiency = 1.2 is outside the valid range (0, 1]"),
    ("sine_prototype.toml", "output_mechanism.pin_count", 1,
     "output_mechanism.pin_count = 1 is outside the valid range [2, 24]"),
    ("rv40e.toml", "rv.pin_count", 39, "rv.pin_count = 39 must exceed disc_teeth = 39"),
    ("rv40e.toml", "rv.mesh_efficiency", 1.2,
     "rv.mesh_efficiency = 1.2 is outside the valid range [0.5, 1]"),
    ("rv40e.toml", "operating.input_power_kW", -2.27,
     "operating.input_power_kW = -2.27 is outside the valid range [1e-06, 10000]"),
]


def _set(mapping, dotted, value):
    keys = dotted.split(".")
    node = mapping
    for k in keys[:-1]:
        node = node[int(k)] if k.isdigit() else node[k]
    node[keys[-1]] = value


@pytest.mark.parametrize("name, key, value, text", RULES, ids=[f"{r[1]}={r[2]}" for r in RULES])
def test_rule_refuses_with_key_value_and_range(cases_dir, name, key, value, text):
    raw = copy.deepcopy(_raw(cases_dir, name))
    _set(raw, key, value)
    with pytest.raises(CaseError) as exc:
        parse_case(raw)
    msg = str(exc.value)
    assert text in msg
    assert "\n" not in msg


def test_missing_section_and_key(cases_dir):
    raw = _raw(cases_dir, "cycloid_pinhousing.toml")
    del raw["cycloid"]["pin_radius_mm"]
    with pytest.raises(CaseError, match=r"^cycloid.pin_radius_mm is required$"):
        parse_case(raw)
    raw = _raw(cases_dir, "cycloid_pinhousing.toml")
    del raw["cycloid"]
    with pytest.raises(CaseError, match=r"\[cycloid\] section is required for drive = 'cycloid'"):
        parse_case(raw)
    raw = _raw(cases_dir, "cycloid_pinhousing.toml")
    raw["gearbox"] = {}
    with pytest.raises(CaseError, match=r"\[gearbox\] is not a known section"):
        parse_case(raw)


def test_load_case_names_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[case]\nname = 'x'\ndrive = 'sine'\n[sine]\nplanet_teeth = 79\n")
    with pytest.raises(CaseError, match=r"bad.toml: sine.ring_teeth is required"):
        load_case(bad)
    with pytest.raises(CaseError, match=r"nope.toml: no such case file"):
        load_case(tmp_path / "nope.toml")
    (tmp_path / "broken.toml").write_text("[case\n")
    with pytest.raises(CaseError, match=r"broken.toml: not valid TOML"):
        load_case(tmp_path / "broken.toml")
