"""Reading TE and hysteresis rig recordings, file by file, each reduced as it is read.

A reducer's TE rig logs an input encoder, an output encoder and a torque meter, in both
directions at a staircase of torques. Two recordings are read here.

**Transmission error** (:func:`read_te_recordings`), one of two file shapes:

(a) forward and backward side by side, one file per operating condition:
    ``output_angle_deg, te_forward_arcsec, te_backward_arcsec`` (an empty TE cell: that
    direction's sweep is shorter);
(b) one long table with a direction column: ``output_angle_deg, te_arcsec, direction``
    (``+1``/``-1`` or ``forward``/``backward``, :data:`.columns.DIRECTION_WORDS`); several
    conditions and sweeps may follow one another in it.

**Hysteresis**: the torque staircase with the input held (:func:`.hysteresis.read_hysteresis`,
on this module's file reading).

The unit is the column name's suffix: angles and TE in ``_deg``, ``_arcmin``, ``_arcsec``
or ``_rad``; the output torque in ``_Nm`` (``_Nmm``, ``_kNm``), the input speed in ``_rpm``
(``_rad_s``, ``_rps``), the oil temperature in ``_C`` (``_K``, ``_F``). Inside, angles are
rad, torques N m, speeds rad/s, temperatures deg C (as the efficiency loader). The
operating condition (torque, speed, oil temperature) comes from columns, from ``# key:
value`` comment lines above the header (``# output_torque_Nm: 100``; the other comments are
the provenance), or from the file's name through a stated pattern
(``"te_{output_torque_Nm}Nm_{input_speed_rpm}rpm.csv"``, :func:`.columns.name_pattern`); a
value given twice must agree (:data:`.columns.CONDITION_RTOL`).

Files are UTF-8 (a byte-order mark dropped; anything else refused naming the byte's line and
column); the delimiter is the comma, or a semicolon or tab when the header has no comma,
and then a decimal comma is read as a point (as :mod:`..measured`). Unknown columns are
skipped (a note says so).

**Streaming.** Each file is read line by line (the csv module over the open file); the rows
of one sweep (consecutive rows of one direction and one condition: a *run*) are kept as two
float arrays only until the run ends, then reduced to a :class:`Run`: its mean TE (over the
whole output revolutions of the spectrum's uniform grid, where whole orders integrate out; a
run shorter than a revolution: the mean of its angle bins), its revolution-averaged TE in
:data:`ANGLE_BINS` bins, and its spectrum up to ``max_order`` (:mod:`.spectrum`). No raw row
outlives its file, so hundreds of files of 1e5 rows take the memory of their reductions
(tens of kB per run). A progress bar runs over the files (:func:`toothfem.bars.bar`).

**Refusals.** A bad file is refused in one line naming the file, and the line and column
where it applies: no header, a required column missing, a column in an unknown unit, a
column twice, a cell that is not a number (or NaN, or empty where a value is required), a
direction word not known, a row with another number of fields than the header, a file name
that does not match the pattern, a condition that disagrees between its sources, bytes
that are not UTF-8. The other files are still read; :attr:`TeRecordings.refused` lists the
refusals.
"""
from __future__ import annotations

import csv
import hashlib
import itertools
import math
from array import array
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....bars import bar
from ....errors import MeasuredDataError, decode_text
from ....units import ARCSEC
from ..measured import delimiter_of
from ..measured_columns import comment_lines, header_names, next_row
from .columns import (CONDITIONS, DIRECTION_WORDS, Condition, close, column,
                      condition_values, field_of, number, values_from_name)
from .columns import name_pattern as compile_pattern
from .spectrum import DEFAULT_MAX_ORDER, WINDOWS, Spectrum, te_spectrum
from .windows import Windows, windows_of
from .plausibility import angle_unit_note

#: Bins of the revolution-averaged TE (0.1 deg of output angle). A bin's mean attenuates a
#: ripple of order q by sin(x)/x, x = pi q / ANGLE_BINS: 0.2 % at order 121, 28 % at 1560
#: (the spectrum is computed from the samples, not the bins). 3600 float32 = 14 kB a run.
ANGLE_BINS = 3600
#: A run of fewer samples is dropped with a note (a logger's stray row at a change of
#: condition or direction; no sweep of a TE test is this short).
MIN_RUN_SAMPLES = 16
#: What a TE file's required columns are called in a refusal.
ANGLE_UNITS_TEXT = "deg, arcmin, arcsec or rad"


@dataclass(frozen=True)
class Refusal:
    """A refused file and the one-line reason (which names the file)."""
    source: str
    reason: str

    def __str__(self):
        return self.reason


@dataclass(frozen=True, kw_only=True)
class Run:
    """One sweep (one direction at one condition) of one file, reduced."""
    source: str
    first_line: int                 # the run's first data line in its file
    direction: int                  # +1 forward, -1 backward
    condition: Condition            # the mean of its rows' values
    samples: int
    revolutions: float              # output revolutions that hold data (the windows'
                                    # spans summed: coverage, not the span)
    mean_te_rad: float              # mean over the whole revolutions of the spectrum's
                                    # uniform grid; below one revolution the mean of the
                                    # angle bins (each angle weighs the same)
    binned_te_rad: np.ndarray       # (ANGLE_BINS,) float32 mean TE per bin of the output
                                    # angle modulo a turn; NaN where no sample fell
    spectrum: Spectrum | None       # None below one whole revolution (``note`` says)
    windows: Windows | None = None  # where it holds data (:mod:`.windows`)
    note: str = ""


@dataclass(frozen=True, kw_only=True)
class TeRecordings:
    """The runs of every file read, and the files refused."""
    runs: tuple                     # Run
    files: tuple                    # the sources read
    refused: tuple                  # Refusal
    notes: tuple = ()               # one line each, naming the file
    angle_bins: int = ANGLE_BINS
    window: str = "hann"
    max_order: float = DEFAULT_MAX_ORDER

    @property
    def samples(self) -> int:
        """Samples in all runs (both directions counted)."""
        return int(sum(r.samples for r in self.runs))


class _Table:
    """A CSV file opened for streaming: its provenance comments, header and delimiter read;
    :meth:`rows` yields the rest."""

    def __init__(self, path):
        self.path = Path(path)
        self.source = str(path)
        try:
            self._file = open(self.path, encoding="utf-8-sig", newline="")  # noqa: SIM115  # streamed by rows(), shut by close()
        except FileNotFoundError:
            raise MeasuredDataError(f"{self.source}: no such file") from None
        except OSError as exc:
            raise MeasuredDataError(f"{self.source}: cannot be read ({exc.strerror or exc})") \
                from None
        try:
            self._open()
        except BaseException:
            self._file.close()
            raise

    def _open(self):
        self._lines = self._decoded()
        comments, n, head = [], 0, None
        for line in self._lines:
            n += 1
            text = line.strip()
            if not text or text.startswith("#"):
                comments.append(line)
                continue
            head = line
            break
        if head is None:
            raise MeasuredDataError(f"{self.source}: no header line (columns with units, "
                                    "e.g. output_angle_deg,te_arcsec,direction)")
        self.provenance, _ = comment_lines(comments)
        self.delimiter = delimiter_of(head)
        self._base = n - 1
        self._reader = csv.reader(itertools.chain([head], self._lines),
                                  delimiter=self.delimiter)
        self.header = header_names(next_row(self._reader, self.source, n), self.source)

    def _decoded(self):
        """The file's lines; bytes that are not UTF-8 refuse it naming their place."""
        try:
            yield from self._file
        except UnicodeDecodeError:
            decode_text(self.path.read_bytes(), self.source, MeasuredDataError)
            raise MeasuredDataError(f"{self.source}: not UTF-8 text") from None

    def rows(self):
        """(line, cells) of each data row: blank rows skipped, trailing empty fields (a
        trailing delimiter) dropped, a decimal comma read as a point where the delimiter is
        not the comma; a row of another width than the header refuses the file."""
        width, comma, reader, base = len(self.header), self.delimiter != ",", self._reader, \
            self._base
        while True:
            cells = next_row(reader, self.source, base + reader.line_num + 1)
            if cells is None:
                return
            if len(cells) < 2 and not "".join(cells).strip():
                continue
            line = base + reader.line_num
            while len(cells) > width and not cells[-1].strip():
                cells.pop()
            if len(cells) != width:
                raise MeasuredDataError(f"{self.source}: line {line} has {len(cells)} "
                                        f"fields, the header has {width}")
            if comma:
                cells = [c.replace(",", ".") for c in cells]
            yield line, cells

    def close(self):
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _columns(table: _Table) -> tuple:
    """({quantity: (index, factor, offset, name)}, ignored names); refuses an unknown unit
    or a quantity twice, naming the column."""
    cols: dict[str, tuple[int, float | None, float | None, str]] = {}
    ignored: list[str] = []
    for j, name in enumerate(table.header):
        try:
            q, f, o = column(name)
        except MeasuredDataError as exc:
            raise MeasuredDataError(f"{table.source}: {exc}") from None
        if q is None:
            ignored.append(name)
            continue
        if q in cols:
            raise MeasuredDataError(f"{table.source}: {q} appears twice in the header "
                                    f"({cols[q][3]!r} and {name!r})")
        cols[q] = (j, f, o, name)
    return cols, ignored


def _file_values(table: _Table, pattern) -> dict:
    """The condition values (and direction) of the whole file: header comments and the
    file name, which must agree where both give one."""
    src = table.source
    from_comments = condition_values(table.provenance, f"{src}: header comment")
    from_name = values_from_name(pattern, table.path.name, src)
    for key in from_comments.keys() & from_name.keys():
        a, b = from_name[key], from_comments[key]
        same = a == b if key == "direction" else close(key, a, b)
        if not same:
            raise MeasuredDataError(f"{src}: {key} = {a:g} in the file name but {b:g} in a "
                                    "header comment")
    return {**from_comments, **from_name}


def _condition_columns(cols: dict) -> list:
    """[(index, factor, offset, name, field)] of the condition columns."""
    return [(cols[q][0], cols[q][1], cols[q][2], cols[q][3], field_of(q))
            for q in CONDITIONS if q in cols]


def _missing(source, what, header) -> MeasuredDataError:
    return MeasuredDataError(f"{source}: missing column {what}; have {header}")


class _RunBuilder:
    """The samples of the run being read (two float arrays) and its conditions' sums."""
    __slots__ = ("line", "first", "angle", "te", "sums")

    def __init__(self, line, cond):
        self.line, self.first = line, cond
        self.angle, self.te = array("d"), array("d")
        self.sums = [0.0] * len(cond)

    def add(self, angle, te, cond):
        self.angle.append(angle)
        self.te.append(te)
        for k, v in enumerate(cond):
            if v is not None:
                self.sums[k] += v


def _reduce(b: _RunBuilder, direction, fields, source, angle_bins, max_order, window):
    """The :class:`Run` of a finished builder (None and a note below MIN_RUN_SAMPLES)."""
    n = len(b.angle)
    if n < MIN_RUN_SAMPLES:
        return None, (f"{source}: line {b.line}: a run of {n} samples (fewer than "
                      f"{MIN_RUN_SAMPLES}) dropped")
    angle = np.frombuffer(b.angle, dtype=float)
    te = np.frombuffer(b.te, dtype=float)
    two_pi = 2.0 * math.pi
    idx = np.minimum((np.mod(angle, two_pi) * (angle_bins / two_pi)).astype(np.intp),
                     angle_bins - 1)
    counts = np.bincount(idx, minlength=angle_bins)
    sums = np.bincount(idx, te, minlength=angle_bins)
    curve = np.full(angle_bins, np.nan)
    hit = counts > 0
    curve[hit] = sums[hit] / counts[hit]
    win = windows_of(angle, te)
    turns = win.coverage_revolutions
    note = ""
    if win.count > 1:   # a spectrum over the turn would interpolate across the gaps
        spec, note = None, (f"{source}: line {b.line}: {win.count} windows holding "
                            f"{win.coverage_revolutions:.3g} of the "
                            f"{win.span_rad / two_pi:.3g} revolutions they span: no "
                            "spectrum over the turn (a window resolves orders from "
                            f"{win.smallest_order:.0f} per revolution up)")
    else:
        try:
            spec = te_spectrum(angle, te, max_order=max_order, window=window)
        except MeasuredDataError as exc:
            spec, note = None, f"{source}: line {b.line}: no spectrum: {exc}"
    cond = Condition(**{f: (None if b.first[k] is None else b.sums[k] / n)
                        for k, f in enumerate(fields)})
    return Run(source=source, first_line=b.line, direction=direction, condition=cond,
               samples=n, revolutions=turns,
               mean_te_rad=float(np.mean(curve[hit])) if spec is None else spec.mean_arcsec
               * ARCSEC,
               binned_te_rad=curve.astype(np.float32), spectrum=spec, windows=win,
               note=note), note


def _cell(cells, j, name, factor, offset, source, line):
    """A required cell's value; refuses the file naming line and column."""
    try:
        v = float(cells[j])
    except ValueError:
        v = math.nan
    if math.isfinite(v):
        return factor * v + offset
    try:
        return number(cells[j], name, factor, offset)
    except MeasuredDataError as exc:
        raise MeasuredDataError(f"{source}: line {line}: {exc}") from None


def read_te_file(path, *, name_pattern=None, angle_bins: int = ANGLE_BINS,
                 max_order: float = DEFAULT_MAX_ORDER, window: str = "hann") -> tuple:
    """One TE file's runs, each reduced as it ends (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV (shape (a) or (b)).
    name_pattern : str or re.Pattern, optional
        The file-name pattern (:func:`.columns.name_pattern`).
    angle_bins : int
        Bins of the revolution-averaged TE.
    max_order : float
        Orders kept of each run's spectrum.
    window : {"hann", "rect"}
        The spectrum's window.

    Returns
    -------
    runs : tuple of Run
        In the order they end in the file.
    notes : tuple of str
        Skipped columns, dropped short runs, runs without a spectrum; each names the file.

    Raises
    ------
    MeasuredDataError
        One line naming the file (and the line and column) for any refusal.
    """
    pattern = _pattern(name_pattern)
    with _Table(path) as table:
        src, header = table.source, table.header
        cols, ignored = _columns(table)
        fixed = _file_values(table, pattern)
        if "output_angle" not in cols:
            raise _missing(src, f"output_angle_<unit> ({ANGLE_UNITS_TEXT})", header)
        both = [q for q in ("te_forward", "te_backward") if q in cols]
        if both and "te" in cols:
            raise MeasuredDataError(f"{src}: columns {cols['te'][3]!r} and "
                                    f"{cols[both[0]][3]!r}: give te with a direction, or "
                                    "te_forward and te_backward, not both")
        if len(both) == 1:
            other = ({"te_forward", "te_backward"} - set(both)).pop()
            raise _missing(src, f"{other}_<unit> (beside {cols[both[0]][3]!r})", header)
        if not both and "te" not in cols:
            raise _missing(src, f"te_<unit> ({ANGLE_UNITS_TEXT}), or te_forward_<unit> and "
                           "te_backward_<unit>", header)
        if both and "direction" in cols:
            raise MeasuredDataError(f"{src}: column {cols['direction'][3]!r}: the te_forward "
                                    "and te_backward columns give the direction already")
        if not both and "direction" not in cols and "direction" not in fixed:
            raise _missing(src, "direction (+1/-1 or forward/backward) beside "
                           f"{cols['te'][3]!r}, or a direction in the file name or a "
                           "'# direction: forward' comment", header)
        notes = [f"{src}: column {name!r} not used" for name in ignored]
        runs = _read_te_rows(table, cols, fixed, bool(both), angle_bins, max_order, window,
                             notes)
    return tuple(runs), tuple(notes) + angle_unit_note(src, cols["output_angle"], runs)


def _read_te_rows(table, cols, fixed, sides, angle_bins, max_order, window, notes):
    """The row loop of :func:`read_te_file`: rows into runs, runs reduced as they end."""
    src = table.source
    fields = [CONDITIONS[q][2] for q in CONDITIONS]
    cond_cols = _condition_columns(cols)
    by_column = {c[4] for c in cond_cols}
    constant = tuple(fixed.get(f) for f in fields)
    ja, fa, oa, na = cols["output_angle"]
    if sides:
        te_cols = [(cols[q][0], cols[q][1], cols[q][3], d)
                   for q, d in (("te_forward", 1), ("te_backward", -1))]
    else:
        jt, ft, _, nt = cols["te"]
        jd, nd = (cols["direction"][0], cols["direction"][3]) if "direction" in cols \
            else (None, None)
    current: dict = {}
    runs: list = []

    def finish(d):
        run, note = _reduce(current.pop(d), d, fields, src, angle_bins, max_order, window)
        if note:
            notes.append(note)
        if run is not None:
            runs.append(run)

    last = None
    for line, cells in table.rows():
        if cond_cols:
            cells_cond: list = list(constant)
            for j, f, o, name, fld in cond_cols:
                v = _cell(cells, j, name, f, o, src, line)
                k = fields.index(fld)
                if cells_cond[k] is not None and not close(fld, v, cells_cond[k]):
                    raise MeasuredDataError(
                        f"{src}: line {line}: column {name!r} = {cells[j].strip()} disagrees "
                        f"with {fld} = {fixed[fld]:g} from the file name or a comment")
                cells_cond[k] = v
            cond = tuple(cells_cond)
        else:
            cond = constant
        angle = _cell(cells, ja, na, fa, oa, src, line)
        if sides:
            samples = []
            for j, f, name, d in te_cols:
                if cells[j].strip():
                    samples.append((d, _cell(cells, j, name, f, 0.0, src, line)))
        else:
            if jd is None:
                way = fixed["direction"]
            else:
                way = DIRECTION_WORDS.get(cells[jd].strip().lower())
                if way is None:
                    raise MeasuredDataError(
                        f"{src}: line {line}: column {nd!r} = {cells[jd].strip()!r} is not a "
                        "direction (+1/-1, forward/backward)")
            samples = [(way, _cell(cells, jt, nt, ft, 0.0, src, line))]
        if cond is not last and by_column and current:
            first = next(iter(current.values())).first
            if not all(a is None or close(fld, a, b) for fld, a, b in zip(fields, first, cond)
                       if fld in by_column):
                for d in list(current):
                    finish(d)
        last = cond
        for d, te in samples:
            if not sides and current and d not in current:
                for other in list(current):
                    finish(other)
            b = current.get(d)
            if b is None:
                b = current[d] = _RunBuilder(line, cond)
            b.add(angle, te, cond)
    for d in list(current):
        finish(d)
    if not runs:
        raise MeasuredDataError(f"{src}: no run of {MIN_RUN_SAMPLES} samples or more (no "
                                "data rows, or only stray ones)")
    return runs


def _pattern(name_pattern):
    """A compiled pattern from a string (None stays None)."""
    if name_pattern is None or hasattr(name_pattern, "fullmatch"):
        return name_pattern
    return compile_pattern(name_pattern)


def recording_paths(paths) -> list:
    """The files to read.

    Parameters
    ----------
    paths : str, pathlib.Path or iterable of them
        Folders (each its ``*.csv`` files, sorted by name) and files, in the order given.

    Returns
    -------
    list of pathlib.Path
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    out = []
    for p in map(Path, paths):
        out += sorted(p.glob("*.csv")) if p.is_dir() else [p]
    return out


def each_file(paths, read, *, desc: str, progress: bool = True) -> tuple:
    """``read(path)`` of every file under a progress bar; a refusal is kept and the next
    file read.

    Parameters
    ----------
    paths : str, pathlib.Path or iterable
        As :func:`recording_paths`.
    read : callable
        path -> result; raises MeasuredDataError to refuse the file.
    desc : str
        The bar's label.
    progress : bool
        Show the bar (on a terminal only, :func:`toothfem.bars.bar`).

    Returns
    -------
    results : list
        (path, result) of each file read.
    refused : list of Refusal
        One line each, naming the file; a file with the same bytes as one already read is
        refused too (given twice, or copied: it would weigh double and sit on both sides of
        the held-out split).
    """
    results, refused = [], []
    files = recording_paths(paths)
    seen: dict[str, Path] = {}
    for path in bar(files, enabled=progress, desc=desc, unit="file"):
        try:
            digest = _digest(path)
        except OSError:
            digest = ""                     # read() says why, naming the file
        if digest and digest in seen:       # the same recording twice would weigh double
            refused.append(Refusal(str(path), f"{path}: the same bytes as {seen[digest]}: "
                                              "read once"))
            continue
        seen.setdefault(digest, path)
        try:
            results.append((path, read(path)))
        except MeasuredDataError as exc:
            refused.append(Refusal(str(path), _one_line(exc, path)))
    return results, refused


def _digest(path) -> str:
    """The file's SHA-256, read in 1 MiB pieces (a recording is never held whole)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for piece in iter(lambda: f.read(1 << 20), b""):
            h.update(piece)
    return h.hexdigest()


def _one_line(exc, path) -> str:
    """The message on one line, beginning with the file."""
    text = " ".join(str(exc).split())
    return text if text.startswith(str(path)) else f"{path}: {text}"


def read_te_recordings(paths, *, name_pattern=None, angle_bins: int = ANGLE_BINS,
                       max_order: float = DEFAULT_MAX_ORDER, window: str = "hann",
                       progress: bool = True) -> TeRecordings:
    """Every TE file, each reduced to its runs as it is read (module docstring).

    Parameters
    ----------
    paths : str, pathlib.Path or iterable
        A folder (its ``*.csv``), a file, or files (:func:`recording_paths`).
    name_pattern : str, optional
        The file-name pattern of the conditions (:func:`.columns.name_pattern`).
    angle_bins : int
        Bins of the revolution-averaged TE (:data:`ANGLE_BINS`).
    max_order : float
        Orders kept of each run's spectrum.
    window : {"hann", "rect"}
        The spectrum's window (:data:`.spectrum.WINDOWS`).
    progress : bool
        A progress bar over the files (on a terminal).

    Returns
    -------
    TeRecordings
        The runs of the files read, the refusals, the notes.

    Raises
    ------
    MeasuredDataError
        For a bad pattern, window or bin count (nothing is read then).
    """
    pattern = _pattern(name_pattern)
    if window not in WINDOWS:
        raise MeasuredDataError(f"window = {window!r} is not one of {sorted(WINDOWS)}")
    if isinstance(angle_bins, bool) or int(angle_bins) != angle_bins or angle_bins < 1:
        raise MeasuredDataError(f"angle_bins = {angle_bins!r} must be a positive integer")
    results, refused = each_file(
        paths, lambda p: read_te_file(p, name_pattern=pattern, angle_bins=int(angle_bins),
                                      max_order=max_order, window=window),
        desc="TE recordings", progress=progress)
    runs, notes = [], []
    for _, (file_runs, file_notes) in results:
        runs.extend(file_runs)
        notes.extend(file_notes)
    return TeRecordings(runs=tuple(runs), files=tuple(str(p) for p, _ in results),
                        refused=tuple(refused), notes=tuple(notes),
                        angle_bins=int(angle_bins), window=window, max_order=float(max_order))
