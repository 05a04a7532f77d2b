"""What the TE loop's pin ring effects need (``Effects(pin_ring_m=...)``, the drive's
``pin_ring_offsets``): the TE of the pins' centres moved in one order round the ring, at
the rows the loop fits (the drive's named orders and their doubles, forward and backward,
and the hysteresis width), measured on a case at 50 and 100 % of its rated torque.

For each pattern (order 1 tangential: the cumulative pitch error; order 2 radial: the
ovality; order 2 tangential and order 1 radial for comparison; the ring's centre moved),
5 um, this prints:

1. the rows' change from the drawn design's and what one TE call costs (two torques, both
   directions) at the default sampling (``RecordingModel.default_samples``, 4 (2 Zb + h)
   + 1 pitches);
2. convergence: the largest relative difference of those rows against the whole
   revolution's (every pitch solved) at each sample count;
3. orientation: the pattern turned by 0.37 rad round the ring (rows' largest change, arcsec);
4. linearity: the rows' change at 2.5 um over that at 5 um (0.5 where linear).

Nothing is written but this table. Run: .venv/bin/python benchmarks/pin_ring_response.py
[--case cases/rv40e.toml] [--quick] (the full run, RV-40E: about 4 minutes on 2 cores;
--quick skips the whole-revolution reference and the convergence: about a minute).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem import load_case  # noqa: E402
from toothfem.efficiency.loop.te.loop import fitted_orders  # noqa: E402
from toothfem.efficiency.loop.te.model import Effects, RecordingModel  # noqa: E402
from toothfem.efficiency.loop.te.observations import ORDER_MULTIPLES  # noqa: E402
from toothfem.geometry.cycloid_mesh import pin_centres  # noqa: E402

AMPLITUDE_UM = 5.0
TURN_RAD = 0.37
#: Sample counts tried against the whole revolution (the default added).
SAMPLES = (81, 161, 241)
#: Rows whose reference is below this [arcsec] count as zero in relative differences.
TINY_ARCSEC = 0.01


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default=str(ROOT / "cases" / "rv40e.toml"))
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    model = RecordingModel(load_case(args.case))
    drive = model.drive
    c = pin_centres(drive.geometry)
    theta = np.arctan2(c[1], c[0])
    outward = c / np.linalg.norm(c, axis=0)
    along = np.stack([-outward[1], outward[0]])
    zb = c.shape[1]
    torques = (0.5 * model.rated_torque_Nm, model.rated_torque_Nm)
    orders = sorted({q * k for q in fitted_orders(model.te_orders()).values()
                     for k in ORDER_MULTIPLES})

    def rows(effects, samples=None):
        out = []
        for x in model.te(effects, torques, samples=samples):
            for d in (1, -1):
                out += [x.amplitude_arcsec(q, d) for q in orders]
            out.append(x.width_arcsec)
        return np.array(out)

    def pattern(kind, order, um, turn=0.0):
        e = outward if kind == "radial" else along
        return Effects(pin_offset_m=e * um * 1e-6 * np.cos(order * (theta - turn)))

    base = rows(Effects())
    labels = [f"{'fwd' if d > 0 else 'bwd'} {q:g}" for d in (1, -1) for q in orders] + ["width"]
    print(f"{model.case.name}: Zb = {zb}, torques {torques[0]:.0f} and {torques[1]:.0f} N m, "
          f"rows at orders {', '.join(f'{q:g}' for q in orders)} and the width")
    print(f"drawn design, {torques[1]:.0f} N m: "
          + ", ".join(f"{lab} {v:.3f}" for lab, v in
                      zip(labels, base[len(base) // 2:])) + " arcsec")
    cases = [("tangential", 1, "cumulative pitch error"), ("radial", 2, "ovality"),
             ("tangential", 2, "order 2 tangential"), ("radial", 1, "order 1 radial")]
    for kind, order, what in cases:
        key = f"{kind}_{order}"
        t0 = time.perf_counter()
        at = rows(Effects(pin_ring_m={key: AMPLITUDE_UM * 1e-6}))
        cost = time.perf_counter() - t0
        n = model.default_samples(Effects(pin_ring_m={key: 1e-6}), drive.full_period_pitches
                                  * zb)
        change = at - base
        big = np.argsort(-np.abs(change))[:4]
        print(f"\n== {what} ({key}), {AMPLITUDE_UM:g} um: {n} sampled pitches, "
              f"{cost:.1f} s a call (two torques)")
        print("   largest changes: " + ", ".join(
            f"{labels[i % len(labels)]} @{torques[i // len(labels)]:.0f} N m {change[i]:+.3f}"
            for i in big) + " arcsec")
        turned = rows(pattern(kind, order, AMPLITUDE_UM, TURN_RAD), samples=n)
        print(f"   turned {TURN_RAD} rad round the ring: rows move by at most "
              f"{np.max(np.abs(turned - at)):.4f} arcsec")
        half = rows(Effects(pin_ring_m={key: 0.5 * AMPLITUDE_UM * 1e-6})) - base
        i = big[0]
        print(f"   at {0.5 * AMPLITUDE_UM:g} um the largest change is {half[i] / change[i]:.3f}"
              " of it (0.5 where linear)")
        if args.quick:
            continue
        t0 = time.perf_counter()
        whole = rows(Effects(pin_ring_m={key: AMPLITUDE_UM * 1e-6}),
                     samples=drive.full_period_pitches * zb)
        dt = time.perf_counter() - t0
        ok = np.abs(whole) > TINY_ARCSEC
        for s in (*SAMPLES, n):
            x = at if s == n else rows(Effects(pin_ring_m={key: AMPLITUDE_UM * 1e-6}),
                                       samples=s)
            rel = np.max(np.abs(x[ok] - whole[ok]) / np.abs(whole[ok]))
            print(f"   {s:5d} sampled pitches: rows within {100 * rel:.2f} % of the whole "
                  f"revolution's ({drive.full_period_pitches * zb} pitches, {dt:.1f} s)")
    shift = Effects(pin_offset_m=np.tile(AMPLITUDE_UM * 1e-6 * np.array([[1.0], [0.0]]),
                                         (1, zb)))
    moved = rows(shift, samples=model.default_samples(Effects(pin_ring_m={"radial_1": 1e-6}),
                                                      drive.full_period_pitches * zb))
    print(f"\n== the ring's centre moved {AMPLITUDE_UM:g} um: rows move by at most "
          f"{np.max(np.abs(moved - base)):.4f} arcsec")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
