"""Values that crashed a command or passed silently (issue 45): each key has one range,
refused at load (so by `check` and by every command) in one line naming the key.

Facts checked: [published] figures in their unit's range and a [lo, hi] range in order;
the duty cycle's torque and speed in [operating]'s ranges; the supports' sizes bounded
(`check` refuses what a command would fail on); `efficiency --thermal --duration-h`
bounded, before any work.
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
        node = node[k] if not k.isdigit() else node[int(k)]
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
