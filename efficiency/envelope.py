"""The reducer around its meshing stage, where the case leaves it out.

Seals, bearings and the housing need sizes that the tooth geometry does not fix: the shaft
diameter under each seal, the type, pitch diameter and number of the bearings on the
eccentrics, the main bearing's pitch diameter, the housing's radius and length. A case
declares them in ``[seals]``, ``[bearings]`` and ``[thermal]``; what it leaves out is taken
from the drive's own geometry by its layout's rule (its ``Layout.envelope``,
every rule an ASSUMPTION stated beside it and in docs/case_schema.md).
"""
from __future__ import annotations

from dataclasses import dataclass


#: Pitch diameter of a light-series ball bearing per bore: 1.5 (a 6004 has d = 20 mm,
#: D = 42 mm, d_m = 31 mm = 1.55 d; makers' catalogues). ASSUMPTION for the sine eccentric.
BALL_PITCH_PER_BORE = 1.5
#: Input shaft diameter of a cycloid drive without a centre bore, per pin-circle radius.
#: ASSUMPTION: 0.2 R_z (a 16 mm shaft on the RV-40E-like disc of R_z = 64 mm).
INPUT_SHAFT_PER_PIN_CIRCLE = 0.2


@dataclass(frozen=True, kw_only=True)
class Envelope:
    """Sizes of the parts around the meshing stage [m] (SI)."""
    input_seal_diameter_m: float       # 0: no seal
    output_seal_diameter_m: float
    eccentric_type: str                # toothfem.case.BEARING_TYPES
    eccentric_pitch_diameter_m: float
    eccentric_count: int               # eccentric bearings in the reducer
    main_pitch_diameter_m: float
    main_count: int                    # rows of the main bearing
    housing_radius_m: float
    housing_length_m: float


def cycloid_envelope(si, eccentric_diameter_m, eccentric_count) -> dict:
    """Cycloid and RV drives: the output seal and the main bearing sit at the pin circle,
    the housing is the pin housing (radius ``housing_outer_radius``, as long as its
    diameter), the eccentric bearings are needle rollers. All ASSUMPTIONS.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    eccentric_diameter_m : float
        The eccentric bearings' pitch diameter [m].
    eccentric_count : int
        Eccentric bearings in the reducer.

    Returns
    -------
    dict
        :class:`Envelope`'s fields [m].
    """
    g = si.cycloid.geometry
    r_h = si.cycloid.housing_outer_radius_m
    return dict(input_seal_diameter_m=input_shaft_m(si),
                output_seal_diameter_m=2 * g.pin_circle_radius_m,
                eccentric_type="needle", eccentric_pitch_diameter_m=eccentric_diameter_m,
                eccentric_count=eccentric_count, main_pitch_diameter_m=2 * g.pin_circle_radius_m,
                main_count=2, housing_radius_m=r_h, housing_length_m=2 * r_h)


def input_shaft_m(si) -> float:
    """The input shaft runs through the discs' centre bore (or is sized on the pin circle).

    Parameters
    ----------
    si : toothfem.si.CaseSI

    Returns
    -------
    float
        The input shaft's diameter [m].
    """
    bore = 2 * si.cycloid.holes.centre_bore_radius_m
    return bore if bore > 0 else INPUT_SHAFT_PER_PIN_CIRCLE * si.cycloid.geometry.pin_circle_radius_m


def envelope(si, drive) -> Envelope:
    """The parts around the meshing stage: the case's ``[seals]`` and ``[bearings]`` sizes,
    and the layout's own rule (its ``envelope`` part) for what the case leaves out.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    Envelope
    """
    sizes = drive.layout.envelope(si, drive)
    seals, bearings = si.seals, si.bearings
    declared = {
        "input_seal_diameter_m": None if seals is None else seals.input_diameter_m,
        "output_seal_diameter_m": None if seals is None else seals.output_diameter_m,
        "eccentric_type": None if bearings is None else bearings.eccentric_type,
        "eccentric_pitch_diameter_m": (None if bearings is None
                                       else bearings.eccentric_pitch_diameter_m),
        "main_pitch_diameter_m": None if bearings is None else bearings.main_pitch_diameter_m,
    }
    sizes.update({k: v for k, v in declared.items() if v is not None})
    return Envelope(**sizes)
