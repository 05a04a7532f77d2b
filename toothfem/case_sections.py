"""The sections of a case file: one frozen dataclass per TOML table, units in the key names,
each field's valid range (and its plausibility bound, :mod:`toothfem.case_checks`) in its
metadata, checked in ``__post_init__``. :mod:`toothfem.case` assembles them into a
:class:`~toothfem.case.Case`.

The metadata is the case schema, declared here once (:func:`_f`): beside the range, ``doc``
(what the key is), ``source`` (where its default comes from: a paper, a standard, a
catalogue, ASSUMPTION with its reason, or what 0 or an empty value means), ``unset`` (what
a default of None stands for) and ``unit`` (where the key's suffix does not say it).
:mod:`toothfem.case_schema` reads it for the report's inputs and docs/case_schema.md."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from .units import M_PER_MM, MM_PER_M
from .case_checks import (DRAG_NMM, ECCENTRICITY_MM, FACE_WIDTH_MM, HOUSING_WALL_MAX,
                          INPUT_TORQUE_NM, MESH_EFFICIENCY_MIN, MODULE_MM, PIN_RADIUS_MM,
                          POWER_KW, RADIUS_MM, SPEED_RPM, TORQUE_NM, check_type, expected_type)
from .errors import CaseError, GeometryError, check_range
from .geometry.cycloid import CycloidGeometry
from .geometry.disc import DiscHolesSI, disc_polygon
from .geometry.sine import SineGearPair, check_load_carrying

INF = math.inf


def _f(lo=None, hi=None, *, lo_open=False, hi_open=False, default=dataclasses.MISSING,
       doc: str = "", source: str = "", unset: str = "", unit: str | None = None,
       choices=None, integer=False):
    """A dataclass field with its schema in metadata: the valid range [lo, hi] (open ends,
    choices, integer), ``doc`` (what the key is; refusals quote it), ``source`` (one line:
    where the default comes from), ``unset`` (what a default of None stands for) and
    ``unit`` (None: from the key's suffix, :func:`toothfem.case_schema.unit_of`)."""
    md = dict(lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open, doc=doc, choices=choices,
              integer=integer, source=source, unset=unset, unit=unit)
    return field(default=default, metadata=md)


def _stress(default: float, doc: str, source: str):
    """A positive stress limit [MPa] with its default and the default's source."""
    return _f(0.0, None, lo_open=True, default=default, doc=doc, source=source)


class _Section:
    """Mixin: validate every field against the range in its metadata."""

    _section = ""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            md = f.metadata
            if not md:
                continue
            value = getattr(self, f.name)
            if value is None:
                continue
            key = f"{self._section}.{f.name}" if self._section else f.name
            expected = expected_type(f)
            check_type(key, value, expected)
            if md.get("choices") is not None:
                if value not in md["choices"]:
                    raise CaseError(f"{key} = {value!r} is not one of {list(md['choices'])}")
                continue
            if expected == "string":
                continue
            check_range(key, value, md.get("lo"), md.get("hi"), lo_open=md.get("lo_open"),
                        hi_open=md.get("hi_open"), error=CaseError, why=md.get("doc", ""))
        self._check()

    def _check(self):
        """Cross-field rules of the section (override)."""


#: The source of the modifications' defaults.
_UNMODIFIED = "0: no modification (the theoretical conjugate profile)"

#: SI parameter of a geometry record -> (case key, factor from SI to the key's unit)
_CYCLOID_KEYS = {
    "pin_count": ("pin_count", 1.0),
    "pin_circle_radius_m": ("pin_circle_radius_mm", MM_PER_M),
    "eccentricity_m": ("eccentricity_mm", MM_PER_M),
    "pin_radius_m": ("pin_radius_mm", MM_PER_M),
    "pin_radius_m + equidistant_m": ("pin_radius_mm + equidistant_modification_mm", MM_PER_M),
    "equidistant_m": ("equidistant_modification_mm", MM_PER_M),
    "move_distance_m": ("move_distance_modification_mm", MM_PER_M),
    "rotation_rad": ("rotation_modification_deg", 180 / math.pi),
    "equidistant_m - move_distance_m":
        ("equidistant_modification_mm - move_distance_modification_mm", MM_PER_M),
}
_SINE_KEYS = {
    "planet_teeth": ("planet_teeth", 1.0),
    "ring_teeth": ("ring_teeth", 1.0),
    "module_m": ("module_mm", MM_PER_M),
    "tooth_height_m": ("tooth_height_mm", MM_PER_M),
    "face_width_m": ("face_width_mm", MM_PER_M),
}


def _restate(exc: GeometryError, section: str, keys) -> CaseError:
    """A geometry error restated with the case's key and units (one line)."""
    if exc.param in keys:
        key, scale = keys[exc.param]
        return exc.restated(f"{section}.{key}", scale, CaseError)
    return CaseError(f"{section}: {exc}")


#: The source of the holes' defaults: a disc without the hole.
_NO_HOLE = "0: no such hole"

#: Hole names in the disc-layout messages -> the [cycloid.disc_holes] keys that place them.
_HOLE_KEYS = {"centre_bore": ("centre_bore_radius_mm",),
              "crank": ("crank_hole_circle_radius_mm", "crank_hole_radius_mm"),
              "pillar": ("pillar_hole_circle_radius_mm", "pillar_hole_radius_mm")}


def _with_hole_keys(err: CaseError) -> CaseError:
    """A disc-layout refusal (which names holes, not keys) with the keys that set those
    holes appended, so that every refusal names a case key (issue 14)."""
    msg = str(err)
    keys = [f"cycloid.disc_holes.{k}" for name, ks in _HOLE_KEYS.items() if name in msg
            for k in ks]
    return CaseError(f"{msg} (set by {', '.join(keys)})") if keys else err


@dataclass(frozen=True)
class Material(_Section):
    """Elastic constants, and the hardness and strengths of life and strength checks
    (defaults: through-hardened bearing steel)."""
    _section = "material"
    youngs_modulus_GPa: float = _f(1.0, 1000.0)
    poisson_ratio: float = _f(0.0, 0.5, hi_open=True)
    density_kg_m3: float = _f(500.0, 25000.0, default=7850.0,
                              doc="density of the parts (the housing's heat capacity)",
                              source="carbon steel, 7854 kg/m³ (F.P. Incropera & D.P. DeWitt, "
                                     "Fundamentals of Heat and Mass Transfer, Table A.1)")
    # limits of the life and strength checks
    hardness_HV: float = _f(50.0, 2000.0, default=700.0,
                            doc="hardness of the flanks: the asperities' flow pressure "
                                "H = HV x 9.807 MPa",
                            source="60 HRC by the ASTM E140 conversion table (697 HV); "
                                   "through-hardened bearing steel (100Cr6/52100) is 58-64 HRC")
    allowable_contact_stress_MPa: float = _stress(
        1500.0, "contact fatigue limit (life and strength checks)",
        "ISO 281:2007: the fatigue load limit C_u of a rolling bearing gives 1500 MPa at the "
        "most loaded contact of through-hardened bearing steel of common quality")
    static_contact_stress_MPa: float = _stress(
        4000.0, "static contact stress limit (permanent deformation)",
        "ISO 76:2006: the basic static load rating of roller bearings gives 4000 MPa (a "
        "permanent deformation of 1e-4 of the roller diameter)")
    yield_strength_MPa: float = _stress(
        1700.0, "0.2 % proof stress",
        "ASSUMPTION: the lower end of the 0.2 % proof stress of through-hardened, "
        "low-tempered 100Cr6, about 1.7-2.0 GPa (H.K.D.H. Bhadeshia, Steels for bearings, "
        "Prog. Mater. Sci. 57 (2012) 268-435)")
    fatigue_limit_MPa: float = _stress(
        700.0, "endurance limit",
        "R.G. Budynas & J.K. Nisbett, Shigley's Mechanical Engineering Design (10th ed.), "
        "Eq. 6-8: the rotating-beam endurance limit S'e = 700 MPa for steels with "
        "S_ut > 1400 MPa")


@dataclass(frozen=True)
class DiscHoles(_Section):
    """Holes of the cycloid disc: centre bore, crank-bearing holes, carrier-pillar holes."""
    _section = "cycloid.disc_holes"
    centre_bore_radius_mm: float = _f(0.0, RADIUS_MM[1], default=0.0, source=_NO_HOLE)
    crank_hole_count: int = _f(0, 12, integer=True, default=0, source=_NO_HOLE)
    crank_hole_circle_radius_mm: float = _f(0.0, RADIUS_MM[1], default=0.0, source=_NO_HOLE)
    crank_hole_radius_mm: float = _f(0.0, RADIUS_MM[1], default=0.0, source=_NO_HOLE)
    pillar_hole_count: int = _f(0, 12, integer=True, default=0, source=_NO_HOLE)
    pillar_hole_circle_radius_mm: float = _f(0.0, RADIUS_MM[1], default=0.0, source=_NO_HOLE)
    pillar_hole_radius_mm: float = _f(0.0, RADIUS_MM[1], default=0.0, source=_NO_HOLE)

    def _check(self):
        for kind in ("crank", "pillar"):
            n = getattr(self, f"{kind}_hole_count")
            rc = getattr(self, f"{kind}_hole_circle_radius_mm")
            rh = getattr(self, f"{kind}_hole_radius_mm")
            if n and (rc <= 0 or rh <= 0):
                raise CaseError(f"{self._section}.{kind}_hole_radius_mm = {rh!r} and "
                                f"{kind}_hole_circle_radius_mm = {rc!r} must both be > 0 "
                                f"when {kind}_hole_count = {n}")


@dataclass(frozen=True)
class CycloidStage(_Section):
    """Cycloid disc and pin ring (K-H-V stage). Angles of modification in degrees."""
    _section = "cycloid"
    pin_count: int = _f(4, 400, integer=True)
    lobe_count: int = _f(3, 399, integer=True)
    pin_circle_radius_mm: float = _f(*RADIUS_MM)
    eccentricity_mm: float = _f(*ECCENTRICITY_MM)
    pin_radius_mm: float = _f(*PIN_RADIUS_MM)
    face_width_mm: float = _f(*FACE_WIDTH_MM)
    disc_count: int = _f(1, 4, integer=True, default=1,
                         source="one disc, the simplest K-H-V stage (the shipped cases "
                                "declare theirs)")
    pin_structure: str = _f(choices=("conventional", "integral"), default="conventional",
                            doc="pins in housing grooves, or one piece with the housing",
                            source="the usual construction, pins in grooves (the pin-housing "
                                   "paper's baseline beside its integral housing)")
    equidistant_modification_mm: float = _f(-1.0, 1.0, default=0.0, source=_UNMODIFIED)
    move_distance_modification_mm: float = _f(-1.0, 1.0, default=0.0, source=_UNMODIFIED)
    rotation_modification_deg: float = _f(-1.0, 1.0, default=0.0, source=_UNMODIFIED)
    disc_load_factor: float = _f(1.0, 2.0, default=1.0,
                                 doc="torque on one disc = factor * output torque / disc_count",
                                 source="an even split between the discs; the pin-housing "
                                        "paper's 1.1 covers manufacturing errors "
                                        "(docs/derivations.md C4)")
    housing_outer_radius_mm: float | None = _f(0.0, None, lo_open=True, default=None,
                                               doc="outer radius of the pin housing",
                                               unset="the pin circle + 5 pin radii",
                                               source="ASSUMPTION: a wall of 4 pin radii "
                                                      "outside the pins (no source)")
    disc_holes: DiscHoles = field(default_factory=DiscHoles)

    def _check(self):
        if self.housing_outer_radius_mm is None:       # a wall of 5 pin radii by default
            object.__setattr__(self, "housing_outer_radius_mm",
                               self.pin_circle_radius_mm + 5 * self.pin_radius_mm)
        inner = self.pin_circle_radius_mm + self.pin_radius_mm
        wall = max(HOUSING_WALL_MAX * self.pin_circle_radius_mm, 4 * self.pin_radius_mm)
        check_range("cycloid.housing_outer_radius_mm", self.housing_outer_radius_mm, inner,
                    inner + wall, lo_open=True, error=CaseError,
                    why="the housing must enclose the pins, with a wall up to the pin circle "
                        "radius (or the default 4 pin radii) thick")
        if self.lobe_count != self.pin_count - 1:
            raise CaseError(f"cycloid.lobe_count = {self.lobe_count} must equal "
                            f"pin_count - 1 = {self.pin_count - 1} (one-tooth-difference drive)")
        # Looped / cusped / undercut profiles and hole layout: the geometry's own checks,
        # restated with the case's keys and units.
        try:
            geometry = self.geometry()
            if self.disc_holes != DiscHoles():
                disc_polygon(geometry, self.holes_si(), points_per_lobe=16)
        except GeometryError as exc:
            raise _with_hole_keys(_restate(exc, "cycloid", _CYCLOID_KEYS)) from None

    def geometry(self):
        """The SI geometry record :class:`toothfem.geometry.cycloid.CycloidGeometry`.

        Returns
        -------
        CycloidGeometry
            Radii and modifications in m, the rotation modification in rad.

        Raises
        ------
        GeometryError
            If the profile is looped, undercut or interferes (the record's own checks).
        """
        return CycloidGeometry(
            pin_count=self.pin_count,
            pin_circle_radius_m=self.pin_circle_radius_mm * M_PER_MM,
            eccentricity_m=self.eccentricity_mm * M_PER_MM,
            pin_radius_m=self.pin_radius_mm * M_PER_MM,
            equidistant_m=self.equidistant_modification_mm * M_PER_MM,
            move_distance_m=self.move_distance_modification_mm * M_PER_MM,
            rotation_rad=math.radians(self.rotation_modification_deg),
        )

    def holes_si(self, output=None):
        """The disc's holes in metres.

        Parameters
        ----------
        output : OutputMechanism, optional
            A K-H-V drive's output pins: their holes in the disc (radius ``hole_radius_mm``,
            else the pin's or roller's radius plus the eccentricity).

        Returns
        -------
        toothfem.geometry.disc.DiscHolesSI
            Counts and radii [m] of the centre bore, crank holes, pillar holes and output
            pins' holes.
        """
        h = self.disc_holes
        hole = None if output is None else (
            output.hole_radius_mm if output.hole_radius_mm is not None
            else output.contact_radius_mm + self.eccentricity_mm)
        return DiscHolesSI(
            output_hole_count=0 if output is None else output.pin_count,
            output_hole_circle_radius_m=0.0 if output is None else
            output.pin_hole_circle_radius_mm * M_PER_MM,
            output_hole_radius_m=0.0 if hole is None else hole * M_PER_MM,
            centre_bore_radius_m=h.centre_bore_radius_mm * M_PER_MM,
            crank_hole_count=h.crank_hole_count,
            crank_hole_circle_radius_m=h.crank_hole_circle_radius_mm * M_PER_MM,
            crank_hole_radius_m=h.crank_hole_radius_mm * M_PER_MM,
            pillar_hole_count=h.pillar_hole_count,
            pillar_hole_circle_radius_m=h.pillar_hole_circle_radius_mm * M_PER_MM,
            pillar_hole_radius_m=h.pillar_hole_radius_mm * M_PER_MM,
        )


@dataclass(frozen=True)
class SpurStage(_Section):
    """First (involute spur planetary) stage of an RV-type drive: sun on the input shaft,
    planets on the crankshafts."""
    _section = "first_stage"
    sun_teeth: int = _f(6, 400, integer=True)
    planet_teeth: int = _f(6, 400, integer=True)
    planet_count: int = _f(1, 8, integer=True, default=2,
                           source="ASSUMPTION: one planet on each of two crankshafts, as the "
                                  "shipped RV cases")
    module_mm: float = _f(*MODULE_MM, default=1.0, source="ASSUMPTION: no source")
    pressure_angle_deg: float = _f(10.0, 35.0, default=20.0,
                                   source="the standard basic rack's 20 deg (ISO 53:1998)")
    face_width_mm: float | None = _f(*FACE_WIDTH_MM, default=None,
                                     unset="10 modules",
                                     source="ASSUMPTION: the middle of the usual 8-12 modules "
                                            "of industrial spur gears (the RV paper gives "
                                            "none; toothfem.si.SPUR_DEFAULT_WIDTH_MODULES)")
    mesh_efficiency: float | None = _f(MESH_EFFICIENCY_MIN, 1.0, default=None,
                                       doc="the sun-planet mesh efficiency, declared",
                                       unset="from the friction model",
                                       source="Ohlendorf's loss factor with Schlenk's mean "
                                              "friction coefficient (ISO/TR 14179-2; "
                                              "efficiency/spur.py)")


@dataclass(frozen=True)
class SineStage(_Section):
    """One-tooth-difference sine-profile pair (planet inside a fixed ring)."""
    _section = "sine"
    planet_teeth: int = _f(10, 1000, integer=True)
    ring_teeth: int = _f(11, 1001, integer=True)
    module_mm: float = _f(*MODULE_MM)
    tooth_height_mm: float = _f(0.0, None, lo_open=True)
    face_width_mm: float = _f(*FACE_WIDTH_MM)
    centre_distance_mm: float | None = _f(0.0, None, lo_open=True, default=None,
                                          doc="a0; checked against m (z2 - z1)/2",
                                          unset="m (z2 - z1)/2",
                                          source="the pitch circles roll: a0 = m (z2 - z1)/2 "
                                                 "(the sine paper's Table 2)")

    def _check(self):
        if self.ring_teeth <= self.planet_teeth:
            raise CaseError(f"sine.ring_teeth = {self.ring_teeth} must exceed "
                            f"planet_teeth = {self.planet_teeth} (internal mesh)")
        a0 = self.module_mm * (self.ring_teeth - self.planet_teeth) / 2
        if self.centre_distance_mm is not None and not math.isclose(
                self.centre_distance_mm, a0, rel_tol=1e-6):
            raise CaseError(f"sine.centre_distance_mm = {self.centre_distance_mm!r} is not "
                            f"module*(ring_teeth-planet_teeth)/2 = {a0:g}: the pitch "
                            "circles must roll")
        try:
            check_load_carrying(self.geometry())   # issue 14: low teeth carry no torque
        except GeometryError as exc:
            raise _restate(exc, "sine", _SINE_KEYS) from None

    def geometry(self):
        """The SI geometry record of the pair.

        Returns
        -------
        toothfem.geometry.sine.SineGearPair
            Tooth numbers, module, tooth height and face width [m].

        Raises
        ------
        GeometryError
            If the pair's shape is invalid (the record's own checks).
        """
        return SineGearPair(planet_teeth=self.planet_teeth, ring_teeth=self.ring_teeth,
                            module_m=self.module_mm * M_PER_MM,
                            tooth_height_m=self.tooth_height_mm * M_PER_MM,
                            face_width_m=self.face_width_mm * M_PER_MM)


@dataclass(frozen=True)
class RVTrain(_Section):
    """Tooth numbers of a 2K-V (RV) train as in the RV paper's notation."""
    _section = "rv"
    sun_teeth: int = _f(6, 400, integer=True)          # z1
    planet_teeth: int = _f(6, 400, integer=True)       # z2
    disc_teeth: int = _f(3, 399, integer=True)         # z4 = z4'
    pin_count: int = _f(4, 400, integer=True)          # z5
    disc_count: int = _f(1, 4, integer=True, default=2,
                         source="the RV paper's two discs, 4 and 4'")
    mesh_efficiency: float = _f(MESH_EFFICIENCY_MIN, 1.0, default=0.94,
                                doc="efficiency assumed for every gear pair (RV paper)",
                                source="the RV paper assumes 0.94 for every gear pair "
                                       "(Eqs. 18-19)")

    def _check(self):
        if self.pin_count <= self.disc_teeth:
            raise CaseError(f"rv.pin_count = {self.pin_count} must exceed "
                            f"disc_teeth = {self.disc_teeth}")


#: What an unset load key of [operating] stands for, and why.
_LOAD_UNSET = "from the load key given"
_LOAD_SOURCE = ("one of output_torque_Nm, input_torque_Nm and input_power_kW is required; "
                "the others follow from it")


@dataclass(frozen=True)
class Operating(_Section):
    _section = "operating"
    input_speed_rpm: float = _f(*SPEED_RPM, default=1000.0,
                                source="ASSUMPTION: a round input speed (no source)")
    output_torque_Nm: float | None = _f(*TORQUE_NM, default=None, unset=_LOAD_UNSET,
                                        source=_LOAD_SOURCE)
    input_torque_Nm: float | None = _f(*INPUT_TORQUE_NM, default=None, unset=_LOAD_UNSET,
                                       source=_LOAD_SOURCE)
    input_power_kW: float | None = _f(*POWER_KW, default=None, unset=_LOAD_UNSET,
                                      source=_LOAD_SOURCE)
    rated_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="rated output torque of the reducer (catalogue, datasheet): check warns above "
            "it; the stiffness curve spans +-it",
        unset="the operating torque stands in",
        source="none: the catalogue's rated torque where the case states it")
    start_stop_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="allowable output torque when starting and stopping (catalogue): above it a "
            "warning",
        unset="no check",
        source="none: the catalogue's figure where the case states it (RV-40E: 1029 N m)")
    momentary_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="momentary maximum output torque (catalogue, e.g. an emergency stop): above it a "
            "warning that the reducer is damaged; rated <= start/stop <= momentary, else refused",
        unset="no check",
        source="none: the catalogue's figure where the case states it (RV-40E: 2058 N m)")

    def _check(self):
        limits = [("rated_torque_Nm", self.rated_torque_Nm),
                  ("start_stop_torque_Nm", self.start_stop_torque_Nm),
                  ("momentary_torque_Nm", self.momentary_torque_Nm)]
        given = [(k, v) for k, v in limits if v]
        for (k1, v1), (k2, v2) in zip(given, given[1:]):
            if v2 < v1:
                raise CaseError(f"operating.{k2} = {v2:g} is below operating.{k1} = {v1:g}: "
                                "rated <= start/stop <= momentary")


#: Where the Vogel constants' defaults come from (docs/efficiency.md, "Oil temperature").
_VOGEL_SOURCE = ("ASSUMPTION: a mineral oil; B = 1000, C = 95 °C take 100 mm²/s at 40 °C to "
                 "10.2 at 100 °C (B = 900 reproduces ISO VG 68's 68 -> 8.7 within 5 %)")


@dataclass(frozen=True)
class Lubricant(_Section):
    _section = "lubricant"
    dynamic_viscosity_Pa_s: float = _f(1e-4, 10.0, default=0.02,
                                       doc="eta0 at the reference temperature (EHL friction)",
                                       source="the sine paper's Table 3: eta0 = 2e-8 MPa s")
    kinematic_viscosity_mm2_s: float = _f(0.1, 10000.0, default=100.0,
                                          doc="nu at the reference temperature (churning, "
                                              "Palmgren's drag, film thickness)",
                                          source="ASSUMPTION: ISO VG 100 (ISO 3448: 100 mm²/s "
                                                 "at 40 °C)")
    density_kg_m3: float = _f(500.0, 1500.0, default=870.0,
                              source="ASSUMPTION: a mineral gear oil (no source)")
    pressure_viscosity_1_per_GPa: float = _f(1.0, 50.0, default=20.0,
                                             doc="alpha of Barus' law (EHL film)",
                                             source="ASSUMPTION: typical of mineral gear oils "
                                                    "at moderate temperature, about 10-30 "
                                                    "1/GPa (efficiency/friction.py)")
    reference_temperature_C: float = _f(-40.0, 200.0, default=40.0,
                                        doc="where the viscosities above hold",
                                        source="ISO 3448: viscosity grades are stated at "
                                               "40 °C")
    roughness_Ra_um: float = _f(0.0, 10.0, default=0.4,
                                doc="arithmetic mean roughness of the flanks",
                                source="the sine paper's Table 3: R_a = 0.4 µm")
    vogel_B_C: float = _f(100.0, 5000.0, default=1000.0,
                          doc="Vogel B: eta = A exp(B/(T + C)), T in deg C",
                          source=_VOGEL_SOURCE)
    vogel_C_C: float = _f(0.0, 300.0, default=95.0, doc="Vogel C [deg C]",
                          source=_VOGEL_SOURCE)
    churning: str = _f(choices=("none", "lu_xu_2024"), default="lu_xu_2024",
                       doc="churning (oil agitation and splash) law of an oil bath; "
                           "lu_xu_2024: the sine paper's Eq. 42",
                       source="Y. Lu & L. Xu, Heliyon 10 (2024) e26300, Eq. 42, on every gear "
                              "stage in an oil bath (was none before issue 13)")
    churning_scale: float = _f(0.0, 100.0, default=1.0,
                               doc="factor on the churning law",
                               source="1: the law as published (the loop's churning effect "
                                      "fits a correction)")
    lubrication: str = _f(choices=("oil_bath", "oil_mist", "oil_jet", "grease"),
                          default="oil_bath",
                          doc="how the reducer is lubricated: the churning law acts in an oil "
                              "bath; the bearings' viscous drag takes Palmgren's f0 of it",
                          source="ASSUMPTION: a horizontal reducer with its lower half in oil "
                                 "(the sine paper's rig)")
    pour_point_C: float = _f(-80.0, 50.0, default=-15.0,
                             doc="lowest temperature of the viscosity law",
                             source="ASSUMPTION: mineral ISO VG 68-680 gear oils pour at about "
                                    "-9 to -30 °C (makers' data sheets)")
    max_temperature_C: float = _f(0.0, 300.0, default=150.0,
                                  doc="highest temperature of the viscosity law",
                                  source="the upper limit of mineral oil named in issue 13 "
                                         "(oxidation); ISO/TR 14179-1 rates gear drives at a "
                                         "95 °C sump")

    def _check(self):
        t_ref = self.reference_temperature_C
        if not self.pour_point_C < t_ref < self.max_temperature_C:
            raise CaseError(f"lubricant.reference_temperature_C = {t_ref!r} is outside the "
                            f"valid range ({self.pour_point_C:g}, {self.max_temperature_C:g})"
                            ": between pour_point_C and max_temperature_C")


@dataclass(frozen=True)
class Friction(_Section):
    _section = "friction"
    coefficient: float = _f(0.0, 1.0, default=0.05,
                            doc="Coulomb friction at the tooth/pin contacts (mesh_law = "
                                "coulomb only)",
                            source="ASSUMPTION: lubricated steel on steel (no source); read "
                                   "by the Coulomb law only")
    bearing_coefficient: float = _f(0.0, 0.1, default=0.0015,
                                    doc="rolling bearings' load term M1 = mu P d_m/2 "
                                        "(Palmgren's mu = 2 f1)",
                                    source="SKF's constant coefficient of friction of deep "
                                           "groove ball bearings, 0.0015 (SKF General "
                                           "Catalogue, Friction, Table 1)")
    output_pin_coefficient: float = _f(0.0, 1.0, default=0.05,
                                       doc="output pins sliding in their holes or sleeves "
                                           "(the sine paper's f_k)",
                                       source="ASSUMPTION: lubricated steel sliding (no "
                                              "source; the sine paper's rig: f_k = 0.03)")
    pin_groove_coefficient: float = _f(0.0, 1.0, default=0.0,
                                       doc="conventional pins sliding in their housing "
                                           "grooves (0: pins roll freely)",
                                       source="0: the pins roll freely in their grooves")
    mesh_law: str = _f(choices=("ehl_xu2007", "coulomb", "benedict_kelley"),
                       default="ehl_xu2007", doc="friction law at the tooth/pin contacts",
                       source="the sine paper's choice: Xu, Kahraman et al., J. Mech. Des. "
                              "129 (2007) 58-68")
    boundary_coefficient: float = _f(0.0, 1.0, default=0.1,
                                     doc="asperity (boundary) friction of lubricated steel "
                                         "in mixed lubrication; 0: the EHL law alone",
                                     source="boundary-lubricated steel, about 0.1 (Bowden & "
                                            "Tabor 1950; Hutchings & Shipway 2017: "
                                            "0.05-0.15); was 0 before issue 13")
    drag_torque_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                doc="load-independent drag on the input shaft (seals, preload)",
                                source="0: no drag beyond the seals and bearings modelled")
    windage_torque_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                   doc="drag on the input shaft at 1000 rpm that grows with "
                                       "the square of the speed (windage: P = T_w (n/1000 "
                                       "rpm)^2 omega_in; Dawson 1984)",
                                   source="0: these reducers turn slowly in an oil bath, "
                                          "whose churning law covers the bath")


#: The source of an output mechanism's size where the case gives none.
_NO_SOURCE = "ASSUMPTION: no source fixes it (the sine prototype declares its own)"


@dataclass(frozen=True)
class OutputMechanism(_Section):
    """Pins in holes (W mechanism) and the eccentric bearing of a K-H-V stage."""
    _section = "output_mechanism"

    def _check(self):
        if self.roller_radius_mm is not None and self.roller_radius_mm <= self.pin_radius_mm:
            raise CaseError(f"output_mechanism.roller_radius_mm = {self.roller_radius_mm!r} "
                            f"must exceed pin_radius_mm = {self.pin_radius_mm!r} (a sleeve on "
                            "the pin)")

    @property
    def contact_radius_mm(self) -> float:
        """The radius that touches the hole: the roller's, else the pin's [mm]."""
        return self.roller_radius_mm if self.roller_radius_mm is not None else self.pin_radius_mm
    pin_count: int = _f(2, 24, integer=True, default=8, source=_NO_SOURCE)
    pin_hole_circle_radius_mm: float = _f(*RADIUS_MM, default=30.0, source=_NO_SOURCE)
    pin_radius_mm: float = _f(*PIN_RADIUS_MM, default=5.0, source=_NO_SOURCE)
    roller_radius_mm: float | None = _f(*PIN_RADIUS_MM, default=None,
                                        doc="a roller sleeve on each pin",
                                        unset="bare pins",
                                        source="none: a sleeve is declared where the "
                                               "drawing has one")
    hole_radius_mm: float | None = _f(*PIN_RADIUS_MM, default=None,
                                      doc="radius of the member's holes the pins pass "
                                          "through",
                                      unset="the pin's or roller's radius plus the "
                                            "eccentricity",
                                      source="zero nominal clearance: the pin touches its hole "
                                             "as the disc orbits (the K-H-V output "
                                             "mechanism's kinematics)")
    eccentric_bearing_inner_radius_mm: float = _f(*PIN_RADIUS_MM, default=10.0,
                                                  doc="r_p, the eccentric bearing's inner "
                                                      "radius",
                                                  source="the sine paper's Table 4: r_p = "
                                                         "10 mm")
    plain_bearing_friction_torque_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                                  doc="M_f of the bearings on the "
                                                      "non-eccentric shaft (sine paper Eq. 34)",
                                                  source="0: the sine paper states no M_f")


BEARING_TYPES = ("ball", "angular_ball", "cylindrical", "tapered", "needle")
#: The source of the external loads' defaults.
_NO_LOAD = "0: no external load on the output"


@dataclass(frozen=True)
class Seals(_Section):
    """Radial lip seals on the input and the output shaft (ISO/TR 14179-1 seal loss).
    None: the drive's own diameter (efficiency/envelope.py, ASSUMPTION); 0: no seal."""
    _section = "seals"
    # a shaft no larger than the largest reducer the case model takes (RADIUS_MM)
    input_diameter_mm: float | None = _f(
        0.0, 2 * RADIUS_MM[1], default=None,
        doc="shaft diameter under the input seal; seal loss P = 7.69e-6 D² n W (D in mm, n in "
            "rpm), ISO/TR 14179-1:2001; 0: no seal",
        unset="the drive's (efficiency/envelope.py)",
        source="ASSUMPTION: cycloid, RV: the input shaft in the discs' centre bore; sine: "
               "through the eccentric bearing (2 r_p)")
    output_diameter_mm: float | None = _f(
        0.0, 2 * RADIUS_MM[1], default=None,
        doc="shaft diameter under the output seal; the same law at the output speed",
        unset="the drive's (efficiency/envelope.py)",
        source="ASSUMPTION: the pin-circle diameter (cycloid, RV); 2 (R_w + r_x) (sine)")


@dataclass(frozen=True)
class Bearings(_Section):
    """The bearings on the eccentrics (crank bearings in the discs' holes of a 2K-V drive,
    the eccentric bearing of a K-H-V drive) and the main (output) bearing pair, with the
    external loads on the output. None: the drive's own value (efficiency/envelope.py)."""
    _section = "bearings"
    eccentric_type: str | None = _f(choices=BEARING_TYPES, default=None,
                                    doc="rolling-element type of the eccentric bearings "
                                        "(ISO 281's exponent, Palmgren's f0)",
                                    unset="needle",
                                    source="RV reducers' crank bearings are needle roller "
                                           "bearings (Nabtesco's RV construction): the "
                                           "system model's rollers; another type is refused")
    eccentric_pitch_diameter_mm: float | None = _f(
        0.0, None, lo_open=True, default=None,
        doc="checked to lie between the journal and the hole (refused naming the hole's key)",
        unset="the rollers' pitch circle",
        source="the system model's rollers: the hole less one roller diameter (2K-V crank "
               "hole, K-H-V centre bore); 2 r_p plus one roller (sine)")
    eccentric_dynamic_rating_kN: float | None = _f(
        0.0, None, lo_open=True, default=None,
        doc="basic dynamic load rating C of one eccentric bearing (ISO 281); refused above "
            "1.3x the rating of the rolling set that fits the hole",
        unset="ISO 281 of the rollers that fit (sine: no life)",
        source="ISO 281 of the needle rollers that fit the hole (efficiency/bearing_set.py); "
               "a sine reducer's has none")
    main_type: str = _f(choices=BEARING_TYPES, default="angular_ball",
                        doc="main bearing pair: angular contact ball bearings (RV-E)",
                        source="the RV-E's built-in main bearings; ISO 281:2007 Table 3 of a "
                               "40 deg contact: X = 0.35, Y = 0.57, e = 1.14")
    main_pitch_diameter_mm: float | None = _f(
        0.0, None, lo_open=True, default=None,
        unset="the pin-circle diameter (sine: 2 (R_w + r_x))",
        source="ASSUMPTION: the rows at the pin circle (Palmgren drag without an oil bath)")
    main_dynamic_rating_kN: float | None = _f(
        0.0, None, lo_open=True, default=None,
        doc="basic dynamic load rating C of one main bearing row (ISO 281)",
        unset="ISO 281 of an assumed ball set (sine: none)",
        source="ASSUMPTION: ISO 281 of a ball set with balls 6 % of the pitch diameter "
               "(cycloid, RV); a sine reducer's has none")
    contamination: str | None = _f(
        choices=("extreme_cleanliness", "high_cleanliness", "normal_cleanliness",
                 "slight_contamination", "typical_contamination", "severe_contamination",
                 "very_severe_contamination"), default=None,
        doc="lubricant cleanliness (ISO 281:2007 Table 13): with it, the modified life "
            "L10m = a_ISO L10 of every bearing",
        unset="no modified life",
        source="none: ISO 281's basic rating life L10 alone")
    main_span_mm: float | None = _f(0.0, None, lo_open=True, default=None,
                                    doc="distance between the load centres of the two rows",
                                    unset="needed with an external moment",
                                    source="none: needed only with an external moment")
    main_preload_N: float | None = _f(0.0, None, default=None,
                                      doc="axial preload of each main bearing row",
                                      unset="ASSUMPTION 2 % of the row's C0",
                                      source="ASSUMPTION: a light preload of makers' matched "
                                             "angular contact pairs is about 1-2 % of C0")
    external_radial_load_N: float = _f(0.0, None, default=0.0, source=_NO_LOAD)
    external_axial_load_N: float = _f(0.0, None, default=0.0, source=_NO_LOAD)
    external_moment_Nm: float = _f(0.0, None, default=0.0,
                                   doc="tilting moment on the output besides the one the "
                                       "offsets below give",
                                   source=_NO_LOAD)
    external_radial_offset_mm: float = _f(0.0, None, default=0.0,
                                          doc="axial distance from the main pair's centre to "
                                              "the radial load's line (its moment arm)",
                                          source=_NO_LOAD)
    external_axial_radius_mm: float = _f(0.0, None, default=0.0,
                                         doc="distance from the axis to the axial load's line "
                                             "(its moment arm)",
                                         source=_NO_LOAD)


@dataclass(frozen=True)
class Thermal(_Section):
    """Heat balance of the housing: losses = h A (T_oil - T_ambient). None: a cited
    estimate (efficiency/thermal.py)."""
    _section = "thermal"
    ambient_C: float = _f(-40.0, 100.0, default=20.0,
                          doc="ambient air; within [pour point, max_temperature_C) of the oil",
                          source="ASSUMPTION: a laboratory")
    housing_area_m2: float | None = _f(0.0, None, lo_open=True, default=None,
                                       doc="surface that sheds heat",
                                       unset="6 pi r² of the housing radius r",
                                       source="ASSUMPTION: a cylinder of the housing radius as "
                                              "long as its diameter (RV-40E: 0.118 m² against "
                                              "about 0.12 m² of the real reducer)")
    heat_transfer_W_m2K: float | None = _f(0.0, 1000.0, lo_open=True, default=None,
                                           doc="heat transfer coefficient of the housing's "
                                               "surface",
                                           unset="natural convection + radiation at each "
                                                 "temperature",
                                           source="J.P. Holman, Heat Transfer (10th ed.), "
                                                  "Table 7-2: a horizontal cylinder in air, "
                                                  "h = 1.32 (dT/d)^(1/4), plus radiation")
    emissivity: float = _f(0.0, 1.0, default=0.9,
                           doc="of the housing's surface (radiation)",
                           source="painted housing: Incropera & DeWitt, Fundamentals of Heat "
                                  "and Mass Transfer, Table A.11 (paints 0.90-0.98)")
    heat_capacity_J_K: float | None = _f(0.0, None, lo_open=True, default=None,
                                         doc="lumped heat capacity",
                                         unset="half the housing envelope in steel at "
                                               "450 J/(kg K)",
                                         source="ASSUMPTION on the share (an RV-40E weighs "
                                                "about 9 kg, 0.4 of its envelope); steel: 434-477 "
                                                "J/(kg K) at 300 K (Incropera & DeWitt, Table "
                                                "A.1)")
    sensor_resistance_K_W: float = _f(0.0, 20.0, default=0.0,
                                      doc="oil at the contacts above a sump sensor per W "
                                          "of loss (the loop's thermal effect; 0: none)",
                                      source="0: none; fitted by the loop's thermal effect "
                                             "(docs/loop.md)")
    case_temperature_limit_C: float | None = _f(0.0, 300.0, lo_open=True, default=None,
                                                doc="the maker's limit of the case surface "
                                                    "(a warning above it)",
                                                unset="60 °C for a 2K-V drive, else none",
                                                source="Nabtesco RV-E catalogue: the surface "
                                                       "at most 60 °C (ASSUMPTION for another "
                                                       "maker's RV)")
    mounting: str = _f(choices=("free", "flange"), default="free",
                       doc="free: the housing sheds heat to the air only (convection and "
                           "radiation); flange: one end face is bolted to a machine that "
                           "conducts heat away",
                       source="ASSUMPTION: no conduction into a machine (the hotter case)")
    contact_conductance_W_m2K: float = _f(1.0, 1e6, default=1000.0,
                                          doc="thermal contact conductance of the bolted "
                                              "flange joint",
                                          source="ASSUMPTION: bolted steel joints 400-1700 "
                                                 "W/(m² K) (Incropera & DeWitt, Table 3.1)")
    mount_conductivity_W_mK: float = _f(0.1, 1000.0, default=50.0,
                                        doc="thermal conductivity of the machine the flange "
                                            "is bolted to",
                                        source="steel (Incropera & DeWitt, Table A.1: carbon "
                                               "steel 60.5, AISI 4140 42.6)")


@dataclass(frozen=True)
class DutyPoint(_Section):
    """One row of a duty cycle: output torque, input speed and the share of time."""
    _section = "duty_cycle"
    output_torque_Nm: float = _f(0.0, None, lo_open=True, doc="load torque of the row")
    input_speed_rpm: float = _f(0.0, None, lo_open=True, doc="input speed of the row")
    time_share: float = _f(0.0, 1.0, lo_open=True,
                           doc="share of the operating time; the rows' shares add up to 1")


#: Tolerance on the sum of a duty cycle's time shares (shares quoted to three digits).
DUTY_SHARE_TOL = 1e-3


def check_ambient(thermal: Thermal, lubricant: Lubricant) -> None:
    """Refuse an ambient at which the oil is outside its range (below its pour point, at or
    above its upper limit).

    Parameters
    ----------
    thermal : Thermal
        The ``[thermal]`` section (ambient [deg C]).
    lubricant : Lubricant
        The ``[lubricant]`` section (pour point and upper limit [deg C]).

    Raises
    ------
    CaseError
        One line with the valid range.
    """
    lo, hi = lubricant.pour_point_C, lubricant.max_temperature_C
    if not lo <= thermal.ambient_C < hi:
        raise CaseError(f"thermal.ambient_C = {thermal.ambient_C!r} is outside the valid "
                        f"range [{lo:g}, {hi:g}): the lubricant's pour_point_C to "
                        "max_temperature_C")


def check_duty_cycle(rows) -> None:
    """Refuse a duty cycle whose time shares do not sum to 1.

    Parameters
    ----------
    rows : sequence of DutyPoint
        The ``[[duty_cycle]]`` rows (empty: nothing to check).

    Raises
    ------
    CaseError
        One line with the sum and the valid range (1 within DUTY_SHARE_TOL).
    """
    if rows:
        total = float(sum(r.time_share for r in rows))
        check_range("duty_cycle time_share sum", total, 1 - DUTY_SHARE_TOL,
                    1 + DUTY_SHARE_TOL, error=CaseError,
                    why="the shares of time must add up to 1")


@dataclass(frozen=True)
class Supports(_Section):
    """The elastic supports in series with the mesh (``toothfem stiffness``): the rollers of
    the crank bearings (RV: in the disc's crank holes) or of the eccentric bearing (K-H-V),
    the crankshafts (span between their carrier bearings) and the output carrier."""
    _section = "supports"
    bearing_roller_count: int | None = _f(
        3, 200, integer=True, default=None, unset="as many as fit",
        source="ASSUMPTION: rollers 1.2 diameters apart on their pitch circle, cage webs "
               "between them (fem/datasheet/supports.py)")
    bearing_roller_length_mm: float | None = _f(
        0.0, None, lo_open=True, default=None, unset="the member's face width",
        source="ASSUMPTION: rollers as long as the disc (planet) is wide")
    bearing_roller_diameter_mm: float | None = _f(
        0.0, None, lo_open=True, default=None, unset="a quarter of the raceway's radius",
        source="ASSUMPTION: needle and cylindrical roller bearings of reducers, 0.2-0.3 of "
               "the raceway's radius (fem/datasheet/supports.py)")
    crankshaft_diameter_mm: float | None = _f(
        0.0, None, lo_open=True, default=None, unset="the journal less twice the eccentricity",
        source="ASSUMPTION: the shaft passes through its eccentric journal (sine: "
               "2 (r_p - a0))")
    crankshaft_span_mm: float | None = _f(
        0.0, None, lo_open=True, default=None, unset="(discs + 2) face widths",
        source="ASSUMPTION: the discs side by side and one face width for each support "
               "bearing")
    carrier_stiffness_Nm_per_arcmin: float | None = _f(
        0.0, None, lo_open=True, default=None, unset="a rigid carrier",
        source="none: no carrier compliance in series")


@dataclass(frozen=True)
class MeasuredPoint(_Section):
    _section = "measured"
    input_speed_rpm: float = _f(*SPEED_RPM)
    output_torque_Nm: float = _f(*TORQUE_NM)
    efficiency: float = _f(0.0, 1.0, lo_open=True, doc="output power / input power")
    source: str = _f(default="", doc="where the point comes from",
                     source="empty: none stated")
