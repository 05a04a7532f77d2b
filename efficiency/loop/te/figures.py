"""Model-free figures of TE and hysteresis recordings (no reducer model involved).

**Transmission error** (:func:`te_figures`, from :class:`.recordings.TeRecordings`). The
runs are grouped by operating condition (:meth:`.columns.Condition.matches`); per condition
and direction: the mean TE, the revolution-averaged TE curve and its peak-to-peak, the
spectrum (the runs' spectra power-averaged, :func:`.spectrum.combine_spectra`) and its
peaks named by a mapping {name: order} (a drive's
:meth:`~toothfem.fem.drives.base.Drive.te_orders`); per condition the **hysteresis
width**: forward mean TE less backward mean TE.

*Per-file offsets.* The encoders are re-zeroed between files, so each file's TE carries an
unknown constant. It is removed by a joint least-squares fit: each run's mean TE is its
file's offset plus the level of its (condition, direction), mean_r = o_file(r) +
m_(condition, direction)(r), every run weighing the same. Forward and backward runs of one
file share its offset, so the width m_(c,+) - m_(c,-) is the mean of the within-file
differences and no offset, however large, enters it. The fit is the plain rule "subtract
each file's mean of (forward + backward)/2" when every file holds one condition; it also
keeps how the level moves with the torque within a file that steps through several (a
long table), which the plain rule would erase. The absolute level is not measurable: the
levels of the conditions that files join are fixed so that their mean is zero (the TE
levels reported are relative). A condition whose forward and backward runs never share a
file (nor are joined through other conditions' files) has no width (NaN, with a note).

**Hysteresis** (:func:`hysteresis_figures`, from a :class:`.recordings.HysteresisRecording`
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
from dataclasses import dataclass

import numpy as np

from ....errors import MeasuredDataError, check_range
from ....fem.datasheet.sheet import LOST_MOTION_FRACTION, RIGIDITY_FRACTIONS
from .columns import ANGLE_UNITS, Condition
from .recordings import HysteresisRecording, TeRecordings, each_file, read_hysteresis
from .spectrum import (MAX_MULTIPLE, NAMING_TOLERANCE_ORDERS, Spectrum, combine_spectra,
                       named_peaks)

ARCSEC = ANGLE_UNITS["arcsec"]
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


# -- transmission error ------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class DirectionFigures:
    """One direction at one condition, over its runs."""
    direction: int                  # +1 forward, -1 backward
    mean_arcsec: float              # fitted level, relative (module docstring)
    ripple_pp_arcsec: float         # peak-to-peak of the revolution-averaged TE
    curve_arcsec: np.ndarray        # (bins,) revolution-averaged TE, offsets removed; NaN:
                                    # no sample
    runs: int
    files: int
    samples: int
    revolutions: float              # output revolutions swept, all runs
    spectrum: Spectrum | None       # power average of the runs' spectra
    peaks: tuple = ()               # spectrum.Peak, by order, named where they match


@dataclass(frozen=True, kw_only=True)
class ConditionFigures:
    """Forward, backward and the hysteresis width at one operating condition."""
    condition: Condition
    forward: DirectionFigures | None
    backward: DirectionFigures | None
    width_arcsec: float             # forward less backward mean TE; NaN: not measurable
    files: tuple                    # the sources of its runs
    notes: tuple = ()


@dataclass(frozen=True, kw_only=True)
class TeFigures:
    """The TE figures of a set of recordings, per operating condition."""
    conditions: tuple               # ConditionFigures, by torque, speed, temperature
    offsets_arcsec: dict            # source -> fitted zero offset of the file
    level_scatter_arcsec: float     # RMS of the runs' mean TE about the offset fit
    named_orders: dict              # name -> order (the names the peaks are given)
    tolerance_orders: float         # the stated naming tolerance (a spectrum coarser than
                                    # 2x it is named within half its resolution)
    refused: tuple = ()             # recordings.Refusal
    notes: tuple = ()

    def rows(self) -> list:
        """The table of the figures, one row per condition.

        Returns
        -------
        list of dict
            Condition fields, forward and backward mean and peak-to-peak [arcsec], width
            [arcsec], runs per direction.
        """
        out = []
        for c in self.conditions:
            row = dict(c.condition.values())
            for key, d in (("forward", c.forward), ("backward", c.backward)):
                row[f"{key}_mean_arcsec"] = math.nan if d is None else d.mean_arcsec
                row[f"{key}_ripple_pp_arcsec"] = math.nan if d is None else d.ripple_pp_arcsec
                row[f"{key}_runs"] = 0 if d is None else d.runs
            row["width_arcsec"] = c.width_arcsec
            out.append(row)
        return out

    def summary(self) -> dict:
        """Plain JSON types.

        Returns
        -------
        dict
            ``conditions`` (each row of :meth:`rows` with its named peaks per direction),
            ``offsets_arcsec``, ``level_scatter_arcsec``, ``named_orders``,
            ``tolerance_orders``, ``refused`` and ``notes``.
        """
        conds = []
        for c, row in zip(self.conditions, self.rows()):
            for key, d in (("forward", c.forward), ("backward", c.backward)):
                row[f"{key}_peaks"] = [] if d is None else [
                    {"order": p.order, "amplitude_arcsec": p.amplitude_arcsec,
                     "names": list(p.names)} for p in d.peaks]
                row[f"{key}_resolution_orders"] = (None if d is None or d.spectrum is None
                                                   else d.spectrum.resolution_orders)
            conds.append(row)
        return {"conditions": conds, "offsets_arcsec": dict(self.offsets_arcsec),
                "level_scatter_arcsec": self.level_scatter_arcsec,
                "named_orders": dict(self.named_orders),
                "tolerance_orders": self.tolerance_orders,
                "refused": [str(r) for r in self.refused], "notes": list(self.notes)}


def group_conditions(runs) -> list:
    """The runs by operating condition (:meth:`.columns.Condition.matches` of the group's
    first, in the order of :meth:`~.columns.Condition.sort_key`).

    Parameters
    ----------
    runs : sequence of recordings.Run

    Returns
    -------
    list of (Condition, list of int)
        Each group's condition (its runs' sample-weighted mean) and its runs' indices,
        sorted by torque, speed, temperature.
    """
    groups: list[tuple[Condition, list[int]]] = []
    for i in sorted(range(len(runs)), key=lambda k: runs[k].condition.sort_key()):
        c = runs[i].condition
        for first, members in groups:
            if first.matches(c):
                members.append(i)
                break
        else:
            groups.append((c, [i]))
    out = []
    for first, members in groups:
        values: dict[str, float | None] = {}
        for name, v in first.values().items():
            if v is None:
                values[name] = None
                continue
            w = np.array([runs[i].samples for i in members], float)
            x = np.array([getattr(runs[i].condition, name) for i in members], float)
            values[name] = float(np.dot(w, x) / w.sum())
        out.append((Condition(**values), members))
    out.sort(key=lambda g: g[0].sort_key())
    return out


def file_offsets(runs, group_of) -> tuple:
    """The joint fit of the files' zero offsets and the levels (module docstring).

    Parameters
    ----------
    runs : sequence of recordings.Run
    group_of : sequence of int
        Each run's condition group.

    Returns
    -------
    offsets : dict
        source -> offset [rad].
    levels : dict
        (group, direction) -> level [rad], the mean over each set of joined levels zero.
    component : dict
        (group, direction) -> the index of its joined set (a width is measurable where both
        directions of a group are in one).
    scatter : float
        RMS of the residuals [rad].
    """
    files = sorted({r.source for r in runs})
    fi = {s: k for k, s in enumerate(files)}
    keys = sorted({(g, r.direction) for r, g in zip(runs, group_of)})
    li = {k: len(files) + j for j, k in enumerate(keys)}
    n = len(files) + len(keys)
    a = np.zeros((len(runs), n))
    y = np.array([r.mean_te_rad for r in runs])
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for row, (r, g) in enumerate(zip(runs, group_of)):
        f, lv = fi[r.source], li[(g, r.direction)]
        a[row, f] = a[row, lv] = 1.0
        parent[find(f)] = find(lv)
    sol = np.linalg.lstsq(a, y, rcond=None)[0]
    resid = y - a @ sol
    roots = [find(i) for i in range(n)]
    for root in set(roots):
        members = [i for i in range(n) if roots[i] == root]
        level_cols = [i for i in members if i >= len(files)]
        shift = float(np.mean(sol[level_cols])) if level_cols else 0.0
        for i in members:
            sol[i] += shift if i < len(files) else -shift
    offsets = {s: float(sol[fi[s]]) for s in files}
    levels = {k: float(sol[li[k]]) for k in keys}
    component = {k: roots[li[k]] for k in keys}
    scatter = float(np.sqrt(np.mean(resid ** 2))) if resid.size else 0.0
    return offsets, levels, component, scatter


def _direction(runs, members, offsets, level, named, tolerance, max_multiple):
    """DirectionFigures of a group's runs of one direction."""
    stack = np.array([np.asarray(runs[i].binned_te_rad, float) - offsets[runs[i].source]
                      for i in members])
    ok = np.isfinite(stack)
    counts = ok.sum(axis=0)
    sums = np.where(ok, stack, 0.0).sum(axis=0)
    curve = np.full(stack.shape[1], np.nan)
    curve[counts > 0] = sums[counts > 0] / counts[counts > 0] / ARCSEC
    spectra = [runs[i].spectrum for i in members if runs[i].spectrum is not None]
    spec = combine_spectra(spectra) if spectra else None
    peaks = () if spec is None else named_peaks(spec, named, tolerance_orders=tolerance,
                                                 max_multiple=max_multiple)
    finite = curve[np.isfinite(curve)]
    return DirectionFigures(
        direction=runs[members[0]].direction, mean_arcsec=level / ARCSEC,
        ripple_pp_arcsec=float(finite.max() - finite.min()) if finite.size else math.nan,
        curve_arcsec=curve, runs=len(members),
        files=len({runs[i].source for i in members}),
        samples=int(sum(runs[i].samples for i in members)),
        revolutions=float(sum(runs[i].revolutions for i in members)),
        spectrum=spec, peaks=peaks)


def te_figures(recordings: TeRecordings, *, named_orders: dict | None = None,
               tolerance_orders: float = NAMING_TOLERANCE_ORDERS,
               max_multiple: int = MAX_MULTIPLE) -> TeFigures:
    """The model-free TE figures per operating condition (module docstring).

    Parameters
    ----------
    recordings : recordings.TeRecordings
        From :func:`.recordings.read_te_recordings`.
    named_orders : dict of str to float, optional
        name -> order per output revolution (e.g. ``drive.te_orders()``); None: the peaks
        unnamed.
    tolerance_orders : float
        A peak is named by an order (or a multiple up to ``max_multiple``) within this
        many orders (:func:`.spectrum.naming_tolerance`).
    max_multiple : int
        Multiples of the named orders tried.

    Returns
    -------
    TeFigures

    Raises
    ------
    MeasuredDataError
        If no run was read (the refusals say why).
    """
    runs = list(recordings.runs)
    if not runs:
        why = "; ".join(str(r) for r in recordings.refused[:3]) or "no file given"
        raise MeasuredDataError(f"no TE run to analyse ({why})")
    groups = group_conditions(runs)
    group_of = [0] * len(runs)
    for g, (_, members) in enumerate(groups):
        for i in members:
            group_of[i] = g
    offsets, levels, component, scatter = file_offsets(runs, group_of)
    conditions = []
    for g, (cond, members) in enumerate(groups):
        per = {}
        for d in (1, -1):
            idx = [i for i in members if runs[i].direction == d]
            per[d] = None if not idx else _direction(runs, idx, offsets, levels[(g, d)],
                                                     named_orders, tolerance_orders,
                                                     max_multiple)
        notes = []
        if per[1] is None or per[-1] is None:
            width = math.nan
            notes.append(f"{cond.label()}: only the {'forward' if per[1] else 'backward'} "
                         "direction recorded: no width")
        elif component[(g, 1)] != component[(g, -1)]:
            width = math.nan
            notes.append(f"{cond.label()}: forward and backward never in one file (nor "
                         "joined through other conditions): each file's zero offset hides "
                         "the width")
        else:
            width = (levels[(g, 1)] - levels[(g, -1)]) / ARCSEC
        conditions.append(ConditionFigures(
            condition=cond, forward=per[1], backward=per[-1], width_arcsec=width,
            files=tuple(sorted({runs[i].source for i in members})), notes=tuple(notes)))
    return TeFigures(conditions=tuple(conditions),
                     offsets_arcsec={s: v / ARCSEC for s, v in offsets.items()},
                     level_scatter_arcsec=scatter / ARCSEC,
                     named_orders=dict(named_orders or {}),
                     tolerance_orders=float(tolerance_orders),
                     refused=tuple(recordings.refused),
                     notes=tuple(recordings.notes) + tuple(n for c in conditions
                                                           for n in c.notes))


# -- hysteresis ----------------------------------------------------------------------------


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
    recording : recordings.HysteresisRecording
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

