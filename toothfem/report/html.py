"""report.html: one self-contained page per output folder, the one place HTML is written.

:func:`write_report` turns what a command wrote into its folder into ``report.html``: a
header (the case, toothfem's version, the date and the command line), the warnings, the
command's results (its report.md, split into sections, and the tables it passes), the case's
published figures beside ours, every figure (PNG) of the folder, the assumptions, every
input of the case with its unit and where it came from, and the files beside the page.

The page opens from the file system with no network: every picture is embedded as a
``data:`` URI, the style sheet is inline, there is no script, and its Content-Security-
Policy forbids loading anything else (a reader's browser refuses even a stray reference).

Where each part comes from:

- inputs: the case record (:class:`toothfem.case.Case`), each field's unit from its key's
  suffix; *declared* when the case file sets the key, else *default* with the schema's
  source (the field's ``doc`` in :mod:`toothfem.case_sections`, and its row in
  docs/case_schema.md where that file is beside the package);
- assumptions: every comment of the case file that says ASSUMPTION (with its reason), every
  default whose source says ASSUMPTION, and every ``assumed`` entry of the folder's JSON
  summaries;
- warnings: every ``warnings`` entry of the folder's JSON summaries (the
  :class:`toothfem.limits.Exceeded` records' messages) and the Python warnings shown while
  the command ran (:func:`warnings_kept`);
- published figures: the rows of the command's summary tables that carry a ``published``
  column (:mod:`toothfem.report.summary`), each with the reason for a difference where
  :data:`toothfem.report.summary.PUBLISHED_REASONS` states one, else "no reason recorded";
  the case's other ``[published]`` figures are listed with their sources.
"""
from __future__ import annotations

import base64
import contextlib
import dataclasses
import datetime as _dt
import html
import json
import math
import re
import sys
import warnings
from collections.abc import Iterator
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

from .. import __version__
from ..errors import ToothfemError
from . import summary as report_summary

#: The page's name in every output folder.
REPORT = "report.html"
#: The Markdown report a command may have written beside it (run, loop, tolerance, design).
MARKDOWN = "report.md"
#: A PNG file's first eight bytes (the PNG specification, Sec. 5.2): a figure is embedded
#: only if it is one.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: Rows of a long table (a sweep's CSV) shown on the page; the file beside it has them all.
MAX_TABLE_ROWS = 500
#: How much of a JSON summary is searched for warnings and assumptions (nesting depth): the
#: summaries are a few levels deep; a deeper structure is data, not a statement.
MAX_JSON_DEPTH = 8
#: Where docs/case_schema.md lies from this file in a source tree (toothfem/report/ ->
#: the repository): the defaults' sources are read from it when it is there.
CASE_SCHEMA = Path(__file__).resolve().parents[2] / "docs" / "case_schema.md"
#: Content-Security-Policy of the page: nothing from anywhere but the page itself (the
#: pictures are data: URIs, the style inline), and no script at all.
CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"

#: Unit of a case key by its name's suffix (longest first; the case names carry units).
UNIT_SUFFIXES = (
    ("_Nm_per_arcmin", "N m/arcmin"), ("_1_per_GPa", "1/GPa"), ("_W_m2K", "W/(m² K)"),
    ("_W_mK", "W/(m K)"), ("_mm2_s", "mm²/s"), ("_kg_m3", "kg/m³"), ("_Pa_s", "Pa s"),
    ("_J_K", "J/K"), ("_K_W", "K/W"), ("_Nmm", "N mm"), ("_Nm", "N m"), ("_kN", "kN"),
    ("_GPa", "GPa"), ("_MPa", "MPa"), ("_HV", "HV"), ("_rpm", "rpm"), ("_kW", "kW"),
    ("_arcmin", "arcmin"), ("_mm", "mm"), ("_um", "µm"), ("_m2", "m²"), ("_deg", "deg"),
    ("_C", "°C"), ("_h", "h"), ("_N", "N"), ("_W", "W"),
)
#: The marker of a reasoned choice where no source fixes a value (case files, schema).
ASSUMPTION = "ASSUMPTION"

#: The Python warnings of the command now running (:func:`warnings_kept`).
_KEPT: ContextVar = ContextVar("toothfem_report_warnings", default=None)


@contextlib.contextmanager
def warnings_kept() -> Iterator[list[str]]:
    """Keep the message of every Python warning shown inside the block, for the report;
    each is still shown as before (the previous ``warnings.showwarning`` is called).

    Yields
    ------
    list of str
        The messages, in the order shown (also what :func:`write_report` adds to the
        page's warnings while the block lasts).
    """
    kept: list[str] = []
    previous = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        kept.append(str(message))
        previous(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    token = _KEPT.set(kept)
    try:
        yield kept
    finally:
        warnings.showwarning = previous
        _KEPT.reset(token)


@dataclass(frozen=True)
class Table:
    """A table of the page: a title, column names and rows of cells (numbers or text)."""
    title: str
    columns: tuple
    rows: tuple
    note: str = ""

    @classmethod
    def of_summary(cls, title: str, rows, note: str = "") -> Table:
        """A table of summary rows ``(quantity, unit, {column: value})``
        (:mod:`toothfem.report.summary`) or ``(quantity, value)`` pairs.

        Parameters
        ----------
        title : str
            The table's caption.
        rows : sequence of tuple
            The rows.
        note : str
            A line under the table.

        Returns
        -------
        Table
        """
        rows = list(rows)
        if rows and len(rows[0]) == 2:
            return cls(title, ("quantity", "value"), tuple(tuple(r) for r in rows), note)
        cols = list(dict.fromkeys(c for _, _, vals in rows for c in vals))
        body = tuple((what, unit, *(vals.get(c) for c in cols)) for what, unit, vals in rows)
        if report_summary.PUBLISHED in cols and not note:
            note = report_summary.PUBLISHED_NOTE
        return cls(title, ("quantity", "unit", *cols), body, note)

    @classmethod
    def of_mapping(cls, title: str, mapping: dict, note: str = "") -> Table:
        """A two-column table of a JSON summary's values (nested ones as JSON text).

        Parameters
        ----------
        title : str
            The caption.
        mapping : dict
            {name (with its unit suffix): value}.
        note : str
            A line under the table.

        Returns
        -------
        Table
        """
        rows = tuple((k, v if isinstance(v, (int, float, str)) or v is None
                      else json.dumps(v, default=str)) for k, v in mapping.items())
        return cls(title, ("quantity", "value"), rows, note)

    @classmethod
    def of_csv(cls, title: str, path) -> Table:
        """A table of a CSV file (its first line the header), at most MAX_TABLE_ROWS rows.

        Parameters
        ----------
        title : str
            The caption.
        path : str or pathlib.Path
            The CSV file.

        Returns
        -------
        Table
        """
        import csv

        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
        head, body = (rows[0], rows[1:]) if rows else ([], [])
        note = (f"the first {MAX_TABLE_ROWS} of {len(body)} rows; all in {Path(path).name}"
                if len(body) > MAX_TABLE_ROWS else f"{len(body)} rows, as in {Path(path).name}")
        return cls(title, tuple(head), tuple(tuple(r) for r in body[:MAX_TABLE_ROWS]), note)


# ------------------------------------------------------------------------------------------
# the case file: which keys it declares, and its comments


@dataclass
class Comment:
    """A comment of the case file: its first line and its text (continuations joined)."""
    line: int                 # 1-based line of the case file
    text: str


@dataclass
class CaseText:
    """What the case file says beyond its values: the keys it sets (dotted, with the index
    of an array of tables: ``measured[0].efficiency``), each key's comment and each
    section's (the file's head under ``""``)."""
    declared: set
    keys: dict                # key -> Comment
    sections: dict            # section -> Comment
    path: str


_HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\-]+)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=\s*(.*)$")


def _split_comment(value: str):
    """(value, comment or None) of the text after ``key =``: the first ``#`` outside a
    quoted string."""
    quoting, i = None, 0
    while i < len(value):
        ch = value[i]
        if quoting:
            if ch == "\\" and quoting == '"':
                i += 1                      # an escaped character of a basic string
            elif ch == quoting:
                quoting = None
        elif ch in "\"'":
            quoting = ch
        elif ch == "#":
            return value[:i].rstrip(), value[i + 1:].strip()
        i += 1
    return value.rstrip(), None


def read_case_text(path) -> CaseText:
    """The keys a case file sets and its comments.

    A comment on a key's line is that key's; a comment on a section's line, or a comment
    line before the section's first key, is the section's; a comment line indented after a
    commented line continues that comment; any other comment line is a note of its section.

    Parameters
    ----------
    path : str or pathlib.Path
        The case file (TOML, UTF-8).

    Returns
    -------
    CaseText
    """
    path = Path(path)
    text = path.read_text(encoding="utf-8", errors="replace")
    declared: set[str] = set()
    keys: dict[str, Comment] = {}
    sections: dict[str, Comment] = {}
    counts: dict[str, int] = {}
    section, last = "", None

    def extend(comment: Comment, more: str) -> Comment:
        comment.text = f"{comment.text} {more}".strip()
        return comment

    for n, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped:
            last = None
            continue
        if stripped.startswith("#"):
            body = stripped.lstrip("#").strip()
            if last is not None and raw[:1].isspace():      # an indented continuation
                extend(last, body)
            else:                                           # a note of the section
                last = extend(sections.setdefault(section, Comment(n, "")), body)
            continue
        head = _HEADER.match(raw)
        if head:
            section = head.group(2)
            if head.group(1) == "[[":                       # an array of tables
                counts[section] = counts.get(section, -1) + 1
                section = f"{section}[{counts[section]}]"
            last = extend(sections.setdefault(section, Comment(n, "")),
                          (head.group(3) or "").lstrip("#").strip())
            continue
        key = _KEY.match(raw)
        if key:
            dotted = f"{section or 'case'}.{key.group(1)}"
            declared.add(dotted)
            _, comment = _split_comment(key.group(2))
            last = None
            if comment:
                last = keys[dotted] = Comment(n, comment)
    return CaseText(declared, keys, sections, str(path))


def _reason(text: str) -> str:
    """A comment's text if it says more than the ASSUMPTION marker, else ''."""
    return text if re.sub(rf"{ASSUMPTION}S?", "", text).strip(" :;,.-()") else ""


# ------------------------------------------------------------------------------------------
# the schema: each default's source


def _schema_rows(path: Path = CASE_SCHEMA) -> dict:
    """{``section.key``: (default, source)} of docs/case_schema.md's tables (Markdown),
    or {} where the file is not beside the package."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError:
        return {}
    rows, section = {}, None
    for line in text.splitlines():
        head = re.match(r"^##\s+`\[\[?([a-z_]+)\]?\]`", line)
        if head:
            section = head.group(1)
            continue
        row = re.match(r"^\|\s*`([a-z_0-9]+)`\s*\|(.*?)\|(.*)\|\s*$", line)
        if row and section:
            rows[f"{section}.{row.group(1)}"] = (row.group(2).strip(), row.group(3).strip())
    return rows


def _plain(markdown: str) -> str:
    """A schema cell's Markdown as plain text (code and emphasis marks dropped)."""
    return re.sub(r"\*\*?([^*]+)\*\*?", r"\1", re.sub(r"`([^`]*)`", r"\1", markdown))


def unit_of(key: str) -> str:
    """The unit of a case key from its name's suffix ('' where the name has none).

    Parameters
    ----------
    key : str
        A case key, e.g. ``pin_circle_radius_mm``.

    Returns
    -------
    str
        E.g. "mm"; "" for a count, a ratio or a name.
    """
    for suffix, unit in UNIT_SUFFIXES:
        if key.endswith(suffix):
            return unit
    return ""


@dataclass(frozen=True)
class InputRow:
    """One value of the case: its dotted key, value, unit, whether the case file sets it
    (``declared``; None when no file says), the comment or source beside it, and the
    assumption it is (its reason), if any."""
    key: str
    value: object
    unit: str
    declared: bool | None
    note: str
    assumption: str | None


def case_inputs(case, case_text: CaseText | None = None, schema: dict | None = None) -> list:
    """Every value of a case as :class:`InputRow` records, in the case's order.

    Parameters
    ----------
    case : toothfem.case.Case
        The case.
    case_text : CaseText, optional
        What its file declares and comments (:func:`read_case_text`); None: not known.
    schema : dict, optional
        The defaults' sources (:func:`_schema_rows`); default: read them.

    Returns
    -------
    list of InputRow
        The ``[case]`` head, then every section present (nested tables and arrays of
        tables with their index); ``[published]`` is not an input and is left out.
    """
    schema = _schema_rows() if schema is None else schema
    rows = []
    for name in ("name", "drive", "source", "stated_ratio"):
        rows.append(_row(f"case.{name}", getattr(case, name), None, case_text, schema))
    for f in dataclasses.fields(case):
        value = getattr(case, f.name)
        if f.name in ("name", "drive", "source", "stated_ratio", "published") or value is None:
            continue
        if isinstance(value, tuple):
            for i, item in enumerate(value):
                rows += _section_rows(f"{f.name}[{i}]", item, case_text, schema)
        elif dataclasses.is_dataclass(value):
            rows += _section_rows(f.name, value, case_text, schema)
    return rows


def _section_rows(prefix: str, record, case_text, schema) -> list:
    rows = []
    for f in dataclasses.fields(record):
        value = getattr(record, f.name)
        key = f"{prefix}.{f.name}"
        if dataclasses.is_dataclass(value):
            rows += _section_rows(key, value, case_text, schema)
        else:
            rows.append(_row(key, value, f, case_text, schema))
    return rows


def _section_of(key: str) -> str:
    return key.rsplit(".", 1)[0]


def _row(key: str, value, field, case_text, schema) -> InputRow:
    """One input row: declared (with its comment, or its section's ASSUMPTION) or a default
    (with the schema's source)."""
    unit = unit_of(key.rsplit(".", 1)[1])
    if case_text is None:
        return InputRow(key, value, unit, None, "", None)
    if key in case_text.declared:
        own = case_text.keys.get(key)
        sec = case_text.sections.get(_section_of(key))
        own_text, sec_text = (own.text if own else ""), (sec.text if sec else "")
        note, assumption = own_text, None
        if ASSUMPTION in own_text:
            assumption = _reason(own_text) or (
                f"as [{_section_of(key)}] (line {sec.line})" if _reason(sec_text)
                else "no reason stated in the case file")
            if not _reason(own_text):
                note = f"{own_text}: {assumption}"
        elif ASSUMPTION in sec_text:
            assumption = (f"[{_section_of(key)}]: "
                          + (_reason(sec_text) or "no reason stated in the case file"))
        elif isinstance(value, str) and ASSUMPTION in value:
            assumption = _reason(value) or "no reason stated in the case file"
        return InputRow(key, value, unit, True, note, assumption)
    bare = re.sub(r"\[\d+\]", "", key)
    doc = spoken((field.metadata.get("doc", "") if field is not None else "") or "")
    default, source = (spoken(_plain(x)) for x in schema.get(bare, ("", "")))
    note = "; ".join(x for x in (doc, source) if x) or "toothfem's default (no source recorded)"
    assumption = None
    if ASSUMPTION in note or ASSUMPTION in default:
        assumption = note
    return InputRow(key, value, unit, False, note, assumption)


# ------------------------------------------------------------------------------------------
# what the folder's JSON summaries state


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


def _summaries(folder: Path) -> dict:
    """{relative name: parsed JSON} of the folder's JSON files (those that parse)."""
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


#: What a value left unset means, by its key (the page never prints Python's None): the
#: others read "not set".
NOT_SET = {
    "carrier_stiffness_Nm_per_arcmin": "not set (a rigid carrier)",
    "carrier_stiffness_Nm_per_rad": "not set (a rigid carrier)",
    "roller_radius_mm": "not set (bare pins)",
    "hole_radius_mm": "not set (the pin's or roller's radius plus the eccentricity)",
    "main_preload_N": "not set (ASSUMPTION 2 % of the row's C0)",
    "crankshaft_diameter_mm": "not set (no crankshafts)",
    "crankshaft_span_mm": "not set (no crankshafts)",
}


def missing(key: str) -> str:
    """What a key left unset means ("not set", or :data:`NOT_SET`'s reading).

    Parameters
    ----------
    key : str
        The key, bare or dotted (``supports.carrier_stiffness_Nm_per_arcmin``).

    Returns
    -------
    str
    """
    return NOT_SET.get(str(key).rsplit(".", 1)[-1].split(" › ")[-1], "not set")


#: Python's None as the schema's texts write an unset value ("None: bare pins").
_PY_NONE = re.compile(r"\bNone\b")


def spoken(text: str) -> str:
    """A schema text with Python's ``None`` said as "not set" ("a roller sleeve on each
    pin (None: bare pins)" -> "... (not set: bare pins)").

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return _PY_NONE.sub("not set", text)


# ------------------------------------------------------------------------------------------
# the page


def _esc(x) -> str:
    return html.escape(str(x), quote=True)


def _cell(v) -> str:
    """A value as the tables show it (numbers to 4 significant digits, as the summaries)."""
    if isinstance(v, float) and math.isfinite(v):
        return report_summary._cell(v)
    if v is None:
        return "–"
    return str(v)


def _value(v) -> str:
    """A case value as written (floats exactly, strings as they are)."""
    if v is None:
        return "not set"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _shown(row) -> str:
    """An input row's value as the page shows it: an unset one as what it means."""
    return missing(row.key) if row.value is None else _value(row.value)


def _png_uri(path: Path) -> str | None:
    """The PNG as a data: URI, or None if it is not a PNG."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if not data.startswith(PNG_SIGNATURE):
        return None
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _figure(uri: str, caption: str) -> str:
    return (f'<figure><img src="{uri}" alt="{_esc(caption)}">'
            f"<figcaption>{_esc(caption)}</figcaption></figure>")


def _num(v) -> str:
    """The class attribute of a number's cell (right-aligned), else ''."""
    return ' class="num"' if isinstance(v, (int, float)) and not isinstance(v, bool) else ""


def _table(t: Table) -> str:
    numeric = [all(isinstance(r[i], (int, float)) and not isinstance(r[i], bool)
                   for r in t.rows if i < len(r) and r[i] is not None)
               for i in range(len(t.columns))]
    head = "".join(f"<th>{_esc(c)}</th>" for c in t.columns)
    body = "".join(
        "<tr>" + "".join(f'<td{" class=num" if numeric[i] else ""}>{_esc(_cell(v))}</td>'
                         for i, v in enumerate(r)) + "</tr>" for r in t.rows)
    note = f'<p class="note">{_esc(t.note)}</p>' if t.note else ""
    caption = f"<caption>{_esc(t.title)}</caption>" if t.title else ""
    return f'<table>{caption}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{note}'


def _markdown_sections(text: str, folder: Path, embedded: set) -> list:
    """(title, html) of each ``## `` section of a Markdown report, the part before the first
    one under "Overview" (its ``# `` title left out: the page's header says it); a
    ``## Warnings`` section is left out (the page's own lists every warning). Pictures are
    embedded (their paths added to ``embedded``); links outside the folder lose their
    target (the address stays as text)."""
    from markdown_it import MarkdownIt

    md = MarkdownIt("commonmark", {"html": False}).enable("table")
    parts: list[tuple[str, list[str]]] = []
    lines: list[str] = []
    title = "Overview"
    for line in text.splitlines():
        if line.startswith("## "):
            parts.append((title, lines))
            title, lines = line[3:].strip(), []
        elif line.startswith("# ") and title == "Overview" and not any(x.strip() for x in lines):
            continue
        else:
            lines.append(line)
    parts.append((title, lines))
    out = []
    for title, lines in parts:
        body = "\n".join(lines).strip()
        if not body or title.lower() == "warnings":
            continue
        tokens = md.parse(body)
        for tok in tokens:
            for _i, child in enumerate(tok.children or ()):
                if child.type == "image":
                    _embed_image(child, folder, embedded)
                elif child.type == "link_open":
                    href = str(child.attrGet("href") or "")
                    if re.match(r"^[a-z][a-z0-9+.-]*:|^//", href, re.I):
                        child.attrs.pop("href", None)
                        child.attrSet("title", href)
        out.append((title, md.renderer.render(tokens, md.options, {})))
    return out


def _embed_image(tok, folder: Path, embedded: set) -> None:
    """An image token's source as a data: URI of the folder's PNG, or its alt text shown
    as missing (never a broken picture)."""
    src = tok.attrGet("src") or ""
    path = (folder / src).resolve()
    uri = None
    if folder.resolve() in path.parents and path.suffix.lower() == ".png":
        uri = _png_uri(path)
    if uri is None:
        tok.type, tok.tag = "text", ""
        tok.content = f"[figure {src} is not in the folder]"
        tok.children = None
        return
    tok.attrSet("src", uri)
    embedded.add(path.relative_to(folder.resolve()).as_posix())


#: The page's style sheet (inline: nothing is fetched).
STYLE = """
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;
 color:#1d232a;max-width:1180px;margin:0 auto;padding:0 24px 48px}
header{border-bottom:3px solid #2d5d8a;padding:18px 0 10px;margin-bottom:8px}
h1{font-size:1.6em;margin:0 0 6px}h2{font-size:1.3em;border-bottom:1px solid #cfd8e0;
 padding-bottom:3px;margin-top:30px}h3{font-size:1.1em}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:2px 14px;margin:6px 0}
dl.meta dt{font-weight:600;color:#4a5560}dl.meta dd{margin:0;word-break:break-word}
nav{font-size:.92em;margin:8px 0}nav a{margin-right:12px;color:#2d5d8a}
table{border-collapse:collapse;margin:10px 0;font-size:.92em;max-width:100%}
caption{text-align:left;font-weight:600;padding:4px 0}
th,td{border:1px solid #cfd8e0;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#eef3f7}tbody tr:nth-child(even){background:#f7f9fb}td.num{text-align:right;
 font-variant-numeric:tabular-nums}
tr.default td{color:#5b6670}tr.sec td{background:#e4ecf3;font-weight:600}
.tag{display:inline-block;border-radius:3px;padding:0 5px;font-size:.82em;font-weight:600}
.declared{background:#dff0df;color:#1e5b1e}.default{background:#eceff2;color:#4a5560}
.assumed{background:#fff1c9;color:#7a5200}
.warnings li{background:#fdecea;border-left:4px solid #c0392b;padding:4px 8px;margin:4px 0;
 list-style:none}.warnings{padding:0}.where{color:#6b747c;font-size:.85em}
figure{margin:14px 0;text-align:center}img{max-width:100%;height:auto;
 border:1px solid #e1e6ea}figcaption{font-size:.88em;color:#4a5560}
code{background:#f1f3f5;padding:0 3px;border-radius:3px}.note{font-size:.88em;color:#4a5560}
p.none{color:#2e7d32}
@media print{nav{display:none}section{break-inside:avoid-page}}
"""


def _header(case, command: str, case_file) -> str:
    from ..output import command_line

    name = case.name if case is not None else "(no case)"
    now = _dt.datetime.now().astimezone().isoformat(timespec="seconds")
    items = [("command", command_line()), ("toothfem", __version__), ("date", now),
             ("Python", sys.version.split()[0])]
    if case is not None:
        items += [("case file", str(case_file) if case_file else "(given in memory)"),
                  ("drive", case.drive)]
        if case.source:
            items.append(("source", case.source))
    meta = "".join(f"<dt>{_esc(k)}</dt><dd>{_esc(v)}</dd>" for k, v in items)
    return (f"<header><h1>{_esc(name)}: toothfem {_esc(command)}</h1>"
            f'<dl class="meta">{meta}</dl></header>')


def _section(ident: str, title: str, body: str) -> str:
    return f'<section id="{ident}"><h2>{_esc(title)}</h2>\n{body}\n</section>'


def _warnings_html(found: dict, kept: list) -> str:
    items = [(m, ", ".join(w)) for m, w in found.items()]
    items += [(m, "shown while the command ran") for m in dict.fromkeys(kept)
              if m not in found]
    if not items:
        return '<p class="none">No warning: no result passes a limit.</p>'
    return '<ul class="warnings">' + "".join(
        f'<li>{_esc(m)} <span class="where">({_esc(w)})</span></li>' for m, w in items) + "</ul>"


def _published_html(case, compared, reasons: dict, case_text=None) -> str:
    """Our figures beside the case's published ones, each with the reason for a difference
    (or "no reason recorded") and its source as the case file's comment says it; then the
    case's other published figures."""
    pub = dict(case.published)
    comments = case_text.keys if case_text is not None else {}

    def source(name):
        c = comments.get(f"published.{name}")
        return c.text if c else "–"

    rows, used = [], set()
    for what, unit, cols in compared:
        if report_summary.PUBLISHED not in cols:
            continue
        p = cols[report_summary.PUBLISHED]
        name = _published_name(pub, p)
        used.add(name)
        for col, ours in cols.items():
            if col == report_summary.PUBLISHED or not isinstance(ours, (int, float)):
                continue
            diff = (f"{100 * (ours - p) / p:+.1f} %" if isinstance(p, (int, float)) and p
                    else "–")
            reason = reasons.get(name) or "no reason recorded"
            rows.append((what, unit, col, ours, p, diff, name or "–", source(name), reason))
    out = []
    if rows:
        out.append(_table(Table("",
                                ("quantity", "unit", "ours (column)", "ours", "published",
                                 "ours vs published", "[published] key",
                                 "its source (case file)", "reason for the difference"),
                                tuple(rows), report_summary.PUBLISHED_NOTE)))
    rest = [(k, v) for k, v in pub.items() if k not in used]
    if rest:
        out.append(_table(Table("The case's other published figures (not in this command's "
                                "tables above)", ("[published] key", "value",
                                                  "its source (case file)"),
                                tuple((k, _value(v), source(k)) for k, v in rest))))
    return "\n".join(out)


def _published_name(pub: dict, value):
    """The ``[published]`` key whose figure a compared row shows: the one of that value
    (the tables show it as quoted, or times 100 as a percentage)."""
    for k, v in pub.items():
        if isinstance(v, (int, float)) and isinstance(value, (int, float)) and (
                math.isclose(v, value, rel_tol=1e-12) or math.isclose(100 * v, value,
                                                                      rel_tol=1e-12)):
            return k
    return None


def _assumptions_html(case_text, inputs, found) -> str:
    items = []
    if case_text is not None:
        for sec, c in case_text.sections.items():
            if ASSUMPTION in c.text:
                where = f"[{sec}]" if sec else "the case file's head"
                text = c.text if sec else " ".join(     # the head: its sentences that say it
                    x for x in re.split(r"(?<=[.;])\s+", c.text) if ASSUMPTION in x)
                items.append((f"{where} (line {c.line})", text))
        resolved = {r.key: r.assumption for r in inputs if r.declared}
        for key, c in case_text.keys.items():
            if ASSUMPTION in c.text:
                items.append((f"{key} (line {c.line})",
                              c.text if _reason(c.text) else
                              f"{c.text}: {resolved.get(key) or 'no reason stated'}"))
    for r in inputs:
        if r.declared and isinstance(r.value, str) and ASSUMPTION in r.value:
            items.append((r.key, r.value))
        if r.declared is False and r.assumption:
            items.append((f"{r.key} = {_shown(r)} (default)", r.assumption))
    items += found
    if not items:
        return '<p class="none">No assumption recorded: the case file marks no value ' \
               "ASSUMPTION and " \
               "no default taken is one.</p>"
    return ("<p>Values chosen where no source fixes them, each with its reason as stated "
            "(the case file's comments, the schema's defaults, the results' own "
            "records).</p>" + _table(Table("", ("where", "assumption and its reason"),
                                           tuple(items))))


def _inputs_html(inputs, case_text) -> str:
    if case_text is None:
        intro = ("<p>The case was given in memory: which values a file declared is not "
                 "known.</p>")
    else:
        intro = (f"<p>Every value of the case: <span class='tag declared'>declared</span> in "
                 f"{_esc(case_text.path)}, or <span class='tag default'>default</span> "
                 "(toothfem's, with its source; docs/case_schema.md); "
                 "<span class='tag assumed'>ASSUMPTION</span> marks a reasoned choice.</p>")
    rows, section = [], None
    for r in inputs:
        sec = _section_of(r.key)
        if sec != section:
            section = sec
            note = case_text.sections.get(sec) if case_text else None
            extra = f": {_esc(note.text)}" if note and note.text else ""
            rows.append(f'<tr class="sec"><td colspan="5">[{_esc(sec)}]{extra}</td></tr>')
        origin = ("" if r.declared is None else
                  "<span class='tag declared'>declared</span>" if r.declared else
                  "<span class='tag default'>default</span>")
        if r.assumption:
            origin += " <span class='tag assumed'>ASSUMPTION</span>"
        note = r.note
        rows.append(f'<tr class="{"declared" if r.declared else "default"}">'
                    f"<td><code>{_esc(r.key.rsplit('.', 1)[1])}</code></td>"
                    f"<td{_num(r.value)}>{_esc(_shown(r))}</td><td>{_esc(r.unit)}</td>"
                    f"<td>{origin}</td><td>{_esc(note)}</td></tr>")
    head = ("<thead><tr><th>key</th><th>value</th><th>unit</th><th>from</th>"
            "<th>source, comment or reason</th></tr></thead>")
    return intro + f"<table>{head}<tbody>{''.join(rows)}</tbody></table>"


def _files_html(folder: Path) -> str:
    from ..output import MARKER

    names = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*")
                   if p.is_file() and p.name not in (MARKER, REPORT))
    if not names:
        return "<p>No other file.</p>"
    items = "".join(f'<li><a href="{_esc(quote(n))}">{_esc(n)}</a> '
                    f'<span class="where">({(folder / n).stat().st_size:,} bytes)</span></li>'
                    for n in names)
    return f"<p>Beside this page in the output folder:</p><ul>{items}</ul>"


def render(folder, case=None, *, command: str, case_file=None, tables=(), compared=None,
           reasons=None) -> str:
    """The page of an output folder as HTML text (:func:`write_report` writes it).

    Parameters
    ----------
    folder : str or pathlib.Path
        The folder the command wrote (its report.md, PNGs and JSON summaries are read).
    case : toothfem.case.Case, optional
        The case analysed (its inputs and published figures).
    command : str
        The command's name ("run", "contact", ...), for the title.
    case_file : str or pathlib.Path, optional
        The case file: which values it declares and its comments; None for a case given
        in memory.
    tables : sequence of Table
        The command's tables, shown among its results.
    compared : sequence of tuple, optional
        Summary rows ``(quantity, unit, {column: value})`` whose ``published`` column is
        compared (default: the rows of ``tables`` that have one).
    reasons : dict, optional
        {``[published]`` key: why ours differs}; default
        :data:`toothfem.report.summary.PUBLISHED_REASONS`.

    Returns
    -------
    str
        The page.
    """
    folder = Path(folder)
    reasons = report_summary.PUBLISHED_REASONS if reasons is None else reasons
    case_text = None
    if case_file is not None and Path(case_file).is_file():
        case_text = read_case_text(case_file)
    summaries = _summaries(folder)
    embedded: set = set()
    parts, nav = [], []

    def add(ident, title, body):
        parts.append(_section(ident, title, body))
        nav.append(f'<a href="#{ident}">{_esc(title)}</a>')

    add("warnings", "Warnings", _warnings_html(folder_warnings(summaries), _KEPT.get() or []))
    md = folder / MARKDOWN
    if md.is_file():
        text = md.read_text(encoding="utf-8", errors="replace")
        for i, (title, body) in enumerate(_markdown_sections(text, folder, embedded)):
            add(f"result-{i}", title, body)
    if tables:
        add("tables", "Tables", "\n".join(_table(t) for t in tables))
    if case is not None and case.published:
        if compared is None:
            compared = [(r[0], r[1], dict(zip(t.columns[2:], r[2:]))) for t in tables
                        for r in t.rows if report_summary.PUBLISHED in t.columns]
        body = _published_html(case, compared, reasons, case_text)
        if body:
            add("published", "Published figures beside ours", body)
    figures = [p for p in sorted(folder.rglob("*.png"))
               if p.relative_to(folder).as_posix() not in embedded]
    uris = [(p, _png_uri(p)) for p in figures]
    shown = [(p, uri) for p, uri in uris if uri]
    if shown:
        add("figures", "Figures" if not embedded else "Further figures",
            "\n".join(_figure(uri, p.relative_to(folder).as_posix()) for p, uri in shown))
    inputs = case_inputs(case, case_text) if case is not None else []
    add("assumptions", "Assumptions",
        _assumptions_html(case_text, inputs, folder_assumptions(summaries)))
    if case is not None:
        add("inputs", "Inputs", _inputs_html(inputs, case_text))
    add("files", "Files", _files_html(folder))
    title = f"{case.name if case is not None else 'toothfem'}: toothfem {command}"
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{_esc(title)}</title><style>{STYLE}</style></head><body>\n"
            + _header(case, command, case_file)
            + f"<nav>{''.join(nav)}</nav>\n" + "\n".join(parts)
            + f'\n<footer class="note">Written by toothfem {_esc(__version__)}; this page '
              "holds every picture and needs no network.</footer>\n</body></html>\n")


def write_report(folder, case=None, *, command: str, case_file=None, tables=(),
                 compared=None, reasons=None) -> Path:
    """Write ``folder/report.html``: the folder's results as one self-contained page
    (module docstring). Call it last inside the command's output folder
    (:func:`toothfem.output.atomic_dir`), after everything else is written.

    Parameters
    ----------
    folder : str or pathlib.Path
        The output folder being written.
    case, command, case_file, tables, compared, reasons
        As :func:`render`.

    Returns
    -------
    pathlib.Path
        The page.

    Raises
    ------
    ToothfemError
        If ``folder`` is not a folder.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ToothfemError(f"folder = {str(folder)!r} is not a folder; valid: the output "
                            "folder being written")
    page = render(folder, case, command=command, case_file=case_file, tables=tables,
                  compared=compared, reasons=reasons)
    path = folder / REPORT
    path.write_text(page, encoding="utf-8")
    return path
