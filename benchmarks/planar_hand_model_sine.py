#!/usr/bin/env python3
"""Independent planar hand model of the sine-profile K-H-V reducer (cases/sine_prototype.toml)
at one crank angle, to check toothfem's system model (fem/system) on its torsional rigidity.

toothfem is imported only to read the case, the geometry and the clamped FE mesh (cycle
mode, fem/sine_fe); the system model is called at the end, to compare against.
Small displacements, quasi-static, plane, housing frame, SI; crank angle chi = 0.

Bodies, q = [out, dx, dy, th]: output flange rotation `out`; planet translation d = (dx, dy)
and rotation th about its centre; input (eccentric) held.  x below: e_z cross, perp(v) = e_z x v.
  Eccentric E = a0 e, e = (cos chi, sin chi); planet centre C = E (+ d); planet turns -chi/z1.
  Output pin k: centre P_k = R_w (cos a_k, sin a_k), a_k = 2 pi k/n - chi/z1, radius r; its hole
  in the planet: centre P_k + E, radius r + a0 (zero clearance).  The pin sits at -E from the
  hole centre, so it touches the hole wall along n = -e and can only push the wall along n:
  every pin pushes the planet toward the axis, along the same line, whatever the torque.
  Pin moves by out x P_k; hole centre by d + th x P_k (it sits P_k from C).  Compression
      delta_k = n.((out - th) perp(P_k) - d) = (out - th) R_w sin(a_k - chi) + d.e
  (the negative of toothfem's gap change -n.(out x P_k - d - th x P_k): the same sign).
  Force f_k n on the planet, moment about C: (P_k + (r+a0) n) x f_k n = f_k R_w sin(a_k - chi);
  on the flange -f_k R_w sin: since all pin forces are parallel to E the planet's pin torque
  equals the output torque T exactly.  Pin law: Palmgren line contact over the face width l,
  delta = 3.84e-5 Q^0.9 / l^0.8 [mm, N, mm], in series with the pin's bending on two simple
  supports (the member at mid-span: L^3/(48 E I) + L/(4 kappa G A), kappa = 0.9), as toothfem
  assumes; compression only; the secant stiffness Q/delta(Q) is iterated to the found loads.
Mesh (the simplest model with the mechanism): one spring along the line of the clamped mesh's
  resultant.  From the FE cycle mode with the planet's centre held (toothfem.fem.sine_fe):
  column forces f_i at points p_i, ring normals m_i (into the planet, from the ring profile's
  geometry at p_i), planet rotation th_c (the clamped TE).  Resultant on the planet
  R = sum f_i m_i, unit t = R/|R|, signed arm h = -T/|R| (the ring's torque on the planet: -T).
  A translation d opens the teeth by t.d, a rotation th by h th: compression -(t.d + h th);
  stiffness k_m = |R|^2/(T th_c) reproduces th_c under T with d = 0 (a secant: gaps + Hertz).
  Variant "columns": one such spring per loaded column, along m_i with the FE record's arm
  (force-weighted over the column's hats), k_i = f_i/(-arm_i th_c), no gaps.
Eccentric bearing: linear isotropic spring K between planet centre and eccentric; K is the
  secant of Stribeck-Palmgren (most loaded roller 4.08 F/Z, approach on both races) at the
  bearing load the hand model finds (fixed point).  Full configuration (c) only: in series
  the input shaft's two tapered bearings (F/2 each, radial 2 delta(4.08 F/2/(Z cos a))/cos a,
  toothfem's assumed Z=14, l=0.55 d, a=15 deg) and its bending at mid-span; its torsion
  (0.45 mm x ~0.7 kN = 0.3 N m) is left rigid.
Potential  Pi(q) = 1/2 k_m delta_m^2 + 1/2 sum k_k max(delta_k,0)^2 + 1/2 K |d|^2 - T out,
  dPi/dq = 0 is every body's balance.  Work balance (Clapeyron, secants): T out = F_m delta_m
  + sum f_k delta_k + K|d|^2: each part's share of the twist.  K d = R_m + F_p n, so the
  bearing's share K|d|^2/T splits into translation through the pins  F_p (-d.e)/T  (the
  claimed mechanism) and through the mesh  R_m.d/T  (the teeth open as the planet moves).
Left out: the mesh's own redistribution under translation (one line of action, or fixed
  columns without gaps: the clamped secant at every planet pose), friction, output flange translation, the planet body's
  deformation between bore and holes, the input shaft's torsion, tilts; the roller bearings'
  anisotropy (secant along the load only).
Run:  .venv/bin/python benchmarks/planar_hand_model_sine.py  (about 3 s, FE tables cold)
"""
import json
import math
import os

import numpy as np
from toothfem import load_case
from toothfem.fem.drives import drive_for
from toothfem.geometry import sine

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
T, P, ARCMIN = 26.1, 0, 60 * 180 / math.pi          # output torque, position, rad -> arcmin


def palmgren(q, l):
    """Approach [m] of one line contact of length l [m] under Q [N] (Palmgren)."""
    return 3.84e-5 * np.maximum(q, 0) ** 0.9 / (l * 1e3) ** 0.8 * 1e-3


def beam_mid(F_unit, L, d, E, nu):
    """Deflection per N at mid-span of a round shaft on simple supports (bending + shear)."""
    I, A, G = math.pi * d**4 / 64, math.pi * d**2 / 4, E / (2 * (1 + nu))
    return F_unit * (L**3 / (48 * E * I) + L / (4 * 0.9 * G * A))


def read_case():
    case = load_case(os.path.join(ROOT, "cases", "sine_prototype.toml"))
    drive = drive_for(case)
    pr, om = drive.pair, drive.output
    sup = drive.supports(case.to_si().supports)
    mat = drive.material_si
    E, nu = mat.youngs_modulus_Pa, mat.poisson_ratio
    cyc = drive.cycle_solver(12)
    chi = float(cyc.positions_rad[P])
    ls = cyc.solve(T)                                  # planet centre held: clamped mesh
    on = ls.force[P] > 0
    f, pts = ls.force[P][on], ls.point[P][on].T        # (C,), (2, C) ring frame
    f2, _ = sine.foot_point(pr, pts)
    d1 = sine.ring_curve(pr, f2).d1
    m = np.stack([-d1[1], d1[0]]) / np.hypot(*d1)      # ring normal, sign set below
    e = np.array([math.cos(chi), math.sin(chi)])
    C = pr.centre_distance_m * e
    rel_p = pts - C[:, None]
    arm = rel_p[0] * m[1] - rel_p[1] * m[0]            # (p - C) x m
    m, arm = (m, arm) if np.sum(f * arm) < 0 else (-m, -arm)   # ring's torque on planet: -T
    span, w = sup.crankshaft_span_m, pr.face_width_m
    return dict(drive=drive, sup=sup, chi=chi, e=e, a0=pr.centre_distance_m,
                z1=pr.planet_teeth, n=om.pin_count, Rw=om.pin_hole_circle_radius_m, w=w,
                th_c=float(ls.transmission_error[P]), f=f, m=m, arm=arm,
                arm_fe=ls.moment_arm[P][on], c_pin_bend=beam_mid(1, span, 2 * om.pin_radius_m, E, nu),
                c_shaft=beam_mid(1, span, sup.crankshaft_diameter_m, E, nu),
                Z=sup.bearing_roller_count, l_b=sup.bearing_roller_length_m,
                d_in=sup.crankshaft_diameter_m)


def support_compliance(g, F, full):
    """Secant compliance [m/N] of what holds the planet's centre, at its load F [N]."""
    c = 2 * palmgren(4.08 * F / g["Z"], g["l_b"]) / F          # eccentric bearing
    if full:
        a = math.radians(15.0)
        c += 2 * palmgren(4.08 * 0.5 * F / (14 * math.cos(a)), 0.55 * g["d_in"]) / math.cos(a) / F
        c += g["c_shaft"]
    return c


def solve(g, support, mesh="lumped"):
    """support: None (rigid), a stiffness [N/m], or 'eccentric' / 'full' (secants iterated)."""
    e, n = g["e"], -g["e"]
    ang = 2 * math.pi * np.arange(g["n"]) / g["n"] - g["chi"] / g["z1"]
    Pk = g["Rw"] * np.stack([np.cos(ang), np.sin(ang)])        # (2, n)
    lev = n @ np.stack([-Pk[1], Pk[0]])                         # n . perp(P_k)
    B = np.column_stack([lev, -np.tile(n, (g["n"], 1)), -lev])  # pin compression rows
    R = g["f"] @ g["m"].T
    if mesh == "lumped":
        Rn = np.hypot(*R)
        Mrows, km = np.array([[0, *(-R / Rn), T / Rn]]), np.array([Rn**2 / (T * g["th_c"])])
    else:
        Mrows = np.column_stack([np.zeros(g["f"].size), -g["m"].T, -g["arm_fe"]])
        km = g["f"] / (-g["arm_fe"] * g["th_c"])
    free = [0, 3] if support is None else [0, 1, 2, 3]
    Q = np.full(g["n"], 4 * T / (g["n"] * g["Rw"]))
    Fb = 2000.0
    act = lev > 0
    for it in range(300):  # noqa: B007 (its count is read after the loop)
        K = support if isinstance(support, float) else None
        if isinstance(support, str):
            K = 1 / support_compliance(g, Fb, support == "full")
        kp = np.maximum(Q, 1e-3) / (palmgren(np.maximum(Q, 1e-3), g["w"]) + g["c_pin_bend"] * np.maximum(Q, 1e-3))
        H = (B[act].T * kp[act]) @ B[act] + (Mrows.T * km) @ Mrows
        if K is not None:
            H[1:3, 1:3] += K * np.eye(2)
        q = np.zeros(4)
        q[free] = np.linalg.solve(H[np.ix_(free, free)], np.array([T, 0, 0, 0])[free])
        delta = B @ q
        Qn = np.where(delta > 0, kp * delta, 0.0)
        Fb_new = K * np.hypot(*q[1:3]) if K is not None else Fb
        done = np.array_equal(delta > 0, act) and np.max(np.abs(Qn - Q)) < 1e-9 * Q.max() \
            and abs(Fb_new - Fb) < 1e-9 * Fb
        act, Q, Fb = delta > 0, Qn, Fb_new
        if done:
            break
    dm = Mrows @ q                                               # mesh compression(s)
    Fm = km * dm
    Rm = (Fm[:, None] * -Mrows[:, 1:3]).sum(0)                   # mesh force on the planet
    Fp = Q.sum()
    Fbear = Rm + Fp * n                                          # = K d, force on the journal
    res = dict(twist=q[0], th=q[3], along=q[1:3] @ e, across=q[1:3] @ np.array([-e[1], e[0]]),
               bearing=float(np.hypot(*Fbear)), pins=Q[Q > 0], iterations=it + 1,
               K=K, mesh_force=float(np.hypot(*Rm)))
    res["shares"] = {"mesh": float(Fm @ dm) / T, "output pins": float(Q @ np.maximum(delta, 0)) / T,
                     "supports": float(Fbear @ q[1:3]) / T}
    res["via pins"], res["via mesh"] = Fp * -res["along"] / T, float(Rm @ q[1:3]) / T
    res["balance"] = abs(sum(res["shares"].values()) / q[0] - 1)           # Clapeyron check
    mom = float(Q @ lev) - T                                                 # flange balance
    res["equilibrium"] = max(abs(mom) / T, float(np.hypot(*(Rm + Fp * n - (K or 0) * q[1:3]))) / Fp
                             if K else abs(mom) / T)
    return res


def toothfem_state(g, K, rigid):
    """toothfem's system model, only here, to compare against."""
    kw = {} if K is None else {"crank_bearing_stiffness_N_per_m": K}
    sysm = g["drive"].system_model(g["sup"], 12, rigid=rigid, **kw)
    st = sysm.solve(T, P)
    d = st.equilibrium.u[sysm.coords.index["disc0"]]
    e = g["e"]
    p = st.paths_rad
    Fb = st.bearing_force_N["eccentric bearing disc 1"]
    sup = p["eccentric bearings"] + p["input bearings"] + p["input shaft bending"] + p["input shaft torsion"]
    via = float(np.sum(st.output_pin_force_N)) * -float(d[:2] @ e) / T     # as the hand's split
    return dict(twist=st.twist_rad, th=float(d[2]), along=float(d[:2] @ e),
                across=float(d[:2] @ np.array([-e[1], e[0]])), bearing=float(np.hypot(*Fb)),
                pins=st.output_pin_force_N[0][st.output_pin_force_N[0] > 0],
                shares={"mesh": p["mesh"] + p["mesh clearance"], "output pins": p["output pins"],
                        "supports": sup}, **{"via pins": via, "via mesh": sup - via}, mesh_force=float(np.hypot(*np.sum(
                            st.mesh[0].force_N * -st.mesh[0].contacts.normal, 1))))


def rel(a, b):
    return f"{(a / b - 1) * 100:+6.1f}%" if b else "   -  "


def table(title, h, t, alt):
    print(f"\n{title}")
    print(f"  {'quantity':<34}{'hand':>10}{'toothfem':>10}{'diff':>9}{'hand, 3 columns':>17}")
    rows = [("output twist [arcmin]", lambda r: r["twist"] * ARCMIN),
            ("rigidity T/twist [N m/arcmin]", lambda r: T / (r["twist"] * ARCMIN)),
            ("planet rotation th [urad]", lambda r: r["th"] * 1e6),
            ("planet translation along e [um]", lambda r: r["along"] * 1e6),
            ("planet translation across e [um]", lambda r: r["across"] * 1e6),
            ("eccentric bearing force [N]", lambda r: r["bearing"]),
            ("mesh resultant [N]", lambda r: r["mesh_force"])]
    rows += [(f"output pin {i + 1} force [N]", lambda r, i=i: r["pins"][i]) for i in range(len(t["pins"]))]
    rows += [(f"twist share {k} [urad]", lambda r, k=k: r["shares"][k] * 1e6) for k in t["shares"]]
    for name, fn in rows:
        a, b, c = fn(h), fn(t), fn(alt)
        print(f"  {name:<34}{a:10.3f}{b:10.3f}{rel(a, b) if abs(b) > 0.05 else '     -  ':>9}{c:17.3f}")
    for who, r in (("hand", h), ("toothfem", t)):
        print(f"  {who:>8}: supports' share = through the pins F_p(-d.e)/T {r['via pins'] * 1e6:6.1f} urad"
              f" + through the mesh {r['via mesh'] * 1e6:6.1f} urad (twist {r['twist'] * 1e6:.1f})")


def main():
    g = read_case()
    print(f"clamped mesh (FE cycle mode, chi = {math.degrees(g['chi']):.1f} deg, T = {T} N m): "
          f"th_c = {g['th_c'] * 1e6:.2f} urad, columns f = {np.round(g['f'], 1).tolist()} N; "
          f"arms from the ring normals {np.round(g['arm'] * 1e3, 3).tolist()} mm, "
          f"FE record {np.round(g['arm_fe'] * 1e3, 3).tolist()} mm")
    R = g["f"] @ g["m"].T
    print(f"  resultant on the planet {np.round(R, 1).tolist()} N: {math.degrees(math.atan2(-R[1], -R[0])):.1f}"
          f" deg from -e; line of action {T / np.hypot(*R) * 1e3:.2f} mm from the planet centre")
    out = {"torque_Nm": T, "crank_angle_rad": g["chi"]}
    rig = ("support bearings", "crankshaft bending", "crankshaft torsion")
    ha = solve(g, "eccentric")
    K = ha["K"]
    cases = [("a", f"(a) eccentric bearing linear K = {K:.4g} N/m (Stribeck-Palmgren secant at "
              f"{ha['bearing']:.0f} N); input bearings, shaft bending and torsion rigid",
              ha, solve(g, K, "columns"), (K, rig)),
             ("b", "(b) rigid except the output pins and the mesh", solve(g, None),
              solve(g, None, "columns"), (None, rig + ("crank bearings",))),
             ("c", "(c) full: nonlinear bearings and input shaft bending (hand: their secants)",
              solve(g, "full"), solve(g, "full", "columns"), (None, ()))]
    for key, title, h, alt, (k, rigid) in cases:
        t = toothfem_state(g, k, rigid)
        table(title, h, t, alt)
        print(f"  hand checks: {h['iterations']} secant iterations, Clapeyron {h['balance']:.1e}, "
              f"balance {h['equilibrium']:.1e}")
        out[key] = {"hand": h, "hand_columns": alt, "toothfem": t}
    a, b = out["a"], out["b"]
    print("\nthe planet's translation on its eccentric bearing, (a) - (b): " + ", ".join(
        f"{w} {(a[w]['twist'] - b[w]['twist']) * 1e6:.1f} urad" for w in ("hand", "toothfem")))
    print("twist, hand against toothfem: " + ", ".join(
        f"({k}) {rel(out[k]['hand']['twist'], out[k]['toothfem']['twist']).strip()}" for k in "abc"))
    path = os.path.join(ROOT, "benchmarks", "results", "planar_hand_model_sine.json")
    with open(path, "w") as fh:
        json.dump(out, fh, indent=1, default=lambda x: x.tolist() if hasattr(x, "tolist") else None)
    print("wrote", path)


if __name__ == "__main__":
    main()
