"""Hand checks of the main-bearing tilt model (toothfem.fem.datasheet.tilt, .ball_pair,
.hertz_point), as a table:
the Hertz constant against closed forms, a single row under axial and radial load against
the textbook load shares, the pair under a moment against its torque balance and the
analytic linear stiffness, the mirror symmetry, and an RV-40E-like pair beside the
catalogue (tests/test_tilt.py asserts the same checks).

Run: .venv/bin/python benchmarks/tilt_hand_check.py
"""
import math

import numpy as np

from toothfem.fem.datasheet import ball_pair as B, hertz_point as H, tilt as T
from toothfem.fem.hertz import reduced_modulus

#: The RV-40E-like pair of the comparison (not Nabtesco's data: the catalogue gives no
#: bearing geometry): 2 x 40 balls of 9 mm on 150 mm, 40 deg, ball planes 55 mm apart,
#: 3 kN preload.
RV40E_LIKE = dict(balls_per_row=40, ball_diameter_m=9e-3, pitch_diameter_m=150e-3,
                  contact_angle_rad=math.radians(40), row_span_m=55e-3, preload_N=3000.0)
#: Nabtesco RV-E catalogue, RV-40E: moment rigidity (reference value) [N m/arcmin] and
#: allowable moment [N m], as the task brief quotes them; not confirmed from a stored copy
#: of the catalogue (the search found the catalogue's pages but not its rating table).
RV40E_MOMENT_RIGIDITY = 931.0
RV40E_ALLOWABLE_MOMENT = 1666.0


def arms(pair, res):
    """Normal and tangential moment arms of every ball at its loaded contact angle."""
    z = pair.balls_per_row
    s = np.repeat([1.0, -1.0], z).reshape(2, z)
    zc = np.repeat(pair.inner_centre_z_m, z).reshape(2, z)
    c = np.cos(pair.azimuths_rad)[None, :]
    a = res.contact_angle_rad
    rc = pair.inner_centre_radius_m
    return ((np.cos(a) * zc - s * np.sin(a) * rc) * c,
            (-np.sin(a) * zc - s * np.cos(a) * rc) * c)


def rows():
    out = []
    e = 208e9
    es = float(reduced_modulus(e, 0.3, e, 0.3))
    d, q = 9e-3, 500.0
    # 1. Hertz
    flat = H.hertz_point_contact(q, d / 2, d / 2, es)
    hertz = (9 * q * q / (16 * es * es * d / 2)) ** (1 / 3)
    out.append(("1a ball on flat, exact vs Hertz circular (Johnson 4.2)", flat.approach_m * 1e6,
                hertz * 1e6, "um"))
    palm = 4.36e-4 * q ** (2 / 3) * (d * 1e3) ** (-1 / 3) * 1e-3
    out.append(("1b ball on flat vs Palmgren 4.36e-4 Q^2/3 D^-1/3", flat.approach_m * 1e6,
                palm * 1e6, "um"))
    harris = 2.79e-4 * (4 / (d * 1e3)) ** (1 / 3) * q ** (2 / 3) * 1e-3
    out.append(("1c ball on flat vs Harris 2.79e-4 Q^2/3 (sum rho)^1/3", flat.approach_m * 1e6,
                harris * 1e6, "um"))
    pair = B.BallPair(**RV40E_LIKE)
    hb = B.BallPair(**RV40E_LIKE, hertz_method="hamrock_brewe")
    rc, rch = B.raceway_contact(pair), B.raceway_contact(hb)
    out.append(("1d K of ball (both contacts), Hamrock-Brewe vs exact", rch.K, rc.K, "N/m^1.5"))
    out.append(("1e p/Q^(1/3) inner, Hamrock-Brewe vs exact", rch.pressure_coeff_inner / 1e6,
                rc.pressure_coeff_inner / 1e6, "MPa N^-1/3"))
    both = (rc.approach_coeff_inner + rc.approach_coeff_outer) * q ** (2 / 3)
    out.append(("1f ball between raceways (order) vs Palmgren", both * 1e6, palm * 1e6, "um"))
    # 2. single row, axial
    fa = 5000.0
    r = T.solve_row(pair, 0.0, fa)
    out.append(("2 axial, every ball: Q vs F_a/(Z sin alpha)", r.ball_load_N.max(),
                fa / (pair.balls_per_row * math.sin(r.contact_angle_rad[0, 0])), "N"))
    # 3. single row, radial, zero clearance
    for z in (9, 40):
        p0 = B.BallPair(z, d, 65e-3 if z == 9 else 150e-3, 0.0, 0.0, 0.0)
        fr = 2000.0
        r = T.solve_row(p0, fr, 0.0)
        c = np.cos(p0.azimuths_rad)
        exact = z / np.sum(np.clip(c, 0, None) ** 2.5)
        out.append((f"3 radial, Z = {z}: Q_max Z/F_r vs discrete Z/sum cos^2.5",
                    r.max_ball_load_N * z / fr, exact, "-"))
        out.append((f"3 radial, Z = {z}: Q_max Z/F_r vs Stribeck 4.37",
                    r.max_ball_load_N * z / fr, T.STRIBECK_POINT, "-"))
    # 4. pair, moment
    m = 1666.0
    r = T.solve(pair, 0.0, 0.0, m)
    an, _ = arms(pair, r)
    out.append(("4 torque balance sum Q arm vs M", float(np.sum(r.ball_load_N * an)), m, "N m"))
    r0 = T.solve(pair, 0.0, 0.0, 0.0)
    an0, at0 = arms(pair, r0)
    kn = 1.5 * rc.K * np.sqrt(r0.approach_m)
    geo = r0.ball_load_N / (pair.groove_centre_distance_m + r0.approach_m)
    k_sum = float(np.sum(kn * an0 ** 2 + geo * at0 ** 2))
    small = 1.0
    sec = small / T.solve(pair, 0.0, 0.0, small).tilt_rad
    out.append(("4 secant at 1 N m vs sum k arm^2 (+ Q/L arm_t^2)", sec, k_sum, "N m/rad"))
    out.append(("4 share of the contact lines' turning Q/L arm_t^2",
                float(np.sum(geo * at0 ** 2)) / k_sum * 100, 0.0, "%"))
    # 5. mirror
    rp, rm = T.solve(pair, 1000.0, 0.0, m), T.solve(pair, 1000.0, 0.0, -m)
    out.append(("5 +M/-M: tilt(+M) + tilt(-M)", (rp.tilt_rad + rm.tilt_rad) / ARC, 0.0,
                "arcmin"))
    out.append(("5 +M/-M: max |Q(+M)[row] - Q(-M)[other row]|",
                float(np.max(np.abs(rp.ball_load_N - rm.ball_load_N[::-1]))), 0.0, "N"))
    return out


ARC = T.ARCMIN


def rv40e_like():
    pair = B.BallPair(**RV40E_LIKE)
    lines = []
    for m in (0.0, 400.0, RV40E_ALLOWABLE_MOMENT):
        r = T.solve(pair, 0.0, 0.0, m)
        sec = T.moment_rigidity_Nm_per_arcmin(pair, m)
        lines.append(f"| {m:.0f} | {sec:.0f} | "
                     f"{r.tangent_moment_rigidity_Nm_per_rad * ARC:.0f} | "
                     f"{r.tilt_arcmin:.3f} | {r.max_ball_load_N:.0f} | "
                     f"{r.max_pressure_Pa / 1e6:.0f} | {r.balls_in_contact} |")
    m_iso = T.moment_at_pressure(pair, T.ISO76_BALL_PRESSURE_PA)
    return lines, m_iso, pair


if __name__ == "__main__":
    print("| check | model | reference | unit | deviation |")
    print("|---|---|---|---|---|")
    for name, got, ref, unit in rows():
        dev = f"{(got / ref - 1) * 100:+.3g} %" if ref else f"{got:.3g}"
        print(f"| {name} | {got:.6g} | {ref:.6g} | {unit} | {dev} |")
    lines, m_iso, pair = rv40e_like()
    print()
    print(f"RV-40E-like pair: {RV40E_LIKE}; pressure-cone apexes "
          f"{pair.pressure_centre_spread_m * 1e3:.0f} mm apart")
    print("| M [N m] | secant [N m/arcmin] | tangent [N m/arcmin] | tilt [arcmin] | "
          "Q_max [N] | p_max [MPa] | balls in contact |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(lines))
    print(f"moment at ISO 76's 4200 MPa: {m_iso:.0f} N m; catalogue (brief): moment rigidity "
          f"{RV40E_MOMENT_RIGIDITY:.0f} N m/arcmin, allowable moment "
          f"{RV40E_ALLOWABLE_MOMENT:.0f} N m")
