#!/usr/bin/env python3
"""Independent planar hand model of an RV (2K-V) reducer's second stage (oracle).

Written from first principles with numpy only; it does NOT import toothfem.
Small displacements, quasi-static, plane (x, y), housing frame, SI units.

Bodies and dofs  q = [theta_c, x_0, y_0, th_0, ..., x_{M-1}, y_{M-1}, th_{M-1}]
  carrier (output) rotation theta_c; disc j rigid translation d_j = (x_j, y_j), rotation th_j.
  Input (sun of stage 1) held; spur mesh and crank torsion rigid; carrier bearings of
  the cranks rigid simple supports.  Crank bending + crank bearing are condensed.

Geometry at the analysed instant (crank angle phi):
  pins   C_i = Rp (cos 2 pi i/Zp, sin 2 pi i/Zp)
  disc j u_j = (cos(phi+a_j), sin(phi+a_j)),  O_j = e u_j,  pitch point P_j = e Zp u_j
  normal n_ij = (C_i - P_j)/|C_i - P_j|  (from disc into pin; the pin pushes the disc
         with -f n_ij, i.e. back toward P_j), contact point K_ij = C_i - rp n_ij
  crank k axis A_k = Rc (cos b_k, sin b_k), b_k = 2 pi k/N.  CHOICE: the crank holes of
         every disc use these nominal housing-frame angles (disc rotation taken as 0):
         hole centre H_jk = O_j + R_k with R_k = A_k; journal centre J_jk = A_k + e u_j.

Pin contact (spring k_pin that can only push, zero initial gap on every pin):
  compression  delta_ij = n_ij . (d_j + th_j e_z x (K_ij - O_j)) = b_ij . q
  force        f_ij = k_pin max(delta_ij, 0)      (complementarity f >= 0, gap >= 0, f gap = 0)
Crank bearing + crank bending, crank k, one direction (x or y) at a time, all M discs:
  rigid-line journal motion  r_jk = theta_c v_jk,
      v_jk = e_z x A_k + (1 + z_s/z_p) e_z x (e u_j)   (axis carried by carrier, crank turns
      absolutely by (1+z_s/z_p) theta_c because the sun is held: planet_rel = (z_s/z_p) theta_c)
  hole motion                h_jk = d_j + th_j e_z x R_k
  force crank k receives from disc j:  F_jk = k_b (h_jk - q_jk), journal q_jk = r_jk + sum_l W(a_j,a_l) F_lk
  => F_k = (W + I/k_b)^-1 (h_k - r_k) = Keff (h_k - r_k)   (bearing in series with the beam)
  W (simply supported Timoshenko beam, x <= a, b = L - a; swap otherwise):
      W = b x (L^2 - b^2 - x^2)/(6 L E I) + x b/(L kappa G A)
Total potential (convex, piecewise quadratic):
  Pi(q) = 1/2 sum_{k,c} (D_kc q)^T Keff (D_kc q) + 1/2 k_pin sum max(B q, 0)^2 - T theta_c
  Stationarity dPi/dq = 0 is the equilibrium of every body (virtual work).  In particular
  dPi/dtheta_c = 0  <=>  T + sum_k [A_k x sum_j F_jk + (1+z_s/z_p) sum_j (e u_j) x F_jk] = 0,
  the carrier balance with the crank torques reacted by the sun mesh.  Solved by a
  semismooth (generalized) Newton method with Armijo line search on Pi: the active pin set
  is {delta > 0} at each iterate, so the contact set is found, not assumed.
Closed form (k_b, crank -> infinitely stiff): disc j moves as d_j = (1+s) theta_c e e_z x u_j,
  th_j = theta_c, hence delta_ij = theta_c e (Zp + s) s_ij with s_ij = (u_j x n_ij)_z, and
  theta_pin = T / (k_pin e^2 (Zp + s)^2 sum_{loaded} s_ij^2);  f_ij = k_pin e (Zp+s) theta s_ij.
  Since sum_{half} s^2 -> Zp/4 and max s -> 1 for many pins (any e Zp/Rp < 1),
  F_max -> 4 T_disc/(e Zp Zc) with T_disc = e Zc sum f s the pin moment about O_j.
Run:  python benchmarks/planar_hand_model.py
"""
import json
import os
import numpy as np

KAPPA = 0.9  # Timoshenko shear coefficient of the round crank


def ez_cross(v):
    """e_z x v for planar vectors (..., 2)."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def cross_z(a, b):
    """z-component of a x b."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def beam_influence(pos, L, E, nu, d):
    """W[j, l]: deflection at pos[j] per unit force at pos[l] (Euler-Bernoulli + shear)."""
    I, A, G = np.pi * d**4 / 64, np.pi * d**2 / 4, E / (2 * (1 + nu))
    W = np.empty((len(pos), len(pos)))
    for j, x in enumerate(pos):
        for l, a in enumerate(pos):
            lo, hi = min(x, a), max(x, a)
            b = L - hi
            W[j, l] = b * lo * (L**2 - b**2 - lo**2) / (6 * L * E * I) + lo * b / (L * KAPPA * G * A)
    return W


def solve(params):
    p = params
    Zp, Zc, N = int(p['pins']), int(p['lobes']), int(p['cranks'])
    Rp, e, rp, w = p['pin_circle_radius'], p['eccentricity'], p['pin_radius'], p['face_width']
    Rc, s, T = p['crank_circle_radius'], p['sun_over_planet'], p['torque']
    kp, kb, L = p['k_pin'], p['k_bearing'], p['crank_span']
    phases = np.asarray(p['phases'], float)
    if T == 0:
        raise ValueError('torque must be non-zero (shares are undefined at zero load)')
    M, ndof = len(phases), 1 + 3 * len(phases)
    # ---- pin contacts: delta = B q -------------------------------------------------
    ang = 2 * np.pi * np.arange(Zp) / Zp
    C = Rp * np.stack([np.cos(ang), np.sin(ang)], 1)                     # (Zp, 2)
    u = np.stack([np.cos(p['phi'] + phases), np.sin(p['phi'] + phases)], 1)  # (M, 2)
    O, P = e * u, e * Zp * u
    n = C[None] - P[:, None]
    n /= np.linalg.norm(n, axis=2, keepdims=True)                         # (M, Zp, 2)
    K = C[None] - rp * n                                                  # contact points
    arm = cross_z(K - O[:, None], n)                                      # (K-O) x n
    B = np.zeros((M * Zp, ndof))
    for j in range(M):
        B[j * Zp:(j + 1) * Zp, 1 + 3 * j:4 + 3 * j] = np.column_stack([n[j, :, 0], n[j, :, 1], arm[j]])
    # ---- crank bearings + crank bending: F_kc = Keff D_kc q --------------------------
    bk = 2 * np.pi * np.arange(N) / N
    A_ax = Rc * np.stack([np.cos(bk), np.sin(bk)], 1)                    # crank axes = R_k
    apos = L / 2 + (np.arange(M) - (M - 1) / 2) * w                      # disc axial positions
    W = beam_influence(apos, L, p['youngs_modulus'], p['poisson_ratio'], p['crank_diameter'])
    Keff = np.linalg.inv(W + np.eye(M) / kb)
    v = ez_cross(A_ax)[:, None, :] + (1 + s) * ez_cross(e * u)[None, :, :]  # (N, M, 2)
    D = np.zeros((N, 2, M, ndof))
    for k in range(N):
        for j in range(M):
            D[k, :, j, 0] = -v[k, j]                                      # - rigid journal
            D[k, :, j, 1 + 3 * j:3 + 3 * j] = np.eye(2)                  # + disc translation
            D[k, :, j, 3 + 3 * j] = ez_cross(A_ax[k])                     # + th_j e_z x R_k
    Kb = sum(D[k, c].T @ Keff @ D[k, c] for k in range(N) for c in range(2))
    F = np.zeros(ndof)
    F[0] = T

    # ---- complementarity: generalized Newton on the convex potential -----------------
    def pi(q):
        dl = np.maximum(B @ q, 0)
        return 0.5 * q @ Kb @ q + 0.5 * kp * dl @ dl - F @ q

    def grad(q):
        return Kb @ q + kp * B.T @ np.maximum(B @ q, 0) - F

    act = (np.sign(T) * cross_z(u[:, None], n) > 0).ravel()             # initial guess only
    q = np.linalg.solve(Kb + kp * B[act].T @ B[act], F)
    for it in range(200):  # noqa: B007 (its count is read after the loop)
        g = grad(q)
        act = B @ q > 0
        H = Kb + kp * B[act].T @ B[act]
        dq = np.linalg.lstsq(H, -g, rcond=None)[0]
        t, p0 = 1.0, pi(q)
        while pi(q + t * dq) > p0 + 1e-4 * t * (g @ dq) and t > 1e-12:
            t *= 0.5
        q = q + t * dq
        if t == 1.0 and np.array_equal(B @ q > 0, act):
            break
    delta = B @ q
    f = (kp * np.maximum(delta, 0)).reshape(M, Zp)
    # ---- results --------------------------------------------------------------------
    Fb = np.stack([np.stack([Keff @ (D[k, c] @ q) for c in range(2)], 1) for k in range(N)], 1)  # (M,N,2) on crank
    Mj = np.sum(cross_z(K, -f[..., None] * n), axis=1)                   # pin moment about housing centre
    Tdisc = np.sum(cross_z(K - O[:, None], -f[..., None] * n), axis=1)   # about O_j
    fmax = f.max(1)
    ncont = (f > 1e-9 * f.max()).sum(1)
    # ---- verification residuals -----------------------------------------------------
    fscale = np.abs(f).sum() + np.abs(Fb).sum()
    res = {}
    res['newton_iterations'] = it + 1
    res['gradient'] = float(np.linalg.norm(grad(q)) / (abs(T) + fscale * Rp))
    fd = np.sum(-f[..., None] * n, 1) - Fb.sum(1)                       # disc force balance
    md = Tdisc - np.sum(cross_z(A_ax[None], Fb), 1)                     # disc moment about O_j
    res['disc_force'] = float(np.abs(fd).max() / (np.abs(f).sum(1).max()))
    res['disc_moment'] = float(np.abs(md).max() / abs(T))
    rpl, rs = Rc / (1 + s), Rc * s / (1 + s)                             # planet/sun pitch radii
    tau = np.sum(cross_z(e * u[:, None], Fb), 0)                         # crank torque from discs
    g_mesh = tau / rpl                                                   # tangential sun-mesh force
    res['carrier_moment'] = float(abs(T + np.sum(cross_z(A_ax, Fb.sum(0))) + Rc * g_mesh.sum()) / abs(T))
    res['global_moment'] = float(abs(T + rs * g_mesh.sum() + Mj.sum()) / abs(T))
    # independent check: a rigid mechanism motion (sun d_in, carrier d_in/i, i = 1 + Zp/s) leaves
    # every spring undeformed, so by virtual work the sun holding torque must be -T/i exactly
    res['sun_torque_ratio'] = float(abs(rs * g_mesh.sum() + T / (1 + Zp / s)) / abs(T))
    comp = 0.0
    for k in range(N):                                                   # bearing/beam compatibility
        for c in range(2):
            h = D[k, c] @ q + q[0] * v[k, :, c]                          # absolute hole motion
            qj = q[0] * v[k, :, c] + W @ Fb[:, k, c]                     # journal: rigid + bending
            comp = max(comp, np.abs(Fb[:, k, c] - kb * (h - qj)).max() / np.abs(Fb).max())
    res['crank_compatibility'] = float(comp)
    # ---- closed-form rigid crank/bearing (pin springs only, zero clearance) ---------
    sij = cross_z(u[:, None], n)
    loaded = np.sign(T) * sij > 0
    th_pin = T / (kp * e**2 * (Zp + s)**2 * np.sum(sij[loaded]**2))
    smax = np.where(loaded, np.abs(sij), 0).max(1)
    fmax_pin = kp * e * (Zp + s) * abs(th_pin) * smax
    ratio_pin = smax * Zp / (4 * np.where(loaded, sij**2, 0).sum(1))   # F_max/(4 T_disc/(e Zp Zc)), f ~ s
    return dict(twist_rad=float(q[0]), shares=(Mj / Mj.sum()).tolist(), f_max=fmax.tolist(),
                pins_in_contact=ncont.tolist(), bearing_forces=Fb.tolist(),
                twist_pin_only_rad=th_pin, f_max_pin_only=fmax_pin.tolist(),
                t_disc=np.abs(Tdisc).tolist(), f_max_classical=(4 * np.abs(Tdisc) / (e * Zp * Zc)).tolist(),
                sun_hold_torque=float(rs * g_mesh.sum()), residuals=res,
                classical_ratio_pin_only=ratio_pin.tolist(), loaded_pins_against_flank=((f > 0) & (np.sign(T) * sij <= 0)).sum(1).tolist())


def base(M=3, Zp=41, N=3, phases_deg=(0, 120, 240), T=167.0):
    w = 0.01
    return dict(pins=Zp, lobes=Zp - 1, pin_circle_radius=0.1, eccentricity=0.001, pin_radius=0.002,
                face_width=w, cranks=N, crank_circle_radius=0.027, sun_over_planet=9 / 27,
                youngs_modulus=208e9, poisson_ratio=0.295,
                crank_diameter=0.01395,   # = 2*(0.011-0.275*0.011) - 2*0.001, as stated
                crank_span=(M + 2) * w, k_pin=1.0e9, k_bearing=5.0e8, torque=T, phi=0.0,
                phases=tuple(np.radians(phases_deg)))


def row(name, r):
    sh = ' '.join(f'{x:.4f}' for x in r['shares'])
    fm = ' '.join(f'{x:7.1f}' for x in r['f_max'])
    nc = ' '.join(str(x) for x in r['pins_in_contact'])
    print(f'{name:<26} {r["twist_rad"]*1e6:9.3f} {r["twist_pin_only_rad"]*1e6:9.3f}  [{sh}]  [{fm}]  [{nc}]'
          f'  maxres {max(v for k, v in r["residuals"].items() if k != "newton_iterations"):.1e}')


def main():
    out = {'cases': {}, 'notes': 'twist in rad; forces in N; bearing_forces[disc][crank] = force the crank '
           'receives from the disc (disc receives the opposite); twist_pin_only_rad = rigid crank/bearing, '
           'zero clearance, pin springs only (closed form); crank holes at nominal angles 2 pi k/N.'}
    print(f'{"case":<26} {"theta_c urad":>9} {"pin-only":>9}  shares  F_max [N]  pins in contact')
    cases = {}
    for lab, ph in [('A in phase 0/0/0', (0, 0, 0)), ('A 0/120/240', (0, 120, 240)), ('A 0/180/0', (0, 180, 0))]:
        for T in (167.0, -167.0):
            cases[f'{lab} T={T:+.0f}'] = base(phases_deg=ph, T=T)
    for T in (167.0, -167.0):
        cases[f'B 2 discs 0/180 T={T:+.0f}'] = base(M=2, Zp=40, N=2, phases_deg=(0, 180), T=T)
    for name, prm in cases.items():
        r = solve(prm)
        row(name, r)
        if name.endswith('+167'):
            print('    |bearing force| [N] per disc (cranks 0..N-1):',
                  np.round(np.linalg.norm(r['bearing_forces'], axis=2), 1).tolist(),
                  ' loaded pins on the unloaded flank:', r['loaded_pins_against_flank'])
        out['cases'][name] = dict(params={k: (list(v) if isinstance(v, tuple) else v) for k, v in prm.items()}, **r)
    print('\nmiddle-disc share, case A:', {k: round(out['cases'][k]['shares'][1], 5)
                                          for k in out['cases'] if k.startswith('A')})
    rb = out['cases']['B 2 discs 0/180 T=+167']
    print(f'case B split: {rb["shares"][0]:.15f} / {rb["shares"][1]:.15f}  '
          f'(|diff| = {abs(rb["shares"][0] - rb["shares"][1]):.1e})')
    # ---- C: stiffness sweep (A, 0/120/240) ---------------------------------------------
    print('\nC) middle-disc share, A 0/120/240, T=+167: rows k_pin scale, columns k_b scale (0.25, 1, 4)')
    sweep = []
    for sp in (0.25, 1, 4):
        line = []
        for sb in (0.25, 1, 4):
            prm = base()
            prm['k_pin'] *= sp
            prm['k_bearing'] *= sb
            r = solve(prm)
            line.append(r['shares'][1])
            sweep.append(dict(k_pin_scale=sp, k_b_scale=sb, shares=r['shares'], twist_rad=r['twist_rad']))
        print(f'  k_pin x{sp:<5}' + ''.join(f'  {x:.5f}' for x in line))
    out['sweep_C'] = sweep
    # ---- rigid limit: k_b and crank stiffness -> infinity -----------------------------------
    print('\nRigid limit (k_b and E scaled by lam), A 0/120/240, T=+167:')
    print(f'  {"lam":>7} {"theta_c/theta_pin-1":>20} {"max|Fmax/Fmax_pin-1|":>21}')
    rig = []
    for lam in (1, 1e2, 1e4, 1e6):
        prm = base()
        prm['k_bearing'] *= lam
        prm['youngs_modulus'] *= lam
        r = solve(prm)
        e1 = r['twist_rad'] / r['twist_pin_only_rad'] - 1
        e2 = max(abs(a / b - 1) for a, b in zip(r['f_max'], r['f_max_pin_only']))
        print(f'  {lam:7.0e} {e1:20.3e} {e2:21.3e}')
        rig.append(dict(lam=lam, twist_rel_err=e1, fmax_rel_err=e2))
    out['rigid_limit'] = rig
    print('\nMany-pin limit (e Zp/Rp = 0.41 fixed): F_max / (4 T_disc/(e Zp Zc)) per disc;'
          ' solver at lam=1e8 | exact rigid closed form max(s) Zp / (4 sum s^2)')
    mp = []
    for Zp in (41, 161, 641, 2561):
        prm = base(Zp=Zp)
        prm['eccentricity'] = 0.041 / Zp
        prm['k_bearing'] *= 1e8
        prm['youngs_modulus'] *= 1e8
        r = solve(prm)
        ratio = [a / b for a, b in zip(r['f_max'], r['f_max_classical'])]
        exact = r['classical_ratio_pin_only']
        print(f'  Zp={Zp:5d}: ' + '  '.join(f'{x:.6f}' for x in ratio) + '  | ' + '  '.join(f'{x:.6f}' for x in exact))
        mp.append(dict(pins=Zp, ratio_solver=ratio, ratio_closed_form=exact))
    out['many_pin_limit'] = mp
    allres = {k: max(c['residuals'][k] for c in out['cases'].values())
              for k in next(iter(out['cases'].values()))['residuals'] if k != 'newton_iterations'}
    print('\nWorst verification residuals over all cases (relative):', allres)
    out['worst_residuals'] = allres
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results', 'planar_hand_model.json')
    with open(path, 'w') as fh:
        json.dump(out, fh, indent=1)
    print('wrote', path)


if __name__ == '__main__':
    main()
