"""The sine reducer's own parts: its ratio, the bearings and envelope around the planet
(the eccentric bearing in the planet's bore, the input shaft's ball bearings), and its
losses (Lu & Xu 2024, Eqs. 21-45)."""
from __future__ import annotations

import math

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ...case import Case

import numpy as np

from ...efficiency.bearing_set import main_pair, roller_bearing, sized_bearing
from ...efficiency.contact_friction import contact_mu, sliding_loss
from ...efficiency.drive_losses import (DriveLosses, OperatingPoints, mesh_table_of,
                                        w_mechanism)
from ...efficiency.envelope import BALL_PITCH_PER_BORE
from ...efficiency.no_load import no_load_losses
from ...errors import CaseError
from ...fem.drives import SineDrive
from ...report import plots
from ...geometry import sine, train
from ...limits import Exceeded
from ...units import M_PER_UM, MM_PER_M
from ..common import need, rounded


def ratio(case: Case) -> float:
    """The sine pair: one tooth difference, the planet's teeth on the ring's.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    float
        The signed ratio i = n_input / n_output.
    """
    st = need(case.sine, "sine", case)
    return train.khv_ratio(st.planet_teeth, st.ring_teeth)


#: Housing radius of a sine reducer per ring pitch radius (ASSUMPTION: a wall of a quarter
#: of the ring radius around the ring gear).
SINE_HOUSING_PER_RING_RADIUS = 1.25


def envelope(si, drive) -> dict:
    """Sine reducer (Lu & Xu 2024, Fig. 1): the input shaft carries the eccentric bearing
    (bore 2 r_p), a deep-groove ball bearing of pitch 1.5 bores; the output seal and the
    main bearing sit at the outer edge of the output pins' circle (2 (R_w + r_x)); the
    housing wraps the ring gear. All ASSUMPTIONS.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    dict
        :class:`toothfem.efficiency.envelope.Envelope`'s fields the layout sizes [m].
    """
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


def bearings(si, drive) -> tuple:
    """The sine reducer's bearings: the system model's rollers on the eccentric (inner
    raceway r_p, the output mechanism's ``eccentric_bearing_inner_radius``) in the
    planet's bore, which must clear the output pins' holes and the teeth's roots; the
    main pair; the input shaft's deep groove ball bearings on the shaft of
    ``Drive.supports`` (2 (r_p - a0), the eccentric's shaft).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    tuple of toothfem.efficiency.bearing_set.Bearing
    """
    om, pair = si.output_mechanism, drive.pair
    if om is None:
        raise CaseError("a sine reducer needs [output_mechanism] (its eccentric bearing's "
                        "raceway and the pins that carry the torque out) for its bearings")
    supports = drive.supports(si.supports)
    w = drive.speeds()
    r_p = om.eccentric_bearing_inner_radius_m
    d_w = supports.bearing_roller_diameter_m
    bore_out = 2 * (r_p + d_w)                       # the planet's bore
    hole = om.hole_radius_m or (om.pin_radius_m + pair.centre_distance_m)
    room = 2 * min(om.pin_hole_circle_radius_m - hole,
                   pair.planet_pitch_radius_m - pair.tooth_height_m)
    if bore_out > room * (1 + 1e-9):
        raise CaseError(
            f"output_mechanism.eccentric_bearing_inner_radius_mm = {r_p * MM_PER_M:.4g} with "
            f"rollers of supports.bearing_roller_diameter_mm = {d_w * MM_PER_M:.4g} needs a "
            f"{bore_out * MM_PER_M:.4g} mm bore in the planet, which does not clear the output "
            f"pins' holes (output_mechanism.pin_hole_circle_radius_mm = "
            f"{om.pin_hole_circle_radius_m * MM_PER_M:.4g}) or the teeth ({room * MM_PER_M:.4g} mm)")
    ecc = roller_bearing(
        si, supports, name="eccentric_bearing",
        label="eccentric bearing (rollers on the eccentric in the planet's bore)", count=1,
        bore_m=2 * r_p, outer_m=bore_out, pitch_m=2 * r_p + d_w,
        speed=abs(w["crank"] - w["member"]),
        space=f"output_mechanism.eccentric_bearing_inner_radius_mm = {r_p * MM_PER_M:.4g}")
    return (ecc, main_pair(si, drive),
            sized_bearing("input_bearings", "input bearings (deep groove balls on the input shaft)",
                          "ball", 2, supports.crankshaft_diameter_m,
                          "output_mechanism.eccentric_bearing_inner_radius_mm", 1.0,
                          ["input shaft diameter"]))


def losses(si, drive, points: OperatingPoints) -> DriveLosses:
    """Losses of the sine reducer (Lu & Xu 2024, Eqs. 21-45).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Needs [output_mechanism] (pins in holes, plain bearings).
    drive : toothfem.fem.drives.SineDrive
    points : OperatingPoints
        Speeds [rad/s], torques [N m] and the load source of the meshing table.

    Returns
    -------
    DriveLosses
        Components mesh, eccentric_bearing, plain_bearings, output_mechanism and the
        load-independent ones; the mesh efficiency in the crank frame.

    Raises
    ------
    CaseError
        Without an [output_mechanism] (:func:`w_mechanism`).
    """
    pair = drive.pair
    w = drive.speeds()
    crank = points.input_speed_rad_s
    w_planet = crank * w["member"]
    rel = np.abs(crank - w_planet)                          # crank relative to the planet
    t2 = points.output_torque_Nm
    notes: list[str] = []
    table = mesh_table_of(si, drive, points, t2, notes)
    force, ph = table.at(t2)
    eta0 = si.lubricant.dynamic_viscosity_Pa_s * points.viscosity_factor
    limits: list[Exceeded] = []
    mu, _ = contact_mu(si, drive.e_star_Pa, table, force, ph, crank, eta0, notes, limits,
                       memo=points.memo)
    mesh = sliding_loss(table, force, mu, crank)
    if np.any(table.hertz_invalid):
        notes.append(f"Hertz's assumptions fail at {int(table.hertz_invalid.sum())} of "
                     f"{table.hertz_invalid.size} loaded contacts (half-width not small against "
                     "the radii); "
                     + ("P_h there is the FE pressure" if np.any(table.pressure_from_fe) else
                        "P_h there is still Hertz's (analytic loads): use loads='fem'"))
    a0 = pair.centre_distance_m
    f_r1, out_mech = w_mechanism(si, table, force, t2, a0, rel)
    ecc = si.friction.bearing_coefficient * si.output_mechanism.eccentric_bearing_inner_radius_m \
        * f_r1 * rel                                                                 # Eq. 32
    plain = si.output_mechanism.plain_bearing_friction_torque_Nm * crank          # Eq. 34
    losses = {"mesh": mesh, "eccentric_bearing": ecc, "plain_bearings": plain,
              "output_mechanism": out_mech,
              **no_load_losses(si, drive, stages=[(a0, crank)], input_rad_s=crank,
                               output_rad_s=w_planet,
                               viscosity_factor=points.viscosity_factor)}
    # the mesh efficiency in the crank frame (virtual power T2 |w_planet - w_crank|), for
    # display: in a K-H-V stage the energy balance with the contact loss itself is exact
    return DriveLosses(output_power_W=t2 * np.abs(w_planet), losses_W=losses,
                       notes=tuple(notes), mesh_efficiency={"sine": 1 - mesh / (t2 * rel)},
                       limits=tuple(limits))


def sine_drive(si, layout):
    """The sine pair of a case with its output pins (:meth:`toothfem.fem.drives.SineDrive.
    from_case`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    layout : toothfem.layout.Layout
        The layout the drive belongs to.

    Returns
    -------
    toothfem.fem.drives.SineDrive
    """
    return SineDrive.from_case(si, layout)


def pair_drawing(drive, case_name: str):
    """The sine pair with its dimensions, at crank angle 0.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    case_name : str
        Named in the title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    return plots.sine_drawing(drive.pair, case_name=case_name)


def rows(case: Case) -> dict:
    """The sine pair's rows ``toothfem check`` prints: its radii, the tooth height's bound,
    the conjugate contact's smallest pressure angle and equivalent radius over a pitch, and
    the tooth pairs within 1, 5 and 10 um.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    dict
        Units in the key names.
    """
    st = case.sine
    if st is None:
        raise CaseError(f"[sine] section is required for drive = {case.drive!r}")
    pair = st.geometry()
    d = {
        "planet_pitch_radius_mm": rounded(pair.planet_pitch_radius_m * MM_PER_M),
        "ring_pitch_radius_mm": rounded(pair.ring_pitch_radius_m * MM_PER_M),
        "centre_distance_mm": rounded(pair.centre_distance_m * MM_PER_M),
        "tooth_height_bound_mm": rounded(sine.max_tooth_height_m(pair) * MM_PER_M),
    }
    pitch = 2 * math.pi / st.ring_teeth
    chi = np.linspace(0.0, pitch, 13)
    m = sine.meshing(pair, chi)
    conj = m.gap <= 1e-9                   # the conjugate contact of each position
    d["conjugate_pressure_angle_min_deg"] = rounded(math.degrees(float(np.min(
        m.pressure_angle[conj]))))
    d["conjugate_equivalent_radius_min_mm"] = rounded(
        float(np.min(m.equivalent_radius[conj])) * MM_PER_M)
    for gap_um in (1.0, 5.0, 10.0):
        n = sine.contact_count(pair, chi, gap_um * M_PER_UM)
        d[f"tooth_pairs_within_{gap_um:g}um_min"] = int(np.min(n))
        d[f"tooth_pairs_within_{gap_um:g}um_max"] = int(np.max(n))
    return d
