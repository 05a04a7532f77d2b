"""Synthetic TE and hysteresis recordings with known figures (the tests, the docs).

:class:`Loop` is an analytic hysteresis loop: an elastic curve with a backlash (a jump b at
zero torque), a compliance c1 up to a knee and c2 above it, and a Coulomb friction of loop
width w acting as a play operator (after a reversal the twist stays until the branch's own
curve passes it). Its figures by the catalogue definitions (:mod:`.figures`) are known in
closed form: rigidity 1/c2 (the knee below 50 %), lost motion b + 2 c1 t (t = 3 % of the
rated torque, below the knee), hysteresis loss b + w, backlash b.

:class:`Ripple` is a TE: sinusoids of given orders of the output revolution (amplitude,
phase) plus a level and half the hysteresis width, + in the forward direction and - backward.

The writers put recordings in either file shape of :mod:`.recordings`, with encoder noise,
uneven angle steps, a per-file zero offset, any units, delimiter and comment lines. This
is the only module of the package that writes files.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ....fem.datasheet.sheet import LOST_MOTION_FRACTION
from .columns import ANGLE_UNITS

#: The catalogue staircase of :func:`Loop.samples`, fractions of the rated torque: fine
#: steps near zero (lost motion at 3 %, the backlash fit up to 10 %), then 25-50-75-100 %.
STAIRCASE = (0.0, 0.03, 0.06, 0.1, 0.25, 0.5, 0.75, 1.0)


@dataclass(frozen=True, kw_only=True)
class Loop:
    """An analytic hysteresis loop with known catalogue figures (module docstring)."""
    rated_torque_Nm: float
    rigidity_Nm_per_arcmin: float           # 1/c2, above the knee
    low_rigidity_Nm_per_arcmin: float       # 1/c1, below the knee
    backlash_arcmin: float
    friction_width_arcmin: float
    knee_fraction: float = 0.25

    @property
    def lost_motion_arcmin(self) -> float:
        """b + 2 c1 t, t = LOST_MOTION_FRACTION of the rated torque [arcmin]."""
        return self.backlash_arcmin + 2 * LOST_MOTION_FRACTION * self.rated_torque_Nm \
            / self.low_rigidity_Nm_per_arcmin

    @property
    def hysteresis_loss_arcmin(self) -> float:
        """b + w [arcmin]."""
        return self.backlash_arcmin + self.friction_width_arcmin

    def elastic_arcmin(self, torque_Nm: float, side: int) -> float:
        """The elastic curve [arcmin] on flank ``side`` (the sign of the torque; at zero,
        the flank the path comes from).

        Parameters
        ----------
        torque_Nm : float
        side : int
            +1 or -1.

        Returns
        -------
        float
        """
        knee = self.knee_fraction * self.rated_torque_Nm
        t = abs(torque_Nm)
        c1, c2 = 1 / self.low_rigidity_Nm_per_arcmin, 1 / self.rigidity_Nm_per_arcmin
        mag = c1 * t if t <= knee else c1 * knee + c2 * (t - knee)
        return side * (0.5 * self.backlash_arcmin + mag)

    def path(self, levels=STAIRCASE, cycles: int = 1) -> tuple:
        """The staircase 0 -> +T -> -T -> +T (``cycles`` loops) and each step's branch and
        twist (the play operator from rest at zero twist).

        Parameters
        ----------
        levels : sequence of float
            Fractions of the rated torque from 0 to 1, rising.
        cycles : int
            Loops after the virgin rise.

        Returns
        -------
        torque_Nm, branch, twist_arcmin : numpy.ndarray
            One entry per step.
        """
        up = [f for f in levels]
        down = [f for f in reversed(levels[:-1])] + [-f for f in levels[1:]]
        rise = [-f for f in reversed(levels[:-1])] + [f for f in levels[1:]]
        fractions = up + (down + rise) * int(cycles)
        torques = np.array(fractions) * self.rated_torque_Nm
        h = 0.5 * self.friction_width_arcmin
        branch, twist, theta = [], [], None
        for k, t in enumerate(torques):
            b = 1 if k == 0 or t > torques[k - 1] else -1
            # at zero torque the flank the path comes from (rising: from -)
            side = (1 if t > 0 else -1) if t != 0 else (-b if k else 1)
            e = self.elastic_arcmin(t, side)
            if theta is None:
                theta = e - h                   # from rest, loading
            elif b > 0:
                theta = max(theta, e - h)       # rising: stuck until e - h passes
            else:
                theta = min(theta, e + h)
            branch.append(b)
            twist.append(theta)
        return torques, np.array(branch), np.array(twist)

    def samples(self, *, levels=STAIRCASE, cycles: int = 1, samples_per_step: int = 50,
                torque_noise_Nm: float = 0.0, twist_noise_arcmin: float = 0.0,
                rng=None) -> dict:
        """A recording of the staircase: ``samples_per_step`` readings per step.

        Parameters
        ----------
        levels : sequence of float
            As :meth:`path`.
        cycles : int
            As :meth:`path`.
        samples_per_step : int
            Readings per step.
        torque_noise_Nm, twist_noise_arcmin : float
            Standard deviations of the readings' Gaussian noise.
        rng : numpy.random.Generator, optional
            Default seed 0.

        Returns
        -------
        dict of numpy.ndarray
            ``torque_Nm``, ``twist_arcmin``, ``branch`` (per reading), ``step`` (the index
            of its step), ``set_torque_Nm``.
        """
        rng = np.random.default_rng(0) if rng is None else rng
        torques, branch, twist = self.path(levels, cycles)
        n = int(samples_per_step)
        step = np.repeat(np.arange(torques.size), n)
        return {"torque_Nm": torques[step] + torque_noise_Nm * rng.standard_normal(step.size),
                "twist_arcmin": twist[step] + twist_noise_arcmin
                * rng.standard_normal(step.size),
                "branch": branch[step], "step": step, "set_torque_Nm": torques[step]}


@dataclass(frozen=True, kw_only=True)
class Ripple:
    """A TE: sinusoids of orders of the output revolution, and the hysteresis width."""
    amplitudes_arcsec: dict                 # order -> amplitude
    phases_rad: dict = field(default_factory=dict)   # order -> phase (default 0)
    width_arcsec: float = 0.0               # forward less backward
    level_arcsec: float = 0.0               # the mean of forward and backward (e.g. a twist
                                            # under the run's torque)

    def te_arcsec(self, angle_rad, direction: int) -> np.ndarray:
        """The TE at the output angles [arcsec].

        Parameters
        ----------
        angle_rad : array_like
            Output angle [rad].
        direction : int
            +1 forward (adds half the width), -1 backward (subtracts it).

        Returns
        -------
        numpy.ndarray
        """
        a = np.asarray(angle_rad, float)
        out = np.full(a.shape, self.level_arcsec + 0.5 * direction * self.width_arcsec)
        for q, amp in self.amplitudes_arcsec.items():
            out += amp * np.sin(q * a + self.phases_rad.get(q, 0.0))
        return out


def sweep_angles(revolutions: float, samples_per_revolution: int, *, jitter: float = 0.0,
                 rng=None, start_rad: float = 0.0) -> np.ndarray:
    """Output angles of a forward sweep, uneven by ``jitter`` of a step.

    Parameters
    ----------
    revolutions : float
        Output revolutions swept.
    samples_per_revolution : int
        Mean samples per revolution.
    jitter : float
        Each sample moved by up to +-jitter/2 of the mean step (0: even), < 1.
    rng : numpy.random.Generator, optional
        Default seed 0.
    start_rad : float
        The first angle [rad].

    Returns
    -------
    numpy.ndarray
        Rising angles [rad].
    """
    rng = np.random.default_rng(0) if rng is None else rng
    n = int(round(revolutions * samples_per_revolution)) + 1
    step = 2 * math.pi / samples_per_revolution
    k = np.arange(n, dtype=float)
    if jitter:
        k[1:-1] += jitter * (rng.random(n - 2) - 0.5)
    return start_rad + k * step


def _format(values, digits, decimal_comma):
    text = [f"{v:.{digits}f}" for v in np.asarray(values, float)]
    return [s.replace(".", ",") for s in text] if decimal_comma else text


def write_csv(path, columns: dict, *, comments: dict | None = None, delimiter: str = ",",
              digits: int = 7) -> Path:
    """A recording's CSV.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (written as UTF-8).
    columns : dict
        Header name -> values (numbers, or strings written as they are).
    comments : dict, optional
        ``# key: value`` lines above the header.
    delimiter : str
        "," or ";" or a tab; with another than the comma, numbers get a decimal comma.
    digits : int
        Decimals of the numbers.

    Returns
    -------
    pathlib.Path
    """
    comma = delimiter != ","
    cols = []
    for v in columns.values():
        arr = np.asarray(v)
        cols.append([str(x) for x in arr] if arr.dtype.kind in "USO"
                    else _format(arr, digits, comma))
    lines = [f"# {k}: {v}" for k, v in (comments or {}).items()]
    lines.append(delimiter.join(columns))
    lines.extend(delimiter.join(row) for row in zip(*cols))
    path = Path(path)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_te_sides(path, ripple: Ripple, *, revolutions: float = 3.0,
                   samples_per_revolution: int = 2048, offset_arcsec: float = 0.0,
                   noise_arcsec: float = 0.0, jitter: float = 0.0, rng=None,
                   angle_unit: str = "deg", te_unit: str = "arcsec",
                   comments: dict | None = None, delimiter: str = ",",
                   extra_columns: dict | None = None) -> Path:
    """Shape (a): ``output_angle, te_forward, te_backward`` at the same angles.

    Parameters
    ----------
    path : str or pathlib.Path
    ripple : Ripple
    revolutions : float
        Output revolutions of each sweep.
    samples_per_revolution : int
    offset_arcsec : float
        The file's zero offset (both directions).
    noise_arcsec : float
        Encoder noise, standard deviation [arcsec].
    jitter : float
        Uneven angle steps (:func:`sweep_angles`).
    rng : numpy.random.Generator, optional
    angle_unit, te_unit : str
        Suffixes (:data:`.columns.ANGLE_UNITS`).
    comments : dict, optional
        Header comments (e.g. the condition).
    delimiter : str
        As :func:`write_csv`.
    extra_columns : dict, optional
        name -> a value for every row (a condition column).

    Returns
    -------
    pathlib.Path
    """
    rng = np.random.default_rng(0) if rng is None else rng
    a = sweep_angles(revolutions, samples_per_revolution, jitter=jitter, rng=rng)
    fwd = ripple.te_arcsec(a, 1) + offset_arcsec + noise_arcsec * rng.standard_normal(a.size)
    bwd = ripple.te_arcsec(a, -1) + offset_arcsec + noise_arcsec * rng.standard_normal(a.size)
    to_angle, to_te = 1 / ANGLE_UNITS[angle_unit], ANGLE_UNITS["arcsec"] / ANGLE_UNITS[te_unit]
    cols = {f"output_angle_{angle_unit}": a * to_angle,
            f"te_forward_{te_unit}": fwd * to_te, f"te_backward_{te_unit}": bwd * to_te}
    for k, v in (extra_columns or {}).items():
        cols[k] = np.full(a.size, v)
    return write_csv(path, cols, comments=comments, delimiter=delimiter)


def write_te_long(path, sweeps, *, revolutions: float = 3.0,
                  samples_per_revolution: int = 2048, offset_arcsec: float = 0.0,
                  noise_arcsec: float = 0.0, jitter: float = 0.0, rng=None,
                  angle_unit: str = "deg", te_unit: str = "arcsec",
                  direction_words: bool = False, comments: dict | None = None,
                  delimiter: str = ",", torque_noise_Nm: float = 0.0) -> Path:
    """Shape (b): sweeps one after another in a long table with a direction column.

    Parameters
    ----------
    path : str or pathlib.Path
    sweeps : sequence of (Ripple, int, float or None)
        Each sweep's TE, direction (+1 forward: the angle rises from 0; -1 backward: it
        falls back to 0) and output torque [N m] (None: no torque column).
    revolutions : float
        Output revolutions of each sweep.
    samples_per_revolution : int
    offset_arcsec : float
        The file's zero offset.
    noise_arcsec : float
        Encoder noise [arcsec].
    jitter : float
        Uneven angle steps.
    rng : numpy.random.Generator, optional
    angle_unit, te_unit : str
        Suffixes.
    direction_words : bool
        ``forward``/``backward`` instead of +1/-1.
    comments : dict, optional
    delimiter : str
    torque_noise_Nm : float
        Noise of a logged torque column [N m].

    Returns
    -------
    pathlib.Path
    """
    rng = np.random.default_rng(0) if rng is None else rng
    angle, te, dirs, torque = [], [], [], []
    for ripple, d, t in sweeps:
        a = sweep_angles(revolutions, samples_per_revolution, jitter=jitter, rng=rng)
        if d < 0:
            a = a[::-1]
        angle.append(a)
        te.append(ripple.te_arcsec(a, d) + offset_arcsec
                  + noise_arcsec * rng.standard_normal(a.size))
        word = ("forward" if d > 0 else "backward") if direction_words else \
            ("1" if d > 0 else "-1")
        dirs.append(np.full(a.size, word))
        torque.append(np.full(a.size, np.nan if t is None else t)
                      + torque_noise_Nm * rng.standard_normal(a.size))
    to_angle, to_te = 1 / ANGLE_UNITS[angle_unit], ANGLE_UNITS["arcsec"] / ANGLE_UNITS[te_unit]
    cols = {f"output_angle_{angle_unit}": np.concatenate(angle) * to_angle,
            f"te_{te_unit}": np.concatenate(te) * to_te,
            "direction": np.concatenate(dirs)}
    if any(t is not None for _, _, t in sweeps):
        cols["output_torque_Nm"] = np.concatenate(torque)
    return write_csv(path, cols, comments=comments, delimiter=delimiter)


def write_hysteresis(path, samples: dict, *, twist_unit: str = "arcmin",
                     with_branch: bool = False, comments: dict | None = None,
                     delimiter: str = ",", offset_arcmin: float = 0.0) -> Path:
    """A hysteresis recording: ``output_torque_Nm, twist_<unit>`` (and ``branch``).

    Parameters
    ----------
    path : str or pathlib.Path
    samples : dict
        From :meth:`Loop.samples`.
    twist_unit : str
        Suffix of the twist column.
    with_branch : bool
        Write the branch column (+1/-1).
    comments : dict, optional
    delimiter : str
    offset_arcmin : float
        The file's zero offset of the twist.

    Returns
    -------
    pathlib.Path
    """
    twist = (np.asarray(samples["twist_arcmin"]) + offset_arcmin) \
        * ANGLE_UNITS["arcmin"] / ANGLE_UNITS[twist_unit]
    cols = {"output_torque_Nm": samples["torque_Nm"], f"twist_{twist_unit}": twist}
    if with_branch:
        cols["branch"] = np.array([str(int(b)) for b in samples["branch"]])
    return write_csv(path, cols, comments=comments, delimiter=delimiter, digits=8)


@dataclass(frozen=True, kw_only=True)
class RunningRig:
    """A running TE rig's recordings as production rigs write them: one file per output
    torque (the brake opposing the motion both ways), each re-zeroed, each holding short
    windows scattered over part of a turn, forward and backward at other angles."""
    loop: Loop                                # the elastic curve, play and friction width
    ripple: Ripple                            # the mesh orders (its width and level unused)
    once_per_turn_arcsec: float = 20.0        # the rig's / output's eccentricity
    once_per_turn_phase_rad: float = 0.7
    windows_per_direction: int = 8
    window_deg: float = 1.0
    samples_per_window: int = 100
    spread_revolutions: float = 0.75          # the windows' angles within this part of a turn
    noise_arcsec: float = 1.0
    offset_sigma_arcsec: float = 30.0         # each file's zero

    def width_arcsec(self, torque_Nm: float) -> float:
        """The true width at the torque: 2 x the elastic curve + the friction width.

        Parameters
        ----------
        torque_Nm : float
            Its size counts (the brake opposes the motion both ways).

        Returns
        -------
        float
            [arcsec]
        """
        t = abs(float(torque_Nm))
        side = self.loop.elastic_arcmin(t, 1) - self.loop.elastic_arcmin(-t, -1)
        return 60.0 * (side + self.loop.friction_width_arcmin)

    def truth(self) -> dict:
        """The figures a reading of the widths must find above the knee.

        Returns
        -------
        dict
            ``rigidity_Nm_per_arcmin`` 1/c2, ``lost_motion_intercept_arcmin`` b + w + 2 knee
            (c1 - c2), ``knee_Nm``.
        """
        lp = self.loop
        c1, c2 = 1 / lp.low_rigidity_Nm_per_arcmin, 1 / lp.rigidity_Nm_per_arcmin
        knee = lp.knee_fraction * lp.rated_torque_Nm
        return {"rigidity_Nm_per_arcmin": lp.rigidity_Nm_per_arcmin,
                "lost_motion_intercept_arcmin": lp.backlash_arcmin
                + lp.friction_width_arcmin + 2 * knee * (c1 - c2),
                "knee_Nm": knee}

    def write(self, folder, torques_Nm, *, rng=None, comments: dict | None = None) -> list:
        """One file ``te_<T>Nm.csv`` per torque (shape B: output_angle_deg, direction,
        te_arcsec; the torque in a ``# output_torque_Nm:`` line).

        Parameters
        ----------
        folder : str or pathlib.Path
            An existing folder.
        torques_Nm : sequence of float
            Output torques >= 0.
        rng : numpy.random.Generator, optional
            Default seed 0.
        comments : dict, optional
            More ``# key: value`` lines (the provenance).

        Returns
        -------
        list of pathlib.Path
        """
        rng = np.random.default_rng(0) if rng is None else rng
        span = math.radians(self.window_deg)
        out = []
        for t in torques_Nm:
            angles, dirs, te = [], [], []
            offset = rng.normal(0.0, self.offset_sigma_arcsec)
            for d in (1, -1):
                starts = rng.uniform(0, 2 * math.pi * self.spread_revolutions,
                                     self.windows_per_direction)
                for a0 in np.sort(starts)[::d]:
                    a = a0 + d * np.linspace(0, span, self.samples_per_window)
                    level = 0.5 * d * self.width_arcsec(t)
                    y = (level + offset + self.ripple.te_arcsec(a, d) - self.ripple.level_arcsec
                         - 0.5 * d * self.ripple.width_arcsec
                         + self.once_per_turn_arcsec * np.sin(a + self.once_per_turn_phase_rad)
                         + rng.normal(0.0, self.noise_arcsec, a.size))
                    angles.append(np.degrees(a))
                    dirs.append(np.full(a.size, "forward" if d > 0 else "backward"))
                    te.append(y)
            path = Path(folder) / f"te_{t:g}Nm.csv"
            write_csv(path, {"output_angle_deg": np.concatenate(angles),
                             "direction": np.concatenate(dirs),
                             "te_arcsec": np.concatenate(te)},
                      comments={**(comments or {}), "output_torque_Nm": f"{t:g}",
                                "zero_offset_arcsec": f"{offset:.3f} (this file)"},
                      digits=4)
            out.append(path)
        return out
