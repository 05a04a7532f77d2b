"""The windows of a TE run: where a rig recorded, and what a window can say.

A running TE rig of a production reducer rarely sweeps whole output revolutions: it logs
short windows (about a degree of output each) scattered over part of a turn, forward and
backward at other angles. A run (one direction of one condition in one file) is cut into
windows where the output angle jumps by more than :data:`GAP_STEPS` times the run's median
step (a logger's missed sample or two is not a gap). Per window: its centre angle, its span
and its mean TE; over the run:

- **coverage**: the sum of the windows' spans in output revolutions (what holds data), beside
  the span from the first angle to the last (what a sweep would have covered);
- **ripple within a window**: the median over the windows of each window's peak-to-peak
  about its own mean (a spread between windows far apart is the once-per-turn component of
  the rig or the output, not a ripple);
- **noise**: the samples' scatter about their neighbours, the standard deviation of the
  first differences over sqrt(2) inside windows (white noise of s gives s; a ripple of many
  samples per period adds little).

The orders a window resolves: one period of the order must fit in it, so a window of span s
[rad] of output resolves orders from 2 pi / s per output revolution up (a 1 degree window:
from order 360 up, the fast mesh orders; never the once-per-turn, which only the spread of
window means over the turn shows).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: An angle step this many times the run's median step starts a new window.
GAP_STEPS = 10.0


@dataclass(frozen=True)
class Windows:
    """The windows of one run (module docstring); angles in rad, TE in rad."""
    centres_rad: np.ndarray         # (W,) each window's mean output angle, modulo a turn
    spans_rad: np.ndarray           # (W,) last less first angle of each window
    means_rad: np.ndarray           # (W,) each window's mean TE
    samples: np.ndarray             # (W,) samples per window
    ripple_pp_rad: float            # median peak-to-peak about the window's mean
    noise_rad: float                # first differences' std / sqrt 2, inside windows
    span_rad: float                 # first to last angle of the run

    @property
    def count(self) -> int:
        return int(self.means_rad.size)

    @property
    def coverage_revolutions(self) -> float:
        """Output revolutions that hold data (the windows' spans summed)."""
        return float(self.spans_rad.sum() / (2 * math.pi))

    @property
    def smallest_order(self) -> float:
        """The lowest order per output revolution one period of which fits in the median
        window (2 pi / span; inf for a window of one angle)."""
        s = float(np.median(self.spans_rad)) if self.spans_rad.size else 0.0
        return 2 * math.pi / s if s > 0 else math.inf


def windows_of(angle_rad, te_rad) -> Windows:
    """Cut a run into windows at its gaps (module docstring).

    Parameters
    ----------
    angle_rad : numpy.ndarray, shape (N,)
        Output angle [rad] in recorded order, N >= 2.
    te_rad : numpy.ndarray, shape (N,)
        TE [rad].

    Returns
    -------
    Windows
    """
    a = np.unwrap(np.asarray(angle_rad, float))
    y = np.asarray(te_rad, float)
    step = np.abs(np.diff(a))
    typical = float(np.median(step)) if step.size else 0.0
    gap = step > GAP_STEPS * typical if typical > 0 else np.zeros(step.size, bool)
    cuts = np.flatnonzero(gap) + 1
    bounds = np.concatenate([[0], cuts, [a.size]])
    centres, spans, means, counts, pps = [], [], [], [], []
    diffs = []
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        wa, wy = a[lo:hi], y[lo:hi]
        centres.append(float(np.mod(wa.mean(), 2 * math.pi)))
        spans.append(float(wa.max() - wa.min()))
        means.append(float(wy.mean()))
        counts.append(int(wy.size))
        pps.append(float(wy.max() - wy.min()))
        if wy.size > 1:
            diffs.append(np.diff(wy))
    d = np.concatenate(diffs) if diffs else np.zeros(0)
    return Windows(centres_rad=np.array(centres), spans_rad=np.array(spans),
                   means_rad=np.array(means), samples=np.array(counts),
                   ripple_pp_rad=float(np.median(pps)),
                   noise_rad=float(np.std(d) / math.sqrt(2)) if d.size > 1 else math.nan,
                   span_rad=float(a.max() - a.min()))
