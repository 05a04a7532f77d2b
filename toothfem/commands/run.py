"""`toothfem run CASE --out DIR`: the whole pipeline (geometry, contact, efficiency) and a
Markdown report with its pictures, CSV tables and VTU fields."""
from __future__ import annotations

import argparse
import csv
import json

import numpy as np


def add_parser(sub):
    p = sub.add_parser("run", help="geometry, FE contact and efficiency of a case, with a "
                       "report (report.md, PNGs, CSV, VTU)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pitch (default 36)")
    p.add_argument("--field", choices=("detailed", "structural", "none"), default="structural",
                   help="stress field at the worst position (see `toothfem contact --help`); "
                        "default structural (fast)")
    p.add_argument("--no-fem", action="store_true",
                   help="skip the FE contact; efficiency from the analytic split only")
    p.set_defaults(func=run)


def _fe_available(case) -> bool:
    """A cycloid disc ([cycloid] section, also on rv cases) and the sine pair have FE
    models."""
    return case.cycloid is not None or case.drive == "sine"


def run(args) -> int:
    from .. import plots
    from ..case import load_case
    from ..efficiency.model import evaluate, operating_point
    from ..output import atomic_dir
    from . import contact, efficiency, geometry

    case = load_case(args.case)
    fem = not args.no_fem and _fe_available(case)
    report = [f"# {case.name}", "", f"Case file: `{args.case}`; source: {case.source}", ""]
    with atomic_dir(args.out) as tmp:
        # 1. geometry
        if case.drive in ("cycloid", "sine"):
            geometry.run(argparse.Namespace(case=args.case, out=tmp / "geometry",
                                            points_per_tooth=96))
            report += ["## Geometry", "", "![drawing](geometry/drawing.png)", "",
                       "Profiles: `geometry/*.csv` (x_mm, y_mm); checks: "
                       "`geometry/check.json`.", ""]
        # 2. contact
        if fem:
            contact.run(argparse.Namespace(case=args.case, positions=args.positions,
                                           torque=None, mode="cycle", pins=None,
                                           field=args.field, out=tmp / "contact"))
            summ = json.loads((tmp / "contact" / "summary.json").read_text())
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
        results = {s: efficiency.result(case, speed, torque, loads=s) for s in sources}
        if case.drive == "rv":
            results["rv_split_power"] = efficiency.result(case, speed, torque,
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
        (tmp / "report.md").write_text("\n".join(report) + "\n")
    print(f"wrote the report to {args.out}/report.md")
    return 0
