"""report.html: one self-contained page per output folder, the one place HTML is written.

:func:`write_report` turns what a command wrote into its folder into ``report.html``: a
header (the case, toothfem's version, the date and the command line), the warnings, the
command's results (its report.md, split into sections, and the tables it passes), the case's
published figures beside ours, every figure (PNG) of the folder, the assumptions, every
input of the case with its unit and where it came from, and the files beside the page.

The page opens from the file system with no network: every picture is embedded as a
``data:`` URI, the style sheet is inline, there is no script, and its Content-Security-
Policy forbids loading anything else (a reader's browser refuses even a stray reference).
It reads nothing but the folder, the case file and the package itself.

Where each part comes from (each read by its own module beside this one):

- inputs (:mod:`toothfem.report.inputs`): the case record (:class:`toothfem.case.Case`);
  *declared* when the case file sets the key (:mod:`toothfem.report.case_text`), else
  *default* with the meaning and source the schema declares for it
  (:mod:`toothfem.case_schema`, the sections' field metadata), each unit from the schema;
- assumptions: every comment of the case file that says ASSUMPTION (with its reason), every
  default whose source says ASSUMPTION, and every ``assumed`` entry of the folder's JSON
  summaries (:mod:`toothfem.report.folder_json`);
- warnings: every ``warnings`` entry of the folder's JSON summaries (the
  :class:`toothfem.limits.Exceeded` records' messages) and the Python warnings shown while
  the command ran (:func:`warnings_kept`);
- results: the command's report.md (:mod:`toothfem.report.html_markdown`) and tables;
- published figures: the rows of the command's summary tables that carry a ``published``
  column (:mod:`toothfem.report.summary`), each with the reason for a difference where
  :data:`toothfem.report.summary.PUBLISHED_REASONS` states one, else "no reason recorded";
  the case's other ``[published]`` figures are listed with their sources.
"""
from __future__ import annotations

import contextlib
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
from ..units import symbol_of as unit_of
from ..errors import ToothfemError
from . import summary as report_summary
from .case_text import ASSUMPTION, CaseText, read_case_text, reason
from .folder_json import folder_assumptions, folder_warnings, summaries
from .html_markdown import PNG_SIGNATURE, markdown_sections, png_uri
from .inputs import InputRow, case_inputs, missing, section_of, shown, spoken, value_text

#: What other modules and the tests take from here (the page's parts re-exported).
__all__ = ["ASSUMPTION", "CSP", "CaseText", "InputRow", "MARKDOWN", "PNG_SIGNATURE", "REPORT",
           "STYLE", "Table", "ToothfemError", "case_inputs", "folder_assumptions",
           "folder_warnings", "missing", "read_case_text", "render", "spoken", "unit_of",
           "warnings_kept", "write_report"]

#: The page's name in every output folder.
REPORT = "report.html"
#: The Markdown report a command may have written beside it (run, loop, tolerance, design).
MARKDOWN = "report.md"
#: Rows of a long table (a sweep's CSV) shown on the page; the file beside it has them all.
MAX_TABLE_ROWS = 500
#: Content-Security-Policy of the page: nothing from anywhere but the page itself (the
#: pictures are data: URIs, the style inline), and no script at all.
CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"

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
                                tuple((k, value_text(v), source(k)) for k, v in rest))))
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
                              c.text if reason(c.text) else
                              f"{c.text}: {resolved.get(key) or 'no reason stated'}"))
    for r in inputs:
        if r.declared and isinstance(r.value, str) and ASSUMPTION in r.value:
            items.append((r.key, r.value))
        if r.declared is False and r.assumption:
            items.append((f"{r.key} = {shown(r)} (default)", r.assumption))
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
                 "(toothfem's, with its meaning and source, as docs/case_schema.md lists them); "
                 "<span class='tag assumed'>ASSUMPTION</span> marks a reasoned choice.</p>")
    rows, section = [], None
    for r in inputs:
        sec = section_of(r.key)
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
                    f"<td{_num(r.value)}>{_esc(shown(r))}</td><td>{_esc(r.unit)}</td>"
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
    found = summaries(folder)
    embedded: set = set()
    parts, nav = [], []

    def add(ident, title, body):
        parts.append(_section(ident, title, body))
        nav.append(f'<a href="#{ident}">{_esc(title)}</a>')

    add("warnings", "Warnings", _warnings_html(folder_warnings(found), _KEPT.get() or []))
    md = folder / MARKDOWN
    if md.is_file():
        text = md.read_text(encoding="utf-8", errors="replace")
        for i, (title, body) in enumerate(markdown_sections(text, folder, embedded)):
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
    uris = [(p, png_uri(p)) for p in figures]
    shown = [(p, uri) for p, uri in uris if uri]
    if shown:
        add("figures", "Figures" if not embedded else "Further figures",
            "\n".join(_figure(uri, p.relative_to(folder).as_posix()) for p, uri in shown))
    inputs = case_inputs(case, case_text) if case is not None else []
    add("assumptions", "Assumptions",
        _assumptions_html(case_text, inputs, folder_assumptions(found)))
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
