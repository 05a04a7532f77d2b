"""Mesh-convergence table of the Hertz line-contact checks (docs/fem.md).

Run: .venv/bin/python benchmarks/hertz_convergence.py
"""
import time

from toothfem.fem.verification import cylinder_contact

CASES = {
    "cylinder on flat (NAFEMS, 35 kN/mm)": dict(load_per_length=35e6),
    "cylinder in bore R2 = 2 R1 (5 kN/mm)": dict(load_per_length=5e6, bore_radius=0.1),
}

if __name__ == "__main__":
    print("| case | elements per half-width | dofs | p_max [MPa] | p0 [MPa] | error p | "
          "b_FE [mm] | b [mm] | error b | time [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, kw in CASES.items():
        for n in (5, 10, 20, 30):
            t = time.perf_counter()
            r = cylinder_contact(0.05, 210e9, 0.3, 70e9, 0.3, elements_per_halfwidth=n, **kw)
            dt = time.perf_counter() - t
            print(f"| {name} | {n} | {r.dofs} | {r.p_max / 1e6:.1f} | {r.p0_analytic / 1e6:.1f} | "
                  f"{r.p_error * 100:+.2f} % | {r.b_fe * 1e3:.4f} | {r.b_analytic * 1e3:.4f} | "
                  f"{r.b_error * 100:+.2f} % | {dt:.1f} |", flush=True)
