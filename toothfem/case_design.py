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


def _zone(doc: str):
    return _f(0.0, TOLERANCE_MAX_MM, default=0.0, doc=doc)


def _own_distribution():
    return _f(choices=DISTRIBUTIONS, default=None,
              doc="this tolerance's distribution instead of the section's")


@dataclass(frozen=True)
class Tolerances(_Section):
    """Manufacturing tolerances of the meshing parts (0: made exactly). Zones as drawings
    state them: ISO 1101 true position (a circle of the zone's diameter), symmetric limits
    +-a, ISO 286 deviation limits of a diameter (docs/tolerance.md)."""
    _section = "tolerances"
    distribution: str = _f(choices=DISTRIBUTIONS, default="normal",
                           doc="normal: 3 sigma at the zone's limit; uniform: over the zone")
    pin_position_mm: float = _zone("true-position zone diameter of each pin's centre")
    pin_diameter_lower_mm: float = _f(-TOLERANCE_MAX_MM, TOLERANCE_MAX_MM, default=0.0,
                                      doc="lower deviation of each pin's diameter")
    pin_diameter_upper_mm: float = _f(-TOLERANCE_MAX_MM, TOLERANCE_MAX_MM, default=0.0,
                                      doc="upper deviation of each pin's diameter")
    pin_circle_radius_mm: float = _zone("+- limit of the pin-circle radius")
    disc_profile_mm: float = _zone("+- limit of each disc flank's normal deviation")
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


@dataclass(frozen=True)
class Design(_Section):
    """Targets of the modification search (``toothfem design``): the largest backlash, the
    fewest pins in contact at every position, optionally a limit on the maximum Hertz
    pressure (else it is minimised), optionally at a percentile of the tolerance ensemble;
    the bounds of each modification searched."""
    _section = "design"
    max_backlash_arcmin: float = _f(0.0, 60.0, lo_open=True, default=1.0,
                                    doc="catalogue class of precision reducers: 1 arcmin")
    min_contacts: int = _f(1, 400, integer=True, default=3)
    max_ph_MPa: float | None = _f(0.0, 10000.0, lo_open=True, default=None,
                                  doc="limit of the maximum Hertz pressure; none: minimised")
    percentile: float | None = _f(*PERCENTILE_RANGE, default=None,
                                  doc="targets hold at this percentile of [tolerances]")
    samples: int = _f(4, 2000, integer=True, default=8,
                      doc="tolerance samples per candidate when percentile is set")
    # bounds of the search; a positive equidistant and a negative move-distance
    # modification open clearance (docs/tolerance.md)
    equidistant_min_mm: float = _f(-0.1, 0.1, default=0.0)
    equidistant_max_mm: float = _f(-0.1, 0.1, default=0.02)
    move_distance_min_mm: float = _f(-0.1, 0.1, default=-0.02)
    move_distance_max_mm: float = _f(-0.1, 0.1, default=0.0)
    rotation_min_deg: float = _f(-1.0, 1.0, default=-0.02)
    rotation_max_deg: float = _f(-1.0, 1.0, default=0.02)

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
