"""The reducer around its meshing stage, where the case leaves it out.

Seals, bearings and the housing need sizes that the tooth geometry does not fix: the shaft
diameter under each seal, the type, pitch diameter and number of the bearings on the
eccentrics, the main bearing's pitch diameter, the housing's radius and length. A case
declares them in ``[seals]``, ``[bearings]`` and ``[thermal]``; what it leaves out is taken
from the drive's own geometry by the rule of :data:`ENVELOPES` (keyed by ``drive.kind``,
every rule an ASSUMPTION stated beside it and in docs/case_schema.md).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import CaseError

#: Pitch diameter of a light-series ball bearing per bore: 1.5 (a 6004 has d = 20 mm,
#: D = 42 mm, d_m = 31 mm = 1.55 d; makers' catalogues). ASSUMPTION for the sine eccentric.
BALL_PITCH_PER_BORE = 1.5
#: Input shaft diameter of a cycloid drive without a centre bore, per pin-circle radius.
#: ASSUMPTION: 0.2 R_z (a 16 mm shaft on the RV-40E-like disc of R_z = 64 mm).
INPUT_SHAFT_PER_PIN_CIRCLE = 0.2
#: Housing radius of a sine reducer per ring pitch radius (ASSUMPTION: a wall of a quarter
#: of the ring radius around the ring gear).
SINE_HOUSING_PER_RING_RADIUS = 1.25


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


def _cycloid_envelope(si, drive) -> dict:
    """Cycloid and RV drives: the input shaft runs through the discs' centre bore, the output
    seal and the main bearing sit at the pin circle, the housing is the pin housing
    (radius ``housing_outer_radius``, as long as its diameter), the eccentric bearings are
    needle rollers (RV reducers' crank bearings) running in the crank holes (2K-V), or in
    the centre bore (K-H-V). All ASSUMPTIONS."""
    st = si.cycloid
    g, h = st.geometry, st.holes
    bore = 2 * h.centre_bore_radius_m
    shaft = bore if bore > 0 else INPUT_SHAFT_PER_PIN_CIRCLE * g.pin_circle_radius_m
    if drive.two_stage:
        if h.crank_hole_count < 1:
            raise CaseError("cycloid.disc_holes.crank_hole_count = 0: a 2K-V drive needs its "
                            "crank holes for the crank bearings")
        ecc_d, ecc_n = 2 * h.crank_hole_radius_m, h.crank_hole_count * st.disc_count
    else:
        ecc_d, ecc_n = (bore if bore > 0 else shaft * BALL_PITCH_PER_BORE), st.disc_count
    r_h = st.housing_outer_radius_m
    return dict(input_seal_diameter_m=shaft, output_seal_diameter_m=2 * g.pin_circle_radius_m,
                eccentric_type="needle", eccentric_pitch_diameter_m=ecc_d,
                eccentric_count=ecc_n, main_pitch_diameter_m=2 * g.pin_circle_radius_m,
                main_count=2, housing_radius_m=r_h, housing_length_m=2 * r_h)


def _sine_envelope(si, drive) -> dict:
    """Sine reducer (Lu & Xu 2024, Fig. 1): the input shaft carries the eccentric bearing
    (bore 2 r_p), a deep-groove ball bearing of pitch 1.5 bores; the output seal and the
    main bearing sit at the outer edge of the output pins' circle (2 (R_w + r_x)); the
    housing wraps the ring gear. All ASSUMPTIONS."""
    om = si.output_mechanism
    if om is None:
        raise CaseError("a sine reducer needs [output_mechanism] for its bearings and seals")
    bore = 2 * om.eccentric_bearing_inner_radius_m
    out = 2 * (om.pin_hole_circle_radius_m + om.pin_radius_m)
    pair = si.sine.pair
    r_h = SINE_HOUSING_PER_RING_RADIUS * pair.module_m * pair.ring_teeth / 2
    return dict(input_seal_diameter_m=bore, output_seal_diameter_m=out,
                eccentric_type="ball", eccentric_pitch_diameter_m=BALL_PITCH_PER_BORE * bore,
                eccentric_count=1, main_pitch_diameter_m=out, main_count=2,
                housing_radius_m=r_h, housing_length_m=2 * r_h)


#: The envelope rule of each drive kind (toothfem.fem.drives.Drive.kind).
ENVELOPES = {"cycloid": _cycloid_envelope, "sine": _sine_envelope}


def envelope(si, drive) -> Envelope:
    """The parts around the meshing stage: the case's ``[seals]`` and ``[bearings]`` sizes,
    and the drive's own rule (:data:`ENVELOPES`) for what the case leaves out.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    Envelope
    """
    sizes = ENVELOPES[drive.kind](si, drive)
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
