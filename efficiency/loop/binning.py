"""Many measured rows onto fewer operating points: the mean of each cell of a grid.

The loop evaluates the model at every point it fits, so its time and memory grow with the
rows (the analytic model takes about 26 kB a point in one evaluation: 1e5 rows peaked at
2.9 GB). A rig's logger writes many rows per operating point, and the loop needs the
efficiency at each operating point, not every reading of it. Above
:attr:`~.settings.Settings.max_points` rows, :func:`bin_rows` therefore puts the rows on a
grid of the operating point and keeps, per occupied cell, the mean of its rows and their
count:

* the grid's axes are the operating point: input speed, output torque and, when the data
  carry it, oil temperature; each axis is cut into the same number of equal cells over its
  range, the largest number that leaves at most ``max_points`` occupied cells (found by
  bisection);
* every numeric column (efficiency, torques, temperature, time, further covariates) is the
  mean over the cell's rows; the model is evaluated at that mean operating point, an error
  of second order in the cell width (the model's curvature: with the cells of 1e4 rows on
  2000 points, 12 a side, no catalog effect fits it; cut also by time and run, 7 a side,
  a churning correction began to, at a BIC gain of 12);
* a cell's ``run_id`` is the run of its rows, or ``"mixed"`` when they come from several
  (a label cannot be averaged). Time and run are kept by the cells of rig data logged at
  one operating point after another (a cell's rows share a run and a stretch of time); the
  cells of points taken in shuffled order mix them, and a trend over time or run no longer
  shows;
* the uncertainty of a point is that of a mean: sqrt(sum sigma_i^2) / n with the rows' own
  sigma (the sensors), else s / sqrt(n) with s the pooled scatter of the efficiency within
  the cells (the rig's repeatability; it holds the model's change across a cell too, the
  same for every cell, so the weights stay proportional to sqrt(n)).

The :class:`Binning` record says what was done; its :meth:`~Binning.note` goes into the
data's ``notes`` and so into the loop's report.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .measured import MeasuredData, grid_axes

#: The run label of a cell whose rows come from several runs.
MIXED_RUNS = "mixed"


@dataclass(frozen=True, kw_only=True)
class Binning:
    """How the rows were binned: ``rows`` rows onto ``points`` operating points."""
    rows: int
    points: int
    max_points: int                # the most points kept (Settings.max_points)
    axes: tuple                    # covariate names of the grid's axes
    cells: int                     # equal cells per axis over its range
    rows_per_point: tuple          # (fewest, median, most)
    sigma: str                     # where each point's uncertainty comes from
    mixed_runs: int | None = None  # points whose rows come from several runs (None: no
                                   # run_id column)

    def note(self) -> str:
        """One line for the data's notes and the report.

        Returns
        -------
        str
            Rows and points, the cells per axis, the rows per point, the mixed runs and
            where sigma comes from.
        """
        least, median, most = self.rows_per_point
        return (f"{self.rows} rows binned onto {self.points} operating points (more rows "
                f"than max_points = {self.max_points}): {self.cells} equal cells on each of "
                f"{', '.join(self.axes)}; each point is the mean of its cell's rows "
                f"({least} to {most}, median {median:g}), time and further columns included"
                + ("" if self.mixed_runs is None else
                   f"; {self.mixed_runs} of the points mix runs (run_id {MIXED_RUNS!r})")
                + f"; its sigma {self.sigma}")

    def to_dict(self) -> dict:
        """Plain JSON types: the fields by name.

        Returns
        -------
        dict
            ``cells`` as ``cells_per_axis``, ``rows_per_point`` as {min, median, max}.
        """
        return {"rows": self.rows, "points": self.points, "max_points": self.max_points,
                "axes": list(self.axes),
                "cells_per_axis": self.cells,
                "rows_per_point": {"min": self.rows_per_point[0],
                                   "median": self.rows_per_point[1],
                                   "max": self.rows_per_point[2]},
                "sigma": self.sigma, "mixed_runs": self.mixed_runs}


#: Codes below this bound (or below 4 codes a row) are compacted through a table of them
#: (np.unique sorts the rows: 1e6 rows took 0.1 s an axis, 4 s of bisection).
DENSE_CODES = 1 << 22


def _compact(values, bound):
    """np.unique(values, return_inverse=True)'s inverse of non-negative ints below
    ``bound``: each value's rank among the distinct values."""
    if bound <= max(DENSE_CODES, 4 * values.size):
        seen = np.zeros(bound, bool)
        seen[values] = True
        return (np.cumsum(seen) - 1)[values]
    return np.unique(values, return_inverse=True)[1].reshape(-1)


def _codes(axes: dict, cells: int, limit=None):
    """(compact codes, occupied cells) of :func:`cell_codes`; with ``limit``, (None, count)
    as soon as more than ``limit`` cells are occupied (another axis can only split them)."""
    code = np.zeros(next(iter(axes.values())).size, np.int64)
    count = 1
    for x in axes.values():
        lo, span = x.min(), np.ptp(x)
        if span > 0:
            index = np.minimum(((x - lo) / span * cells).astype(np.int64), cells - 1)
            code = _compact(code * cells + index, count * cells)
            count = int(code.max()) + 1
            if limit is not None and count > limit:
                return None, count
    return code, count


def cell_codes(axes: dict, cells: int) -> np.ndarray:
    """(M,) compact code of each row's cell (``cells`` equal cells per axis).

    Parameters
    ----------
    axes : dict
        name -> (M,) values; an axis of one value is one cell.
    cells : int
        Equal cells per axis over its range (the top edge belongs to the last cell).

    Returns
    -------
    numpy.ndarray
        (M,) int, 0 to (occupied cells - 1).
    """
    return _codes(axes, cells)[0]      # compact already, or all one cell


def _most_cells(axes, max_points) -> int:
    """Largest number of cells per axis leaving at most ``max_points`` occupied cells
    (bisection; occupied cells grow with the cells per axis, all but for the shifts of the
    cell edges, and the result is checked). It starts from the d-th root of ``max_points``,
    which no data can overfill."""
    lo, hi = max(1, int(max_points ** (1 / len(axes)))), max_points
    while lo ** len(axes) > max_points:         # the root's rounding
        lo -= 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if _codes(axes, mid, max_points)[1] <= max_points:
            lo = mid
        else:
            hi = mid - 1
    return lo


def _bin_sigma(data, code, counts, eta_mean):
    """Each point's uncertainty and what it is (module docstring)."""
    if data.sigma is not None:
        s2 = np.bincount(code, weights=np.asarray(data.sigma, float) ** 2)
        return np.sqrt(s2) / counts, ("the standard error of the mean from the rows' "
                                      "sigma, sqrt(sum sigma_i^2)/n")
    dof = code.size - counts.size
    scatter = np.asarray(data.efficiency, float) - eta_mean[code]
    s = float(np.sqrt(np.sum(scatter ** 2) / dof)) if dof > 0 else 0.0
    if not s > 0:
        return None, "none (no scatter within the cells to estimate it from): unweighted"
    return s / np.sqrt(counts), (f"s/sqrt(n), with s = {100 * s:.3g} points the pooled "
                                 "scatter of the efficiency within the cells")


def bin_rows(data: MeasuredData, max_points: int) -> tuple:
    """The rows of ``data`` binned onto at most ``max_points`` operating points (module
    docstring), or ``data`` itself when it has no more rows than that.

    Parameters
    ----------
    data : MeasuredData
        Measured rows, M of them.
    max_points : int
        Most operating points to keep (>= 1).

    Returns
    -------
    tuple
        (MeasuredData of the points, :class:`Binning` or None when not binned). The binned
        record's ``notes`` end with :meth:`Binning.note`; its ``lines`` are the first
        source line of each point's rows.
    """
    if len(data) <= max_points:
        return data, None
    axes = grid_axes(data)
    cells = _most_cells(axes, max_points)
    code = cell_codes(axes, cells)
    counts = np.bincount(code)
    first = np.unique(code, return_index=True)[1]         # each point's first row

    def mean(a):
        return None if a is None else np.bincount(code, weights=np.asarray(a, float)) / counts

    eta = mean(data.efficiency)
    sigma, sigma_from = _bin_sigma(data, code, counts, eta)
    runs = _cell_runs(data.run_id, code, first)
    info = Binning(rows=len(data), points=int(counts.size), max_points=max_points,
                   axes=tuple(axes), cells=cells,
                   rows_per_point=(int(counts.min()), float(np.median(counts)),
                                   int(counts.max())),
                   sigma=sigma_from,
                   mixed_runs=None if runs is None else int(np.sum(runs == MIXED_RUNS)))
    binned = replace(data, speed_rpm=mean(data.speed_rpm), torque_Nm=mean(data.torque_Nm),
                     efficiency=eta, oil_temp_C=mean(data.oil_temp_C),
                     time_h=mean(data.time_h), run_id=runs,
                     input_torque_Nm=mean(data.input_torque_Nm), sigma=sigma,
                     extra={k: mean(v) for k, v in data.extra.items()},
                     lines=None if data.lines is None else np.asarray(data.lines)[first],
                     notes=data.notes + (info.note(),))
    return binned, info


def _cell_runs(run_id, code, first):
    """Each cell's run label: that of its rows, or :data:`MIXED_RUNS`; None without runs."""
    if run_id is None:
        return None
    labels, runs = np.unique(np.asarray(run_id).astype(str), return_inverse=True)
    runs = runs.reshape(-1)
    lo = np.full(first.size, labels.size)
    np.minimum.at(lo, code, runs)
    hi = np.full(first.size, -1)
    np.maximum.at(hi, code, runs)
    out = labels[runs[first]].astype(object)
    out[lo != hi] = MIXED_RUNS
    return out
