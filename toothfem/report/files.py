"""The files of the pipeline: a contact result, a case's geometry, its efficiency charts
and the whole run.

:func:`write_contact` (load_sharing.csv, pictures, the VTU field, summary.json),
:func:`write_geometry` (profiles as CSV, DXF and SVG, the parts' drawing as DXF and SVG,
STEP with the extra ``[cad]``, drawing.png, check.json), the efficiency curves and maps of
a run (:func:`efficiency_charts`) and :func:`write_run` (every file of ``toothfem run``
from its records); the analyses that produce the records are :mod:`toothfem.pipeline`,
which calls these writers.
"""
from __future__ import annotations

import csv
import dataclasses
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .. import cad
from ..cad_parts import part_drawing
from ..case import Case
from ..derived import derived
from ..errors import CaseError, check_range
from ..fem import export
from ..fem.drives import drive_for
from ..units import MM_PER_M, PA_PER_MPA, UM_PER_M
from . import (contact as report_contact, durability as report_durability, field as report_field,
               html as report_html, plots, save, summary as report_summary)
from .contact import ContactLabels
from .face_width import write_face
from .plots import Marked

if TYPE_CHECKING:   # annotations only: the pipeline imports this module
    from ..maps import EfficiencyMaps
    from ..pipeline import ContactResult, RunAnalysis

#: Largest b_ref-scaled zoom of the contact close-up: 6 half-widths around the worst contact
#: show the Hertz zone and its subsurface maximum (at 0.78 b) with margin.
CLOSE_UP_HALF_WIDTHS = 6.0
#: Smallest half-width used for the close-up's zoom [m] (a contact with b = 0 in the record).
CLOSE_UP_MIN_HALF_WIDTH_M = 1e-6
#: Half-width [m] of the close-up of a structural field: its contact loads are strips of
#: b_ref = 0.1 mm on a mesh refined over 20 b_ref around each contact
#: (fem/cycloid_fe/cycle.py), so the view shows that refined zone, not a Hertz zone.
STRUCTURAL_CLOSE_UP_M = 2e-3


CONTACT_COLUMNS = ("position_deg", "contact_id", "force_N", "moment_arm_mm", "half_width_mm",
                   "ph_MPa", "gap_mm")


def contact_labels(result: ContactResult):
    """The :class:`toothfem.report.contact.ContactLabels` of a contact result.

    Parameters
    ----------
    result : ContactResult
        The contact analysis.

    Returns
    -------
    toothfem.report.contact.ContactLabels
        Names of the case, contacts and member, the torques [N m], the mode, and the
        reducer-wide largest force [N] and P_h [MPa] of the system model where the summary
        has them (the pictures show one member held, and say so beside these).
    """

    s = result.summary
    return ContactLabels(case_name=result.case_name, contact=result.contact_name,
                         contacts=result.contacts_name, member=result.member_name,
                         members=result.members, output_torque_Nm=s["output_torque_Nm"],
                         member_torque_Nm=s[f"{result.member_name}_torque_Nm"],
                         mode=result.mode,
                         reducer_max_force_N=s.get("max_force_reducer_N"),
                         reducer_max_ph_MPa=s.get("max_ph_reducer_MPa"))


def contact_figures(result: ContactResult) -> dict:
    """The contact's pictures over the period: the load per contact, the load around the
    ring and the transmission error (the stress field's need the VTU: :func:`write_contact`).

    Parameters
    ----------
    result : ContactResult

    Returns
    -------
    dict
        File name -> matplotlib Figure.
    """
    ls, labels = result.load_sharing, contact_labels(result)
    return {f"load_per_{result.contact_name}.png": report_contact.load_per_contact(ls, labels),
            "load_around_ring.png": report_contact.load_around_ring(ls, labels),
            "transmission_error.png": report_contact.transmission_error(ls, labels)}


def write_contact(result: ContactResult, folder: Path) -> dict:
    """Write load_sharing.csv, the pictures, the VTU field and summary.json into ``folder``.

    Pictures: ``load_per_<contact>.png`` (force and P_h per contact over the period),
    ``load_around_ring.png``, ``transmission_error.png`` and, with a field,
    ``von_mises.png`` (whole member) and ``von_mises_contact.png`` (close-up).

    Parameters
    ----------
    result : ContactResult
        The contact analysis.
    folder : pathlib.Path
        An existing folder.

    Returns
    -------
    dict
        The summary with its file list.
    """
    import csv


    folder = Path(folder)
    ls = result.load_sharing
    with open(folder / "load_sharing.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CONTACT_COLUMNS)
        for row in ls.rows():
            w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
    pictures = contact_figures(result)
    for name, fig in pictures.items():
        save(fig, folder / name)
    summary = {**result.summary, "files": ["load_sharing.csv", "summary.json", *pictures]}
    if result.sliced is not None:       # the face width in slices (issue 43)
        summary["files"] += write_face(result.sliced, folder, f"{result.case_name}: "
                                       f"{result.member_name} torque "
                                       f"{result.summary[result.member_name + '_torque_Nm']:.2f} N m")
    if result.body is not None:
        vtu = export.write_vtu(folder / f"{result.member_name}_worst_position.vtu",
                               result.body, result.displacement)
        summary["files"] += [vtu.name, *field_pictures(result, vtu, folder)]
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def member_frame(result: ContactResult, points) -> np.ndarray | None:
    """Housing-frame points of the worst position in the member's frame, from the one
    contact whose member-frame point the result holds (``member_point``, the largest force)
    and the fixed member's outlines: pins or ring teeth evenly around the housing's centre,
    the mean of their (evenly sampled) outlines is that centre in the member's frame. The
    frames differ by a rotation and a shift, so these two points give both.

    Parameters
    ----------
    result : ContactResult
        With its outlines (a result with a field).
    points : array_like, shape (..., 2)
        Housing frame [m].

    Returns
    -------
    numpy.ndarray or None
        Member frame [m], the input's shape; None without outlines, or where the two
        points disagree (the largest-force contact not at its distance from the centre).
    """
    if not result.outlines:
        return None
    ls, worst = result.load_sharing, result.worst
    k = int(np.argmax(ls.force[worst]))
    centre = np.concatenate([np.asarray(o, float) for o in result.outlines], axis=1)
    centre = centre.mean(axis=1)
    housing = np.asarray(ls.point[worst, k], float)
    member = np.asarray(result.member_point, float) - centre
    if abs(np.hypot(*member) - np.hypot(*housing)) > 1e-6 * max(np.hypot(*housing), 1e-3):
        return None
    turn = math.atan2(member[1], member[0]) - math.atan2(housing[1], housing[0])
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return centre + np.asarray(points, float) @ rot.T


def field_pictures(result: ContactResult, vtu: Path, folder: Path) -> list:
    """von_mises.png (the whole member) and von_mises_contact.png (close-up of the
    contact with the largest P_h at the worst position) of the member's field ``vtu``,
    labelled structural or contact-resolved, the model (one member held) and the case
    named.

    Parameters
    ----------
    result : ContactResult
        The contact analysis (with a field).
    vtu : pathlib.Path
        The member's VTU field.
    folder : pathlib.Path
        Where the pictures go.

    Returns
    -------
    list of str
        The names of the pictures.
    """

    labels = contact_labels(result)
    ls, worst = result.load_sharing, result.worst
    kf = int(np.argmax(ls.force[worst]))                 # the largest force
    k = int(np.argmax(ls.ph[worst]))                     # the largest P_h: the close-up's
    at = member_frame(result, ls.point[worst, k]) if k != kf else None
    if at is None:                                       # one contact, or no frame known
        k, at = kf, np.asarray(result.member_point, float)
    number, force_number = int(ls.contact_id[worst, k]), int(ls.contact_id[worst, kf])
    ph = float(ls.ph[worst, k] / PA_PER_MPA)
    b = max(float(ls.half_width[worst, k]), CLOSE_UP_MIN_HALF_WIDTH_M)
    case_line = f"{labels.case_name}: {labels.torque_text} ({labels.mode} mode)"
    where = (f"{labels.model_text}, at the worst position "
             f"({np.degrees(result.positions_rad[worst]):.2f} deg crank, the largest force); "
             f"{result.member_name} frame")
    compare = f"\n{labels.reducer(force=False)}" if labels.reducer(force=False) else ""
    if k == kf:
        marked = (f"x: {labels.contact} {number}, the largest force "
                  f"({float(ls.force[worst, kf]):.4g} N) and P_h ({ph:.4g} MPa) here")
        marks = [(at, "x")]
    else:
        marked = (f"x: {labels.contact} {number}, the largest P_h here ({ph:.4g} MPa); "
                  f"+: {labels.contact} {force_number}, the largest force "
                  f"({float(ls.force[worst, kf]):.4g} N)")
        marks = [(at, "x"), (result.member_point, "+")]
    if result.detail is not None:
        kind = "contact-resolved field (two-body FE, contact zones refined)"
        radius = CLOSE_UP_HALF_WIDTHS * b
        zone = (f"of the contact zone of {labels.contact} {number}, the largest P_h at this "
                f"position: P_h {ph:.4g} MPa, half-width b = {b * UM_PER_M:.3g} um")
    else:
        kind = "structural field (contact loads spread over strips: Hertz stress not resolved)"
        radius = STRUCTURAL_CLOSE_UP_M
        zone = (f"near {labels.contact} {number}, the largest P_h at this position "
                f"({ph:.4g} MPa); structural field, Hertz stress not resolved")
    report_field.field_png(
        vtu, folder / "von_mises.png",
        title=f"von Mises stress of the {result.member_name}, {kind}\n{case_line}\n{where}\n"
              f"lines: the fixed {labels.contacts}; {marked}{compare}",
        outlines=result.outlines, marks=marks)
    report_field.field_png(
        vtu, folder / "von_mises_contact.png", zoom_centre=at, zoom_radius=radius,
        title=f"Close-up {zone}\n{case_line}\n{where}\n{marked}{compare}",
        outlines=result.outlines, marks=marks)
    return ["von_mises.png", "von_mises_contact.png"]


def _write_xy(path: Path, pts):
    np.savetxt(path, np.asarray(pts).T * MM_PER_M, delimiter=",", header="x_mm,y_mm", comments="",
               fmt="%.9f")


def write_geometry(case: Case, folder: Path, points_per_tooth: int = 96) -> dict:
    """Profiles, the full drawing (DXF, SVG; STEP with the extra ``[cad]``), drawing.png
    and check.json of a case into ``folder``.

    Each profile (the disc's ``profile``; the sine pair's ``planet`` and ``ring``, each
    about its own centre) as CSV (x_mm,y_mm), DXF (one closed LWPOLYLINE, mm) and SVG
    (one closed path, mm). The drive's parts (:func:`toothfem.cad_parts.part_drawing`: the
    disc or planet with every hole, the pins, the housing or ring) as ``drawing.dxf`` (one
    layer per body, mm) and ``drawing.svg`` (one group per body, mm); with the extra
    ``[cad]`` installed each part as ``NAME.step`` (``disc``, ``housing``, the conventional
    ``pins``; ``planet`` and ``ring``; the ``output_pins`` and their ``output_rollers``
    where the drive has them), the disc's, planet's, housing's and ring's centre at the
    origin, the pins in the housing frame. ``check.json`` holds under ``cad`` the layers, the
    dimensions [mm], what is assumed and the STEP files (or why there are none).

    Parameters
    ----------
    case : Case
        The case.
    folder : pathlib.Path
        The output folder (already created).
    points_per_tooth : int
        Profile points per lobe or tooth, [8, 10000].

    Returns
    -------
    dict
        The derived quantities (``toothfem check``) with the files written.

    Raises
    ------
    CaseError
        If ``points_per_tooth`` is outside its range.
    """

    check_range("points_per_tooth", points_per_tooth, 8, 10000, error=CaseError)
    folder = Path(folder)
    summary = derived(case)
    drive = drive_for(case)
    profiles, checks = drive.profiles(points_per_tooth)
    files = []
    for name, pts in profiles.items():
        _write_xy(folder / f"{name}.csv", pts)
        cad.write_dxf(folder / f"{name}.dxf", pts, layer=name.upper())
        cad.write_svg(folder / f"{name}.svg", pts)
        files += [f"{name}.{ext}" for ext in ("csv", "dxf", "svg")]
    summary.update(checks)
    parts = part_drawing(case, points_per_tooth, drive=drive)
    cad.write_drawing_dxf(folder / "drawing.dxf", parts)
    cad.write_drawing_svg(folder / "drawing.svg", parts)
    files += ["drawing.dxf", "drawing.svg"]
    step: list[str] | str
    if cad.step_available():
        step = [cad.write_step(folder / f"{r.name}.step", r).name for r in parts.regions]
        files += step
    else:
        step = f"not written: the optional extra [{cad.CAD_EXTRA}] is not installed " \
               f"({cad.CAD_EXTRA_INSTALL})"
    summary["cad"] = {"layers": {b.layer: b.description for b in parts.bodies},
                      "dimensions_mm": parts.dimensions_mm, "assumed": parts.assumed,
                      "step": step}
    summary["files"] = files + ["drawing.png", "check.json"]
    save(plots.drawing(drive, case_name=case.name, parts=parts), folder / "drawing.png")
    (folder / "check.json").write_text(json.dumps(summary, indent=2))
    return summary


def loss_shares_chart(case: Case, results: dict, speed: float, torque: float):
    """The loss shares at the operating point (:func:`toothfem.report.plots.loss_shares`)
    with the case's published shares (``[published]`` keys ``loss_share_<component>``).

    Parameters
    ----------
    case : Case
    results : dict
        {source: efficiency summary} at the operating point (``efficiency.json``).
    speed, torque : float
        Input speed [rpm] and output torque [N m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(dict.fromkeys(k for r in results.values() for k in r["loss_shares"]))
    published = {k.removeprefix("loss_share_"): float(v) for k, v in case.published.items()
                 if k.startswith("loss_share_")}
    point = f"{speed:g} rpm input, {torque:.4g} N m output"
    return plots.loss_shares(names, {s: r["loss_shares"] for s, r in results.items()},
                             title=f"Loss shares at the operating point ({point})\n"
                                   f"{case.name}", published=published or None)


def efficiency_charts(case: Case, maps: EfficiencyMaps, tmp: Path, results: dict) -> list:
    """Efficiency against torque (with the measured and published points) and the two
    catalogue maps into ``tmp``, from the run's :class:`toothfem.maps.EfficiencyMaps`; the
    loss shares again with the case's published ones, where it has them.

    Parameters
    ----------
    case : toothfem.case.Case
    maps : toothfem.maps.EfficiencyMaps
        The efficiency over the operating range.
    tmp : pathlib.Path
        The run's folder being written.
    results : dict
        {source: efficiency summary} at the operating point.

    Returns
    -------
    list of str
        The report's lines.
    """
    speed, torque, sources = maps.speed_rpm, maps.torque_Nm, maps.sources
    if any(k.startswith("loss_share_") for k in case.published):
        save(loss_shares_chart(case, results, speed, torque), tmp / "loss_shares.png")
    oil = f"oil at {case.lubricant.reference_temperature_C:g} deg C (the lubricant's reference)"
    t_grid, curves, speed_curve = maps.torque_grid_Nm, maps.curves, maps.curve_speed_rpm
    with open(tmp / "efficiency_vs_torque.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["output_torque_Nm"] + [f"efficiency_{s}" for s in sources])
        for i, t in enumerate(t_grid):
            w.writerow([f"{t:.6g}"] + [f"{curves[s][i]:.6f}" for s in sources])
    at = " (the measured points' speed)" if speed_curve != speed else ""
    shown = {f"{s} loads, {speed_curve:g} rpm{at}": curves[s] for s in sources}
    dashed: tuple[str, ...] = ()
    if maps.operating_speed_curve is not None:     # the operating point's own speed as well
        label = f"analytic loads, {speed:g} rpm (the operating point's speed)"
        shown[label] = maps.operating_speed_curve
        dashed = (label,)
    eta_op = maps.operating_efficiency
    marked = [Marked(x=torque, y=eta_op, kind="operating",
                     label=f"operating point: {speed:g} rpm, {torque:.4g} N m, "
                           f"{100 * eta_op:.2f} % (analytic)")]
    for m, model in zip(case.measured, maps.measured_model):   # each with its gap to the model
        marked.append(Marked(
            x=m.output_torque_Nm, y=m.efficiency,
            label=f"measured {100 * m.efficiency:.2f} % ({m.input_speed_rpm:g} rpm, "
                  f"{m.output_torque_Nm:g} N m): {100 * (m.efficiency - model):+.1f} points "
                  "from the model (analytic);\n`toothfem loop` says what each effect would "
                  "need to close it"))
    pub = case.published
    if isinstance(pub.get("efficiency"), (int, float)):    # the paper's, at the operating point
        marked.append(Marked(x=torque, y=float(pub["efficiency"]), kind="published",
                             label=f"published {100 * pub['efficiency']:.2f} % at the operating "
                                   f"point ({speed:g} rpm, {torque:.4g} N m)"))
    if "efficiency_computed" in pub and "rig_output_torque_max_Nm" in pub:
        rig = pub.get("rig_input_speed_rpm")
        marked.append(Marked(x=pub["rig_output_torque_max_Nm"], y=pub["efficiency_computed"],
                             kind="published",
                             label=f"paper's model {100 * pub['efficiency_computed']:.2f} %"
                                   + (f" ({rig:g} rpm)" if rig else "")))
    save(plots.efficiency_vs_torque(
        t_grid, shown, marked, dashed=dashed,
        title=f"Efficiency against output torque; {oil}\n{case.name}"),
        tmp / "efficiency_vs_torque.png")
    # catalogue charts: torque x speed, and torque x oil temperature
    tt, nn, eta = maps.speed_map
    save(plots.efficiency_map(
        tt, nn, eta, "output torque [N m]", "input speed [rpm]",
        f"Efficiency [%] over output torque and input speed (analytic loads); {oil}\n"
        f"{case.name}", marked=[dataclasses.replace(m, y=speed) for m in marked[:1]]
        + [Marked(x=m.output_torque_Nm, y=m.input_speed_rpm, label="measured")
           for m in case.measured[:1]]),
        tmp / "efficiency_map.png")
    # at the operating point's speed, like the speed map; the point at its oil temperature
    tt2, th, eta_t = maps.temperature_map
    save(plots.efficiency_map(
        tt2, th, eta_t, "output torque [N m]", "oil temperature [deg C]",
        f"Efficiency [%] over output torque and oil temperature at {speed:g} rpm input (the "
        f"operating point's speed; analytic loads)\n{case.name}",
        marked=[Marked(x=torque, y=maps.oil_C, kind="operating",
                       label=f"operating point: {torque:.4g} N m, {maps.oil_words}: "
                             f"{100 * maps.operating_oil_efficiency:.2f} % (analytic)")]),
        tmp / "efficiency_temperature.png")
    np.savetxt(tmp / "efficiency_map.csv",
               np.column_stack([tt.ravel(), nn.ravel(), eta.ravel()]), delimiter=",",
               header="output_torque_Nm,input_speed_rpm,efficiency", comments="", fmt="%.6g")
    return ["![efficiency vs torque](efficiency_vs_torque.png)", "",
            "![efficiency map](efficiency_map.png)", "",
            "![efficiency over oil temperature](efficiency_temperature.png)", "",
            "Tables: `efficiency.json`, `efficiency_vs_torque.csv`, `efficiency_map.csv`.", ""]


def write_run(run: RunAnalysis, folder: Path, case_file=None) -> None:
    """The files of ``toothfem run`` from its records: the geometry, the contact, the
    datasheet, the efficiency (JSON, loss shares, curves and maps), life, strength and heat,
    report.md and report.html.

    Parameters
    ----------
    run : toothfem.pipeline.RunAnalysis
    folder : pathlib.Path
        An existing, empty folder (``run_case`` writes into a temporary one and renames it).
    case_file : path, optional
        The case file, named in the reports.
    """
    case = run.case
    label = str(case_file) if case_file is not None else "(in memory)"
    report = [f"# {case.name}", "", f"Case file: `{label}`; source: {case.source}", ""]
    (folder / "geometry").mkdir()
    write_geometry(case, folder / "geometry")
    report += ["## Geometry", "", "![drawing](geometry/drawing.png)", "",
               "Profiles: `geometry/*.csv` (x_mm, y_mm); the parts (disc or planet "
               "with its holes, pins, housing or ring): `geometry/drawing.dxf` and "
               "`geometry/drawing.svg` (mm, one layer or group per body; STEP of each "
               "part with the extra `[cad]`); checks: `geometry/check.json`.", ""]
    contact, summ, labels = run.contact, None, None
    if contact is not None:
        (folder / "contact").mkdir()
        summ = write_contact(contact, folder / "contact")
        labels = contact_labels(contact)
        report += [f"## Contact (FE, {contact.mode} mode)", "",
                   *report_summary.markdown(report_summary.contact_rows(
                       summ, labels, case.published)), ""]
        report += [f"![{png}](contact/{png})\n" for png in summ["files"]
                   if png.endswith(".png")]
        report += [f"Per {labels.contact} and position: `contact/load_sharing.csv`; "
                   "fields: `contact/*.vtu` (mm and MPa, the unit in each field's "
                   "name).", ""]
    if run.datasheet is not None:
        (folder / "stiffness").mkdir()
        stiff = run.datasheet.write(folder / "stiffness")
        report += ["## Datasheet (the system model of the whole reducer)", "",
                   "| quantity | value |", "|---|---|"]
        report += [f"| {q} | {v} |" for q, v in run.datasheet.table()]
        assumed = [k for k, v in stiff["supports"].items() if v["assumed"]]
        if assumed:
            report += ["", "Assumed (not in the case): " + ", ".join(assumed) + "."]
        report += ["", "![hysteresis](stiffness/hysteresis.png)", "",
                   "![loaded TE](stiffness/te.png)", "",
                   "Tables: `stiffness/hysteresis.csv`, `stiffness/te.csv`, "
                   "`stiffness/summary.json` (docs/stiffness.md).", ""]
    results, speed, torque = run.efficiency, run.speed_rpm, run.output_torque_Nm
    (folder / "efficiency.json").write_text(json.dumps(results, indent=2))
    names = list(dict.fromkeys(k for r in results.values() for k in r["losses"]))
    point = f"{speed:g} rpm input, {torque:.4g} N m output"
    report += ["## Efficiency", "", f"Operating point: {point}.", "",
               *report_summary.markdown(report_summary.efficiency_rows(
                   results, case.published))]
    laws = {k: v for r in results.values() for k, v in r["loss_sources"].items()}
    report += ["", "Each loss and its law:", ""]
    report += [f"- {name}: {law}" for name, law in laws.items()]
    for src, r in results.items():
        for note in r["notes"]:
            report.append(f"\n- {src}: {note}")
    save(plots.loss_shares(names, {s: r["loss_shares"] for s, r in results.items()},
                           title=f"Loss shares at the operating point ({point})\n"
                                 f"{case.name}"), folder / "loss_shares.png")
    report += ["", "![loss shares](loss_shares.png)", ""]
    report += efficiency_charts(case, run.maps, folder, results)
    dur = run.durability
    (folder / "durability.json").write_text(json.dumps(dur, indent=2))
    rv_teeth = None if case.rv is None else (case.rv.sun_teeth, case.rv.planet_teeth,
                                             case.rv.disc_teeth, case.rv.pin_count)
    report += report_durability.markdown(dur["life"], dur["strength"], dur["heat"], rv_teeth,
                                         dur.get("as_built"))
    said = run.warnings
    report += ["## Warnings", "", *([f"- {w}" for w in said] or ["None."]), ""]
    (folder / "report.md").write_text("\n".join(report) + "\n")
    report_html.write_report(folder, case, command="run", case_file=case_file, compared=(
        report_summary.efficiency_rows(results, case.published) + ([] if summ is None
        else report_summary.contact_rows(summ, labels, case.published))))
