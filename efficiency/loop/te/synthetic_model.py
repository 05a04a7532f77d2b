"""Synthetic rig recordings from the system model with an undeclared effect (issue 24,
item 5): what a TE and hysteresis rig would log of a reducer whose crank bearings have
play, or one of whose cranks is off its eccentricity, so that a fit of the model's effects
(:mod:`.model`) can be checked against a known answer (docs/te_model.md).

(The analytic recordings with closed-form figures are :mod:`.synthetic`'s; these come from
the reducer model itself.)

**Noise model** (:class:`Noise`), stated in every file's header:

- the TE and twist readings carry white Gaussian encoder noise, ``te_noise_arcsec`` rms per
  reading (default 1 arcsec) and ``twist_noise_arcmin`` (default 1 arcsec);
- each file carries one zero offset (the encoders zeroed before it), drawn normal with
  ``zero_offset_sigma_arcsec`` (default 30 arcsec), the same for both directions of a file;
- optionally one re-zeroing (``rezero_at``, ``rezero_offset_arcsec``): in the per-torque
  files an extra offset on that file; in the long table an extra offset from that sweep
  (one torque level, both directions) on, the encoders re-zeroed between torque levels;
- the torque readings of the hysteresis staircase carry ``torque_noise_Nm`` rms.

**Files** (UTF-8, ``# key: value`` header comments: ``synthetic``, the case, the effect and
its true value, the noise and this file's offset, then the condition; each written to a
temporary file in the folder and renamed, so no reader sees half a file):

- (A) ``te_<T>Nm.csv``, one per torque level: ``output_angle_deg, te_forward_arcsec,
  te_backward_arcsec`` at the same angles, with ``# output_torque_Nm``, ``#
  input_speed_rpm``, ``# oil_temp_C``;
- (B) ``te_long.csv``: ``output_angle_deg, direction, output_torque_Nm, te_arcsec``, each
  torque level's forward sweep (angle rising, direction +1) then its backward sweep (angle
  falling back, -1);
- ``hysteresis.csv``: ``output_torque_Nm, twist_arcmin, direction``, ``samples_per_step``
  readings per step of the staircase 0 -> +T -> -T -> +T (direction +1 where the torque
  rises, -1 where it falls; the virgin rise +1).

The TE of a sweep is the model's over its period (:class:`.model.ModelTe`) repeated over
``revolutions`` output revolutions, at the model's own angle grid (or, with
``samples_per_revolution``, interpolated onto an even grid: an order above half that rate
aliases).
"""
from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypedDict

import numpy as np

from ....errors import CaseError
from ....fem.datasheet.twist import ARCMIN, ARCSEC
from ...evaluation import operating_point
from .model import Effects, ModelLoop, ModelTe, RecordingModel

#: Encoder noise of one TE reading [arcsec rms]: a rig's output encoder (about 0.1-0.3
#: arcsec resolution) with its interpolation error and the shafts' vibration (ASSUMPTION).
TE_NOISE_ARCSEC = 1.0
#: The spread of a file's zero offset [arcsec] (the encoders zeroed at an arbitrary
#: angle before each file; ASSUMPTION of tens of arcsec).
ZERO_OFFSET_SIGMA_ARCSEC = 30.0
#: Noise of one twist reading of the hysteresis staircase [arcmin rms]: 1 arcsec.
TWIST_NOISE_ARCMIN = 1.0 / 60.0
#: Readings per step of the hysteresis staircase (a rig logs a settled step some tens of
#: times).
SAMPLES_PER_STEP = 20
#: Output revolutions per TE sweep: two let a spectrum's Hann window tell orders one
#: apart (Zc = 39 from Zb = 40; :mod:`.spectrum`).
REVOLUTIONS = 2
#: The oil temperature the headers state [deg C] (the model has none; a rig's usual
#: warm state, ASSUMPTION).
OIL_TEMP_C = 40.0
#: Decimals written: 1e-6 deg of angle, 1e-4 arcsec of TE, 1e-6 arcmin of twist, 1e-4 N m
#: (far below the noise).
DIGITS = {"angle": 6, "te": 4, "twist": 6, "torque": 4}


@dataclass(frozen=True, kw_only=True)
class Noise:
    """The rig's noise (module docstring); ``seed`` makes it repeatable."""
    te_noise_arcsec: float = TE_NOISE_ARCSEC
    zero_offset_sigma_arcsec: float = ZERO_OFFSET_SIGMA_ARCSEC
    twist_noise_arcmin: float = TWIST_NOISE_ARCMIN
    torque_noise_Nm: float = 0.0
    rezero_at: int | None = None
    rezero_offset_arcsec: float = 0.0
    seed: int = 0

    def __post_init__(self):
        for name in ("te_noise_arcsec", "zero_offset_sigma_arcsec", "twist_noise_arcmin",
                     "torque_noise_Nm"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise CaseError(f"{name} = {v!r}: >= 0 and finite")
        if not math.isfinite(self.rezero_offset_arcsec):
            raise CaseError(f"rezero_offset_arcsec = {self.rezero_offset_arcsec!r}: finite")

    def describe(self) -> str:
        """The noise model in one line (the headers' ``noise``).

        Returns
        -------
        str
        """
        return (f"white Gaussian encoder noise {self.te_noise_arcsec:g} arcsec rms per TE "
                f"reading and {self.twist_noise_arcmin:g} arcmin per twist reading; torque "
                f"{self.torque_noise_Nm:g} N m rms; a zero offset per file, normal with "
                f"sigma {self.zero_offset_sigma_arcsec:g} arcsec (both directions alike); "
                f"seed {self.seed}")


@dataclass(frozen=True, kw_only=True)
class SyntheticRecordings:
    """What :func:`write_synthetic_recordings` wrote, and the truth behind it."""
    folder: Path
    te_files: tuple                  # shape (A), one per torque
    long_file: Path | None           # shape (B)
    hysteresis_file: Path | None
    effects: Effects
    te_offsets_arcsec: tuple         # each (A) file's zero offset, re-zeroing included
    long_offsets_arcsec: tuple       # each torque level's offset in the (B) file
    hysteresis_offset_arcmin: float
    loop: ModelLoop | None = field(repr=False, default=None)
    te: tuple = field(repr=False, default=())


def write_atomic(path, text: str) -> Path:
    """``text`` into ``path`` through a temporary file in its folder, then renamed (a
    reader never sees half a file; a failed write leaves no partial file).

    Parameters
    ----------
    path : str or pathlib.Path
    text : str
        Written as UTF-8.

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        with _suppress():
            os.unlink(tmp)
        raise
    return path


class _suppress:
    """Ignore an OSError (removing a temporary file that may already be gone)."""

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        return kind is not None and issubclass(kind, OSError)


def _csv(header, columns, digits, comments) -> str:
    """The text of a recording: ``# key: value`` lines, the header, the rows."""
    lines = [f"# {k}: {v}" for k, v in comments.items()]
    lines.append(",".join(header))
    cols = []
    for col, d in zip(columns, digits):
        arr = np.asarray(col)
        cols.append([str(x) for x in arr] if d is None else [f"{x:.{d}f}" for x in arr])
    lines.extend(",".join(row) for row in zip(*cols))
    return "\n".join(lines) + "\n"


def sweep(te: ModelTe, direction: int, revolutions: float,
          samples_per_revolution: int | None = None):
    """The model's TE of one direction repeated over ``revolutions`` output revolutions.

    Parameters
    ----------
    te : ModelTe
    direction : {1, -1}
    revolutions : float
        > 0.
    samples_per_revolution : int, optional
        An even grid (the TE interpolated, periodic); None the model's own grid.

    Returns
    -------
    output_angle_rad, te_rad : numpy.ndarray
        The angles rising from 0.
    """
    if not (revolutions > 0 and math.isfinite(revolutions)):
        raise CaseError(f"revolutions = {revolutions!r}: > 0 and finite")
    values = te.te_forward_rad if direction > 0 else te.te_backward_rad
    period = te.period_output_rad
    span = 2 * math.pi * revolutions
    if samples_per_revolution is None:
        copies = int(math.ceil(span / period - 1e-9))
        angle = (te.output_angle_rad[None, :] + period * np.arange(copies)[:, None]).ravel()
        keep = angle < span * (1 - 1e-12)
        return angle[keep], np.tile(values, copies)[keep]
    n = int(round(samples_per_revolution * revolutions))
    angle = np.arange(n) * (2 * math.pi / int(samples_per_revolution))
    return angle, np.interp(angle, te.output_angle_rad, values, period=period)


def _offsets(noise: Noise, count: int, rng) -> np.ndarray:
    """Each file's (or torque level's) zero offset [arcsec]."""
    return noise.zero_offset_sigma_arcsec * rng.standard_normal(count)


def _fmt_torque(t: float) -> str:
    """A torque for a file name: 412 -> "412", 2.5 -> "2p5"."""
    text = f"{t:.6g}"
    return text.replace(".", "p").replace("-", "m")


def write_te_per_torque(folder, tes, *, noise: Noise, rng, header: dict,
                        revolutions: float = REVOLUTIONS, input_speed_rpm: float,
                        oil_temp_C: float = OIL_TEMP_C,
                        samples_per_revolution: int | None = None) -> tuple:
    """Shape (A): one file per torque level, both directions side by side.

    Parameters
    ----------
    folder : pathlib.Path
    tes : sequence of ModelTe
    noise : Noise
        ``rezero_at``: the index of the file given ``rezero_offset_arcsec`` more.
    rng : numpy.random.Generator
    header : dict
        The comments every file starts with (synthetic, case, effect, noise).
    revolutions, samples_per_revolution
        As :func:`sweep`.
    input_speed_rpm, oil_temp_C : float
        The condition the headers state.

    Returns
    -------
    (tuple of pathlib.Path, tuple of float)
        The files and each one's zero offset [arcsec].
    """
    offsets = _offsets(noise, len(tes), rng)
    if noise.rezero_at is not None:
        offsets[int(noise.rezero_at)] += noise.rezero_offset_arcsec
    paths = []
    for i, te in enumerate(tes):
        angle, fwd = sweep(te, 1, revolutions, samples_per_revolution)
        _, bwd = sweep(te, -1, revolutions, samples_per_revolution)
        fwd = fwd / ARCSEC + offsets[i] + noise.te_noise_arcsec * rng.standard_normal(fwd.size)
        bwd = bwd / ARCSEC + offsets[i] + noise.te_noise_arcsec * rng.standard_normal(bwd.size)
        comments = {**header, "zero_offset_arcsec": f"{offsets[i]:.4f} (this file"
                    + (", re-zeroed" if noise.rezero_at == i else "") + ")",
                    "output_torque_Nm": f"{te.output_torque_Nm:g}",
                    "input_speed_rpm": f"{input_speed_rpm:g}", "oil_temp_C": f"{oil_temp_C:g}"}
        text = _csv(("output_angle_deg", "te_forward_arcsec", "te_backward_arcsec"),
                    (np.degrees(angle), fwd, bwd),
                    (DIGITS["angle"], DIGITS["te"], DIGITS["te"]), comments)
        paths.append(write_atomic(Path(folder) / f"te_{_fmt_torque(te.output_torque_Nm)}Nm.csv",
                                  text))
    return tuple(paths), tuple(float(x) for x in offsets)


#: The running-rig shape ("W"): windows a direction, each of this span of output
#: [deg] read every 0.01 deg, their starts spread over this part of a turn, and the rig's
#: once-per-turn (its encoder's eccentricity) [arcsec] and phase [rad].
WINDOWS_PER_DIRECTION = 24
WINDOW_DEG = 1.0
WINDOW_STEP_DEG = 0.02
WINDOW_SPREAD_REVOLUTIONS = 0.75
ONCE_PER_TURN_ARCSEC = 20.0
ONCE_PER_TURN_PHASE_RAD = 0.7


def write_te_windows(folder, tes, *, noise: Noise, rng, header: dict,
                     input_speed_rpm: float, oil_temp_C: float = OIL_TEMP_C) -> tuple:
    """Shape (W), as production rigs write it: one file per torque (shape B's columns),
    each re-zeroed, each holding short windows scattered over part of a turn, forward and
    backward at other angles, with the rig's once-per-turn (:data:`WINDOWS_PER_DIRECTION`
    and the other constants above).

    Parameters
    ----------
    folder : pathlib.Path
    tes : sequence of ModelTe
    noise, rng, header, input_speed_rpm, oil_temp_C
        As :func:`write_te_per_torque`.

    Returns
    -------
    (tuple of pathlib.Path, tuple of float)
        The files and each one's zero offset [arcsec].
    """
    offsets = _offsets(noise, len(tes), rng)
    per_window = int(round(WINDOW_DEG / WINDOW_STEP_DEG)) + 1
    paths = []
    for i, te in enumerate(tes):
        angles, dirs, values = [], [], []
        for d in (1, -1):
            full_a, full_te = sweep(te, d, 1.0, int(round(360 / WINDOW_STEP_DEG)))
            starts = np.sort(rng.uniform(0.0, 360.0 * WINDOW_SPREAD_REVOLUTIONS,
                                         WINDOWS_PER_DIRECTION))[::d]
            for a0 in starts:
                a = np.radians(a0 + d * WINDOW_STEP_DEG * np.arange(per_window))
                y = np.interp(np.mod(a, 2 * math.pi), full_a, full_te, period=2 * math.pi)
                y = (y / ARCSEC + offsets[i]
                     + ONCE_PER_TURN_ARCSEC * np.sin(a + ONCE_PER_TURN_PHASE_RAD)
                     + noise.te_noise_arcsec * rng.standard_normal(a.size))
                angles.append(np.degrees(a))
                dirs.append(np.full(a.size, d))
                values.append(y)
        comments = {**header, "zero_offset_arcsec": f"{offsets[i]:.4f} (this file)",
                    "once_per_turn_arcsec": f"{ONCE_PER_TURN_ARCSEC:g} (the rig's)",
                    "output_torque_Nm": f"{te.output_torque_Nm:g}",
                    "input_speed_rpm": f"{input_speed_rpm:g}", "oil_temp_C": f"{oil_temp_C:g}"}
        text = _csv(("output_angle_deg", "direction", "te_arcsec"),
                    (np.concatenate(angles), np.concatenate(dirs), np.concatenate(values)),
                    (DIGITS["angle"], 0, DIGITS["te"]), comments)
        paths.append(write_atomic(Path(folder) / f"te_{_fmt_torque(te.output_torque_Nm)}Nm.csv",
                                  text))
    return tuple(paths), tuple(float(x) for x in offsets)


def write_te_long(path, tes, *, noise: Noise, rng, header: dict,
                  revolutions: float = REVOLUTIONS, input_speed_rpm: float,
                  oil_temp_C: float = OIL_TEMP_C,
                  samples_per_revolution: int | None = None) -> tuple:
    """Shape (B): one long table, each torque level's forward sweep then its backward sweep
    (the angle falling back); one zero offset for the file, and with ``rezero_at`` the
    extra offset from that torque level on.

    Parameters
    ----------
    path : pathlib.Path
    tes : sequence of ModelTe
    noise, rng, header, revolutions, input_speed_rpm, oil_temp_C, samples_per_revolution
        As :func:`write_te_per_torque`.

    Returns
    -------
    (pathlib.Path, tuple of float)
        The file and each torque level's zero offset [arcsec].
    """
    base = float(_offsets(noise, 1, rng)[0])
    offsets = []
    angle_c, dir_c, torque_c, te_c = [], [], [], []
    for i, te in enumerate(tes):
        off = base + (noise.rezero_offset_arcsec if noise.rezero_at is not None
                      and i >= int(noise.rezero_at) else 0.0)
        offsets.append(off)
        for d in (1, -1):
            angle, values = sweep(te, d, revolutions, samples_per_revolution)
            if d < 0:
                angle, values = angle[::-1], values[::-1]
            angle_c.append(np.degrees(angle))
            dir_c.append(np.full(angle.size, "1" if d > 0 else "-1"))
            torque_c.append(np.full(angle.size, te.output_torque_Nm))
            te_c.append(values / ARCSEC + off
                        + noise.te_noise_arcsec * rng.standard_normal(angle.size))
    comments = {**header, "zero_offset_arcsec": f"{base:.4f} (this file)"
                + ("" if noise.rezero_at is None else
                   f"; re-zeroed by {noise.rezero_offset_arcsec:g} arcsec more from torque "
                   f"level {int(noise.rezero_at)} on"),
                "input_speed_rpm": f"{input_speed_rpm:g}", "oil_temp_C": f"{oil_temp_C:g}"}
    text = _csv(("output_angle_deg", "direction", "output_torque_Nm", "te_arcsec"),
                (np.concatenate(angle_c), np.concatenate(dir_c), np.concatenate(torque_c),
                 np.concatenate(te_c)),
                (DIGITS["angle"], None, DIGITS["torque"], DIGITS["te"]), comments)
    return write_atomic(path, text), tuple(offsets)


def write_hysteresis(path, loop: ModelLoop, *, noise: Noise, rng, header: dict,
                     samples_per_step: int = SAMPLES_PER_STEP) -> tuple:
    """The hysteresis staircase: ``samples_per_step`` readings of each step.

    Parameters
    ----------
    path : pathlib.Path
    loop : ModelLoop
    noise : Noise
    rng : numpy.random.Generator
    header : dict
    samples_per_step : int
        >= 1.

    Returns
    -------
    (pathlib.Path, float)
        The file and its zero offset [arcmin].
    """
    n = int(samples_per_step)
    if n < 1:
        raise CaseError(f"samples_per_step = {samples_per_step!r}: >= 1")
    offset = float(_offsets(noise, 1, rng)[0]) * ARCSEC / ARCMIN
    step = np.repeat(np.arange(loop.torque_Nm.size), n)
    torque = loop.torque_Nm[step] + noise.torque_noise_Nm * rng.standard_normal(step.size)
    twist = loop.twist_arcmin[step] + offset \
        + noise.twist_noise_arcmin * rng.standard_normal(step.size)
    direction = np.array([f"{int(b)}" for b in loop.branch[step]])
    comments = {**header, "zero_offset_arcmin": f"{offset:.6f} (this file)",
                "rated_torque_Nm": f"{loop.rated_torque_Nm:g}",
                "staircase": "0 -> +T -> -T -> +T, input held, "
                             f"{n} readings per step"}
    text = _csv(("output_torque_Nm", "twist_arcmin", "direction"), (torque, twist, direction),
                (DIGITS["torque"], DIGITS["twist"], None), comments)
    return write_atomic(path, text), offset


class _SweepOptions(TypedDict):
    """The TE files' sweep and condition keywords (:func:`write_te_per_torque`,
    :func:`write_te_long`)."""
    revolutions: float
    input_speed_rpm: float
    oil_temp_C: float
    samples_per_revolution: int | None


def write_synthetic_recordings(folder, case, effects: Effects, torques_Nm, *,
                               noise: Noise | None = None, revolutions: float = REVOLUTIONS,
                               samples_per_revolution: int | None = None,
                               samples_per_step: int = SAMPLES_PER_STEP,
                               input_speed_rpm: float | None = None,
                               oil_temp_C: float = OIL_TEMP_C, model: RecordingModel | None = None,
                               te_samples: int | None = None, shapes=("A", "B", "hysteresis"),
                               **loop_options) -> SyntheticRecordings:
    """Rig-like recordings of a case's model with undeclared effects, with noise.

    Parameters
    ----------
    folder : str or pathlib.Path
        Created if missing.
    case : toothfem.case.Case or path
    effects : Effects
        The undeclared effect(s) and their true values (the headers state them).
    torques_Nm : sequence of float
        The TE's torque levels [N m], >= 0.
    noise : Noise, optional
        Default :class:`Noise` ().
    revolutions, samples_per_revolution
        Of each TE sweep (:func:`sweep`).
    samples_per_step : int
        Readings per staircase step.
    input_speed_rpm : float, optional
        The condition the TE headers state (default the case's operating input speed).
    oil_temp_C : float
        Likewise.
    model : RecordingModel, optional
        A model of the case already set up (its tables in memory).
    te_samples : int, optional
        Sampled pitches of the TE (:meth:`RecordingModel.te`).
    shapes : sequence of {"A", "B", "W", "hysteresis"}
        The files to write (A and W both write one file per torque: give one of them).
    **loop_options
        Go to :meth:`RecordingModel.hysteresis` (``torque_max_Nm``, ``fractions``, ...).

    Returns
    -------
    SyntheticRecordings

    Raises
    ------
    CaseError
        For an unknown shape, a re-zeroing index out of range, or what the model refuses.
    """
    noise = Noise() if noise is None else noise
    unknown = set(shapes) - {"A", "B", "W", "hysteresis"}
    if unknown:
        raise CaseError(f"shapes {sorted(unknown)}: known are A, B, W, hysteresis")
    torques = [float(t) for t in torques_Nm]
    if noise.rezero_at is not None and not 0 <= int(noise.rezero_at) < len(torques):
        raise CaseError(f"rezero_at = {noise.rezero_at!r}: a torque level's index, 0 to "
                        f"{len(torques) - 1}")
    model = RecordingModel(case) if model is None else model
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(noise.seed)
    speed = float(operating_point(model.si)[0] if input_speed_rpm is None
                  else input_speed_rpm)
    truth = effects.describe()
    header = {"synthetic": "toothfem system model (efficiency/loop/te/synthetic_model.py), "
                           "not a measurement",
              "case": model.case.name,
              "effect": "; ".join(f"{k} = {v}" for k, v in truth.items()) or "none",
              "noise": noise.describe()}
    tes = model.te(effects, torques, samples=te_samples) if {"A", "B", "W"} & set(shapes) \
        else ()
    opts: _SweepOptions = {"revolutions": revolutions, "input_speed_rpm": speed,
                           "oil_temp_C": oil_temp_C,
                           "samples_per_revolution": samples_per_revolution}
    files, offsets, long_file, long_offsets = (), (), None, ()
    if "A" in shapes:
        files, offsets = write_te_per_torque(folder, tes, noise=noise, rng=rng,
                                             header=header, **opts)
    if "W" in shapes:
        files, offsets = write_te_windows(folder, tes, noise=noise, rng=rng, header=header,
                                          input_speed_rpm=speed, oil_temp_C=oil_temp_C)
    if "B" in shapes:
        long_file, long_offsets = write_te_long(folder / "te_long.csv", tes, noise=noise,
                                                rng=rng, header=header, **opts)
    loop, hyst, h_off = None, None, 0.0
    if "hysteresis" in shapes:
        loop = model.hysteresis(effects, **loop_options)
        hyst, h_off = write_hysteresis(folder / "hysteresis.csv", loop, noise=noise, rng=rng,
                                       header=header, samples_per_step=samples_per_step)
    return SyntheticRecordings(folder=folder, te_files=files, long_file=long_file,
                               hysteresis_file=hyst, effects=effects,
                               te_offsets_arcsec=offsets, long_offsets_arcsec=long_offsets,
                               hysteresis_offset_arcmin=h_off, loop=loop, te=tuple(tes))
