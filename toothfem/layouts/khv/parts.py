"""The K-H-V cycloid drive's own parts: its ratio and section rules, the bearings and
envelope around its disc (the eccentric bearings in the discs' centre bore on the input
shaft), and its power flow (the disc's torque leaves through output pins in holes)."""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ...case import Case


from ...efficiency.bearing_set import cycloid_set, needle_set
from ...efficiency.drive_losses import (DriveLosses, OperatingPoints, PowerFlow, StageLoads,
                                        cycloid_losses, w_mechanism)
from ...efficiency.envelope import BALL_PITCH_PER_BORE, cycloid_envelope, input_shaft_m
from ...errors import CaseError, GeometryError
from ...fem.system.paths import PinsInHoles
from ...geometry import train
from ...geometry.disc import disc_polygon
from ...units import M_PER_MM
from ..common import need, needs_output_pins
from ..cycloid import cycloid_drive


def ratio(case: Case) -> float:
    """A K-H-V cycloid drive: the disc's lobes on the pins.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    float
        The signed ratio i = n_input / n_output.
    """
    cyc = need(case.cycloid, "cycloid", case)
    return train.khv_ratio(cyc.lobe_count, cyc.pin_count)


def khv_drive(si, layout):
    """The K-H-V drive: its discs on the input shaft's eccentrics, their torque out through
    the output pins in their holes (:class:`toothfem.fem.system.paths.PinsInHoles`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    layout : toothfem.layout.Layout

    Returns
    -------
    toothfem.fem.drives.CycloidDrive
    """
    return cycloid_drive(si, layout, PinsInHoles(si.output_mechanism))


def case_checks(case: Case) -> None:
    """K-H-V: the output pins, and the disc on its eccentric bearing in the centre bore
    with the output pins' holes beside it.

    Parameters
    ----------
    case : toothfem.case.Case
    """
    needs_output_pins(case)
    _check_khv_disc(case)


def _check_khv_disc(case: Case) -> None:
    """A K-H-V disc sits on its eccentric bearing in the centre bore, and the output
    pins' holes fit in the disc beside it."""
    cyc = need(case.cycloid, "cycloid", case)
    om = need(case.output_mechanism, "output_mechanism", case)
    if cyc.disc_holes.centre_bore_radius_mm <= 0:
        raise CaseError("cycloid.disc_holes.centre_bore_radius_mm = "
                        f"{cyc.disc_holes.centre_bore_radius_mm!r} must be > 0 for a K-H-V "
                        "drive: the disc sits on its eccentric bearing in the centre bore")
    holes = cyc.holes_si(om)
    gap = holes.output_hole_radius_m - om.contact_radius_mm * M_PER_MM \
        - cyc.eccentricity_mm * M_PER_MM
    if gap < 0:
        raise CaseError(f"output_mechanism.hole_radius_mm = {om.hole_radius_mm!r} is "
                        "outside the valid range: at least the pin's (or roller's) radius "
                        f"plus the eccentricity, {om.contact_radius_mm + cyc.eccentricity_mm:g}"
                        " mm (else the disc cannot orbit on its output pins)")
    try:
        disc_polygon(cyc.geometry(), holes, points_per_lobe=16)
    except GeometryError as exc:
        raise CaseError(f"{exc} (the output pins' holes: output_mechanism.pin_count, "
                        "pin_hole_circle_radius_mm, hole_radius_mm; the bore: "
                        "cycloid.disc_holes.centre_bore_radius_mm)") from None


def envelope(si, drive) -> dict:
    """K-H-V: the eccentric bearings (RV reducers' needle rollers) run in the centre bore,
    one per disc (:func:`cycloid_envelope`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    dict
        :class:`toothfem.efficiency.envelope.Envelope`'s fields the layout sizes [m].
    """
    bore = 2 * si.cycloid.holes.centre_bore_radius_m
    d = bore if bore > 0 else input_shaft_m(si) * BALL_PITCH_PER_BORE
    return cycloid_envelope(si, d, si.cycloid.disc_count)


def bearings(si, drive) -> tuple:
    """K-H-V: needle rollers in each disc's centre bore on the input shaft's eccentrics.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    tuple of toothfem.efficiency.bearing_set.Bearing
    """
    supports = drive.supports(si.supports)
    return cycloid_set(si, drive, needle_set(
        si, drive, supports, name="eccentric_bearing",
        label="eccentric bearings (needle rollers in the centre bore)",
        count=si.cycloid.disc_count, hole_m=2 * si.cycloid.holes.centre_bore_radius_m,
        hole_key="cycloid.disc_holes.centre_bore_radius_mm"))


def power_flow(si, drive, points, st: StageLoads) -> PowerFlow:
    """K-H-V: the disc's torque leaves through pins in holes; its central eccentric bearing
    carries the pin resultant and the pins' load (as the sine planet); the energy balance
    with the contact loss itself (Chen & Angeles' closed form agrees to first order).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    points : toothfem.efficiency.drive_losses.OperatingPoints
    st : toothfem.efficiency.drive_losses.StageLoads
        The cycloid stage's loads and losses (:func:`toothfem.efficiency.drive_losses.cycloid_losses`).

    Returns
    -------
    toothfem.efficiency.drive_losses.PowerFlow
    """
    ecc = out_mech = 0.0
    for _, tab, t_j, count in st.members:
        f_r1, o = w_mechanism(si, tab, tab.at(t_j)[0], t_j,
                              si.cycloid.geometry.eccentricity_m, st.disc_rel)
        ecc, out_mech = ecc + count * f_r1, out_mech + count * o
    # one disc's eccentric load reaches the input shaft's two bearings; discs evenly
    # phased balance there (their couple is left out)
    loads = {"eccentric_bearing": ecc, "input_bearings": ecc if drive.members == 1 else 0}
    return PowerFlow(loads=loads, losses={"pin_contacts": st.pins_W, "output_mechanism": out_mech},
                     mesh_efficiency={}, churning_stages=(), stage_names=("cycloid stage",))


def losses(si, drive, points: OperatingPoints) -> DriveLosses:
    """Losses of a K-H-V cycloid drive (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Needs [output_mechanism] (the output pins in the discs' holes).
    drive : toothfem.fem.drives.CycloidDrive
    points : OperatingPoints

    Returns
    -------
    DriveLosses
        pin_contacts, eccentric_bearing, output_mechanism, the bearings' and the
        load-independent losses; the cycloid mesh efficiency.
    """
    return cycloid_losses(si, drive, points, power_flow)
