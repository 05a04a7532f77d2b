"""The hysteresis staircase recording: read (:func:`read_hysteresis`) and its model-free
catalogue figures (:func:`hysteresis_figures`; no reducer model involved).

**The recording** (:func:`read_hysteresis`): the torque staircase with the input held,
``output_torque_Nm, twist_arcmin`` and optionally ``direction`` or ``branch`` (+1 where the
torque rises, -1 where it falls; without it the branches are found from the torque). The
file is read as :mod:`.recordings` reads TE files (units from the column names, the
condition from columns, comments or the file name, one-line refusals).

**Hysteresis** (:func:`hysteresis_figures`, from a :class:`HysteresisRecording`
and the rated torque), by the definitions of :mod:`toothfem.fem.datasheet.sheet` so that the
measured and the modelled figures compare (its constants are imported, not copied):

- the branches: +1 where the torque rises, -1 where it falls (a ``direction``/``branch``
  column, else the torque's reversals beyond :data:`BRANCH_DEADBAND_FRACTION` of the rated
  torque); the first branch, from rest to the first reversal (the virgin curve), is left
  out; each branch is cut at zero torque into its two flanks, the samples within
  :data:`ZERO_BAND_FRACTION` of zero belonging to the flank the branch comes from (the
  rising branch at zero is still on the negative flank, the falling one on the positive);
- each flank of each branch is binned on the torque (:data:`TORQUE_BIN_FRACTION`; mean
  torque and mean twist per bin) and read at a torque by linear interpolation
  (extrapolation up to :data:`EXTRAPOLATION_FRACTION` beyond its last bin, else the figure
  is NaN with a note);
- torsional rigidity [N m/arcmin]: (T100 - T50) / (theta(T100) - theta(T50)) on the
  loading branch (rising at positive torque, falling at negative), T50 and T100 from
  ``sheet.RIGIDITY_FRACTIONS`` of the rated torque; both directions and their mean;
- lost motion [arcmin]: the twist between the midpoints of the loop's width (the mean of
  the rising and falling branch) at +3 % and at -3 % (``sheet.LOST_MOTION_FRACTION``);
- hysteresis loss [arcmin]: the loop's width at zero torque, the falling branch (from +T)
  less the rising branch (from -T);
- backlash [arcmin]: the elastic curve's jump at zero torque, theta(0 from +) - theta(0 from
  -). A recording does not hold the elastic curve apart from the friction; its estimate is
  the loop's midline (a friction of one magnitude on both branches shifts them equally up
  and down), extrapolated to zero from each side by a straight line through the midline
  between the zero band and :data:`BACKLASH_FIT_FRACTION` of the rated torque. Where the
  contacts close progressively near zero the line is an estimate; the other three figures
  are the definitions themselves.

Twists are differences within one file, so a file's zero offset does not enter them.
"""
from __future__ import annotations

import math
from array import array
from dataclasses import dataclass, field

import numpy as np

from ....errors import MeasuredDataError, check_range
from ....fem.datasheet.sheet import LOST_MOTION_FRACTION, RIGIDITY_FRACTIONS
from .columns import ANGLE_UNITS, DIRECTION_WORDS, Condition, close
from .recordings import (ANGLE_UNITS_TEXT, _cell, _columns, _condition_columns, _file_values,
                         _missing, _pattern, _Table, each_file)

ARCMIN = ANGLE_UNITS["arcmin"]

#: The torque must move back by this fraction of the rated torque from its last extreme
#: for a reversal (a new branch): above a torque meter's noise (0.1-0.2 % of its range),
#: below the smallest step of a catalogue staircase (3 %).
BRANCH_DEADBAND_FRACTION = 0.01
#: Bin width on the torque, a fraction of the rated torque: the samples of one staircase
#: step fall in one or two bins; a continuous ramp is averaged over 0.5 %.
TORQUE_BIN_FRACTION = 0.005
#: Samples within this fraction of the rated torque of zero are on the flank their branch
#: comes from (a zero step reads the meter's zero noise, of either sign); below the
#: lost-motion torque (3 %), which must lie outside it.
ZERO_BAND_FRACTION = 0.01
#: The midline is extrapolated to zero (backlash) from the bins up to this fraction of the
#: rated torque: the lost-motion point (3 %) and the next steps of a catalogue staircase,
#: near enough to zero for a straight line.
BACKLASH_FIT_FRACTION = 0.10
#: A branch is read up to this fraction of the rated torque beyond its last bin (the top
#: step's mean torque reads a little under the set torque), by its end bins' line.
EXTRAPOLATION_FRACTION = 0.02


@dataclass(frozen=True, kw_only=True)
class HysteresisRecording:
    """A hysteresis (torque staircase) recording: output twist against output torque."""
    source: str
    torque_Nm: np.ndarray           # (N,) applied output torque
    twist_rad: np.ndarray           # (N,) output twist, input held
    branch: np.ndarray | None       # (N,) +1 rising, -1 falling, from the file; None: not
                                    # given (found from the torque)
    lines: np.ndarray               # (N,) each sample's line in the file
    condition: Condition = Condition()
    provenance: dict = field(default_factory=dict)
    notes: tuple = ()

    def __len__(self):
        return int(self.torque_Nm.size)


def read_hysteresis(path, *, name_pattern=None) -> HysteresisRecording:
    """A hysteresis recording: ``output_torque_<unit>``, ``twist_<unit>`` and optionally a
    ``direction`` or ``branch`` column (+1 rising torque, -1 falling).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV.
    name_pattern : str or re.Pattern, optional
        File-name pattern of its condition (speed, oil temperature; the torque is the
        column's).

    Returns
    -------
    HysteresisRecording
        Torque [N m] and twist [rad] in file order.

    Raises
    ------
    MeasuredDataError
        One line naming the file (and the line and column).
    """
    pattern = _pattern(name_pattern)
    with _Table(path) as table:
        src, header = table.source, table.header
        cols, ignored = _columns(table)
        fixed = _file_values(table, pattern)
        for q in ("output_torque", "twist"):
            if q not in cols:
                unit = "Nm" if q == "output_torque" else f"<unit> ({ANGLE_UNITS_TEXT})"
                raise _missing(src, f"{q}_{unit}", header)
        jt, ft, ot, nt = cols["output_torque"]
        jw, fw, _, nw = cols["twist"]
        jd, nd = (cols["direction"][0], cols["direction"][3]) if "direction" in cols \
            else (None, None)
        others = [c for c in _condition_columns(cols) if c[4] != "output_torque_Nm"]
        torque, twist, branch, lines = array("d"), array("d"), array("b"), array("l")
        sums = {c[4]: 0.0 for c in others}
        for line, cells in table.rows():
            torque.append(_cell(cells, jt, nt, ft, ot, src, line))
            twist.append(_cell(cells, jw, nw, fw, 0.0, src, line))
            lines.append(line)
            for j, f, o, name, fld in others:
                sums[fld] += _cell(cells, j, name, f, o, src, line)
            if jd is not None:
                d = DIRECTION_WORDS.get(cells[jd].strip().lower())
                if d is None:
                    raise MeasuredDataError(
                        f"{src}: line {line}: column {nd!r} = {cells[jd].strip()!r} is not a "
                        "branch (+1 rising torque, -1 falling)")
                branch.append(d)
    n = len(torque)
    if n == 0:
        raise MeasuredDataError(f"{src}: no data rows")
    values = {k: v for k, v in fixed.items() if k not in ("direction", "output_torque_Nm")}
    for fld, s in sums.items():
        if fld in values and not close(fld, s / n, values[fld]):
            raise MeasuredDataError(f"{src}: {fld} = {s / n:g} (the column's mean) disagrees "
                                    f"with {values[fld]:g} from the file name or a comment")
        values[fld] = s / n
    return HysteresisRecording(
        source=src, torque_Nm=np.frombuffer(torque, dtype=float).copy(),
        twist_rad=np.frombuffer(twist, dtype=float).copy(),
        branch=np.frombuffer(branch, dtype=np.int8).astype(int) if jd is not None else None,
        lines=np.asarray(lines, dtype=int), condition=Condition(**values),
        provenance=dict(table.provenance),
        notes=tuple(f"{src}: column {name!r} not used" for name in ignored))


@dataclass(frozen=True, kw_only=True)
class BranchCurve:
    """One flank of one branch of the loop, binned on the torque."""
    branch: int                     # +1 rising torque, -1 falling
    flank: int                      # +1 positive torque side, -1 negative
    torque_Nm: np.ndarray           # (B,) mean torque of each bin, rising
    twist_arcmin: np.ndarray        # (B,) mean twist of each bin
    samples: np.ndarray             # (B,) samples in each bin


@dataclass(frozen=True, kw_only=True)
class HysteresisFigures:
    """The catalogue figures of one hysteresis recording (module docstring)."""
    source: str
    rated_torque_Nm: float
    rigidity_Nm_per_arcmin: float
    rigidity_by_direction_Nm_per_arcmin: tuple  # (positive, negative)
    lost_motion_arcmin: float
    hysteresis_loss_arcmin: float
    backlash_arcmin: float
    window: dict                    # torque_Nm (-3 %, 0, +3 %), rising_arcmin and
                                    # falling_arcmin there (as the datasheet's window)
    curves: tuple                   # BranchCurve, four at most
    torque_range_Nm: tuple          # (min, max) of the recording
    condition: Condition = Condition()
    notes: tuple = ()

    def summary(self) -> dict:
        """The figures under the datasheet's summary keys.

        Returns
        -------
        dict
            ``torsional_rigidity_Nm_per_arcmin`` (and ``_positive_``/``_negative_``),
            ``lost_motion_arcmin``, ``backlash_arcmin``, ``hysteresis_loss_arcmin``,
            ``rated_torque_Nm``, ``source`` and ``notes``.
        """
        pos, neg = self.rigidity_by_direction_Nm_per_arcmin
        return {"source": self.source, "rated_torque_Nm": self.rated_torque_Nm,
                "torsional_rigidity_Nm_per_arcmin": self.rigidity_Nm_per_arcmin,
                "torsional_rigidity_positive_Nm_per_arcmin": pos,
                "torsional_rigidity_negative_Nm_per_arcmin": neg,
                "lost_motion_arcmin": self.lost_motion_arcmin,
                "backlash_arcmin": self.backlash_arcmin,
                "hysteresis_loss_arcmin": self.hysteresis_loss_arcmin,
                "notes": list(self.notes)}


@dataclass(frozen=True, kw_only=True)
class HysteresisSet:
    """The figures of several hysteresis files, and the files refused."""
    figures: tuple                  # HysteresisFigures, in file order
    refused: tuple = ()             # recordings.Refusal
    notes: tuple = ()

    def mean(self) -> dict:
        """The mean of each figure over the files that have it.

        Returns
        -------
        dict
            The :meth:`HysteresisFigures.summary` keys of the figures -> mean (NaN where
            no file has the figure).
        """
        keys = ("torsional_rigidity_Nm_per_arcmin", "torsional_rigidity_positive_Nm_per_arcmin",
                "torsional_rigidity_negative_Nm_per_arcmin", "lost_motion_arcmin",
                "backlash_arcmin", "hysteresis_loss_arcmin")
        out = {}
        for k in keys:
            v = np.array([f.summary()[k] for f in self.figures], float)
            v = v[np.isfinite(v)]
            out[k] = float(v.mean()) if v.size else math.nan
        return out


def loop_branches(torque_Nm, deadband_Nm: float) -> np.ndarray:
    """The branch of each sample from the torque alone: +1 while it rises, -1 while it
    falls; a reversal once it has moved back from its last extreme by more than the
    deadband (noise within a step does not reverse).

    Parameters
    ----------
    torque_Nm : array_like, shape (N,)
        In recording order [N m].
    deadband_Nm : float
        [N m], > 0.

    Returns
    -------
    numpy.ndarray of int, shape (N,)
        The samples before the torque first moves by the deadband take the first
        branch's sign.
    """
    t = np.asarray(torque_Nm, float)
    out = np.zeros(t.size, dtype=int)
    state, ref = 0, t[0] if t.size else 0.0
    for i, ti in enumerate(t.tolist()):
        if state == 0:
            if ti >= ref + deadband_Nm:
                state, ref = 1, ti
            elif ti <= ref - deadband_Nm:
                state, ref = -1, ti
        elif state > 0:
            if ti > ref:
                ref = ti
            elif ti < ref - deadband_Nm:
                state, ref = -1, ti
        else:
            if ti < ref:
                ref = ti
            elif ti > ref + deadband_Nm:
                state, ref = 1, ti
        out[i] = state
    first = out[out != 0]
    out[out == 0] = first[0] if first.size else 1
    return out


def _binned(torque, twist, bin_Nm, branch, flank) -> BranchCurve:
    """Mean torque and twist per bin of width bin_Nm centred on its multiples."""
    if torque.size == 0:
        empty = np.zeros(0)
        return BranchCurve(branch=branch, flank=flank, torque_Nm=empty, twist_arcmin=empty,
                           samples=np.zeros(0, int))
    idx = np.rint(torque / bin_Nm).astype(np.int64)
    idx -= idx.min()
    n = np.bincount(idx)
    hit = n > 0
    t = np.bincount(idx, torque)[hit] / n[hit]
    w = np.bincount(idx, twist)[hit] / n[hit]
    order = np.argsort(t, kind="stable")
    return BranchCurve(branch=branch, flank=flank, torque_Nm=t[order],
                       twist_arcmin=w[order] / ARCMIN, samples=n[hit][order])


_BRANCH = {1: "rising", -1: "falling"}
_FLANK = {1: "positive", -1: "negative"}


def _at(curve: BranchCurve, torque: float, reach: float, what: str, notes: list) -> float:
    """The curve's twist [arcmin] at a torque: interpolated, or extrapolated by its end
    bins' line up to ``reach`` [N m] beyond them; else NaN and a note naming ``what``."""
    t, w = curve.torque_Nm, curve.twist_arcmin
    where = f"the {_BRANCH[curve.branch]} branch's {_FLANK[curve.flank]} flank"
    if t.size == 0:
        notes.append(f"{what}: no sample on {where}")
        return math.nan
    if t[0] <= torque <= t[-1]:
        return float(np.interp(torque, t, w))
    end = 0 if torque < t[0] else -1
    if abs(torque - t[end]) > reach:
        notes.append(f"{what}: needs {torque:.4g} N m on {where}, which covers "
                     f"{t[0]:.4g} to {t[-1]:.4g} N m")
        return math.nan
    if t.size == 1:
        return float(w[0])
    i, j = (0, 1) if end == 0 else (-2, -1)
    if t[j] == t[i]:
        return float(w[end])
    return float(w[i] + (w[j] - w[i]) * (torque - t[i]) / (t[j] - t[i]))


def hysteresis_figures(recording: HysteresisRecording, rated_torque_Nm: float, *,
                       deadband_fraction: float = BRANCH_DEADBAND_FRACTION,
                       bin_fraction: float = TORQUE_BIN_FRACTION,
                       zero_band_fraction: float = ZERO_BAND_FRACTION,
                       backlash_fit_fraction: float = BACKLASH_FIT_FRACTION,
                       skip_first_branch: bool = True) -> HysteresisFigures:
    """The catalogue figures of a hysteresis recording (module docstring).

    Parameters
    ----------
    recording : HysteresisRecording
        Torque and twist in recording order.
    rated_torque_Nm : float
        The rated output torque [N m] the figures refer to, > 0.
    deadband_fraction : float
        Reversal deadband (without a branch column), fraction of the rated torque.
    bin_fraction : float
        Torque bin width, fraction of the rated torque.
    zero_band_fraction : float
        The zero band, fraction of the rated torque; below LOST_MOTION_FRACTION.
    backlash_fit_fraction : float
        The midline's fit range for the backlash, fraction of the rated torque.
    skip_first_branch : bool
        Leave out the branch from rest to the first reversal (the virgin curve).

    Returns
    -------
    HysteresisFigures
        A figure the recording cannot give (a branch missing, a torque not reached) is NaN
        and ``notes`` says why.

    Raises
    ------
    MeasuredDataError
        For a rated torque or a fraction out of range.
    """
    rated = float(check_range("rated_torque_Nm", rated_torque_Nm, 0, None, lo_open=True,
                              error=MeasuredDataError))
    for name, v, hi in (("deadband_fraction", deadband_fraction, 1.0),
                        ("bin_fraction", bin_fraction, 1.0),
                        ("zero_band_fraction", zero_band_fraction, LOST_MOTION_FRACTION),
                        ("backlash_fit_fraction", backlash_fit_fraction, 1.0)):
        check_range(name, v, 0, hi, lo_open=True, hi_open=name == "zero_band_fraction",
                    error=MeasuredDataError)
    t, w = recording.torque_Nm, recording.twist_rad
    branch = (np.asarray(recording.branch, int) if recording.branch is not None
              else loop_branches(t, deadband_fraction * rated))
    seg = np.concatenate([[0], np.cumsum(branch[1:] != branch[:-1])]) if t.size else \
        np.zeros(0, int)
    keep = seg > 0 if skip_first_branch else np.ones(t.size, bool)
    notes = list(recording.notes)
    if skip_first_branch and not keep.any():
        notes.append("no reversal of the torque: the recording is the virgin curve only")
    zero = zero_band_fraction * rated
    flank = np.where(branch > 0, np.where(t > zero, 1, -1), np.where(t < -zero, -1, 1))
    curves = {}
    for b in (1, -1):
        for s in (1, -1):
            m = keep & (branch == b) & (flank == s)
            curves[(b, s)] = _binned(t[m], w[m], bin_fraction * rated, b, s)
    reach = EXTRAPOLATION_FRACTION * rated

    def at(b, s, torque, what):
        return _at(curves[(b, s)], torque, reach, what, notes)

    t50, t100 = (f * rated for f in RIGIDITY_FRACTIONS)
    span = t100 - t50
    pos = span / (at(1, 1, t100, "rigidity +") - at(1, 1, t50, "rigidity +"))
    neg = span / (at(-1, -1, -t50, "rigidity -") - at(-1, -1, -t100, "rigidity -"))
    tl = LOST_MOTION_FRACTION * rated
    rising = [at(1, -1, -tl, "lost motion"), at(1, -1, 0.0, "hysteresis loss"),
              at(1, 1, tl, "lost motion")]
    falling = [at(-1, -1, -tl, "lost motion"), at(-1, 1, 0.0, "hysteresis loss"),
               at(-1, 1, tl, "lost motion")]
    lost = 0.5 * (rising[2] + falling[2]) - 0.5 * (rising[0] + falling[0])
    loss = falling[1] - rising[1]
    backlash = _backlash(curves, zero, backlash_fit_fraction * rated, reach, notes)
    return HysteresisFigures(
        source=recording.source, rated_torque_Nm=rated,
        rigidity_Nm_per_arcmin=0.5 * (pos + neg), rigidity_by_direction_Nm_per_arcmin=(pos, neg),
        lost_motion_arcmin=lost, hysteresis_loss_arcmin=loss, backlash_arcmin=backlash,
        window={"torque_Nm": np.array([-tl, 0.0, tl]), "rising_arcmin": np.array(rising),
                "falling_arcmin": np.array(falling)},
        curves=tuple(c for c in curves.values() if c.torque_Nm.size),
        torque_range_Nm=(float(t.min()), float(t.max())) if t.size else (math.nan, math.nan),
        condition=recording.condition, notes=tuple(dict.fromkeys(notes)))


def _backlash(curves, zero, top, reach, notes) -> float:
    """The midline's straight line through (zero, top] of each flank, at zero: + less -."""
    ends = []
    for s in (1, -1):
        r, f = curves[(1, s)], curves[(-1, s)]
        torques = np.union1d(r.torque_Nm, f.torque_Nm)
        torques = torques[(np.abs(torques) > zero) & (np.abs(torques) <= top)]
        mids = []
        for q in torques:
            scratch: list[str] = []
            a = _at(r, q, reach, "", scratch)
            b = _at(f, q, reach, "", scratch)
            if not scratch:
                mids.append((q, 0.5 * (a + b)))
        if len(mids) < 2:
            notes.append(f"backlash: fewer than two torques on the {_FLANK[s]} flank between "
                         f"{zero:.4g} and {top:.4g} N m where both branches are read")
            return math.nan
        q, m = np.array(mids).T
        ends.append(np.polyfit(q, m, 1)[1])            # the line's value at zero
    return float(ends[0] - ends[1])


def read_hysteresis_recordings(paths, rated_torque_Nm: float, *, name_pattern=None,
                               progress: bool = True, **options) -> HysteresisSet:
    """The figures of every hysteresis file (each read, reduced to its figures, dropped).

    Parameters
    ----------
    paths : str, pathlib.Path or iterable
        A folder (its ``*.csv``), a file, or files.
    rated_torque_Nm : float
        [N m].
    name_pattern : str, optional
        File-name pattern of the condition (:func:`.columns.name_pattern`).
    progress : bool
        A progress bar over the files (on a terminal).
    **options
        Go to :func:`hysteresis_figures`.

    Returns
    -------
    HysteresisSet
    """
    check_range("rated_torque_Nm", rated_torque_Nm, 0, None, lo_open=True,
                error=MeasuredDataError)
    results, refused = each_file(
        paths, lambda p: hysteresis_figures(read_hysteresis(p, name_pattern=name_pattern),
                                            rated_torque_Nm, **options),
        desc="hysteresis recordings", progress=progress)
    figs = tuple(f for _, f in results)
    return HysteresisSet(figures=figs, refused=tuple(refused),
                         notes=tuple(n if n.startswith(f.source) else f"{f.source}: {n}"
                                     for f in figs for n in f.notes))

