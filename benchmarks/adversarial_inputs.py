"""Adversarial inputs through the CLI: how many are handled well (issue 14).

Every key of the three seed cases gets values a careless or hostile user might write (a
number as a string, a bool, a table, an array, zero, negatives, 1e-300, 1e300, inf, NaN,
huge integers, the value x 1000 and x 0.001), and 1e300 goes into every numeric key of
[material], [bearings] and [thermal] a seed case leaves at its default; the files get
encodings and byte-order marks.
Each variant runs ``toothfem check`` and, when accepted, ``efficiency`` (analytic loads)
and ``geometry``, each in a forked child with a memory limit and a time limit.

Handled well means one of:

* exit 0 and every number printed finite (efficiency in (0, 1], losses finite and >= 0);
* exit 2 with one line on stderr that names a case key (or the file, for file-level faults);
  also when ``check`` accepted and ``efficiency`` refuses so (an input torque that cannot
  overcome the no-load losses): the refusal is in the case's terms, not an internal
  variable's (issue 14, item 2). These are counted apart in the tally's ``later`` line.

Handled badly: a traceback, another exit code, a timeout, the memory limit, NaN/inf in an
accepted result, a refusal naming no case key, or more than one line.

Run: ``python benchmarks/adversarial_inputs.py [--quick] [--json OUT]``; prints the counts
per category and every badly handled input.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import re
import resource
import signal
import sys
import tempfile
import traceback
from pathlib import Path

try:
    import tomllib
except ImportError:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
CASES = ("cycloid_pinhousing.toml", "sine_prototype.toml", "rv40e.toml")
#: Memory limit of a probe's child process (address space, bytes): the issue's "runaway".
MEMORY_LIMIT = 3 * 2**30
#: Wall time limit of one command (s).
TIME_LIMIT = 120


# --- a minimal TOML writer (values: str, bool, int, float, list, dict) ------------------
def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dumps(doc: dict) -> str:
    lines = []

    def table(prefix, d):
        scalars = {k: v for k, v in d.items() if not isinstance(v, dict)
                   and not (isinstance(v, list) and v and all(isinstance(x, dict) for x in v))}
        if prefix:
            lines.append(f"[{prefix}]")
        lines.extend(f"{k} = {_value(v)}" for k, v in scalars.items())
        for k, v in d.items():
            if isinstance(v, dict):
                table(f"{prefix}.{k}" if prefix else k, v)
        for k, v in d.items():
            if isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                for item in v:
                    lines.append(f"[[{k}]]")
                    lines.extend(f"{kk} = {_value(vv)}" for kk, vv in item.items())

    table("", doc)
    return "\n".join(lines) + "\n"


# --- the variants ----------------------------------------------------------------------
def _numeric_values(v):
    out = {"string-number": str(v), "string-word": "abc", "bool": True, "table": {"x": 1},
           "array": [v], "zero": 0, "minus-one": -1, "tiny": 1e-300, "huge": 1e300,
           "inf": math.inf, "nan": math.nan, "int-1e30": 10**30, "int-1e400": 10**400}
    if isinstance(v, (int, float)) and not isinstance(v, bool) and v:
        out["x1000"] = v * 1000
        out["x0.001"] = v * 0.001
        out["x1.5"] = v * 1.5 if isinstance(v, float) else v + 1
    return out


def _string_values(v):
    return {"number": 1, "bool": False, "empty": "", "unknown": "nonsense", "table": {"x": 1}}


def variants(doc: dict):
    """(label, key, mutated document) for every key of ``doc``."""
    def walk(d, path):
        for k, v in d.items():
            p = path + (k,)
            if isinstance(v, dict):
                yield from walk(v, p)
            elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                for i, item in enumerate(v):
                    for kk, vv in item.items():
                        yield p + (i, kk), vv
            else:
                yield p, v

    for path, v in list(walk(doc, ())):
        if path[0] == "published":
            continue
        values = _string_values(v) if isinstance(v, str) else _numeric_values(v)
        for label, new in values.items():
            yield label, path, _set(doc, path, new)
        yield "missing", path, _set(doc, path, _DELETE)
    for path in absent_numeric_keys(doc):      # keys the seed case leaves at their default
        yield "huge-absent", path, _set(doc, path, 1e300)
    yield "unknown-key", ("case", "colour"), _set(doc, ("case", "colour"), "red")
    yield "unknown-section", ("gearbox",), _set(doc, ("gearbox",), {"x": 1})


_DELETE = object()
#: Sections whose numeric keys are tried at 1e300 where a seed case does not set them (issue
#: 45: the external loads, the bearings' sizes and the thermal keys had no upper bound).
ABSENT_SECTIONS = ("material", "bearings", "thermal")


def absent_numeric_keys(doc: dict):
    """(section, key) of the numeric keys of :data:`ABSENT_SECTIONS` the document lacks."""
    import dataclasses

    from toothfem.case import _SECTIONS
    from toothfem.case_checks import expected_type
    for sec in ABSENT_SECTIONS:
        for f in dataclasses.fields(_SECTIONS[sec]):
            if f.metadata and f.metadata.get("choices") is None \
                    and expected_type(f) != "string" and f.name not in doc.get(sec, {}):
                yield sec, f.name


def _set(doc, path, value):
    out = json.loads(json.dumps(doc, allow_nan=True))
    d = out
    for k in path[:-1]:
        d = d.setdefault(k, {}) if isinstance(k, str) else d[k]
    if value is _DELETE:
        del d[path[-1]]
    else:
        d[path[-1]] = value
    return out


def file_variants(text: str):
    """(label, bytes) of encodings and byte faults of a case file."""
    raw = text.encode()
    yield "utf-8-bom", b"\xef\xbb\xbf" + raw
    yield "utf-16", text.encode("utf-16")
    yield "latin-1-byte", raw.replace(b"# ", b"# \xe9 ", 1)
    yield "bare-0xff", raw + b"\xff\n"
    yield "nul-byte", raw + b"\x00\n"
    yield "empty", b""
    yield "binary", bytes(range(256))
    yield "crlf", raw.replace(b"\n", b"\r\n")
    yield "truncated", raw[: len(raw) // 2]


# --- running a command in a limited child ----------------------------------------------
def run_limited(argv):
    """(exit code or 'traceback'/'timeout'/'memory', stdout, stderr) of ``main(argv)``."""
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:                                     # child: always ends in os._exit
        try:
            os.close(r)
            resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
            signal.alarm(TIME_LIMIT)
            out, err = io.StringIO(), io.StringIO()
            try:
                from toothfem.cli import main
                with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                    code = main(argv)
            except MemoryError:
                code = "memory"
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else 1
            except BaseException:           # noqa: BLE001 (the probe records every failure)
                code = "traceback"
                err.write(traceback.format_exc())
            with os.fdopen(w, "w") as fh:
                json.dump([code, out.getvalue(), err.getvalue()], fh)
        finally:
            os._exit(0)
    os.close(w)
    with os.fdopen(r) as fh:
        data = fh.read()
    _, status = os.waitpid(pid, 0)
    if not data:
        sig = os.WTERMSIG(status) if os.WIFSIGNALED(status) else None
        return ("timeout" if sig == signal.SIGALRM else f"killed({sig})"), "", ""
    return tuple(json.loads(data))


_NONFINITE = re.compile(r"(?<![A-Za-z_])(nan|inf|-inf|NaN|Infinity)(?![A-Za-z_])")


def _finite_json(x) -> bool:
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, dict):
        return all(_finite_json(v) for v in x.values())
    if isinstance(x, list):
        return all(_finite_json(v) for v in x)
    return True


def judge_refusal(stderr: str, names) -> str | None:
    """Why a refusal is badly handled, or None."""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    if "Traceback" in stderr:
        return "traceback"
    if len(lines) != 1:
        return f"{len(lines)} lines on stderr"
    if not any(n in lines[0] for n in names):
        return "names no case key"
    return None


def probe_case(path: Path, key_names, tmp: Path):
    """Run check / efficiency / geometry on a case file; (ok, why, detail)."""
    code, out, err = run_limited(["check", str(path), "--json"])
    if code == 2:
        why = judge_refusal(err, key_names + [path.name])
        return why is None, why or "refused", err.strip()[-300:]
    if code != 0:
        return False, f"check: {code}", err.strip()[-300:]
    try:
        d = json.loads(out, parse_constant=lambda c: float(c))
    except json.JSONDecodeError:
        return False, "check: output not JSON", out[-200:]
    if not _finite_json(d):
        return False, "check: non-finite value printed", out[-300:]
    code, out, err = run_limited(["efficiency", str(path), "--json"])
    if code == 2:
        why = judge_refusal(err, key_names + [path.name])
        if why is None:       # the physics says no, in the case's own terms (one line, a key)
            return True, "refused by efficiency naming a key", err.strip()[-300:]
        return False, f"efficiency refused an accepted case ({why})", err.strip()[-300:]
    if code != 0:
        return False, f"efficiency: {code}", err.strip()[-300:]
    e = json.loads(out, parse_constant=lambda c: float(c))
    if not (_finite_json(e) and 0 < e["efficiency"] <= 1
            and all(v >= 0 for v in e["losses"].values())):
        return False, "efficiency: non-finite or out of (0, 1]", out[-300:]
    return True, "accepted", ""


def all_keys():
    from toothfem.case import _NESTED, _SECTIONS
    import dataclasses

    names = ["case.name", "case.drive", "case.source", "case.stated_ratio", "[case]"]
    for sec, cls in _SECTIONS.items():
        names.append(f"[{sec}]")
        for f in dataclasses.fields(cls):
            names.append(f"{sec}.{f.name}")
        for sub, scls in _NESTED.get(cls, {}).items():
            names += [f"{sec}.{sub}.{f.name}" for f in dataclasses.fields(scls)]
    names += ["measured[", "[[measured]]", "[published]"]
    return names


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one case, fewer values")
    ap.add_argument("--json", default=None, help="write the tally here")
    args = ap.parse_args(argv)
    keys = all_keys()
    import toothfem.cli  # noqa: F401  (imported once here, so that each fork starts warm)
    from toothfem.commands import check, efficiency  # noqa: F401
    from toothfem.efficiency import evaluation  # noqa: F401
    tally = {}
    bad, later = [], []
    with tempfile.TemporaryDirectory() as tmpd:
        tmp = Path(tmpd)
        for name in CASES[:1] if args.quick else CASES:
            text = (ROOT / "cases" / name).read_text()
            doc = tomllib.loads(text)
            items = [(lab, ".".join(map(str, key)), dumps(d).encode())
                     for lab, key, d in variants(doc)]
            items += [(lab, "<file>", b) for lab, b in file_variants(text)]
            for k, (label, key, data) in enumerate(items):
                path = tmp / f"probe_{k}.toml"
                path.write_bytes(data)
                ok, why, detail = probe_case(path, keys, tmp)
                if why == "refused by efficiency naming a key":
                    later.append(f"{name} {key} [{label}]: {detail.splitlines()[-1]}")
                cat = label
                t = tally.setdefault(cat, [0, 0])
                t[0] += 1
                t[1] += ok
                if not ok:
                    bad.append({"case": name, "key": key, "variant": label, "why": why,
                                "detail": detail})
                    print(f"BAD {name} {key} [{label}]: {why}: {detail.splitlines()[-1:]}",
                          flush=True)
    total = sum(t[0] for t in tally.values())
    good = sum(t[1] for t in tally.values())
    print(f"\ninputs tried: {total}; handled well: {good} ({100 * good / total:.1f} %)")
    print(f"  of which accepted by check and refused by efficiency naming a key (later): "
          f"{len(later)}")
    for line in later:
        print(f"    {line}")
    for cat, (n, g) in sorted(tally.items()):
        print(f"  {cat:<16s} {g:4d} / {n:4d}")
    if args.json:
        Path(args.json).write_text(json.dumps({"tried": total, "handled_well": good,
                                               "by_variant": tally, "bad": bad,
                                               "later": later}, indent=1))
    return 0 if good == total else 1


if __name__ == "__main__":
    sys.exit(main())
