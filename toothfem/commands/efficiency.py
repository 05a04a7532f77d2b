"""`toothfem efficiency CASE [--loads fem|analytic] [--method NAME] [--torque-Nm T]
[--speed-rpm N] [--oil-temp-C T] [--json]`."""
from __future__ import annotations

import json


def add_parser(sub):
    from ..efficiency.model import LOADS, METHODS

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


def result(case, speed, torque, oil_temp=None, loads="analytic", method="power_flow") -> dict:
    """The efficiency record of one operating point as a plain mapping (the JSON)."""
    from ..efficiency.model import evaluate

    e = evaluate(case, speed, torque, oil_temp, loads=loads, method=method)
    shares = e.shares()
    return {
        "case": case.name, "loads": e.loads, "method": e.method,
        "input_speed_rpm": float(speed), "output_torque_Nm": float(torque),
        "oil_temp_C": oil_temp,
        "efficiency": float(e.efficiency[0]),
        "input_power_W": float(e.input_power_W[0]),
        "output_power_W": float(e.output_power_W[0]),
        "losses": {k: float(v[0]) for k, v in e.losses_W.items()},
        "loss_shares": {k: float(v[0]) for k, v in shares.items()},
        "mesh_efficiency": {k: float(v[0]) for k, v in e.mesh_efficiency.items()},
        "notes": list(e.notes),
    }


def run(args) -> int:
    from ..case import load_case
    from ..case_checks import SPEED_RPM, TORQUE_NM
    from ..efficiency.model import operating_point
    from ..errors import CaseError, check_range

    for flag, value, (lo, hi) in (("--speed-rpm", args.speed, SPEED_RPM),
                                  ("--torque-Nm", args.torque, TORQUE_NM)):
        if value is not None:           # the case's plausibility bounds (issue 14; the
            check_range(flag, value, lo, hi, error=CaseError)   # oil: the Vogel law's)
    case = load_case(args.case)
    speed, torque = args.speed, args.torque
    if speed is None or torque is None:
        speed0, torque0 = operating_point(case, loads=args.loads, method=args.method)
        speed = speed0 if speed is None else speed
        torque = torque0 if torque is None else torque
    out = result(case, speed, torque, args.oil_temp, args.loads, args.method)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{case.name}: {out['input_speed_rpm']:g} rpm, {out['output_torque_Nm']:g} N m, "
          f"loads {out['loads']}, method {out['method']}")
    print(f"  efficiency {100 * out['efficiency']:.2f} %  (input {out['input_power_W']:.2f} W,"
          f" output {out['output_power_W']:.2f} W)")
    for k, w in out["losses"].items():
        print(f"  {k:<20s} {w:10.4f} W  {100 * out['loss_shares'][k]:6.2f} % of input")
    for note in out["notes"]:
        print(f"  note: {note}")
    return 0
