"""`toothfem geometry CASE --out DIR`: profiles as CSV, a drawing and a check summary."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def add_parser(sub):
    p = sub.add_parser("geometry", help="write the tooth profiles (CSV), a drawing (PNG) and "
                       "a check summary (JSON)")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--points-per-tooth", type=int, default=96,
                   help="profile points per lobe or tooth (default 96)")
    p.set_defaults(func=run)


def _write_xy(path: Path, pts):
    np.savetxt(path, np.asarray(pts).T * 1e3, delimiter=",", header="x_mm,y_mm", comments="",
               fmt="%.9f")


def run(args) -> int:
    from ..case import load_case
    from ..derived import derived
    from ..errors import CaseError, check_range
    from ..output import atomic_dir
    from .. import plots

    check_range("--points-per-tooth", args.points_per_tooth, 8, 10000, error=CaseError)
    case = load_case(args.case)
    summary = derived(case)
    with atomic_dir(args.out) as tmp:
        if case.drive == "cycloid":
            from ..geometry import cycloid as cy

            geom = case.cycloid.geometry()
            holes = case.cycloid.holes_si()
            disc = cy.disc_polygon(geom, holes, points_per_lobe=args.points_per_tooth)
            _write_xy(tmp / "profile.csv", np.asarray(disc.exterior.coords).T[:, :-1])
            summary["disc_area_mm2"] = float(disc.area * 1e6)
            summary["disc_polygon_valid"] = bool(disc.is_valid)
            summary["files"] = ["profile.csv", "drawing.png", "check.json"]
            fig = plots.cycloid_drawing(geom, holes)
        elif case.drive == "sine":
            from ..geometry import sine

            pair = case.sine.geometry()
            phi1 = np.linspace(0, 2 * np.pi, pair.planet_teeth * args.points_per_tooth,
                               endpoint=False)
            _write_xy(tmp / "planet.csv", sine.planet_profile(pair, phi1))
            phi2 = np.linspace(0, 2 * np.pi * pair.ring_teeth / pair.planet_teeth,
                               pair.ring_teeth * args.points_per_tooth, endpoint=False)
            _write_xy(tmp / "ring.csv", sine.ring_profile(pair, phi2))
            summary["files"] = ["planet.csv", "ring.csv", "drawing.png", "check.json"]
            fig = plots.sine_drawing(pair)
        else:
            raise CaseError(f"{args.case}: drive = 'rv' has tooth numbers only, no profile "
                            "geometry to write (use a cycloid or sine case)")
        fig.savefig(tmp / "drawing.png", dpi=120)
        (tmp / "check.json").write_text(json.dumps(summary, indent=2))
    print(f"wrote {', '.join(summary['files'])} to {args.out}")
    return 0
