"""`toothfem modes CASE [--load-inertia-kgm2 J] [--motor-inertia-kgm2 J] [--torque-Nm T]
[--input held|free] [--json] [--out DIR]`: the torsional-lateral modes of the reducer's
system model linearised at an output torque, each mode's strain-energy shares, and the
Campbell diagram of the TE orders against input speed (docs/dynamics.md)."""
from __future__ import annotations

import textwrap
from pathlib import Path

#: The subcommand, and its line in ``toothfem --help``.
NAME = "modes"
HELP = ("modes of the whole reducer at an output torque (tangent stiffness, inertias from "
        "the geometry) with their energy shares, and the Campbell diagram of the TE orders")


def add_parser(sub):
    """Add ``toothfem modes`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", default=None,
                   help="output folder (written atomically): modes.csv, bodies.csv, "
                        "campbell.csv, modes.png, campbell.png, summary.json")
    p.add_argument("--load-inertia-kgm2", type=float, default=None, dest="load",
                   help="the load's inertia on the output [kg m²] (default: the case's "
                        "operating.load_inertia_kgm2, else 0)")
    p.add_argument("--motor-inertia-kgm2", type=float, default=None, dest="motor",
                   help="the motor's inertia on the input [kg m²], with --input free "
                        "(default: the case's operating.motor_inertia_kgm2, else 0)")
    p.add_argument("--torque-Nm", type=float, default=None, dest="torque",
                   help="output torque the system is linearised at [N m] (default: rated)")
    p.add_argument("--input", choices=("held", "free"), default="held",
                   help="the input held (the sun, or the input shaft's end, fixed) or free "
                        "(the motor's inertia on it; the first mode is then the train's "
                        "rigid rotation, 0 Hz); default held")
    p.add_argument("--positions", type=int, default=12,
                   help="meshing positions over one pitch the tangent is averaged over "
                        "(default 12)")
    p.add_argument("--response", action="store_true",
                   help="also the dynamic TE and output torque ripple against input speed "
                        "(harmonic balance about the static path, input driven at constant "
                        "speed; dynamic.csv, dynamic.png) and at each warned crossing")
    p.add_argument("--damping-ratio", type=float, default=None, dest="zeta",
                   help="modal damping ratio of --response (default 0.05, docs/dynamics.md)")
    p.add_argument("--speeds", type=int, default=50,
                   help="input speeds of --response, log-spaced to the top speed (default 50)")
    p.add_argument("--backdrive", action="store_true",
                   help="also the backdrive torque at the output and the starting torque at "
                        "the input, both directions, from the system model's friction, and "
                        "the no-load running torque against speed")
    p.add_argument("--json", action="store_true",
                   help="print the summary (modes with frequency_Hz, shares and shape) as "
                        "JSON instead of the mode list")
    p.set_defaults(func=run)


def run(args) -> int:
    """The modes of a case on screen (or JSON), and its files into ``--out``.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out``, ``load``, ``motor``, ``torque``, ``input``, ``positions``,
        ``response``, ``zeta``, ``speeds``, ``backdrive``, ``json``.

    Returns
    -------
    int
        0 once done.
    """
    from ..case import load_case
    from ..dynamics import modes_analysis
    from ..output import atomic_dir
    from ..backdrive import backdrive, no_load_torque
    from ..dynamic_response import DAMPING_RATIO, dynamic_response
    from ..dynamics import WARN_AMPLITUDE_REL
    from ..report.modes import dynamic_summary, finite_json, write_dynamic
    from ..report.modes import mode_lines, summary as modes_summary
    case = load_case(args.case)

    def analyse():
        result = modes_analysis(case, load_kgm2=args.load, motor_kgm2=args.motor,
                                torque_Nm=args.torque, input_free=args.input == "free",
                                positions=args.positions)
        extra = {} if not args.backdrive else {
            "backdrive": backdrive(case, positions=args.positions),
            "no_load_running_torque": no_load_torque(case, result.speed_range_rpm[1])}
        if not args.response:
            return result, extra, None
        return result, extra, dynamic_response(
            case, load_kgm2=result.load_kgm2, torque_Nm=result.torque_Nm,
            zeta=DAMPING_RATIO if args.zeta is None else args.zeta, speeds=args.speeds,
            crossings=[c for c in result.crossings if c["warned"]],
            top_rpm=result.speed_range_rpm[1])

    if args.out is not None:
        with atomic_dir(args.out) as tmp:   # a bad --out refused before any work
            result, extra, dyn = analyse()
            summary = result.write(tmp)
            summary.update(extra)
            if dyn is not None:
                summary["files"] += write_dynamic(dyn, tmp)
                summary["dynamic"] = dynamic_summary(dyn)
            if dyn is not None or extra:
                (Path(tmp) / "summary.json").write_text(finite_json(summary) + "\n",
                                                        encoding="utf-8")
    else:
        result, extra, dyn = analyse()
        summary = {**modes_summary(result), **extra}
        if dyn is not None:
            summary["dynamic"] = dynamic_summary(dyn)
    if args.json:
        print(finite_json(summary))
        return 0
    def say(text):                      # one item, wrapped at 100 columns
        print(textwrap.fill(text, 100, subsequent_indent="  "))

    say(f"{case.name}: modes at {result.torque_Nm:g} N m, input {args.input}, load "
          f"{result.load_kgm2:g} kg m², motor {result.motor_kgm2:g} kg m²")
    for line in mode_lines(result):
        print(line)
    say(f"two-inertia estimate sqrt(k/J)/(2 pi) = {result.two_inertia_Hz:.4g} Hz (k the "
          f"tangent rigidity {summary['tangent_rigidity_Nm_per_arcmin']:.4g} N m/arcmin, "
          "input held)")
    for what, text in result.assumed.items():
        say(f"assumed {what}: {text}")
    if result.bandwidth is not None:
        b = result.bandwidth
        say(f"torque bandwidth (-3 dB of the output torque per motor torque, damping ratio "
            f"{DAMPING_RATIO:g}): {b['bandwidth_Hz']:.4g} Hz ({b['range_Hz'][0]:.4g}-"
            f"{b['range_Hz'][1]:.4g} over the mesh), first mode {b['first_mode_Hz']:.4g} Hz")
    bd = extra.get("backdrive", {}).get("by_direction", {})
    if bd:
        say("backdrive torque at the output (input free, from rest): "
            + ", ".join(f"{k} {v['backdrive_torque_Nm']:.4g} N m" for k, v in bd.items())
            + "; starting torque at the input (output free): "
            + ", ".join(f"{k} {v['input_starting_torque_Nm']:.4g} N m"
                        for k, v in bd.items()))
        nl = extra["no_load_running_torque"]
        say("no-load running torque at the input: " + ", ".join(
            f"{t:.3g} N m at {n:.4g} rpm" for n, t in list(zip(nl["speeds_rpm"],
                                                                nl["input_torque_Nm"]))[::3]))
    quiet = sum(not c["warned"] for c in result.crossings)
    if quiet:
        say(f"{quiet} crossings of orders the TE spectrum carries below "
              f"{100 * WARN_AMPLITUDE_REL:g} % of its largest line (campbell.csv, --json)")
    for w in result.warnings:
        print(f"warning: {w}")            # one line each (a log's grep finds it whole)
    if dyn is not None:
        say(f"dynamic response ({dyn.method}; damping ratio {dyn.damping_ratio:g}: "
            f"{dyn.damping_source}): static TE {dyn.static_te_pp_arcsec:.4g} arcsec peak to "
            f"peak; largest over {len(dyn.speeds_rpm)} speeds {dyn.te_pp_arcsec.max():.4g} "
            f"arcsec, torque ripple {dyn.ripple_pp_Nm.max():.4g} N m peak to peak")
        for c in dyn.crossings:
            print(f"at crossing: {c['order_name']} (order {c['order']:g}) x mode {c['mode']}, "
                  f"{c['speed_rpm']:.4g} rpm: "
                  f"TE {c['te_pp_arcsec']:.4g} arcsec, torque ripple {c['ripple_pp_Nm']:.4g} N m "
                  "peak to peak")
    if args.out is not None:
        print(f"wrote {Path(args.out).resolve()} (summary.json, modes.png, campbell.png)")
    return 0
