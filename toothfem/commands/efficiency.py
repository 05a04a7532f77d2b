"""`toothfem efficiency CASE [--loads fem|analytic] [--method NAME] [--torque-Nm T]
[--speed-rpm N] [--oil-temp-C T | --thermal [--duration-h H]] [--json]`."""
from __future__ import annotations

import json


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "efficiency"
HELP = "reducer efficiency and the loss of every component at one operating point"


def add_parser(sub):
    """Add ``toothfem efficiency`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    from ..efficiency.evaluation import METHODS
    from ..efficiency.mesh_table import LOADS

    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--loads", choices=LOADS, default="analytic",
                   help="load sharing: analytic (the seeds' split, default) or fem (cycle-mode "
                        "FE contact, tabulated over torque, each disc at its FE share of the "
                        "torque; takes seconds to a minute)")
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
    p.add_argument("--thermal", action="store_true",
                   help="solve the heat balance: the oil temperature at which the losses "
                        "leave through the housing ([thermal] of the case), and the "
                        "efficiency there")
    p.add_argument("--duration-h", type=float, default=None, dest="duration",
                   help="with --thermal: the warm-up from the ambient over this time [h]")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=run)


def run(args) -> int:
    """Efficiency and the loss of every component at one operating point (or at the
    oil temperature of the heat balance with ``--thermal``).

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``loads``, ``method``, ``torque`` [N m], ``speed`` [rpm], ``oil_temp``
        [deg C], ``thermal``, ``duration`` [h] and ``json``.

    Returns
    -------
    int
        0 after the table (or JSON) is printed.

    Raises
    ------
    CaseError
        If a value is outside its range or the options exclude each other.
    """
    from ..efficiency.mesh_table import fe_progress
    from ..bars import bar

    with fe_progress(bar):          # the FE load table's solves on a bar (stderr)
        return _run(args)


def _run(args) -> int:

    from ..case import load_case
    from ..case_checks import SPEED_RPM, TORQUE_NM
    from ..durability import thermal_summary
    from ..efficiency import operating_point
    from ..errors import CaseError, check_range
    from ..pipeline import efficiency_summary
    from ..report import summary as report_summary

    for flag, value, (lo, hi) in (("--speed-rpm", args.speed, SPEED_RPM),
                                  ("--torque-Nm", args.torque, TORQUE_NM)):
        if value is not None:           # the case's plausibility bounds (issue 14; the
            check_range(flag, value, lo, hi, error=CaseError)   # oil: the Vogel law's)
    case = load_case(args.case)
    if args.thermal and args.oil_temp is not None:
        raise CaseError(f"--oil-temp-C = {args.oil_temp!r} and --thermal exclude each other "
                        "(--thermal finds the oil temperature)")
    if args.thermal and args.method != "power_flow":
        raise CaseError(f"--thermal needs --method power_flow, not {args.method!r} (the RV "
                        "paper's method takes no oil temperature)")
    if args.duration is not None and not args.thermal:
        raise CaseError(f"--duration-h = {args.duration!r} needs --thermal")
    speed, torque = args.speed, args.torque
    if speed is None or torque is None:
        speed0, torque0 = operating_point(case, loads=args.loads, method=args.method)
        speed = speed0 if speed is None else speed
        torque = torque0 if torque is None else torque
    oil_temp, heat = args.oil_temp, None
    if args.thermal:
        heat = thermal_summary(case, speed, torque, loads=args.loads,
                               duration_h=args.duration)
        oil_temp = heat["equilibrium_oil_temp_C"]
    out = efficiency_summary(case, speed, torque, oil_temp, args.loads, args.method)
    if args.torque is None and not case.operating.output_torque_Nm:
        # a case that declares its input torque or power: the output torque comes through
        # this model's own efficiency (operating_point), not through the analytic power
        # flow's that run, contact and check take: said beside the numbers
        out["operating_point_from"] = f"{args.loads} loads, {args.method}"
    if heat is not None:
        out["thermal"] = heat
        # the command's one list: every warning once, the heat balance's with the rest
        said = {w["message"] for w in out["warnings"]}
        out["warnings"] = out["warnings"] + [w for w in heat.get("warnings", [])
                                             if w["message"] not in said]
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    rows = report_summary.efficiency_rows({f"{out['loads']} loads, {out['method']}": out},
                                          case.published)
    oil = ("the lubricant's reference" if out["oil_temp_C"] is None
           else f"{out['oil_temp_C']:g} deg C")
    source = (f" (the case's input through the {out['operating_point_from']} efficiency)"
              if "operating_point_from" in out else "")
    print(report_summary.text(rows, title=f"{case.name}: {out['input_speed_rpm']:g} rpm input, "
                                          f"{out['output_torque_Nm']:.4g} N m output{source}, "
                                          f"oil at {oil}"))
    if heat is not None:
        print(f"  heat balance: oil {heat['equilibrium_oil_temp_C']:.1f} C at ambient "
              f"{heat['ambient_C']:g} C (h = {heat['heat_transfer_W_m2K']:.1f} W/m2K, "
              f"A = {heat['housing_area_m2']:.3f} m2, {heat['losses_W']:.1f} W)")
        for row in heat.get("warm_up", [])[::10]:
            print(f"  warm-up {row['time_h']:6.2f} h: oil {row['oil_temp_C']:6.1f} C, "
                  f"efficiency {100 * row['efficiency']:.2f} %")
    for name, source in out["loss_sources"].items():
        print(report_summary.wrapped(f"source: {name}: {source}"))
    for note in out["notes"]:
        print(report_summary.wrapped(f"note: {note}"))
    for w in out["warnings"]:
        print(f"warning: {w['message']}")
    return 0
