"""A disc's FE influence tables at every pin pitch of the drive's full period, filled from a
few sampled pitches (the system model's tables at a built ring's true positions,
docs/tolerance.md)."""
from __future__ import annotations

import numpy as np

from ..datasheet.transmission import fourier_fill, sampled_pitches


class PitchTables:
    """A disc's influence tables at every pin pitch of the full period, filled from the
    cycle solvers at a few sampled pitches by a least-squares Fourier series in the pitch
    (:func:`toothfem.fem.datasheet.transmission.fourier_fill`: exact up to the order
    (Q-1)/2 per full period of the holes' part), as the TE over the full period is filled.
    At pitch m the contacts are those of pitch 0 moved m lobes on against the disc's holes:
    every pin a candidate (both flanks), candidate j of pitch 0 is pin j + m there, so the
    tables line up entry by entry once turned by m pins.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    n_positions, offset : int
        The disc's grid (positions per pitch) and its grid offset.
    options : dict
        Its cycle solvers' options (both flanks).
    cache
        The FE tables' disk cache.
    samples : int
        Sampled pitches Q.
    """

    def __init__(self, drive, n_positions: int, offset: int, options: dict, cache,
                 samples: int):
        self.full_period = drive.full_period_pitches
        self.zb = drive.geometry.pin_count
        self.pitches = sampled_pitches(self.full_period, samples)
        self.solvers = [drive.cycle_solver(n_positions, cache=cache,
                                           offset=offset + m * n_positions,
                                           solver_options=options) for m in self.pitches]
        self._filled: dict[tuple[int, int], np.ndarray] = {}   # (p, side) -> (full period, C, C)

    def prepare(self) -> None:
        """Every sampled pitch's tables now: from the disk cache where it holds them, else
        computed (and stored there)."""
        for solver in self.solvers:
            solver.prepare()

    def table(self, p: int, pitch: int, side: int) -> np.ndarray:
        """The influence table of position p's candidates (pitch 0's order) at a pitch.

        Parameters
        ----------
        p : int
            Position index.
        pitch : int
            Pin pitches on (any; taken over the full period).
        side : {1, -1}
            The flank.

        Returns
        -------
        numpy.ndarray, shape (C, C)
            [m per N/m].
        """
        key = (p, side)
        if key not in self._filled:
            if not self._filled:
                self.prepare()
            ref = self.solvers[0].candidates(side)[p].pins
            mats = []
            for m, solver in zip(self.pitches, self.solvers):
                pins = solver.candidates(side)[p].pins
                where = {int(j): i for i, j in enumerate(pins)}
                order = [where[(int(j) + m - self.pitches[0]) % self.zb] for j in ref]
                mats.append(solver.influence(p, side)[np.ix_(order, order)].ravel())
            self._filled[key] = fourier_fill(self.pitches, np.array(mats),
                                             self.full_period).reshape(
                self.full_period, ref.size, ref.size)
        return self._filled[key][int(pitch) % self.full_period]
