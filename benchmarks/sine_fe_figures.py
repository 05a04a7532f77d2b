"""The measured figures of docs/fem_sine.md: the sine prototype's FE load sharing over one
tooth pitch (cycle mode), where Hertz fails and by how much, cycle vs detailed mode, mesh
convergence, the supports' influence, a torque sweep and the timings (wall and CPU).

Run: .venv/bin/python benchmarks/sine_fe_figures.py [--skip-detailed] [--skip-convergence]
Prints markdown tables. Timings depend on the machine's load: the CPU time is printed
beside the wall time.
"""
import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402
from toothfem.fem import sine_fe as sf  # noqa: E402
from toothfem.fem.load_sharing import analytic_split, hertz_fields  # noqa: E402
from toothfem.geometry import sine  # noqa: E402
from toothfem.fem.drives import drive_for  # noqa: E402

ARCSEC = 180 * 3600 / math.pi


class Clock:
    def __enter__(self):
        self.w, self.c = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall = time.perf_counter() - self.w
        self.cpu = time.process_time() - self.c


def cycle_figures(case, model, torque, n):
    with Clock() as setup:
        solver = sf.CycleSolver(model, np.arange(n) * model.pair.crank_pitch_rad / n)
        _ = solver.planet, solver.ring         # the meshes and tables, timed here
    with Clock() as run:
        ls = solver.solve(torque)
    with Clock() as again:
        solver.solve(1.5 * torque)
    print(f"## Cycle mode, {n} positions, T = {torque:.2f} N m, spacing "
          f"{solver.spacing * 1e6:.0f} um\n")
    print(f"planet {solver.planet.body.basis.N} dofs, ring {solver.ring.body.basis.N} dofs, "
          f"{solver.planet.n_hats} hats per tooth")
    print(f"setup (meshes, factorisations, influence tables): wall {setup.wall:.1f} s, cpu "
          f"{setup.cpu:.1f} s; {n} positions: wall {run.wall:.1f} s, cpu {run.cpu:.1f} s; "
          f"total wall {setup.wall + run.wall:.1f} s; a new load case: wall {again.wall:.1f} s")
    f = ls.force
    te = ls.transmission_error * ARCSEC
    print(f"max |torque residual| {np.max(np.abs(ls.torque_residual())):.1e}")
    print(f"teeth in contact: {np.min(ls.contacts_per_position)}-"
          f"{np.max(ls.contacts_per_position)} (count per position: "
          f"{''.join(str(c) for c in ls.contacts_per_position)})")
    print(f"F_max per position: {f.max(axis=1).min():.1f}-{f.max(axis=1).max():.1f} N "
          f"(at {math.degrees(ls.position_rad[np.argmax(f.max(axis=1))]):.3f} deg)")
    print(f"TE: {te.min():.2f}-{te.max():.2f} arcsec (mean {te.mean():.2f}, peak-to-peak "
          f"{np.ptp(te):.2f})")
    loaded = ls.in_contact
    b_h, ph_h, _ = hertz_fields(f, ls.face_width, ls.equivalent_radius, model.e_star)
    print(f"hertz_invalid {np.sum(ls.hertz_invalid[loaded])}/{np.sum(loaded)} contacts; "
          f"pressure_from_fe {np.sum(ls.pressure_from_fe)}")
    r = ls.ph[loaded] / ph_h[loaded]
    rb = ls.half_width[loaded] / b_h[loaded]
    print(f"FE P_h / Hertz P_h (geometric R_eq at the resultant): {r.min():.2f}-{r.max():.2f}; "
          f"FE b / Hertz b: {rb.min():.2f}-{rb.max():.2f}")
    print(f"FE P_h {ls.ph[loaded].min() / 1e6:.1f}-{ls.ph[loaded].max() / 1e6:.1f} MPa, "
          f"FE b {ls.half_width[loaded].min() * 1e3:.3f}-{ls.half_width[loaded].max() * 1e3:.3f}"
          f" mm, R_eq {ls.equivalent_radius[loaded].min():.3f}-"
          f"{ls.equivalent_radius[loaded].max():.3f} m\n")
    print("| crank angle [deg] | contact (tooth, flank) | F [N] | arm [mm] | R_eq [m] | "
          "Hertz P_h [MPa] | FE P_h [MPa] | Hertz b [mm] | FE b [mm] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in range(0, n, max(n // 4, 1)):
        for c in np.flatnonzero(loaded[p]):
            flank = "+1" if c % 2 else "-1"
            print(f"| {math.degrees(ls.position_rad[p]):.3f} | {ls.contact_id[p, c]}, {flank} | "
                  f"{f[p, c]:.1f} | {ls.moment_arm[p, c] * 1e3:.2f} | "
                  f"{ls.equivalent_radius[p, c]:.3f} | {ph_h[p, c] / 1e6:.1f} | "
                  f"{ls.ph[p, c] / 1e6:.1f} | {b_h[p, c] * 1e3:.3f} | "
                  f"{ls.half_width[p, c] * 1e3:.3f} |")
    # the seed's split (sine paper Eqs. 16-19) on the pairs within the FE's loaded deflection
    state = sine.meshing(model.pair, ls.position_rad)
    delta = np.max(ls.transmission_error[:, None] * np.abs(ls.moment_arm) * loaded, axis=1)
    seed = analytic_split(state, torque, ls.face_width, model.e_star, float(np.mean(delta)),
                          weight="cos_pressure_angle")
    print(f"\nseed split (Eqs. 16-19) within the mean loaded deflection "
          f"{np.mean(delta) * 1e6:.2f} um: {np.min(seed.contacts_per_position)}-"
          f"{np.max(seed.contacts_per_position)} pairs, F_max {seed.force.max(axis=1).min():.1f}"
          f"-{seed.force.max(axis=1).max():.1f} N\n")
    return ls


def detailed_figures(model, torque, fractions):
    print("## Cycle vs detailed mode\n")
    print("| crank angle [deg] | cycle F_max [N] | detailed F_max [N] | ratio | cycle P_h "
          "[MPa] | detailed P_h [MPa] | teeth (cycle/detailed) | TE cycle / detailed "
          "[arcsec] | detailed dofs | slave nodes | detailed wall / cpu [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for fr in fractions:
        phi = fr * model.pair.crank_pitch_rad
        with Clock() as clk:
            det = sf.solve_detailed(model, phi, torque)
        cyc = sf.CycleSolver(model, [phi]).solve(torque)
        d = det.load_sharing
        print(f"| {math.degrees(phi):.3f} | {cyc.force.max():.2f} | {d.force.max():.2f} | "
              f"{d.force.max() / cyc.force.max():.4f} | {cyc.ph.max() / 1e6:.1f} | "
              f"{d.ph.max() / 1e6:.1f} | {cyc.contacts_per_position[0]}/"
              f"{d.contacts_per_position[0]} | {cyc.transmission_error[0] * ARCSEC:.3f} / "
              f"{d.transmission_error[0] * ARCSEC:.3f} | {det.dofs} | {det.nodes.force.size} | "
              f"{clk.wall:.1f} / {clk.cpu:.1f} |")
    print()


def convergence_figures(model, torque, spacings, fractions):
    phis = np.asarray(fractions) * model.pair.crank_pitch_rad
    print("## Mesh convergence (cycle mode; every mesh size scales with the hat spacing)\n")
    print("| spacing [um] | dofs planet + ring | hats per tooth | F_max [N] at "
          + ", ".join(f"{math.degrees(p):.2f}" for p in phis)
          + " deg | P_h max [MPa] | TE [arcsec] | setup + solve wall / cpu [s] |")
    print("|---|---|---|---|---|---|---|")
    for s in spacings:
        with Clock() as clk:
            solver = sf.CycleSolver(model, phis, spacing=s)
            ls = solver.solve(torque)
        print(f"| {s * 1e6:.1f} | {solver.planet.body.basis.N} + {solver.ring.body.basis.N} | "
              f"{solver.planet.n_hats} | "
              + ", ".join(f"{x:.2f}" for x in ls.force.max(axis=1))
              + " | " + ", ".join(f"{x / 1e6:.2f}" for x in ls.ph.max(axis=1)) + " | "
              + ", ".join(f"{x * ARCSEC:.3f}" for x in ls.transmission_error)
              + f" | {clk.wall:.1f} / {clk.cpu:.1f} |")
    print()


def support_figures(model, torque, n):
    print("## Supports (ASSUMPTIONS) and torque\n")
    print("| planet bore [mm] | ring rim [mm] | torque [N m] | teeth in contact | F_max [N] | "
          "TE [arcsec] |")
    print("|---|---|---|---|---|---|")
    phis = np.arange(n) * model.pair.crank_pitch_rad / n
    rows = [(model, torque)]
    rows += [(replace(model, planet_bore_radius=28e-3), torque),
             (replace(model, ring_outer_radius=45e-3), torque)]
    rows += [(model, f * torque) for f in (0.1, 0.3, 3.0)]
    for m, t in rows:
        ls = sf.CycleSolver(m, phis).solve(t)
        te = ls.transmission_error * ARCSEC
        print(f"| {m.planet_bore_radius * 1e3:.2f} | {m.ring_outer_radius * 1e3:.2f} | {t:.2f} | "
              f"{ls.contacts_per_position.min()}-{ls.contacts_per_position.max()} | "
              f"{ls.force.max():.1f} | {te.min():.2f}-{te.max():.2f} |")
    print()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--positions", type=int, default=36)
    ap.add_argument("--skip-detailed", action="store_true")
    ap.add_argument("--skip-convergence", action="store_true")
    ap.add_argument("--skip-supports", action="store_true")
    args = ap.parse_args(argv)
    case = load_case(ROOT / "cases" / "sine_prototype.toml")
    model = drive_for(case).fe_model()
    torque = drive_for(case).member_torque(case.to_si().declared_output_torque_Nm())
    cycle_figures(case, model, torque, args.positions)
    if not args.skip_detailed:
        detailed_figures(model, torque, [0.0, 0.3, 0.62])
    if not args.skip_convergence:
        convergence_figures(model, torque, [70e-6, 50e-6, 35e-6, 25e-6, 17.7e-6],
                            [0.0, 0.3, 0.62])
    if not args.skip_supports:
        support_figures(model, torque, 12)


if __name__ == "__main__":
    main()
