"""The datasheet of a case from the contact model, as Python calls: ``stiffness_analysis``
(hysteresis, rigidity, lost motion, backlash, compliances in series, loaded TE, the split
between the members) and ``write_stiffness`` (CSV, PNG, JSON), what ``toothfem stiffness``
and the run report call (fem/datasheet/ holds the mechanics; docs/stiffness.md)."""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .case import Case, as_case
from .errors import CaseError, check_range
from .fem.datasheet.sheet import datasheet, loop_torques, plural
from .fem.datasheet.transmission import loaded_te
from .fem.datasheet.twist import ARCSEC, TwistModel
from .fem.drives import MAX_POSITIONS, drive_for
from .efficiency import rated_output_torque
from .efficiency.no_load import output_friction_torque
from .fem.system.cycloid import PathFriction
from .fem.system.datasheet import SystemTwist, system_te
from .report import save
from .report import stiffness as report_stiffness

#: The one transmission error every command names (docs/stiffness.md, "One transmission
#: error").
TE_DEFINITION = ("the output's lag behind its kinematic position, input held at each crank "
                 "angle, under the output torque: the system model of the whole reducer")
#: Full-period sampling of the loaded TE by default: cycle solvers over the period and
#: positions per pitch of each (fem/datasheet/transmission.py; one factorisation each).
TE_SAMPLES, TE_PER_PITCH = 6, 12


@dataclass(frozen=True, kw_only=True)
class StiffnessResult:
    """The datasheet of a case (hysteresis loop and catalogue figures), its loaded TE over
    the full period, the split between the members (None for one member) and every
    bearing's load over the period (None without a system model)."""
    case_name: str
    sheet: object                   # toothfem.fem.datasheet.sheet.Datasheet
    te: object                      # toothfem.fem.datasheet.transmission.LoadedTE
    split: object                   # MemberSplit or None
    summary: dict
    bearings: object = None         # toothfem.fem.system.datasheet.BearingLoads or None


def path_friction(si, drive) -> PathFriction:
    """The case's friction in the quasi-static path: the pin contacts, output pins and
    grooves slide at creep speed with no film, so with their boundary coefficients
    (``friction.boundary_coefficient`` for the pin contacts, ``pin_groove_coefficient``,
    ``output_pin_coefficient``); the bearings with ``bearing_coefficient``; the output's
    seal and main bearings (:func:`toothfem.efficiency.no_load.output_friction_torque`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    toothfem.fem.system.cycloid.PathFriction
    """
    f = si.friction
    return PathFriction(pin_disc=f.boundary_coefficient, pin_groove=f.pin_groove_coefficient,
                        bearing=f.bearing_coefficient, output_pin=f.output_pin_coefficient,
                        output_torque_Nm=output_friction_torque(si, drive))


def stiffness_analysis(case: Case, *, torque_max_Nm: float | None = None, steps: int = 8,
                       positions: int = 36, te_torque_Nm: float | None = None,
                       te_samples: int = TE_SAMPLES, te_positions: int = TE_PER_PITCH,
                       friction: bool = True) -> StiffnessResult:
    """Torsional stiffness, hysteresis, lost motion, loaded TE and member split of a case
    (docs/stiffness.md).

    Parameters
    ----------
    case : toothfem.case.Case
    torque_max_Nm : float, optional
        Largest torque of the loop [N m]; default the rated torque (``[operating]
        rated_torque_Nm``, else the operating torque, marked assumed).
    steps : int
        Torque steps from 0 to the largest torque (the loop has 5 steps + 1 points).
    positions : int
        Meshing positions over one period of the loop's cycle solver.
    te_torque_Nm : float, optional
        Output torque of the loaded TE and the split; default the rated torque.
    te_samples, te_positions : int
        Cycle solvers over the full period, and positions per pitch of each.
    friction : bool
        Friction in the quasi-static path (:func:`path_friction`): the loop's width and
        the hysteresis loss; False: the elastic curve.

    Returns
    -------
    StiffnessResult

    Raises
    ------
    CaseError
        If ``positions`` is outside its range, ``torque_max_Nm`` is not positive, or the
        case declares neither a rated nor an operating torque and none is given.
    """
    case = as_case(case)
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    loop_torques(1.0, steps)                   # steps refused before any work
    drive = drive_for(case)
    si = case.to_si()
    rated, assumed = rated_output_torque(si)
    if torque_max_Nm is not None:
        check_range("torque_max_Nm", torque_max_Nm, 0, None, lo_open=True, error=CaseError)
    supports = drive.supports(si.supports)
    system = drive.system_model(supports, positions)
    if system is not None:          # the whole reducer around the contact
        twist = SystemTwist(system, friction=path_friction(si, drive) if friction else None)
        te, split, bearings = system_te(drive, supports, te_torque_Nm or rated,
                                        samples=te_samples, per_pitch=te_positions)
    else:                           # the load paths chained (the sine pair, for now)
        twist = TwistModel(drive, supports, drive.cycle_solver(
            positions, solver_options=drive.both_sides_options))
        te, split = loaded_te(drive, supports, te_torque_Nm or rated, samples=te_samples,
                              per_pitch=te_positions)
        bearings = None
    sheet = datasheet(twist, rated, rated_assumed=assumed, torque_max_Nm=torque_max_Nm,
                      steps=steps)
    summary = {"case": case.name, "drive": drive.kind, **sheet.summary(), **te.summary(),
               "te_definition": TE_DEFINITION if system is not None else
               "the chained load paths' twist of one member (mesh and supports in series)",
               **({} if split is None else split.summary()),
               **({} if bearings is None else bearings.summary())}
    if split is not None:
        summary["member_load_factor_case"] = drive.load_factor
    return StiffnessResult(case_name=case.name, sheet=sheet, te=te, split=split,
                           summary=summary, bearings=bearings)


HYSTERESIS_COLUMNS = ("torque_Nm", "twist_arcmin", "twist_min_arcmin", "twist_max_arcmin")


def write_stiffness(result: StiffnessResult, folder: Path) -> dict:
    """hysteresis.csv/png, te.csv/png, split.csv (several members), split.png (a split the
    layout does not make even) and summary.json into
    ``folder``.

    Parameters
    ----------
    result : StiffnessResult
        The data sheet, loaded TE and split.
    folder : pathlib.Path
        Where the files go (it must exist).

    Returns
    -------
    dict
        The data sheet's figures and the names of the files written.
    """
    import csv


    folder = Path(folder)
    sheet, te = result.sheet, result.te
    contacts = f"{plural(sheet.contact_name)}_in_contact"
    with open(folder / "hysteresis.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(HYSTERESIS_COLUMNS + (contacts,))
        for row in sheet.loop.rows():
            w.writerow([f"{v:.9g}" for v in row])
    arcsec = 1 / ARCSEC
    with open(folder / "te.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["crank_angle_deg", "output_angle_deg", "te_arcsec", "mesh_arcsec"])
        for row in zip(np.degrees(te.crank_angle_rad), np.degrees(te.output_angle_rad),
                       te.te_rad * arcsec, te.mesh_rad * arcsec):
            w.writerow([f"{v:.9g}" for v in row])
    files = ["hysteresis.csv", "hysteresis.png", "te.csv", "te.png", "summary.json"]
    if result.bearings is not None:
        b = result.bearings
        with open(folder / "bearings.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["crank_angle_deg"] + [f"{n.replace(' ', '_')}_N" for n in b.names])
            for g, phi in enumerate(np.degrees(b.crank_angle_rad)):
                w.writerow([f"{phi:.9g}"] + [f"{x:.9g}" for x in b.load_N[:, g]])
        files.append("bearings.csv")
    if result.split is not None:
        with open(folder / "split.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            share = result.split.share
            w.writerow(["crank_angle_deg"] + [f"share_{sheet.member_name}_{j}"
                                              for j in range(share.shape[0])])
            for g, phi in enumerate(np.degrees(result.split.crank_angle_rad)):
                w.writerow([f"{phi:.9g}"] + [f"{x:.9g}" for x in share[:, g]])
        files.append("split.csv")
        if not result.split.even_by_layout:
            save(report_stiffness.member_split(result.split, sheet.member_name,
                                               result.case_name), folder / "split.png", dpi=120)
            files.append("split.png")
    title = (f"{result.case_name}\nrated {sheet.rated_torque_Nm:.4g} N m"
             + (" (the operating output torque: no rating named)"
                if sheet.rated_torque_assumed else "")
             + f", rigidity {sheet.rigidity_Nm_per_arcmin:.4g} N m/arcmin")
    save(report_stiffness.hysteresis(sheet, title=title), folder / "hysteresis.png", dpi=120)
    which = ("the reducer's TE (system model, input held)"
             if result.bearings is not None else "one member's chained load paths")
    save(report_stiffness.transmission_error(te, heading=f"{result.case_name}: {which}"),
         folder / "te.png", dpi=120)
    summary = {**result.summary, "files": files}
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def datasheet_rows(summary: dict) -> list:
    """(quantity, value) rows of the datasheet table of a report.

    Parameters
    ----------
    summary : dict
        The summary :func:`write_stiffness` returns.

    Returns
    -------
    list of (str, str)
        Quantity with its unit, and the formatted value.
    """
    rows = [("rated torque [N m]", f"{summary['rated_torque_Nm']:.4g}"
             + (" (the operating output torque: no rating named)"
                if summary["rated_torque_assumed"] else "")),
            ("torsional rigidity 50-100 % [N m/arcmin]",
             f"{summary['torsional_rigidity_Nm_per_arcmin']:.4g}"),
            ("lost motion ±3 % [arcmin]", f"{summary['lost_motion_arcmin']:.4g}"),
            ("backlash [arcmin]", f"{summary['backlash_arcmin']:.4g}"),
            ("hysteresis loss [arcmin]", f"{summary['hysteresis_loss_arcmin']:.4g}"),
            (f"transmission error of the reducer at {summary['te_torque_Nm']:.4g} N m, mean "
             "[arcsec]", f"{summary['te_mean_arcsec']:.4g}"),
            (f"  its peak to peak over the full period ({summary['te_full_period_pitches']} "
             f"pitch{'' if summary['te_full_period_pitches'] == 1 else 'es'}, "
             f"{summary['te_positions_per_pitch']} positions each) [arcsec]",
             f"{summary['te_peak_to_peak_arcsec']:.4g}")]
    if "member_share_max" in summary:
        rows.append(("largest member share of the torque (FE; case's factor)",
                     f"{summary['member_share_max']:.4f} "
                     f"(load factor {summary['member_load_factor_fe']:.4f}; case "
                     f"{summary['member_load_factor_case']:.3g})"))
    for name, share in summary["compliance_shares"].items():
        rows.append((f"compliance share: {name}", f"{100 * share:.1f} %"))
    return rows
