"""The sizing rules of a cycloid stage that the K-H-V and RV templates of ``toothfem new``
both take: the pin radius (a share of the pin pitch below the undercut bound), the disc's
lobes and its ``[cycloid]`` section, the centre bore and the holes between the bore and the
root circle, the pins' tolerances (ISO 286 h5), the key numbers' ranges and help, and the
friction and lubrication a cycloid stage is written with. Each rule's ASSUMPTION and its
reason stand beside it. Units: the key numbers' (mm, N m, rpm). The rules every layout
shares: :mod:`toothfem.case_template`.
"""
from __future__ import annotations

import math

from .case_checks import PIN_RADIUS_MM
from .case_sections import CycloidStage
from .case_template import NewCaseTemplate, Ranges, entry_value, put, restated, round_to, size_step
from .efficiency.bearing_set import ISO15_SERIES_0
from .errors import CaseError, ToothfemError, check_range
from .geometry.cycloid import CycloidGeometry, min_convex_curvature_radius
from .units import M_PER_MM, MM_PER_M

#: Pin radius per pin pitch 2 pi Rz / Zb. ASSUMPTION: the shipped conventional-pin cases
#: (RV-40E-like 3.0 mm on a 10.05 mm pitch, 0.30; the K-H-V robot joint 3.0 on 10.5, 0.29).
PIN_RADIUS_PER_PITCH = 0.3


#: Largest pin radius per the undercut bound (the smallest convex curvature radius of the
#: theoretical profile): a fifth of margin keeps the working profile's sharpest convex
#: point from a cusp where K1 is high.
PIN_RADIUS_PER_UNDERCUT = 0.8


#: Discs of a cycloid stage. ASSUMPTION: two discs 180 deg apart balance each other's
#: eccentric force (every shipped cycloid case).
DISC_COUNT = 2


#: A hole's radius per the radial room of its circle (the smaller distance to the bore and
#: to the root circle), capped at a share of half the spacing of the holes on that circle.
#: ASSUMPTION: the shipped K-H-V case (6.7 mm holes in a 15.8 mm room, 0.42; 0.58 of the
#: half spacing) and the RV-40E-like crank holes (10 mm in 23.7 mm at m = 1.5: 0.42).
HOLE_PER_ROOM = 0.42


HOLE_PER_HALF_SPACING = 0.6


#: ISO 286-1 standard tolerance grade IT5 [um] by diameter range (upper limits [mm]): the
#: h5 pins' lower diameter deviation (the shipped cases: h5, -5 um on 3-6 mm).
IT5_UM = ((3.0, 4.0), (6.0, 5.0), (10.0, 6.0), (18.0, 8.0), (30.0, 9.0), (50.0, 11.0),
          (80.0, 13.0), (120.0, 15.0), (180.0, 18.0), (250.0, 20.0), (315.0, 23.0),
          (400.0, 25.0))


def _it5_um(diameter_mm: float) -> float:
    """ISO 286 IT5 [um] of a diameter [mm] (the largest tabulated step above 400 mm)."""
    return next((it for top, it in IT5_UM if diameter_mm <= top), IT5_UM[-1][1])


def _pin_radius(pins: int, rz_mm: float, e_mm: float) -> tuple:
    """The pin radius [mm] by PIN_RADIUS_PER_PITCH, below the undercut bound, and its
    reason."""
    pitch = 2 * math.pi * rz_mm / pins
    step = 0.1 if pitch >= 2.0 else 0.01
    free = CycloidGeometry(pin_count=pins, pin_circle_radius_m=rz_mm * M_PER_MM,
                           eccentricity_m=e_mm * M_PER_MM, pin_radius_m=1e-9)
    rho = min_convex_curvature_radius(free.nominal()) * MM_PER_M
    r = round_to(min(PIN_RADIUS_PER_PITCH * pitch, PIN_RADIUS_PER_UNDERCUT * rho), step, "down")
    why = (f"{PIN_RADIUS_PER_PITCH:g} of the pin pitch {pitch:.4g} mm (the shipped cases: "
           "0.29-0.30)")
    if PIN_RADIUS_PER_UNDERCUT * rho < PIN_RADIUS_PER_PITCH * pitch:
        why = (f"{PIN_RADIUS_PER_UNDERCUT:g} of the undercut bound {rho:.4g} mm (the "
               f"smallest convex curvature radius; {PIN_RADIUS_PER_PITCH:g} of the pitch "
               "would undercut the profile)")
    return r, why


def hole_radius(circle_mm: float, inner_mm: float, outer_mm: float, holes_on_circle: int):
    """A hole's radius [mm] on a circle between two radii (module constants).

    Parameters
    ----------
    circle_mm : float
        The holes' circle radius [mm].
    inner_mm : float
        The bore's radius [mm].
    outer_mm : float
        The root circle's radius [mm].
    holes_on_circle : int

    Returns
    -------
    (float, float)
        The hole's radius and the radial room [mm].
    """
    room = min(circle_mm - inner_mm, outer_mm - circle_mm)
    spacing = circle_mm * math.sin(math.pi / holes_on_circle)
    return min(HOLE_PER_ROOM * room, HOLE_PER_HALF_SPACING * spacing), room


def disc_lobes(template: NewCaseTemplate, given: dict, train=None) -> tuple:
    """The disc's lobes and their entry's kind and note, once the case model's own checks
    pass (K1 < 1 and the tooth numbers; ``train(lobes)`` builds the layout's other section
    that holds them), its refusal restated in the options' names.

    Parameters
    ----------
    template : NewCaseTemplate
        The layout's template.
    given : dict
        Key number -> value (checked; those not given left out).
    train : callable, optional
        ``train(lobes)`` builds the layout's other section that holds them.

    Returns
    -------
    (int, tuple)
        The lobes and their entry's (kind, note).
    """
    zb, rz, e = given["pins"], given["pin_circle_radius_mm"], given["eccentricity_mm"]
    za = given.get("lobes")
    lobes_kind = ("key", "--lobes") if za is not None else (
        "follows", "pins - 1: a one-tooth-difference disc")
    za = zb - 1 if za is None else za
    try:       # K1 < 1 and the tooth numbers, by the case model's own checks
        CycloidStage(pin_count=zb, lobe_count=za, pin_circle_radius_mm=rz,
                     eccentricity_mm=e, pin_radius_mm=PIN_RADIUS_MM[0], face_width_mm=1.0)
        if train is not None:
            train(za)
    except ToothfemError as exc:
        raise restated(exc, template, given) from None
    return za, lobes_kind


def cycloid_stage(s: dict, given: dict, za: int, lobes_kind: tuple) -> tuple:
    """The ``[cycloid]`` section (K-H-V and RV alike); returns the disc's root radius [mm]
    and the step [mm] its layout is rounded to.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.
    given : dict
        Key number -> value (checked; those not given left out).
    za : int
        The disc's lobes.
    lobes_kind : tuple
        Their entry's (kind, note).

    Returns
    -------
    (float, float)
        The disc's root radius and the layout's step [mm].
    """
    zb, rz, e = given["pins"], given["pin_circle_radius_mm"], given["eccentricity_mm"]
    c = "cycloid"
    put(s, c, "pin_count", zb, "key", "--pins")
    put(s, c, "lobe_count", za, *lobes_kind)
    put(s, c, "pin_circle_radius_mm", rz, "key", "--pin-circle-radius-mm (Rz)")
    put(s, c, "eccentricity_mm", e, "key", f"--eccentricity-mm (K1 = e Zb / Rz = "
        f"{e * zb / rz:.3g})")
    r_pin, why = _pin_radius(zb, rz, e)
    put(s, c, "pin_radius_mm", r_pin, "assumption", why)
    put(s, c, "face_width_mm", None, "assumption", "")      # placed here, sized below
    put(s, c, "disc_count", DISC_COUNT, "assumption",
        "two discs 180 deg apart balance their eccentric forces (every shipped case)")
    put(s, c, "pin_structure", "conventional", "assumption",
        "pins in grooves of the housing, the common build")
    return rz - e - r_pin, size_step(rz)


def centre_bore(per_root: float, root: float, step: float) -> tuple:
    """The disc's centre bore radius [mm], ``per_root`` of the root radius rounded up and
    at most the largest shaft of the model's input bearings; returns (bore, whether that
    cap applied, the cap).

    Parameters
    ----------
    per_root : float
        The bore per root radius.
    root : float
        The root radius [mm].
    step : float
        The layout's step [mm].

    Returns
    -------
    (float, bool, float)
        The bore [mm], whether the cap applied, the cap [mm].
    """
    bore = round_to(per_root * root, step, "up")
    largest = max(ISO15_SERIES_0) / 2          # the input bearings' shaft: the bore's diameter
    return min(bore, largest), bore > largest, largest


def check_lobes(given: dict) -> None:
    """A cycloid disc's lobes, where given: one fewer than the pins.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).
    """
    if given.get("lobes") is not None:
        zb = given["pins"]
        check_range("--lobes", given["lobes"], zb - 1, zb - 1, error=CaseError,
                    why="a cycloid disc has one lobe fewer than its pins (--pins - 1)")


def disc_keys(given: dict) -> dict:
    """A cycloid stage's keys its key numbers set (K-H-V and RV).

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).

    Returns
    -------
    dict
        Case key -> key number.
    """
    return {"cycloid.pin_count": "pins", "cycloid.lobe_count": "lobes",
            "cycloid.pin_circle_radius_mm": "pin_circle_radius_mm",
            "cycloid.eccentricity_mm": "eccentricity_mm"}


def pin_tolerances(s: dict) -> tuple:
    """A cycloid stage's tolerances: the pins' (ISO 286 h5 on their diameter), the pin
    circle's and the disc profile's.

    Parameters
    ----------
    s : dict
        Section -> its entries so far.

    Returns
    -------
    tuple of (str, float, str)
        Key, value [mm] and reason.
    """
    pin_diameter_mm = 2 * entry_value(s, "cycloid", "pin_radius_mm")
    it5 = _it5_um(pin_diameter_mm)
    return (("pin_position_mm", 0.005, "true-position zone of each pin, jig-ground bores"),
            ("pin_diameter_lower_mm", -it5 * 1e-3,
             f"ISO 286 h5 on a {pin_diameter_mm:g} mm pin: 0 / -{it5:g} um"),
            ("pin_diameter_upper_mm", 0.0, "ISO 286 h5: the upper deviation is 0"),
            ("pin_circle_radius_mm", 0.003, "+- limit, ground parts"),
            ("disc_profile_mm", 0.003, "+- limit of each flank, profile grinding"))


def disc_name(given: dict, s: dict) -> str:
    """A cycloid stage's size in the case's default name.

    Parameters
    ----------
    given : dict
        Key number -> value (checked; those not given left out).
    s : dict
        Section -> its entries so far.

    Returns
    -------
    str
    """
    return f"{given['pins']} pins on a {given['pin_circle_radius_mm']:g} mm radius"


DISC_RANGES: Ranges = {"pins": (CycloidStage, "pin_count"),
                       "lobes": (CycloidStage, "lobe_count"),
                       "pin_circle_radius_mm": (CycloidStage, "pin_circle_radius_mm")}


#: Checked after the operating point's (the order of the refusals before the templates).
ECCENTRICITY_RANGE: Ranges = {"eccentricity_mm": (CycloidStage, "eccentricity_mm")}


DISC_HELP = {"pins": "pins Zb in the housing",
             "lobes": "lobes Za of a disc (default pins - 1)",
             "pin_circle_radius_mm": "pin circle radius Rz [mm]",
             "eccentricity_mm": "the crank's eccentricity [mm]"}


GREASE = ("grease", "robot-joint cycloid and RV units are grease-filled (Nabtesco RV-E "
                     "catalogue)")


PIN_GROOVE_FRICTION = ("pin_groove_coefficient", 0.05, "conventional pins sliding in "
                       "lubricated grooves (the shipped cycloid cases)")
