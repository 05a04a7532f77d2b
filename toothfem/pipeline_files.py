"""The files of the pipeline: a contact result, a case's geometry and its efficiency charts.

:func:`write_contact` (load_sharing.csv, pictures, the VTU field, summary.json),
:func:`write_geometry` (profiles as CSV, DXF and SVG, the parts' drawing as DXF and SVG,
STEP with the extra ``[cad]``, drawing.png, check.json) and the
efficiency curves and maps of a run; the analyses that produce what they write are
:mod:`toothfem.pipeline`, which calls them.
"""
from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import cad
from .cad_parts import part_drawing
from .case import Case
from .derived import derived
from .efficiency import evaluate
from .errors import CaseError, check_range
from .fem import export
from .fem.drives import drive_for
from .report import contact as report_contact, plots, save
from .report.contact import ContactLabels
from .report.plots import Marked

if TYPE_CHECKING:   # annotations only: the pipeline imports this module
    from .pipeline import ContactResult

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
        Names of the case, contacts and member, the torques [N m] and the mode.
    """

    s = result.summary
    return ContactLabels(case_name=result.case_name, contact=result.contact_name,
                         contacts=result.contacts_name, member=result.member_name,
                         members=result.members, output_torque_Nm=s["output_torque_Nm"],
                         member_torque_Nm=s[f"{result.member_name}_torque_Nm"],
                         mode=result.mode)


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
    labels = contact_labels(result)
    with open(folder / "load_sharing.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CONTACT_COLUMNS)
        for row in ls.rows():
            w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
    pictures = {f"load_per_{result.contact_name}.png": report_contact.load_per_contact,
                "load_around_ring.png": report_contact.load_around_ring,
                "transmission_error.png": report_contact.transmission_error}
    for name, draw in pictures.items():
        save(draw(ls, labels), folder / name)
    summary = {**result.summary, "files": ["load_sharing.csv", "summary.json", *pictures]}
    if result.body is not None:
        vtu = export.write_vtu(folder / f"{result.member_name}_worst_position.vtu",
                               result.body, result.displacement)
        summary["files"] += [vtu.name, *field_pictures(result, vtu, folder)]
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def field_pictures(result: ContactResult, vtu: Path, folder: Path) -> list:
    """von_mises.png (the whole member) and von_mises_contact.png (close-up of the most
    loaded contact) of the member's field ``vtu``, labelled structural or
    contact-resolved.

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
    k = int(np.argmax(ls.force[worst]))
    number = int(ls.contact_id[worst, k])
    ph = float(ls.ph[worst, k] / 1e6)
    b = max(float(ls.half_width[worst, k]), CLOSE_UP_MIN_HALF_WIDTH_M)
    where = (f"{result.member_name} frame at the worst position "
             f"({np.degrees(result.positions_rad[worst]):.2f} deg crank); "
             f"{labels.torque_text}")
    if result.detail is not None:
        kind = "contact-resolved field (two-body FE, contact zones refined)"
        radius = CLOSE_UP_HALF_WIDTHS * b
        zone = (f"of the contact zone of {labels.contact} {number}: P_h {ph:.4g} MPa, "
                f"half-width b = {b * 1e6:.3g} um")
    else:
        kind = (f"structural field (contact loads spread over strips: the Hertz stress, "
                f"P_h {ph:.4g} MPa at {labels.contact} {number}, is not resolved)")
        radius = STRUCTURAL_CLOSE_UP_M
        zone = (f"near {labels.contact} {number}, structural field: the Hertz stress "
                f"(P_h {ph:.4g} MPa) is not resolved")
    draw = dict(outlines=result.outlines, mark=result.member_point)
    report_contact.field_png(
        vtu, folder / "von_mises.png",
        title=f"von Mises stress of the {result.member_name}, {kind}\n{where}\n"
              f"lines: the fixed member's {labels.contacts}; x: the most loaded {labels.contact}",
        **draw)
    report_contact.field_png(
        vtu, folder / "von_mises_contact.png", zoom_centre=result.member_point,
        zoom_radius=radius, title=f"Close-up {zone}\n{where}", **draw)
    return ["von_mises.png", "von_mises_contact.png"]


def _write_xy(path: Path, pts):
    np.savetxt(path, np.asarray(pts).T * 1e3, delimiter=",", header="x_mm,y_mm", comments="",
               fmt="%.9f")


def write_geometry(case: Case, folder: Path, points_per_tooth: int = 96) -> dict:
    """Profiles, the full drawing (DXF, SVG; STEP with the extra ``[cad]``), drawing.png
    and check.json of a case into ``folder``.

    Each profile (the disc's ``profile``; the sine pair's ``planet`` and ``ring``, each
    about its own centre) as CSV (x_mm,y_mm), DXF (one closed LWPOLYLINE, mm) and SVG
    (one closed path, mm). The drive's parts (:func:`toothfem.cad_parts.part_drawing`: the
    disc or planet with every hole, the pins, the housing or ring) as ``drawing.dxf`` (one
    layer per body, mm) and ``drawing.svg`` (one group per body, mm); with the extra
    ``[cad]`` installed each part as ``NAME.step`` (``disc`` and ``housing``; ``planet`` and
    ``ring``), its centre at the origin. ``check.json`` holds under ``cad`` the layers, the
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
    save(plots.drawing(drive, case_name=case.name), folder / "drawing.png")
    (folder / "check.json").write_text(json.dumps(summary, indent=2))
    return summary

#: Output torques of the efficiency curves and maps, as fractions of the largest torque of
#: the case (its operating point or a measured point): from near no load to 10 % beyond it,
#: so every marked point sits inside the chart, not on its edge.
TORQUE_GRID = np.linspace(0.02, 1.1, 55)
#: Input speeds of the speed map, as fractions of the operating speed.
SPEED_GRID = np.linspace(0.1, 2.0, 60)
#: Oil temperatures of the temperature map [deg C].
OIL_TEMPERATURE_GRID_C = np.linspace(20.0, 100.0, 41)


def _efficiency_charts(case: Case, tmp: Path, speed: float, torque: float, sources) -> list:
    """Efficiency against torque (with the measured and published points) and the two
    catalogue maps into ``tmp``; returns the report's lines."""
    import csv


    t_max = max([torque] + [m.output_torque_Nm for m in case.measured])
    speed_curve = case.measured[0].input_speed_rpm if case.measured else speed
    oil = f"oil at {case.lubricant.reference_temperature_C:g} deg C (the lubricant's reference)"
    t_grid = TORQUE_GRID * t_max
    curves = {s: evaluate(case, speed_curve, t_grid, loads=s).efficiency for s in sources}
    with open(tmp / "efficiency_vs_torque.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["output_torque_Nm"] + [f"efficiency_{s}" for s in sources])
        for i, t in enumerate(t_grid):
            w.writerow([f"{t:.6g}"] + [f"{curves[s][i]:.6f}" for s in sources])
    at = " (the measured points' speed)" if speed_curve != speed else ""
    shown = {f"{s} loads, {speed_curve:g} rpm{at}": curves[s] for s in sources}
    dashed = ()
    if speed_curve != speed:            # the operating point's own speed as well
        label = f"analytic loads, {speed:g} rpm (the operating point's speed)"
        shown[label] = evaluate(case, speed, t_grid).efficiency
        dashed = (label,)
    eta_op = float(evaluate(case, speed, torque).efficiency[0])
    marked = [Marked(x=torque, y=eta_op, kind="operating",
                     label=f"operating point: {speed:g} rpm, {torque:.4g} N m, "
                           f"{100 * eta_op:.2f} % (analytic)")]
    for m in case.measured:            # each with its gap to the model, never left silent
        model = float(evaluate(case, m.input_speed_rpm, m.output_torque_Nm).efficiency[0])
        marked.append(Marked(
            x=m.output_torque_Nm, y=m.efficiency,
            label=f"measured {100 * m.efficiency:.2f} % ({m.input_speed_rpm:g} rpm, "
                  f"{m.output_torque_Nm:g} N m): {100 * (m.efficiency - model):+.1f} points "
                  "from the model (analytic);\n`toothfem loop` says what each effect would "
                  "need to close it"))
    pub = case.published
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
    tt, nn = np.meshgrid(t_grid, SPEED_GRID * speed)
    eta = evaluate(case, nn, tt).efficiency.reshape(nn.shape)
    save(plots.efficiency_map(
        tt, nn, eta, "output torque [N m]", "input speed [rpm]",
        f"Efficiency [%] over output torque and input speed (analytic loads); {oil}\n"
        f"{case.name}", marked=[dataclasses.replace(m, y=speed) for m in marked[:1]]
        + [Marked(x=m.output_torque_Nm, y=m.input_speed_rpm, label="measured")
           for m in case.measured[:1]]),
        tmp / "efficiency_map.png")
    tt2, th = np.meshgrid(t_grid, OIL_TEMPERATURE_GRID_C)
    eta_t = evaluate(case, speed_curve, tt2, th).efficiency.reshape(th.shape)
    save(plots.efficiency_map(
        tt2, th, eta_t, "output torque [N m]", "oil temperature [deg C]",
        f"Efficiency [%] over output torque and oil temperature at {speed_curve:g} rpm "
        f"input (analytic loads)\n{case.name}"), tmp / "efficiency_temperature.png")
    np.savetxt(tmp / "efficiency_map.csv",
               np.column_stack([tt.ravel(), nn.ravel(), eta.ravel()]), delimiter=",",
               header="output_torque_Nm,input_speed_rpm,efficiency", comments="", fmt="%.6g")
    return ["![efficiency vs torque](efficiency_vs_torque.png)", "",
            "![efficiency map](efficiency_map.png)", "",
            "![efficiency over oil temperature](efficiency_temperature.png)", "",
            "Tables: `efficiency.json`, `efficiency_vs_torque.csv`, `efficiency_map.csv`.", ""]
