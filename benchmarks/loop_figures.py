"""Figures of docs/loop.md: the measured-data loop on synthetic rig data (each catalog effect,
two at once, one outside the catalog, none over 20 seeds), its time on 200 points, and the
real data of the sine prototype and the RV-40E.

    .venv/bin/python benchmarks/loop_figures.py            # everything (about 2 min)
    .venv/bin/python benchmarks/loop_figures.py --quick    # skip the 20-seed study

Timings are wall-clock on whatever machine runs this (docs/loop.md: a 2-core machine).
"""
from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

from toothfem import load_case
from toothfem.efficiency.loop import effects as fx
from toothfem.efficiency import loop as lp
from toothfem.efficiency.loop import synthetic as sy
from toothfem.efficiency.loop.measured import load_measured

ROOT = Path(__file__).resolve().parent.parent
R = dataclasses.replace


def row(label, truth, rep):
    vals = "; ".join(f"{e.name} {p['value']:.4g} ± {p['stderr']:.2g}"
                     for e in rep.effects for p in e.parameters.values()) or "none"
    return (f"| {label} | {truth} | {vals} | {100 * rep.baseline.rmse:.3f} | "
            f"{100 * rep.final.rmse:.3f} | {rep.baseline.rmse / rep.final.rmse:.1f} | "
            f"{100 * rep.final.max_abs:.2f} | {', '.join(rep.unexplained) or '–'} | "
            f"{rep.elapsed_s:.1f} | {rep.evaluations} |")


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    sine = load_case(ROOT / "cases/sine_prototype.toml")
    cyc = load_case(ROOT / "cases/cycloid_pinhousing.toml")
    rv = load_case(ROOT / "cases/rv40e.toml")
    cat = fx.catalog()          # clearance springs from the FE, as the CLI uses
    print("| data (200 points) | truth | found (± std. error) | RMSE before [pt] | "
          "RMSE after [pt] | cut | max abs after [pt] | unexplained | time [s] | "
          "evaluations |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, (case, truth, kw) in sy.reference_scenarios(sine, cyc).items():
        data = sy.generate(case, {name: truth}, seed=1, catalog=cat, **kw)
        rep = lp.run_loop(case, data, cat)
        print(row(f"{name} ({case.drive})", f"{truth[0]:g}", rep))
    two = R(sine, friction=R(sine.friction, output_pin_coefficient=0.05))
    data = sy.generate(two, {"drag_torque": (20.0,), "output_mechanism_friction": (0.03,)},
                       seed=2, catalog=cat)
    print(row("drag + output pins (sine)", "20; 0.03", lp.run_loop(two, data, cat)))
    data = sy.generate(cyc, {"drag_torque": (200.0,), "mixed_lubrication": (0.07,)},
                       torque_Nm=(50.0, 167.0), seed=2, catalog=cat)
    print(row("drag + mixed (cycloid)", "200; 0.07", lp.run_loop(cyc, data, cat)))
    data = sy.generate(sine, {}, extra_loss=sy.running_in(0.05, 5.0), seed=3, catalog=cat)
    print(row("running-in, outside the catalog (sine)", "5 % e^(-t/5 h)",
              lp.run_loop(sine, data, cat)))
    data = sy.generate(rv, {"drag_torque": (300.0,)}, torque_Nm=(150.0, 500.0), seed=4,
                       catalog=cat)
    print(row("drag (rv)", "300", lp.run_loop(rv, data, cat)))
    if not args.quick:
        free = R(sine, friction=R(sine.friction, bearing_coefficient=0.0015,
                                  output_pin_coefficient=0.05),
                 lubricant=R(sine.lubricant, vogel_B_C=1000.0))
        t0 = time.perf_counter()
        false, unexplained = 0, 0
        for seed in range(20):
            data = sy.generate(free, {}, oil_temp_C=(20, 100), seed=100 + seed, catalog=cat)
            rep = lp.run_loop(free, data, cat)
            false += len(rep.effects)
            unexplained += bool(rep.unexplained)
        print(f"\nno effect, 20 seeds (sine, 7 candidates): {false} false effects, "
              f"{unexplained} data sets with an unexplained trend, "
              f"{time.perf_counter() - t0:.1f} s")
    print("\nReal data:")
    for case, name in ((sine, "sine_prototype_rig"), (rv, "rv40e_rig")):
        data = load_measured(ROOT / "data" / f"{name}.csv", ratio=case.ratio())
        rep = lp.run_loop(case, data, cat)
        r = rep.baseline_fit
        print(f"- {case.name}: measured {100 * data.efficiency[0]:.2f} %, model "
              f"{100 * r.prediction[0]:.2f} %, residual {100 * r.residual[0]:+.2f} pt"
              + (f", sensor sigma {100 * data.sigma[0]:.2f} pt" if data.sigma is not None
                 else "") + f" ({rep.elapsed_s:.1f} s)")
        for c in rep.closing:
            print(f"    {c.name}: {', '.join(f'{v:.4g}' for v in c.values)} -> "
                  f"RMSE {100 * c.rmse:.3f} pt ({c.note})")
        for k, v in rep.skipped.items():
            print(f"    not a candidate: {k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
