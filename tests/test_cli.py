"""The console script: `main(argv)` as a user calls it."""
import json
import re

import numpy as np
import pytest

from toothfem import cli
from toothfem.maps import TORQUE_GRID


def test_check_prints_derived_quantities(cases_dir, capsys):
    assert cli.main(["check", str(cases_dir / "cycloid_pinhousing.toml")]) == 0
    out = capsys.readouterr().out
    assert "OK" in out and "K1" in out and "ratio" in out


def test_check_json(cases_dir, capsys):
    assert cli.main(["check", str(cases_dir / "rv40e.toml"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["ratio"] == pytest.approx(121, rel=1e-12)
    assert d["crank_to_output_ratio"] == pytest.approx(-39, rel=1e-12)


def test_cycloid_geometry_files(geometry_of):
    out, _ = geometry_of("cycloid_pinhousing")       # `toothfem geometry`, shared (conftest)
    head = (out / "profile.csv").read_text().splitlines()[0]
    assert head == "x_mm,y_mm"
    xy = np.loadtxt(out / "profile.csv", delimiter=",", skiprows=1)
    r = np.hypot(xy[:, 0], xy[:, 1])
    # working profile between root (Rz - A - rz = 97) and tip (Rz + A - rz = 99) radius
    assert r.min() == pytest.approx(97.0, abs=1e-6) and r.max() == pytest.approx(99.0, abs=1e-3)
    assert (out / "drawing.png").stat().st_size > 10_000
    summary = json.loads((out / "check.json").read_text())
    assert summary["disc_polygon_valid"] is True


def test_error_is_one_line_nonzero_exit(tmp_path, capsys, cases_dir):
    bad = tmp_path / "bad.toml"
    bad.write_text((cases_dir / "cycloid_pinhousing.toml").read_text()
                   .replace("eccentricity_mm = 1.0", "eccentricity_mm = 3.0"))
    out = tmp_path / "never"
    assert cli.main(["geometry", str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "cycloid.eccentricity_mm = 3.0 is outside the valid range (0, 2.5)" in err
    assert not out.exists()
    assert cli.main(["check", str(tmp_path / "missing.toml")]) == 2
    assert "no such case file" in capsys.readouterr().err


def test_rv_case_profiles_come_from_its_disc(geometry_of):
    """An RV case with its [cycloid] disc has a profile to write (issue 15 item 3; it was
    refused before the drive abstraction): `toothfem geometry`, shared (conftest)."""
    out, _ = geometry_of("rv40e")
    assert (out / "profile.csv").exists()


def test_failed_run_leaves_no_half_written_folder(cases_dir, tmp_path, monkeypatch):
    """The CSV is written, then the drawing fails: the output folder must not appear, and an
    existing folder from an earlier run must stay as it was."""
    from toothfem.report import plots

    out = tmp_path / "geo"
    out.mkdir()
    (out / "old.txt").write_text("earlier run")

    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(plots, "cycloid_drawing", boom)
    assert cli.main(["geometry", str(cases_dir / "cycloid_pinhousing.toml"), "--out",
                     str(out)]) == 2
    assert sorted(p.name for p in out.iterdir()) == ["old.txt"]
    assert [p.name for p in tmp_path.iterdir()] == ["geo"]


def test_help_lists_commands(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    out = capsys.readouterr().out
    assert "check" in out and "geometry" in out


def test_the_console_script_answers_help_without_numpy_or_the_fe():
    """The installed console script (a real process, its exit path) lists every command
    under --help, and a --help imports neither numpy nor scipy nor the FE: each command
    imports what it needs inside its own functions (toothfem/cli.py;
    benchmarks/cli_startup.py times it). A command's own --help builds its arguments."""
    import shutil
    import subprocess
    import sys
    import textwrap
    from pathlib import Path

    script = shutil.which("toothfem", path=str(Path(sys.executable).parent))
    assert script, f"no toothfem console script beside {sys.executable}"
    p = subprocess.run([script, "--help"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    assert all(f"    {c.NAME}" in p.stdout for c in cli.COMMANDS), p.stdout
    probe = textwrap.dedent("""\
        import json, sys
        from toothfem.cli import main
        for argv in (["--help"], ["efficiency", "--help"]):
            try:
                main(argv)
            except SystemExit as e:
                loaded = {m if m.startswith("toothfem.") else m.split(".")[0]
                          for m in sys.modules}
                print("LOADED", json.dumps([argv[0], e.code, sorted(loaded)]))
        """)
    p = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 0, p.stderr
    top, own = (json.loads(line.split(" ", 1)[1]) for line in p.stdout.splitlines()
                if line.startswith("LOADED "))
    heavy = {"numpy", "scipy", "toothfem.fem", "toothfem.geometry", "toothfem.efficiency"}
    assert top[:2] == ["--help", 0] and not heavy & set(top[2]), top
    assert own[:2] == ["efficiency", 0] and "toothfem.efficiency" in own[2]


def test_contact_command_writes_results(cases_dir, tmp_path, capsys):
    """Three positions, structural field: CSV columns, summary keys, VTU and PNGs."""
    import csv

    import meshio

    out = tmp_path / "contact"
    assert cli.main(["contact", str(cases_dir / "cycloid_pinhousing.toml"), "--positions", "3",
                     "--field", "structural", "--out", str(out)]) == 0
    with open(out / "load_sharing.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["position_deg", "contact_id", "force_N", "moment_arm_mm",
                       "half_width_mm", "ph_MPa", "gap_mm"]
    assert 3 * 19 <= len(rows) - 1 <= 3 * 20
    s = json.loads((out / "summary.json").read_text())
    for key in ("pins_in_contact_max", "max_force_N", "max_ph_MPa", "transmission_error_arcsec"):
        assert key in s
    assert s["pins_in_contact_max"] == 20 and 240 < s["max_force_N"] < 270
    assert s["torque_equilibrium_max_rel_error"] < 1e-8
    vtu = meshio.read(out / "disc_worst_position.vtu")       # mm and MPa, named so
    assert {"displacement_mm", "von_mises_MPa"} <= set(vtu.point_data)
    assert 98.0 < np.hypot(*vtu.points[:, :2].T).max() < 100.0    # the disc's tips [mm]
    for png in ("load_per_pin.png", "load_around_ring.png", "transmission_error.png",
                "von_mises.png", "von_mises_contact.png"):
        assert (out / png).stat().st_size > 5_000
    printed = capsys.readouterr().out     # a table on screen, the case's paper beside ours
    assert "pins in contact, most" in printed and "published" in printed
    assert f"to {out.resolve()}" in printed


def test_contact_command_refuses_bad_torque_and_pins_on_sine(cases_dir, tmp_path, capsys):
    assert cli.main(["contact", str(cases_dir / "sine_prototype.toml"), "--pins", "integral",
                     "--out", str(tmp_path / "o")]) == 2
    assert "--pins applies to cycloid drives" in capsys.readouterr().err
    assert cli.main(["contact", str(cases_dir / "cycloid_pinhousing.toml"), "--torque-Nm", "-5",
                     "--out", str(tmp_path / "o")]) == 2
    assert "--torque-Nm = -5.0 is outside the valid range [0.001, 1e+06]" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_efficiency_command_json(cases_dir, capsys):
    assert cli.main(["efficiency", str(cases_dir / "sine_prototype.toml"), "--torque-Nm", "28",
                     "--speed-rpm", "500", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert 0.5 < d["efficiency"] < 1
    assert set(d["losses"]) >= {"mesh", "eccentric_bearing", "output_mechanism", "churning"}
    # the losses close the energy balance
    assert d["input_power_W"] - d["output_power_W"] == pytest.approx(sum(d["losses"].values()),
                                                                     rel=1e-12)


def test_efficiency_command_rv_paper_method_from_declared_input_power(cases_dir, capsys):
    """The case declares 2.27 kW input: the output torque follows from the method's own
    efficiency, so the RV paper's L1 and L2 come out in watts (Eqs. 13-14)."""
    assert cli.main(["efficiency", str(cases_dir / "rv_paper_example.toml"), "--method",
                     "rv_split_power", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["input_power_W"] == pytest.approx(2270.0, rel=1e-9)
    assert d["losses"]["sun_planet_mesh"] == pytest.approx(136.2, abs=0.05)
    assert d["losses"]["cycloid_mesh"] == pytest.approx(131.52, abs=0.01)
    assert d["efficiency"] == pytest.approx(0.882, abs=5e-4)


def test_efficiency_command_bad_input(cases_dir, capsys):
    assert cli.main(["efficiency", str(cases_dir / "sine_prototype.toml"),
                     "--oil-temp-C", "-150"]) == 2
    err = capsys.readouterr().err.strip()
    assert "oil_temp_C = -150.0 is outside the valid range" in err and "\n" not in err


def test_run_command_writes_report(sine_run):
    out, printed = sine_run        # `toothfem run` of the sine prototype, shared (conftest)
    report = (out / "report.md").read_text()
    for png in ("geometry/drawing.png", "efficiency_vs_torque.png", "efficiency_map.png",
                "efficiency_temperature.png", "loss_shares.png"):
        assert f"]({png})" in report and (out / png).stat().st_size > 10_000
    d = json.loads((out / "efficiency.json").read_text())
    assert 0.5 < d["analytic"]["efficiency"] < 1
    rows = (out / "efficiency_vs_torque.csv").read_text().splitlines()
    assert rows[0] == "output_torque_Nm,efficiency_analytic" and len(rows) == 1 + len(TORQUE_GRID)
    # a table on screen, the folder by its name
    assert re.search(r"^efficiency +% +[\d.]+ +83\.72$", printed, re.M)  # the paper beside
    assert f"wrote the report to {(out / 'report.md').resolve()}" in printed
    assert ".run." not in printed              # not the temporary folder's name


@pytest.mark.slow
def test_contact_command_sine_pair(cases_dir, tmp_path, capsys):
    """The sine pair through the CLI: multi-tooth contact, FE pressure where Hertz fails,
    the planet's field from the detailed mode at the worst position."""
    out = tmp_path / "sine"
    assert cli.main(["contact", str(cases_dir / "sine_prototype.toml"), "--positions", "6",
                     "--torque-Nm", "28", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["teeth_in_contact_max"] >= 2                  # teeth sharing the load
    assert "pins_in_contact_max" not in s                  # the sine pair has teeth
    assert s["torque_equilibrium_max_rel_error"] < 1e-8
    assert s["ph_from_fe_contacts"] == s["hertz_invalid_contacts"] > 0
    assert abs(s["detailed_check_at_worst_position"]["max_force_ratio_detailed_to_cycle"]
               - 1) < 0.02                                 # issue 3: modes within 2 %
    for png in ("load_per_tooth.png", "load_around_ring.png", "transmission_error.png",
                "von_mises.png", "von_mises_contact.png"):
        assert (out / png).stat().st_size > 5_000
    rows = (out / "load_sharing.csv").read_text().splitlines()
    assert rows[0] == ("position_deg,contact_id,force_N,moment_arm_mm,half_width_mm,ph_MPa,"
                       "gap_mm") and len(rows) > 6


def test_an_ascii_terminal_and_a_stale_matplotlib_backend_are_no_errors(cases_dir, tmp_path):
    """PYTHONIOENCODING=ascii (the efficiency table holds en dashes and Greek letters) and
    an MPLBACKEND matplotlib does not know (it refuses to import under it): the commands
    print with the characters replaced and draw off-screen as always. A real process: both
    variables act when the interpreter and matplotlib start; the two commands run in one
    (each exit code printed), which is what the variables act on."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, PYTHONIOENCODING="ascii", MPLBACKEND="no_such_backend")
    commands = (["efficiency", str(cases_dir / "sine_prototype.toml")],
                ["geometry", str(cases_dir / "sine_prototype.toml"), "--out",
                 str(tmp_path / "g")])
    script = ("import sys; from toothfem.cli import main\n"
              f"codes = [main(a) for a in {commands!r}]\n"
              "print('exit codes', codes)")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, env=env,
                       timeout=120)
    assert p.returncode == 0 and p.stderr == b"", p.stderr.decode()[-500:]
    assert p.stdout.decode("ascii").splitlines()[-1] == "exit codes [0, 0]"
    assert (tmp_path / "g" / "drawing.png").stat().st_size > 0


def test_the_console_script_ignores_a_signal_once_its_command_has_ended(cases_dir,
                                                                        monkeypatch):
    """`toothfem` ends with the command's exit code even when a SIGTERM arrives during the
    interpreter's shutdown (it was killed by the signal's default action, exit -15, with
    its result complete on disk); main() called from Python restores the handlers it
    found."""
    import signal

    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    assert cli.main(["check", str(cases_dir / "sine_prototype.toml")]) == 0
    assert {s: signal.getsignal(s) for s in before} == before
    monkeypatch.setattr("sys.argv", ["toothfem", "check",
                                     str(cases_dir / "sine_prototype.toml")])
    try:
        with pytest.raises(SystemExit) as done:
            cli.console()
        assert done.value.code == 0
        assert all(signal.getsignal(s) is signal.SIG_IGN for s in before)
    finally:
        for s, h in before.items():
            signal.signal(s, h)
