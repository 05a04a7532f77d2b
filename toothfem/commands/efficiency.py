"""`toothfem efficiency CASE [--loads fem|analytic] [--method NAME] [--torque-Nm T]
[--speed-rpm N] [--oil-temp-C T] [--json]`."""
from __future__ import annotations

import json


def add_parser(sub):
    from ..efficiency.evaluation import METHODS
    from ..efficiency.mesh_table import LOADS

    p = sub.add_parser("efficiency", help="reducer efficiency and the loss of every component "
                       "at one operating point")
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--loads", choices=LOADS, default="analytic",
                   help="load sharing: analytic (the seeds' split, default) or fem (cycle-mode "
                        "FE contact, tabulated over torque; takes seconds to a minute)")
    p.add_argument("--method", choices=METHODS, default="power_flow",
                   help="power_flow: losses from the friction models through Chen & Angeles' "
                        "virtual power (default); rv_split_power: the RV paper's method with "
                        "the declared mesh efficiency (rv cases)")
    p.add_argument("--torque-Nm", type=float, default=None, dest="torque",
                   help="output torque [N m] (default: the case's operating point)")
    p.add_argument("--speed-rpm", type=float, default=None, dest="speed",
                   help="input speed [rpm] (default: the case's)")
    p.add_argument("--oil-temp-C", type=float, default=None, dest="oil_temp",
                   help="oil temperature [deg C] (default: the lubricant's reference)")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..case import load_case
    from ..efficiency import operating_point
    from ..pipeline import efficiency_summary
    from ..report import summary as report_summary

    case = load_case(args.case)
    speed, torque = args.speed, args.torque
    if speed is None or torque is None:
        speed0, torque0 = operating_point(case, loads=args.loads, method=args.method)
        speed = speed0 if speed is None else speed
        torque = torque0 if torque is None else torque
    out = efficiency_summary(case, speed, torque, args.oil_temp, args.loads, args.method)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    rows = report_summary.efficiency_rows({f"{out['loads']} loads, {out['method']}": out},
                                          case.published)
    oil = ("the lubricant's reference" if out["oil_temp_C"] is None
           else f"{out['oil_temp_C']:g} deg C")
    print(report_summary.text(rows, title=f"{case.name}: {out['input_speed_rpm']:g} rpm input, "
                                          f"{out['output_torque_Nm']:.4g} N m output, oil at "
                                          f"{oil}"))
    for note in out["notes"]:
        print(f"note: {note}")
    return 0
