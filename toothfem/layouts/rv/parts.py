"""The RV (2K-V) reducer's own parts: its ratio and section rules, the bearings and
envelope around its discs (needle rollers in the crank holes, the cranks' tapered roller
supports in the carrier), and its power flow (the spur first stage, the cranks carrying
the discs: Chen & Angeles' closed form)."""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ...case import Case

import math

import numpy as np

from ...efficiency import spur as sp
from ...efficiency.bearing_set import cycloid_set, needle_set, sized_bearing
from ...efficiency.drive_losses import (DriveLosses, OperatingPoints, PowerFlow, StageLoads,
                                        crank_bearing_load, crank_support_load,
                                        cycloid_losses)
from ...efficiency.envelope import cycloid_envelope
from ...errors import CaseError
from ...fem.system.paths import Cranks
from ...geometry import train
from ...units import MM_PER_M
from ..common import need, rounded
from ..cycloid import cycloid_drive, cycloid_rows


def ratio(case: Case) -> float:
    """A 2K-V drive: from [rv], or from [first_stage] and [cycloid].

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    float
        The signed ratio i = n_input / n_output.
    """
    if case.rv is not None:
        z = case.rv
        return train.rv_ratio(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count)
    fs = need(case.first_stage, "first_stage", case)
    cyc = need(case.cycloid, "cycloid", case)
    return train.rv_ratio(fs.sun_teeth, fs.planet_teeth, cyc.lobe_count, cyc.pin_count)


def rv_drive(si, layout):
    """The 2K-V drive: its discs on crankshafts turned by the spur first stage's planets
    (:class:`toothfem.fem.system.paths.Cranks`, the teeth from [rv], else from
    [first_stage]).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    layout : toothfem.layout.Layout

    Returns
    -------
    toothfem.fem.drives.CycloidDrive

    Raises
    ------
    CaseError
        Without the first stage's teeth, the [cycloid] or the [material] section.
    """
    if si.rv is not None:
        teeth = (si.rv.sun_teeth, si.rv.planet_teeth)
    elif si.first_stage is not None:
        teeth = (si.first_stage.sun_teeth, si.first_stage.planet_teeth)
    else:
        raise CaseError(f"drive = {si.drive!r}: [rv] or [first_stage] is required (the "
                        "sun and planet teeth that turn the cranks)")
    return cycloid_drive(si, layout, Cranks(teeth, si.first_stage))


def case_checks(case: Case) -> None:
    """2K-V: a cycloid stage behind its spur first stage, on cranks in crank holes.

    Parameters
    ----------
    case : toothfem.case.Case
    """
    if case.cycloid is None:
        return                          # the [rv] train alone (the RV paper's method)
    if case.first_stage is None:
        raise CaseError("[first_stage] section is required with a [cycloid] section for "
                        f"drive = {case.drive!r} (the sun-planet mesh)")
    h = case.cycloid.disc_holes
    if h.crank_hole_count < 1:     # (their radii: DiscHoles checks them with a count)
        raise CaseError(f"cycloid.disc_holes.crank_hole_count = {h.crank_hole_count} "
                        "is outside the valid range [1, 12]: a two-stage (RV-type) "
                        "drive carries its discs on crankshafts in crank holes "
                        "(crank_hole_count, crank_hole_radius_mm and "
                        "crank_hole_circle_radius_mm > 0)")


def envelope(si, drive) -> dict:
    """2K-V: the crank bearings run in the crank holes, one per hole of every disc
    (:func:`cycloid_envelope`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    dict
        :class:`toothfem.efficiency.envelope.Envelope`'s fields the layout sizes [m].
    """
    h = si.cycloid.holes
    if h.crank_hole_count < 1:
        raise CaseError("cycloid.disc_holes.crank_hole_count = 0: a 2K-V drive needs its "
                        "crank holes for the crank bearings")
    return cycloid_envelope(si, 2 * h.crank_hole_radius_m,
                            h.crank_hole_count * si.cycloid.disc_count)


def bearings(si, drive) -> tuple:
    """2K-V: needle rollers in every disc's crank holes, the cranks' tapered roller
    supports in the carrier.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    tuple of toothfem.efficiency.bearing_set.Bearing
    """
    supports = drive.supports(si.supports)
    w = drive.speeds()
    h = si.cycloid.holes
    k, r_c = h.crank_hole_count, h.crank_hole_circle_radius_m
    needles = needle_set(si, drive, supports, name="crank_bearings",
                         label="crank bearings (needle rollers in the discs' crank holes)",
                         count=k * si.cycloid.disc_count, hole_m=2 * h.crank_hole_radius_m,
                         hole_key="cycloid.disc_holes.crank_hole_radius_mm")
    # neighbouring cranks' bearings must not overlap, nor reach past the pins
    room = min(2 * r_c * math.sin(math.pi / k) if k > 1 else math.inf,
               2 * (si.cycloid.geometry.pin_circle_radius_m
                    - si.cycloid.geometry.pin_radius_m - r_c))
    support = sized_bearing(
        "crank_support_bearings", "crank support bearings (tapered rollers in the "
        "carrier)", "tapered", 2 * k, supports.crankshaft_diameter_m,
        "supports.crankshaft_diameter_mm", abs(w["crank"] - w["output"]),
        [f"supports.{n}" for n in supports.assumed if n.startswith("crankshaft")],
        room=(room, f"the carrier ({room * MM_PER_M:.4g} mm between the cranks at "
                    f"cycloid.disc_holes.crank_hole_circle_radius_mm = {r_c * MM_PER_M:.4g} "
                    "and the pins)"))
    return cycloid_set(si, drive, needles, support)


def _first_stage_efficiency(si, t_sun, rel_sun, eta0):
    """Sun-planet mesh efficiency in the carrier frame: declared, or Ohlendorf/Schlenk."""
    stage = si.first_stage
    if stage is not None and stage.mesh_efficiency is not None:
        return np.full_like(t_sun, stage.mesh_efficiency)
    if stage is None:
        raise CaseError("a [first_stage] section is required for the sun-planet mesh")
    return sp.mesh_efficiency(stage, t_sun, rel_sun, eta0, si.lubricant.roughness_Ra_m)


def power_flow(si, drive, points, st: StageLoads) -> PowerFlow:
    """2K-V: the closed form of the general power flow (Chen & Angeles), the spur stage
    first, the cranks carrying the discs.

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
    w, w_in, t2 = drive.speeds(), points.input_speed_rad_s, points.output_torque_Nm
    loads = {"crank_bearings": sum(count * crank_bearing_load(si, f_b, t_j)
                                   for (_, _, t_j, count), f_b in zip(st.members, st.f_bearing)),
             "crank_support_bearings": crank_support_load(
                 si, sum(count * t_j for _, _, t_j, count in st.members))}
    ratio = abs(1 / w["output"])
    eta1 = _first_stage_efficiency(si, t2 / ratio, w_in * (1 - w["output"]), st.eta0)
    zs, zp = drive.path.teeth
    cyc = si.cycloid
    r, z4, z5 = zp / zs, cyc.lobe_count, cyc.geometry.pin_count
    if np.any(z5 - z4 * st.eta2 <= 0):
        raise CaseError(f"the disc-pin mesh efficiency {float(np.min(st.eta2)):.4g} in the "
                        f"crank frame is at or below z4/z5 = {z4 / z5:.4g}: the train "
                        "self-locks (friction too high for these operating points)")
    eta_train = (1 + r * eta1 * z5 / (z5 - z4 * st.eta2)) / ratio
    eta_lossless_1 = (1 + r * eta1 * z5 / (z5 - z4)) / ratio   # only the spur losses
    p_in = st.p_out / eta_train
    first = st.p_out / eta_lossless_1 - st.p_out
    losses = {"first_stage": first, "pin_contacts": p_in - st.p_out - first}
    fs = si.first_stage           # the spur stage churns too (a0, sun vs carrier)
    churn = () if fs is None else ((fs.module_m * (fs.sun_teeth + fs.planet_teeth) / 2,
                                    w_in * (1 - w["output"])),)
    return PowerFlow(loads=loads, losses=losses, mesh_efficiency={"first_stage": eta1},
                     churning_stages=churn,
                     stage_names=("spur", "cycloid stages") if churn else ("cycloid stage",))


def losses(si, drive, points: OperatingPoints) -> DriveLosses:
    """Losses of an RV-type (2K-V) drive (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Needs [first_stage] and the discs' crank holes.
    drive : toothfem.fem.drives.CycloidDrive
    points : OperatingPoints

    Returns
    -------
    DriveLosses
        first_stage, pin_contacts, crank_bearings, crank_support_bearings, the main
        bearings' and the load-independent losses; the cycloid and first-stage mesh
        efficiencies.

    Raises
    ------
    CaseError
        For a missing section, or a train that self-locks at these points.
    """
    return cycloid_losses(si, drive, points, power_flow)


def _rv_train_rows(case: Case) -> dict:
    rv = case.rv
    if rv is None:
        raise CaseError(f"[rv] section is required for drive = {case.drive!r}")
    w = train.rv_speeds(rv.sun_teeth, rv.planet_teeth, rv.disc_teeth, rv.pin_count)
    d = {f"speed_{k}_per_input": rounded(v) for k, v in w.items()}
    d["crank_to_output_ratio"] = rounded(w["planet"] / w["carrier"])
    return d


def rows(case: Case) -> dict:
    """An RV (2K-V) case: its train from [rv], its disc from [cycloid], each if declared.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    dict
        Units in the key names.
    """
    return {**(cycloid_rows(case) if case.cycloid is not None else {}),
            **(_rv_train_rows(case) if case.rv is not None else {})}
