"""Measured efficiency data: CSV with the unit in each column name, provenance beside it.

``load_measured(path, ratio=None)`` opens a CSV (and its sidecar ``<stem>.json``);
``parse_measured(text, ...)`` validates text, so tests pass strings. The result is a
:class:`MeasuredData` record of arrays.

Columns (the unit is the suffix of the name; :data:`.measured_columns.QUANTITIES` lists the
units known):

* required: ``input_speed_rpm``, ``output_torque_Nm`` and ``efficiency`` (a fraction;
  ``efficiency_pct`` in percent) or ``input_torque_Nm`` (then the efficiency is
  T2 / (|i| T1), which needs the reducer ratio ``ratio``);
* optional: ``oil_temp_C``, ``time_h``, ``run_id`` (a label), ``efficiency_sigma`` (the
  standard uncertainty of the efficiency, a fraction); any other numeric column is kept as
  a further covariate of the residual analysis.

Provenance: ``# key: value`` comment lines above the header, and the sidecar JSON (which
wins on a clash). A sidecar ``sensors`` table gives the rig's torque sensors,
``{"input_torque": {"range_Nm": 10, "accuracy": 0.001}, "output_torque": {...}}``;
with it and an input-torque column each row gets an efficiency uncertainty
sigma = eta sqrt((a1 R1 / T1)^2 + (a2 R2 / T2)^2) (the accuracy taken as one standard
deviation of the reading, a conservative reading of a sensor's accuracy class); without an
input-torque column the input torque is the one the efficiency implies, T2 / (|i| eta).

Bad rows are refused one by one, with the line number and the reason (empty or missing
value, NaN, not a number, efficiency <= 0 or > 1, speed or torque <= 0, efficiency and
torques that disagree); every good row is kept. A further covariate column is lenient: if
any of its cells is text, empty or NaN the column is dropped whole (``notes`` says so), and
no row is refused for it. A bad header (a required column missing, a quantity in a unit
not known, a column twice) refuses the whole file, naming the column; a trailing comma in
the header or the rows is accepted; an ``efficiency_pct`` column whose every value is at
most 1 (fractions) is refused. ``strict=True`` raises on the first bad row instead. Files
are UTF-8 (a byte-order mark is dropped); other encodings are refused in one line. The
delimiter is the comma; a header without a comma but with semicolons or tabs is read with
that delimiter, and then a decimal comma in a number (``28,5``: a spreadsheet's export in
many locales) is read as a decimal point; ``notes`` says both.
:func:`require_distinct` refuses data with too few distinct operating points.
"""
from __future__ import annotations

import csv
import math
import io
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import MeasuredDataError, decode_text
from ...errors import ToothfemError  # noqa: F401 (re-exported)
from .measured_columns import (QUANTITIES, _check_percent_column, _check_row, _columns,
                               clean_rows, comment_lines, _free_columns, header_names, next_row,
                               parse_number,
                               _percent_hint)


@dataclass(frozen=True)
class Rejected:
    """A refused row: its line in the file (1-based, header and comments counted)."""
    line: int
    reason: str

    def __str__(self):
        return f"line {self.line}: {self.reason}"


@dataclass(frozen=True, kw_only=True)
class MeasuredData:
    """Measured operating points, arrays of shape (M,); optional columns None if absent."""
    speed_rpm: np.ndarray
    torque_Nm: np.ndarray                     # output torque
    efficiency: np.ndarray                    # fraction, 0 < eta <= 1
    oil_temp_C: np.ndarray | None = None
    time_h: np.ndarray | None = None
    run_id: np.ndarray | None = None          # labels (str)
    input_torque_Nm: np.ndarray | None = None
    sigma: np.ndarray | None = None           # standard uncertainty of the efficiency
    extra: dict = field(default_factory=dict)  # further numeric covariates, name -> (M,)
    lines: np.ndarray | None = None           # source line of each row
    rejected: tuple = ()                      # Rejected rows
    provenance: dict = field(default_factory=dict)
    source: str = ""
    notes: tuple = ()                         # what the loader dropped, one line each

    def __len__(self):
        return int(self.speed_rpm.size)

    def covariates(self) -> dict:
        """Every covariate in the data; ``run_id`` is a label array, the others numbers.

        Returns
        -------
        dict of str to numpy.ndarray
            Name (with unit) -> (M,) array.
        """
        out = {"input_speed_rpm": self.speed_rpm, "output_torque_Nm": self.torque_Nm}
        for name, arr in (("oil_temp_C", self.oil_temp_C), ("time_h", self.time_h),
                          ("run_id", self.run_id)):
            if arr is not None:
                out[name] = arr
        out.update(self.extra)
        return out

    def subset(self, index) -> MeasuredData:
        """The rows ``index``.

        Parameters
        ----------
        index : array_like
            An index array or boolean mask over the M rows.

        Returns
        -------
        MeasuredData
            Those rows (rejected rows, provenance and notes kept).
        """
        def take(a):
            return None if a is None else np.asarray(a)[index]
        return MeasuredData(speed_rpm=take(self.speed_rpm), torque_Nm=take(self.torque_Nm),
                            efficiency=take(self.efficiency), oil_temp_C=take(self.oil_temp_C),
                            time_h=take(self.time_h), run_id=take(self.run_id),
                            input_torque_Nm=take(self.input_torque_Nm), sigma=take(self.sigma),
                            extra={k: v[index] for k, v in self.extra.items()},
                            lines=take(self.lines), rejected=self.rejected,
                            provenance=dict(self.provenance), source=self.source,
                            notes=self.notes)


def sensor_sigma(eff, t_in, t_out, sensors) -> np.ndarray | None:
    """Standard uncertainty of eta = T2 / (i T1) from the torque sensors' accuracy (a
    fraction of range, taken as one standard deviation): eta sqrt((a1 R1/T1)^2 +
    (a2 R2/T2)^2).

    Parameters
    ----------
    eff : array_like, shape (M,)
        Efficiency [-].
    t_in : array_like, shape (M,) or None
        Input torque [N m].
    t_out : array_like, shape (M,)
        Output torque [N m].
    sensors : dict or None
        The provenance ``sensors`` table: ``input_torque`` and ``output_torque``, each with
        ``range_Nm`` [N m] and ``accuracy`` [-].

    Returns
    -------
    numpy.ndarray or None
        sigma [-], shape (M,); None without both sensors or without input torques.

    Raises
    ------
    MeasuredDataError
        If the sensors table lacks a sensor, its range or accuracy.
    """
    if t_in is None or not sensors:
        return None
    try:
        s1, s2 = (float(sensors[k]["accuracy"]) * float(sensors[k]["range_Nm"])
                  for k in ("input_torque", "output_torque"))
    except (KeyError, TypeError, ValueError):
        raise MeasuredDataError("provenance 'sensors' needs input_torque and output_torque "
                                "tables with range_Nm and accuracy (a fraction of range)") \
            from None
    return np.asarray(eff) * np.hypot(s1 / np.asarray(t_in), s2 / np.asarray(t_out))


def parse_measured(text: str, *, ratio=None, provenance=None, source="<string>",
                   strict=False) -> MeasuredData:
    """Validate CSV text into :class:`MeasuredData` (module docstring for the rules).

    Parameters
    ----------
    text : str
        The CSV, header comments included.
    ratio : float, optional
        The reducer's speed ratio (its magnitude is used), needed when the efficiency comes
        from an input-torque column and used to check one against the other when both are
        given.
    provenance : dict, optional
        A mapping merged over the header comments.
    source : str
        Names the text in messages.
    strict : bool
        Refuse the whole text at the first bad row instead of rejecting the row.

    Returns
    -------
    MeasuredData
        The good rows, with the rejected ones listed.

    Raises
    ------
    MeasuredDataError
        No header, no good row, a missing ratio, or (strict) a bad row.
    """
    lines = text.splitlines()
    prov, start = comment_lines(lines)
    prov.update(provenance or {})
    if start >= len(lines):
        raise MeasuredDataError(f"{source}: no header line (columns with units, e.g. "
                                "input_speed_rpm,output_torque_Nm,efficiency)")
    body = lines[start:]
    del lines                                   # large files: keep one copy of the text
    delimiter = delimiter_of(body[0])
    reader = csv.reader(body, delimiter=delimiter)
    header = header_names(next_row(reader, source, start + 1), source)
    columns = _columns(header, source)
    i_abs = None if ratio is None else abs(float(ratio))
    if "efficiency" not in columns and i_abs is None:
        raise MeasuredDataError(f"{source}: the efficiency comes from input_torque_Nm, which "
                                "needs the reducer ratio (ratio=...)")
    known = set(QUANTITIES) | {"run_id"}
    checked = [k for k in columns if k in QUANTITIES]      # a bad cell refuses the row
    free = [k for k in columns if k not in known]           # further covariates: lenient
    values: dict[str, list[float]] = {k: [] for k in checked}
    cells_free: dict[str, list[str]] = {k: [] for k in free}
    run, rejected, line_no = [], [], []
    decimal_comma = False
    clean = None if delimiter != "," else clean_rows(body, header, columns, checked, free,
                                                      i_abs, start)
    if clean is not None:       # a plain file of good rows: read column by column
        values, cells_free, run, line_no = clean
        body = []
    k = 0
    while clean is None:
        line = start + 2 + k
        cells = next_row(reader, source, line)
        k += 1
        if cells is None:
            break
        if not cells or all(not c.strip() for c in cells):
            continue
        while len(cells) > len(header) and not cells[-1].strip():
            cells = cells[:-1]                  # trailing separators (a trailing comma)
        if delimiter != ",":
            commas = [c.replace(",", ".") for c in cells]
            decimal_comma |= commas != cells
            cells = commas
        reason = None
        if len(cells) != len(header):
            reason = f"has {len(cells)} fields, the header has {len(header)}"
        row = {}
        for key in checked if reason is None else ():
            j, f, o = columns[key]
            try:                    # a finite number: parse_number's value, at once
                v = float(cells[j])
            except ValueError:
                v = math.nan
            if v - v != 0:          # NaN, infinite or not a number: its reason
                v, why = parse_number(cells[j], header[j])
                if why:
                    reason = why
                    break
            row[key] = f * v + o
        if reason is None:
            reason = _check_row(row, i_abs)
        if reason is not None:
            if strict:
                raise MeasuredDataError(f"{source}: line {line}: {reason}")
            rejected.append(Rejected(line, reason))
            continue
        for key in checked:
            values[key].append(row[key])
        for key in free:
            cells_free[key].append(cells[columns[key][0]])
        if "run_id" in columns:
            run.append(cells[columns["run_id"][0]].strip())
        line_no.append(line)
    del body
    if not line_no:
        why = "; ".join(str(r) for r in rejected[:3]) or "no data rows"
        raise MeasuredDataError(f"{source}: no good row ({why})" + _percent_hint(rejected))

    def col(key):
        return None if key not in values else np.array(values[key], float)

    _check_percent_column(header, columns, values, source)
    t_out, t_in = col("output_torque"), col("input_torque")
    eff = col("efficiency")
    if eff is None:
        eff = t_out / (i_abs * t_in)
    sigma = col("efficiency_sigma")
    if sigma is None:
        # without an input-torque column the reading it implies is T2 / (|i| eta)
        implied = t_in if t_in is not None or i_abs is None else t_out / (i_abs * eff)
        sigma = sensor_sigma(eff, implied, t_out, prov.get("sensors"))
    extra, notes = _free_columns(cells_free)
    if delimiter != ",":
        notes = [f"read with {delimiter!r} as the delimiter (the header has no comma)"] + \
            (["decimal commas read as decimal points"] if decimal_comma else []) + list(notes)
    return MeasuredData(speed_rpm=col("input_speed"), torque_Nm=t_out, efficiency=eff,
                        oil_temp_C=col("oil_temp"), time_h=col("time"),
                        run_id=np.array(run, dtype=object) if "run_id" in columns else None,
                        input_torque_Nm=t_in, sigma=sigma, extra=extra,
                        lines=np.array(line_no), rejected=tuple(rejected), provenance=prov,
                        source=source, notes=tuple(notes))


#: The delimiters read besides the comma, when the header has no comma.
OTHER_DELIMITERS = (";", "\t")


def delimiter_of(header_line: str) -> str:
    """The comma, or the first of OTHER_DELIMITERS in a header that has no comma.

    Parameters
    ----------
    header_line : str

    Returns
    -------
    str
        The delimiter.
    """
    if "," not in header_line:
        for d in OTHER_DELIMITERS:
            if d in header_line:
                return d
    return ","


def grid_axes(data: MeasuredData) -> dict:
    """The covariates of the operating point (what the binning grid is cut on, what makes
    two rows distinct points).

    Parameters
    ----------
    data : MeasuredData
        M rows.

    Returns
    -------
    dict of str to numpy.ndarray
        input_speed_rpm [rpm], output_torque_Nm [N m] and, when the data carry it,
        oil_temp_C [deg C]; each (M,).
    """
    axes = {"input_speed_rpm": data.speed_rpm, "output_torque_Nm": data.torque_Nm}
    if data.oil_temp_C is not None:
        axes["oil_temp_C"] = data.oil_temp_C
    return {k: np.asarray(v, float) for k, v in axes.items()}


def distinct_points(data: MeasuredData) -> int:
    """Number of distinct operating points (speed, output torque and, if given, oil
    temperature) among the rows.

    Parameters
    ----------
    data : MeasuredData
        The rows.

    Returns
    -------
    int
        The count.
    """
    cols = list(grid_axes(data).values())
    return int(np.unique(np.column_stack(cols), axis=0).shape[0]) if len(data) else 0


def require_distinct(data: MeasuredData, needed: int, purpose: str, *,
                     rows: int | None = None) -> MeasuredData:
    """``data`` if it has at least ``needed`` distinct operating points (repeated readings of
    one point say nothing about how the efficiency changes with speed, torque or
    temperature).

    Parameters
    ----------
    data : MeasuredData
        The rows.
    needed : int
        Distinct points required.
    purpose : str
        What needs them (for the message).
    rows : int, optional
        The good rows ``data`` was binned from (default: its own rows).

    Returns
    -------
    MeasuredData
        ``data`` itself.

    Raises
    ------
    MeasuredDataError
        One line saying how many it has and what needs more.
    """
    n = distinct_points(data)
    if n < needed:
        rows = len(data) if rows is None else rows
        binned = f" binned onto {len(data)} points" if rows != len(data) else ""
        raise MeasuredDataError(
            f"{data.source or 'measured data'}: {rows} good rows{binned} but only {n} "
            f"distinct operating point{'s' if n != 1 else ''} (speed, torque, oil "
            f"temperature); {purpose} needs at least {needed}")
    return data


def sidecar_path(path) -> Path:
    """The provenance sidecar of a CSV: the same name with ``.json``.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV.

    Returns
    -------
    pathlib.Path
        The sidecar's path.
    """
    return Path(path).with_suffix(".json")


def load_measured(path, *, ratio=None, strict=False) -> MeasuredData:
    """Open a measured-data CSV and its sidecar ``<stem>.json`` (if present).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV (UTF-8).
    ratio : float, optional
        As :func:`parse_measured`.
    strict : bool
        As :func:`parse_measured`.

    Returns
    -------
    MeasuredData
        The good rows.

    Raises
    ------
    MeasuredDataError
        If a file cannot be read or decoded, the sidecar is not a JSON object, or as
        :func:`parse_measured`.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise MeasuredDataError(f"{path}: no such measured-data file") from None
    except OSError as exc:
        raise MeasuredDataError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    text = decode_text(raw, path, MeasuredDataError)
    del raw
    prov = {}
    side = sidecar_path(path)
    if side.is_file():
        try:
            prov = json.loads(decode_text(side.read_bytes(), side, MeasuredDataError))
        except json.JSONDecodeError as exc:
            raise MeasuredDataError(f"{side}: not valid JSON: {exc}") from None
        except OSError as exc:
            raise MeasuredDataError(f"{side}: cannot be read ({exc.strerror or exc})") \
                from None
        if not isinstance(prov, dict):
            raise MeasuredDataError(f"{side}: must hold a JSON object")
    return parse_measured(text, ratio=ratio, provenance=prov, source=str(path), strict=strict)


def from_case(case) -> MeasuredData:
    """The case's ``[[measured]]`` points as :class:`MeasuredData` (no oil temperature).

    Parameters
    ----------
    case : toothfem.case.Case
        With [[measured]] points: speed [rpm], output torque [N m], efficiency [-].

    Returns
    -------
    MeasuredData
        Speed [rpm], output torque [N m] and efficiency [-].

    Raises
    ------
    MeasuredDataError
        If the case has no [[measured]] points.
    """
    pts = case.measured
    if not pts:
        raise MeasuredDataError(f"case {case.name!r} has no [[measured]] points")
    return MeasuredData(speed_rpm=np.array([p.input_speed_rpm for p in pts], float),
                        torque_Nm=np.array([p.output_torque_Nm for p in pts], float),
                        efficiency=np.array([p.efficiency for p in pts], float),
                        lines=np.arange(len(pts)),
                        provenance={"source": "; ".join(dict.fromkeys(
                            p.source for p in pts if p.source))},
                        source=f"case {case.name!r} [[measured]]")


def to_csv(data: MeasuredData) -> str:
    """CSV text of a record (canonical columns; the inverse of :func:`parse_measured`).

    Parameters
    ----------
    data : MeasuredData
        The record.

    Returns
    -------
    str
        The CSV, 10 significant digits.
    """
    cols = {"input_speed_rpm": data.speed_rpm, "output_torque_Nm": data.torque_Nm}
    if data.input_torque_Nm is not None:
        cols["input_torque_Nm"] = data.input_torque_Nm
    cols["efficiency"] = data.efficiency
    for name, arr in (("oil_temp_C", data.oil_temp_C), ("time_h", data.time_h),
                      ("run_id", data.run_id)):
        if arr is not None:
            cols[name] = arr
    cols.update(data.extra)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(list(cols))
    for i in range(len(data)):
        w.writerow([c[i] if isinstance(c[i], str) else f"{float(c[i]):.10g}"
                    for c in cols.values()])
    return buf.getvalue()
