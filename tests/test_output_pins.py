"""The output mechanism's pins in the members' holes (issue 41, missing results): the
K-H-V case's and the sine pair's contact summary gives the output pins' largest force
and Hertz pressure from the system model, in the contact table (and so report.md), with a
warning where the pressure passes the allowable."""
from __future__ import annotations

import dataclasses
import math

import pytest

from toothfem.case import load_case
from toothfem.pipeline import contact_analysis
from toothfem.report.files import contact_labels
from toothfem.report.summary import contact_rows, text


@pytest.fixture(scope="module")
def khv(cases_dir):
    return load_case(cases_dir / "cycloid_khv.toml")


@pytest.fixture(scope="module")
def khv_contact(khv):
    return contact_analysis(khv, positions=12, field="none")


def test_khv_output_pins_force_and_hertz_pressure(khv, khv_contact):
    """The largest output-pin force carries part of the disc torque (its moment at the
    pin circle below the disc's torque, above the torque shared evenly by all pins), its
    P_h is Hertz's line contact of the case's roller in its hole (sqrt(w E* / (pi R)),
    1/R = 1/r_roller - 1/r_hole, w over the disc's face width; 1e-9: the same formula in
    floating point), and the pins' largest figures are those of the pin that carries most."""
    s = khv_contact.summary
    om, m = khv.output_mechanism, khv.material
    t_disc = s["disc_torque_Nm"]
    r_w = om.pin_hole_circle_radius_mm * 1e-3
    f = s["output_pin_force_max_N"]
    assert t_disc / (om.pin_count * r_w) < f < t_disc / r_w
    r = 1 / (1 / om.roller_radius_mm - 1 / om.hole_radius_mm) * 1e-3
    e_star = m.youngs_modulus_GPa * 1e9 / (2 * (1 - m.poisson_ratio ** 2))
    w = f / (khv.cycloid.face_width_mm * 1e-3)
    assert s["output_pin_ph_max_MPa"] == pytest.approx(
        math.sqrt(w * e_star / (math.pi * r)) / 1e6, rel=1e-9)
    assert s["output_pin_ph_contact"]["equivalent_radius_mm"] == pytest.approx(r * 1e3)
    assert s["output_pin_ph_contact"]["contact"] == "roller r 5.5 mm in hole r 6.7 mm"
    assert max(s["output_pin_force_max_by_pin_N"]) == f
    assert len(s["output_pin_ph_max_by_pin_MPa"]) == om.pin_count
    assert 1 <= s["output_pins_in_contact_min"] <= om.pin_count // 2 + 1
    # at the case's allowable pressure nothing to say of them
    assert not [w for w in s["warnings"] if "output pins" in w["quantity"]]


def test_khv_output_pins_in_the_contact_table(khv, khv_contact):
    """The contact table (the terminal's, report.md's) holds the output pins' rows."""
    rows = contact_rows(khv_contact.summary, contact_labels(khv_contact), khv.published)
    by = {q: (u, v["ours"]) for q, u, v in rows}
    force = by["largest output pin force on a hole (system model, one pitch)"]
    assert force == ("N", khv_contact.summary["output_pin_force_max_N"])
    assert by["largest Hertz pressure P_h, output pin (roller) on its hole, one pitch"][0] \
        == "MPa"
    assert "output pins carrying on one disc, fewest" in text(rows)


def test_output_pins_above_the_allowable_pressure_warn(khv, khv_contact):
    """Below the output pins' P_h, the allowable contact pressure is a warning naming them,
    its value and the material's key."""
    ph = khv_contact.summary["output_pin_ph_max_MPa"]
    low = dataclasses.replace(khv, material=dataclasses.replace(
        khv.material, allowable_contact_stress_MPa=0.9 * ph))
    warned = [w for w in contact_analysis(low, positions=12, field="none").summary["warnings"]
              if "output pins" in w["quantity"]]
    assert len(warned) == 1
    assert warned[0]["value"] == pytest.approx(ph)
    assert warned[0]["limit"] == pytest.approx(0.9 * ph)
    assert "material.allowable_contact_stress_MPa" in warned[0]["source"]


def test_sine_pair_output_pins(cases_dir):
    """The sine pair's bare pins (no roller) in holes of the pin radius plus the
    eccentricity: the contact named so, P_h Hertz's on that radius."""
    case = load_case(cases_dir / "sine_prototype.toml")
    s = contact_analysis(case, positions=6, field="none").summary
    c = s["output_pin_ph_contact"]
    assert c["contact"].startswith("pin r 6 mm in hole r ")
    hole = float(c["contact"].split("hole r ")[1].split(" mm")[0])
    assert hole > 6.0
    assert s["output_pin_ph_max_MPa"] > 0 and s["output_pin_force_max_N"] == c["force_N"]
