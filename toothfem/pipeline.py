"""The pipeline as Python calls: contact analysis of a case and the whole run.

``run_case(case, out)`` is what ``toothfem run`` does (geometry, FE contact, efficiency with
analytic and FE loads side by side, curves and maps, report.md); ``contact_analysis`` is
what ``toothfem contact`` does. Both work for every drive through
:func:`toothfem.fem.drives.drive_for`; the CLI only parses arguments and prints.
"""
from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import durability
from .case import Case, load_case
from .efficiency import evaluate, operating_point
from .errors import CaseError, check_range
from .fem import export
from .fem.drives import MAX_POSITIONS, drive_for
from .output import atomic_dir

MODES = ("cycle", "detailed")
FIELDS = ("detailed", "structural", "none")
#: Largest b_ref-scaled zoom of the contact close-up: 6 half-widths around the worst contact
#: show the Hertz zone and its subsurface maximum (at 0.78 b) with margin.
CLOSE_UP_HALF_WIDTHS = 6.0
#: Smallest half-width used for the close-up's zoom [m] (a contact with b = 0 in the record).
CLOSE_UP_MIN_HALF_WIDTH_M = 1e-6


@dataclass(frozen=True, kw_only=True)
class ContactResult:
    """FE load sharing of a case over one meshing period, and the field at its worst
    position (``body``/``displacement`` None without a field)."""
    case_name: str
    mode: str
    load_sharing: object            # toothfem.fem.load_sharing.LoadSharing
    positions_rad: np.ndarray
    worst: int                      # index of the position with the largest force
    detail: object                  # detailed result at the worst position, or None
    body: object
    displacement: np.ndarray | None
    member_point: np.ndarray        # worst contact in the member's frame, m
    member_name: str                # "disc" | "planet"
    summary: dict


def _output_torque(case: Case, torque_Nm) -> float:
    """The output torque of a contact analysis: given, or the case's operating point."""
    if torque_Nm is not None:
        return float(check_range("torque_Nm", torque_Nm, 0, None, lo_open=True,
                                 error=CaseError))
    return float(operating_point(case)[1])


def contact_analysis(case: Case, *, positions: int = 36, torque_Nm: float | None = None,
                     mode: str = "cycle", pins: str | None = None, field: str = "detailed",
                     progress=None) -> ContactResult:
    """FE load sharing over one meshing period.

    Parameters
    ----------
    case : toothfem.case.Case
    positions : int
        Meshing positions over one period.
    torque_Nm : float, optional
        Reducer output torque [N m]; default the case's operating point. The member carries
        :meth:`~toothfem.fem.drives.Drive.member_torque` of it.
    mode : {"cycle", "detailed"}
        Influence coefficients + Hertz (fast), or two-body FE contact at every position.
    pins : {"conventional", "integral", "rigid"}, optional
        Pin structure of a cycloid drive (default the case's); not for the sine pair.
    field : {"detailed", "structural", "none"}
        Stress field at the worst position (the sine pair has no structural field of its
        own: it always uses the detailed mode).
    progress : callable, optional
        Wraps the iterable of positions (a progress bar).

    Returns
    -------
    ContactResult
    """
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    if mode not in MODES:
        raise CaseError(f"mode = {mode!r} is not one of {list(MODES)}")
    if field not in FIELDS:
        raise CaseError(f"field = {field!r} is not one of {list(FIELDS)}")
    drive = drive_for(case)
    overrides = {}
    if pins is not None:
        choices = drive.fe_options.get("pin_structure")
        if choices is None:
            raise CaseError(f"--pins applies to cycloid drives, not to the {drive.kind} pair")
        if pins not in choices:
            raise CaseError(f"pins = {pins!r} is not one of {list(choices)}")
        overrides["pin_structure"] = pins
    output = _output_torque(case, torque_Nm)
    torque = drive.member_torque(output)
    phis = drive.positions(positions)
    detail = body = u = None
    if mode == "cycle":
        solver = drive.cycle_solver(positions, **overrides)
        model = solver.model
        ls = solver.solve(torque, progress=progress)
        worst = int(np.argmax(ls.force.max(axis=1)))
        if field == "structural" and solver.has_structural_field:
            body, u = solver.structural_field(worst, ls)
        elif field != "none":       # the pair's own detailed field
            detail = drive.solve_detailed(model, phis[worst], torque)
    else:
        model = drive.fe_model(**overrides)
        results = [drive.solve_detailed(model, phi, torque)
                   for phi in (progress or iter)(phis)]
        ls = stack_records([r.load_sharing for r in results])
        worst = int(np.argmax(ls.force.max(axis=1)))
        detail = results[worst]
    if detail is not None and field != "none":
        body, u = detail.member_body, detail.member_displacement
    k = int(np.argmax(ls.force[worst]))
    point = drive.member_frame_point(model, phis[worst], ls.point[worst, k])
    summary = {
        "case": case.name, "mode": mode, "positions": int(positions),
        "output_torque_Nm": output, f"{drive.member_name}_torque_Nm": torque,
        **model.describe(),
        "pins_in_contact_max": int(ls.contacts_per_position.max()),
        "pins_in_contact_min": int(ls.contacts_per_position.min()),
        "max_force_N": float(ls.force.max()),
        "max_ph_MPa": float(ls.ph.max() / 1e6),
        "transmission_error_arcsec": float(np.degrees(ls.transmission_error.mean()) * 3600),
        "transmission_error_ripple_arcsec": float(np.degrees(np.ptp(ls.transmission_error))
                                                  * 3600),
        "torque_equilibrium_max_rel_error": float(np.max(np.abs(ls.torque_residual()))),
        "worst_position_deg": float(np.degrees(phis[worst])),
        "hertz_invalid_contacts": int(np.sum(ls.hertz_invalid)),
        "ph_from_fe_contacts": int(np.sum(ls.pressure_from_fe)),
    }
    if mode == "cycle" and detail is not None:
        fd = detail.load_sharing.force[0]
        summary["detailed_check_at_worst_position"] = {
            "max_force_N": float(fd.max()),
            "max_ph_MPa": float(detail.load_sharing.ph.max() / 1e6),
            "max_force_ratio_detailed_to_cycle": float(fd.max() / ls.force[worst].max()),
            "dofs": int(detail.dofs)}
    return ContactResult(case_name=case.name, mode=mode, load_sharing=ls, positions_rad=phis,
                         worst=worst, detail=detail, body=body, displacement=u,
                         member_point=point, member_name=drive.member_name, summary=summary)


def stack_records(records):
    """One LoadSharing of several one-position records (concatenated over positions)."""
    first = records[0]
    out = {}
    for f in dataclasses.fields(first):
        vals = [getattr(r, f.name) for r in records]
        out[f.name] = np.concatenate(vals, axis=0) if isinstance(vals[0], np.ndarray) \
            else vals[0]
    return type(first)(**out)


CONTACT_COLUMNS = ("position_deg", "contact_id", "force_N", "moment_arm_mm", "half_width_mm",
                   "ph_MPa", "gap_mm")


def write_contact(result: ContactResult, folder: Path) -> dict:
    """Write load_sharing.csv, the pictures, the VTU field and summary.json into
    ``folder`` (an existing folder); returns the summary with its file list."""
    import csv

    from .report import contact as report_contact

    folder = Path(folder)
    ls = result.load_sharing
    with open(folder / "load_sharing.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CONTACT_COLUMNS)
        for row in ls.rows():
            w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
    summary = {**result.summary, "files": ["load_sharing.csv", "summary.json",
                                           "load_per_pin.png"]}
    report_contact.load_per_contact(ls).savefig(folder / "load_per_pin.png", dpi=120)
    if result.body is not None:
        label = result.member_name
        vtu = export.write_vtu(folder / f"{label}_worst_position.vtu", result.body,
                               result.displacement)
        kind = "detailed" if result.detail is not None else "structural"
        worst = result.worst
        report_contact.field_png(
            vtu, folder / "von_mises.png",
            title=f"von Mises ({kind}), worst position "
                  f"{np.degrees(result.positions_rad[worst]):.2f} deg, {label} frame")
        k = int(np.argmax(ls.force[worst]))
        b = max(float(ls.half_width[worst, k]), CLOSE_UP_MIN_HALF_WIDTH_M)
        report_contact.field_png(vtu, folder / "von_mises_contact.png",
                                 zoom_centre=result.member_point,
                                 zoom_radius=CLOSE_UP_HALF_WIDTHS * b,
                                 title=f"contact zone of contact "
                                       f"{int(ls.contact_id[worst, k])} ({kind})")
        summary["files"] += [vtu.name, "von_mises.png", "von_mises_contact.png"]
    (folder / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def _write_xy(path: Path, pts):
    np.savetxt(path, np.asarray(pts).T * 1e3, delimiter=",", header="x_mm,y_mm", comments="",
               fmt="%.9f")


def write_geometry(case: Case, folder: Path, points_per_tooth: int = 96) -> dict:
    """Profiles (CSV x_mm,y_mm), drawing.png and check.json of a case into ``folder``.

    Returns
    -------
    dict
        The derived quantities (``toothfem check``) with the files written.
    """
    from .derived import derived
    from .report import plots

    check_range("points_per_tooth", points_per_tooth, 8, 10000, error=CaseError)
    folder = Path(folder)
    summary = derived(case)
    drive = drive_for(case)
    profiles, checks = drive.profiles(points_per_tooth)
    for name, pts in profiles.items():
        _write_xy(folder / f"{name}.csv", pts)
    summary.update(checks)
    summary["files"] = [f"{n}.csv" for n in profiles] + ["drawing.png", "check.json"]
    plots.drawing(drive).savefig(folder / "drawing.png", dpi=120)
    (folder / "check.json").write_text(json.dumps(summary, indent=2))
    return summary


def efficiency_summary(case, speed, torque, oil_temp=None, loads="analytic",
                       method="power_flow") -> dict:
    """The efficiency record of one operating point as a plain mapping (the JSON)."""
    e = evaluate(case, speed, torque, oil_temp, loads=loads, method=method)
    shares = e.shares()
    return {
        "case": case.name, "loads": e.loads, "method": e.method,
        "input_speed_rpm": float(speed), "output_torque_Nm": float(torque),
        "oil_temp_C": oil_temp,
        "efficiency": float(e.efficiency[0]),
        "input_power_W": float(e.input_power_W[0]),
        "output_power_W": float(e.output_power_W[0]),
        "losses": {k: float(v[0]) for k, v in e.losses_W.items()},
        "loss_shares": {k: float(v[0]) for k, v in shares.items()},
        "mesh_efficiency": {k: float(v[0]) for k, v in e.mesh_efficiency.items()},
        "notes": list(e.notes),
    }


@dataclass(frozen=True, kw_only=True)
class RunResult:
    """What ``run_case`` computed and where it wrote it."""
    out: Path
    report: Path
    contact: ContactResult | None
    efficiency: dict               # {source: efficiency_summary(...)} at the operating point
    speed_rpm: float
    output_torque_Nm: float
    durability: dict = None        # {"life", "strength", "heat"}: toothfem.durability


def run_case(case: Case | str | Path, out, *, positions: int = 36, field: str = "structural",
             fem: bool = True, progress=None) -> RunResult:
    """The whole pipeline of a case with its report.

    Parameters
    ----------
    case : toothfem.case.Case or path
        The case (a path is loaded).
    out : path
        Output folder, written atomically (a failed run leaves none).
    positions : int
        Meshing positions over one period of the FE contact.
    field : {"detailed", "structural", "none"}
        Stress field at the worst position.
    fem : bool
        Run the FE contact, and the efficiency with FE loads beside the analytic one.
    progress : callable, optional
        Wraps the iterable of positions (a progress bar).

    Returns
    -------
    RunResult
        Contact result, efficiency at the operating point, and the report's path
        (``out/report.md`` with its PNGs, CSV tables and VTU fields).
    """
    import csv

    from .report import durability as report_durability
    from .report import plots

    label = str(case) if not isinstance(case, Case) else "(in memory)"
    if not isinstance(case, Case):
        case = load_case(case)
    out = Path(out)
    report = [f"# {case.name}", "", f"Case file: `{label}`; source: {case.source}", ""]
    contact = None
    with atomic_dir(out) as tmp:
        # 1. geometry
        (tmp / "geometry").mkdir()
        write_geometry(case, tmp / "geometry")
        report += ["## Geometry", "", "![drawing](geometry/drawing.png)", "",
                   "Profiles: `geometry/*.csv` (x_mm, y_mm); checks: "
                   "`geometry/check.json`.", ""]
        # 2. contact
        if fem:
            contact = contact_analysis(case, positions=positions, field=field,
                                       progress=progress)
            (tmp / "contact").mkdir()
            summ = write_contact(contact, tmp / "contact")
            report += ["## Contact (FE, cycle mode)", "",
                       "| quantity | value |", "|---|---|"]
            for k in ("pins_in_contact_max", "pins_in_contact_min", "max_force_N",
                      "max_ph_MPa", "transmission_error_arcsec",
                      "transmission_error_ripple_arcsec", "hertz_invalid_contacts",
                      "ph_from_fe_contacts", "torque_equilibrium_max_rel_error"):
                if k in summ:
                    v = summ[k]
                    report.append(f"| {k} | {v:.6g} |" if isinstance(v, float) else
                                  f"| {k} | {v} |")
            report += ["", "![load per contact](contact/load_per_pin.png)", ""]
            for png in ("von_mises.png", "von_mises_contact.png"):
                if (tmp / "contact" / png).exists():
                    report += [f"![{png}](contact/{png})", ""]
            report += ["Per contact and position: `contact/load_sharing.csv`; fields: "
                       "`contact/*.vtu`.", ""]
        # 3. efficiency at the operating point, analytic and FE loads side by side
        speed, torque = operating_point(case)
        sources = ["analytic"] + (["fem"] if fem else [])
        results = {s: efficiency_summary(case, speed, torque, loads=s) for s in sources}
        if case.rv is not None:       # the RV paper method beside ours
            results["rv_split_power"] = efficiency_summary(case, speed, torque,
                                                          method="rv_split_power")
        (tmp / "efficiency.json").write_text(json.dumps(results, indent=2))
        names = list(dict.fromkeys(k for r in results.values() for k in r["losses"]))
        report += ["## Efficiency", "",
                   f"Operating point: {speed:g} rpm input, {torque:.4g} N m output.", "",
                   "| | " + " | ".join(results) + " |",
                   "|---|" + "---|" * len(results),
                   "| efficiency [%] | " + " | ".join(f"{100 * r['efficiency']:.2f}"
                                                     for r in results.values()) + " |"]
        for n in names:
            report.append(f"| {n} [W] | " + " | ".join(
                f"{r['losses'][n]:.4g}" if n in r["losses"] else "–"
                for r in results.values()) + " |")
        for src, r in results.items():
            for note in r["notes"]:
                report.append(f"\n- {src}: {note}")
        fig = plots.loss_shares(names, {s: r["loss_shares"] for s, r in results.items()},
                                title="loss shares at the operating point")
        fig.savefig(tmp / "loss_shares.png", dpi=110)
        report += ["", "![loss shares](loss_shares.png)", ""]
        # efficiency versus torque with the measured points
        t_max = max([torque] + [m.output_torque_Nm for m in case.measured])
        speed_curve = case.measured[0].input_speed_rpm if case.measured else speed
        t_grid = np.linspace(0.02, 1.0, 50) * t_max
        curves = {f"{s} loads": evaluate(case, speed_curve, t_grid, loads=s).efficiency
                  for s in sources}
        with open(tmp / "efficiency_vs_torque.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["output_torque_Nm"] + [f"efficiency_{s}" for s in sources])
            for i, t in enumerate(t_grid):
                w.writerow([f"{t:.6g}"] + [f"{curves[f'{s} loads'][i]:.6f}" for s in sources])
        measured = [(m.output_torque_Nm, m.efficiency, f"measured {100 * m.efficiency:.2f} %")
                    for m in case.measured]
        pub = case.published
        if "efficiency_computed" in pub and "rig_output_torque_max_Nm" in pub:
            measured.append((pub["rig_output_torque_max_Nm"], pub["efficiency_computed"],
                             f"paper's model {100 * pub['efficiency_computed']:.2f} %"))
        plots.efficiency_vs_torque(t_grid, curves, measured,
                                   title=f"efficiency at {speed_curve:g} rpm").savefig(
            tmp / "efficiency_vs_torque.png", dpi=110)
        report += [f"![efficiency vs torque](efficiency_vs_torque.png)", ""]
        # catalogue charts: torque x speed, and torque x oil temperature
        n_grid = np.linspace(0.1, 2.0, 60) * speed
        tt, nn = np.meshgrid(t_grid, n_grid)
        eta = evaluate(case, nn, tt).efficiency.reshape(nn.shape)
        plots.efficiency_map(tt, nn, eta, "output torque [N m]", "input speed [rpm]",
                             "efficiency map (analytic loads)").savefig(
            tmp / "efficiency_map.png", dpi=110)
        temps = np.linspace(20.0, 100.0, 41)
        tt2, th = np.meshgrid(t_grid, temps)
        eta_t = evaluate(case, speed_curve, tt2, th).efficiency.reshape(th.shape)
        plots.efficiency_map(tt2, th, eta_t, "output torque [N m]", "oil temperature [deg C]",
                             f"efficiency at {speed_curve:g} rpm over oil temperature").savefig(
            tmp / "efficiency_temperature.png", dpi=110)
        np.savetxt(tmp / "efficiency_map.csv",
                   np.column_stack([tt.ravel(), nn.ravel(), eta.ravel()]), delimiter=",",
                   header="output_torque_Nm,input_speed_rpm,efficiency", comments="",
                   fmt="%.6g")
        report += ["![efficiency map](efficiency_map.png)", "",
                   "![efficiency over oil temperature](efficiency_temperature.png)", "",
                   "Tables: `efficiency.json`, `efficiency_vs_torque.csv`, "
                   "`efficiency_map.csv`.", ""]
        # 4. life, strength and heat beside the efficiency
        dur = {"heat": durability.thermal_summary(case, speed, torque),
               "life": durability.life_summary(case),
               "strength": durability.strength_summary(case, contact=contact)}
        (tmp / "durability.json").write_text(json.dumps(dur, indent=2))
        rv_teeth = None if case.rv is None else (case.rv.sun_teeth, case.rv.planet_teeth,
                                                 case.rv.disc_teeth, case.rv.pin_count)
        report += report_durability.markdown(dur["life"], dur["strength"], dur["heat"],
                                             rv_teeth)
        (tmp / "report.md").write_text("\n".join(report) + "\n")
    return RunResult(out=out, report=out / "report.md", contact=contact, efficiency=results,
                     speed_rpm=float(speed), output_torque_Nm=float(torque), durability=dur)
