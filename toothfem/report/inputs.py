"""The inputs of report.html: every value of a case, with its unit and where it came from.

A value the case file sets is *declared*, with the file's comment (and its ASSUMPTION
reason, if it is one); any other is toothfem's *default*, with the schema's meaning and
source of that default (:mod:`toothfem.case_schema`, read from the package: an installed
wheel shows the same sources as the checkout). A value left unset reads as what it stands
for, never as Python's None.
"""
from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass

from ..case_schema import HEAD, schema as case_schema
from ..units import symbol_of
from .case_text import ASSUMPTION, CaseText, reason

#: An array of tables' index in a key (``measured[0].efficiency``).
_INDEX = re.compile(r"\[\d+\]")
#: The note of a default that has no source (the schema test keeps this from happening).
NO_SOURCE = "toothfem's default (no source recorded)"


@dataclass(frozen=True)
class InputRow:
    """One value of the case: its dotted key, value, unit, whether the case file sets it
    (``declared``; None when no file says), the comment or meaning and source beside it, the
    assumption it is (its reason), if any, and for a default the default's source."""
    key: str
    value: object
    unit: str
    declared: bool | None
    note: str
    assumption: str | None
    source: str = ""


def case_inputs(case, case_text: CaseText | None = None, schema: dict | None = None) -> list:
    """Every value of a case as :class:`InputRow` records, in the case's order.

    Parameters
    ----------
    case : toothfem.case.Case
        The case.
    case_text : CaseText, optional
        What its file declares and comments (:func:`toothfem.report.case_text.read_case_text`);
        None: not known.
    schema : dict, optional
        {dotted key: :class:`toothfem.case_schema.KeyRow`}; default the package's
        (:func:`toothfem.case_schema.schema`).

    Returns
    -------
    list of InputRow
        The ``[case]`` head, then every section present (nested tables and arrays of
        tables with their index); ``[published]`` is not an input and is left out.
    """
    schema = case_schema() if schema is None else schema
    rows = [_row(f"case.{name}", getattr(case, name), case_text, schema) for name in HEAD]
    for f in dataclasses.fields(case):
        value = getattr(case, f.name)
        if f.name in HEAD or f.name == "published" or value is None:
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
            rows.append(_row(key, value, case_text, schema))
    return rows


def section_of(key: str) -> str:
    """The table of a dotted key (``cycloid.disc_holes.crank_hole_count`` ->
    ``cycloid.disc_holes``).

    Parameters
    ----------
    key : str

    Returns
    -------
    str
    """
    return key.rsplit(".", 1)[0]


def _row(key: str, value, case_text, schema) -> InputRow:
    """One input row: declared (with its comment, or its section's ASSUMPTION) or a default
    (with the schema's meaning and source)."""
    spec = schema.get(_INDEX.sub("", key))
    unit = spec.unit if spec is not None else symbol_of(key.rsplit(".", 1)[1])
    if case_text is None:
        return InputRow(key, value, unit, None, "", None)
    if key in case_text.declared:
        own = case_text.keys.get(key)
        sec = case_text.sections.get(section_of(key))
        own_text, sec_text = (own.text if own else ""), (sec.text if sec else "")
        note, assumption = own_text, None
        if ASSUMPTION in own_text:
            assumption = reason(own_text) or (
                f"as [{section_of(key)}] (line {sec.line})" if reason(sec_text)
                else "no reason stated in the case file")
            if not reason(own_text):
                note = f"{own_text}: {assumption}"
        elif ASSUMPTION in sec_text:
            assumption = (f"[{section_of(key)}]: "
                          + (reason(sec_text) or "no reason stated in the case file"))
        elif isinstance(value, str) and ASSUMPTION in value:
            assumption = reason(value) or "no reason stated in the case file"
        return InputRow(key, value, unit, True, note, assumption)
    doc, source, unset = ((spoken(spec.doc), spoken(spec.source), spec.unset)
                          if spec is not None else ("", "", ""))
    note = "; ".join(x for x in (doc, source) if x) or NO_SOURCE
    assumption = note if ASSUMPTION in note or ASSUMPTION in unset else None
    return InputRow(key, value, unit, False, note, assumption, source)


#: What a value left unset in a JSON summary means, by its name (the page never prints
#: Python's None): a case key's is the schema's (:func:`missing`), the others read "not set".
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
    """What a key left unset means: a case key's as the schema says (its ``unset``), another
    name's as :data:`NOT_SET` says, else "not set".

    Parameters
    ----------
    key : str
        A case key, dotted (``supports.carrier_stiffness_Nm_per_arcmin``, an array's with
        its index), or a JSON summary's name.

    Returns
    -------
    str
    """
    spec = case_schema().get(_INDEX.sub("", str(key)))
    if spec is not None:
        return f"not set ({spec.unset})" if spec.unset else "not set"
    return NOT_SET.get(str(key).rsplit(".", 1)[-1].split(" › ")[-1], "not set")


#: Python's None as a schema text may write an unset value ("None: bare pins").
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


def value_text(v) -> str:
    """A case value as written (floats exactly, strings as they are, None as "not set").

    Parameters
    ----------
    v : object

    Returns
    -------
    str
    """
    if v is None:
        return "not set"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def shown(row: InputRow) -> str:
    """An input row's value as the page shows it: an unset one as what it means.

    Parameters
    ----------
    row : InputRow

    Returns
    -------
    str
    """
    return missing(row.key) if row.value is None else value_text(row.value)
