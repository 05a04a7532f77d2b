"""Faults of a hostile environment around the output folder, each tried for real (issue 45).

Facts checked: two runs into one ``--out`` at once: the second is refused in one line and
the first's result is whole (two real processes); a dead run's lock never blocks; a sweep
killed (SIGKILL) while running into the folder of a finished sweep leaves that result
whole, and the same command resumes and finishes; a run killed (SIGKILL) at the swap of
the new result for the old one leaves a whole result under the name (the exchange in one
step), and, where the platform has no exchange, the next run puts the old one back; a
file-size limit (RLIMIT_FSIZE, in the child) leaves nothing under the final name and one
error line naming ``--out``, and a cache that cannot be written is one warning line, the
sweep's result written and exit 0; an output name that is not UTF-8 is written; a
read-only output folder of a user who is not root (as root: a forked child that drops to
nobody) is refused in one line naming ``--out`` as given.
"""
from __future__ import annotations

import contextlib
import json
import os
import resource
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from toothfem.folder_lock import exchange
from toothfem.output import JOURNAL, MARKER, atomic_dir, journal_folder

CLI = [sys.executable, "-c", "import sys; from toothfem.cli import main; sys.exit(main())"]
ECC = "cycloid.eccentricity_mm"


def _lock_files(out: Path) -> list[Path]:
    return list(out.parent.glob(f".{out.name}~*.lock"))


def _journals(out: Path) -> list[Path]:
    return list(out.parent.glob(f".{out.name}~*.journal-*/{JOURNAL}"))


def _whole(out: Path) -> bool:
    """``out`` is a finished result: its marker lists what the run wrote, all there."""
    lines = (out / MARKER).read_text().splitlines()
    return (lines[0].endswith(":") and "unfinished" not in lines[0]
            and all((out / name).exists() for name in lines[1:]))


def _limited(kbytes: int):
    """A child's file-size limit (RLIMIT_FSIZE), as `ulimit -f` sets it."""
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (kbytes * 1024, kbytes * 1024))
    return limit


@pytest.mark.slow
def test_two_runs_into_one_out_the_second_refused_the_first_whole(cases_dir, tmp_path):
    """A cold `contact` runs into ``out``; `geometry` and `sweep` started into the same
    folder meanwhile are each refused at once in one line naming ``--out`` and the first
    run's process; the contact ends with its result whole. A run killed outright while it
    holds the name does not block the next one."""
    case = str(cases_dir / "cycloid_pinhousing.toml")
    out = tmp_path / "res"
    env = {**os.environ, "TOOTHFEM_CACHE": str(tmp_path / "cold")}
    first = subprocess.Popen(CLI + ["contact", case, "--positions", "36", "--field", "none",
                                    "--out", str(out)], env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        while first.poll() is None and not _lock_files(out):
            time.sleep(0.02)
        assert first.poll() is None, first.stderr.read().decode()[-500:]
        for second in (["geometry", case], ["sweep", case, "--torque-Nm", "100",
                                            "--positions", "2", "--workers", "1"]):
            t0 = time.monotonic()
            done = subprocess.run(CLI + second + ["--out", str(out)], capture_output=True,
                                  timeout=120, env=env)
            err = done.stderr.decode().strip()
            assert done.returncode == 2 and len(err.splitlines()) == 1, err
            assert err.startswith(f"toothfem {second[0]}: error: --out {out} is being "
                                  f"written by another toothfem run (process {first.pid})")
            assert time.monotonic() - t0 < 60 and first.poll() is None
        assert first.wait(timeout=300) == 0, first.stderr.read().decode()[-500:]
    finally:
        with contextlib.suppress(ProcessLookupError):
            first.kill()
    assert _whole(out) and json.loads((out / "summary.json").read_text())["max_force_N"] > 0
    assert not _lock_files(out) and not (out / "profile.csv").exists()
    # killed while holding the name: its lock dies with it
    holder = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import time
        from toothfem.output import reserved
        with reserved({str(out)!r}):
            print("held", flush=True)
            time.sleep(600)
        """)], stdout=subprocess.PIPE)
    assert holder.stdout.readline() == b"held\n"
    refused = subprocess.run(CLI + ["geometry", case, "--out", str(out)], capture_output=True)
    assert refused.returncode == 2 and b"being written by another" in refused.stderr
    holder.send_signal(signal.SIGKILL)
    holder.wait()
    done = subprocess.run(CLI + ["geometry", case, "--out", str(out)], capture_output=True)
    assert done.returncode == 0, done.stderr.decode()[-500:]
    assert _whole(out) and (out / "profile.csv").exists() and not _lock_files(out)


@pytest.mark.slow
def test_a_killed_sweep_never_replaces_a_finished_result(cases_dir, tmp_path):
    """A finished sweep; another sweep into its folder killed (SIGKILL, the whole process
    group) once a point is kept: the finished result is byte for byte as it was, the
    points kept beside it; the same command resumes, finishes, and leaves no journal."""
    out = tmp_path / "sw"
    base = CLI + ["sweep", str(cases_dir / "cycloid_pinhousing.toml"), "--torque-Nm", "100",
                  "--positions", "2", "--pins", "rigid", "--workers", "1", "--no-cache",
                  "--out", str(out)]
    done = subprocess.run(base + ["--vary", f"{ECC}=1.0,0.98"], capture_output=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr.decode()[-800:]
    finished = {p.name: p.read_bytes() for p in out.iterdir()}
    longer = base + ["--vary", f"{ECC}=1.0,0.98,0.96,0.94,0.92,0.9"]
    p = subprocess.Popen(longer, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         start_new_session=True)
    try:
        while p.poll() is None and not (_journals(out) and _journals(out)[0].read_text()):
            time.sleep(0.02)
        os.killpg(p.pid, signal.SIGKILL)
        p.wait(timeout=60)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(p.pid, signal.SIGKILL)
    assert p.returncode == -signal.SIGKILL, p.stderr.read().decode()[-800:]
    assert {q.name: q.read_bytes() for q in out.iterdir()} == finished
    kept = len(_journals(out)[0].read_text().splitlines())
    assert 1 <= kept < 6
    done = subprocess.run(longer, capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr.decode()[-800:]
    summary = json.loads((out / "sweep.json").read_text())
    assert summary["rows"] == 6 and summary["resumed"] >= kept and summary["failed"] == 0
    assert not _journals(out) and _whole(out)
    assert sorted(q.name for q in tmp_path.iterdir()) == ["sw"]


def test_the_swap_exchanges_two_names_in_one_step(tmp_path):
    """On Linux the earlier result and the new one trade names in one call (no instant
    with nothing under the name)."""
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    (a / "v").write_text("a")
    (b / "v").write_text("b")
    if not sys.platform.startswith("linux"):
        pytest.skip("renameat2 is Linux's")
    assert exchange(a, b)
    assert (a / "v").read_text() == "b" and (b / "v").read_text() == "a"


_KILLED_AT_THE_SWAP = """
import os, shutil, signal, sys
from pathlib import Path
from toothfem import output
out = Path(sys.argv[1])
with output.atomic_dir(out) as tmp:
    (tmp / "v").write_text("1")
if sys.argv[2] == "two renames":            # a platform without the exchange
    output.exchange = lambda a, b: False
    replace = Path.replace
    def killed_after_one(self, target):
        replace(self, target)
        os.kill(os.getpid(), signal.SIGKILL)
    Path.replace = killed_after_one
else:                                       # killed once the names are exchanged
    shutil.rmtree = lambda *a, **kw: os.kill(os.getpid(), signal.SIGKILL)
with output.atomic_dir(out) as tmp:
    (tmp / "v").write_text("2")
"""


@pytest.mark.parametrize("how", ["exchange", "two renames"])
def test_a_run_killed_at_the_swap_leaves_a_whole_result(tmp_path, how):
    """A process SIGKILLed at the swap itself: with the exchange the name holds the new
    result at once (the old one, in the hidden folder, is removed by the next run); with
    two renames the name is empty until the next run puts the old result back (and says
    so). Either way nothing is lost and nothing is left over."""
    out = tmp_path / "res"
    p = subprocess.run([sys.executable, "-c", _KILLED_AT_THE_SWAP, str(out), how],
                       capture_output=True, timeout=120)
    assert p.returncode == -signal.SIGKILL, p.stderr.decode()[-500:]
    if how == "exchange":
        assert (out / "v").read_text() == "2" and _whole(out)
        with atomic_dir(out) as tmp:
            (tmp / "v").write_text("3")
        assert (out / "v").read_text() == "3"
    else:
        assert not out.exists()
        with pytest.warns(RuntimeWarning, match="back under its name"), \
                atomic_dir(out) as tmp:
            (tmp / "v").write_text("3")
        assert (out / "v").read_text() == "3"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["res"]


@pytest.mark.slow
def test_a_file_size_limit_leaves_nothing_under_the_final_name(cases_dir, tmp_path):
    """RLIMIT_FSIZE of 4 KiB in the child: a sweep (its points kept beside, its tables too
    large) and a tolerance ensemble each exit 2 with one error line naming ``--out``
    (and at most one line for the cache that cannot be written either); nothing is under
    the final name; an earlier result there stays whole."""
    case = str(cases_dir / "cycloid_pinhousing.toml")
    sweep = ["sweep", case, "--torque-Nm", "100", "--positions", "2", "--pins", "rigid",
             "--workers", "1", "--no-cache"]
    tolerance = ["tolerance", case, "--samples", "2", "--positions", "4",
                 "--share-samples", "0", "--workers", "1"]
    earlier = tmp_path / "earlier"
    with atomic_dir(earlier) as tmp:
        (tmp / "v").write_text("kept")
    # the tolerance's FE tables put in the suite's cache here first (a minute cold, none
    # warm), so that the limited child reads them instead of building them again
    from toothfem import load_case
    from toothfem.tolerance import tolerance_analysis
    tolerance_analysis(load_case(case), samples=2, positions=4, share_samples=0, workers=1,
                       progress=False)
    # the sweep into a new name and over an earlier result; the tolerance over the earlier
    # result only
    for args, outs in ((sweep, (tmp_path / "sweep", earlier)), (tolerance, (earlier,))):
        for out in outs:
            # the suite's FE cache ($TOOTHFEM_CACHE, tests/conftest.py): its tables are
            # read (a table it lacks cannot be written here: one warning line), so each
            # child does not build its FE tables again; the output's limit is the point
            done = subprocess.run(CLI + args + ["--out", str(out)], capture_output=True,
                                  timeout=600, preexec_fn=_limited(4))
            lines = [line for line in done.stderr.decode().splitlines()
                     if not line.startswith("progress:")]
            err = [line for line in lines if ": warning: the FE cache" not in line]
            assert len(lines) - len(err) <= 1, lines      # the cache: one line if any
            assert done.returncode == 2 and len(err) == 1, err
            assert err[0].startswith(f"toothfem {args[0]}: error: --out {out} cannot be "
                                     "written (File too large); nothing was written"), err
            assert "Traceback" not in done.stderr.decode()
            assert not (tmp_path / args[0]).exists()
            assert (earlier / "v").read_text() == "kept" and _whole(earlier)
    assert not list(tmp_path.glob(".*.tmp-*")) and not list(tmp_path.glob(".*.lock"))


@pytest.mark.slow
def test_a_cache_that_cannot_be_written_never_stops_a_sweep(cases_dir, tmp_path):
    """RLIMIT_FSIZE of 100 KiB: the influence tables (128 and 470 KiB) cannot be cached,
    the sweep's own files can: one warning line (from the driver, not a worker's
    traceback-like report), the result written, exit 0."""
    out = tmp_path / "sw"
    done = subprocess.run(CLI + ["sweep", str(cases_dir / "cycloid_pinhousing.toml"),
                                 "--torque-Nm", "100", "--positions", "36", "--workers", "1",
                                 "--cache-dir", str(tmp_path / "cache"), "--out", str(out)],
                          capture_output=True, timeout=600, preexec_fn=_limited(100))
    err = [line for line in done.stderr.decode().splitlines()
           if not line.startswith("progress:")]
    assert done.returncode == 0, err
    assert len(err) == 1 and err[0].startswith("toothfem sweep: warning: the FE cache") \
        and "(File too large)" in err[0], err
    assert _whole(out) and json.loads((out / "sweep.json").read_text())["rows"] == 1
    assert list((tmp_path / "cache").iterdir()) == []


def test_an_output_name_that_is_not_utf8_is_written(cases_dir, tmp_path):
    """An ``--out`` of bytes from another locale (surrogate escapes in Python): the
    geometry is written under exactly those bytes, the line printed safely, exit 0."""
    out = os.fsencode(tmp_path) + b"/g\xff"
    done = subprocess.run([os.fsencode(sys.executable), b"-c", CLI[2].encode(), b"geometry",
                           os.fsencode(cases_dir / "cycloid_pinhousing.toml"), b"--out",
                           out], capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr.decode(errors="replace")[-500:]
    assert os.path.isfile(out + b"/profile.csv") and os.path.isfile(out + b"/disc.step")
    assert b"wrote " in done.stdout and _whole(Path(os.fsdecode(out)))
    assert os.listdir(os.fsencode(tmp_path)) == [b"g\xff"]


def test_the_journal_is_kept_under_a_name_of_its_own(tmp_path):
    """journal_folder: a hidden sibling named by the output and the run's key."""
    out = tmp_path / "res"
    assert journal_folder(out, "ab12").parent == tmp_path
    assert journal_folder(out, "ab12").name.startswith(".res~")
    assert journal_folder(out, "ab12").name.endswith(".journal-ab12")


@pytest.mark.parametrize("where, says", [
    ("loop", "is a symbolic link that cannot be followed"),
    ("a_file/res", "a part of its folder is a file"),
    ("/proc/res", "its folder cannot be written")])
def test_an_output_that_cannot_be_written_is_refused_before_computing(
        cases_dir, tmp_path, monkeypatch, capsys, where, says):
    """A symbolic link that loops, a folder under a file, /proc: `run` is refused before
    it computes anything, in one line naming the path as given (not a hidden temporary
    folder)."""
    from toothfem import cli, pipeline

    def never(*args, **kwargs):
        raise AssertionError("computed before the output was checked")

    monkeypatch.setattr(pipeline, "analyse_run", never)
    monkeypatch.chdir(tmp_path)
    Path("loop").symlink_to("loop2")
    Path("loop2").symlink_to("loop")
    Path("a_file").write_text("x")
    assert cli.main(["run", str(cases_dir / "cycloid_pinhousing.toml"), "--no-fem",
                     "--out", where]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err and "~" not in err, err
    assert err.startswith(f"toothfem run: error: --out {where}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file", "loop", "loop2"]


@pytest.mark.slow
def test_a_journal_that_cannot_be_written_is_one_line(cases_dir, tmp_path):
    """RLIMIT_FSIZE of 1 KiB: the sweep's journal fills it after two points; one error
    line naming ``--out`` and the points kept (not the journal's second failure on
    closing), nothing under the final name."""
    out = tmp_path / "sw"
    done = subprocess.run(CLI + ["sweep", str(cases_dir / "cycloid_pinhousing.toml"),
                                 "--vary", f"{ECC}=1.0,0.98,0.96,0.94,0.92,0.9",
                                 "--torque-Nm", "100", "--positions", "2", "--pins", "rigid",
                                 "--workers", "1", "--no-cache", "--out", str(out)],
                          capture_output=True, timeout=600, preexec_fn=_limited(1))
    err = [line for line in done.stderr.decode().splitlines()
           if not line.startswith("progress:")]
    assert done.returncode == 2 and len(err) == 1, err
    assert err[0].startswith(f"toothfem sweep: error: --out {out}: its finished points "
                             "cannot be kept beside it (File too large);"), err
    assert "finished points kept beside" in err[0] and not out.exists()


def _as_nobody_or_self(argv, cwd: Path) -> tuple[int, str]:
    """Exit code and stderr of ``toothfem ARGV`` run by a user who is not root: this user
    where it is not root; as root, a forked child that drops to ``nobody`` (os.setuid) and
    calls the CLI in the same interpreter (root's Python may sit where nobody cannot read
    it; the modules the refusal needs are loaded by a first run as root)."""
    from toothfem import cli

    if os.geteuid() != 0:
        done = subprocess.run(CLI + argv, capture_output=True, cwd=cwd, timeout=300)
        return done.returncode, done.stderr.decode()
    import pwd
    nobody = pwd.getpwnam("nobody")
    cli.main([argv[0], argv[1], "--out", "/proc/res"])     # the refusal's modules loaded
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:                                            # the child: nobody from here
        code = 99
        try:
            os.close(r)
            os.dup2(w, 2)
            sys.stderr = os.fdopen(2, "w", closefd=False)
            os.setgroups([])
            os.setgid(nobody.pw_gid)
            os.setuid(nobody.pw_uid)
            os.chdir(cwd)
            code = cli.main(argv)
            sys.stderr.flush()
        except BaseException as exc:        # said on the pipe, the test fails on it
            os.write(2, f"child: {exc!r}".encode())
        finally:
            os._exit(code)
    os.close(w)
    with os.fdopen(r, "rb") as fh:
        err = fh.read().decode()
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]), err


def test_a_read_only_output_folder_of_a_user_is_one_line_naming_out(cases_dir, capsys):
    """A user who cannot write the output's folder (not root, who writes anywhere): exit 2,
    one line naming ``--out`` as given (no hidden temporary folder), nothing left there."""
    import shutil
    import tempfile

    base = Path(tempfile.mkdtemp(prefix="toothfem-ro-"))      # nobody may look in, not write
    try:
        base.chmod(0o755)
        (base / "ro").mkdir(mode=0o555)
        (base / "ro").chmod(0o555)
        code, err = _as_nobody_or_self(
            ["geometry", str(cases_dir / "sine_prototype.toml"), "--out", "ro/res"], base)
        capsys.readouterr()                                   # the root run's own line
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1, err
        assert lines[0].startswith("toothfem geometry: error: --out ro/res: its folder "
                                   "cannot be written (Permission denied)"), err
        assert list((base / "ro").iterdir()) == [] and sorted(p.name for p in base.iterdir()) \
            == ["ro"]
    finally:
        (base / "ro").chmod(0o755)
        shutil.rmtree(base)
