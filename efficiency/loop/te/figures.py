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

The hysteresis staircase's figures are :mod:`.hysteresis`'s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ....errors import MeasuredDataError
from ....units import ARCSEC
from .columns import Condition
from .recordings import TeRecordings
from .spectrum import (MAX_MULTIPLE, NAMING_TOLERANCE_ORDERS, Spectrum, combine_spectra,
                       named_peaks)




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
    revolutions: float              # output revolutions holding data, all runs
    spectrum: Spectrum | None       # power average of the runs' spectra
    peaks: tuple = ()               # spectrum.Peak, by order, named where they match
    windows: int = 1                # windows of data, all runs (:mod:`.windows`)
    level_sigma_arcsec: float = math.nan   # standard error of mean_arcsec (sigma_source)
    sigma_source: str = ""          # "between windows" | "within a window"
    ripple_source: str = "revolution-averaged curve"   # or "within windows (median)"
    wins: tuple = ()                # (windows.Windows, file offset [rad]) per run


@dataclass(frozen=True, kw_only=True)
class ConditionFigures:
    """Forward, backward and the hysteresis width at one operating condition."""
    condition: Condition
    forward: DirectionFigures | None
    backward: DirectionFigures | None
    width_arcsec: float             # forward less backward mean TE; NaN: not measurable
    files: tuple                    # the sources of its runs
    width_sigma_arcsec: float = math.nan   # from the two levels' standard errors
    once_per_turn_arcsec: float = math.nan  # first harmonic of the window means (fitted
                                            # out of the width); NaN: not fitted
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
            row["width_sigma_arcsec"] = c.width_sigma_arcsec
            for key, d in (("forward", c.forward), ("backward", c.backward)):
                row[f"{key}_windows"] = 0 if d is None else d.windows
                row[f"{key}_coverage_revolutions"] = math.nan if d is None else d.revolutions
            row["once_per_turn_arcsec"] = c.once_per_turn_arcsec
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
                row[f"{key}_sigma_source"] = None if d is None else d.sigma_source
                row[f"{key}_ripple_source"] = None if d is None else d.ripple_source
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
    wins = [(runs[i].windows, offsets[runs[i].source]) for i in members
            if runs[i].windows is not None]
    gapped = any(w.count > 1 for w, _ in wins)
    if gapped:
        ripple = float(np.median([w.ripple_pp_rad for w, _ in wins])) / ARCSEC
    else:
        ripple = float(finite.max() - finite.min()) if finite.size else math.nan
    sigma, source = level_sigma(wins)
    return DirectionFigures(
        direction=runs[members[0]].direction, mean_arcsec=level / ARCSEC,
        ripple_pp_arcsec=ripple, curve_arcsec=curve, runs=len(members),
        files=len({runs[i].source for i in members}),
        samples=int(sum(runs[i].samples for i in members)),
        revolutions=float(sum(runs[i].revolutions for i in members)),
        spectrum=spec, peaks=peaks, windows=int(sum(w.count for w, _ in wins)) or 1,
        level_sigma_arcsec=sigma / ARCSEC, sigma_source=source,
        ripple_source="within windows (median)" if gapped else "revolution-averaged curve",
        wins=tuple(wins))


#: The once-per-turn component is fitted to the window means where at least this many
#: windows spread over at least this part of a turn (fewer, or closer, do not tell a first
#: harmonic from a level).
ONCE_PER_TURN_WINDOWS = 4
ONCE_PER_TURN_SPREAD_RAD = math.pi / 2


def level_sigma(wins) -> tuple:
    """The standard error of a direction's level from the data's own scatter [rad], and
    which scatter: between windows (each window's mean less its file's offset; the standard
    deviation over sqrt(count)) where there are two or more, else within the one window
    (the samples' noise, :attr:`.windows.Windows.noise_rad`, over sqrt(samples)).

    Parameters
    ----------
    wins : sequence of (windows.Windows, float)
        Each run's windows and its file's offset [rad].

    Returns
    -------
    sigma : float
        [rad]; NaN where neither can be taken.
    source : str
    """
    means = np.concatenate([w.means_rad - off for w, off in wins]) if wins else np.zeros(0)
    if means.size >= 2:
        return float(np.std(means, ddof=1) / math.sqrt(means.size)), \
            f"between windows ({means.size})"
    if wins and math.isfinite(wins[0][0].noise_rad):
        w = wins[0][0]
        return float(w.noise_rad / math.sqrt(max(int(w.samples.sum()), 1))), \
            "within a window (sample noise)"
    return math.nan, "none"


def once_per_turn_width(forward, backward) -> tuple | None:
    """The width with the once-per-turn component fitted out of the window means: one
    least-squares fit of both directions' window means (each less its file's offset),
    m = L_direction + A cos(angle) + B sin(angle), the first harmonic shared (the rig's or
    the output's eccentricity is a function of the angle, whichever way it turns); width
    L_forward - L_backward, its sigma from the fit's residual scatter. None where the
    windows are too few or too close together to tell the harmonic from the levels
    (:data:`ONCE_PER_TURN_WINDOWS` a direction, spread over :data:`ONCE_PER_TURN_SPREAD_RAD`).

    Parameters
    ----------
    forward, backward : DirectionFigures

    Returns
    -------
    (width, sigma, amplitude) [rad], or None
    """
    cols, ms, cs = [], [], []
    for k, d in enumerate((forward, backward)):
        c = np.concatenate([w.centres_rad for w, _ in d.wins]) if d.wins else np.zeros(0)
        if c.size < ONCE_PER_TURN_WINDOWS:
            return None
        cs.append(c)
        ms.append(np.concatenate([w.means_rad - off for w, off in d.wins]))
        cols.append(np.full(c.size, k))
    c, m, which = np.concatenate(cs), np.concatenate(ms), np.concatenate(cols)
    ring = np.sort(c)
    if 2 * math.pi - np.diff(np.concatenate([ring, ring[:1] + 2 * math.pi])).max() \
            < ONCE_PER_TURN_SPREAD_RAD:
        return None
    a = np.column_stack([which == 0, which == 1, np.cos(c), np.sin(c)]).astype(float)
    sol, *_ = np.linalg.lstsq(a, m, rcond=None)
    dof = m.size - 4
    if dof < 1:
        return None
    var = float(np.sum((m - a @ sol) ** 2) / dof)
    cov = np.linalg.inv(a.T @ a) * var
    sigma = math.sqrt(cov[0, 0] + cov[1, 1] - 2 * cov[0, 1])
    return float(sol[0] - sol[1]), sigma, float(math.hypot(sol[2], sol[3]))


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
        fwd, bwd = per[1], per[-1]
        sig = (math.hypot(fwd.level_sigma_arcsec, bwd.level_sigma_arcsec)
               if fwd is not None and bwd is not None else math.nan)
        turn = math.nan
        fitted = (once_per_turn_width(fwd, bwd) if fwd is not None and bwd is not None
                  and math.isfinite(width) and (fwd.windows > 1 or bwd.windows > 1)
                  else None)
        if fitted is not None:
            width, sig, turn = (v / ARCSEC for v in fitted)
            notes.append(f"{cond.label()}: width from the window means with the "
                         f"once-per-turn component fitted out ({turn:.3g} arcsec)")
        conditions.append(ConditionFigures(
            condition=cond, forward=per[1], backward=per[-1], width_arcsec=width,
            files=tuple(sorted({runs[i].source for i in members})), notes=tuple(notes),
            width_sigma_arcsec=sig, once_per_turn_arcsec=turn))
    return TeFigures(conditions=tuple(conditions),
                     offsets_arcsec={s: v / ARCSEC for s, v in offsets.items()},
                     level_scatter_arcsec=scatter / ARCSEC,
                     named_orders=dict(named_orders or {}),
                     tolerance_orders=float(tolerance_orders),
                     refused=tuple(recordings.refused),
                     notes=tuple(recordings.notes) + tuple(n for c in conditions
                                                           for n in c.notes))
