"""Exception types, one per concern, and the range check that names the parameter.

Library code raises these; only the CLI turns them into a message and an exit code.
"""
from __future__ import annotations

import math


class ToothfemError(ValueError):
    """Base class of every error toothfem raises on bad input."""


class CaseError(ToothfemError):
    """A case file or mapping is malformed or holds an impossible value."""


class GeometryError(ToothfemError):
    """Geometry parameters that give a looped, cusped, undercut or interfering profile."""


def check_range(name: str, value, lo=None, hi=None, *, lo_open=False, hi_open=False,
                error=ToothfemError, why: str = ""):
    """Return ``value`` if it lies in the range, else raise ``error`` naming it.

    ``lo``/``hi`` are the bounds (None: unbounded); ``lo_open``/``hi_open`` exclude them.
    The message reads ``name = value is outside the valid range [lo, hi)`` plus ``why``.
    NaN and infinite values are always refused.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise error(f"{name} = {value!r} is not a number") from None
    bad = not math.isfinite(v)
    if lo is not None:
        bad |= v <= lo if lo_open else v < lo
    if hi is not None:
        bad |= v >= hi if hi_open else v > hi
    if bad:
        left = "(" if lo_open or lo is None else "["
        right = ")" if hi_open or hi is None else "]"
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        msg = f"{name} = {value!r} is outside the valid range {left}{lo_s}, {hi_s}{right}"
        raise error(msg + (f": {why}" if why else ""))
    return value
