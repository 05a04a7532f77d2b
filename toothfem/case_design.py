"""The sections of a case file about the reducer as built and the design sought:
``[tolerances]`` (what ``toothfem tolerance`` samples) and ``[design]`` (the targets of
``toothfem design``). Units in the key names; ranges checked as in
:mod:`toothfem.case_sections`."""
from __future__ import annotations

from dataclasses import dataclass

from .case_sections import _f, _Section
from .errors import CaseError
from .fem.deviations import DISTRIBUTIONS
from .layouts import LAYOUTS

#: Largest tolerance zone accepted [mm]: a tenth of a millimetre is coarse turning; the
#: contact model's first-order gap shifts hold for deviations far below the part sizes.
TOLERANCE_MAX_MM = 0.1


#: The source of every zone's default: the part as drawn.
_EXACT = "0: the part is made exactly"


def _zone(doc: str):
    return _f(0.0, TOLERANCE_MAX_MM, default=0.0, doc=doc, source=_EXACT)


def _own_distribution():
    return _f(choices=DISTRIBUTIONS, default=None,
              doc="this tolerance's distribution instead of the section's",
              unset="the section's distribution", source="none: the section's distribution")


@dataclass(frozen=True)
class Tolerances(_Section):
    """Manufacturing tolerances of the meshing parts (0: made exactly). Zones as drawings
    state them: ISO 1101 true position (a circle of the zone's diameter), symmetric limits
    +-a, ISO 286 deviation limits of a diameter (docs/tolerance.md)."""
    _section = "tolerances"
    distribution: str = _f(choices=DISTRIBUTIONS, default="normal",
                           doc="normal: 3 sigma at the zone's limit; uniform: over the zone "
                               "(a true-position zone: over its area)",
                           source="a capable process: 3 sigma at each limit (Cpk = 1)")
    pin_position_mm: float = _zone("ISO 1101 true-position zone diameter of each pin's "
                                   "centre")
    pin_diameter_lower_mm: float = _f(-TOLERANCE_MAX_MM, TOLERANCE_MAX_MM, default=0.0,
                                      doc="ISO 286 lower deviation of each pin's diameter "
                                          "(h5 on 3-6 mm: -0.005 and 0)", source=_EXACT)
    pin_diameter_upper_mm: float = _f(-TOLERANCE_MAX_MM, TOLERANCE_MAX_MM, default=0.0,
                                      doc="ISO 286 upper deviation of each pin's diameter",
                                      source=_EXACT)
    pin_circle_radius_mm: float = _zone("+- limit of the pin-circle radius (one value for the ring)")
    disc_profile_mm: float = _zone("+- limit of each disc flank's normal deviation (one value per "
                                   "flank)")
    eccentricity_mm: float = _zone("+- limit of the crank's eccentricity")
    crank_hole_position_mm: float = _zone("true-position zone diameter of the disc's crank "
                                          "hole(s) against its profile")
    tooth_profile_mm: float = _zone("+- limit of each sine tooth flank's normal deviation "
                                    "(planet and ring)")
    # each tolerance's own distribution, instead of ``distribution`` (none: that one)
    pin_position_distribution: str | None = _own_distribution()
    pin_diameter_distribution: str | None = _own_distribution()
    pin_circle_radius_distribution: str | None = _own_distribution()
    disc_profile_distribution: str | None = _own_distribution()
    eccentricity_distribution: str | None = _own_distribution()
    crank_hole_position_distribution: str | None = _own_distribution()
    tooth_profile_distribution: str | None = _own_distribution()

    def _check(self):
        if self.pin_diameter_lower_mm > self.pin_diameter_upper_mm:
            raise CaseError(f"tolerances.pin_diameter_lower_mm = {self.pin_diameter_lower_mm!r}"
                            f" is outside the valid range [-{TOLERANCE_MAX_MM:g}, "
                            f"pin_diameter_upper_mm = {self.pin_diameter_upper_mm!r}]")


#: Percentiles of a tolerance ensemble a target may be set at.
PERCENTILE_RANGE = (50.0, 99.9)
#: The source of the search box's default bounds.
_BOUNDS = ("ASSUMPTION: 0.02 of each modification on the side that opens clearance, "
           "both sides for the rotation (docs/tolerance.md)")


@dataclass(frozen=True)
class Design(_Section):
    """Targets of the modification search (``toothfem design``): the largest backlash, the
    fewest pins in contact at every position, optionally a limit on the maximum Hertz
    pressure (else it is minimised), optionally at a percentile of the tolerance ensemble;
    the bounds of each modification searched."""
    _section = "design"
    max_backlash_arcmin: float = _f(0.0, 60.0, lo_open=True, default=1.0,
                                    doc="the largest backlash sought",
                                    source="the catalogue class of precision robot reducers: "
                                           "1 arcmin")
    min_contacts: int = _f(1, 400, integer=True, default=3,
                           doc="pins in contact at every position at the operating torque",
                           source="ASSUMPTION: three pins share the load (no source)")
    max_ph_MPa: float | None = _f(0.0, 10000.0, lo_open=True, default=None,
                                  doc="limit of the maximum Hertz pressure",
                                  unset="minimised", source="none: the search minimises it")
    percentile: float | None = _f(*PERCENTILE_RANGE, default=None,
                                  doc="targets hold at this percentile of reducers built "
                                      "within [tolerances] (backlash, pressure: P_q; "
                                      "contacts: P_(100-q))",
                                  unset="the nominal reducer",
                                  source="none: the targets hold for the reducer as drawn")
    samples: int = _f(4, 2000, integer=True, default=8,
                      doc="tolerance samples per candidate when percentile is set (the same "
                          "draws for every candidate)",
                      source="ASSUMPTION: a small ensemble per candidate (no source)")
    # bounds of the search; a positive equidistant and a negative move-distance
    # modification open clearance (docs/tolerance.md)
    equidistant_min_mm: float = _f(-0.1, 0.1, default=0.0, source=_BOUNDS)
    equidistant_max_mm: float = _f(-0.1, 0.1, default=0.02, source=_BOUNDS)
    move_distance_min_mm: float = _f(-0.1, 0.1, default=-0.02, source=_BOUNDS)
    move_distance_max_mm: float = _f(-0.1, 0.1, default=0.0, source=_BOUNDS)
    rotation_min_deg: float = _f(-1.0, 1.0, default=-0.02, source=_BOUNDS)
    rotation_max_deg: float = _f(-1.0, 1.0, default=0.02, source=_BOUNDS)

    def _check(self):
        for name, unit in (("equidistant", "mm"), ("move_distance", "mm"), ("rotation", "deg")):
            lo = getattr(self, f"{name}_min_{unit}")
            hi = getattr(self, f"{name}_max_{unit}")
            if lo > hi:
                raise CaseError(f"design.{name}_min_{unit} = {lo!r} is outside the valid range "
                                f"(-inf, {name}_max_{unit} = {hi!r}]")

    def bounds(self) -> dict:
        """The box the search varies the modifications in.

        Returns
        -------
        dict of str to tuple
            [cycloid] key -> (lo, hi) in that key's unit (mm, deg).
        """
        return {"equidistant_modification_mm": (self.equidistant_min_mm,
                                                self.equidistant_max_mm),
                "move_distance_modification_mm": (self.move_distance_min_mm,
                                                  self.move_distance_max_mm),
                "rotation_modification_deg": (self.rotation_min_deg, self.rotation_max_deg)}


def check_tolerances(tolerances: Tolerances, stage: str | None) -> None:
    """Refuse a tolerance of a part the reducer lacks (a pin zone on a sine pair).

    Parameters
    ----------
    tolerances : Tolerances
    stage : {"cycloid", "sine"} or None
        The meshing stage modelled (None: none).

    Raises
    ------
    CaseError
        Naming the first nonzero key of another stage.
    """
    for layout in LAYOUTS:
        if layout.stage_section == stage:
            continue
        for key in layout.tolerance_keys:
            value = getattr(tolerances, key)
            if value:
                raise CaseError(f"tolerances.{key} = {value!r} applies to a {layout.stage_section} stage, "
                                f"which this case has not: valid value 0")


@dataclass(frozen=True)
class Envelope(_Section):
    """The catalogue's outer envelope a reducer must fit (``toothfem size``: every dimension
    chosen inside it; ``check``: the case's parts against it)."""
    _section = "envelope"
    outer_diameter_mm: float = _f(1.0, 4000.0, doc="the case's largest outer diameter "
                                                   "(the maker's outline drawing)")
    length_mm: float = _f(1.0, 4000.0, doc="axial length from the output flange's face to "
                                           "the case's input side (the motor flange "
                                           "excluded; the maker's outline drawing)")
    centre_bore_diameter_mm: float = _f(0.0, 4000.0, default=0.0,
                                        doc="the input shaft's (or a hollow unit's) bore "
                                            "through the discs", source="0: no bore "
                                            "required (the outline drawing gives a hollow "
                                            "unit's)")

    def _check(self):
        if self.centre_bore_diameter_mm >= self.outer_diameter_mm:
            raise CaseError(f"envelope.centre_bore_diameter_mm = {self.centre_bore_diameter_mm!r}"
                            f" is outside the valid range [0, outer_diameter_mm = "
                            f"{self.outer_diameter_mm!r})")
