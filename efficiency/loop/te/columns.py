"""The columns of a TE or hysteresis recording: quantities, units, conditions, file names.

The vocabulary of :mod:`.recordings`: which column names are known, the unit of each (the
suffix of the name) and its factor to SI; the operating condition of a run (output torque,
input speed, oil temperature) and where it may come from (a column, a ``# key: value``
comment above the header, or the file's name through a stated pattern); the words of a
direction column. The refusals are one line each and name the column.
"""
from __future__ import annotations

import math
import re
import string
from dataclasses import dataclass

from ....errors import MeasuredDataError
from ....units import RAD_S_PER_RPM, RPM_PER_RAD_S, unit
from ..measured_columns import QUANTITIES, parse_number

#: Angle units (the column-name suffix) -> radians per unit (:data:`toothfem.units.UNITS`).
ANGLE_UNITS = {s: unit(s).factor for s in ("rad", "deg", "arcmin", "arcsec")}
#: Angle quantities of the recordings, longest first (``te_forward`` before ``te``).
ANGLE_QUANTITIES = ("te_forward", "te_backward", "te", "output_angle", "twist")
#: Condition quantities: quantity -> (units as :data:`QUANTITIES` knows them, factor from
#: the canonical unit there to the one stored, the stored field's name). Speed is stored in
#: rad/s, torque in N m, oil temperature in deg C (as the efficiency loader does).
CONDITIONS = {
    "output_torque": (QUANTITIES["output_torque"], 1.0, "output_torque_Nm"),
    "input_speed": (QUANTITIES["input_speed"], RAD_S_PER_RPM, "input_speed_rad_s"),
    "oil_temp": (QUANTITIES["oil_temp"], 1.0, "oil_temp_C"),
}
#: Names of a direction (TE) or branch (hysteresis) column; either name, one vocabulary.
DIRECTION_COLUMNS = ("direction", "branch")
#: Words of a direction cell (case-insensitive) -> +1 (forward; rising torque) or -1.
DIRECTION_WORDS = {"1": 1, "+1": 1, "1.0": 1, "+1.0": 1, "forward": 1, "fwd": 1,
                   "rising": 1, "up": 1,
                   "-1": -1, "-1.0": -1, "backward": -1, "bwd": -1, "falling": -1,
                   "down": -1}
#: Two values of a condition are one operating point within this fraction of the first
#: (a logged set value repeats exactly; a measured torque or speed scatters by the sensor's
#: noise, well under 2 %, while a test plan's steps differ by far more).
CONDITION_RTOL = 0.02
#: ... or within these absolute amounts (near zero, where a fraction is no tolerance: a
#: no-load TE run's torque reads the meter's zero noise): 0.5 N m, 0.5 rpm, 1 deg C.
CONDITION_ATOL = {"output_torque_Nm": 0.5, "input_speed_rad_s": 0.5 * RAD_S_PER_RPM,
                  "oil_temp_C": 1.0}
#: A number in a file name: decimal point, decimal comma or ``p`` (``2p5`` = 2.5).
NAME_NUMBER = r"[-+]?(?:\d+(?:[.,p]\d*)?|[.,]\d+)(?:[eE][-+]?\d+)?"


@dataclass(frozen=True)
class Condition:
    """The operating condition of a run; None where the recording does not say."""
    output_torque_Nm: float | None = None
    input_speed_rad_s: float | None = None
    oil_temp_C: float | None = None

    def label(self) -> str:
        """One line: torque [N m], speed [rpm], oil temperature [deg C]; "no condition
        given" when all are unknown.

        Returns
        -------
        str
        """
        parts = []
        if self.output_torque_Nm is not None:
            parts.append(f"{self.output_torque_Nm:.4g} N m")
        if self.input_speed_rad_s is not None:
            parts.append(f"{self.input_speed_rad_s * RPM_PER_RAD_S:.4g} rpm")
        if self.oil_temp_C is not None:
            parts.append(f"{self.oil_temp_C:.4g} C")
        return ", ".join(parts) or "no condition given"

    def values(self) -> dict:
        """The fields by name.

        Returns
        -------
        dict of str to float or None
        """
        return {"output_torque_Nm": self.output_torque_Nm,
                "input_speed_rad_s": self.input_speed_rad_s, "oil_temp_C": self.oil_temp_C}

    def sort_key(self) -> tuple:
        """Sorts by torque, speed, temperature, an unknown value first.

        Returns
        -------
        tuple
        """
        return tuple((v is not None, v if v is not None else 0.0)
                     for v in self.values().values())

    def matches(self, other: Condition) -> bool:
        """Within :data:`CONDITION_RTOL` or :data:`CONDITION_ATOL` of ``other`` in every
        field (an unknown field matches only an unknown one).

        Parameters
        ----------
        other : Condition

        Returns
        -------
        bool
        """
        for name, a in self.values().items():
            b = getattr(other, name)
            if (a is None) != (b is None):
                return False
            if a is not None and not close(name, a, b):
                return False
        return True


def close(field: str, a: float, b: float) -> bool:
    """Two values of a condition field are one operating point.

    Parameters
    ----------
    field : str
        A :class:`Condition` field (its absolute tolerance).
    a, b : float
        The values, in the field's unit.

    Returns
    -------
    bool
        Within CONDITION_RTOL of the larger magnitude or CONDITION_ATOL[field].
    """
    return abs(a - b) <= max(CONDITION_RTOL * max(abs(a), abs(b)), CONDITION_ATOL[field])


def column(name: str):
    """What a column holds.

    Parameters
    ----------
    name : str
        The header's name, e.g. ``te_forward_arcsec``, ``output_torque_Nm``.

    Returns
    -------
    tuple
        (quantity, factor, offset): the value stored is ``factor * cell + offset`` (angles
        in rad, conditions in the :class:`Condition` field's unit); ("direction", None,
        None) for a direction or branch column; (None, None, None) for a column not used.

    Raises
    ------
    MeasuredDataError
        For a known quantity in a unit not known (the message names the column).
    """
    if name in DIRECTION_COLUMNS:
        return "direction", None, None
    for q in ANGLE_QUANTITIES:
        if name == q or name.startswith(q + "_"):
            unit = name[len(q) + 1:]
            if unit not in ANGLE_UNITS:
                raise MeasuredDataError(f"column {name!r}: unknown unit {unit!r} for {q}; "
                                        f"known: {', '.join(ANGLE_UNITS)}")
            return q, ANGLE_UNITS[unit], 0.0
    for q, (units, to_stored, _) in CONDITIONS.items():
        if name == q or name.startswith(q + "_"):
            unit = name[len(q) + 1:]
            if unit not in units:
                raise MeasuredDataError(f"column {name!r}: unknown unit {unit!r} for {q}; "
                                        f"known: {', '.join(units)}")
            f, o = units[unit]
            return q, f * to_stored, o * to_stored
    return None, None, None


def field_of(quantity: str) -> str:
    """The :class:`Condition` field of a condition quantity.

    Parameters
    ----------
    quantity : str
        ``output_torque``, ``input_speed`` or ``oil_temp``.

    Returns
    -------
    str
        E.g. ``output_torque_Nm``.
    """
    return CONDITIONS[quantity][2]


def direction_of(text: str):
    """+1 or -1 from a direction cell, or None if the word is not known.

    Parameters
    ----------
    text : str
        The cell (:data:`DIRECTION_WORDS`, case-insensitive).

    Returns
    -------
    int or None
    """
    return DIRECTION_WORDS.get(text.strip().lower())


def number(cell: str, name: str, factor: float, offset: float) -> float:
    """A cell's value in the stored unit.

    Parameters
    ----------
    cell : str
        The text (a decimal comma already turned into a point where the file allows it).
    name : str
        The column, for the message.
    factor, offset : float
        From :func:`column`.

    Returns
    -------
    float

    Raises
    ------
    MeasuredDataError
        For an empty, non-numeric, NaN or infinite cell: "column 'x' = '1.2y' is not a
        number", "column 'x' is empty".
    """
    try:
        v = float(cell)
    except ValueError:
        v = None
    if v is None or not math.isfinite(v):
        _, why = parse_number(cell, name)            # "<name> = '12.3x' is not a number"
        raise MeasuredDataError(f"column {name!r} {why[len(name) + 1:]}")
    return factor * v + offset


def condition_values(mapping: dict, where: str) -> dict:
    """Condition values (and a direction) from ``key: value`` pairs whose keys are column
    names with units (header comments, or a file name's fields).

    Parameters
    ----------
    mapping : dict of str to str
        E.g. {"output_torque_Nm": "100", "operator": "me"}; keys that are not a condition
        or ``direction`` are skipped.
    where : str
        What the pairs come from, for the message (e.g. "header comment").

    Returns
    -------
    dict
        :class:`Condition` field -> value (stored unit), and ``direction`` -> +1 or -1.

    Raises
    ------
    MeasuredDataError
        For a value that is not a number (not a direction word), or a condition key in an
        unknown unit.
    """
    out = {}
    for key, text in mapping.items():
        key = key.strip()
        if key in DIRECTION_COLUMNS:
            d = direction_of(str(text))
            if d is None:
                raise MeasuredDataError(f"{where} {key!r}: {text!r} is not a direction "
                                        f"({', '.join(DIRECTION_WORDS)})")
            out["direction"] = d
            continue
        if not any(key == q or key.startswith(q + "_") for q in CONDITIONS):
            continue
        try:
            q, f, o = column(key)
            out[field_of(q)] = number(str(text).replace(",", "."), key, f, o)
        except MeasuredDataError as exc:
            raise MeasuredDataError(f"{where}: {exc}") from None
    return out


def name_pattern(pattern: str):
    """A compiled file-name pattern.

    ``{field}`` is a condition column name with its unit (``{output_torque_Nm}``,
    ``{input_speed_rpm}``, ``{oil_temp_C}``) and matches a number (decimal point, decimal
    comma or ``p``); ``{direction}`` matches a direction word; ``*`` matches anything; the
    rest is literal. The whole file name (not its folder) must match.

    Parameters
    ----------
    pattern : str
        E.g. ``"te_{output_torque_Nm}Nm_{input_speed_rpm}rpm.csv"``.

    Returns
    -------
    re.Pattern
        Its groups named by the fields.

    Raises
    ------
    MeasuredDataError
        For a field that is not a condition column or ``direction``, or a field twice.
    """
    parts, seen = [], set()
    words = "|".join(re.escape(w) for w in sorted(DIRECTION_WORDS, key=len, reverse=True))
    for literal, field, spec, conv in string.Formatter().parse(pattern):
        parts.append(".*".join(re.escape(p) for p in literal.split("*")))
        if field is None:
            continue
        if spec or conv:
            raise MeasuredDataError(f"file-name pattern {pattern!r}: write {{{field}}} "
                                    "without a format")
        if field in seen:
            raise MeasuredDataError(f"file-name pattern {pattern!r}: {{{field}}} twice")
        seen.add(field)
        if field in DIRECTION_COLUMNS:
            parts.append(f"(?P<{field}>{words})")
            continue
        q = next((q for q in CONDITIONS if field == q or field.startswith(q + "_")), None)
        if q is None or not field.isidentifier():
            raise MeasuredDataError(
                f"file-name pattern {pattern!r}: {{{field}}} is not a condition column "
                f"({', '.join(k + '_<unit>' for k in CONDITIONS)}) nor direction")
        column(field)                       # refuses an unknown unit here
        parts.append(f"(?P<{field}>{NAME_NUMBER})")
    return re.compile("".join(parts), re.IGNORECASE)


def values_from_name(pattern, file_name: str, source: str) -> dict:
    """The condition values (and direction) a file's name states.

    Parameters
    ----------
    pattern : re.Pattern or None
        From :func:`name_pattern`; None: nothing.
    file_name : str
        The file's name without its folder.
    source : str
        The file, for the message.

    Returns
    -------
    dict
        As :func:`condition_values`.

    Raises
    ------
    MeasuredDataError
        If the name does not match the pattern.
    """
    if pattern is None:
        return {}
    m = pattern.fullmatch(file_name)
    if m is None:
        raise MeasuredDataError(f"{source}: the file name does not match the pattern "
                                f"{pattern.pattern!r}")
    raw = {k: v.replace("p", ".").replace("P", ".") if k not in DIRECTION_COLUMNS else v
           for k, v in m.groupdict().items()}
    return condition_values(raw, f"{source}: file-name field")
