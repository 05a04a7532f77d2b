"""Adversarial faults around the commands: how many the project handles as it promises (issue 27).

Each case runs ``toothfem`` (or Python snippets) in a subprocess, in a fresh temporary folder
with ``TOOTHFEM_CACHE`` inside it and ``MPLBACKEND=Agg``, under a time limit (120 s), and is
judged ``good`` or ``bad: <why>``; a hidden ``.NAME*.tmp-*`` folder left in the case's folder
makes any case bad. The classes and what they judge:

filesystem  ``--out`` naming a new folder (written); a user's folder, the case file's own
            folder, a file (exit 2, one line naming the path, nothing changed); a symlink
            (written where it points, the link stays a link); an earlier result (replaced);
            one holding a user's note (refused); a 255-character name; a read-only parent
            (one line, nothing written); the leftover of a run killed between the two
            renames of the output swap (the earlier result kept, or its loss said on stderr).
signals     SIGTERM to ``run`` at instants over a run (a third inside the first gmsh meshes)
            and SIGINT to its group: exit 143 / 130 (0 only if it finished within 1 s of
            the signal: else the signal was lost), one stderr line, no output folder, no
            ``*.tmp`` in the cache, no process left; SIGTERM to a ``sweep`` after its first
            row: 143, one line, the row kept, no stray Dask process.
cache       a two-day-old temporary file of a killed write is gone after a run; a cache of
            mode 500 costs a warning line, not the result; corrupt files are misses.
sweeps      SIGKILL to a sweep's group half-way: the finished rows are under DIR and a rerun
            says it resumed them; SIGINT: 130, one line, rows kept; every point failing
            (TOOTHFEM_SOLVER=bogus): non-zero, and stderr counts the failed points.
dask        ``--scheduler`` at a port that never answers, at a scheduler without workers; a
            sweep whose only worker or whose scheduler is killed -9 half-way: ends within
            60 s of the fault, non-zero (not 3), one line, rows kept.
api         README's Python API: a path for a Case (works, or a ToothfemError naming
            ``case``); strings, bools, NaN, inf for speed, torque, temperature, angles and
            ``run_case(case, None)`` (a ToothfemError naming the argument, never NaN); an
            absurd torque (a ToothfemError naming the load, or a warning).
races       (issue 45) two runs into one ``--out`` (the second refused in one line, the
            first whole); a sweep killed -9 into a finished sweep's folder (the finished
            result byte for byte as it was); a sweep under ``ulimit -f 4`` (nothing under
            DIR, one line naming ``--out``); an ``--out`` that is not UTF-8 (written);
            values out of their key's range ([published], [[duty_cycle]], ``--duration-h``:
            refused in one line naming the key).
misc        measured CSVs with ';', tabs, decimal commas (refused saying delimiter or
            decimal, or read whole saying so); a misspelled [published] key (named); 400
            pins (exit 0 or 2); 1e6 N m (a warning or a refusal); PYTHONIOENCODING=ascii,
            MPLBACKEND=bogus, HOME unset (never exit 3, at most two stderr lines).

Run: ``python benchmarks/adversarial_faults.py [--classes filesystem,signals,...]
[--signal-tries N] [--seed S] [--quick] [--keep]``: a verdict line per case, the bad ones
again, ``handled well: X of Y``; exit 1 when any case is handled badly. As root, the
read-only cases drop the capabilities that bypass file permissions in the child.
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
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent     # the environment running the probe (make probe: .venv)
PY, TF, DASK = str(BIN / "python"), str(BIN / "toothfem"), str(BIN / "dask")
CASE, SINE = ROOT / "cases" / "cycloid_pinhousing.toml", ROOT / "cases" / "sine_prototype.toml"
TIMEOUT = 120                     # s, any subprocess; killed (and judged bad) beyond it
CLASSES = ("filesystem", "signals", "cache", "sweeps", "dask", "api", "misc", "races")
OK_ROW = re.compile(r"\bok\b")    # a finished sweep row, in CSV or JSON
KEEP = False                      # --keep: leave the temporary folders
#: How toothfem's progress line of a finished stage begins off a terminal (toothfem/bars.py;
#: not imported: the probe judges the installed command from outside).
PROGRESS_PREFIX = "progress: "


# --- running ---------------------------------------------------------------------------
@dataclass
class Outcome:
    rc: int | None                # None: killed at the time limit
    out: str
    err: str
    wall: float                   # s from launch to exit
    stray: int                    # processes of its session alive 10 s after it ended

    @property
    def lines(self):
        """stderr's lines but the progress lines of finished stages (toothfem.bars)."""
        return [ln for ln in self.err.splitlines()
                if ln.strip() and not ln.startswith(PROGRESS_PREFIX)]

    def describe(self):
        head = "timed out" if self.rc is None else f"exit {self.rc}"
        last = f", last: {self.lines[-1][:200]!r}" if len(self.lines) > 1 else ""
        return f"{head}, {len(self.lines)} stderr lines, first: " \
               f"{(self.lines or [''])[0][:200]!r}{last}"


@contextlib.contextmanager
def sandbox():
    """A fresh folder with logs/; removed afterwards (unless --keep)."""
    box = Path(tempfile.mkdtemp(prefix="tf-fault-"))
    (box / "logs").mkdir()
    try:
        yield box
    finally:
        if KEEP:
            print(f"      kept {box}")
        else:                                        # the cases' read-only folders too
            subprocess.run(["chmod", "-R", "u+rwx", box], stderr=subprocess.DEVNULL)
            shutil.rmtree(box, ignore_errors=True)


def env_for(box, **extra):
    """The environment of a case: its own cache, Agg; ``extra`` set (None: removed)."""
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
        libc.prctl(24, cap, 0, 0, 0)      # PR_CAPBSET_DROP: gone from root's caps after exec


def launch(argv, box, env=None, drop_caps=False, tag="cmd"):
    """Start ``argv`` leading its own session; stdout/stderr to box/logs/TAG.{out,err}."""
    logs = (box / "logs" / f"{tag}.out", box / "logs" / f"{tag}.err")
    with open(logs[0], "wb") as fo, open(logs[1], "wb") as fe:
        p = subprocess.Popen([str(a) for a in argv], cwd=box, env=env or env_for(box),
                             stdin=subprocess.DEVNULL, stdout=fo, stderr=fe,
                             start_new_session=True,
                             preexec_fn=_drop_caps if drop_caps and os.geteuid() == 0 else None)
    p.t0, p.logs = time.monotonic(), logs
    return p


def _session(sid):
    """Live processes of session ``sid`` (zombies excluded)."""
    pids = []
    for d in filter(str.isdigit, os.listdir("/proc")):
        with contextlib.suppress(OSError, IndexError, ValueError):
            fields = Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()
            if int(fields[3]) == sid and fields[0] != "Z":
                pids.append(int(d))
    return pids


def stop(p, sig=signal.SIGKILL):
    """Signal ``p``'s whole process group and reap ``p``."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(p.pid, sig)
    with contextlib.suppress(subprocess.TimeoutExpired):
        p.wait(10)


def finish(p, timeout=TIMEOUT):
    """Wait for ``p`` (its group killed at ``timeout``), then up to 10 s for its session."""
    try:
        p.wait(max(1.0, p.t0 + timeout - time.monotonic()))
    except subprocess.TimeoutExpired:
        stop(p)
        p.returncode = None
    wall, deadline = time.monotonic() - p.t0, time.monotonic() + 10
    while _session(p.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    if stray := len(_session(p.pid)):
        stop(p)
    out, err = (f.read_text(errors="replace") for f in p.logs)
    return Outcome(p.returncode, out, err, wall, stray)


def run(argv, box, timeout=TIMEOUT, **kw):
    return finish(launch(argv, box, **kw), timeout)


# --- judging ---------------------------------------------------------------------------
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
    why = "not refused" if o.rc != 2 else one_line(o, *names)
    return why and f"{why}: {o.describe()}"


def problems(o, rc=None, rows=0, out=None):
    """Why ``o`` is bad: not exit ``rc`` (None: any non-zero but 3), not one stderr line,
    fewer than ``rows`` finished rows under ``out``, processes left. None if none."""
    ok = o.rc == rc if rc is not None else (o.rc or 0) > 0 and o.rc != 3
    why = [] if ok else [f"exit {o.rc}" + (f", expected {rc}" if rc else "")]
    why += [w for w in [one_line(o)] if w]
    if rows and (kept := kept_rows(out)) < rows:
        why.append(f"{kept} of the {rows} finished rows kept under DIR")
    why += [f"{o.stray} processes left running"] if o.stray else []
    return f"{'; '.join(why)} ({o.describe()})" if why else None


def hidden_tmp(box):
    """Hidden temporary folders (``.NAME*.tmp-*``) anywhere under ``box``."""
    return [Path(d).name for d, _, _ in os.walk(box)
            if Path(d).name.startswith(".") and ".tmp-" in Path(d).name]


def ok_rows(where):
    """Most finished-row lines in any one file under ``where`` (cache and logs excluded)."""
    best = 0
    for d, dirs, files in os.walk(where):
        dirs[:] = [x for x in dirs if x not in ("cache", "logs")]
        for path in (Path(d, name) for name in files):
            with contextlib.suppress(OSError):
                if path.stat().st_size < 5e6:
                    lines = path.read_text(errors="replace").splitlines()
                    best = max(best, sum(bool(OK_ROW.search(x)) for x in lines))
    return best


def kept_rows(out):
    """Finished rows of a long run into ``out``: in DIR, or in its journal folder beside
    it (``.DIR~<digest>.journal-<key>``, where an unfinished run keeps them)."""
    return max([ok_rows(out) if out.exists() else 0]
               + [ok_rows(j) for j in out.parent.glob(f".{out.name}~*.journal-*")])


def wait_rows(p, box, k, limit=90):
    """Wait until ``k`` finished rows are on disk or ``p`` ended; the count seen."""
    end = time.monotonic() + limit
    while p.poll() is None and time.monotonic() < end and ok_rows(box) < k:
        time.sleep(0.05)
    return ok_rows(box)


def report(name, why):
    v = "good" if why is None else why if why.startswith("good") else f"bad: {why}"
    print(f"  {'good' if v.startswith('good') else 'BAD '} {name}: {v}", flush=True)
    return name, v


def cases_in_boxes(table):
    """[(name, verdict)] of ``table`` [(name, fn(box) -> why or None)], each in a sandbox."""
    res = []
    for name, fn in table:
        with sandbox() as box:
            try:
                why = fn(box)
            except Exception as exc:     # noqa: BLE001 -- a probe failure is reported
                why = f"probe error {type(exc).__name__}: {exc}"
            if (why is None or why.startswith("good")) and hidden_tmp(box):
                why = f"hidden temporary folder left: {hidden_tmp(box)[0]}"
        res.append(report(name, why))
    return res


# --- 1. filesystem ---------------------------------------------------------------------
def geometry(box, out, *extra, **kw):
    return run([TF, "geometry", CASE, *extra, "--out", out], box, **kw)


def written(o, out, name="profile.csv"):
    if o.rc != 0:
        return f"not written: {o.describe()}"
    return None if (Path(out) / name).is_file() else f"exit 0 but no {name}"


def _fs_refused(out, files, case=CASE):
    """``--out out`` where the user's ``files`` ({relative path: text}) are: refused in one
    line naming ``out``, every file unchanged."""
    def fn(box):
        for rel, text in files.items():
            (box / rel).parent.mkdir(parents=True, exist_ok=True)
            (box / rel).write_text(text)
        why = refused(run([TF, "geometry", box / case, "--out", box / out], box), box / out)
        changed = [rel for rel, text in files.items() if (box / rel).read_text() != text]
        return why or (f"changed: {changed}" if changed else None)
    return fn


def _fs_symlink(box):
    (target := box / "elsewhere" / "target").mkdir(parents=True)
    (link := box / "link").symlink_to(target)
    for k in (1, 2):                     # a new result through the link, then a replacement
        if (o := geometry(box, link)).rc != 0:
            return f"run {k}: {o.describe()}"
        if not link.is_symlink():
            return f"run {k}: the symlink was replaced by a real folder or file"
        if not (target / "profile.csv").is_file():
            return f"run {k}: nothing written where the link points"
    return None


def _fs_earlier(note):
    def fn(box):
        if (o := geometry(box, out := box / "res")).rc != 0:
            return f"first run: {o.describe()}"
        if not note:
            return written(geometry(box, out), out)
        (out / "notes.txt").write_text("mine")
        why = refused(geometry(box, out), out)
        kept = (out / "notes.txt").is_file() and (out / "notes.txt").read_text() == "mine"
        return why or (None if kept else "notes.txt changed or gone")
    return fn


def _fs_readonly_parent(box):
    (parent := box / "ro").mkdir()
    parent.chmod(0o555)
    return refused(geometry(box, parent / "new", drop_caps=True), parent) or (
        f"written into the read-only parent: {os.listdir(parent)}" if os.listdir(parent) else None)


def _host():
    try:
        from toothfem.leftovers import host
    except ImportError:                  # the older scheme, in toothfem.output
        return re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"
    return host()


def _dead_pid():
    (p := subprocess.Popen([sys.executable, "-c", "pass"])).wait()
    pid = p.pid
    while True:
        try:
            os.kill(pid, 0)
            pid += 7919
        except ProcessLookupError:
            return pid


def _fs_swap_leftover(box):
    """A run killed between its two renames leaves the earlier result in ``.old-`` only."""
    from toothfem import output           # the siblings' names, in either scheme
    if (o := geometry(box, out := box / "res", "--points-per-tooth", "16")).rc != 0:
        return f"first run: {o.describe()}"
    earlier = (out / "profile.csv").read_bytes()
    stem = getattr(output, "_stem", lambda out: f".{out.name}")(out)
    (side := box / f"{stem}.old-{_host()}-{_dead_pid()}-xyz").mkdir()
    out.rename(side / out.name)
    o = geometry(box, out)
    kept = any(p.read_bytes() == earlier for p in box.rglob("profile.csv") if p.is_file())
    said = [ln for ln in o.lines if re.search(r"earlier|restor|back|aside|left|previous", ln)]
    if kept or said:
        return f"good ({'kept' if kept else 'said: ' + repr(said[0][:120])}; exit {o.rc})"
    return f"the earlier result vanished without a word ({o.describe()})"


def filesystem(args):
    long = "a" * 255
    return cases_in_boxes([
        ("--out a new folder", lambda b: written(geometry(b, b / "new"), b / "new")),
        ("--out a user's folder with thesis.txt",
         _fs_refused("thesis", {"thesis/thesis.txt": "chapter 1"})),
        ("--out the case file's own folder", _fs_refused(
            "proj", {"proj/notes.txt": "my notes", "proj/case.toml": CASE.read_text()},
            case="proj/case.toml")),
        ("--out an existing file", _fs_refused("result.txt", {"result.txt": "keep me"})),
        ("--out a symlink to a folder elsewhere (twice)", _fs_symlink),
        ("--out an earlier result", _fs_earlier(note=False)),
        ("--out an earlier result with the user's notes.txt", _fs_earlier(note=True)),
        ("--out a 255-character name", lambda b: written(geometry(b, b / long), b / long)),
        ("--out in a read-only parent", _fs_readonly_parent),
        ("leftover of a run killed inside the output swap", _fs_swap_leftover)])


# --- 2. signals ------------------------------------------------------------------------
def _signal_run(box, sig, at):
    """``toothfem run`` sent ``sig`` ``at`` s after launch (SIGINT to its group, as Ctrl-C)."""
    p = launch([TF, "run", CASE, "--out", out := box / "res"], box)
    time.sleep(max(0.0, p.t0 + at - time.monotonic()))
    if sent := p.poll() is None:
        (os.killpg if sig == signal.SIGINT else os.kill)(p.pid, sig)
    t_sig = time.monotonic() - p.t0
    o = finish(p)
    left = hidden_tmp(box) + [f.name for f in (box / "cache").glob("*.tmp")]
    if o.rc == 0 and sent and o.wall - t_sig > 1.0:
        return f"the signal was lost: the run went on for {o.wall - t_sig:.1f} s and " \
               f"exited 0 ({o.describe()})"
    if o.rc == 0:
        return "good (finished before the signal)" if out.is_dir() and not left else \
            f"exit 0 before the signal; left behind: {left}"
    if o.rc == -sig and at < 0.8 and not left and not out.exists():
        return f"good (killed while Python started, before toothfem's handler; shell exit " \
               f"{128 + sig}, nothing written)"
    why = problems(o, 128 + sig)
    if left or out.exists():
        why = f"left behind: {left + (['DIR'] if out.exists() else [])}; {why or o.describe()}"
    return why and f"{why} (ended {o.wall - t_sig:.1f} s after the signal)"


def _sweep_sigterm(box):
    p = launch(sweep_argv(out := box / "res", "--workers", "1"), box)
    if (late := _halfway(p, box, 1))[1]:
        return late[1]
    p.send_signal(signal.SIGTERM)
    return problems(finish(p), 143, rows=late[0], out=out)


def signals(args):
    rng, typical, res = random.Random(args.seed), 22.0, []   # 22 s: `run`, cold cache
    if not args.quick:
        with sandbox() as box:
            o = run([TF, "run", CASE, "--out", box / "res"], box)
            typical = o.wall
            res.append(report(f"undisturbed run ({o.wall:.1f} s)",
                              None if o.rc == 0 else o.describe()))
    n = args.signal_tries
    if args.quick:          # inside the first, second and fifth gmsh mesh (timed by hand)
        term, ints = [1.3, 2.65, 6.4][:max(n, 1)], [2.0]
    else:                   # a third inside the first meshes (0.5-3.5 s), the rest anywhere
        term = [rng.uniform(0.5, 3.5) if k < n // 3 else rng.uniform(0.2, 1.05 * typical)
                for k in range(n)]
        ints = [rng.uniform(1.0, 3.5)] + [rng.uniform(1.0, typical)
                                          for _ in range(max(1, n // 5) - 1)]
    table = [(f"run, {signal.Signals(sig).name} at {at:.2f} s",
              lambda b, sig=sig, at=at: _signal_run(b, sig, at))
             for sig, ats in ((signal.SIGTERM, term), (signal.SIGINT, ints)) for at in ats]
    return res + cases_in_boxes(table + [("sweep, SIGTERM after the first row",
                                          _sweep_sigterm)])


# --- 3. cache --------------------------------------------------------------------------
def contact(box, out, **kw):
    return run([TF, "contact", CASE, "--positions", "4", "--field", "none", "--out", out],
               box, **kw)


def _cache_stale_tmp(box):
    try:                     # a killed write's name: with its writer's host and pid if named
        import toothfem.leftovers  # noqa: F401
        start = f".tmp-{_host()}-{_dead_pid()}-"
    except ImportError:
        start = "."
    (box / "cache").mkdir()
    (stale := box / "cache" / f"{start}0123456789abcdef.k3j4h5q1.tmp").write_bytes(b"PK\3\4")
    os.utime(stale, (time.time() - 2 * 86400,) * 2)
    if (o := contact(box, box / "res")).rc != 0:
        return f"run failed: {o.describe()}"
    return f"the stale {stale.name} (two days old) is still there" if stale.exists() else None


def _cache_readonly(box):
    (box / "cache").mkdir()
    (box / "cache").chmod(0o500)
    o = contact(box, box / "res", drop_caps=True)
    return written(o, box / "res", "summary.json") or (
        None if any("cache" in ln for ln in o.lines)
        else f"no warning line naming the cache ({o.describe()})")


def _cache_corrupt(box):
    if (o := contact(box, box / "first")).rc != 0:
        return f"first run: {o.describe()}"
    if not (files := list((box / "cache").glob("*.npz"))):
        return "probe: the first run stored nothing in the cache"
    for k, f in enumerate(files):        # garbage and truncated files, alternately
        f.write_bytes(b"garbage" * 50 if k % 2 == 0 else f.read_bytes()[:100])
    return written(contact(box, box / "res"), box / "res", "summary.json")


def cache(args):
    return cases_in_boxes([("stale temporary file of a killed write", _cache_stale_tmp),
                           ("cache folder not writable (mode 500)", _cache_readonly),
                           ("corrupt and truncated cache files", _cache_corrupt)])


# --- 4. sweeps -------------------------------------------------------------------------
VALUES = "0.8,0.9,1.0,1.1,1.2,1.3"     # cycloid.eccentricity_mm, all valid for the case


def sweep_argv(out, *extra):
    return [TF, "sweep", CASE, "--vary", f"cycloid.eccentricity_mm={VALUES}",
            "--positions", "4", *extra, "--out", out]


def _halfway(p, box, k):
    """Wait for ``k`` finished rows; (rows, None) or (rows, why the probe cannot go on)."""
    n = wait_rows(p, box, k)
    return n, None if p.poll() is None else f"probe: the sweep ended before it was " \
                                             f"half-way ({n} rows seen; {p.returncode})"


def _sweep_kill_resume(box):
    p = launch(argv := sweep_argv(out := box / "res", "--workers", "1"), box)
    if (late := _halfway(p, box, 3))[1]:
        return late[1]
    stop(p)
    n, kept, had = late[0], kept_rows(out), "DIR exists" if out.exists() else "no DIR"
    o = run(argv, box, tag="rerun")
    rows = ok_rows(out) if out.exists() else 0
    text = o.out + o.err + ((out / "sweep.json").read_text()
                            if (out / "sweep.json").is_file() else "")
    said = re.search(r"(resum|skip|reus|already|earlier)\w*\W{0,4}(\d*)", text, re.I)
    why = [] if kept >= n else [f"after SIGKILL {kept} of the {n} finished rows are kept "
                                f"({had})"]
    if o.rc != 0 or rows < 6:
        why.append(f"rerun: {o.describe()}, {rows} ok rows")
    elif not said:
        why.append(f"the rerun recomputed every point (no word of resumed or skipped "
                   f"points; {o.wall:.1f} s)")
    elif said.group(2) and int(said.group(2)) < n:
        why.append(f"the rerun resumed {said.group(2)} of the {n} finished points")
    return "; ".join(why) or None


def _sweep_sigint(box):
    p = launch(sweep_argv(out := box / "res", "--workers", "1"), box)
    if (late := _halfway(p, box, 2))[1]:
        return late[1]
    os.killpg(p.pid, signal.SIGINT)                          # Ctrl-C in a terminal
    return problems(finish(p), 130, rows=late[0], out=out)


def _sweep_all_fail(box):
    o = run(sweep_argv(box / "res", "--workers", "1"), box,
            env=env_for(box, TOOTHFEM_SOLVER="bogus"))
    if o.rc in (None, 0, 3):
        return f"every point failed, yet: {o.describe()}"
    if not re.search(r"\b(6|all)\b[^\n]*fail|fail[^\n]*\b(6|all)\b", o.err):
        return f"stderr does not say how many points failed ({o.describe()})"
    return None


def sweeps(args):
    return cases_in_boxes([("SIGKILL half-way keeps the rows; the rerun resumes",
                            _sweep_kill_resume),
                           ("SIGINT to the group half-way", _sweep_sigint),
                           ("every point fails (TOOTHFEM_SOLVER=bogus)", _sweep_all_fail)])


# --- 5. dask ---------------------------------------------------------------------------
@contextlib.contextmanager
def mute_server():
    """A TCP port that accepts connections and never says a word."""
    srv, conns = socket.socket(), []
    srv.bind(("127.0.0.1", 0))
    srv.listen(16)

    def accept():
        with contextlib.suppress(OSError):       # ends when srv is closed
            while True:
                conns.append(srv.accept()[0])

    threading.Thread(target=accept, daemon=True).start()
    try:
        yield f"tcp://127.0.0.1:{srv.getsockname()[1]}", []
    finally:
        for c in conns + [srv]:
            c.close()


@contextlib.contextmanager
def cluster(box, workers=0):
    """A Dask scheduler on a free port with ``workers`` one-thread workers (no nanny)."""
    def started(p, text, end):
        while time.monotonic() < end and p.poll() is None:
            if text in p.logs[1].read_text(errors="replace"):
                return True
            time.sleep(0.2)
        raise RuntimeError(f"{p.args[1]} did not start: {p.logs[1].read_text()[-300:]}")

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        addr = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    procs = [launch([DASK, "scheduler", "--host", "127.0.0.1", "--port", addr.split(":")[-1],
                     "--no-dashboard"], box, tag="scheduler")]
    try:
        started(procs[0], "Scheduler at", time.monotonic() + 45)
        for k in range(workers):
            procs.append(launch([DASK, "worker", addr, "--nthreads", "1", "--no-nanny",
                                 "--no-dashboard"], box, tag=f"worker{k}"))
            started(procs[-1], "Registered to", time.monotonic() + 45)
        yield addr, procs
    finally:
        for p in procs:
            stop(p)


def _argv(cmd, out, addr):
    if cmd == "sweep":
        return sweep_argv(out, "--scheduler", addr)
    return [TF, "tolerance", CASE, "--samples", "4", "--positions", "4", "--share-samples",
            "0", "--scheduler", addr, "--out", out]


def judge_dask(o, since=0.0, rows=0, out=None):
    """Ended within 60 s of the fault (``since`` s after launch), non-zero, one line."""
    took = o.wall - since
    why = problems(o, rows=rows, out=out)
    if o.rc is not None and took > 60:
        why = f"ended {took:.0f} s after the fault; {why or o.describe()}"
    return f"{why}, {took:.0f} s" if why else f"good (ended {took:.0f} s after the fault: " \
                                              f"{o.describe()})"


def _dask_dead(cmd, mute):
    def fn(box):
        with (mute_server() if mute else cluster(box)) as (addr, _):
            return judge_dask(run(_argv(cmd, box / "res", addr), box))
    return fn


def _dask_kill(which):
    def fn(box):
        with cluster(box, workers=1) as (addr, procs):
            p = launch(_argv("sweep", out := box / "res", addr), box)
            if (late := _halfway(p, box, 2))[1]:
                return late[1]
            stop(procs[1] if which == "worker" else procs[0])
            since = time.monotonic() - p.t0
            return judge_dask(finish(p), since, rows=late[0], out=out)
    return fn


def dask(args):
    table = [("sweep --scheduler at a mute TCP port", _dask_dead("sweep", True))]
    if not args.quick:
        table += [("tolerance --scheduler at a mute TCP port", _dask_dead("tolerance", True)),
                  ("sweep --scheduler without workers", _dask_dead("sweep", False)),
                  ("tolerance --scheduler without workers", _dask_dead("tolerance", False)),
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
def on_alarm(*_):
    raise TimeoutError("no answer within 100 s")
signal.signal(signal.SIGALRM, on_alarm)
for code in map(json.loads, sys.stdin):
    signal.alarm(100)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            r = eval(code)
            said = [str(w.message) for w in caught] + [str(w) for w in getattr(r, "warnings", ())]
            said += [str(w) for w in (getattr(r, "summary", None) or {}).get("warnings", [])]
            rec = {"raised": None, "finite": finite(r), "said": said,
                   "value": " ".join(repr(r).split())[:100]}
        except Exception as e:
            rec = {"raised": type(e).__name__, "tf": isinstance(e, ToothfemError),
                   "msg": (str(e).splitlines() or [""])[0][:240]}
    signal.alarm(0)
    print(json.dumps({"code": code, **rec}), flush=True)
"""
_C = "contact_analysis(case, positions=4, field='none', torque_Nm={})"
_M = "cycloid_mesh.meshing(geom, np.array([0.0, {}]), crank_speed_rad_s=190.1).moment_arm"
_P, _ANGLE = "predict(sine, {}, {})", ("angle", "position", "theta", "phi")
#: (kind, expression, words one of which the message must hold). path: works, or refuses
#: naming `case`; refuse: a ToothfemError naming the argument; absurd: that, or a finite
#: result with a warning naming the load. Another exception, an accepted bad value or a NaN
#: result is bad.
API = [("path", "evaluate(SINE, 500.0, 28.0).efficiency", ("case",)),
       ("path", "predict(SINE, 500.0, 28.0)", ("case",)),
       ("path", "operating_point(CYC)[1]", ("case",)),
       ("path", "contact_analysis(CYC, positions=4, field='none').summary['max_force_N']",
        ("case",)),
       ("path", "drive_for(CYC).member_torque(167.0)", ("case",))] + \
      [("refuse", _P.format(s, t), (w,)) for s, t, w in [
          ("'500'", 28.0, "speed"), ("'fast'", 28.0, "speed"), (True, 28.0, "speed"),
          (500.0, "'28'", "torque"), (500.0, True, "torque"), ("nan", 28.0, "speed"),
          (500.0, "inf", "torque"), (500.0, "28.0, oil_temp_C='hot'", "oil_temp"),
          (500.0, "28.0, oil_temp_C=True", "oil_temp"),
          (500.0, "28.0, oil_temp_C=inf", "oil_temp")]] + \
      [("refuse", _C.format("True"), ("torque",)),
       ("refuse", _C.format("nan"), ("torque",)),
       ("refuse", "drive_for(case).member_torque('88')", ("torque",)),
       ("refuse", "drive_for(case).cycle_solver(4).solve(nan).force", ("torque",)),
       ("refuse", "cycloid_mesh.meshing(geom, [0.0, 0.1], crank_speed_rad_s='fast')"
        ".moment_arm", ("crank_speed",)),
       ("refuse", _M.format("nan"), _ANGLE),
       ("refuse", _M.format("inf"), _ANGLE),
       ("refuse", "run_case(case, None, fem=False)", ("out",)),
       ("refuse", "run_case(None, 'x', fem=False)", ("case",)),
       ("absurd", _C.format("1e12"), ("torque", "load")),
       ("absurd", "drive_for(case).cycle_solver(4).solve(drive_for(case).member_torque(1e12))"
        ".force", ("torque", "load")),
       ("absurd", "evaluate(case, 1815.0, 1e12)", ("torque", "load"))]


def _judge_api(kind, names, r):
    if r is None:
        return "no answer (the runner died)"
    if r["raised"]:
        if r["tf"] and any(n in r["msg"] for n in names):
            return None
        named = f" (a ToothfemError naming none of {list(names)})" if r["tf"] else ""
        return f"{r['raised']}{named}: {r['msg'][:160]}"
    if not r["finite"]:
        return f"a non-finite result, no error: {r['value']}"
    if kind == "path":
        return None
    if kind == "absurd" and any(n in s for s in r["said"] for n in names):
        return "good (finite result with a warning)"
    return f"accepted: {r['value']}"


def api(args):
    table = [t for t in API if not (args.quick and re.search("contact_an|cycle_so", t[1]))]
    with sandbox() as box:
        (box / "runner.py").write_text(API_RUNNER)
        (box / "in.jsonl").write_text("".join(json.dumps(c) + "\n" for _, c, _ in table))
        with open(box / "in.jsonl") as fin:
            p = subprocess.Popen([PY, box / "runner.py", CASE, SINE], cwd=box, stdin=fin,
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                 env=env_for(box), text=True, start_new_session=True)
            try:
                out = p.communicate(timeout=60 + 60 * len(table))[0]
            except subprocess.TimeoutExpired:
                stop(p)
                out = ""
    got = {d["code"]: d for d in map(json.loads, filter(str.strip, out.splitlines()))}
    return [report(code, _judge_api(kind, names, got.get(code))) for kind, code, names in table]


# --- 7. misc ---------------------------------------------------------------------------
_ROWS = [("500", "28", "0.8247"), ("500", "20", "0.80"), ("500", "10", "0.75")]
MEASURED = {"';' delimiter": (";", False), "tab delimiter": ("\t", False),
            "';' and decimal commas": (";", True), "quoted decimal commas": (",", True)}


def _loop_csv(sep, comma):
    def fn(box):
        def cell(v):
            return (f'"{v}"' if sep == "," else v).replace(".", ",") if comma and "." in v \
                    else v
        (box / "rig.csv").write_text("".join(
            sep.join(map(cell, row)) + "\n"
            for row in [("input_speed_rpm", "output_torque_Nm", "efficiency")] + _ROWS))
        o = run([TF, "loop", SINE, box / "rig.csv", "--out", box / "res"], box)
        said = re.search(r"delimiter|decimal", o.out + o.err, re.I)
        if o.rc == 0:                    # read as such, and said so: every row, no silence
            rows = json.loads((box / "res" / "report.json").read_text()).get("n_rows", 3)
            return f"read {rows} of 3 rows" if rows != 3 else None if said else \
                "read without a word about the delimiter or decimal commas"
        if said and not one_line(o):
            return None
        return f"the message says neither delimiter nor decimal comma ({o.describe()})"
    return fn


def _variant(box, *subs):
    """The pin-housing case with regex substitutions (each must apply)."""
    text = CASE.read_text()
    for a, b in subs:
        text, k = re.subn(a, b, text, flags=re.M)
        assert k, a
    (box / "case.toml").write_text(text)
    return box / "case.toml"


def _published_typo(box):
    o = run([TF, "check", _variant(box, (r"^pins_in_contact = 20", "pins_in_contct = 20"))],
            box)
    if o.rc == 2 or (o.rc == 0 and "pins_in_contct" in o.out + o.err):
        return refused(o, "pins_in_contct") if o.rc else None
    return f"accepted without naming the key: {o.describe()}"


def _pins_400(box):
    path = _variant(box, (r"^pin_count = 40 ", "pin_count = 400 "),
                    (r"^lobe_count = 39 ", "lobe_count = 399 "),
                    (r"^eccentricity_mm = 1\.0 ", "eccentricity_mm = 0.1 "),
                    (r"^pin_radius_mm = 2\.0 ", "pin_radius_mm = 0.5 "),
                    (r"^stated_ratio = 121.*$", ""), (r"^housing_outer_radius_mm = .*$", ""))
    o = run([TF, "contact", path, "--positions", "4", "--field", "none", "--out", box / "res"],
            box, timeout=240)
    return None if o.rc == 0 else refused(o)


def _big_torque(cmd):
    def fn(box):
        if cmd == "contact":
            o = run([TF, "contact", CASE, "--torque-Nm", "1e6", "--positions", "4", "--field",
                     "none", "--out", box / "res"], box)
        else:
            path = _variant(box, (r"^output_torque_Nm = 167\.0", "output_torque_Nm = 1e6"))
            o = run([TF, "run", path, "--no-fem", "--out", box / "res"], box)
        if o.rc == 0:
            return None if re.search("warning", o.out + o.err, re.I) else "silent: exit 0"
        return refused(o)
    return fn


def _env(cmd, **extra):
    def fn(box):
        argv = [TF, cmd, CASE, "--out", box / "res"] + \
            (["--positions", "4", "--field", "none"] if cmd == "contact" else [])
        o = run(argv, box, env=env_for(box, **extra))
        if o.rc not in (0, 2) or "Traceback" in o.err or len(o.lines) > 2:
            return o.describe()
        return None
    return fn


def misc(args):
    table = [(f"loop CSV, {k}", _loop_csv(*v)) for k, v in MEASURED.items()]
    table += [("misspelled key in [published]", _published_typo)]
    table += [] if args.quick else [("a case with 400 pins (contact)", _pins_400)]
    return cases_in_boxes(table + [
        ("contact --torque-Nm 1e6", _big_torque("contact")),
        ("run --no-fem, output_torque_Nm = 1e6", _big_torque("run")),
        ("contact, PYTHONIOENCODING=ascii", _env("contact", PYTHONIOENCODING="ascii")),
        ("geometry, MPLBACKEND=bogus", _env("geometry", MPLBACKEND="bogus")),
        ("geometry, HOME unset", _env("geometry", HOME=None)),
        ("contact, all three", _env("contact", PYTHONIOENCODING="ascii", MPLBACKEND="bogus",
                                    HOME=None))])


# --- 8. races, limits and values (issue 45) ---------------------------------------------
def _two_runs(box):
    """`contact` running into DIR, `geometry` started into DIR meanwhile."""
    first = launch([TF, "contact", CASE, "--positions", "36", "--field", "none", "--out",
                    out := box / "res"], box, tag="first")
    end = time.monotonic() + 60
    while first.poll() is None and time.monotonic() < end and \
            not list(box.glob(".res~*.lock")):
        time.sleep(0.02)
    second = run([TF, "geometry", CASE, "--out", out], box, tag="second")
    o = finish(first)
    why = [] if second.rc == 2 and not one_line(second, "--out") else \
        [f"the second run was not refused in one line ({second.describe()})"]
    if o.rc != 0 or not (out / "summary.json").is_file() or (out / "profile.csv").exists():
        why.append(f"the first run's result is not whole ({o.describe()})")
    return "; ".join(why) or None


def _sweep_killed_into_a_result(box):
    """A finished sweep in DIR; another sweep into DIR killed -9 half-way."""
    o = run(sweep_argv(out := box / "res", "--workers", "1", "--torque-Nm", "100"), box,
            tag="first")
    if o.rc != 0:
        return f"probe: the first sweep failed ({o.describe()})"
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    p = launch(sweep_argv(out, "--workers", "1", "--torque-Nm", "100,200"), box)
    if (late := _halfway(p, box, 8))[1]:
        return late[1]
    stop(p)
    after = {q.name: q.read_bytes() for q in out.iterdir()} if out.is_dir() else {}
    return None if after == before else \
        f"the finished result was replaced by the killed run's ({sorted(after)[:4]})"


def _file_size_limit(box):
    """`sweep` under `ulimit -f 4` (KiB): nothing under DIR, one line naming it."""
    argv = ["sh", "-c", 'ulimit -f 4; exec "$@"', "sh",
            *sweep_argv(out := box / "res", "--workers", "1", "--torque-Nm", "100")]
    o = run(argv, box)
    lines = [x for x in o.lines if "warning: the FE cache" not in x]
    if out.exists():
        return f"a folder under the final name after the failed write ({o.describe()})"
    if o.rc != 2 or len(lines) != 1 or "--out" not in lines[0] or ".tmp-" in lines[0]:
        return f"not one line naming --out: {o.describe()}"
    return None


def _not_utf8(box):
    out = os.fsencode(box) + b"/res\xff"
    with open(box / "logs" / "err", "wb") as fe:
        rc = subprocess.run([os.fsencode(TF), b"geometry", os.fsencode(CASE), b"--out", out],
                            cwd=box, env=env_for(box), stdout=subprocess.DEVNULL, stderr=fe,
                            timeout=TIMEOUT).returncode
    return None if rc == 0 and os.path.isfile(out + b"/profile.csv") else \
        f"exit {rc}: {(box / 'logs' / 'err').read_text(errors='replace')[-200:]}"


def _value(subs, cmd=("check",), extra=(), names=()):
    def fn(box):
        path = _variant(box, *subs)          # a copy in the box, never the case itself
        if extra:
            path.write_text(path.read_text() + extra[0])
        argv = [TF, *cmd[:1], path, *cmd[1:]]
        if cmd[0] in ("run",):
            argv += ["--out", box / "res"]
        return refused(run(argv, box), *names)
    return fn


def races(args):
    table = [] if args.quick else [
        ("two runs into one --out: the second refused", _two_runs),
        ("a sweep killed -9 into a finished result", _sweep_killed_into_a_result)]
    table += [("sweep under ulimit -f 4: nothing under DIR", _file_size_limit),
             ("--out not UTF-8", _not_utf8),
             ("[published] pins_in_contact = -20",
              _value([(r"^pins_in_contact = 20", "pins_in_contact = -20")],
                     names=["published.pins_in_contact"])),
             ("[published] max_contact_stress_MPa = 1e300",
              _value([(r"^max_contact_stress_MPa = 45.96", "max_contact_stress_MPa = 1e300")],
                     cmd=("run", "--no-fem"), names=["published.max_contact_stress_MPa"])),
             ("[duty_cycle] input_speed_rpm = 1e300",
              _value([], extra=["\n[[duty_cycle]]\noutput_torque_Nm = 100.0\n"
                                "input_speed_rpm = 1e300\ntime_share = 1.0\n"],
                     names=["duty_cycle[0].input_speed_rpm"])),
             ("efficiency --thermal --duration-h 1e9",
              _value([], cmd=("efficiency", "--thermal", "--duration-h", "1e9"),
                     names=["--duration-h"]))]
    return cases_in_boxes(table)


# --- main ------------------------------------------------------------------------------
def main(argv=None):
    global KEEP
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--classes", default=",".join(CLASSES),
                    help=f"comma-separated, of {', '.join(CLASSES)} (default: all)")
    ap.add_argument("--signal-tries", type=int, default=None,
                    help="SIGTERM instants for `run` (default 20; at most 3 with --quick)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the signal instants")
    ap.add_argument("--quick", action="store_true",
                    help="a reduced set, about 2-3 minutes (no dask class without `dask`)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folders")
    args = ap.parse_args(argv)
    KEEP = args.keep
    if args.signal_tries is None:
        args.signal_tries = 3 if args.quick else 20
    chosen = [c.strip() for c in args.classes.split(",") if c.strip()]
    if unknown := sorted(set(chosen) - set(CLASSES)):
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
