"""`toothfem te-loop CASE --te FILES... [--hysteresis FILE] --out DIR`: compare the model's
transmission error and hysteresis with rig recordings, add the physical effects the
recordings ask for, and report the error before and after (DIR/report.md, report.json,
hysteresis.png, spectrum.png where a recording holds a whole turn, widths.png where widths
were measured, report.html); the running widths' rigidity and lost-motion intercept beside
the model's; each selection step kept beside DIR as it finishes, with its model
evaluations, so the same command resumes after the steps kept; the model's two directions
solved in two processes (``--workers``)."""
from __future__ import annotations

import json
from pathlib import Path


#: The subcommand, and its line in ``toothfem --help`` (the CLI lists every command
#: by these two without importing what the others need).
NAME = "te-loop"
HELP = ("fit physical effects (crank-bearing play, eccentric errors, stiffness, friction, "
        "profile clearance) to transmission-error and hysteresis recordings; the error before "
        "and after")


def add_parser(sub):
    """Add ``toothfem te-loop`` to the CLI.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The CLI's subcommands.
    """
    p = sub.add_parser(NAME, help=HELP)
    p.add_argument("case", help="case file (TOML)")
    p.add_argument("--te", nargs="*", default=None, metavar="PATH",
                   help="TE recordings: CSV files or folders (output_angle_<unit> with "
                        "te_forward_/te_backward_<unit>, or te_<unit> with a direction "
                        "column; whole sweeps or short windows with gaps, one file per "
                        "torque or one long table; the torque from a column, a "
                        "'# output_torque_Nm:' line or --name-pattern)")
    p.add_argument("--hysteresis", default=None, metavar="CSV",
                   help="a hysteresis staircase: output_torque_<unit>, twist_<unit> and "
                        "optionally direction")
    p.add_argument("--name-pattern", default=None,
                   help="file-name pattern of the TE files' conditions, e.g. "
                        "'te_{output_torque_Nm}Nm.csv'")
    p.add_argument("--effects", default=None,
                   help="comma-separated effects to consider, or 'all' (default: every "
                        "effect of the drive but the costly ones, the pin ring's, which the "
                        "report lists; the names are in report.json)")
    p.add_argument("--folds", type=int, default=5, help="k of the k-fold held-out error")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="processes the model's TE is solved in: 1, or 2 (its two directions "
                        "side by side, the same numbers); default 2 where this process may "
                        "run on two processors or more, else 1")
    p.add_argument("--out", required=True, help="output folder (written atomically; each "
                   "selection step is kept in a journal beside it as it finishes, and the "
                   "same command resumes after the steps kept)")
    p.add_argument("--json", action="store_true", help="print report.json instead of the "
                   "summary lines")
    p.set_defaults(func=run)


def run(args) -> int:
    """Fit the effects the recordings ask for and write the report into ``--out``.

    Parameters
    ----------
    args : argparse.Namespace
        ``case``, ``te``, ``hysteresis``, ``name_pattern``, ``effects``, ``folds``,
        ``workers``, ``out``, ``json``.

    Returns
    -------
    int
        0 when the report is written.

    Raises
    ------
    ToothfemError
        Without any recording, for an unknown effect, ``--folds`` below 2 or ``--workers``
        outside [1, 2].
    """
    from ..case import load_case
    from ..errors import ToothfemError
    from ..efficiency.loop.te.model import WORKERS, RecordingModel

    if not args.te and not args.hysteresis:
        raise ToothfemError("--te, --hysteresis: give TE recordings, a hysteresis recording, "
                            "or both")
    if args.folds < 2:
        raise ToothfemError(f"--folds = {args.folds} is outside the valid range [2, inf)")
    workers = default_workers() if args.workers is None else args.workers
    if workers not in WORKERS:
        raise ToothfemError(f"--workers = {workers} is outside the valid range "
                            f"[{min(WORKERS)}, {max(WORKERS)}]")
    case = load_case(args.case)
    with RecordingModel(case, workers=workers, warm_starts=True) as model:
        return _run(args, case, model)


def default_workers() -> int:
    """2 where this process may run on two processors or more, else 1.

    Returns
    -------
    int
    """
    import os

    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:             # not on Linux
        cpus = os.cpu_count() or 1
    return 2 if cpus >= 2 else 1


def _run(args, case, model) -> int:
    """The loop on the case's model, the report written and printed."""
    from ..errors import ToothfemError
    from ..output import reserved, resumable_dir
    from ..fem.cache import content_key
    from . import json_default
    from ..efficiency.loop.settings import Settings
    from ..efficiency.loop.te.effects import catalog
    from ..efficiency.loop.te.loop import run_te_loop

    names = [e.name for e in catalog(model)]
    chosen = None
    if args.effects:
        chosen = [n.strip() for n in args.effects.split(",") if n.strip()]
        unknown = [] if chosen == ["all"] else [n for n in chosen if n not in names]
        if unknown:
            raise ToothfemError(f"--effects = {unknown[0]!r} is not an effect of this drive; "
                                f"valid: {', '.join(names)}; or 'all' alone")
    inputs = [str(p) for p in (args.te or [])] + [str(args.hysteresis)]
    key = content_key("te-loop", case, inputs, args.name_pattern, chosen, args.folds)
    with reserved(args.out):           # the name held for the run; a bad --out refused now
        with resumable_dir(args.out, key) as steps:
            # each selection step kept beside --out as it finishes (a killed run keeps
            # them, and the same command goes through them again without the model)
            replay = [e for _, rec in sorted((int(p.split()[-1]), r)
                                             for p, r in steps.done.items())
                      for e in rec.get("evaluations", ())]
            if steps.done and not args.json:
                print(f"resuming: {len(steps.done)} finished selection steps kept beside "
                      f"{args.out} ({len(replay)} model evaluations read back)", flush=True)
            # the user's input is refused as ToothfemError where it is read; a plain
            # ValueError from the model is a bug (exit 3), never called bad input
            result = run_te_loop(case, te=args.te or None, hysteresis=args.hysteresis,
                                 name_pattern=args.name_pattern,
                                 settings=Settings(folds=args.folds),
                                 candidates="all" if chosen == ["all"] else chosen,
                                 model=model, progress=not args.json,
                                 on_step=lambda i, rec: _keep_step(steps, i, rec),
                                 replay=replay)
        summary = result.summary()
        summary["case_file"] = str(args.case)
        _write(args, case, result, summary)
    if args.json:
        print(json.dumps(summary, indent=2, default=json_default))
        return 0
    _print(result, args)
    return 0


def _keep_step(steps, index: int, record: dict) -> None:
    """A finished selection step into the journal; a step gone through again on resuming
    keeps the evaluations its first run made (none are made again)."""
    earlier = steps.done.get(f"step {index}")
    if earlier:
        record = {**record, "evaluations": list(earlier.get("evaluations", ()))
                  + list(record.get("evaluations", ()))}
    steps.record(f"step {index}", record)


def _write(args, case, result, summary: dict) -> None:
    """The report folder, written whole (the finished result replaces the steps' journal);
    ``summary`` is report.json."""
    from ..output import atomic_dir
    from . import json_default
    from ..report import html as report_html, save, te as report_te

    with atomic_dir(args.out) as tmp:
        summary["case_file"] = str(args.case)
        files = []
        if result.hysteresis is not None:
            save(report_te.hysteresis(result), tmp / "hysteresis.png", dpi=110)
            files.append("hysteresis.png")
        if result.te_figures is not None:
            if any(r.kind == "amplitude" for r in result.layout.rows):
                save(report_te.spectrum(result), tmp / "spectrum.png", dpi=110)
                files.append("spectrum.png")
            fig = report_te.widths(result)
            if fig is not None:
                save(fig, tmp / "widths.png", dpi=110)
                files.append("widths.png")
        (tmp / "report.json").write_text(json.dumps(summary, indent=2, default=json_default) + "\n")
        (tmp / "report.md").write_text(report_te.markdown(result, files=files))
        report_html.write_report(tmp, case, command="te-loop", case_file=args.case)


def _print(result, args) -> None:
    """What the screen shows."""
    loop = result.loop
    replayed = f" (and {loop.replayed} read back from the steps kept)" if loop.replayed else ""
    print(f"{result.case_name}: {result.elapsed_s:.0f} s, {result.evaluations} model "
          f"evaluations{replayed}; {len(loop.observations.values)} observed figures; held-out "
          f"error {loop.baseline.cv_wrmse:.3g} -> {loop.final.cv_wrmse:.3g} sigma; effects: "
          + (", ".join(f"{n} ({', '.join(f'{v:.3g}' for v in loop.final.values[n])})"
                       for n in loop.added) or "none"))
    for name, group in loop.alias_groups.items():
        if group:
            print(f"  {name} is aliased with {', '.join(group)}: the report names the "
                  "measurement that tells each apart")
    print(f"  {loop.stop_reason}")
    for line in running_lines(result):
        print(f"  {line}")
    if loop.failures:
        print(f"  {loop.failure_note()}")
    costly = [n for n, why in result.not_considered.items() if why]
    if costly:
        print(f"  not considered (costly): {', '.join(costly)}; --effects names them, "
              "--effects all takes every effect (report.md says what each costs)")
    for r in result.refused:
        print(f"  refused: {r}")
    print(f"wrote {(Path(args.out) / 'report.md').resolve()}")


def running_lines(result) -> list:
    """The running widths' datasheet, measured beside the model's before and after the loop
    (or why there is none), one line each.

    Parameters
    ----------
    result : toothfem.efficiency.loop.te.loop.TeLoopResult

    Returns
    -------
    list of str
    """
    if result.running is None:
        return [f"no rigidity from the running widths: {result.running_note}"] \
            if result.te_figures is not None else []
    from ..efficiency.loop.te.running import misses
    from ..report.te import width_errors_arcsec

    out = [f"measured {line}" for line in result.running.lines()]
    for which in ("before", "after"):
        m = result.model_running(which)
        if m is not None:
            out.append(f"model {which} the loop: rigidity {m.rigidity_Nm_per_arcmin:.4g} "
                       f"N m/arcmin, lost-motion intercept "
                       f"{m.lost_motion_intercept_arcmin:.4g} arcmin")
    after = result.model_running("after")
    if after is not None:
        out += misses(result.running, after)
    err = width_errors_arcsec(result)
    if err is not None:
        out.append(f"widths' RMS error {err[0]:.3g} arcsec before the loop, {err[1]:.3g} "
                   "arcsec after")
    return out
