"""Sine reducer at the paper's rig condition: each loss share beside the paper's (Sec. 6.4),
the eccentric bearing with and without the pins' load (Sec. 6.3), and efficiency versus
output torque with the measured point (docs/img/sine_efficiency_vs_torque.png).

    .venv/bin/python benchmarks/sine_components.py
"""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from toothfem import load_case
from toothfem.efficiency import evaluation as m
from toothfem.efficiency.mesh_table import mesh_table
from toothfem.fem.drives import drive_for
from toothfem.report.plots import efficiency_vs_torque

ROOT = Path(__file__).resolve().parent.parent


def main():
    case = load_case(ROOT / "cases" / "sine_prototype.toml")
    pub = case.published
    n1, t2 = pub["rig_input_speed_rpm"], pub["rig_output_torque_max_Nm"]
    e = m.evaluate(case, n1, t2)
    sh = {k: float(v[0]) for k, v in e.shares().items()}
    paper = {"mesh": pub["loss_share_mesh"], "bearings": pub["loss_share_bearings"],
             "output_mechanism": pub["loss_share_output_mechanism"],
             "churning": pub["loss_share_churning"]}
    ours = {"mesh": sh["mesh"], "bearings": sh["eccentric_bearing"] + sh["plain_bearings"],
            "output_mechanism": sh["output_mechanism"], "churning": sh["churning"]}
    print(f"rig: {n1:g} rpm, {t2:g} N m, nu50 = {case.lubricant.kinematic_viscosity_mm2_s:g} "
          "mm2/s")
    print(f"{'loss':<18s}{'toothfem [%]':>14s}{'paper [%]':>12s}{'diff [pp]':>11s}")
    for k in paper:
        print(f"{k:<18s}{100 * ours[k]:14.2f}{100 * paper[k]:12.2f}"
              f"{100 * (ours[k] - paper[k]):11.2f}")
    eta = float(e.efficiency[0])
    print(f"{'efficiency':<18s}{100 * eta:14.2f}{100 * pub['efficiency_computed']:12.2f}"
          f"{100 * (eta - pub['efficiency_computed']):11.2f}   measured "
          f"{100 * case.measured[0].efficiency:.2f}")

    # eccentric bearing: the planet's equilibrium with and without the pins' resultant
    table = mesh_table(drive_for(case))
    force, _ = table.at(np.array([t2]))
    mesh_res = table.resultant(force)[0]
    e_dir = table.centre / np.linalg.norm(table.centre, axis=1)[:, None]
    sum_q = 4 * t2 / (math.pi * case.output_mechanism.pin_hole_circle_radius_mm * 1e-3)
    f_with = np.mean(np.linalg.norm(mesh_res - sum_q * e_dir, axis=1))
    f_mesh = np.mean(np.linalg.norm(mesh_res, axis=1))
    radial = float(np.mean(np.sum(mesh_res * e_dir, axis=1)))
    tang = float(np.mean(np.abs(mesh_res[:, 0] * -e_dir[:, 1] + mesh_res[:, 1] * e_dir[:, 0])))
    print(f"planet: mesh resultant {f_mesh:.0f} N (radial {radial:.0f} N, tangential "
          f"{tang:.0f} N = T2/r1 {t2 / (case.sine.module_mm * case.sine.planet_teeth / 2e3):.0f}"
          f" N), pins sum Q = {sum_q:.0f} N, bearing F_R1 = {f_with:.0f} N, "
          f"delta = F_R1/F_mesh = {f_with / f_mesh:.3f}, mean pressure angle of the resultant "
          f"{math.degrees(math.atan2(-radial, tang)):.1f} deg")
    p_in = float(e.input_power_W[0])
    p_b = float(e.losses_W["eccentric_bearing"][0])
    print(f"bearing efficiency 1 - P_b/P: with the pins' load {100 * (1 - p_b / p_in):.2f} % "
          f"(paper 92.58 %), mesh load only {100 * (1 - p_b * f_mesh / f_with / p_in):.2f} % "
          "(paper 98.73 %)")

    torque = np.linspace(0.5, 28.0, 56)
    curves = {"toothfem (analytic loads)": m.evaluate(case, n1, torque).efficiency}
    no_churn = dataclasses.replace(case, lubricant=dataclasses.replace(case.lubricant,
                                                                       churning="none"))
    curves["toothfem without churning/seals"] = m.evaluate(no_churn, n1, torque).efficiency
    measured = [(mp.output_torque_Nm, mp.efficiency, f"measured {100 * mp.efficiency:.2f} %")
                for mp in case.measured]
    measured.append((t2, pub["efficiency_computed"],
                     f"paper's model {100 * pub['efficiency_computed']:.2f} %"))
    fig = efficiency_vs_torque(torque, curves, measured,
                               title=f"sine prototype at {n1:g} rpm, nu50 = 400 mm2/s")
    out = ROOT / "docs" / "img" / "sine_efficiency_vs_torque.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
