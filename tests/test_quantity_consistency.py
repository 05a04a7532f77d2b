"""Issue 41, one quantity, one number: the figures two commands both report agree, or say
which variant each is; benchmarks/quantity_consistency.py finds where they do not."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from toothfem import load_case
from toothfem.derived import derived
from toothfem.fem.drives import drive_for

ROOT = Path(__file__).resolve().parents[1]


def _script():
    spec = importlib.util.spec_from_file_location(
        "quantity_consistency", ROOT / "benchmarks" / "quantity_consistency.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_check_disc_torque_is_the_drives_member_torque():
    """`check` prints the torque on one disc by the drive's one torque rule, the one
    `contact` and `run` load the disc with: a 2K-V disc carries T (1 - 1/i) Za/Zb over the
    discs (RV-40E: 412 (1 - 1/121) 39/40 / 2 = 199.19 N m, where check said 206.0), a
    K-H-V disc the output torque over the discs times the load factor."""
    case = load_case(ROOT / "cases" / "rv40e.toml")
    d = derived(case)
    hand = 412.0 * (1 - 1 / 121) * 39 / 40 / 2
    # check rounds to 10 significant figures (derived._r)
    assert d["disc_torque_Nm"] == pytest.approx(hand, rel=1e-9)
    assert d["disc_torque_Nm"] == pytest.approx(drive_for(case).member_torque(412.0),
                                                 rel=1e-9)
    ph = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    assert derived(ph)["disc_torque_Nm"] == pytest.approx(
        1.1 * 167.0 * (1 - 1 / 121) * 39 / 40 / 2, rel=1e-9)
    khv = load_case(ROOT / "cases" / "cycloid_khv.toml")
    assert derived(khv)["disc_torque_Nm"] == pytest.approx(
        drive_for(khv).member_torque(40.0), rel=1e-9)


def test_contact_pins_reach_the_system_model():
    """`contact --pins conventional` on the pin-housing case (integral pins) changes the
    reducer's figures too: the system model takes the pins asked for, not the case's."""
    from toothfem.pipeline import contact_analysis

    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    assert case.cycloid.pin_structure == "integral"
    own = contact_analysis(case, positions=36, field="none").summary
    conv = contact_analysis(case, positions=36, field="none", pins="conventional").summary
    assert conv["pin_structure"] == "conventional"
    for key in ("transmission_error_reducer_arcsec", "max_force_reducer_N",
                "transmission_error_reducer_mesh_arcsec"):
        assert conv[key] != own[key], key
    # the reducer's mesh part follows the held disc's: conventional pins in their grooves
    # are stiffer than the integral ones here (held disc 9.45 against 9.92 arcsec)
    assert (conv["transmission_error_reducer_mesh_arcsec"]
            < own["transmission_error_reducer_mesh_arcsec"]) == (
        conv["transmission_error_arcsec"] < own["transmission_error_arcsec"])


def test_system_model_takes_the_pin_structure():
    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    drive = drive_for(case)
    system = drive.system_model(drive.supports(case.to_si().supports), 36,
                                pin_structure="conventional")
    assert {s.solver.model.describe()["pin_structure"] for s in system.slots} == \
        {"conventional"}
    plain = drive.system_model(drive.supports(case.to_si().supports), 36)
    assert {s.solver.model.describe()["pin_structure"] for s in plain.slots} == \
        {"integral"}


def test_script_finds_two_values_under_one_name():
    """The script fails on check's old disc torque (206.0 against contact's 199.19 N m:
    check declares no variant, so it meets contact's in any mode), and not on two
    declared variants (efficiency at analytic and at FE loads)."""
    q = _script()
    values = {}
    for out, obj in (("check", {"disc_torque_Nm": 206.0}),
                     ("contact", {"mode": "cycle", "disc_torque_Nm": 199.19}),
                     ("eff a", {"loads": "analytic", "efficiency": 0.8732}),
                     ("eff f", {"loads": "fem", "efficiency": 0.8862})):
        for label, (where, v) in q.numbers(obj).items():
            values.setdefault(label, {})[f"{out}: {where}"] = v
    bad = q.disagreements(values)
    assert set(bad) == {"disc_torque_Nm", "disc_torque_Nm  [mode=cycle]"}
    values["disc_torque_Nm"]["check: disc_torque_Nm"] = 199.19
    assert not q.disagreements(values)
    # within the written tolerance (rounding to 10 significant figures) it passes
    values["disc_torque_Nm"]["check: disc_torque_Nm"] = 199.19 * (1 + 1e-9)
    assert not q.disagreements(values)


def test_efficiency_thermal_json_warnings_hold_the_heat_balances(capsys):
    """`efficiency --thermal --json`: the 60 C warning is in the command's `warnings`
    (not only inside `thermal.warnings`), each message once; the screen says the same."""
    import json

    from toothfem import cli

    path = str(ROOT / "cases" / "rv40e.toml")
    assert cli.main(["efficiency", path, "--thermal", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    messages = [w["message"] for w in out["warnings"]]
    assert len(messages) == len(set(messages))
    hot = [w for w in out["warnings"] if w["quantity"].startswith("case (oil) temperature")]
    assert len(hot) == 1 and hot[0]["limit"] == 60.0 and "Nabtesco" in hot[0]["source"]
    assert {w["message"] for w in out["thermal"]["warnings"]} <= set(messages)
    assert cli.main(["efficiency", path, "--thermal"]) == 0
    screen = [x[len("warning: "):] for x in capsys.readouterr().out.splitlines()
              if x.startswith("warning: ")]
    assert screen == messages


def test_run_warnings_say_a_shared_warning_once():
    """rv_paper_example's torque above its rating is found by the contact, each
    efficiency source and the heat balance alike: the run says it once, bare; a warning
    one part alone found (its own film ratio) says whose it is."""
    from toothfem.limits import run_warnings

    torque = {"message": "output torque: 1524 N m, above the limit 412 N m (x)"}
    film_a = {"message": "film ratio of the mesh contacts: 0.0001757, below 0.1"}
    film_f = {"message": "film ratio of the mesh contacts: 0.0001873, below 0.1"}
    lines = run_warnings({"warnings": [torque]},
                         {"analytic": {"warnings": [torque, film_a]},
                          "fem": {"warnings": [torque, film_f]},
                          "rv_split_power": {"warnings": [torque]}},
                         {"heat": {"warnings": [torque]}})
    assert lines == [torque["message"], f"efficiency (analytic): {film_a['message']}",
                     f"efficiency (fem): {film_f['message']}"]


def test_measured_miss_is_a_warning():
    """The RV-40E's measured 73.23 % against the model's 87.4 % (-14 points) is a
    warning with its source; the sine prototype's measured point, 0.07 points from the
    model, is not (docs/efficiency.md)."""
    from toothfem.limits import MEASURED_GAP_POINTS, measured_efficiency

    case = load_case(ROOT / "cases" / "rv40e.toml")
    (m,) = case.measured
    (hit,) = measured_efficiency(case.measured, [0.8738])
    assert hit.value == pytest.approx(14.15, abs=0.01) and hit.limit == MEASURED_GAP_POINTS
    assert "-14.2 points" in str(hit) and "Lv 2016" in str(hit)
    assert not measured_efficiency(case.measured, [m.efficiency + 0.0007])
    assert measured_efficiency(case.measured, [m.efficiency - 0.03])      # 3 points high


def test_stiffness_table_puts_each_unit_in_its_column():
    """`toothfem stiffness`'s table: the unit column holds each row's unit (it was empty,
    the units in brackets in the quantity), a share's % with it."""
    from toothfem.commands.stiffness import _with_unit
    from toothfem.report.stiffness import datasheet_rows

    summary = {"rated_torque_Nm": 412.0, "rated_torque_assumed": False,
               "torsional_rigidity_Nm_per_arcmin": 69.26, "lost_motion_arcmin": 0.409,
               "backlash_arcmin": 0.0, "hysteresis_loss_arcmin": 0.048,
               "te_torque_Nm": 412.0, "te_mean_arcsec": 367.4,
               "te_peak_to_peak_arcsec": 4.94, "te_full_period_pitches": 39,
               "te_positions_per_pitch": 12, "compliance_shares": {"mesh": 0.036}}
    rows = [_with_unit(w, v) for w, v in datasheet_rows(summary)]
    units = {w: u for w, u, _ in rows}
    assert units["rated torque"] == "N m"
    assert units["torsional rigidity 50-100 %"] == "N m/arcmin"
    assert units["transmission error of the reducer at 412 N m, mean"] == "arcsec"
    assert units["compliance share: mesh"] == "%"
    assert all(u for u in units.values())
    assert not any("[" in w for w in units)
