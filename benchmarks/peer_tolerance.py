"""cycloidgen's tolerance ensemble beside toothfem's tolerance Monte Carlo on the pin-housing
drive, with the same pin true-position zone (issue 12, item 6; docs/tolerance_peer.md).

cycloidgen (PyPI, rigid disc on Hertz line-contact springs) draws whole rings: every pin
moved uniformly inside its true-position zone (a disc of the zone's diameter), and solves
its load sharing on each. This script draws N such rings with cycloidgen's own draw
(seeded), solves each with cycloidgen's own ring-stage functions over its crank sweep and
reports P50/P90/P99 of each output that model has; then, if ``toothfem.tolerance`` is
importable, the same percentiles from ``tolerance_analysis`` on the case, side by side.

The peer is never a dependency of toothfem: it lives in its own environment,

    python3 -m venv benchmarks/.venv-peer && benchmarks/.venv-peer/bin/pip install cycloidgen

and its half runs there (``--peer-python``), results returned as JSON. Run from the
project's venv:

    .venv/bin/python benchmarks/peer_tolerance.py [--samples 200] [--seed 20260805]
        [--zone 0.010] [--positions 36] [--out FILE.json]
"""
import argparse
import dataclasses
import json
import subprocess
from pathlib import Path

import numpy as np

from peer_cycloidgen import PEER_PYTHON, pinhousing_case

#: The outputs compared, toothfem's ``tolerance_analysis(...).samples`` keys.
OUTPUTS = ("max_force_N", "max_ph_MPa", "contacts_min", "lost_motion_arcmin",
           "te_pp_arcsec", "mesh_efficiency_pct", "total_efficiency_pct")
#: Outputs only the peer reports (per ring), printed below the table.
PEER_ONLY = ("pins_engaged_mean", "load_concentration", "mesh_rigidity_Nm_per_arcmin",
             "interference_um")
PERCENTILES = (50.0, 90.0, 99.0)
#: Relative agreement of the per-ring medians with cycloidgen's public analyse_stiffness:
#: the same functions on the same draw, so only rounding may differ.
CHECK_RTOL = 1e-9
#: cycloidgen's own ``tolerance.POSITION_SEED``: with it, the peer's rings are its own draw.
DEFAULT_SEED = 20260805
#: toothfem's [tolerances] key of the pin true-position zone (diameter, mm).
PIN_POSITION_KEY = "pin_position_mm"
#: Unit endings of the deviation keys zeroed so that only the pin position is sampled.
DEVIATION_UNITS = ("_mm", "_um", "_deg", "_arcmin")

#: The peer's half, run by its own interpreter. Its GearSpec of the pin-housing drive is that
#: of peer_cycloidgen.py (40 pins on R 100 mm, rz 2 mm, e 1 mm, 39 lobes, two 10 mm discs,
#: ground steel, equidistant clearance) with ``position_tolerance`` = the zone's diameter.
#: Per ring it repeats the ring-stage loop of cycloidgen.analysis.stiffness._one_ring
#: (its _ring_contacts and _solve_rotation, the same reductions) and keeps, besides those
#: reductions, the extremes over the sweep (peak pin force, its Hertz pressure with
#: cycloidgen.analysis.mechanics' formula, fewest pins loaded); the per-ring medians are
#: checked against the public analyse_stiffness on the same draw. TE: its _te_of_one_ring
#: per ring (ring stage only; the output-pin stage has no counterpart in an RV drive).
PEER_CODE = r"""
import json, sys
import numpy as np
import cycloidgen
from cycloidgen.core.spec import GearSpec, OffsetMode, Process
from cycloidgen.core.kinematics import SWEEP_STEPS, sweep
from cycloidgen.analysis import stiffness as st, tolerance as tol
from cycloidgen.analysis.mechanics import _R_eq_ring, effective_modulus, hertz_line_pressure

args = json.loads(sys.argv[1])
ARCMIN = st.RAD_PER_ARCMIN
OWN_SEED = tol.POSITION_SEED


def spec_for(clearance, zone):
    return GearSpec(pin_circle_radius=100.0, pin_radius=2.0, eccentricity=1.0, lobes=39,
                    disc_thickness=10.0, disc_count=2, process=Process.EDM,
                    offset_mode=OffsetMode.EQUIDISTANT, profile_clearance=clearance,
                    position_tolerance=zone, disc_material="Steel 4140 (hardened)",
                    pin_material="Steel 4140 (hardened)", ring_pins_integral=True,
                    output_torque_Nm=args["torque"])


def one_ring(spec, picked, tpd, error):
    e_star = effective_modulus(spec.disc_mat.E_GPa, spec.disc_mat.nu,
                               spec.pin_mat.E_GPa, spec.pin_mat.nu)
    close, engaged, conc, bites, ks = [], [], [], [], []
    fmax = pmax = 0.0
    cmin = spec.pin_count
    for cs in picked:
        stage = st._ring_contacts(spec, cs, tpd, error)
        if stage is None:
            continue
        bites.append(stage.interference)
        close.append(float((stage.gaps / np.maximum(stage.arms, 1e-9)).min()))
        theta, f = st._solve_rotation(stage.c, stage.arms, stage.gaps, tpd)
        k = st._stage_stiffness(stage.c, stage.arms, f, theta, stage.gaps)
        if k > 0:
            ks.append(k)
        engaged.append(int((f > 0).sum()))
        if stage.ideal.max() > 0:
            conc.append(float(f.max() / stage.ideal.max()))
        p = hertz_line_pressure(f, spec.contact_length,
                                _R_eq_ring(spec, cs.t[cs.loaded_mask]), e_star)
        fmax, pmax = max(fmax, float(f.max())), max(pmax, float(p.max()))
        cmin = min(cmin, int((f > 0).sum()))
    return {"max_force_N": fmax, "max_ph_MPa": pmax, "contacts_min": float(cmin),
            "lost_motion_arcmin": 2.0 * max(close) / ARCMIN,
            "pins_engaged_mean": float(np.mean(engaged)),
            "load_concentration": float(np.mean(conc)),
            "mesh_rigidity_Nm_per_arcmin": spec.disc_count * float(np.mean(ks)) / 1000.0
            * ARCMIN, "interference_um": 1e3 * max(bites)}


def te_arcsec(spec, period, ring_error, carrier_error):
    ring_pp = st._te_of_one_ring(spec, st._TE_STEPS, st._TE_RING_STEPS, period,
                                 ring_error, carrier_error)[0]
    return 60.0 * ring_pp


def ensemble(clearance):
    n, steps = args["samples"], args["steps"]
    spec = spec_for(clearance, args["zone"])
    tpd = spec.output_torque_Nm * 1000.0 / spec.disc_count
    states = sweep(spec, SWEEP_STEPS)
    picked = states[:: max(1, len(states) // steps)]
    period = st.output_stage_period(spec)
    tol.POSITION_SEED = args["seed"]
    ring_err = tol.ring_position_errors(spec, n)
    carrier_err = tol.carrier_position_errors(spec, n)
    rings = []
    for i in range(n):
        r = one_ring(spec, picked, tpd, ring_err[i])
        r["te_pp_arcsec"] = te_arcsec(spec, period, ring_err[i], carrier_err[i])
        rings.append(r)
    samples = {k: [r[k] for r in rings] for k in rings[0]}
    nominal = one_ring(spec, picked, tpd, None)
    nominal["te_pp_arcsec"] = te_arcsec(spec, period, None, None)
    public = st.analyse_stiffness(spec, steps=steps, samples=n)    # the same draw
    check = {"lost_motion_ring_arcmin": (public.lost_motion_ring_arcmin,
                                         float(np.median(samples["lost_motion_arcmin"]))),
             "pins_engaged": (public.pins_engaged,
                              float(np.median(samples["pins_engaged_mean"]))),
             "load_concentration": (public.load_concentration,
                                    float(np.median(samples["load_concentration"]))),
             "position_interference_um": (1e3 * public.position_interference_mm,
                                          max(samples["interference_um"]))}
    tol.POSITION_SEED = OWN_SEED
    own = spec_for(clearance, args["zone"])
    s, te = st.analyse_stiffness(own), st.analyse_transmission_error(own)
    as_shipped = {"rings_sampled": s.rings_sampled, "te_rings_sampled": te.rings_sampled,
                  "lost_motion_ring_arcmin": s.lost_motion_ring_arcmin,
                  "lost_motion_ring_p90_arcmin": s.lost_motion_p90_arcmin
                  - s.lost_motion_output_arcmin,
                  "pins_engaged": s.pins_engaged, "load_concentration": s.load_concentration,
                  "load_concentration_p90": s.load_concentration_p90,
                  "ring_stage_Nm_per_arcmin": s.ring_stage_Nm_per_arcmin,
                  "position_interference_um": 1e3 * s.position_interference_mm,
                  "te_ring_arcsec": 60.0 * te.ring_arcmin,
                  "te_worst_ring_total_arcsec": 60.0 * te.worst_ring_arcmin}
    return {"samples": samples, "nominal": nominal, "public_check": check,
            "as_shipped": as_shipped}


out = {str(c): ensemble(c) for c in args["clearances"]}
out["version"] = cycloidgen.__version__
out["steps"] = args["steps"]
print(json.dumps(out))
"""


def peer(python, torque, zone, clearances, samples, seed, steps):
    """The peer's half: its ensemble per clearance, as parsed JSON (see PEER_CODE)."""
    args = {"torque": torque, "zone": zone, "clearances": list(clearances),
            "samples": samples, "seed": seed, "steps": steps}
    res = subprocess.run([str(python), "-c", PEER_CODE, json.dumps(args)],
                         check=True, capture_output=True, text=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def percentiles(values):
    """P50, P90, P99 of one output's samples (numpy's linear interpolation)."""
    return [float(p) for p in np.percentile(np.asarray(values, dtype=float), PERCENTILES)]


def pin_position_only(case, zone, extra):
    """toothfem's ``overrides``: the pin true-position zone, every other deviation of the
    case's [tolerances] section (float keys with a unit ending) set to zero so that only
    the pin position is sampled, as in the peer; ``extra`` (from --override) last."""
    over = {PIN_POSITION_KEY: zone, "distribution": "uniform"}     # as the peer draws
    tol = getattr(case, "tolerances", None)
    if dataclasses.is_dataclass(tol):
        for f in dataclasses.fields(tol):
            value = getattr(tol, f.name)
            if f.name != PIN_POSITION_KEY and isinstance(value, float) \
                    and f.name.endswith(DEVIATION_UNITS):
                over[f.name] = 0.0
    over.update(extra)
    return over


def ours(case, modifications, samples, seed, positions, overrides):
    """toothfem's half, or a note saying why not: ``{modification: {output: samples}}``."""
    try:
        from toothfem.tolerance import tolerance_analysis
    except ImportError as exc:
        return None, f"toothfem.tolerance not available ({exc})"
    out = {}
    for mod in modifications:
        moved = dataclasses.replace(case, cycloid=dataclasses.replace(
            case.cycloid, equidistant_modification_mm=mod))
        res = tolerance_analysis(moved, samples=samples, seed=seed, positions=positions,
                                 workers=1, overrides=overrides)
        out[str(mod)] = {k: np.asarray(res.samples[k], dtype=float).tolist() for k in OUTPUTS
                         if k in res.samples}
    return out, "toothfem.tolerance.tolerance_analysis"


def cell(values):
    if values is None:
        return "n/a"
    return " / ".join(f"{v:.4g}" for v in percentiles(values))


def report(theirs, mine, modifications, header):
    print(header)
    for mod in modifications:
        t = theirs[str(mod)]
        m = (mine or {}).get(str(mod), {})
        print(f"\nequidistant modification {1e3 * mod:g} um   (P50 / P90 / P99)")
        print(f"  {'output':24s} {'cycloidgen':>30s} {'toothfem':>30s} {'peer nominal':>13s}")
        for k in OUTPUTS:
            mine_cell = cell(m.get(k)) if mine is not None else "not available"
            theirs_cell = cell(t["samples"].get(k)) if k in t["samples"] else "not modelled"
            nominal = f"{t['nominal'][k]:.4g}" if k in t["nominal"] else "-"
            print(f"  {k:24s} {theirs_cell:>30s} {mine_cell:>30s} {nominal:>13s}")
        for k in PEER_ONLY:
            print(f"  {k:24s} {cell(t['samples'][k]):>30s} {'(peer only)':>30s} "
                  f"{t['nominal'][k]:13.4g}")
        pairs = t["public_check"].items()
        agree = all(np.isclose(a, b, rtol=CHECK_RTOL, atol=0.0) for _k, (a, b) in pairs)
        print(f"  per-ring medians {'agree with' if agree else 'DIFFER FROM'} cycloidgen's "
              "analyse_stiffness on the same draw: "
              + "; ".join(f"{k} {a:.6g} / {b:.6g}" for k, (a, b) in pairs))
        print("  cycloidgen as shipped (its defaults): " + ", ".join(
            f"{k} {v:.4g}" for k, v in t["as_shipped"].items()))


def parse_override(text):
    key, _, value = text.partition("=")
    try:
        return key, float(value)
    except ValueError:
        return key, value


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=200, help="rings drawn (default 200)")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED,
                    help=f"seed of both draws (default {DEFAULT_SEED}, cycloidgen's own)")
    ap.add_argument("--zone", type=float, default=0.010,
                    help="pin true-position zone diameter, mm (default 0.010)")
    ap.add_argument("--modifications", default="0,0.010",
                    help="equidistant modifications (peer: profile clearance), mm")
    ap.add_argument("--positions", type=int, default=36, help="toothfem's positions")
    ap.add_argument("--steps", type=int, default=48,
                    help="cycloidgen's crank angles per ring over its ring-stage period "
                         "(default 48, its TE resolution; its stiffness default is 8)")
    ap.add_argument("--override", action="append", default=[], metavar="KEY=VALUE",
                    help="an extra toothfem tolerance override (repeatable)")
    ap.add_argument("--peer-python", default=str(PEER_PYTHON))
    ap.add_argument("--out", default=None, help="write both halves (every sample) as JSON")
    args = ap.parse_args(argv)
    case, torque = pinhousing_case(args.peer_python)
    mods = tuple(float(m) for m in args.modifications.split(","))
    theirs = peer(args.peer_python, torque, args.zone, mods, args.samples, args.seed,
                  args.steps)
    overrides = pin_position_only(case, args.zone, dict(map(parse_override, args.override)))
    mine, source = ours(case, mods, args.samples, args.seed, args.positions, overrides)
    report(theirs, mine, mods,
           f"pin-housing drive at {torque:g} N m, pin true position {args.zone:g} mm "
           f"(uniform in the zone), {args.samples} rings, seed {args.seed}\n"
           f"cycloidgen {theirs['version']}: {theirs['steps']} crank angles per ring; "
           f"toothfem: {source}" + (f", {args.positions} positions, overrides {overrides}"
                                    if mine is not None else ""))
    if args.out:
        Path(args.out).write_text(json.dumps(
            {"torque_Nm": torque, "zone_mm": args.zone, "samples": args.samples,
             "seed": args.seed, "positions": args.positions, "overrides": overrides,
             "cycloidgen": theirs, "toothfem": mine, "toothfem_source": source}, indent=1))


if __name__ == "__main__":
    main()
