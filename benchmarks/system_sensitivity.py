"""Which assumed part holds how much of the compliance (issue 21): the sensitivity table of
the system model (fem/drives/assembly.py) for the RV-40E case and the pin-housing drive.

For each group of the model (the disc-pin mesh, the crank bearings, the crankshafts'
support bearings, their bending and torsion, the spur mesh of the first stage):

(a) its share of the compliance 50-100 % of the rated torque, from the datasheet
    (``toothfem.datasheet.stiffness_analysis(case).summary["compliance_shares"]``);
(b) the drive's torsional rigidity 50-100 % with that group made rigid;
(c) the rigidity with that group's stiffness halved (its deflection doubled at the same
    load), each by the change stated in HALVED below;

and whether the group's inputs are assumed (the case's ``Supports.assumed``, the model's
own constants, the case file's ASSUMPTION marks). Nothing is tuned: the figures are the
cases as shipped.

How each group is made rigid (b):
- mesh: the FE influence tables replaced by rigid bodies on equal contact springs of
  1e-14 m/N per pin (``pin_spring_m_per_N``; a pin contact is ~1e-9 m/N): the pins are
  rigid and the load shares as on rigid bodies;
- every other group: the model's ``rigid`` option (RIGID_STIFFNESS, 1e14 N/m).

How each is halved (c), the rest of the model unchanged:
- mesh: the contact flexibility of the FE tables (the discs' and pins' condensed
  compliance and each contact's Hertz approach, ``CycleSolver.compliance``) doubled in this
  script (wrapped for the run, restored after): E of disc and pins halved would do the same
  to the mesh alone;
- crank bearings: ``bearing_roller_length`` x 2^-1.25 (Palmgren's delta ~ l^-0.8: at the
  same load the deflection doubles);
- support bearings: the model's assumed tapered-roller length (SUPPORT_LENGTH_REL x the
  crank's diameter) x 2^-1.25 on the built model's support bearing (same law);
- crankshaft bending: the model's bending stiffness matrix (Euler-Bernoulli + Timoshenko
  shear) x 0.5; through the supports this is ``crankshaft_diameter`` x 2^-0.25, which also
  halves the torsion and shortens the support rollers, so the row "crankshaft diameter x
  2^-0.25" is given beside it as the supports-level change;
- crankshaft torsion: the model's torsion stiffness x 0.5 (the same diameter change, or the
  torsion length doubled);
- spur mesh: the mesh stiffness (ISO 6336-1's c_gamma x face width) x 0.5 (the face width
  halved).

Run from the project's venv:

    .venv/bin/python benchmarks/system_sensitivity.py [--positions 36] [--cases rv40e ...]

Prints a Markdown table per case and writes benchmarks/results/system_sensitivity.json.
"""
import argparse
import contextlib
import dataclasses
import json
import sys
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from toothfem.case import load_case  # noqa: E402
from toothfem.datasheet import stiffness_analysis  # noqa: E402
from toothfem.fem.datasheet.sheet import datasheet  # noqa: E402
from toothfem.fem.contact import ContactError  # noqa: E402
from toothfem.fem.drives import drive_for  # noqa: E402
from toothfem.fem.drives import assembly as sc  # noqa: E402
from toothfem.fem.system.datasheet import SystemTwist  # noqa: E402

OUT_PATH = ROOT / "benchmarks" / "results" / "system_sensitivity.json"
CASES = {"rv40e": ROOT / "cases" / "rv40e.toml",
         "cycloid_pinhousing": ROOT / "cases" / "cycloid_pinhousing.toml"}
#: The groups in the order of the table: the mesh (the FE contact) and fem.drives.assembly.GROUPS.
MESH = "mesh"
#: Rigid pins on equal springs [m/N] (the mesh made rigid).
RIGID_PIN_SPRING = 1e-14
#: Palmgren: deflection ~ l^-0.8 at a given load; the roller length that doubles it.
HALF_ROLLER_LENGTH = 2 ** -1.25
#: Round shaft: bending and torsion stiffness ~ d^4; the diameter that halves both.
HALF_SHAFT_DIAMETER = 2 ** -0.25
#: Nabtesco RV-40E (RV-E series catalogue): torsional rigidity of the size class
#: 108-113 N m/arcmin at a rated torque of 412 N m (the brief's range; the catalogue's
#: 50-100 % secant definition, the same as ours).
RV40E_CATALOGUE_NM_PER_ARCMIN = (108.0, 113.0)

HALVED = {
    MESH: "FE contact flexibility x 2 (disc, pins, Hertz)",
    "crank bearings": "roller length x 2^-1.25 (Palmgren)",
    "support bearings": "support roller length x 2^-1.25 (Palmgren)",
    "crankshaft bending": "bending stiffness x 0.5 (= d x 2^-0.25 on bending alone)",
    "crankshaft torsion": "torsion stiffness x 0.5 (= d x 2^-0.25 on torsion alone)",
    "spur mesh": "mesh stiffness x 0.5 (= face width x 0.5)",
}


def groups():
    return (MESH,) + tuple(sc.GROUPS)


def _rigidity(system, rated) -> tuple:
    """(rigidity 50-100 % [N m/arcmin], compliance per path [arcmin/(N m)]) of a model."""
    sheet = datasheet(SystemTwist(system), rated)
    return float(sheet.rigidity_Nm_per_arcmin), dict(sheet.compliance_arcmin_per_Nm)


@contextlib.contextmanager
def _mesh_flexibility_scaled(system, factor):
    """Each disc's FE contact flexibility times ``factor`` for the duration (the cycle
    solvers may be shared through the drive's memo: restored after)."""
    solvers = {id(s.solver): s.solver for s in system.slots}
    for solver in solvers.values():
        original = solver.compliance

        def scaled(*args, _f=original, **kwargs):
            return factor * _f(*args, **kwargs)
        solver.compliance = scaled
    try:
        yield system
    finally:
        for solver in solvers.values():
            del solver.compliance       # back to the class's method


def _system(drive, supports, positions, **options):
    return drive.system_model(supports, positions, **options)


#: Where the ``rigid`` option's 1e14 stiffness does not converge, a linear group is made
#: this many times stiffer instead (near rigid: its compliance 1e-4 of its own).
NEAR_RIGID = 1e4
LINEAR_ATTRIBUTE = {"crankshaft bending": "bending_stiffness",
                    "crankshaft torsion": "torsion_stiffness",
                    "spur mesh": "spur_stiffness"}
FAILURES = []


def rigid_rigidity(drive, supports, positions, rated, group) -> float:
    if group == MESH:
        for spring in (RIGID_PIN_SPRING, 1e-12):
            try:
                return _rigidity(_system(drive, supports, positions,
                                         pin_spring_m_per_N=spring), rated)[0]
            except ContactError as exc:
                FAILURES.append(f"{drive.kind} mesh rigid (pin springs {spring:g} m/N): {exc}"
                                + ("; retried with 1e-12 m/N" if spring != 1e-12 else ""))
        raise ContactError("the mesh made rigid does not converge")
    try:
        return _rigidity(_system(drive, supports, positions, rigid=(group,)), rated)[0]
    except ContactError as exc:
        FAILURES.append(f"{drive.kind} rigid={group!r}: {exc}")
        if group not in LINEAR_ATTRIBUTE:
            raise
        system = _system(drive, supports, positions)
        name = LINEAR_ATTRIBUTE[group]
        setattr(system, name, NEAR_RIGID * getattr(system, name))
        FAILURES[-1] += f"; taken as {name} x {NEAR_RIGID:g} instead"
        return _rigidity(system, rated)[0]


def halved_rigidity(drive, supports, positions, rated, group):
    """The rigidity with the group's stiffness halved (HALVED), or None if the group is not
    in the drive (e.g. no first stage)."""
    if group == "crank bearings":
        sup = dataclasses.replace(supports, bearing_roller_length_m=(
            supports.bearing_roller_length_m * HALF_ROLLER_LENGTH))
        return _rigidity(_system(drive, sup, positions), rated)[0]
    system = _system(drive, supports, positions)
    if group in getattr(system, "rigid", ()):
        return None                      # the drive has no such part (taken rigid)
    if group == MESH:
        with _mesh_flexibility_scaled(system, 2.0):
            return _rigidity(system, rated)[0]
    if group == "support bearings":
        system.support_bearing = dataclasses.replace(
            system.support_bearing,
            length_m=system.support_bearing.length_m * HALF_ROLLER_LENGTH)
    elif group == "crankshaft bending":
        system.bending_stiffness = 0.5 * system.bending_stiffness
    elif group == "crankshaft torsion":
        system.torsion_stiffness = 0.5 * system.torsion_stiffness
    elif group == "spur mesh":
        system.spur_stiffness = 0.5 * system.spur_stiffness
    else:
        raise ValueError(group)
    return _rigidity(system, rated)[0]


def assumed_inputs(case_path, drive, supports) -> dict:
    """Per group: which inputs are assumed, and by whom (the case's Supports.assumed, the
    model's constants, the case file's ASSUMPTION marks)."""
    text = Path(case_path).read_text()
    lines = text.splitlines()

    def section_assumed(name):
        """The case file's [name] header or its keys marked ASSUMPTION."""
        inside, marks = False, []
        for ln in lines:
            s = ln.strip()
            if s.startswith("["):
                inside = s.split("]")[0].strip("[") == name
                if inside and "ASSUMPTION" in s:
                    marks.append("the whole section")
                continue
            if inside and "ASSUMPTION" in s and "=" in s:
                marks.append(s.split("=")[0].strip())
        return marks

    a = set(supports.assumed)
    cyc = [f"[cycloid] {m}" for m in section_assumed("cycloid")] + \
        [f"[cycloid.disc_holes] {m}" for m in section_assumed("cycloid.disc_holes")]
    fs = section_assumed("first_stage")
    stage = getattr(drive.path, "first_stage", None)     # a 2K-V drive's spur stage
    out = {
        MESH: {"assumed": bool(cyc), "what": (
            "case " + ", ".join(cyc)) if cyc else "the case's geometry"},
        "crank bearings": {
            "assumed": bool(a & {"bearing_roller_count", "bearing_roller_length_m",
                                 "bearing_roller_diameter_m"}),
            "what": "rollers " + ", ".join(
                f"{k[len('bearing_roller_'):]}{' (ASSUMED)' if k in a else ''}"
                for k in ("bearing_roller_count", "bearing_roller_length_m",
                          "bearing_roller_diameter_m"))
            + f": {supports.bearing_roller_count} x "
              f"{1e3 * supports.bearing_roller_diameter_m:.2f} x "
              f"{1e3 * supports.bearing_roller_length_m:.1f} mm"},
        "support bearings": {
            "assumed": True,
            "what": f"the model's constant: {sc.SUPPORT_ROLLERS} tapered rollers "
                    f"{sc.SUPPORT_LENGTH_REL} d long at {sc.SUPPORT_ANGLE_DEG:g} deg, on "
                    f"the crank's diameter"
                    + (" (ASSUMED)" if "crankshaft_diameter_m" in a else "")},
        "crankshaft bending": {
            "assumed": bool(a & {"crankshaft_diameter_m", "crankshaft_span_m"}),
            "what": f"d {1e3 * supports.crankshaft_diameter_m:.2f} mm"
                    f"{' (ASSUMED)' if 'crankshaft_diameter_m' in a else ''}, span "
                    f"{1e3 * supports.crankshaft_span_m:.1f} mm"
                    f"{' (ASSUMED)' if 'crankshaft_span_m' in a else ''}"},
        "crankshaft torsion": {
            "assumed": bool(a & {"crankshaft_diameter_m", "crankshaft_span_m"}),
            "what": "the same shaft over half its span"},
        "spur mesh": {
            "assumed": True,
            "what": "ISO 6336-1 c_gamma = 20 N/(mm um) (a constant)"
                    + (f"; case [first_stage]: {', '.join(fs)}" if fs else "")
                    + ("" if stage is None or
                       getattr(stage, "face_width_m", None) is None else
                       f"; face width {1e3 * stage.face_width_m:.1f} mm")},
    }
    if "carrier_stiffness_Nm_per_rad" in a:
        out["carrier"] = {"assumed": True, "what": "no carrier stiffness given: rigid"}
    return out


def analyse(name, case_path, positions, te_samples, te_positions, progress=print) -> dict:
    FAILURES.clear()
    t0 = time.perf_counter()
    case = load_case(case_path)
    res = stiffness_analysis(case, positions=positions, te_samples=te_samples,
                             te_positions=te_positions)
    summary = res.summary
    t_sheet = time.perf_counter() - t0
    progress(f"{name}: datasheet {t_sheet:.1f} s")
    drive = drive_for(case)
    si = case.to_si()
    supports = drive.supports(si.supports)
    rated = float(summary["rated_torque_Nm"])
    base_rigidity, base_paths = _rigidity(_system(drive, supports, positions), rated)
    shares = summary["compliance_shares"]
    assumed = assumed_inputs(case_path, drive, supports)
    rows = {}
    for g in groups():
        t1 = time.perf_counter()
        probe = _system(drive, supports, positions)
        absent = g != MESH and g in getattr(probe, "rigid", ())
        row = {"share": float(shares.get(g, 0.0)),
               "absent": bool(absent),
               "rigid_Nm_per_arcmin": None if absent else
               rigid_rigidity(drive, supports, positions, rated, g),
               "halved_Nm_per_arcmin": None if absent else
               halved_rigidity(drive, supports, positions, rated, g),
               "halved_by": HALVED[g],
               **assumed[g]}
        rows[g] = row
        progress(f"  {g}: {time.perf_counter() - t1:.1f} s")
    # the supports-level change of the crankshaft: diameter x 2^-0.25
    sup_d = dataclasses.replace(supports, crankshaft_diameter_m=(
        supports.crankshaft_diameter_m * HALF_SHAFT_DIAMETER))
    diameter_rigidity = _rigidity(_system(drive, sup_d, positions), rated)[0]
    # everything around the mesh rigid, and the mesh alone (what the supports cost)
    try:
        all_rigid = _rigidity(_system(drive, supports, positions,
                                      rigid=tuple(sc.GROUPS)), rated)[0]
    except ContactError as exc:
        FAILURES.append(f"every group rigid: {exc}")
        all_rigid = None
    out = {
        "case": case.name,
        "rated_torque_Nm": rated,
        "rated_torque_assumed": bool(summary["rated_torque_assumed"]),
        "positions": positions,
        "datasheet_rigidity_Nm_per_arcmin": float(summary["torsional_rigidity_Nm_per_arcmin"]),
        "rigidity_Nm_per_arcmin": base_rigidity,
        "compliance_arcmin_per_Nm": base_paths,
        "compliance_shares": {k: float(v) for k, v in shares.items()},
        "lost_motion_arcmin": float(summary["lost_motion_arcmin"]),
        "backlash_arcmin": float(summary["backlash_arcmin"]),
        "supports": summary["supports"],
        "groups": rows,
        "crankshaft_diameter_x_2^-0.25_Nm_per_arcmin": diameter_rigidity,
        "every_group_rigid_Nm_per_arcmin": all_rigid,
        "summary_keys": sorted(summary),
        "solver_failures": list(FAILURES),
        "seconds": {"datasheet": t_sheet, "total": time.perf_counter() - t0},
    }
    return out


def markdown(res) -> str:
    lines = [f"**{res['case']}** — rated {res['rated_torque_Nm']:g} N m"
             f"{' (assumed)' if res['rated_torque_assumed'] else ''}; torsional rigidity "
             f"50-100 % {res['datasheet_rigidity_Nm_per_arcmin']:.1f} N m/arcmin (datasheet; "
             f"{res['rigidity_Nm_per_arcmin']:.1f} from the loop alone), lost motion "
             f"{res['lost_motion_arcmin']:.3f} arcmin, {res['positions']} positions",
             "",
             "| group | share of compliance | rigid: rigidity [N m/arcmin] | "
             "halved: rigidity [N m/arcmin] | halved by | inputs | assumed |",
             "|---|---:|---:|---:|---|---|---|"]
    base = res["rigidity_Nm_per_arcmin"]

    def cell(v):
        return "—" if v is None else f"{v:.1f} ({100 * (v / base - 1):+.1f} %)"
    for g, r in res["groups"].items():
        share = "not in drive" if r["absent"] else f"{100 * r['share']:.1f} %"
        lines.append(
            f"| {g} | {share} | "
            f"{cell(r['rigid_Nm_per_arcmin'])} | {cell(r['halved_Nm_per_arcmin'])} | "
            f"{r['halved_by']} | {r['what']} | {'ASSUMED' if r['assumed'] else 'case'} |")
    lines.append(f"| (supports) crankshaft diameter x 2^-0.25 | | | "
                 f"{cell(res['crankshaft_diameter_x_2^-0.25_Nm_per_arcmin'])} | bending and "
                 f"torsion halved, support rollers 0.84x | | |")
    lines.append("| (all groups but the mesh rigid) | | "
                 f"{cell(res['every_group_rigid_Nm_per_arcmin'])} | | | | |")
    sup = res["supports"]
    def value(v):
        return "—" if v["value"] is None else f"{v['value']:.4g}"
    lines += ["", "supports table (summary): " + "; ".join(
        f"{k} = {value(v)}{' (assumed)' if v['assumed'] else ''}" for k, v in sup.items())]
    return "\n".join(lines)


def rv40e_gap(res) -> str:
    """Our RV-40E figure against the catalogue's, and what the assumed parts would have to
    do to close the gap (nothing is tuned)."""
    lo, hi = RV40E_CATALOGUE_NM_PER_ARCMIN
    k = res["datasheet_rigidity_Nm_per_arcmin"]
    c = 1.0 / k
    c_cat = (1.0 / hi, 1.0 / lo)
    lines = [f"RV-40E catalogue torsional rigidity {lo:g}-{hi:g} N m/arcmin (Nabtesco RV-E, "
             f"rated 412 N m); ours {k:.1f} N m/arcmin ({100 * (k / (0.5 * (lo + hi)) - 1):+.0f} % "
             f"against the middle). Compliance ours {c:.5f}, catalogue "
             f"{c_cat[0]:.5f}-{c_cat[1]:.5f} arcmin/(N m)."]
    delta = c - c_cat[1], c - c_cat[0]
    if delta[0] > 0:
        lines.append(f"Too soft by {delta[0]:.5f}-{delta[1]:.5f} arcmin/(N m); the assumed "
                     "groups' compliances (arcmin/(N m)) that could hold it:")
    else:
        lines.append(f"Too stiff by {-delta[1]:.5f}-{-delta[0]:.5f} arcmin/(N m): a "
                     "compliance the model lacks (the carrier, the main bearings, the disc "
                     "between its holes, the housing), or assumed groups stiffer than real, "
                     "would have to add it:")
    comp = res["compliance_arcmin_per_Nm"]
    for g, r in res["groups"].items():
        if r["absent"]:
            continue
        cg = comp.get(g, 0.0)
        need = "" if delta[0] <= 0 else (
            f"; alone it would have to fall by {100 * delta[0] / cg:.0f}-{100 * delta[1] / cg:.0f} %"
            if cg > delta[0] else "; too small to close the gap alone")
        lines.append(f"- {g}: {cg:.5f} ({100 * r['share']:.1f} %), "
                     f"{'ASSUMED' if r['assumed'] else 'case'}: {r['what']}{need}")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--positions", type=int, default=36,
                    help="positions per pin pitch (the datasheet's default, 36)")
    ap.add_argument("--te-samples", type=int, default=6)
    ap.add_argument("--te-positions", type=int, default=12)
    ap.add_argument("--out", default=str(OUT_PATH))
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    results = {}
    for name in args.cases:
        res = analyse(name, CASES[name], args.positions, args.te_samples, args.te_positions)
        results[name] = res
        print()
        print(markdown(res))
        for f in res["solver_failures"]:
            print(f"note: {f}")
        if name == "rv40e":
            print()
            print(rv40e_gap(res))
        print()
    results["seconds"] = time.perf_counter() - t0
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(results, indent=2, default=float))
    print(f"written {args.out} ({results['seconds']:.0f} s)")


if __name__ == "__main__":
    main()
