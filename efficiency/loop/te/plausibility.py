"""Recordings in the wrong unit, refused before a fit (issue 45): a rig's TE, twist and torque
held against what the case itself predicts.

A column's unit is its name's suffix (:mod:`.columns`); a wrong suffix passes every reader's
check and then fits to thousands of sigma. Against the case:

- **torque**: a recorded output torque above :data:`TORQUE_LIMIT_RATED` times the rated torque
  (the catalogues' momentary limit is 5 times the rating at most; a staircase or a brake
  beyond it breaks the reducer) is a torque in another unit (N mm as N m: 1000x);
- **output angle**: a recording sweeps the output through a revolution, or through
  windows spread over it (the once-per-turn ripple, the mesh orders); one whose angles span
  under :data:`SHORT_SWEEP_REVOLUTIONS` of a revolution in its labelled unit while their
  numbers, read as radians, span a quarter revolution or more (pi/2 to about 2 pi) is a
  turn in radians under a deg (arcmin, arcsec) label: warned, in one line naming the
  column (the recordings' notes name each file), not refused (a short sweep in degrees is
  possible);
- **TE widths and twists**: the recordings' largest hysteresis width (or the loop's twist
  range) against the model's own at the same torques, the case as declared; a ratio beyond
  :data:`SCALE_LIMIT` either way is another unit (deg as arcsec: 3600x; arcmin as arcsec:
  60x; rad as arcsec: 1/206265), not a reducer the model misses: a real unit's rigidity and
  play are within a few times the model's.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ....errors import MeasuredDataError

#: A recorded torque beyond this multiple of the rated torque is refused (the momentary
#: limit of RV catalogues is 5x the rating; 10x leaves room for a case's own).
TORQUE_LIMIT_RATED = 10.0
#: A measured TE or twist scale this many times the model's, or its inverse, is refused (a
#: real reducer's rigidity and play are within a few times its model's; the unit slips
#: seen are 60x, 3600x, 206265x).
SCALE_LIMIT = 20.0
#: The unit slips a ratio is compared with: factor -> what it would be.
SLIPS = {60.0: "arcmin labelled arcsec (or deg labelled arcmin)",
         3600.0: "deg labelled arcsec",
         206264.8: "rad labelled arcsec",
         1 / 60.0: "arcsec labelled arcmin",
         1 / 3600.0: "arcsec labelled deg",
         1 / 206264.8: "arcsec labelled rad (or a twist in rad labelled arcmin: 1/3438)",
         1 / 3437.7: "rad labelled arcmin"}


def _likely(ratio: float) -> str:
    """The unit slip nearest to ``ratio`` (in log)."""
    best = min(SLIPS, key=lambda f: abs(np.log(ratio / f)))
    return SLIPS[best]


def check_torques(rated_torque_Nm: float, torques) -> None:
    """Refuse recorded torques beyond TORQUE_LIMIT_RATED x the rating.

    Parameters
    ----------
    rated_torque_Nm : float
    torques : iterable of (float, str)
        Each torque [N m] and where it comes from (a file, a column).

    Raises
    ------
    MeasuredDataError
        Naming the first torque too large, its source and the likely unit.
    """
    top = TORQUE_LIMIT_RATED * rated_torque_Nm
    for t, where in torques:
        if t is not None and abs(t) > top:
            raise MeasuredDataError(
                f"output_torque_Nm = {t:.6g} ({where}) is outside the valid range [-{top:.6g}, "
                f"{top:.6g}] N m ({TORQUE_LIMIT_RATED:g}x the case's rated {rated_torque_Nm:.6g}"
                " N m): a torque in another unit (N mm as N m: 1000x)?")


def check_scale(measured, model, what: str, column: str) -> None:
    """Refuse a measured scale (a width, a twist range) off the model's by more than
    SCALE_LIMIT either way.

    Parameters
    ----------
    measured, model : float
        The two scales in one unit; nothing is checked where either is not positive.
    what : str
        What the scale is (for the message).
    column : str
        The column the unit comes from.

    Raises
    ------
    MeasuredDataError
    """
    if not (measured > 0 and model > 0 and np.isfinite(measured) and np.isfinite(model)):
        return
    r = measured / model
    if r > SCALE_LIMIT or r < 1 / SCALE_LIMIT:
        raise MeasuredDataError(
            f"{column}: the recorded {what} is {r:.3g}x the case's model's ({measured:.4g} "
            f"against {model:.4g}); a reducer differs from its model by less than "
            f"{SCALE_LIMIT:g}x either way: a unit slip ({_likely(r)})?")


#: A recording's output angles spanning less than this share of a revolution in their
#: labelled unit (10 deg: about a mesh period of a 36-pin drive) are a short sweep...
SHORT_SWEEP_REVOLUTIONS = 1 / 36
#: ... and, with their numbers spanning at least this many radians (a quarter revolution),
#: likelier a turn in radians under another unit's label.
RADIAN_SPAN_MIN = math.pi / 2
#: The note :func:`angle_unit_note` writes (in report.md's notes on the recordings).
ANGLE_NOTE = "output angle in radians?"


def angle_unit_note(source, column, runs) -> tuple:
    """A note on a file whose output angles look like radians under another unit's label,
    and a warning naming the column (the same line for every file: said once).

    Parameters
    ----------
    source : str
        The file.
    column : tuple
        The output-angle column as the reader holds it: (index, radians per labelled unit,
        offset, name); its unit is the name's suffix (rad: no note).
    runs : iterable of .recordings.Run
        The file's runs (their windows' first-to-last angle spans [rad, read with the
        label]).

    Returns
    -------
    tuple of str
        One line naming the file, the column, its span and the likely unit; or none.
    """
    factor, name = column[1], column[3]
    span = max((r.windows.span_rad for r in runs), default=0.0)
    numbers = span / factor                     # the span in the column's own numbers
    if factor == 1.0 or not (span < 2 * math.pi * SHORT_SWEEP_REVOLUTIONS
                             and numbers >= RADIAN_SPAN_MIN):
        return ()
    unit = name.rsplit("_", 1)[-1]
    # the warning the same for every file (said once), the note naming the file and span
    warnings.warn(
        f"{name!r}: a recording's output angles span under {SHORT_SWEEP_REVOLUTIONS * 360:g} "
        f"deg of output while their numbers span a quarter revolution or more as radians: "
        f"radians under a {unit} label (1 rad = "
        f"{180 / math.pi:.4g} deg)? A TE recording sweeps the output through its revolution; "
        "name the column by its unit (output_angle_rad)", stacklevel=3)
    return (f"{source}: {ANGLE_NOTE} column {name!r} spans {numbers:.4g} {unit}, "
            f"{span / (2 * math.pi):.2g} of a revolution; read as rad, "
            f"{numbers / (2 * math.pi):.2g} of one",)
