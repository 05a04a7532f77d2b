"""The columns of a measured-data CSV: quantities and units, header, cells and rows.

The vocabulary (:data:`QUANTITIES`: each quantity's units and their conversion to the
canonical one) and the checks :func:`toothfem.efficiency.loop.measured.parse_measured`
applies to the header comments, the header, each cell and each row. The rules they
implement (which rows are refused and why, which columns are dropped) are stated in
:mod:`toothfem.efficiency.loop.measured`.
"""
from __future__ import annotations

import csv
import itertools
import math
import re

import numpy as np

from ...errors import MeasuredDataError
from ...units import conversion


#: Each quantity's canonical unit (its first) and the other units a column may carry it
#: in, by their suffixes of :data:`toothfem.units.UNITS` ("" a plain number).
_UNITS_OF = {
    "input_speed": ("rpm", "rad_s", "rps"),
    "output_torque": ("Nm", "Nmm", "kNm"),
    "input_torque": ("Nm", "Nmm", "kNm"),
    "oil_temp": ("C", "K", "F"),
    "time": ("h", "min", "s"),
    "efficiency_sigma": ("", "pct"),
    "efficiency": ("", "pct"),
}
#: quantity -> {unit suffix: (factor, offset)} to the canonical unit (the first listed):
#: value_canonical = factor * value + offset (:func:`toothfem.units.conversion`).
QUANTITIES = {q: {u: conversion(u, units[0]) for u in units} for q, units in _UNITS_OF.items()}
#: Canonical column names of the record.
CANONICAL = {"input_speed": "input_speed_rpm", "output_torque": "output_torque_Nm",
             "input_torque": "input_torque_Nm", "oil_temp": "oil_temp_C", "time": "time_h",
             "efficiency": "efficiency", "efficiency_sigma": "efficiency_sigma"}
#: Relative disagreement allowed between an efficiency column and T2 / (|i| T1) (the
#: rounding of values written with 6-7 significant digits, with a wide margin).
CONSISTENCY_RTOL = 1e-4
#: Oil temperatures outside this range [deg C] are refused as misread.
OIL_TEMP_RANGE_C = (-40.0, 250.0)


def _column(name: str):
    """(quantity, factor, offset) of a known column, ('run_id', None, None), or
    (None, None, None) for a free covariate. Raises on a known quantity in an unknown
    unit."""
    if name == "run_id":
        return "run_id", None, None
    for q, units in QUANTITIES.items():     # efficiency_sigma before efficiency
        if name == q or name.startswith(q + "_"):
            unit = name[len(q) + 1:]
            if q == "efficiency" and unit.startswith("sigma"):
                continue
            if unit not in units:
                known = ", ".join(repr(u) if u else "(none)" for u in units)
                raise MeasuredDataError(
                    f"column {name!r}: unknown unit {unit!r} for {q}; known: {known}")
            f, o = units[unit]
            return q, f, o
    return None, None, None


def parse_number(text, name):
    """The float in a cell, or None and why not.

    Parameters
    ----------
    text : str
        The cell.
    name : str
        The column, named in the reason.

    Returns
    -------
    (float or None, str or None)
        The value and None, or None and the reason.
    """
    s = text.strip()
    if s == "":
        return None, f"{name} is empty"
    try:
        v = float(s)
    except ValueError:
        if re.fullmatch(r"[-+]?\d+,\d+", s):
            return None, (f"{name} = {s!r} is not a number: a decimal comma in a comma-"
                          "separated file (write a decimal point, or separate the columns "
                          "with ';')")
        return None, f"{name} = {s!r} is not a number"
    if math.isnan(v):
        return None, f"{name} is NaN"
    if math.isinf(v):
        return None, f"{name} = {s} is not finite"
    return v, None


def comment_lines(lines):
    """The provenance in a file's leading ``# key: value`` lines.

    Parameters
    ----------
    lines : list of str
        The file's lines.

    Returns
    -------
    (dict, int)
        key -> value, and the index of the first line that is neither a comment nor
        blank (the header).
    """
    prov, start = {}, 0
    while start < len(lines) and (lines[start].lstrip().startswith("#")
                                  or not lines[start].strip()):
        body = lines[start].lstrip().lstrip("#").strip()
        if ":" in body:
            k, v = body.split(":", 1)
            prov[k.strip()] = v.strip()
        start += 1
    return prov, start


def next_row(reader, source, line):
    """The next row of cells, or None at the end.

    Parameters
    ----------
    reader : csv.reader
    source : str
        The file, named in a refusal.
    line : int
        The row's line number, named in a refusal.

    Returns
    -------
    list of str or None

    Raises
    ------
    MeasuredDataError
        A row the csv module cannot split (a NUL byte, a field beyond its size limit).
    """
    try:
        return next(reader)
    except StopIteration:
        return None
    except csv.Error as exc:
        raise MeasuredDataError(f"{source}: line {line}: cannot be read as CSV ({exc})") \
            from None


def header_names(cells, source):
    """Column names, stripped; empty names at the end (a trailing comma) are dropped.

    Parameters
    ----------
    cells : list of str or None
        The header row.
    source : str
        The file, named in a refusal.

    Returns
    -------
    list of str

    Raises
    ------
    MeasuredDataError
        A column without a name.
    """
    header = [h.strip() for h in cells or ()]
    while header and not header[-1]:
        header.pop()
    for j, name in enumerate(header):
        if not name:
            raise MeasuredDataError(f"{source}: column {j + 1} of the header has no name")
    return header


def _columns(header, source):
    """quantity or column name -> (index, factor, offset); refuses a bad header."""
    columns: dict = {}
    for j, name in enumerate(header):
        q, f, o = _column(name)
        key = q or name
        if key in columns:
            raise MeasuredDataError(f"{source}: {key} appears twice in the header "
                                    f"({header[columns[key][0]]!r} and {name!r})")
        columns[key] = (j, f, o)
    for q in ("input_speed", "output_torque"):
        if q not in columns:
            raise MeasuredDataError(f"{source}: missing column {CANONICAL[q]} (have "
                                    f"{header})")
    if "efficiency" not in columns and "input_torque" not in columns:
        raise MeasuredDataError(f"{source}: missing column efficiency (or input_torque_Nm "
                                f"with the reducer ratio); have {header}")
    return columns


def _free_columns(cells):
    """Further covariates from their cells: a column whose every cell is a finite number is
    kept; any other (text, a label, empty or NaN cells) is dropped whole, with a note, so
    that it never refuses a good row nor puts a hole in a covariate."""
    extra, notes = {}, []
    for name, col in cells.items():
        try:                    # every cell a finite number: parse_number's values at once
            values = np.array([float(c) for c in col], float)
            if np.all(np.isfinite(values)):
                extra[name] = values
                continue
        except ValueError:
            pass
        parsed = [parse_number(c, name) for c in col]
        bad = [why for _, why in parsed if why]
        if not bad:
            extra[name] = np.array([v for v, _ in parsed], float)
            continue
        n_text = sum(" is not a number" in why for why in bad)
        kind = ("text" if n_text == len(col) else
                f"{len(bad)} of {len(col)} cells empty or not a number")
        notes.append(f"column {name!r} dropped ({kind}): not used as a covariate; the rows "
                     "are kept")
    return extra, notes


#: An efficiency in percent at or below this in every row reads as a fraction.
PERCENT_AS_FRACTION_MAX = 1.0


def _check_percent_column(header, columns, values, source):
    """Refuse an ``efficiency_pct`` column whose every value looks like a fraction (a
    column in percent that holds 0.82 would make the efficiency 0.8 %)."""
    if "efficiency" not in columns or columns["efficiency"][1] != 0.01:
        return
    pct = np.asarray(values["efficiency"]) * 100
    if pct.size and np.all(pct <= PERCENT_AS_FRACTION_MAX):
        name = header[columns["efficiency"][0]]
        raise MeasuredDataError(
            f"{source}: column {name!r} holds fractions (every value <= "
            f"{PERCENT_AS_FRACTION_MAX:g}, largest {pct.max():.6g}): name it 'efficiency' for "
            "fractions, or give the values in percent")


def _percent_hint(rejected) -> str:
    """A hint when every row was refused for an efficiency above 1 (percent in a column of
    fractions)."""
    if rejected and all(r.reason.startswith("efficiency =") and "outside (0, 1]" in r.reason
                        and not r.reason.startswith("efficiency = -") for r in rejected):
        return ": the efficiency column seems to hold percent; name it 'efficiency_pct'"
    return ""


def _check_row(v, i_abs):
    """Why a parsed row is refused, or None."""
    if v["input_speed"] < 0:
        return f"input_speed_rpm = {v['input_speed']:g} is negative"
    if v["input_speed"] == 0:
        return "input_speed_rpm = 0: no efficiency at standstill"
    for q in ("output_torque", "input_torque"):
        if q in v and v[q] <= 0:
            return f"{CANONICAL[q]} = {v[q]:g} must be > 0 (the drive direction)"
    eff = v.get("efficiency")
    if eff is None:
        eff = v["output_torque"] / (i_abs * v["input_torque"])
        label = "efficiency T2/(|i| T1)"
    else:
        label = "efficiency"
    if not 0 < eff <= 1:
        return f"{label} = {eff:.6g} is outside (0, 1]"
    if "efficiency" in v and "input_torque" in v and i_abs is not None:
        from_torques = v["output_torque"] / (i_abs * v["input_torque"])
        if abs(from_torques - eff) > CONSISTENCY_RTOL * eff:
            return (f"efficiency = {eff:.6g} disagrees with T2/(|i| T1) = {from_torques:.6g} "
                    f"(ratio {i_abs:g})")
    if "efficiency_sigma" in v and not v["efficiency_sigma"] > 0:
        return f"efficiency_sigma = {v['efficiency_sigma']:g} must be > 0"
    if "oil_temp" in v and not OIL_TEMP_RANGE_C[0] <= v["oil_temp"] <= OIL_TEMP_RANGE_C[1]:
        return (f"oil_temp_C = {v['oil_temp']:g} is outside [{OIL_TEMP_RANGE_C[0]:g}, "
                f"{OIL_TEMP_RANGE_C[1]:g}]")
    if "time" in v and v["time"] < 0:
        return f"time_h = {v['time']:g} is negative"
    return None


#: Rows :func:`clean_rows` splits at a time (their cells' strings, some 30 MB, are all it
#: holds beside the values).
CLEAN_CHUNK = 65536
#: The longest line the csv module reads (its field_size_limit; a longer one is refused
#: by the row loop, which reads the file then).
_CSV_FIELD_LIMIT = 131072


def clean_rows(body, header, columns, checked, free, i_abs, start):
    """The rows of a plain comma-separated body read at once, column by column: every line
    with the header's fields, no quote, NUL or overlong line, every checked cell a finite
    number and every row passing :func:`_check_row`'s rules. None for anything else (an
    empty or short line, a bad cell or row), which the row loop of
    :func:`~toothfem.efficiency.loop.measured.parse_measured` then reads (1e6 rows: 2.8 s
    against 5 s, the same values).

    Parameters
    ----------
    body : list of str
        The header line and the rows, as split into lines.
    header : list of str
        The column names.
    columns : dict
        quantity or column -> (index, factor, offset) (:func:`_columns`).
    checked, free : list of str
        The quantities whose bad cell refuses a row, and the further covariates.
    i_abs : float or None
        The ratio's magnitude (the efficiency from torques, its check).
    start : int
        The header's index among the file's lines (a row's line number follows from it).

    Returns
    -------
    tuple or None
        (values {key: array}, free cells {key: list}, run labels, line numbers).
    """
    n = len(header)
    rows = body[1:]
    if not rows or max(map(len, rows)) >= _CSV_FIELD_LIMIT:
        return None
    if set(map(str.count, rows, itertools.repeat(","))) != {n - 1}:
        return None
    parts: dict = {key: [] for key in checked}
    cells_free: dict = {key: [] for key in free}
    run: list = []
    for first in range(0, len(rows), CLEAN_CHUNK):
        text = ",".join(rows[first:first + CLEAN_CHUNK])
        if '"' in text or "\x00" in text:
            return None
        cells = text.split(",")     # one list of strings: no list a row for the collector
        del text
        try:
            for key in checked:
                j, f, o = columns[key]
                v = np.array(list(map(float, cells[j::n])), float)
                if not np.all(np.isfinite(v)):
                    return None
                parts[key].append(f * v + o)
        except ValueError:
            return None
        for key in free:
            cells_free[key] += cells[columns[key][0]::n]
        if "run_id" in columns:
            run += [c.strip() for c in cells[columns["run_id"][0]::n]]
    values = {key: np.concatenate(p) for key, p in parts.items()}
    if not np.all(values["input_speed"] > 0):
        return None
    for q in ("output_torque", "input_torque"):
        if q in values and not np.all(values[q] > 0):
            return None
    eff = values.get("efficiency")
    if eff is None:
        eff = values["output_torque"] / (i_abs * values["input_torque"])
    if not np.all((eff > 0) & (eff <= 1)):
        return None
    if "efficiency" in values and "input_torque" in values and i_abs is not None:
        from_torques = values["output_torque"] / (i_abs * values["input_torque"])
        if np.any(np.abs(from_torques - eff) > CONSISTENCY_RTOL * eff):
            return None
    if "efficiency_sigma" in values and not np.all(values["efficiency_sigma"] > 0):
        return None
    if "oil_temp" in values and not np.all((OIL_TEMP_RANGE_C[0] <= values["oil_temp"])
                                           & (values["oil_temp"] <= OIL_TEMP_RANGE_C[1])):
        return None
    if "time" in values and np.any(values["time"] < 0):
        return None
    return values, cells_free, run, list(range(start + 2, start + 2 + len(rows)))
