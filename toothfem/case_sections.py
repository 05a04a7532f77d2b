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
from .case_checks import (CARRIER_NM_PER_ARCMIN, DRAG_NMM, ECCENTRICITY_MM, FACE_WIDTH_MM,
                          HOUSING_WALL_MAX, MESH_EFFICIENCY_MIN, MODULE_MM, PIN_RADIUS_MM,
                          RADIUS_MM, STRESS_MPA, SUPPORT_MM, check_type, expected_type)
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
    ``unit`` (None: from the key's suffix, :func:`toothfem.units.symbol_of`)."""
    md = dict(lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open, doc=doc, choices=choices,
              integer=integer, source=source, unset=unset, unit=unit)
    return field(default=default, metadata=md)


def _stress(default: float, doc: str, source: str):
    """A positive stress limit [MPa] with its default and the default's source."""
    return _f(*STRESS_MPA, lo_open=True, default=default, doc=doc, source=source)


class _Section:
    """Mixin: validate every field against the range in its metadata."""

    _section = ""

    def __post_init__(self):
        for f in dataclasses.fields(self):  # type: ignore[arg-type]  # every subclass is a dataclass
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


#: The source of the face width's modifications' defaults (issue 43).
_FLAT = "0: none (straight along the width; the partial crown's flat: half the width)"

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
    # at most the largest pin circle, a pin and a wall as thick as that circle (_check)
    housing_outer_radius_mm: float | None = _f(0.0, 2 * RADIUS_MM[1] + PIN_RADIUS_MM[1],
                                               lo_open=True, default=None,
                                               doc="outer radius of the pin housing",
                                               unset="the pin circle + 5 pin radii",
                                               source="ASSUMPTION: a wall of 4 pin radii "
                                                      "outside the pins (no source)")
    # the face width in slices (docs/face_width.md; fem/cycloid_fe/slices.py)
    face_slices: int = _f(1, 99, integer=True, default=1, doc="slices along the face width",
                          source="1: the planar model, the load uniform over the width")
    disc_tilt_arcmin: float = _f(-60.0, 60.0, default=0.0, doc="the disc's imposed tilt "
                                 "about the axis normal to its pins' resultant", source=_FLAT)
    face_crowning_um: float = _f(0.0, 100.0, default=0.0, doc="the disc's crown: its drop "
                                 "at each edge of the face", source=_FLAT)
    face_crowning_form: str = _f(choices=("circular", "partial", "logarithmic"),
                                 default="circular", doc="the crown's form along the width",
                                 source="a circular arc, the usual crown")
    face_crowning_flat_fraction: float = _f(0.0, 1.0, hi_open=True, default=0.5,
                                            doc="a partial crown's flat middle, a fraction "
                                                "of the width", source=_FLAT)
    face_crowning_load_N: float | None = _f(0.0, 1e6, lo_open=True, default=None,
                                            doc="the pin force a logarithmic crown is "
                                                "designed for (Lundberg)",
                                            unset="required for the logarithmic form",
                                            source="none: the design load is the user's")
    pin_span_mm: float | None = _f(0.0, 1000.0, lo_open=True, default=None,
                                   doc="conventional pins held at their ends this far apart "
                                       "(beams coupling the slices)",
                                   unset="held along their length in the grooves: no bending",
                                   source="the usual construction, pins in grooves (no "
                                          "bending between supports)")
    disc_holes: DiscHoles = field(default_factory=DiscHoles)

    def _check(self):
        if self.pin_span_mm is not None and (self.face_slices == 1 or self.pin_span_mm
                                             < self.face_width_mm):
            raise CaseError(f"cycloid.pin_span_mm = {self.pin_span_mm!r} is outside the valid "
                            f"range: >= face_width_mm = {self.face_width_mm} with face_slices "
                            "> 1")
        if self.face_slices == 1 and (self.disc_tilt_arcmin or self.face_crowning_um):
            raise CaseError("cycloid.face_slices = 1 is outside the valid range with a tilt "
                            "or a crown: 2 to 99 slices (the planar model has one gap)")
        if (self.face_crowning_form == "logarithmic" and self.face_crowning_um
                and self.face_crowning_load_N is None):
            raise CaseError("cycloid.face_crowning_load_N = None is outside the valid range "
                            "for a logarithmic crown: > 0 N (its design pin force)")
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
    # a tooth no taller than the largest module (the pair's own bound, a fraction of its
    # module, is checked with its geometry)
    tooth_height_mm: float = _f(0.0, MODULE_MM[1], lo_open=True)
    face_width_mm: float = _f(*FACE_WIDTH_MM)
    # inside the largest ring (RADIUS_MM)
    centre_distance_mm: float | None = _f(0.0, RADIUS_MM[1], lo_open=True, default=None,
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
        *SUPPORT_MM, lo_open=True, default=None, unset="the member's face width",
        source="ASSUMPTION: rollers as long as the disc (planet) is wide")
    bearing_roller_diameter_mm: float | None = _f(
        *SUPPORT_MM, lo_open=True, default=None, unset="a quarter of the raceway's radius",
        source="ASSUMPTION: needle and cylindrical roller bearings of reducers, 0.2-0.3 of "
               "the raceway's radius (fem/datasheet/supports.py)")
    crankshaft_diameter_mm: float | None = _f(
        *SUPPORT_MM, lo_open=True, default=None, unset="the journal less twice the eccentricity",
        source="ASSUMPTION: the shaft passes through its eccentric journal (sine: "
               "2 (r_p - a0))")
    crankshaft_span_mm: float | None = _f(
        *SUPPORT_MM, lo_open=True, default=None, unset="(discs + 2) face widths",
        source="ASSUMPTION: the discs side by side and one face width for each support "
               "bearing")
    carrier_stiffness_Nm_per_arcmin: float | None = _f(
        *CARRIER_NM_PER_ARCMIN, lo_open=True, default=None, unset="a rigid carrier",
        source="none: no carrier compliance in series")


