"""Every rolling bearing of a cycloid or RV reducer: its size, ratings and speed.

One record (:class:`Bearing`) per group of like bearings of the layout, built from the
case where it names them and from the geometry where it does not (each assumed value
named in ``assumed``, every rule below an ASSUMPTION stated beside it):

* ``crank_bearings`` (2K-V) or ``eccentric_bearing`` (K-H-V): needle rollers running in
  the disc's crank hole (centre bore) on the crank's eccentric journal, the rolling set of
  :meth:`toothfem.fem.drives.Drive.supports` (the system model's rollers);
* ``crank_support_bearings`` (2K-V): a tapered roller bearing at each end of each
  crankshaft in the carrier, bore the crankshaft's diameter;
* ``main_bearings``: the output's angular contact ball pair at the pin circle (RV-E);
* ``input_bearings``: deep groove ball bearings on the input shaft.

The sine reducer (:func:`_sine_bearings`) has the eccentric bearing's rollers on the
eccentric in the planet's bore, the main pair and the input bearings; its losses stay the
sine paper's laws (:mod:`.drive_losses`), the set gives its bearings' life.

A bearing without a declared rating has the ISO 281 / ISO 76 ratings of its rolling set
(:mod:`.rating`), the set sized from the bearing's section (:func:`rolling_set`); a
bearing that cannot fit where it sits is refused naming the keys that clash
(:func:`check_fits`).

Their friction and losses: :mod:`.bearing_friction`; the main pair's preload and its
figures under a tilting moment: :mod:`.main_bearing`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypedDict

from ..errors import CaseError
from .envelope import envelope
from .rating import dynamic_rating_N, static_rating_N
from ..units import M_PER_MM, MM_PER_M, N_PER_KN

#: Standard boundary dimensions, ISO 15:2017, diameter series 0 (60xx, 70xx, 320xx-like
#: sections): bore d -> (outside diameter D, width B) [mm]. The thinnest common radial
#: section, for bearings that sit in a carrier between other parts.
ISO15_SERIES_0 = {10: (26, 8), 12: (28, 8), 15: (32, 9), 17: (35, 10), 20: (42, 12),
                  25: (47, 12), 30: (55, 13), 35: (62, 14), 40: (68, 15), 45: (75, 16),
                  50: (80, 16), 55: (90, 18), 60: (95, 18), 65: (100, 18), 70: (110, 20),
                  75: (115, 20), 80: (125, 22), 85: (130, 22), 90: (140, 24),
                  95: (145, 24), 100: (150, 24)}
#: ASSUMPTION: the rolling set of a bearing of radial section h = (D - d)/2: elements of
#: diameter ELEMENT_PER_SECTION h (deep groove 6204: 7.94 mm balls in a 13.5 mm section,
#: 0.59; tapered 32004 X and cylindrical rollers about 0.5), spaced ELEMENT_PITCH element
#: diameters apart on the pitch circle (a cage web between them; 6204: 8 balls on 33.5 mm
#: is 1.66 (a Conrad bearing's assembly limit), angular contact and roller bearings 1.2-1.4),
#: rollers as long as ROLLER_LENGTH_PER_WIDTH of the width (the ends' chamfers and flanges).
ELEMENT_PER_SECTION = {"ball": 0.59, "angular_ball": 0.55, "tapered": 0.5, "cylindrical": 0.5}
ELEMENT_PITCH = {"ball": 1.66, "angular_ball": 1.35, "tapered": 1.25, "cylindrical": 1.25}
ROLLER_LENGTH_PER_WIDTH = 0.7
#: Nominal contact angles [deg]: angular contact ball bearings of a reducer's main bearing
#: (RV-E: 40-45 deg back to back; ISO 281 tabulates X, Y at 40 deg), tapered rollers of
#: the 320 X series (about 15 deg: e = 1.5 tan(alpha) = 0.37-0.43 in makers' tables).
CONTACT_ANGLE_DEG = {"ball": 0.0, "angular_ball": 40.0, "tapered": 15.0, "cylindrical": 0.0,
                     "needle": 0.0}
#: ASSUMPTION: the main bearing's balls, as a share of its pitch diameter (RV-E reducers'
#: integral main bearings run balls of about 6-8 % of the pitch circle).
MAIN_BALL_PER_PITCH = 0.06


@dataclass(frozen=True, kw_only=True)
class Bearing:
    """One group of like bearings: dimensions [m], rolling set, ratings [N], speed.

    ``speed_per_input``: the rotating ring's speed relative to the other per unit input
    speed [-]; ``rating_source``: "case" or the standard the rating was computed by;
    ``assumed``: what the case did not give.
    """
    name: str
    label: str
    bearing_type: str
    count: int
    bore_m: float
    outer_m: float
    width_m: float
    pitch_diameter_m: float
    elements: int
    element_diameter_m: float
    element_length_m: float | None
    contact_angle_deg: float
    dynamic_rating_N: float
    static_rating_N: float
    rating_source: str
    speed_per_input: float
    assumed: tuple = ()

    def describe(self) -> dict:
        """The record in mm and kN for the outputs.

        Returns
        -------
        dict
        """
        mm = MM_PER_M
        return {"label": self.label, "type": self.bearing_type, "count": self.count,
                "bore_mm": self.bore_m * mm, "outer_mm": self.outer_m * mm,
                "width_mm": self.width_m * mm, "pitch_diameter_mm": self.pitch_diameter_m * mm,
                "elements": self.elements, "element_diameter_mm": self.element_diameter_m * mm,
                "contact_angle_deg": self.contact_angle_deg,
                "dynamic_rating_kN": self.dynamic_rating_N / N_PER_KN,
                "static_rating_kN": self.static_rating_N / N_PER_KN,
                "rating_source": self.rating_source, "assumed": list(self.assumed)}


def standard_size(shaft_m: float, name: str) -> tuple:
    """The smallest bearing of :data:`ISO15_SERIES_0` whose bore takes the shaft.

    Parameters
    ----------
    shaft_m : float
        Shaft diameter [m].
    name : str
        The shaft's case key, for the message.

    Returns
    -------
    tuple
        (bore, outside diameter, width) [m].

    Raises
    ------
    CaseError
        If no bore of the table takes the shaft.
    """
    d_mm = shaft_m * MM_PER_M
    for bore, (outer, width) in ISO15_SERIES_0.items():
        if bore >= d_mm - 1e-9:
            return bore * M_PER_MM, outer * M_PER_MM, width * M_PER_MM
    raise CaseError(f"{name} = {d_mm:.4g} mm: no bearing of ISO 15 diameter series 0 "
                    f"(bores {min(ISO15_SERIES_0)}-{max(ISO15_SERIES_0)} mm) takes it")


def _element_count(bearing_type, pitch_diameter_m, element_diameter_m) -> int:
    """Elements on the pitch circle, :data:`ELEMENT_PITCH` diameters apart (at least 3; a
    type without its own spacing takes the angular contact bearing's)."""
    spacing = ELEMENT_PITCH.get(bearing_type, ELEMENT_PITCH["angular_ball"])
    return max(int(math.pi * pitch_diameter_m / (spacing * element_diameter_m)), 3)


class _RollingSet(TypedDict):
    """A bearing's rolling set: the :class:`Bearing` fields :func:`_ratings` reads."""
    elements: int
    element_diameter_m: float
    element_length_m: float | None
    pitch_diameter_m: float
    contact_angle_deg: float


def rolling_set(bearing_type: str, bore_m: float, outer_m: float, width_m: float) -> dict:
    """The assumed rolling set of a bearing of these boundary dimensions (the rules of
    :data:`ELEMENT_PER_SECTION`, :data:`ELEMENT_PITCH`, :data:`ROLLER_LENGTH_PER_WIDTH`).

    Parameters
    ----------
    bearing_type : str
        "ball", "angular_ball", "tapered" or "cylindrical".
    bore_m, outer_m, width_m : float
        d, D, B [m].

    Returns
    -------
    dict
        ``elements``, ``element_diameter_m``, ``element_length_m`` (None for balls),
        ``pitch_diameter_m``, ``contact_angle_deg``.
    """
    d_w = ELEMENT_PER_SECTION[bearing_type] * (outer_m - bore_m) / 2
    d_m = (outer_m + bore_m) / 2
    z = _element_count(bearing_type, d_m, d_w)
    length = None if "ball" in bearing_type else ROLLER_LENGTH_PER_WIDTH * width_m
    return dict(elements=z, element_diameter_m=d_w, element_length_m=length,
                pitch_diameter_m=d_m, contact_angle_deg=CONTACT_ANGLE_DEG[bearing_type])


def _ratings(bearing_type, rolling, declared_C=None, key=None, space=None):
    """(C, C0, where C comes from): ISO 281 / ISO 76 of the rolling set, or the case's C
    (checked against the set's where ``key`` names it and ``space`` what it must fit)."""
    kw = dict(rows=1, elements=rolling["elements"],
              element_diameter_m=rolling["element_diameter_m"],
              element_length_m=rolling["element_length_m"],
              pitch_diameter_m=rolling["pitch_diameter_m"],
              contact_angle_deg=rolling["contact_angle_deg"])
    c0 = static_rating_N(bearing_type, **kw)
    if declared_C is not None and key is None:
        return declared_C, c0, "case"
    c = dynamic_rating_N(bearing_type, **kw)
    if declared_C is not None:
        check_rating(declared_C, c, key, space)
        return declared_C, c0, "case"
    return c, c0, "ISO 281 / ISO 76 of the rolling set"


def roller_bearing(si, supports, *, name, label, count, bore_m, outer_m, pitch_m, speed,
                   space) -> Bearing:
    """The system model's rollers (``supports``) between ``bore_m`` and ``outer_m`` as a
    needle bearing record; a declared eccentric rating is checked against ``space``.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    supports : toothfem.fem.datasheet.supports.Supports
    name : str
        The bearing group's name (the system model's, efficiency.bearings.SYSTEM_GROUPS).
    label : str
        What it is, for a reader.
    count : int
        Bearings of the group in the reducer.
    bore_m : float
        Bore [m].
    outer_m : float
        Outside diameter [m].
    pitch_m : float
        The rollers' pitch diameter [m].
    speed : float
        Its speed per unit input speed [-].
    space : str
        The case key that sets its room (a refusal names it).

    Returns
    -------
    Bearing
        Its rolling set, ratings and speed.
    """
    rolling = dict(elements=supports.bearing_roller_count,
                   element_diameter_m=supports.bearing_roller_diameter_m,
                   element_length_m=supports.bearing_roller_length_m, pitch_diameter_m=pitch_m,
                   contact_angle_deg=0.0)
    b = si.bearings
    c, c0, source = _ratings("needle", rolling,
                             None if b is None else b.eccentric_dynamic_rating_N,
                             "bearings.eccentric_dynamic_rating_kN", space)
    return Bearing(name=name, label=label, bearing_type="needle", count=count, bore_m=bore_m,
                   outer_m=outer_m, width_m=supports.bearing_roller_length_m,
                   dynamic_rating_N=c, static_rating_N=c0, rating_source=source,
                   speed_per_input=speed,
                   assumed=tuple(f"supports.{n}" for n in supports.assumed
                                 if n.startswith("bearing_roller")), **rolling)


def needle_set(si, drive, supports, *, name, label, count, hole_m, hole_key):
    """The crank (eccentric) bearings: the system model's needle rollers in the hole of
    diameter ``hole_m`` (the case key ``hole_key`` holds its radius), ``count`` of them.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    name : str
        The bearing group's name (the system model's, efficiency.bearings.SYSTEM_GROUPS).
    label : str
        What it is, for a reader.
    count : int
        Bearings of the group in the reducer.
    hole_m : float
        The hole the rollers run in [m].
    hole_key : str
        The case key of that hole (a refusal names it).

    Returns
    -------
    Bearing
        The system model's rollers in the hole, with their ISO 281 / ISO 76 ratings.
    """
    g = si.cycloid.geometry
    b = si.bearings
    hole = hole_m
    d_w = supports.bearing_roller_diameter_m
    journal = hole - 2 * d_w
    if journal <= 0:
        raise CaseError(f"supports.bearing_roller_diameter_mm = {d_w * MM_PER_M:.4g} does not fit "
                        f"{hole_key} = {hole / 2 * MM_PER_M:.4g}: two rollers fill the hole")
    if supports.crankshaft_diameter_m is not None and \
            supports.crankshaft_diameter_m + 2 * g.eccentricity_m > journal * (1 + 1e-9):
        raise CaseError(
            f"supports.crankshaft_diameter_mm = {supports.crankshaft_diameter_m * MM_PER_M:.4g} "
            f"does not fit the eccentric journal ({journal * MM_PER_M:.4g} mm: {hole_key} = "
            f"{hole / 2 * MM_PER_M:.4g} less two rollers of supports.bearing_roller_diameter_mm = "
            f"{d_w * MM_PER_M:.4g}): the shaft must pass through the journal, offset by "
            f"cycloid.eccentricity_mm = {g.eccentricity_m * MM_PER_M:.4g}")
    d_m = hole - d_w
    declared_dm = None if b is None else b.eccentric_pitch_diameter_m
    if declared_dm is not None and not journal < declared_dm < hole:
        raise CaseError(f"bearings.eccentric_pitch_diameter_mm = {declared_dm * MM_PER_M:.4g} does "
                        f"not fit {hole_key} = {hole / 2 * MM_PER_M:.4g}: the rollers' pitch circle "
                        f"lies between the journal ({journal * MM_PER_M:.4g} mm) and the hole")
    if declared_dm is not None and abs(declared_dm - d_m) > PITCH_TOLERANCE_M:
        raise CaseError(f"bearings.eccentric_pitch_diameter_mm = {declared_dm * MM_PER_M:.4g} "
                        f"disagrees with the rollers' pitch circle {d_m * MM_PER_M:.4g} mm "
                        f"({hole_key} = {hole / 2 * MM_PER_M:.4g} less one "
                        f"supports.bearing_roller_diameter_mm = {d_w * MM_PER_M:.4g}): give one "
                        "of them")
    w = drive.speeds()
    return roller_bearing(
        si, supports, name=name, label=label, count=count,
        bore_m=journal, outer_m=hole, pitch_m=d_m, speed=abs(w["crank"] - w["member"]),
        space=f"{hole_key} = {hole / 2 * MM_PER_M:.4g}")


#: A declared pitch diameter agrees with the rollers' when within this [m] (a micrometre:
#: the case's millimetres to three decimals).
PITCH_TOLERANCE_M = 1e-6
#: A declared rating may exceed ISO 281's for the rolling set that fits by this factor
#: (makers rate premium steels and profiles up to about 30 % above the standard's b_m f_c;
#: more than that is a bearing that does not fit the space).
RATING_MARGIN = 1.3


def check_rating(declared_N, fitting_N, key, space):
    """Refuse a declared rating no bearing that fits the space can have.

    Parameters
    ----------
    declared_N, fitting_N : float
        The case's C and ISO 281's C of the rolling set that fits [N].
    key, space : str
        The rating's key, and the key and value of the space it must fit.

    Raises
    ------
    CaseError
        If ``declared_N`` exceeds ``RATING_MARGIN`` times ``fitting_N``.
    """
    if declared_N > RATING_MARGIN * fitting_N:
        raise CaseError(f"{key} = {declared_N / N_PER_KN:.4g} kN does not fit {space}: the rolling "
                        f"set that fits rates {fitting_N / N_PER_KN:.4g} kN (ISO 281), at most "
                        f"{RATING_MARGIN:g}x that is credible")


def sized_bearing(name, label, bearing_type, count, shaft_m, shaft_key, speed, assumed,
                  room=None):
    """A bearing the case does not size: the ISO 15 series-0 size on its shaft, refused
    where its outside diameter does not fit ``room``.

    Parameters
    ----------
    name : str
        The bearing group's name (the system model's, efficiency.bearings.SYSTEM_GROUPS).
    label : str
        What it is, for a reader.
    bearing_type : str
        A type of CONTACT_ANGLE_DEG.
    count : int
        Bearings of the group in the reducer.
    shaft_m : float
        The shaft it sits on [m].
    shaft_key : str
        The case key of that shaft (a refusal names it).
    speed : float
        Its speed per unit input speed [-].
    assumed : list of str
        What of it is assumed (named in the report).
    room : (float, str), optional
        The largest outside diameter that fits [m] and where (refused above it).

    Returns
    -------
    Bearing
        The ISO 15 series-0 bearing on the shaft, its ratings from its rolling set.
    """
    bore, outer, width = standard_size(shaft_m, shaft_key)
    if room is not None and outer > room[0] * (1 + 1e-9):
        raise CaseError(f"{shaft_key} = {shaft_m * MM_PER_M:.4g} mm needs a {label} of outside "
                        f"diameter {outer * MM_PER_M:.4g} mm (ISO 15 series 0), which does not fit "
                        f"{room[1]}")
    rolling = rolling_set(bearing_type, bore, outer, width)
    c, c0, source = _ratings(bearing_type, rolling, None)
    return Bearing(name=name, label=label, bearing_type=bearing_type, count=count,
                   bore_m=bore, outer_m=outer, width_m=width, dynamic_rating_N=c,
                   static_rating_N=c0, rating_source=source + " (ISO 15 series 0 size)",
                   speed_per_input=speed, assumed=tuple(assumed) + ("size",), **rolling)


def main_pair(si, drive) -> Bearing:
    """The output's main bearing pair (one record per row): angular contact balls on the
    pitch diameter of :mod:`.envelope`, balls :data:`MAIN_BALL_PER_PITCH` of it.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    Bearing
    """
    env = envelope(si, drive)
    b = si.bearings
    t = "angular_ball" if b is None else b.main_type
    d_m = env.main_pitch_diameter_m
    d_w = MAIN_BALL_PER_PITCH * d_m
    rolling: _RollingSet = dict(elements=_element_count(t, d_m, d_w), element_diameter_m=d_w,
                   element_length_m=None if "ball" in t else d_w,
                   pitch_diameter_m=d_m, contact_angle_deg=CONTACT_ANGLE_DEG[t])
    declared = None if b is None else b.main_dynamic_rating_N
    c, c0, source = _ratings(t, rolling, declared)
    assumed = ["ball size"] + (["pitch diameter"] if b is None or
                               b.main_pitch_diameter_m is None else [])
    return Bearing(name="main_bearings", label="main bearings (angular contact ball pair)",
                   bearing_type=t, count=env.main_count, bore_m=d_m - 2 * d_w,
                   outer_m=d_m + 2 * d_w, width_m=2 * d_w, dynamic_rating_N=c,
                   static_rating_N=c0, rating_source=source,
                   speed_per_input=abs(drive.speeds()["output"]), assumed=tuple(assumed),
                   **rolling)


def cycloid_set(si, drive, *own) -> tuple:
    """A cycloid or RV reducer's bearings (module docstring): the layout's ``own`` groups,
    the main pair and the input shaft's ball bearings.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    *own : Bearing
        The layout's own groups (its eccentric or crank bearings, supports).

    Returns
    -------
    tuple of Bearing
        The layout's own groups, the main pair and the input bearings.
    """
    env = envelope(si, drive)
    return (*own, main_pair(si, drive),
            sized_bearing("input_bearings", "input bearings (deep groove balls on the input "
                          "shaft)", "ball", 2, env.input_seal_diameter_m,
                          "seals.input_diameter_mm", 1.0, ["input shaft diameter"]))


def reducer_bearings(si, drive) -> tuple:
    """Every bearing group of a reducer (module docstring; the layout's ``bearing_set`` part).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    tuple of Bearing

    Raises
    ------
    CaseError
        A bearing that does not fit where it sits, naming the keys that clash.
    """
    declared = None if si.bearings is None else si.bearings.eccentric_type
    if declared not in (None, "needle"):
        raise CaseError(f"bearings.eccentric_type = {declared!r}: the eccentric bearing is the "
                        "system model's roller set (supports.bearing_roller_*), a 'needle' "
                        "bearing; another type is not modelled")
    return drive.layout.bearing_set(si, drive)
