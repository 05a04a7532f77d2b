"""`toothfem run CASE --out DIR`: the whole pipeline (geometry, contact, efficiency) and a
Markdown report with its pictures, CSV tables and VTU fields."""
from __future__ import annotations

#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "run"
HELP = ("geometry, FE contact and efficiency of a case, with a report (report.md, PNGs, CSV, "
        "VTU)")


def add_parser(sub):
    """Add ``toothfem run`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--out", required=True, help="output folder (written atomically)")
    p.add_argument("--positions", type=int, default=36,
                   help="meshing positions over one pitch (default 36)")
    p.add_argument("--field", choices=("detailed", "structural", "none"), default="structural",
                   help="stress field at the worst position (see `toothfem contact --help`); "
                        "default structural (fast)")
    p.add_argument("--as-built", type=int, default=40, metavar="N",
                   help="reducers built within the case's [tolerances] solved beside the "
                        "nominal: their median and P95 of backlash, lost motion, largest "
                        "force and pressure (default 40; 200 for the full ensemble of "
                        "toothfem tolerance; 0: none)")
    p.add_argument("--no-fem", action="store_true",
                   help="skip the FE contact; efficiency from the analytic split only")
    p.add_argument("--json", action="store_true",
                   help="print the efficiency and contact summaries as JSON instead of tables")
    p.set_defaults(func=run)


def run(args) -> int:
    """The whole pipeline of a case (:func:`toothfem.pipeline.run_case`) and its summary on
    screen.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``out``, ``positions``, ``field``, ``no_fem`` and ``json``.

    Returns
    -------
    int
        0 when the report folder is complete.
    """
    import json
    import textwrap

    from ..bars import bar, stage
    from ..efficiency.mesh_table import fe_progress
    from ..pipeline import run_case
    from ..report import summary as report_summary
    from ..report.durability import as_built_rows


    progress = lambda it: bar(it, desc="cycle mode", unit="position")  # noqa: E731
    with fe_progress(bar):          # the efficiency's FE load table on a bar too
        res = run_case(args.case, args.out, positions=args.positions, field=args.field,
                       fem=not args.no_fem, progress=progress, as_built=args.as_built,
                       stage=stage)
    report = res.report.resolve()
    if args.json:
        contact = None if res.contact is None else res.contact.summary
        print(json.dumps({"efficiency": res.efficiency, "contact": contact,
                          "as_built": (res.durability or {}).get("as_built") or None,
                          "warnings": res.warnings, "report": str(report)}, indent=2))
        return 0
    case, dur = res.case, res.durability
    if case is None or dur is None:
        raise RuntimeError("run_case returned a result without its case or durability")
    print(report_summary.text(
        report_summary.efficiency_rows(res.efficiency, case.published),
        title=f"{case.name}: efficiency at {res.speed_rpm:g} rpm input, "
              f"{res.output_torque_Nm:.4g} N m output"))
    if res.contact is not None:
        print()
        print(report_summary.text(
            res.contact.table(case.published),
            title=f"contact ({res.contact.mode} mode)"))
    if dur.get("as_built"):
        print()
        print(report_summary.text(as_built_rows(dur["as_built"]),
                                  title=f"as built: {dur['as_built']['rings']} reducers within "
                                        "[tolerances] (system model)"))
    heat, life, strength = (dur[k] for k in ("heat", "life", "strength"))
    l10 = life["unit_l10_h"]
    print(f"\nequilibrium oil {heat['equilibrium_oil_temp_C']:.1f} C")
    print("bearings L10 " + ("not rated" if l10 is None else
                             f"{l10:.4g} h (limiting: {life['limiting']})"))
    print(f"contact safety {strength['contact_fatigue_safety'] or float('inf'):.2f} (on "
          f"{strength['ph_max_MPa']:.4g} MPa, "
          + ("the reducer's" if strength.get("judged_on") == "reducer" else
             "one member held") + ")")
    if strength.get("note"):
        print(textwrap.fill(f"note: {strength['note']}", width=100, subsequent_indent="  "))
    for w in res.warnings:
        print(f"warning: {w}")
    print(f"\nwrote the report to {report} (pictures, CSV tables and VTU fields beside it)")
    print(f"one page with every input, assumption, warning and figure: "
          f"{report.with_name('report.html')}")
    return 0
