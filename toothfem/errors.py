"""Exception types, one per concern, and the range check that names the parameter.

Library code raises these; only the CLI turns them into a message and an exit code.
"""
from __future__ import annotations

import decimal
import math
import os

import numpy as np


class ToothfemError(ValueError):
    """Base class of every error toothfem raises on bad input.

    Errors raised by :func:`check_range` carry the parts of their message (``param``,
    ``value``, ``lo``, ``hi``, ``lo_open``, ``hi_open``, ``why``) so that a caller can
    restate them in its own names and units (the case model names its TOML keys).
    """

    param = None

    def restated(self, name: str, scale: float = 1.0, error=None):
        """The same range error for parameter ``name`` in units ``scale`` x SI.

        Parameters
        ----------
        name : str
            The parameter's name as the caller knows it (a TOML key).
        scale : float
            The caller's unit per SI unit (1e3 for mm).
        error : type, optional
            The exception type; default this error's.

        Returns
        -------
        ToothfemError
            The new error (not raised); without range parts, the same message.
        """
        if self.param is None:
            return (error or type(self))(str(self))
        return _range_error(name, self.value * scale,
                            None if self.lo is None else self.lo * scale,
                            None if self.hi is None else self.hi * scale,
                            self.lo_open, self.hi_open, self.why, error or type(self))


class CaseError(ToothfemError):
    """A case file or mapping is malformed or holds an impossible value."""


class GeometryError(ToothfemError):
    """Geometry parameters that give a looped, cusped, undercut or interfering profile."""


class MissingExtra(ToothfemError, ImportError):
    """An optional extra of the package (``pip install 'toothfem[NAME]'``) that a writer
    needs is not installed (an ImportError too, so ``except ImportError`` still sees it)."""


class Terminated(BaseException):
    """SIGTERM, raised in the main thread by the CLI's handler so that ``with`` blocks
    unwind (a BaseException, like KeyboardInterrupt: ``except Exception`` in library code
    does not swallow it)."""


class IncompleteRun(ToothfemError):
    """A long run that did not finish every point (a failed point, a lost cluster); what
    finished is kept (toothfem.output.resumable_dir)."""


class MeasuredDataError(ToothfemError):
    """Measured data that cannot be read: a bad header, no good row, or (strict) a bad row."""


def decode_text(raw: bytes, path, error=ToothfemError) -> str:
    """UTF-8 text of a file's bytes; a UTF-8 byte-order mark is dropped (spreadsheet and
    Windows editors write one). Other encodings are refused in one line that names the
    file and the first bad byte, its line and column (issue 14, item 1).

    Parameters
    ----------
    raw : bytes
        The file's content.
    path : str or pathlib.Path
        The file, for the message.
    error : type
        The exception type raised.

    Returns
    -------
    str
        The text.

    Raises
    ------
    ToothfemError
        (``error``) for UTF-16 or other non-UTF-8 bytes.
    """
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise error(f"{path}: is UTF-16 text; save it as UTF-8")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = raw[:exc.start]
        line = before.count(b"\n") + 1
        col = exc.start - (before.rfind(b"\n") + 1) + 1
        raise error(f"{path}: not UTF-8 text: byte 0x{raw[exc.start]:02x} at line {line}, "
                    f"column {col}; save the file as UTF-8") from None


def check_range(name: str, value, lo=None, hi=None, *, lo_open=False, hi_open=False,
                error=ToothfemError, why: str = ""):
    """Return ``value`` if it lies in the range, else raise ``error`` naming it.

    The message reads ``name = value is outside the valid range [lo, hi)`` plus ``why``.
    NaN and infinite values are always refused, and so are integers too large for a float
    (reported as outside the range). Strings and bools are not numbers here, even where
    ``float()`` would read them ("1.0", True): a value of the wrong type fails later with
    a message that names no parameter.

    Parameters
    ----------
    name : str
        The parameter, as the message names it.
    value : float or int
        The value (any unit; the bounds share it).
    lo, hi : float, optional
        The bounds (None: unbounded).
    lo_open, hi_open : bool
        Exclude the bound.
    error : type
        The exception type raised.
    why : str
        The reason for the range, appended to the message.

    Returns
    -------
    float or int
        ``value`` itself.

    Raises
    ------
    ToothfemError
        (``error``) naming the parameter, its value and the valid range; it carries those
        parts (:meth:`ToothfemError.restated`).
    """
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise error(f"{name} = {value!r} is not a number")
    try:
        v = float(value)
    except OverflowError:                 # an int beyond the float range
        v = math.inf
    except (TypeError, ValueError):
        raise error(f"{name} = {value!r} is not a number") from None
    bad = not math.isfinite(v)
    if lo is not None:
        bad |= v <= lo if lo_open else v < lo
    if hi is not None:
        bad |= v >= hi if hi_open else v > hi
    if bad:
        raise _range_error(name, value, lo, hi, lo_open, hi_open, why, error)
    return value


def _fmt(x):
    """repr, except that float noise (0.0026000000000000003) is rounded to 10 digits and an
    integer of more than 15 digits is written with an exponent."""
    r = repr(x)
    if isinstance(x, int) and not isinstance(x, bool) and len(r.lstrip("-")) > 15:
        return f"{decimal.Decimal(x):.6e}"
    return f"{x:.10g}" if isinstance(x, float) and len(r) > 12 else r


def short_repr(value) -> str:
    """repr of a value for a one-line message: whitespace runs as one space, cut to 60
    characters.

    Parameters
    ----------
    value : object

    Returns
    -------
    str
    """
    r = " ".join(repr(value).split())
    return r if len(r) <= 60 else r[:57] + "..."


def _range_error(name, value, lo, hi, lo_open, hi_open, why, error):
    left = "(" if lo_open or lo is None else "["
    right = ")" if hi_open or hi is None else "]"
    lo_s = "-inf" if lo is None else f"{lo:.6g}"
    hi_s = "inf" if hi is None else f"{hi:.6g}"
    msg = f"{name} = {_fmt(value)} is outside the valid range {left}{lo_s}, {hi_s}{right}"
    exc = error(msg + (f": {why}" if why else ""))
    exc.param, exc.value, exc.lo, exc.hi = name, value, lo, hi
    exc.lo_open, exc.hi_open, exc.why = lo_open, hi_open, why
    return exc


def checked_array(name, value, lo=None, *, lo_open=False, hi=None, hi_open=False, why="",
                  error=ToothfemError):
    """``value`` as a float array, refused at its first bad element (the vectorised
    :func:`check_range`).

    Parameters
    ----------
    name : str
        The parameter; an element is named ``name[i,j]``.
    value : array_like
        The values.
    lo, hi : float, optional
        The bounds (None: unbounded).
    lo_open, hi_open : bool
        Exclude the bound.
    why : str
        The reason for the range.
    error : type
        The exception type raised.

    Returns
    -------
    numpy.ndarray
        The values as floats, shape of ``value``.

    Raises
    ------
    ToothfemError
        Naming the first bad element, its value and the valid range; or the value, when
        it is not numbers (strings, bools and objects are refused, even where ``float()``
        would read them).
    """
    try:
        raw = np.asarray(value)
        if raw.dtype.kind not in "iuf":    # strings, bools, objects: not numbers here
            raise TypeError
        a = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise error(f"{name} = {short_repr(value)} is not a number") from None
    bad = ~np.isfinite(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= (a >= hi) if hi_open else (a > hi)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        label = name if a.ndim == 0 else f"{name}[{','.join(map(str, idx))}]"
        check_range(label, float(a[idx]), lo, hi, lo_open=lo_open, hi_open=hi_open, why=why,
                    error=error)
    return a


def shown(path) -> str:
    """A path as a message line may print it: bytes of another locale (surrogate
    escapes) as ``\\xNN``, never an error on a terminal of another encoding.

    Parameters
    ----------
    path : str or bytes or os.PathLike
        The path as given.

    Returns
    -------
    str
        Its text, every character encodable as UTF-8.
    """
    text = os.fspath(path)
    text = text if isinstance(text, str) else os.fsdecode(text)
    return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def angles_1d(name: str, value, error=ToothfemError) -> np.ndarray:
    """``value`` as a 1-D array of finite angles (a scalar as one), else ``error`` naming
    ``name``, the shape given and the shapes taken.

    Parameters
    ----------
    name : str
        The argument, as the message names it.
    value : array_like
        A scalar or a 1-D sequence of numbers.
    error : type
        The exception type raised.

    Returns
    -------
    numpy.ndarray
        Shape (P,).
    """
    a = np.atleast_1d(checked_array(name, value, error=error))
    if a.ndim != 1:
        raise error(f"{name} has shape {a.shape}; valid: a scalar or a 1-D array of angles "
                    "(np.ravel a grid of them)")
    return a


def of_type(name: str, value, kind: type, hint: str, error=ToothfemError):
    """``value`` if it is a ``kind``, else ``error`` naming ``name``, what it is and
    ``hint`` (where such a value comes from, e.g. ``case.cycloid.geometry()``).

    Parameters
    ----------
    name : str
        The argument, as the message names it.
    value : object
        What was given.
    kind : type
        What belongs there.
    hint : str
        Where such a value comes from.
    error : type
        The exception type raised.

    Returns
    -------
    object
        ``value`` itself.
    """
    if not isinstance(value, kind):
        raise error(f"{name} = {type(value).__name__} is not a {kind.__name__}; valid: "
                    f"{hint}")
    return value
