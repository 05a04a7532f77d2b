"""What the JSON summaries of an output folder state, for report.html: every ``warnings``
entry (the :class:`toothfem.limits.Exceeded` records' messages) and every assumption (an
``assumed`` mapping, list or flag, a ``..._assumed`` flag, a text that says ASSUMPTION)."""
from __future__ import annotations

import json
from pathlib import Path

from .case_text import ASSUMPTION
from .inputs import missing

#: How much of a JSON summary is searched for warnings and assumptions (nesting depth): the
#: summaries are a few levels deep; a deeper structure is data, not a statement.
MAX_JSON_DEPTH = 8


def _walk(x, path=(), depth=0):
    """(path, key, value, mapping) of every mapping entry of a JSON tree, to
    MAX_JSON_DEPTH."""
    if depth > MAX_JSON_DEPTH:
        return
    if isinstance(x, dict):
        for k, v in x.items():
            yield path, k, v, x
            yield from _walk(v, path + (str(k),), depth + 1)
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from _walk(v, path + (str(i),), depth + 1)


def summaries(folder: Path) -> dict:
    """The folder's JSON summaries (the files that parse; others are left out).

    Parameters
    ----------
    folder : pathlib.Path
        An output folder.

    Returns
    -------
    dict
        {name relative to the folder: parsed JSON}.
    """
    out = {}
    for p in sorted(folder.rglob("*.json")):
        try:
            out[p.relative_to(folder).as_posix()] = json.loads(p.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
    return out


def _message(w) -> str | None:
    if isinstance(w, dict):
        return str(w["message"]) if "message" in w else None
    return str(w) if isinstance(w, str) else None


def folder_warnings(summaries: dict) -> dict:
    """{message: [where, ...]} of every ``warnings`` list in the JSON summaries.

    Parameters
    ----------
    summaries : dict
        {file name: parsed JSON}.

    Returns
    -------
    dict
        Each message once, with every place that states it (file and path).
    """
    found: dict = {}
    for name, tree in summaries.items():
        for path, key, value, _ in _walk(tree):
            if key == "warnings" and isinstance(value, list):
                where = " › ".join((name, *path)) if path else name
                for w in value:
                    m = _message(w)
                    if m:
                        found.setdefault(m, [])
                        if where not in found[m]:
                            found[m].append(where)
    return found


def folder_assumptions(summaries: dict) -> list:
    """(where, what) of every assumption the JSON summaries state: the entries of an
    ``assumed`` mapping or list, a ``..._assumed`` flag that is true, and any text that
    says ASSUMPTION outside a ``warnings`` list.

    Parameters
    ----------
    summaries : dict
        {file name: parsed JSON}.

    Returns
    -------
    list of (str, str)
    """
    out = []
    for name, tree in summaries.items():
        for path, key, value, parent in _walk(tree):
            if "warnings" in path or key == "warnings":
                continue
            where = " › ".join((name, *path, str(key)))
            if key == "assumed":
                if isinstance(value, dict):
                    out += [(f"{where} › {k}", str(v)) for k, v in value.items()]
                elif isinstance(value, list) and value:
                    out.append((where, ", ".join(map(str, value))))
                elif value is True:          # a record that says it is assumed: its values
                    out.append((" › ".join((name, *path)),
                                _assumed(parent, "assumed", path[-1] if path else "")))
            elif str(key).endswith("_assumed") and value is True:
                stem = str(key)[:-len("_assumed")]
                out.append((where, _assumed({k: v for k, v in parent.items()
                                             if k.startswith(stem)}, key, stem)))
            elif isinstance(value, str) and ASSUMPTION in value:
                out.append((where, value))
    return out


def _assumed(record: dict, flag: str, name: str = "") -> str:
    """'assumed (not in the case): key = value, ...' of a record's other entries, a
    missing value said as what it means (:data:`NOT_SET`)."""
    values = ", ".join(f"{k} = {missing(name) if v is None else v}"
                       for k, v in record.items()
                       if k != flag and isinstance(v, (int, float, str, type(None))))
    return "assumed (not in the case)" + (f": {values}" if values else "")
