"""The output's main bearing pair of a reducer: each row's axial preload [N]
(:func:`main_preload_N`) and the pair against a tilting moment, ball by ball
(:func:`main_tilt`: the momentary and allowable moments [N m] and the moment rigidity
[N m/arcmin] of :mod:`toothfem.fem.datasheet.tilt`; the model: docs/tilt.md). The pair's
size and ratings: :func:`toothfem.efficiency.bearing_set.main_pair`.
"""
from __future__ import annotations

import math

from ..errors import CaseError
from .bearing_set import main_pair
from ..units import MM_PER_M

#: ASSUMPTION: the distance between the main pair's two rows' ball centres per ball
#: diameter (two rows side by side with a shoulder between them; the balls' size:
#: :data:`toothfem.efficiency.bearing_set.MAIN_BALL_PER_PITCH`).
MAIN_ROW_SPACING_PER_BALL = 2.5
#: ASSUMPTION: each row's axial preload as a share of its static rating C0 (a light
#: preload of makers' matched angular contact pairs is of the order of 1-2 % of C0).
MAIN_PRELOAD_PER_C0 = 0.02


def main_preload_N(si, drive) -> float:
    """Axial preload of each main bearing row [N]: ``bearings.main_preload_N``, else
    :data:`MAIN_PRELOAD_PER_C0` of the row's static rating (an ASSUMPTION). The tilt model
    stiffens the pair with it and the friction model loads each row's Palmgren load term
    with it, so the two read one preload.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    float
        [N].
    """
    declared = None if si.bearings is None else si.bearings.main_preload_N
    if declared is not None:
        return float(declared)
    return MAIN_PRELOAD_PER_C0 * main_pair(si, drive).static_rating_N


#: Makers list a momentary maximum allowable moment twice the allowable moment (Nabtesco
#: RV-E catalogue: RV-40E 3332 and 1666 N m); the momentary one is taken as the moment at
#: which the most loaded ball reaches ISO 76's static limit.
MOMENTARY_PER_ALLOWABLE = 2.0


def main_tilt(si, drive) -> dict:
    """The main bearing pair against a tilting moment, ball by ball
    (:mod:`toothfem.fem.datasheet.tilt`): the moment at ISO 76's static limit (4200 MPa at
    the most loaded ball; the catalogue's momentary maximum allowable moment), the
    allowable moment (half of it, the catalogue's ratio :data:`MOMENTARY_PER_ALLOWABLE`),
    and the moment rigidity (the secant M/theta at the allowable moment, the catalogue's
    figure; the pair alone, its housing and carrier rigid).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    dict
        ``momentary_moment_Nm``, ``allowable_moment_Nm``, ``moment_rigidity_Nm_per_arcmin``,
        ``row_span_mm``, ``preload_N``, the pair's ``assumed`` values.
    """
    from ..fem.datasheet import tilt
    from ..fem.datasheet.ball_pair import BallPair
    b = main_pair(si, drive)
    # bearings.main_span_mm is between the rows' load (pressure cone) centres, the pair's
    # span between its ball planes: back to back, they differ by d_m tan(alpha)
    cone = b.pitch_diameter_m * math.tan(math.radians(b.contact_angle_deg))
    declared = None if si.bearings is None else si.bearings.main_span_m
    span = (MAIN_ROW_SPACING_PER_BALL * b.element_diameter_m if declared is None
            else declared - cone)
    if span <= 0:
        if declared is None:      # the assumed spacing of positive balls: never below 0
            raise CaseError(f"the main bearings' assumed row span {span * MM_PER_M:.4g} mm is "
                            "not positive (ball diameter times MAIN_ROW_SPACING_PER_BALL)")
        raise CaseError(f"bearings.main_span_mm = {declared * MM_PER_M:.4g} is below the pair's "
                        f"pressure-cone spread d_m tan(alpha) = {cone * MM_PER_M:.4g} mm of a "
                        "back-to-back pair: the rows would overlap")
    pair = BallPair(balls_per_row=b.elements, ball_diameter_m=b.element_diameter_m,
                    pitch_diameter_m=b.pitch_diameter_m,
                    contact_angle_rad=math.radians(b.contact_angle_deg), row_span_m=span,
                    preload_N=main_preload_N(si, drive),
                    youngs_modulus_Pa=si.material.youngs_modulus_Pa,
                    poisson_ratio=si.material.poisson_ratio)
    momentary = tilt.moment_at_pressure(pair)
    allowable = momentary / MOMENTARY_PER_ALLOWABLE
    return {"momentary_moment_Nm": float(momentary), "allowable_moment_Nm": float(allowable),
            "moment_rigidity_Nm_per_arcmin": float(
                tilt.moment_rigidity_Nm_per_arcmin(pair, allowable)),
            "row_span_mm": span * MM_PER_M, "preload_N": pair.preload_N,
            "balls_per_row": b.elements, "ball_diameter_mm": b.element_diameter_m * MM_PER_M,
            "pitch_diameter_mm": b.pitch_diameter_m * MM_PER_M,
            "assumed": list(b.assumed) + (["preload"] if si.bearings is None or
                                          si.bearings.main_preload_N is None else [])
                       + ["row span"]}
