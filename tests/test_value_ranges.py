"""Values that crashed a command or passed silently (issue 45): each key has one range,
refused at load (so by `check` and by every command) in one line naming the key.

Facts checked: [published] figures in their unit's range and a [lo, hi] range in order;
the duty cycle's torque and speed in [operating]'s ranges; the supports' sizes bounded
(`check` refuses what a command would fail on); `efficiency --thermal --duration-h`
bounded, before any work; every numeric key of the schema with a finite upper bound, and
1e300 in each key that had none refused naming it, by `check` and by a command alike.
"""
from __future__ import annotations

import copy
import tomllib

import pytest

from toothfem import cli
from toothfem.case import parse_case
from toothfem.errors import CaseError


def _with(cases_dir, name, dotted, value):
    with open(cases_dir / name, "rb") as fh:
        raw = tomllib.load(fh)
    raw = copy.deepcopy(raw)
    node = raw
    *path, last = dotted.split(".")
    for k in path:
        node = node.setdefault(k, {}) if not k.isdigit() else node[int(k)]
    node[last] = value
    return raw


@pytest.mark.parametrize("name, key, value, text", [
    ("rv40e.toml", "published.rated_torque_Nm", -412.0,
     "published.rated_torque_Nm = -412.0 is outside the valid range (0, 1e+07]"),
    ("rv40e.toml", "published.rated_torque_Nm", 1e300,
     "published.rated_torque_Nm = 1e+300 is outside the valid range (0, 1e+07]"),
    ("rv40e.toml", "published.rated_life_h", -6000.0,
     "published.rated_life_h = -6000.0 is outside the valid range (0, 1e+07]"),
    ("rv40e.toml", "published.efficiency_range", [0.95, 0.80],
     "published.efficiency_range = [0.95, 0.8] is a range with its least above its greatest"),
    ("rv40e.toml", "published.efficiency_range", [0.8, 95.0],
     "published.efficiency_range[1] = 95.0 is outside the valid range [0, 1]"),
    ("rv40e.toml", "duty_cycle.0.input_speed_rpm", 1e300,
     "duty_cycle[0].input_speed_rpm = 1e+300 is outside the valid range"),
    ("rv40e.toml", "duty_cycle.0.output_torque_Nm", 1e300,
     "duty_cycle[0].output_torque_Nm = 1e+300 is outside the valid range"),
    ("cycloid_khv.toml", "supports.bearing_roller_diameter_mm", 1e300,
     "supports.bearing_roller_diameter_mm = 1e+300 is outside the valid range"),
    ("cycloid_khv.toml", "supports.bearing_roller_length_mm", 1e300,
     "supports.bearing_roller_length_mm = 1e+300 is outside the valid range"),
])
def test_a_value_out_of_its_range_is_refused_naming_its_key(cases_dir, name, key, value,
                                                             text):
    with pytest.raises(CaseError) as exc:
        parse_case(_with(cases_dir, name, key, value))
    assert text in str(exc.value) and "\n" not in str(exc.value), str(exc.value)


def test_check_refuses_what_the_commands_refuse(cases_dir, tmp_path, capsys):
    """`check` on a file with a roller of 1e300 mm: exit 2, one line naming the key."""
    text = (cases_dir / "cycloid_khv.toml").read_text()
    assert "bearing_roller_length_mm = 8.0" in text
    case = tmp_path / "khv.toml"
    case.write_text(text.replace("bearing_roller_length_mm = 8.0",
                                 "bearing_roller_length_mm = 1e300"))
    assert cli.main(["check", str(case)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "supports.bearing_roller_length_mm" in err, err


@pytest.mark.parametrize("hours", ["1e9", "0", "-1", "nan"])
def test_warm_up_duration_bounded(cases_dir, capsys, monkeypatch, hours):
    """--duration-h outside (0, 100] h: refused in one line before the heat balance."""
    from toothfem import durability
    from toothfem import maps  # noqa: F401 (binds heat_balance by name: imported before the
    # patch, else a first import under it keeps `never` for the worker's later tests)

    def never(*a, **kw):
        raise AssertionError("computed before --duration-h was checked")

    monkeypatch.setattr(durability.th, "heat_balance", never)
    assert cli.main(["efficiency", str(cases_dir / "rv40e.toml"), "--thermal",
                     "--duration-h", hours]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--duration-h = " in err and "(0, 100]" in err, err


def test_meshing_names_its_argument_for_a_grid_of_angles_or_a_case(cases_dir):
    """The API (issue 45): a 2-D array of angles and a Case where a geometry belongs are
    refused in one line naming the argument and what is valid."""
    import numpy as np

    import toothfem
    from toothfem.errors import GeometryError
    from toothfem.geometry import cycloid_mesh
    from toothfem.geometry.sine import meshing as sine_meshing

    cyc = toothfem.load_case(cases_dir / "cycloid_pinhousing.toml")
    sine = toothfem.load_case(cases_dir / "sine_prototype.toml")
    for call, text in [
            (lambda: cycloid_mesh.meshing(cyc.cycloid.geometry(), np.zeros((3, 4))),
             "crank_angle_rad has shape (3, 4); valid: a scalar or a 1-D array"),
            (lambda: cycloid_mesh.meshing(cyc, [0.1]),
             "geom = Case is not a CycloidGeometry; valid: case.cycloid.geometry()"),
            (lambda: sine_meshing(sine.sine.geometry(), np.zeros((2, 2))),
             "crank_angle_rad has shape (2, 2)"),
            (lambda: sine_meshing(sine, [0.1]),
             "pair = Case is not a SineGearPair; valid: case.sine.geometry()")]:
        with pytest.raises(GeometryError) as exc:
            call()
        assert text in str(exc.value), str(exc.value)
    assert cycloid_mesh.meshing(cyc.cycloid.geometry(), 0.1).gap.shape == (1, 40)


def _schema_sections():
    """Every section of the case schema (the dataclasses of the case modules that check
    their keys against the ranges in their fields' metadata), with the [case] table."""
    import dataclasses

    from toothfem import case, case_design, case_running, case_sections
    seen = {case.Case}
    for module in (case_sections, case_running, case_design):
        seen |= {c for c in vars(module).values() if isinstance(c, type)
                 and issubclass(c, case_sections._Section) and dataclasses.is_dataclass(c)
                 and c.__module__ == module.__name__}
    return sorted(seen, key=lambda c: c.__name__)


def test_every_numeric_key_has_an_upper_bound():
    """Each number a case can hold has a finite upper bound in its key's range (issue 45:
    1e300 in a bearing or thermal key passed `check` and ended in a command's overflow)."""
    import dataclasses
    import math

    from toothfem.case_checks import expected_type
    unbounded = [f"{cls.__name__}.{f.name}" for cls in _schema_sections()
                 for f in dataclasses.fields(cls)
                 if f.metadata and f.metadata.get("choices") is None
                 and expected_type(f) != "string"
                 and not math.isfinite(f.metadata.get("hi") or math.inf)]
    assert len(_schema_sections()) > 15 and unbounded == [], unbounded


#: The keys that had no upper bound until issue 45, each with a case that has its section.
BOUNDED_AT_LAST = [
    ("rv40e.toml", f"material.{k}") for k in (
        "allowable_contact_stress_MPa", "static_contact_stress_MPa", "yield_strength_MPa",
        "fatigue_limit_MPa")] + [
    ("cycloid_khv.toml", "cycloid.housing_outer_radius_mm"),
    ("sine_prototype.toml", "sine.tooth_height_mm"),
    ("sine_prototype.toml", "sine.centre_distance_mm")] + [
    ("rv40e.toml", f"bearings.{k}") for k in (
        "eccentric_pitch_diameter_mm", "eccentric_dynamic_rating_kN", "main_pitch_diameter_mm",
        "main_dynamic_rating_kN", "main_span_mm", "main_preload_N", "external_radial_load_N",
        "external_axial_load_N", "external_moment_Nm", "external_radial_offset_mm",
        "external_axial_radius_mm")] + [
    ("rv40e.toml", f"thermal.{k}") for k in ("housing_area_m2", "heat_capacity_J_K")]


@pytest.mark.parametrize("name, key", BOUNDED_AT_LAST)
def test_1e300_refused_in_one_line_naming_the_key(cases_dir, name, key):
    with pytest.raises(CaseError) as exc:
        parse_case(_with(cases_dir, name, key, 1e300))
    msg = str(exc.value)
    assert f"{key} = 1e+300 is outside the valid range" in msg and "\n" not in msg, msg


@pytest.mark.parametrize("command", [["check"], ["efficiency", "--thermal"]])
def test_every_command_refuses_an_external_load_of_1e300(cases_dir, tmp_path, capsys,
                                                         command):
    """`check` and a command share the loader: exit 2, one line naming the key."""
    text = (cases_dir / "rv40e.toml").read_text()
    assert "\n[bearings]" in text
    case = tmp_path / "rv.toml"
    case.write_text(text.replace("\n[bearings]", "\n[bearings]\nexternal_radial_load_N = 1e300",
                                 1))
    assert cli.main([command[0], str(case), *command[1:]]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "bearings.external_radial_load_N = 1e+300" in err, err
