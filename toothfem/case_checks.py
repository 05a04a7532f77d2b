"""What every case value must be before the case model uses it (issue 14): its type, where
it is parsed, and the plausibility bounds of the keys, the ranges a real reducer can have.

The case model (:mod:`toothfem.case`) puts these bounds in its fields' metadata; the
command-line options that stand for case keys (``--speed-rpm``, ``--torque-Nm``) use them
too. A value of the wrong type, or outside its bound, is refused in one line naming the
key, the value and the valid range.
"""
from __future__ import annotations

import math
import numbers
from collections.abc import Mapping

from .errors import CaseError

# Plausibility bounds (issue 14, item 2): ranges a real reducer can have, beyond the
# mathematical validity of each value. They are wide (from a micro drive of a few mm to the
# largest industrial cycloid drives), so that no real design is refused; a value outside
# is a unit slip (m for mm, N mm for N m) or a typo, and left in, it overflows or grows the
# FE mesh without bound instead of failing with a message about its key.
#: Radii of the main circles (pin circle, pin-hole circle, holes) [mm].
RADIUS_MM = (1.0, 2000.0)
#: Pin, roller and bearing radii [mm]: a 0.1 mm needle is the smallest rolling element.
PIN_RADIUS_MM = (0.1, 200.0)
#: Eccentricity of a cycloid stage [mm] (the profile also bounds it: K1 < 1).
ECCENTRICITY_MM = (0.01, 100.0)
#: Face width of a disc, a gear or a sine pair [mm].
FACE_WIDTH_MM = (0.1, 1000.0)
#: Module of a gear or sine pair [mm] (ISO 54 runs from 0.05 to 100).
MODULE_MM = (0.05, 100.0)
#: Housing wall around the pin circle, as a multiple of the pin circle radius: a wall
#: thicker than the pin circle radius itself is not a reducer housing.
HOUSING_WALL_MAX = 1.0
#: Input speed [rpm] (servo motors run up to ~20000 rpm; below 0.01 rpm no film forms
#: and the loss models leave their range).
SPEED_RPM = (0.01, 20000.0)
#: Torques [N m] on the output of a reducer (the largest cycloid drives: ~1e5 N m) and
#: the smallest one meaningful for an efficiency (below 1 mN m the drag dominates).
TORQUE_NM = (1e-3, 1e6)
#: Sizes of the supports' parts [mm] (rollers, crankshafts, their span): more than the
#: largest housing (RADIUS_MM) is not a part of a reducer.
SUPPORT_MM = (0.0, 2000.0)
#: Torsional stiffness of an output carrier [N m/arcmin] (catalogue reducers: 10 to 1e4;
#: above 1e9 it is rigid to every digit the twist shows).
CARRIER_NM_PER_ARCMIN = (0.0, 1e9)
#: Input torque [N m]: the output range over ratios down to 1.
INPUT_TORQUE_NM = (1e-6, 1e6)
#: Input power [kW].
POWER_KW = (1e-6, 1e4)
#: Load-independent torques (drag, plain-bearing friction) [N mm].
DRAG_NMM = (0.0, 1e6)
#: Magnitude of a stated ratio (two-stage drives reach a few thousand).
STATED_RATIO_MAX = 1e5
#: Smallest mesh efficiency accepted: below it the pair is not a working gear mesh.
MESH_EFFICIENCY_MIN = 0.5
#: A material's stress limits [MPa]: no surface of the hardness range (up to 2000 HV, a
#: flow pressure of 19.6 GPa) carries more.
STRESS_MPA = (0.0, 20000.0)
#: Basic load rating of one bearing [kN]: the largest rolling bearings made (slewing rings
#: of several metres) rate about 2e4 kN.
BEARING_RATING_KN = (0.0, 1e5)
#: External loads on the output [N]: above the largest rating (BEARING_RATING_KN) any
#: bearing's ISO 281 life is below one million revolutions.
EXTERNAL_LOAD_N = (0.0, 1e3 * BEARING_RATING_KN[1])
#: Moment arms of the external loads [mm]: 10 m is a crane's jib, not a reducer's output.
LOAD_ARM_MM = (0.0, 10000.0)
#: External tilting moment [N m]: the largest load on the longest arm.
EXTERNAL_MOMENT_NM = (0.0, EXTERNAL_LOAD_N[1] * LOAD_ARM_MM[1] / 1000.0)
#: Axial preload of a main bearing row [N]: a tenth of the largest rating (makers' matched
#: pairs are preloaded with a few % of C0).
PRELOAD_N = (0.0, 0.1 * EXTERNAL_LOAD_N[1])
#: Bearing pitch diameters [mm]: within the largest housing (RADIUS_MM, a radius).
PITCH_DIAMETER_MM = (0.0, 2 * RADIUS_MM[1])
#: Housing surface [m²]: a cylinder of the largest housing (RADIUS_MM's 2 m radius) as long
#: as its diameter has 6 pi (2 m)² = 75 m².
HOUSING_AREA_M2 = (0.0, 100.0)
#: Lumped heat capacity [J/K]: that whole housing solid steel, pi (2 m)² 4 m 7850 kg/m³ x
#: 450 J/(kg K) = 1.8e8 J/K.
HEAT_CAPACITY_J_K = (0.0, 2e8)


def expected_type(f) -> str:
    """What a field holds (from its metadata and annotation).

    Parameters
    ----------
    f : dataclasses.Field
        A case section's field.

    Returns
    -------
    str
        "integer", "number", "string" or "table".
    """
    md = f.metadata
    if md.get("choices") is not None or f.type == "str":
        return "string"
    if md.get("integer"):
        return "integer"
    if f.type.startswith(("float", "int")):
        return "number"
    return "table"


def _kind(value) -> str:
    """How the TOML reader gave ``value``, for messages."""
    if isinstance(value, bool):
        return "true/false"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, (list, tuple)):
        return "an array"
    if isinstance(value, int):
        return "an integer"
    return "a float" if isinstance(value, float) else f"a {type(value).__name__}"


def check_type(key: str, value, expected: str):
    """Refuse a value of the wrong type, naming the key (issue 14, item 1): a string, bool,
    table or array where a number belongs would otherwise fail later in arithmetic, with a
    message about an internal variable.

    Parameters
    ----------
    key : str
        The dotted case key, for the message.
    value : object
        The value as the TOML reader gave it.
    expected : str
        :func:`expected_type` of the field ("table" is not checked here).

    Raises
    ------
    CaseError
        One line naming the key, the value and what it must be.
    """
    if expected == "string":
        ok = isinstance(value, str)
    elif expected == "integer":          # numpy's integers too (callers from Python)
        ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    elif expected == "number":
        ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    else:
        return
    if ok:
        return
    hint = ""
    if expected in ("number", "integer") and isinstance(value, str):
        hint = " (write it without quotes)"
    if expected == "integer" and isinstance(value, float) and math.isfinite(value) \
            and value == int(value):
        hint = f" (write {int(value)})"
    if expected == "integer":
        raise CaseError(f"{key} = {_shown(value)} must be an integer, not {_kind(value)}{hint}")
    raise CaseError(f"{key} = {_shown(value)} is not a {expected}: it is {_kind(value)}{hint}")


def _shown(value) -> str:
    """A value as the message shows it: TOML-like, and short."""
    if isinstance(value, bool):
        return "true" if value else "false"
    r = repr(value)
    return r if len(r) <= 40 else r[:37] + "..."
