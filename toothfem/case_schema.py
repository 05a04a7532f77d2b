"""The case schema: every key of a case file with its unit, valid range, default and the
default's source, read from where it is declared once, the field metadata of the case's
sections (:mod:`toothfem.case_sections`, :mod:`toothfem.case_running`,
:mod:`toothfem.case_design`, and the ``[case]``
table's keys on :class:`toothfem.case.Case`).

:func:`schema` is what everything reads: the report's inputs table
(:mod:`toothfem.report.inputs`: each default's source on report.html, from the package, so
an installed wheel shows the same as the checkout) and the tables of docs/case_schema.md
(:func:`render`, run as ``python -m toothfem.case_schema docs/case_schema.md`` or ``make
schema``; a test checks that the committed file is what this writes).

Units come from the key's suffix (:func:`toothfem.units.symbol_of`: the case keys carry
their units in their names) unless the field states one.
"""
from __future__ import annotations

import argparse
import dataclasses
import functools
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from .units import symbol_of

#: The ``[case]`` table's keys (fields of the Case itself, not a section).
HEAD = ("name", "drive", "source", "stated_ratio")
#: The arrays of tables (``[[measured]]``, ``[[duty_cycle]]``): a row per entry.
ARRAYS = ("measured", "duty_cycle")
#: A block of docs/case_schema.md that :func:`render` fills: ``<!-- schema: section -->``
#: up to ``<!-- /schema -->``.
BLOCK = re.compile(r"(<!-- schema: (?P<section>[a-z_.]+) -->\n)(?P<body>.*?)(<!-- /schema -->)",
                   re.S)


@dataclass(frozen=True)
class KeyRow:
    """One key of the schema: its table and name, unit, valid range (as text), default
    (``required`` where it has none), what a default of None stands for, what the key is and
    where its default comes from."""
    section: str              # "material", "cycloid.disc_holes", "measured" (an array) ...
    key: str
    unit: str
    valid: str
    required: bool
    default: object
    unset: str
    doc: str
    source: str

    @property
    def dotted(self) -> str:
        """``section.key``, as refusals and the report name it."""
        return f"{self.section}.{self.key}"

    @property
    def default_text(self) -> str:
        """The default as a case file would write it ("required" where there is none; a None
        default as "none: " and what it stands for)."""
        if self.required:
            return "required"
        if self.default is None:
            return f"none: {self.unset}" if self.unset else "none"
        return _literal(self.default)


def _literal(value) -> str:
    """A value as TOML writes it (floats short, strings quoted)."""
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _bound(x) -> str:
    if x is None or (isinstance(x, float) and math.isinf(x)):
        return "inf"
    return f"{x:g}"


def range_text(md) -> str:
    """A field's valid values as text: "[0, 1)", "one of a, b", "integer in [1, 4]".

    Parameters
    ----------
    md : Mapping
        The field's metadata (lo, hi, lo_open, hi_open, choices, integer).

    Returns
    -------
    str
        "any text" for a free string.
    """
    if md.get("choices") is not None:
        return "one of " + ", ".join(f'"{c}"' for c in md["choices"])
    lo, hi = md.get("lo"), md.get("hi")
    if lo is None and hi is None:
        return "any text"
    left = "(" if md.get("lo_open") or lo is None else "["
    right = ")" if md.get("hi_open") or hi is None else "]"
    span = f"{left}{'-inf' if lo is None else _bound(lo)}, {_bound(hi)}{right}"
    return f"integer in {span}" if md.get("integer") else span


def _rows_of(section: str, cls, names=None) -> list:
    rows = []
    for f in dataclasses.fields(cls):
        md = f.metadata
        if not md or (names is not None and f.name not in names):
            continue                  # a nested table (its own rows), or not a key
        required = (f.default is dataclasses.MISSING
                    and f.default_factory is dataclasses.MISSING)
        rows.append(KeyRow(section=section, key=f.name,
                           unit=md["unit"] if md.get("unit") is not None else symbol_of(f.name),
                           valid=range_text(md), required=required,
                           default=None if required else f.default,
                           unset=md.get("unset", ""), doc=md.get("doc", ""),
                           source=md.get("source", "")))
    return rows


def tables() -> tuple:
    """Every table of a case file in the order of the Case's fields: (name, section class),
    a nested table after its parent (``cycloid.disc_holes``), the ``[case]`` table first
    (class :class:`toothfem.case.Case`, its keys :data:`HEAD`).

    Returns
    -------
    tuple of (str, type)
    """
    from . import case as case_mod

    sections: dict[str, type] = {**case_mod._SECTIONS, "measured": case_mod.MeasuredPoint,
                                 "duty_cycle": case_mod.DutyPoint}
    nested: dict[type, dict[str, type]] = {k: dict(v) for k, v in case_mod._NESTED.items()}
    out: list[tuple[str, type]] = [("case", case_mod.Case)]
    for f in dataclasses.fields(case_mod.Case):
        cls = sections.get(f.name)
        if cls is None:
            continue
        out.append((f.name, cls))
        out += [(f"{f.name}.{sub}", scls) for sub, scls in nested.get(cls, {}).items()]
    return tuple(out)


@functools.lru_cache(maxsize=1)
def schema() -> dict:
    """Every key of a case file, by its dotted name (``material.hardness_HV``; an array's
    rows without an index: ``measured.efficiency``), in the case's order.

    Returns
    -------
    dict of str to KeyRow
    """
    rows = {}
    for name, cls in tables():
        for row in _rows_of(name, cls, HEAD if name == "case" else None):
            rows[row.dotted] = row
    return rows


def section_rows(section: str) -> list:
    """The keys of one table.

    Parameters
    ----------
    section : str
        Its name as :func:`tables` gives it (``"friction"``, ``"cycloid.disc_holes"``).

    Returns
    -------
    list of KeyRow
    """
    return [r for r in schema().values() if r.section == section]


def _cell(text: str) -> str:
    """Text as a Markdown table cell: pipes escaped, None said as 'none'."""
    return re.sub(r"\bNone\b", "none", text).replace("|", "\\|")


def markdown_table(section: str) -> str:
    """The Markdown table of one case table's keys: key, unit, valid range, default, what the
    key is and the default's source.

    Parameters
    ----------
    section : str
        As :func:`tables` names it.

    Returns
    -------
    str
        The table, ending in a newline.
    """
    lines = ["| key | unit | valid values | default | meaning | the default's source |",
             "|---|---|---|---|---|---|"]
    for r in section_rows(section):
        cells = (f"`{r.key}`", r.unit or "–", r.valid,
                 r.default_text if r.required or r.default is None else f"`{r.default_text}`",
                 r.doc or "–", r.source or "–")
        lines.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines) + "\n"


def render(text: str) -> str:
    """docs/case_schema.md with every ``<!-- schema: section -->`` block filled from the
    schema (the prose between the blocks is kept as written).

    Parameters
    ----------
    text : str
        The document.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        For a block naming no table, a table in two blocks or a table in none (the document
        then lacks or doubles keys).
    """
    names = [n for n, _ in tables()]
    seen = [m.group("section") for m in BLOCK.finditer(text)]
    unknown = sorted(set(seen) - set(names))
    doubled = sorted({n for n in seen if seen.count(n) > 1})
    missing = [n for n in names if n not in seen]
    if unknown or doubled or missing:
        raise ValueError(f"schema blocks: unknown {unknown}, doubled {doubled}, "
                         f"missing {missing} (valid: one per table of {names})")
    return BLOCK.sub(lambda m: m.group(1) + markdown_table(m.group("section")) + m.group(4),
                     text)


def main(argv=None) -> int:
    """``python -m toothfem.case_schema FILE``: fill FILE's schema tables in place;
    ``--check``: only say whether they are current.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: the command line's).

    Returns
    -------
    int
        0, or 1 when ``--check`` finds the file out of date.
    """
    parser = argparse.ArgumentParser(prog="python -m toothfem.case_schema",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("file", type=Path, help="docs/case_schema.md")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if the file's tables are not the schema's")
    args = parser.parse_args(argv)
    text = args.file.read_text(encoding="utf-8")
    new = render(text)
    if args.check:
        if new != text:
            print(f"{args.file} is out of date: run make schema", file=sys.stderr)
            return 1
        return 0
    if new != text:
        args.file.write_text(new, encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
