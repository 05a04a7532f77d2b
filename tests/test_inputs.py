"""Every input handled (issue 14): wrong types and encodings, implausible values, faults and
interrupts, odd measured data and a closed stdout each end in one line naming the cause,
or in a result; never in a traceback, a runaway, a lost result or a half-written folder."""
import contextlib
import copy
import json
import math
import os
import signal
import subprocess
import sys
import warnings

import numpy as np
import pytest

from toothfem import CaseError, load_case, parse_case
from toothfem import cli
from toothfem.report import plots
from toothfem.efficiency.loop import measured as ms
from toothfem.errors import MeasuredDataError, ToothfemError, check_range
from toothfem.fem.cache import CacheWarning, DiskCache, content_key
from toothfem.geometry import cycloid as cy, cycloid_distance as cyd, cycloid_mesh as cym
from toothfem.output import atomic_dir, clean_stale

try:
    import tomllib
except ImportError:  # pragma: no cover
    import tomli as tomllib


def _raw(cases_dir, name):
    with open(cases_dir / name, "rb") as fh:
        return tomllib.load(fh)


def _with(raw, dotted, value):
    raw = copy.deepcopy(raw)
    node = raw
    *path, last = dotted.split(".")
    for k in path:
        node = node[k]
    if value is None:
        del node[last]
    else:
        node[last] = value
    return raw


def _refusal(raw) -> str:
    with pytest.raises(CaseError) as exc:
        parse_case(raw)
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


# ---------------------------------------------------------------------------------------
# 1. types and encodings

@pytest.mark.parametrize("value, kind", [("1.0", "a string"), (True, "true/false"),
                                         ({"x": 1}, "a table"), ([1.0], "an array")])
@pytest.mark.parametrize("key", ["cycloid.eccentricity_mm", "cycloid.housing_outer_radius_mm",
                                 "cycloid.disc_holes.crank_hole_radius_mm",
                                 "operating.output_torque_Nm", "lubricant.dynamic_viscosity_Pa_s",
                                 "material.youngs_modulus_GPa", "first_stage.module_mm"])
def test_wrong_type_where_a_number_belongs_names_the_key(cases_dir, key, value, kind):
    msg = _refusal(_with(_raw(cases_dir, "cycloid_pinhousing.toml"), key, value))
    assert msg.startswith(f"{key} = ") and f"is not a number: it is {kind}" in msg


@pytest.mark.parametrize("key, value, text", [
    ("cycloid.pin_count", 40.0, "cycloid.pin_count = 40.0 must be an integer, not a float "
                                "(write 40)"),
    ("cycloid.pin_count", "40", "cycloid.pin_count = '40' must be an integer, not a string"),
    ("cycloid.pin_structure", 1, "cycloid.pin_structure = 1 is not a string: it is an "
                                 "integer"),
    ("case.name", 7, "case.name = 7 is not a string"),
    ("case.stated_ratio", "121", "case.stated_ratio = '121' is not a number"),
    ("published.pins_in_contact", {"a": 1}, "published.pins_in_contact = {'a': 1} is not a "
                                            "number: it is a table"),
    ("cycloid.pin_count", 10**400, "cycloid.pin_count = 1.000000e+400 is outside the valid "
                                   "range [4, 400]"),
    ("operating.output_torque_Nm", 10**30, "operating.output_torque_Nm = 1e+30 is outside"),
    ("operating.output_torque_Nm", 10**400, "operating.output_torque_Nm = 1.000000e+400 is "
                                            "outside"),
    ("rv40e:cycloid.pin_circle_radius_mm", 10**400, "cycloid.pin_circle_radius_mm = "
                                                    "1.000000e+400 is outside the valid range "
                                                    "[1, 2000]"),
])
def test_other_types_and_overflow(cases_dir, key, value, text):
    name, _, key = key.rpartition(":")      # rv40e: no housing radius (the default rule)
    raw = _raw(cases_dir, f"{name or 'cycloid_pinhousing'}.toml")
    assert text in _refusal(_with(raw, key, value))


def test_check_range_refuses_strings_bools_and_huge_ints():
    for v in ("1.0", True, 10**400):
        with pytest.raises(ValueError):
            check_range("x", v, 0, 10)


def test_encodings_one_line(cases_dir, tmp_path, capsys):
    text = (cases_dir / "cycloid_pinhousing.toml").read_text()
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode())
    assert load_case(bom) == load_case(cases_dir / "cycloid_pinhousing.toml")
    latin = tmp_path / "latin.toml"
    latin.write_bytes(text.encode().replace(b"# Cycloid", b"# Cycl\xe9id", 1))
    utf16 = tmp_path / "utf16.toml"
    utf16.write_bytes(text.encode("utf-16"))
    inf = tmp_path / "inf.toml"
    inf.write_text(text.replace("eccentricity_mm = 1.0 ", "eccentricity_mm = 1e400 "))
    for path, words in ((latin, "not UTF-8 text: byte 0xe9 at line 1, column 7"),
                        (utf16, "is UTF-16 text; save it as UTF-8"),
                        (inf, "cycloid.eccentricity_mm = inf is outside the valid range"),
                        (tmp_path, "is a folder, not a case file")):
        assert cli.main(["check", str(path)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and words in err and "Traceback" not in err


# ---------------------------------------------------------------------------------------
# 2. plausibility bounds and the cross-section rules the analyses need

@pytest.mark.parametrize("name, key, value, text", [
    ("cycloid_pinhousing.toml", "cycloid.housing_outer_radius_mm", 1000.0,
     "cycloid.housing_outer_radius_mm = 1000.0 is outside the valid range (102, 202]"),
    ("cycloid_pinhousing.toml", "cycloid.face_width_mm", 1e300,
     "cycloid.face_width_mm = 1e+300 is outside the valid range [0.1, 1000]"),
    ("cycloid_pinhousing.toml", "cycloid.pin_circle_radius_mm", 1e-300,
     "cycloid.pin_circle_radius_mm = 1e-300 is outside the valid range [1, 2000]"),
    ("cycloid_pinhousing.toml", "operating.input_speed_rpm", 1e-300,
     "operating.input_speed_rpm = 1e-300 is outside the valid range [0.01, 20000]"),
    ("cycloid_pinhousing.toml", "first_stage.module_mm", 1e-3,
     "first_stage.module_mm = 0.001 is outside the valid range [0.05, 100]"),
    ("cycloid_pinhousing.toml", "friction.drag_torque_Nmm", 1e300,
     "friction.drag_torque_Nmm = 1e+300 is outside the valid range [0, 1e+06]"),
    ("sine_prototype.toml", "sine.face_width_mm", 1e300,
     "sine.face_width_mm = 1e+300 is outside the valid range [0.1, 1000]"),
    ("sine_prototype.toml", "output_mechanism.pin_radius_mm", 1e-300,
     "output_mechanism.pin_radius_mm = 1e-300 is outside the valid range [0.1, 200]"),
    ("rv40e.toml", "rv.mesh_efficiency", 0.1,
     "rv.mesh_efficiency = 0.1 is outside the valid range [0.5, 1]"),
    ("cycloid_pinhousing.toml", "operating.output_torque_Nm", None,
     "[operating] needs output_torque_Nm, input_torque_Nm or input_power_kW"),
    ("cycloid_pinhousing.toml", "cycloid.disc_holes.crank_hole_count", 0,
     "cycloid.disc_holes.crank_hole_count = 0 is outside the valid range [1, 12]"),
    ("sine_prototype.toml", "output_mechanism", None,
     "drive = 'sine' without a [first_stage] needs [output_mechanism]"),
    ("rv40e.toml", "first_stage", None, "[first_stage] section is required"),
    ("rv40e.toml", "material", None, "[material] section is required with a [cycloid]"),
])
def test_plausibility_bounds_and_cross_rules(cases_dir, name, key, value, text):
    assert text in _refusal(_with(_raw(cases_dir, name), key, value))


def test_operating_point_where_losses_take_most_of_the_input(cases_dir):
    """The fixed point T2 = i T1 eta(T2) contracts at the rate 1 - eta: with a large
    load-independent loss it is solved by bracketing; an input that cannot overcome the
    no-load losses is refused naming the key."""
    from toothfem.efficiency import evaluate, operating_point

    raw = _raw(cases_dir, "sine_prototype.toml")
    case = parse_case(_with(raw, "output_mechanism.plain_bearing_friction_torque_Nmm", 252.0))
    speed, t2 = operating_point(case)
    eta = float(evaluate(case, speed, t2).efficiency[0])
    assert 0.25 < eta < 0.35                                   # slow contraction here
    assert t2 == pytest.approx(79 * 0.4 * eta, rel=1e-8)
    case = parse_case(_with(raw, "output_mechanism.plain_bearing_friction_torque_Nmm", 2520.0))
    with pytest.raises(CaseError, match=r"^operating.input_torque_Nm = 0.4 does not overcome "
                                        r"the load-independent losses at 300 rpm"):
        operating_point(case)


# ---------------------------------------------------------------------------------------
# 3. valid means analysable

def test_sine_tooth_height_lower_bound_in_check(cases_dir):
    """Low teeth leave crank angles with no drive flank near: refused with the bound."""
    raw = _raw(cases_dir, "sine_prototype.toml")
    msg = _refusal(_with(raw, "sine.tooth_height_mm", 0.1))
    assert msg.startswith("sine.tooth_height_mm = 0.1 is outside the valid range [0.17")
    assert msg.endswith(", 0.45): at some crank angles no drive flank is within 40 um to "
                        "carry the torque (lower bound by bisection)")
    lo = float(msg.split("[")[1].split(",")[0])
    from toothfem.efficiency import evaluate
    case = parse_case(_with(raw, "sine.tooth_height_mm", 1.01 * lo))   # just above: works
    e = evaluate(case, 500.0, 28.0)
    assert 0 < float(e.efficiency[0]) < 1


def test_cycloid_meshing_finite_at_an_inflection_point():
    """K1 = 1/Zb puts an inflection point at the tooth tip (curvature radius infinite):
    the pin on the line of centres gets R_eq = r_pin, not inf/inf."""
    g = cy.CycloidGeometry(20, 40e-3, 0.1e-3, 2e-3)
    assert g.k1 == pytest.approx(1 / 20)
    m = cym.meshing(g, np.linspace(0, 2 * math.pi / 20, 5))
    for f in ("equivalent_radius", "moment_arm", "pressure_angle", "gap"):
        assert np.all(np.isfinite(getattr(m, f))), f
    assert m.equivalent_radius[0, 0] == pytest.approx(2e-3, rel=1e-12)
    # the two-radius form elsewhere: 1/R = 1/(rho - r) + 1/r
    g2 = cy.CycloidGeometry(40, 100e-3, 1e-3, 2e-3)
    m2 = cym.meshing(g2, [0.1])
    rho = cy._rho_of_theta(g2.nominal(), np.mod(2 * np.pi * np.arange(40) / 40 - 0.1,
                                                 2 * np.pi))
    np.testing.assert_allclose(m2.equivalent_radius[0],
                               1 / (1 / (rho - 2e-3) + 1 / 2e-3), rtol=1e-10)


def test_cycloid_clearance_of_a_strongly_curtate_modified_disc():
    """K1 = 0.89 with all three modifications: Newton from the unmodified parameter
    wandered; the nested-grid start gives the minimum distance (checked by brute force)."""
    g = cy.CycloidGeometry(89, 100e-3, 1e-3, 2e-3, 0.01e-3, 0.005e-3, math.radians(0.05))
    phi = np.array([0.0, math.pi / 89])
    assert np.all(np.isfinite(cym.clearance_exact(g, phi)))
    gen = g.generating()
    local = cym.to_disc_frame(g, phi, np.broadcast_to(cym.pin_centres(g)[:, None, :],
                                                     (2, 2, 89))).reshape(2, -1)
    # each turned profile's distance, Newton from the unmodified contact parameter (the
    # disc's own distance takes the corner where the two cross: issue 28)
    psi0 = (2 * math.pi * np.arange(89)[None, :] / 89 + phi[:, None] / 88).ravel()
    d = np.maximum(*(cyd.distance_to_profile(g, local, f, psi0) for f in (1, -1))
                   ).reshape(2, 89) - g.pin_radius_m
    psi = np.linspace(0, 2 * np.pi, 200_001)
    ref = []
    for flank in (1, -1):
        a = -flank * g.rotation_rad
        pts = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]) @ local
        w = cy.working_profile(gen, psi)
        dist = np.empty(pts.shape[1])
        for i in range(pts.shape[1]):
            j = int(np.argmin(np.hypot(w[0] - pts[0, i], w[1] - pts[1, i])))
            out = -cy.inward_normal(gen, psi[j])
            dist[i] = np.sign(np.dot(pts[:, i] - w[:, j], out)) * np.hypot(
                *(pts[:, i] - w[:, j]))
        ref.append(dist)
    ref = np.maximum(*ref).reshape(2, 89) - g.pin_radius_m
    # a sampled distance can only be larger than the minimum, by up to ds^2/(8 rho) with
    # ds up to 6 um along a flank (3e-5 rad): ~1e-9 m
    assert np.all(d <= ref + 1e-12) and np.all(ref - d < 3e-9)


# ---------------------------------------------------------------------------------------
# 4. interrupts and faults

@pytest.mark.parametrize("signum, code, word", [(signal.SIGINT, 130, "interrupted"),
                                                (signal.SIGTERM, 143, "terminated")])
def test_signal_during_a_command_leaves_no_folder(cases_dir, tmp_path, monkeypatch, capsys,
                                                  signum, code, word):
    out = tmp_path / "geo"
    real = plots.cycloid_drawing

    def drawing_then_signal(*a, **kw):
        fig = real(*a, **kw)
        os.kill(os.getpid(), signum)          # arrives inside the atomic folder
        return fig

    monkeypatch.setattr(plots, "cycloid_drawing", drawing_then_signal)
    before = signal.getsignal(signal.SIGTERM)
    assert cli.main(["geometry", str(cases_dir / "cycloid_pinhousing.toml"), "--out",
                     str(out)]) == code
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and word in err
    assert list(tmp_path.iterdir()) == []          # neither the folder nor a temporary one
    assert signal.getsignal(signal.SIGTERM) is before


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_lost_in_a_finalizer_still_stops_the_command(cases_dir, tmp_path,
                                                             monkeypatch, capsys, signum,
                                                             code):
    """Python ignores an exception raised inside a weakref callback or a finalizer; a
    signal whose handler ran there was lost (the probe saw `run` go on and write its result,
    exit 0, 1 in 20 tries). The handler notes the signal, and the output folder stops for it
    before committing: the exit code of the signal, nothing left."""
    import weakref

    out = tmp_path / "geo"
    real = plots.cycloid_drawing

    class Part:
        pass

    def drawing_with_signal_in_a_callback(*a, **kw):
        def callback(ref):
            os.kill(os.getpid(), signum)        # the handler runs here: its raise is lost
            for _ in range(100):                # (a few bytecodes for it to be called)
                pass

        part = Part()
        ref = weakref.ref(part, callback)
        del part
        assert ref() is None
        return real(*a, **kw)

    lost = []
    monkeypatch.setattr(plots, "cycloid_drawing", drawing_with_signal_in_a_callback)
    monkeypatch.setattr(sys, "unraisablehook", lambda u: lost.append(u.exc_type))
    assert cli.main(["geometry", str(cases_dir / "cycloid_pinhousing.toml"), "--out",
                     str(out)]) == code
    assert [t.__name__ for t in lost] == [{130: "KeyboardInterrupt",      # it did land
                                           143: "Terminated"}[code]]     # there
    assert list(tmp_path.iterdir()) == []
    from toothfem import signals
    assert signals.noted() is None                      # cleared for the next command


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signals_to_a_running_contact_command(cases_dir, tmp_path, signum):
    """The real thing: `toothfem contact` in its own process, signalled once its temporary
    output folder exists (meshing, factorising or solving): exit 128 + signal, one line, no
    output folder and no temporary one. (Signalled again after a minute in case the first
    fell into a garbage-collector callback, where Python drops it.)"""
    import time

    out = tmp_path / "contact"
    env = {**os.environ, "TOOTHFEM_CACHE": str(tmp_path / "cache")}
    p = subprocess.Popen([sys.executable, "-c", "import sys; from toothfem.cli import main; "
                          "sys.exit(main())", "contact", str(cases_dir / "rv40e.toml"),
                          "--positions", "36", "--out", str(out)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    while p.poll() is None and not list(tmp_path.glob(".contact~*.tmp-*")):
        time.sleep(0.05)
    while p.poll() is None:
        p.send_signal(signum)
        with contextlib.suppress(subprocess.TimeoutExpired):
            p.wait(timeout=60)
    err = p.stderr.read().decode()
    assert p.returncode == 128 + signum, err[-500:]
    assert err.strip().splitlines()[-1].endswith("; no output written")
    assert "Traceback" not in err
    assert sorted(x.name for x in tmp_path.iterdir()) in (["cache"], [])


def test_stale_temporary_folders_of_dead_runs_are_removed(tmp_path):
    from toothfem import output
    from toothfem.leftovers import host

    out = tmp_path / "res"
    dead = 2 ** 22 + 12345                     # above Linux's pid_max default: no process
    stem = output._stem(out)
    stale = tmp_path / f"{stem}.tmp-{host()}-{dead}-abc"
    stale.mkdir()
    (stale / "half.csv").write_text("x")
    live = tmp_path / f"{stem}.tmp-{host()}-1-abc"      # pid 1 is alive
    live.mkdir()
    other = tmp_path / f"{stem}.tmp-otherhost-{dead}-abc"
    other.mkdir()
    with atomic_dir(out) as tmp:
        (tmp / "a.txt").write_text("done")
    assert not stale.exists() and live.exists() and other.exists()
    assert (out / "a.txt").read_text() == "done"
    assert clean_stale(out) == []


def test_atomic_dir_keeps_the_old_result_on_failure(tmp_path):
    out = tmp_path / "res"
    with atomic_dir(out) as tmp:
        (tmp / "v").write_text("1")
    with pytest.raises(KeyboardInterrupt), atomic_dir(out) as tmp:
        (tmp / "v").write_text("2")
        raise KeyboardInterrupt
    assert (out / "v").read_text() == "1"
    assert [p.name for p in tmp_path.iterdir()] == ["res"]


def test_a_result_left_aside_by_a_killed_swap_is_put_back(tmp_path):
    """A run killed between the two renames of the swap leaves the previous result only in
    its hidden ``.old-`` sibling: the next run puts it back under its name (and says so)
    before deciding anything, so it is neither lost nor deleted."""
    from toothfem import output
    from toothfem.leftovers import host

    out = tmp_path / "res"
    with atomic_dir(out) as tmp:
        (tmp / "v").write_text("1")
    dead = 2 ** 22 + 12345
    aside = tmp_path / f"{output._stem(out)}.old-{host()}-{dead}-abc"
    aside.mkdir()
    out.replace(aside / out.name)                  # the killed swap's first rename
    with pytest.warns(RuntimeWarning, match="back under its name"):
        assert clean_stale(out) == [aside]
    assert (out / "v").read_text() == "1"
    assert [p.name for p in tmp_path.iterdir()] == ["res"]
    # with the new result already in place, the copy left aside is the redundant one
    aside.mkdir()
    (aside / out.name).mkdir()
    with atomic_dir(out) as tmp:
        (tmp / "v").write_text("2")
    assert (out / "v").read_text() == "2"
    assert [p.name for p in tmp_path.iterdir()] == ["res"]


def test_out_follows_a_symlink_and_takes_a_255_character_name(tmp_path):
    """A symbolic link --out is written through (the link stays a link); the longest legal
    folder name is accepted (the hidden temporary name is cut to fit); the marker names the
    version and the command line."""
    from toothfem import __version__
    from toothfem.output import MARKER

    real = tmp_path / "elsewhere"
    link = tmp_path / "link"
    link.symlink_to(real, target_is_directory=True)
    for _ in range(2):                              # new, then an earlier result
        with atomic_dir(link) as tmp:
            (tmp / "a.txt").write_text("done")
    assert link.is_symlink() and (real / "a.txt").read_text() == "done"
    long = tmp_path / ("r" * 255)
    with atomic_dir(long) as tmp:
        (tmp / "a.txt").write_text("done")
    assert (long / "a.txt").exists()
    head = (long / MARKER).read_text().splitlines()[0]
    assert head.startswith(f"written by toothfem {__version__} (") and head.endswith(":")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["elsewhere", "link",
                                                                 long.name])


def test_out_never_replaces_what_toothfem_did_not_write(tmp_path, cases_dir, capsys):
    """--out naming a folder with the user's files (a notes folder, the case's own folder)
    or an existing file is refused in one line before anything is written, and nothing of
    the user's is touched; an empty folder and an earlier result are written into."""
    from toothfem import cli
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "thesis.txt").write_text("mine")
    own = tmp_path / "case"
    own.mkdir()
    case = own / "c.toml"
    case.write_text((cases_dir / "cycloid_pinhousing.toml").read_text())
    afile = tmp_path / "a.txt"
    afile.write_text("keep")
    for out in (notes, own, afile):
        assert cli.main(["geometry", str(case), "--out", str(out)]) == 2
        assert "--out" in capsys.readouterr().err
    assert (notes / "thesis.txt").read_text() == "mine" and case.exists()
    assert afile.read_text() == "keep"
    empty = tmp_path / "empty"
    empty.mkdir()
    for out in (empty, empty):             # empty, then an earlier result
        assert cli.main(["geometry", str(case), "--out", str(out)]) == 0
    assert (empty / "profile.csv").exists()
    # a file of the user's put into an earlier result: refused, the file kept
    (empty / "my_note.txt").write_text("mine")
    assert cli.main(["geometry", str(case), "--out", str(empty)]) == 2
    assert "my_note.txt" in capsys.readouterr().err
    assert (empty / "my_note.txt").read_text() == "mine"


def test_cache_temporary_of_a_killed_write_is_removed(tmp_path):
    """A write killed outright leaves its temporary file (named by host and process); the
    next store removes it once that process is gone, and leaves a live writer's alone."""
    from toothfem.leftovers import host

    dead = 2 ** 22 + 12345
    killed = tmp_path / f".tmp-{host()}-{dead}-0123456789abcdef.x1.tmp"
    live = tmp_path / f".tmp-{host()}-1-0123456789abcdef.x2.tmp"
    for f in (killed, live):
        f.write_bytes(b"half a file")
    DiskCache(tmp_path).store(content_key("a"), {"x": np.ones(2)})
    assert not killed.exists() and live.exists()
    assert DiskCache(tmp_path).load(content_key("a"))["x"].sum() == 2


def test_cache_that_cannot_be_written_warns_and_returns(tmp_path, monkeypatch):
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("x")
    arrays = {"a": np.arange(3.0)}
    with pytest.warns(CacheWarning, match="cannot be written"):
        assert DiskCache(blocker / "cache").store("k" * 64, arrays) is None
    cache = DiskCache(tmp_path / "cache")

    def full(*a, **kw):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    with pytest.warns(CacheWarning, match="No space left on device"):
        assert cache.store("k" * 64, arrays) is None
    assert list((tmp_path / "cache").iterdir()) == []          # no temporary file left


@pytest.mark.slow
def test_contact_result_written_when_the_cache_cannot_be(cases_dir, tmp_path, monkeypatch,
                                                         capsys):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the cache folder should be")
    monkeypatch.setenv("TOOTHFEM_CACHE", str(blocker / "cache"))
    out = tmp_path / "contact"
    assert cli.main(["contact", str(cases_dir / "cycloid_pinhousing.toml"), "--positions", "2",
                     "--field", "none", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "toothfem contact: warning: the FE cache" in err and "cannot be written" in err
    assert json.loads((out / "summary.json").read_text())["max_force_N"] > 0


def test_cache_file_under_another_name_is_a_miss(tmp_path):
    cache = DiskCache(tmp_path)
    a, b = content_key("a"), content_key("b")
    cache.store(a, {"x": np.ones(2)})
    np.testing.assert_array_equal(cache.load(a)["x"], np.ones(2))
    cache.path(a).rename(cache.path(b))            # a renamed or copied file
    assert cache.load(b) is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cache.store(b, {"x": np.zeros(2)})         # recomputed and replaced
    np.testing.assert_array_equal(cache.load(b)["x"], np.zeros(2))


@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_gmsh_meshing_keeps_pythons_signal_handlers(tmp_path, signame):
    """A Ctrl-C or SIGTERM while gmsh meshes reaches Python's handler once the mesher
    returns (a KeyboardInterrupt; the CLI's SIGTERM handler raises likewise); it no longer
    kills the process (gmsh's 'interruptible' set SIGINT to the default action, and its
    initialisation replaced the SIGTERM handler: exit -15, the output folder left)."""
    script = (          # imports first: a Ctrl-C inside an import is another matter
        "import os, signal, threading, time, numpy as np\n"
        "from toothfem.fem.mesh import mesh_rings\n"
        # both, as the CLI does: a process started with SIGINT ignored (a background job
        # of a non-interactive shell, as under a benchmark tool) has no KeyboardInterrupt
        "for s in (signal.SIGINT, signal.SIGTERM):\n"
        "    signal.signal(s, signal.default_int_handler)\n"
        "t = np.linspace(0, 2 * np.pi, 400, endpoint=False)\n"
        "ring = np.stack([np.cos(t), np.sin(t)])\n"
        "mesh_rings([ring], 0.01)\n"
        "stop, sent, meshes = threading.Event(), [0], [0]\n"
        "def ctrl_c():  # again until heard: one landing in a GC finalizer is lost\n"
        "    while not stop.wait(0.3):\n"
        f"        os.kill(os.getpid(), signal.{signame})\n"
        "        sent[0] += 1\n"
        "threading.Thread(target=ctrl_c, daemon=True).start()\n"
        "end = time.monotonic() + 60\n"
        "try:\n"
        "    while time.monotonic() < end:\n"
        "        mesh_rings([ring], 0.01)\n"
        "        meshes[0] += 1\n"
        "except KeyboardInterrupt:\n"
        "    stop.set()\n"
        "    try:\n"
        "        time.sleep(1)  # a last one already on its way\n"
        "    except KeyboardInterrupt:\n"
        "        pass\n"
        "    print('interrupted')\n"
        "else:  # what a failure needs to be understood\n"
        "    print('not interrupted:', sent[0], 'signals sent,', meshes[0], 'meshes, handler',\n"
        f"          signal.getsignal(signal.{signame}), 'mask',\n"
        "          signal.pthread_sigmask(signal.SIG_BLOCK, []))\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0 and p.stdout.strip() == "interrupted", (p.stdout[-500:],
                                                                     p.stderr[-500:])


# ---------------------------------------------------------------------------------------
# 5. measured data

GOOD = "input_speed_rpm,output_torque_Nm,efficiency"


def test_text_and_partly_empty_extra_columns_never_refuse_a_row():
    text = (GOOD + ",operator,humidity_pct,load_cell_V\n"
            "500,28,0.82,anna,40,1.2\n"
            "600,20,0.80,ben,,1.3\n"
            "700,10,0.75,carl,n/a,1.4\n")
    d = ms.parse_measured(text)
    assert len(d) == 3 and d.rejected == ()
    assert set(d.extra) == {"load_cell_V"}
    np.testing.assert_allclose(d.extra["load_cell_V"], [1.2, 1.3, 1.4])
    assert any("'operator' dropped (text)" in n for n in d.notes)
    assert any("'humidity_pct' dropped (2 of 3 cells empty or not a number)" in n
               for n in d.notes)


def test_trailing_commas_accepted():
    d = ms.parse_measured(GOOD + ",\n500,28,0.82,\n600,20,0.80\n")
    assert len(d) == 2 and d.rejected == ()


def test_efficiency_pct_of_fractions_refused_and_percent_in_fractions_hinted():
    with pytest.raises(MeasuredDataError, match=r"column 'efficiency_pct' holds fractions "
                                                r"\(every value <= 1, largest 0.82\)"):
        ms.parse_measured("input_speed_rpm,output_torque_Nm,efficiency_pct\n500,28,0.82\n"
                          "600,20,0.8\n")
    with pytest.raises(MeasuredDataError, match="seems to hold percent; name it "
                                                "'efficiency_pct'"):
        ms.parse_measured(GOOD + "\n500,28,82\n600,20,80\n")


def test_identical_points_one_line(cases_dir, tmp_path, capsys):
    same = tmp_path / "same.csv"
    same.write_text(GOOD + "\n" + "1500,100,0.8\n" * 12)
    d = ms.load_measured(same)
    assert ms.distinct_points(d) == 1
    out = tmp_path / "loop"
    assert cli.main(["loop", str(cases_dir / "rv40e.toml"), str(same), "--out",
                     str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "12 good rows but only 1 distinct operating point" in err
    assert not out.exists()


@pytest.mark.parametrize("data, words", [
    (b"\xef\xbb\xbf" + GOOD.encode() + b"\n500,28,0.82\n", None),
    (GOOD.encode() + b"\n500,28,0.82\n# \xe9t\xe9\n", "not UTF-8 text: byte 0xe9 at line 3"),
    (GOOD.encode() + b"\n500,28,0.8" + b"2" * 200_000 + b"\n", "line 2: cannot be read as CSV "
                                                           r"\(field larger than field limit"),
])
def test_measured_file_encodings(tmp_path, data, words):
    path = tmp_path / "m.csv"
    path.write_bytes(data)
    if words is None:
        assert len(ms.load_measured(path)) == 1
    else:
        with pytest.raises(MeasuredDataError, match=words):
            ms.load_measured(path)


# ---------------------------------------------------------------------------------------
# 7. a closed stdout

def test_broken_pipe_exits_quietly(cases_dir):
    """`toothfem check CASE | head -1` with the reader gone before the first write."""
    r, w = os.pipe()
    os.close(r)
    p = subprocess.run([sys.executable, "-c", "import sys; from toothfem.cli import main; "
                        "sys.exit(main())", "check", str(cases_dir / "rv40e.toml")],
                       stdout=w, stderr=subprocess.PIPE, timeout=120)
    os.close(w)
    assert p.stderr == b"" and p.returncode == 128 + signal.SIGPIPE


def test_internal_error_is_one_line(monkeypatch, cases_dir, capsys):
    from toothfem.commands import check

    def boom(args):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(check, "run", boom)
    monkeypatch.delenv(cli.DEBUG_ENV, raising=False)
    assert cli.main(["check", str(cases_dir / "rv40e.toml")]) == cli.EXIT_INTERNAL
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error: ZeroDivisionError" in err


@pytest.mark.parametrize("value", [1e30, 1e300])
def test_seal_diameter_has_a_plausibility_bound(cases_dir, value):
    """The adversarial probe's last four failures (issue 14): a seal diameter of 1e300 mm
    overflowed inside the seal law, 1e30 mm was accepted and then drove the efficiency to
    zero; both are refused where the case is read, naming the key and its range."""
    from toothfem.case import case_to_dict

    d = case_to_dict(load_case(cases_dir / "sine_prototype.toml"))
    d["seals"]["input_diameter_mm"] = value
    with pytest.raises(CaseError, match=r"seals.input_diameter_mm = .* is outside the valid "
                                        r"range \[0, 4000\]"):
        parse_case(d)


# ---------------------------------------------------------------------------------------
# The public API's arguments (issue 27, item 5)

def test_api_refuses_what_is_not_a_case_a_path_or_a_number(cases_dir, tmp_path):
    """The functions the README shows: a path where a case belongs is loaded (top-level
    analyses) or refused naming the argument (fem, efficiency: they take records); a
    string, bool, NaN or None where a number or a folder belongs is refused naming it."""
    from toothfem.case import as_case
    from toothfem.fem.drives import drive_for
    from toothfem.geometry import cycloid_mesh
    from toothfem.pipeline import run_case

    path = cases_dir / "cycloid_pinhousing.toml"
    case = as_case(str(path))
    assert as_case(case) is case and as_case(path).name == case.name
    with pytest.raises(CaseError, match=r"^case = 5 is not a case; valid: a toothfem.Case"):
        as_case(5)
    with pytest.raises(ToothfemError, match=r"case = '.*\.toml' is not a case; load it first"):
        drive_for(str(path))
    with pytest.raises(ToothfemError, match=r"^out = None is not a folder path"):
        run_case(case, None, field="none")
    assert not list(tmp_path.iterdir())
    geom = case.cycloid.geometry()
    with pytest.raises(ToothfemError, match=r"crank_angle_rad\[1\] = nan is outside"):
        cycloid_mesh.meshing(geom, np.array([0.1, np.nan]))
    with pytest.raises(ToothfemError, match="crank_angle_rad = '0.1' is not a number"):
        cycloid_mesh.meshing(geom, "0.1")
    drive = drive_for(case)
    for bad, words in (("100", "'100' is not a number"), (True, "True is not a number"),
                       (math.nan, "nan is outside")):
        with pytest.raises(CaseError, match=f"output_torque_Nm = {words}"):
            drive.member_torque(bad)


def test_a_contact_that_does_not_settle_names_its_load(cases_dir):
    from toothfem.fem.contact import ContactError
    from toothfem.fem.drives import drive_for

    drive = drive_for(load_case(cases_dir / "cycloid_pinhousing.toml"))
    solver = drive.cycle_solver(2, pin_structure="rigid", cache=False)
    with pytest.raises(ContactError, match=r"did not settle .* \(at disc torque 1e\+12 N m, "
                                           r"position 0\)$"):
        solver.solve(1e12)


@pytest.mark.parametrize("delimiter", [";", "\t"])
def test_semicolon_and_tab_files_with_decimal_commas_are_read_and_said(delimiter):
    """A spreadsheet's export in a locale with decimal commas: the delimiter is taken from
    a header without commas, a decimal comma read as a point, and the notes say both."""
    text = delimiter.join(GOOD.split(",")) + "\n" + "\n".join(
        delimiter.join(row) for row in (("500", "28,5", "0,82"), ("600", "20", "0.80")))
    d = ms.parse_measured(text)
    np.testing.assert_allclose(d.torque_Nm, [28.5, 20.0])
    np.testing.assert_allclose(d.efficiency, [0.82, 0.80])
    assert d.notes[:2] == (f"read with {delimiter!r} as the delimiter (the header has no "
                           "comma)", "decimal commas read as decimal points")
    assert ms.parse_measured(GOOD + "\n500,28.5,0.82\n").notes == ()


def test_a_misspelled_published_figure_is_refused_and_the_read_names_are_complete(cases_dir):
    """[published] is the case's table of quoted figures: one within a typo of a name
    toothfem reads is refused (it would silently not be compared); notes under other names
    stay; every name a reader uses is in the list the check compares against."""
    import tomllib

    from toothfem.case import PUBLISHED_READ
    from toothfem.durability import MAKER_KEYS
    from toothfem.report.summary import PUBLISHED_NAMES

    used = {n.format(contacts=c) for names in PUBLISHED_NAMES.values() for n in names
            for c in ("pins", "teeth")} | set(MAKER_KEYS)
    assert used <= set(PUBLISHED_READ)
    doc = tomllib.loads((cases_dir / "sine_prototype.toml").read_text())
    doc["published"]["max_forse_N"] = 3.0
    with pytest.raises(CaseError, match=r"published\.max_forse_N is not a figure toothfem "
                                        r"reads; did you mean 'max_force_N'\?"):
        parse_case(doc)
    doc["published"] = {"loss_share_mesh": 0.4, "a_note_of_mine": 1.0}
    assert parse_case(doc).published["a_note_of_mine"] == 1.0


def test_a_signal_during_a_deferred_block_is_raised_after_it():
    """signals.deferred: a SIGTERM inside the block (the STEP library's import, where a
    handler's raise fails the import as 'initialization failed' and the run ended 'needs
    the extra [cad]', exit 2) is only noted there and raised once the block is done;
    Python's handler is put back."""
    import signal

    from toothfem import signals
    from toothfem.errors import Terminated

    def raising(signum, frame):
        raise Terminated(signum)

    old = signal.signal(signal.SIGTERM, raising)
    done = []
    try:
        with pytest.raises(Terminated), signals.deferred():
            signal.raise_signal(signal.SIGTERM)
            done.append("the block ran to its end")
        assert done and signal.getsignal(signal.SIGTERM) is raising
    finally:
        signals.note(None)
        signal.signal(signal.SIGTERM, old)
