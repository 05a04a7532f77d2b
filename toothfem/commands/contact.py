"""`toothfem contact CASE --positions N [--torque-Nm T] [--mode cycle|detailed] --out DIR`."""
from __future__ import annotations

import csv
import json
import math

import numpy as np


def add_parser(sub):
    p = sub.add_parser("contact", help="FE load sharing, Hertz or FE pressure and transmission "
                       "error over one meshing period (cycloid discs, sine pair)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pin pitch (default 36)")
    p.add_argument("--torque-Nm", type=float, default=None, dest="torque",
                   help="reducer output torque [N m] (default: the case's); one disc carries "
                        "disc_load_factor * T / disc_count")
    p.add_argument("--mode", choices=("cycle", "detailed"), default="cycle",
                   help="cycle: influence coefficients + Hertz (fast, default); detailed: "
                        "two-body FE contact at each position (slow)")
    p.add_argument("--pins", choices=("conventional", "integral", "rigid"), default=None,
                   help="pin structure: conventional (pins in housing grooves), integral "
                        "(pins one piece with the housing) or rigid (fixed rigid pins, cycle "
                        "mode only: the CalculiX peer's model); default: the case's")
    p.add_argument("--field", choices=("detailed", "structural", "none"), default="detailed",
                   help="stress field at the worst position: detailed (two-body FE with the "
                        "contact zones resolved, ~1-2 min; default), structural (cycloid: the "
                        "cycle mode's loads smeared over b_ref, no contact-zone stress; the "
                        "sine pair always uses detailed) or none")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.set_defaults(func=run)


COLUMNS = ("position_deg", "contact_id", "force_N", "moment_arm_mm", "half_width_mm", "ph_MPa",
           "gap_mm")


def run(args) -> int:
    from tqdm import tqdm

    from ..case import load_case
    from ..errors import CaseError, check_range
    from ..fem import cycloid_fe as cf
    from ..fem import export, plots
    from ..output import atomic_dir

    check_range("--positions", args.positions, 1, 3600, error=CaseError)
    case = load_case(args.case)
    if case.cycloid is None and case.drive != "sine":
        raise CaseError(f"{args.case}: drive = {case.drive!r} has no profile geometry "
                        "([cycloid] disc or sine pair) to put in contact")
    if args.torque is not None:         # the case's plausibility bounds (issue 14)
        from ..case_checks import TORQUE_NM

        check_range("--torque-Nm", args.torque, *TORQUE_NM, error=CaseError)
    from dataclasses import replace

    if args.torque is not None:
        case = replace(case, operating=replace(case.operating, output_torque_Nm=args.torque))
    if case.operating.output_torque_Nm in (None, 0):     # from the declared input
        from ..efficiency.model import operating_point

        case = replace(case, operating=replace(case.operating,
                                               output_torque_Nm=operating_point(case)[1]))
    progress = lambda it: tqdm(it, desc=f"{args.mode} mode", unit="position")  # noqa: E731
    with atomic_dir(args.out) as tmp:
        if case.drive == "sine":
            ls, phis, worst, detail, body, u, centre, label, summary = _sine(case, args,
                                                                           progress)
        else:
            ls, phis, worst, detail, body, u, centre, label, summary = _cycloid(case, args,
                                                                              progress)
        with open(tmp / "load_sharing.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(COLUMNS)
            for row in ls.rows():
                w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
        summary = {
            "case": case.name, "mode": args.mode, "positions": args.positions,
            "output_torque_Nm": case.operating.output_torque_Nm, **summary,
            "pins_in_contact_max": int(ls.contacts_per_position.max()),
            "pins_in_contact_min": int(ls.contacts_per_position.min()),
            "max_force_N": float(ls.force.max()),
            "max_ph_MPa": float(ls.ph.max() / 1e6),
            "transmission_error_arcsec": float(np.degrees(ls.transmission_error.mean()) * 3600),
            "transmission_error_ripple_arcsec": float(np.degrees(np.ptp(ls.transmission_error))
                                                      * 3600),
            "torque_equilibrium_max_rel_error": float(np.max(np.abs(ls.torque_residual()))),
            "worst_position_deg": float(np.degrees(phis[worst])),
            "hertz_invalid_contacts": int(np.sum(ls.hertz_invalid)),
            "ph_from_fe_contacts": int(np.sum(ls.pressure_from_fe)),
            "files": ["load_sharing.csv", "summary.json", "load_per_pin.png"],
        }
        if args.mode == "cycle" and detail is not None:
            fd = detail.load_sharing.force[0]
            summary["detailed_check_at_worst_position"] = {
                "max_force_N": float(fd.max()), "max_ph_MPa": float(detail.load_sharing.ph.max()
                                                                  / 1e6),
                "max_force_ratio_detailed_to_cycle": float(fd.max() / ls.force[worst].max()),
                "dofs": int(detail.dofs)}
        fig = plots.load_per_contact(ls)
        fig.savefig(tmp / "load_per_pin.png", dpi=120)
        if body is not None:
            vtu = export.write_vtu(tmp / f"{label}_worst_position.vtu", body, u)
            kind = "detailed" if detail is not None else "structural"
            plots.field_png(vtu, tmp / "von_mises.png",
                            title=f"von Mises ({kind}), worst position {np.degrees(phis[worst]):.2f}"
                                  f" deg, {label} frame")
            k = int(np.argmax(ls.force[worst]))
            b = max(float(ls.half_width[worst, k]), 1e-6)
            plots.field_png(vtu, tmp / "von_mises_contact.png", zoom_centre=centre,
                            zoom_radius=6 * b, title=f"contact zone of contact "
                            f"{int(ls.contact_id[worst, k])} ({kind})")
            summary["files"] += [vtu.name, "von_mises.png", "von_mises_contact.png"]
        (tmp / "summary.json").write_text(json.dumps(summary, indent=2))
    print(json.dumps({k: v for k, v in summary.items() if k != "files"}, indent=2))
    return 0


def _cycloid(case, args, progress):
    """Cycle or detailed mode of a cycloid disc; the field at the worst position."""
    from ..fem import cycloid_fe as cf

    model = cf.model_from_case(case, args.pins)
    torque = cf.disc_torque(case)
    g = model.geometry
    phis = np.linspace(0, 2 * math.pi / g.pin_count, args.positions, endpoint=False)
    detail = disc = u = None
    if args.mode == "cycle":
        from ..fem.cache import DiskCache, default_dir

        solver = cf.CycleSolver(model, phis, cache=DiskCache(default_dir()))
        ls = solver.solve(torque, progress=progress)
        worst = int(np.argmax(ls.force.max(axis=1)))
        if args.field == "detailed":
            detail = cf.solve_detailed(model, phis[worst], torque)
            disc, u = detail.disc, detail.disc_displacement
        elif args.field == "structural":
            disc, u = solver.disc_field(worst, ls)
    else:
        results = [cf.solve_detailed(model, phi, torque) for phi in progress(phis)]
        ls = _stack([r.load_sharing for r in results])
        worst = int(np.argmax(ls.force.max(axis=1)))
        detail = results[worst]
        if args.field != "none":
            disc, u = detail.disc, detail.disc_displacement
    k = int(np.argmax(ls.force[worst]))
    centre = _disc_frame_point(g, phis[worst], ls.point[worst, k])
    summary = {"pin_structure": model.pin_structure, "disc_torque_Nm": torque}
    return ls, phis, worst, detail, disc, u, centre, "disc", summary


def _sine(case, args, progress):
    """Cycle or detailed mode of the sine pair; the planet's field at the worst position
    (always from the detailed mode: the cycle mode has no stress field of its own)."""
    from ..errors import CaseError
    from ..fem import sine_fe
    from ..geometry import sine

    if args.pins is not None:
        raise CaseError("--pins applies to cycloid drives, not to the sine pair")
    model = sine_fe.model_from_case(case)
    torque = sine_fe.planet_torque(case)
    phis = np.arange(args.positions) * model.pair.crank_pitch_rad / args.positions
    detail = body = u = None
    if args.mode == "cycle":
        from ..fem.cache import DiskCache, default_dir

        ls = sine_fe.CycleSolver(model, phis, cache=DiskCache(default_dir())).solve(
            torque, progress=progress)
        worst = int(np.argmax(ls.force.max(axis=1)))
        if args.field != "none":
            detail = sine_fe.solve_detailed(model, phis[worst], torque)
    else:
        results = [sine_fe.solve_detailed(model, phi, torque) for phi in progress(phis)]
        ls = _stack([r.load_sharing for r in results])
        worst = int(np.argmax(ls.force.max(axis=1)))
        detail = results[worst]
    if detail is not None and args.field != "none":
        body, u = detail.planet, detail.planet_displacement
    k = int(np.argmax(ls.force[worst]))
    c, th = sine.planet_pose(model.pair, phis[worst])
    centre = sine._rot(-th[0], ls.point[worst, k] - c[:, 0])     # planet frame
    summary = {"planet_torque_Nm": torque,
               "planet_bore_radius_mm": model.planet_bore_radius * 1e3,
               "ring_outer_radius_mm": model.ring_outer_radius * 1e3}
    return ls, phis, worst, detail, body, u, centre, "planet", summary


def _disc_frame_point(g, phi, point):
    from ..geometry import cycloid as cy

    local = cy.to_disc_frame(g, [phi], np.asarray(point, float).reshape(2, 1, 1))
    return local[:, 0, 0]


def _stack(records):
    import dataclasses

    first = records[0]
    out = {}
    for f in dataclasses.fields(first):
        vals = [getattr(r, f.name) for r in records]
        if isinstance(vals[0], np.ndarray):
            out[f.name] = np.concatenate(vals, axis=0)
        else:
            out[f.name] = vals[0]
    return type(first)(**out)
