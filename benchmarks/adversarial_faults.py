"""Adversarial faults around the commands: how many the project handles as it promises (issue 27).

Each case runs ``toothfem`` (or a Python snippet) in a subprocess of its own, in a fresh
temporary folder with ``TOOTHFEM_CACHE`` inside it and ``MPLBACKEND=Agg``, with a time limit,
and is judged ``good`` or ``bad: <why>``. The classes:

filesystem  ``geometry --out`` naming a new folder (written), a user's folder (refused in one
            line naming the path, the user's file unchanged), the case file's own folder, a
            file, a symlink (written where it points, the link stays a link), an earlier
            result (replaced), an earlier result holding a user's note (refused), a
            255-character name, a read-only parent (one line, nothing written), and the
            leftover of a run killed between the two renames of the swap (the earlier result
            kept, or the loss said on stderr). After each: no hidden ``.NAME*.tmp-*`` left.
signals     SIGTERM to ``run`` at instants spread over a run, densely inside gmsh meshing, and
            SIGINT to its process group: exit 143 / 130 (0 if it finished first), one stderr
            line, no output folder, no hidden temporary folder, no ``*.tmp`` in the cache, no
            process left; SIGTERM to a ``sweep``: 143 and no stray Dask process.
cache       a stale ``.<16 hex>.<random>.tmp`` (two days old) in the cache is gone after a
            run; a cache folder that cannot be written (mode 500) costs a warning line, not
            the result; corrupt cache files are misses (exit 0).
sweeps      SIGKILL to a sweep's process group half-way: the finished rows are on disk under
            DIR, and a rerun finishes saying it resumed/skipped them; SIGINT: 130, one line,
            no traceback, rows kept; every point failing (TOOTHFEM_SOLVER=bogus): non-zero
            exit and stderr counts the failed points.
dask        ``sweep``/``tolerance --scheduler`` at a port that accepts and never answers, at a
            scheduler without workers, and a sweep whose only worker or whose scheduler is
            killed -9 half-way: end within 60 s, non-zero (not 3), one line, rows kept.
api         the Python API of README.md: a path where a Case is expected (works, or a
            ToothfemError naming ``case``), strings/bools/NaN/inf for speed, torque,
            temperature and angles, ``run_case(case, None)`` (a ToothfemError naming the
            argument), an absurd torque (a ToothfemError naming the load, or a warning).
misc        a measured CSV with ';', tab or decimal commas (the message says delimiter or
            decimal), a misspelled [published] key (named), 400 pins (exit 0 or 2), 1e6 N m
            (a warning or a refusal), PYTHONIOENCODING=ascii, MPLBACKEND=bogus, HOME unset
            (never exit 3, at most two stderr lines).

Run: ``python benchmarks/adversarial_faults.py [--classes filesystem,signals,...]
[--signal-tries N] [--seed S] [--quick] [--keep]``; prints a verdict per case and
``handled well: X of Y``; exits 1 when any case is handled badly. As root, the read-only
cases drop the capabilities that bypass file permissions in the child.
"""
from __future__ import annotations

import argparse
import contextlib
import ctypes
import json
import os
import random
import re
import shutil
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = ROOT / ".venv" / "bin"
PY, TF, DASK = str(BIN / "python"), str(BIN / "toothfem"), str(BIN / "dask")
CASE, SINE = ROOT / "cases" / "cycloid_pinhousing.toml", ROOT / "cases" / "sine_prototype.toml"
TIMEOUT = 120                     # s, any subprocess; killed (and judged bad) beyond it
CLASSES = ("filesystem", "signals", "cache", "sweeps", "dask", "api", "misc")
OK_ROW = re.compile(r"\bok\b")    # a finished sweep row, in CSV or JSON
KEEP = False                      # --keep: leave the temporary folders


# --- running ---------------------------------------------------------------------------
@dataclass
class Outcome:
    rc: int | None
    out: str
    err: str
    wall: float                   # s from launch to exit
    timed_out: bool
    stray: int                    # processes of its session still alive after it ended

    @property
    def lines(self):
        return [ln for ln in self.err.splitlines() if ln.strip()]

    def describe(self):
        first = self.lines[0][:200] if self.lines else ""
        return f"exit {self.rc}, {len(self.lines)} stderr lines, first: {first!r}"


@contextlib.contextmanager
def sandbox():
    """A fresh folder with cache/ and logs/; removed afterwards (unless --keep)."""
    box = Path(tempfile.mkdtemp(prefix="tf-fault-"))
    (box / "logs").mkdir()
    try:
        yield box
    finally:
        if KEEP:
            print(f"      kept {box}")
        else:
            for d, dirs, _ in os.walk(box):
                for x in dirs:
                    if not os.path.islink(os.path.join(d, x)):
                        os.chmod(os.path.join(d, x), 0o700)
            shutil.rmtree(box, ignore_errors=True)


def env_for(box, **extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("TOOTHFEM_DEBUG", "TOOTHFEM_SOLVER", "TOOTHFEM_CACHE")}
    env.update(TOOTHFEM_CACHE=str(box / "cache"), MPLBACKEND="Agg")
    for k, v in extra.items():
        env.pop(k, None) if v is None else env.__setitem__(k, v)
    return env


def _drop_caps():
    """In the child: give up the capabilities that let root ignore file permissions."""
    libc = ctypes.CDLL(None, use_errno=True)
    for cap in (1, 2, 3):                 # DAC_OVERRIDE, DAC_READ_SEARCH, FOWNER
        libc.prctl(24, cap, 0, 0, 0)      # PR_CAPBSET_DROP (effective again after exec)


def launch(argv, box, env=None, drop_caps=False, tag="cmd"):
    """Start ``argv`` in its own session; stdout/stderr to box/logs/TAG.{out,err}."""
    logs = box / "logs"
    with open(logs / f"{tag}.out", "wb") as fo, open(logs / f"{tag}.err", "wb") as fe:
        p = subprocess.Popen([str(a) for a in argv], cwd=box, env=env or env_for(box),
                             stdin=subprocess.DEVNULL, stdout=fo, stderr=fe,
                             start_new_session=True,
                             preexec_fn=_drop_caps if drop_caps and os.geteuid() == 0 else None)
    p.t0, p.logs = time.monotonic(), (logs / f"{tag}.out", logs / f"{tag}.err")
    return p


def _session(sid):
    """Live processes of session ``sid`` (zombies excluded)."""
    pids = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            with contextlib.suppress(OSError, IndexError, ValueError):
                fields = Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()
                if int(fields[3]) == sid and fields[0] != "Z":
                    pids.append(int(d))
    return pids


def stop(p, sig=signal.SIGKILL):
    """Signal ``p``'s whole process group (it leads its own session) and reap ``p``."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(p.pid, sig)
    with contextlib.suppress(subprocess.TimeoutExpired):
        p.wait(10)


def finish(p, timeout=TIMEOUT):
    """Wait for ``p`` (killing its group at ``timeout``), then for its session to empty."""
    timed_out = False
    try:
        p.wait(max(1.0, p.t0 + timeout - time.monotonic()))
    except subprocess.TimeoutExpired:
        timed_out = True
        stop(p)
    wall = time.monotonic() - p.t0
    deadline = time.monotonic() + 10
    while _session(p.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    stray = len(_session(p.pid))
    if stray:
        stop(p)
    read = [f.read_text(errors="replace") for f in p.logs]
    return Outcome(None if timed_out else p.returncode, read[0], read[1], wall, timed_out,
                   stray)


def run(argv, box, timeout=TIMEOUT, **kw):
    return finish(launch(argv, box, **kw), timeout)


# --- judging helpers -------------------------------------------------------------------
def one_line(o, *names):
    """Why stderr is not one line (naming one of ``names``), or None."""
    if "Traceback" in o.err:
        return "a traceback on stderr"
    if len(o.lines) != 1:
        return f"{len(o.lines)} stderr lines"
    if names and not any(str(n) in o.lines[0] for n in names):
        return f"the line names none of {[str(n) for n in names]}"
    return None


def refused(o, *names):
    """None when ``o`` is a one-line refusal (exit 2) naming one of ``names``."""
    if o.timed_out:
        return f"still running after {TIMEOUT} s"
    if o.rc != 2:
        return f"not refused: {o.describe()}"
    why = one_line(o, *names)
    return None if why is None else f"{why}: {o.describe()}"


def hidden_tmp(box):
    """Hidden temporary folders (``.NAME*.tmp-*``) anywhere under ``box``."""
    return [d for d, _, _ in os.walk(box) if Path(d).name.startswith(".")
            and ".tmp-" in Path(d).name]


def cache_tmp(box):
    return [p.name for p in (box / "cache").glob("*.tmp")] if (box / "cache").is_dir() else []


def ok_rows(where):
    """Most finished-row lines in any one file under ``where`` (cache and logs excluded)."""
    best = 0
    for d, dirs, files in os.walk(where):
        dirs[:] = [x for x in dirs if x not in ("cache", "logs")]
        for f in files:
            with contextlib.suppress(OSError):
                p = Path(d, f)
                if p.stat().st_size < 5e6:
                    best = max(best, sum(1 for ln in p.read_text(errors="replace")
                                         .splitlines() if OK_ROW.search(ln)))
    return best


def wait_rows(p, box, k, limit=90):
    """Wait until ``k`` finished rows are on disk (or ``p`` ended); the count seen."""
    end = time.monotonic() + limit
    while p.poll() is None and time.monotonic() < end:
        n = ok_rows(box)
        if n >= k:
            return n
        time.sleep(0.05)
    return ok_rows(box)


def verdict(why):
    return "good" if why is None else (why if why.startswith("good") else f"bad: {why}")


def cases_in_boxes(table):
    """[(name, verdict)] of ``table`` [(name, fn(box) -> why or None)], each in a sandbox;
    a hidden temporary folder left anywhere in the box makes a good case bad."""
    res = []
    for name, fn in table:
        with sandbox() as box:
            try:
                why = fn(box)
            except Exception as exc:     # noqa: BLE001 -- a probe failure is reported
                why = f"probe error {type(exc).__name__}: {exc}"
            left = hidden_tmp(box)
            if (why is None or why.startswith("good")) and left:
                why = f"hidden temporary folder left: {Path(left[0]).name}"
        res.append(report(name, verdict(why)))
    return res


def report(name, v):
    print(f"  {'good' if v.startswith('good') else 'BAD '} {name}: {v}", flush=True)
    return name, v


# --- 1. filesystem ---------------------------------------------------------------------
def geometry(box, out, *extra, **kw):
    return run([TF, "geometry", CASE, *extra, "--out", out], box, **kw)


def written(o, out):
    if o.timed_out or o.rc != 0:
        return f"not written: {o.describe()}"
    return None if (Path(out) / "profile.csv").is_file() else "exit 0 but no profile.csv"


def _fs_new(box):
    return written(geometry(box, box / "new"), box / "new")


def _fs_user_folder(box):
    out = box / "thesis"
    out.mkdir()
    (out / "thesis.txt").write_text("chapter 1")
    why = refused(geometry(box, out), out)
    return why or (None if (out / "thesis.txt").read_text() == "chapter 1"
                   else "thesis.txt changed")


def _fs_case_folder(box):
    proj = box / "proj"
    proj.mkdir()
    shutil.copy(CASE, proj / "case.toml")
    (proj / "notes.txt").write_text("my notes")
    why = refused(run([TF, "geometry", proj / "case.toml", "--out", proj], box), proj)
    same = (proj / "notes.txt").read_text() == "my notes" and \
        (proj / "case.toml").read_bytes() == CASE.read_bytes()
    return why or (None if same else "the case or notes.txt changed")


def _fs_file(box):
    f = box / "result.txt"
    f.write_text("keep me")
    why = refused(geometry(box, f), f)
    return why or (None if f.read_text() == "keep me" else "the file changed")


def _fs_symlink(box):
    (box / "elsewhere" / "target").mkdir(parents=True)
    link = box / "link"
    link.symlink_to(box / "elsewhere" / "target")
    for k in (1, 2):                     # a new result through the link, then a replacement
        o = geometry(box, link)
        if o.rc != 0:
            return f"run {k}: {o.describe()}"
        if not link.is_symlink():
            return f"run {k}: the symlink was replaced by a {'folder' if link.is_dir() else 'file'}"
        if not (box / "elsewhere" / "target" / "profile.csv").is_file():
            return f"run {k}: nothing written where the link points"
    return None


def _fs_earlier(box):
    out = box / "res"
    geometry(box, out)
    return written(geometry(box, out), out)


def _fs_earlier_with_note(box):
    out = box / "res"
    if (o := geometry(box, out)).rc != 0:
        return f"setup: {o.describe()}"
    (out / "notes.txt").write_text("mine")
    why = refused(geometry(box, out), out)
    ok = (out / "notes.txt").is_file() and (out / "notes.txt").read_text() == "mine"
    return why or (None if ok else "notes.txt changed or gone")


def _fs_long_name(box):
    return written(geometry(box, box / ("a" * 255)), box / ("a" * 255))


def _fs_readonly_parent(box):
    parent = box / "ro"
    parent.mkdir()
    parent.chmod(0o555)
    o = geometry(box, parent / "new", drop_caps=True)
    why = refused(o, parent)
    return why or (f"written into the read-only parent: {os.listdir(parent)}"
                   if os.listdir(parent) else None)


def _host():
    try:
        from toothfem.leftovers import host
    except ImportError:
        return re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"
    return host()


def _out_stem(out):
    """The start of ``out``'s hidden siblings as toothfem.output names them (either scheme)."""
    from toothfem import output
    return getattr(output, "_stem", lambda out: f".{out.name}")(out)


def _cache_tmp_start():
    """The start of a cache temporary file a killed write leaves (either scheme)."""
    try:
        import toothfem.leftovers  # noqa: F401  (the scheme that names the writer)
    except ImportError:
        return "."
    return f".tmp-{_host()}-{_dead_pid()}-"


def _dead_pid():
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    pid = p.pid
    while True:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return pid
        pid += 7919


def _fs_swap_leftover(box):
    out = box / "res"
    if (o := geometry(box, out, "--points-per-tooth", "16")).rc != 0:
        return f"setup: {o.describe()}"
    earlier = (out / "profile.csv").read_bytes()
    side = box / f"{_out_stem(out)}.old-{_host()}-{_dead_pid()}-xyz"
    side.mkdir()
    out.rename(side / out.name)
    o = geometry(box, out)
    kept = any(p.read_bytes() == earlier for p in box.rglob("profile.csv") if p.is_file())
    said = [ln for ln in o.lines if re.search(r"earlier|restor|back|aside|left|previous", ln)]
    if kept or said:
        return "good" + (" (kept)" if kept else f" (said: {said[0][:120]!r})") + \
            f" exit {o.rc}"
    return f"the earlier result vanished without a word ({o.describe()})"


FS = [("geometry --out new folder", _fs_new),
      ("--out a user's folder with thesis.txt", _fs_user_folder),
      ("--out the case file's own folder", _fs_case_folder),
      ("--out an existing file", _fs_file),
      ("--out a symlink to a folder elsewhere (twice)", _fs_symlink),
      ("--out an earlier result", _fs_earlier),
      ("--out an earlier result with the user's notes.txt", _fs_earlier_with_note),
      ("--out a 255-character name", _fs_long_name),
      ("--out in a read-only parent", _fs_readonly_parent),
      ("leftover of a run killed inside the output swap", _fs_swap_leftover)]


def filesystem(args):
    return cases_in_boxes(FS)


# --- 2. signals ------------------------------------------------------------------------
def _signal_run(sig, at):
    """``toothfem run`` sent ``sig`` ``at`` s after launch (SIGINT to the group)."""
    with sandbox() as box:
        out = box / "res"
        p = launch([TF, "run", CASE, "--out", out], box)
        time.sleep(max(0.0, p.t0 + at - time.monotonic()))
        if p.poll() is None:
            (os.killpg if sig == signal.SIGINT else os.kill)(p.pid, sig)
        t_sig = time.monotonic() - p.t0
        o = finish(p)
        left = [Path(x).name for x in hidden_tmp(box)] + cache_tmp(box)
        trail = f"; left behind: {left}" if left else ""
        if o.stray:
            trail += f"; {o.stray} process(es) left running"
        if o.timed_out:
            return f"still running {TIMEOUT} s after launch"
        if o.rc == 0:
            if out.is_dir() and not trail:
                return "good (finished before the signal)"
            return f"exit 0 before the signal{trail}{'' if out.is_dir() else '; no DIR'}"
        if o.rc == -sig and at < 0.8 and not left and not out.exists():
            return "good (killed at start-up, before toothfem's handler: shell exit " \
                   f"{128 + sig}, nothing written)"
        why = None if o.rc == 128 + sig else f"exit {o.rc}, expected {128 + sig}"
        why = why or one_line(o)
        if out.exists():
            why = (why + "; " if why else "") + "the output folder exists"
        if why or trail:
            return f"{why or 'exit ok'}{trail} (ended {o.wall - t_sig:.1f} s after the " \
                   f"signal; {o.describe()})"
        return None


def _sweep_sigterm(box):
    out = box / "res"
    p = launch(sweep_argv(out, "--workers", "1"), box)
    wait_rows(p, box, 1, limit=30)
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
    o = finish(p)
    if o.timed_out:
        return f"still running {TIMEOUT} s after launch"
    why = (None if o.rc == 143 else f"exit {o.rc}, expected 143") or one_line(o)
    if o.stray:
        why = (why + "; " if why else "") + f"{o.stray} process(es) left running"
    return None if why is None else f"{why} ({o.describe()})"


def signals(args):
    rng = random.Random(args.seed)
    typical = 22.0                # s, `run` on the pin-housing case with a cold cache
    res = []
    if not args.quick:
        with sandbox() as box:
            o = run([TF, "run", CASE, "--out", box / "res"], box)
            typical = o.wall
            res.append(report(f"undisturbed run ({o.wall:.1f} s)",
                              verdict(None if o.rc == 0 else o.describe())))
    n = args.signal_tries
    if args.quick:
        term = [1.3, 2.9, 6.4][:max(n, 1)]   # inside gmsh meshing (TOOTHFEM_DEBUG timings)
        ints = [2.0]
    else:                                 # a third inside the first meshes, the rest anywhere
        term = [rng.uniform(0.5, 3.5) if k < n // 3 else rng.uniform(0.2, 1.05 * typical)
                for k in range(n)]
        ints = [rng.uniform(1.0, 3.5)] + [rng.uniform(1.0, typical)
                                          for _ in range(max(1, n // 5) - 1)]
    for sig, instants in ((signal.SIGTERM, term), (signal.SIGINT, ints)):
        for at in instants:
            name = f"run, {signal.Signals(sig).name} at {at:.2f} s"
            try:
                res.append(report(name, verdict(_signal_run(sig, at))))
            except Exception as exc:      # noqa: BLE001
                res.append(report(name, f"bad: probe error {exc}"))
    res += cases_in_boxes([("sweep, SIGTERM after the first row", _sweep_sigterm)])
    return res


# --- 3. cache --------------------------------------------------------------------------
def contact(box, out, **kw):
    return run([TF, "contact", CASE, "--positions", "4", "--field", "none", "--out", out],
               box, **kw)


def _cache_stale_tmp(box):
    (box / "cache").mkdir()
    stale = box / "cache" / f"{_cache_tmp_start()}0123456789abcdef.k3j4h5q1.tmp"
    stale.write_bytes(b"PK\x03\x04 half a file")
    old = time.time() - 2 * 86400
    os.utime(stale, (old, old))
    o = contact(box, box / "res")
    if o.rc != 0:
        return f"run failed: {o.describe()}"
    return f"the stale {stale.name} (two days old) is still there" if stale.exists() else None


def _cache_readonly(box):
    (box / "cache").mkdir()
    (box / "cache").chmod(0o500)
    o = contact(box, box / "res", drop_caps=True)
    why = written(o, box / "res") if o.rc else None
    if why is None and not (box / "res" / "summary.json").is_file():
        why = "exit 0 but no summary.json"
    if why is None and not any("cache" in ln for ln in o.lines):
        why = f"no warning line naming the cache ({o.describe()})"
    return why


def _cache_corrupt(box):
    if (o := contact(box, box / "first")).rc != 0:
        return f"setup: {o.describe()}"
    files = list((box / "cache").glob("*.npz"))
    if not files:
        return "probe: the first run stored nothing in the cache"
    for k, f in enumerate(files):
        f.write_bytes(b"garbage" * 50 if k % 2 == 0 else f.read_bytes()[:100])
    o = contact(box, box / "res")
    return None if o.rc == 0 and (box / "res" / "summary.json").is_file() else o.describe()


def cache(args):
    return cases_in_boxes([("stale temporary cache file is removed", _cache_stale_tmp),
                           ("cache folder not writable (mode 500)", _cache_readonly),
                           ("corrupt and truncated cache files", _cache_corrupt)])


# --- 4. sweeps -------------------------------------------------------------------------
VALUES = "0.8,0.9,1.0,1.1,1.2,1.3"     # cycloid.eccentricity_mm, all valid for the case


def sweep_argv(out, *extra):
    return [TF, "sweep", CASE, "--vary", f"cycloid.eccentricity_mm={VALUES}",
            "--positions", "4", *extra, "--out", out]


def _sweep_kill_resume(box):
    out = box / "res"
    argv = sweep_argv(out, "--workers", "1")
    p = launch(argv, box)
    n = wait_rows(p, box, 3)
    if p.poll() is not None:
        return f"probe: the sweep ended before it was half-way ({n} rows seen)"
    stop(p)
    kept, had = (ok_rows(out), "DIR exists") if out.exists() else (0, "no DIR")
    o = run(argv, box, tag="rerun")
    rows = ok_rows(out) if out.exists() else 0
    summary = (out / "sweep.json").read_text() if (out / "sweep.json").is_file() else ""
    said = re.search(r"resum|skip|reus|already|earlier", o.out + o.err + summary, re.I)
    why = [] if kept >= n else [f"after SIGKILL {kept} of the {n} finished rows are under "
                                f"DIR ({had})"]
    if o.rc != 0 or rows < 6:
        why.append(f"rerun: {o.describe()}, {rows} ok rows")
    elif not said:
        why.append(f"rerun recomputed every point (no word of resumed or skipped points; "
                   f"{o.wall:.1f} s)")
    return "; ".join(why) or None


def _sweep_sigint(box):
    out = box / "res"
    p = launch(sweep_argv(out, "--workers", "1"), box)
    n = wait_rows(p, box, 2)
    if p.poll() is not None:
        return f"probe: the sweep ended before it was half-way ({n} rows seen)"
    os.killpg(p.pid, signal.SIGINT)
    o = finish(p)
    why = [] if o.rc == 130 else [f"exit {o.rc}, expected 130"]
    if (w := one_line(o)):
        why.append(w)
    if (kept := ok_rows(out) if out.exists() else 0) < n:
        why.append(f"{kept} of the {n} finished rows kept under DIR")
    if o.stray:
        why.append(f"{o.stray} process(es) left running")
    return f"{'; '.join(why)} ({o.describe()})" if why else None


def _sweep_all_fail(box):
    o = run(sweep_argv(box / "res", "--workers", "1"), box,
            env=env_for(box, TOOTHFEM_SOLVER="bogus"))
    if o.rc in (0, None, 3):
        return f"{'timed out' if o.timed_out else 'exit ' + str(o.rc)} with every point failed " \
               f"({o.describe()})"
    if not re.search(r"\b(6|all)\b[^\n]*fail|fail[^\n]*\b(6|all)\b", o.err):
        return f"stderr does not say how many points failed ({o.describe()})"
    return None


def sweeps(args):
    return cases_in_boxes([("SIGKILL half-way keeps the rows; the rerun resumes",
                            _sweep_kill_resume),
                           ("SIGINT to the group half-way", _sweep_sigint),
                           ("every point fails (TOOTHFEM_SOLVER=bogus)", _sweep_all_fail)])


# --- 5. dask ---------------------------------------------------------------------------
def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def mute_server():
    """A TCP port that accepts connections and never says a word."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(16)
    conns, done = [], threading.Event()

    def accept():
        while not done.is_set():
            with contextlib.suppress(OSError):
                conns.append(srv.accept()[0])

    threading.Thread(target=accept, daemon=True).start()
    try:
        yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    finally:
        done.set()
        for c in conns + [srv]:
            c.close()


def _wait_log(p, text, limit=45):
    end = time.monotonic() + limit
    while time.monotonic() < end and p.poll() is None:
        if text in p.logs[1].read_text(errors="replace"):
            return True
        time.sleep(0.2)
    return False


@contextlib.contextmanager
def cluster(box, workers=0):
    """A dask scheduler on a free port with ``workers`` single-thread workers (no nanny)."""
    port = _free_port()
    procs = [launch([DASK, "scheduler", "--host", "127.0.0.1", "--port", port,
                     "--no-dashboard"], box, tag="scheduler")]
    addr = f"tcp://127.0.0.1:{port}"
    try:
        if not _wait_log(procs[0], "Scheduler at"):
            raise RuntimeError("the dask scheduler did not start")
        for k in range(workers):
            procs.append(launch([DASK, "worker", addr, "--nthreads", "1", "--no-nanny",
                                 "--no-dashboard"], box, tag=f"worker{k}"))
            if not _wait_log(procs[-1], "Registered to"):
                raise RuntimeError("the dask worker did not register")
        yield addr, procs
    finally:
        for p in procs:
            stop(p)


def tolerance_argv(out, addr):
    return [TF, "tolerance", CASE, "--samples", "4", "--positions", "4", "--share-samples",
            "0", "--scheduler", addr, "--out", out]


def judge_dask(o, since=0.0, rows=None, out=None):
    took = o.wall - since
    if o.timed_out:
        return f"still running {TIMEOUT} s after launch: killed"
    why = [] if took <= 60 else [f"ended {took:.0f} s after the fault"]
    if o.rc in (0, 3) or o.rc < 0:
        why.append(f"exit {o.rc}")
    if (w := one_line(o)):
        why.append(w)
    if rows is not None and (kept := ok_rows(out) if out.exists() else 0) < rows:
        why.append(f"{kept} of the {rows} finished rows kept under DIR")
    if o.stray:
        why.append(f"{o.stray} process(es) left running")
    return f"{'; '.join(why)} ({o.describe()}, {took:.0f} s)" if why else None


def _dask_mute(cmd):
    def fn(box):
        with mute_server() as addr:
            argv = (sweep_argv(box / "res", "--scheduler", addr) if cmd == "sweep"
                    else tolerance_argv(box / "res", addr))
            return judge_dask(run(argv, box))
    return fn


def _dask_no_workers(cmd):
    def fn(box):
        with cluster(box) as (addr, _):
            argv = (sweep_argv(box / "res", "--scheduler", addr) if cmd == "sweep"
                    else tolerance_argv(box / "res", addr))
            return judge_dask(run(argv, box))
    return fn


def _dask_kill(which):
    def fn(box):
        out = box / "res"
        with cluster(box, workers=1) as (addr, procs):
            p = launch(sweep_argv(out, "--scheduler", addr), box)
            n = wait_rows(p, box, 2)
            if p.poll() is not None:
                finish(p)
                return f"probe: the sweep ended before it was half-way ({n} rows seen)"
            stop(procs[1] if which == "worker" else procs[0])
            since = time.monotonic() - p.t0
            return judge_dask(finish(p), since, rows=n, out=out)
    return fn


def dask(args):
    table = [("sweep --scheduler at a mute TCP port", _dask_mute("sweep")),
             ("tolerance --scheduler at a mute TCP port", _dask_mute("tolerance"))]
    if not args.quick:
        table += [("sweep --scheduler without workers", _dask_no_workers("sweep")),
                  ("tolerance --scheduler without workers", _dask_no_workers("tolerance")),
                  ("sweep whose only worker is killed -9 half-way", _dask_kill("worker")),
                  ("sweep whose scheduler is killed -9 half-way", _dask_kill("scheduler"))]
    return cases_in_boxes(table)


# --- 6. api ----------------------------------------------------------------------------
API_RUNNER = r"""
import json, signal, sys, warnings
import numpy as np
import toothfem
from toothfem.errors import ToothfemError
from toothfem.efficiency import evaluate, predict, operating_point
from toothfem.geometry import cycloid_mesh
from toothfem.pipeline import run_case, contact_analysis
from toothfem.fem.drives import drive_for
CYC, SINE = sys.argv[1], sys.argv[2]
case, sine = toothfem.load_case(CYC), toothfem.load_case(SINE)
geom, nan, inf = case.cycloid.geometry(), float("nan"), float("inf")
def finite(x):
    try:
        return bool(np.all(np.isfinite(np.asarray(x, float))))
    except (TypeError, ValueError):
        return True
for line in sys.stdin:
    name, code = json.loads(line)
    signal.alarm(100)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            r = eval(code)
            said = [str(w.message) for w in caught] + [str(w) for w in getattr(r, "warnings", ())]
            said += [str(w) for w in (getattr(r, "summary", None) or {}).get("warnings", [])]
            rec = {"raised": None, "finite": finite(r), "value": repr(r)[:100], "said": said}
        except Exception as e:
            rec = {"raised": type(e).__name__, "tf": isinstance(e, ToothfemError),
                   "msg": (str(e).splitlines() or [""])[0][:240]}
    signal.alarm(0)
    print(json.dumps({"name": name, **rec}), flush=True)
"""
_C = "contact_analysis(case, positions=4, field='none', torque_Nm={})"
#: (kind, expression, names the message may use). Kinds: path (works or refuses naming
#: `case`), refuse (a ToothfemError naming the argument), absurd (refused naming the load,
#: or a finite result with a warning naming it).
API = [("path", "evaluate(SINE, 500.0, 28.0).efficiency", ("case",)),
       ("path", "predict(SINE, 500.0, 28.0)", ("case",)),
       ("path", "operating_point(CYC)[1]", ("case",)),
       ("path", "contact_analysis(CYC, positions=4, field='none').summary['max_force_N']",
        ("case",)),
       ("path", "drive_for(CYC).member_torque(167.0)", ("case",)),
       ("refuse", "predict(sine, '500', 28.0)", ("speed",)),
       ("refuse", "predict(sine, 'fast', 28.0)", ("speed",)),
       ("refuse", "predict(sine, True, 28.0)", ("speed",)),
       ("refuse", "predict(sine, 500.0, '28')", ("torque",)),
       ("refuse", "predict(sine, 500.0, True)", ("torque",)),
       ("refuse", "predict(sine, 500.0, 28.0, oil_temp_C='hot')", ("oil_temp",)),
       ("refuse", "predict(sine, 500.0, 28.0, oil_temp_C=True)", ("oil_temp",)),
       ("refuse", _C.format("True"), ("torque",)),
       ("refuse", "drive_for(case).member_torque('88')", ("torque",)),
       ("refuse", "cycloid_mesh.meshing(geom, [0.0, 0.1], crank_speed_rad_s='fast')"
        ".moment_arm", ("crank_speed",)),
       ("refuse", "predict(sine, nan, 28.0)", ("speed",)),
       ("refuse", "predict(sine, 500.0, inf)", ("torque",)),
       ("refuse", "predict(sine, 500.0, 28.0, oil_temp_C=inf)", ("oil_temp",)),
       ("refuse", "cycloid_mesh.meshing(geom, np.array([0.0, nan]), crank_speed_rad_s=190.1)"
        ".moment_arm", ("angle", "position", "theta", "phi")),
       ("refuse", "cycloid_mesh.meshing(geom, np.array([0.0, inf]), crank_speed_rad_s=190.1)"
        ".moment_arm", ("angle", "position", "theta", "phi")),
       ("refuse", _C.format("nan"), ("torque",)),
       ("refuse", "drive_for(case).cycle_solver(4).solve(nan).force", ("torque",)),
       ("refuse", "run_case(case, None, fem=False)", ("out",)),
       ("refuse", "run_case(None, 'x', fem=False)", ("case",)),
       ("absurd", _C.format("1e12"), ("torque", "load")),
       ("absurd", "drive_for(case).cycle_solver(4).solve(drive_for(case).member_torque(1e12))"
        ".force", ("torque", "load")),
       ("absurd", "evaluate(case, 1815.0, 1e12)", ("torque", "load"))]


def _judge_api(kind, names, r):
    if r is None:
        return "no answer (the runner died or timed out)"
    named = r["raised"] and r["tf"] and any(n in r["msg"] for n in names)
    if named:
        return None
    if r["raised"]:
        return f"{r['raised']}{' (a ToothfemError naming none of ' + str(list(names)) + ')' if r['tf'] else ''}: {r['msg'][:160]}"
    if not r["finite"]:
        return f"a non-finite result, no error: {r['value']}"
    if kind == "path":
        return None
    if kind == "absurd" and any(any(n in s for n in names) for s in r["said"]):
        return "good (finite result with a warning)"
    return f"accepted: {r['value']}"


def api(args):
    table = [(f"{code}", kind, code, names) for kind, code, names in API]
    if args.quick:
        table = [t for t in table if "contact_analysis" not in t[2] and "cycle_solver" not in t[2]]
    with sandbox() as box:
        (box / "runner.py").write_text(API_RUNNER)
        (box / "in.jsonl").write_text("".join(json.dumps([n, c]) + "\n"
                                              for n, _, c, _ in table))
        with open(box / "in.jsonl") as fin:
            p = subprocess.Popen([PY, box / "runner.py", CASE, SINE], cwd=box, stdin=fin,
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                 env=env_for(box), text=True, start_new_session=True)
            try:
                out, _ = p.communicate(timeout=60 + 60 * len(table))
            except subprocess.TimeoutExpired:
                stop(p)
                out = ""
        got = {}
        for ln in out.splitlines():
            with contextlib.suppress(ValueError):
                d = json.loads(ln)
                got[d["name"]] = d
    return [report(name, verdict(_judge_api(kind, names, got.get(name))))
            for name, kind, _, names in table]


# --- 7. misc ---------------------------------------------------------------------------
MEASURED = {"';' delimiter": "input_speed_rpm;output_torque_Nm;efficiency\n500;28;0.8247\n"
                             "500;20;0.80\n500;10;0.75\n",
            "tab delimiter": "input_speed_rpm\toutput_torque_Nm\tefficiency\n500\t28\t0.8247\n"
                             "500\t20\t0.80\n500\t10\t0.75\n",
            "';' with decimal commas": "input_speed_rpm;output_torque_Nm;efficiency\n500;28;0,8247"
                                       "\n500;20;0,80\n500;10;0,75\n",
            "quoted decimal commas": 'input_speed_rpm,output_torque_Nm,efficiency\n500,28,"0,8247"'
                                     '\n500,20,"0,80"\n500,10,"0,75"\n'}


def _loop_csv(text):
    def fn(box):
        (box / "rig.csv").write_text(text)
        o = run([TF, "loop", SINE, box / "rig.csv", "--out", box / "res"], box)
        if o.rc == 0:
            return f"accepted: {o.describe()}"
        if re.search(r"delimiter|decimal", o.err, re.I) and not one_line(o):
            return None
        return f"the message says neither delimiter nor decimal comma ({o.describe()})"
    return fn


def _variant(box, subs):
    text = CASE.read_text()
    for a, b in subs:
        text, k = re.subn(a, b, text, flags=re.M)
        assert k, a
    (box / "case.toml").write_text(text)
    return box / "case.toml"


def _published_typo(box):
    path = _variant(box, [(r"^pins_in_contact = 20", "pins_in_contct = 20")])
    o = run([TF, "check", path], box)
    if o.rc == 2:
        return refused(o, "pins_in_contct")
    if o.rc == 0 and "pins_in_contct" in o.out + o.err:
        return None
    return f"accepted without naming the key: {o.describe()}"


def _pins_400(box):
    path = _variant(box, [(r"^pin_count = 40 ", "pin_count = 400 "),
                          (r"^lobe_count = 39 ", "lobe_count = 399 "),
                          (r"^eccentricity_mm = 1\.0 ", "eccentricity_mm = 0.1 "),
                          (r"^pin_radius_mm = 2\.0 ", "pin_radius_mm = 0.5 "),
                          (r"^stated_ratio = 121.*$", ""),
                          (r"^housing_outer_radius_mm = .*$", "")])
    o = run([TF, "contact", path, "--positions", "4", "--field", "none", "--out", box / "res"],
            box, timeout=240)
    if o.rc == 0:
        return None
    return refused(o) if o.rc == 2 else (f"still running after 240 s" if o.timed_out
                                         else o.describe())


def _big_torque(cmd):
    def fn(box):
        if cmd == "contact":
            o = run([TF, "contact", CASE, "--torque-Nm", "1e6", "--positions", "4", "--field",
                     "none", "--out", box / "res"], box)
        else:
            path = _variant(box, [(r"^output_torque_Nm = 167\.0", "output_torque_Nm = 1e6")])
            o = run([TF, "run", path, "--no-fem", "--out", box / "res"], box)
        if o.rc == 2:
            return refused(o)
        if o.rc == 0:
            return None if re.search(r"warning", o.out + o.err, re.I) else "silent: exit 0, no warning"
        return o.describe()
    return fn


def _env(cmd, **extra):
    def fn(box):
        argv = ([TF, "geometry", CASE, "--out", box / "res"] if cmd == "geometry" else
                [TF, "contact", CASE, "--positions", "4", "--field", "none", "--out",
                 box / "res"])
        o = run(argv, box, env=env_for(box, **extra))
        if o.timed_out or o.rc == 3 or o.rc not in (0, 2) or "Traceback" in o.err:
            return o.describe()
        return None if len(o.lines) <= 2 else f"{len(o.lines)} stderr lines ({o.describe()})"
    return fn


def misc(args):
    table = [(f"loop CSV, {k}", _loop_csv(v)) for k, v in MEASURED.items()]
    table += [("misspelled key in [published]", _published_typo),
              ("contact --torque-Nm 1e6", _big_torque("contact")),
              ("run --no-fem, output_torque_Nm = 1e6", _big_torque("run")),
              ("contact, PYTHONIOENCODING=ascii", _env("contact", PYTHONIOENCODING="ascii")),
              ("geometry, MPLBACKEND=bogus", _env("geometry", MPLBACKEND="bogus")),
              ("geometry, HOME unset", _env("geometry", HOME=None)),
              ("contact, all three", _env("contact", PYTHONIOENCODING="ascii",
                                          MPLBACKEND="bogus", HOME=None))]
    if not args.quick:
        table.insert(4, ("a case with 400 pins (contact)", _pins_400))
    return cases_in_boxes(table)


# --- main ------------------------------------------------------------------------------
def main(argv=None):
    global KEEP
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--classes", default=",".join(CLASSES),
                    help=f"comma-separated, of {', '.join(CLASSES)} (default: all)")
    ap.add_argument("--signal-tries", type=int, default=None,
                    help="SIGTERM instants for `run` (default 20; 3 with --quick)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the signal instants")
    ap.add_argument("--quick", action="store_true",
                    help="a reduced set, about 2-3 minutes (no dask class without `dask`)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folders")
    args = ap.parse_args(argv)
    KEEP = args.keep
    if args.signal_tries is None:
        args.signal_tries = 3 if args.quick else 20
    chosen = [c.strip() for c in args.classes.split(",") if c.strip()]
    unknown = sorted(set(chosen) - set(CLASSES))
    if unknown:
        ap.error(f"unknown classes {unknown}; valid: {', '.join(CLASSES)}")
    if "dask" in chosen and not Path(DASK).exists():
        print(f"no {DASK}: the dask class is skipped")
        chosen.remove("dask")
    t0, results = time.monotonic(), []
    for cls in chosen:
        print(f"{cls}:", flush=True)
        t1 = time.monotonic()
        results += [(f"{cls}/{n}", v) for n, v in globals()[cls](args)]
        print(f"  ({time.monotonic() - t1:.0f} s)", flush=True)
    bad = [(n, v) for n, v in results if not v.startswith("good")]
    print(f"\nbadly handled ({len(bad)}):")
    for n, v in bad:
        print(f"  {n}: {v}")
    print(f"\nhandled well: {len(results) - len(bad)} of {len(results)} "
          f"({time.monotonic() - t0:.0f} s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
