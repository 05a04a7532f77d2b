"""The sine gear pair record: tooth numbers, module, tooth height and face width, refused
when out of range or when the tooth height breaks a validity bound (limits.py).

(Kept apart from profile.py: its validation needs the bounds, the bounds need the conjugate
ring, and the ring needs the planet profile.)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ...errors import GeometryError, check_range
from .limits import check_tooth_height
from .profile import profile_params

#: Fewest planet teeth accepted (the case model's range starts there too).
MIN_PLANET_TEETH = 10


@dataclass(frozen=True)
class SineGearPair:
    """Planet (external sine gear, the sine paper's Eq. 1) inside a fixed ring (its
    conjugate), SI units.

    Refused (GeometryError naming the parameter, its value and the bound): non-integer or
    too few teeth, ring_teeth <= planet_teeth, module or face width <= 0, tooth height
    outside (0, r1) (Eq. 1 needs a < r1), and tooth heights for which the conjugate ring is
    cusped or self-intersecting, the contact path reverses on the planet, or the planet
    interferes with the ring somewhere on its circumference (bounds from
    :func:`~toothfem.geometry.sine.tooth_height_limits`).

    Attributes
    ----------
    planet_teeth : int
        z1 (>= MIN_PLANET_TEETH).
    ring_teeth : int
        z2 (>= z1 + 1).
    module_m : float
        Module m (m).
    tooth_height_m : float
        Tooth height a, the sine amplitude (m).
    face_width_m : float
        Face width (m).
    """
    planet_teeth: int
    ring_teeth: int
    module_m: float
    tooth_height_m: float
    face_width_m: float

    def __post_init__(self):
        z1 = _teeth("planet_teeth", self.planet_teeth, MIN_PLANET_TEETH,
                    "fewer teeth are outside the tested range")
        _teeth("ring_teeth", self.ring_teeth, z1 + 1,
               "the ring needs at least one tooth more than the planet (z2 - z1 >= 1)")
        m = check_range("module_m", self.module_m, 0, None, lo_open=True, error=GeometryError)
        check_range("face_width_m", self.face_width_m, 0, None, lo_open=True,
                    error=GeometryError)
        r1 = m * z1 / 2
        check_range("tooth_height_m", self.tooth_height_m, 0, r1, lo_open=True,
                    hi_open=True, error=GeometryError,
                    why="Eq. 1 needs a < r1 (planet pitch radius)")
        check_tooth_height(profile_params(self))

    @property
    def planet_pitch_radius_m(self) -> float:
        """r1 = m z1/2 (m)."""
        return profile_params(self).r1

    @property
    def ring_pitch_radius_m(self) -> float:
        """r2 = m z2/2 (m)."""
        return profile_params(self).r2

    @property
    def centre_distance_m(self) -> float:
        """a0 = r2 - r1 = m (z2 - z1)/2 (m)."""
        return profile_params(self).a0

    @property
    def tooth_difference(self) -> int:
        """z2 - z1."""
        return self.ring_teeth - self.planet_teeth

    @property
    def crank_pitch_rad(self) -> float:
        """Crank angle 2 pi/z2 after which the mesh repeats (turned by 2 pi/z2, with the
        planet tooth index advanced by one)."""
        return 2 * math.pi / self.ring_teeth


def _teeth(name, z, lo, why):
    try:
        integral = not isinstance(z, bool) and float(z) == int(z)
    except (TypeError, ValueError, OverflowError):
        integral = False
    if not integral:
        raise GeometryError(f"{name} = {z!r} must be an integer")
    return int(check_range(name, z, lo, None, error=GeometryError, why=why))
