"""The pipeline as Python calls: contact analysis of a case and the whole run.

``run_case(case, out)`` is what ``toothfem run`` does (geometry, FE contact, efficiency with
analytic and FE loads side by side, curves and maps, report.md); ``contact_analysis`` is
what ``toothfem contact`` does. Both work for every drive through
:func:`toothfem.fem.drives.drive_for`; the CLI only parses arguments and prints. The files
they write (contact, geometry, efficiency charts, the run): :mod:`toothfem.report.files`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import durability, limits
from .bars import no_stage
from .case import Case, as_case
from .datasheet import TE_DEFINITION, StiffnessResult, stiffness_analysis
from .efficiency import evaluate, operating_point
from .efficiency.drive_losses import loss_sources
from .efficiency.mesh_table import LoadsMemo
from .layouts.cycloid import reducer_backlash
from .errors import CaseError, check_range
from .face_width import sliced_contact
from .fem.drives import MAX_POSITIONS, drive_for
from .fem.elastic import Body
from .fem.load_sharing import LoadSharing
from .fem.system.datasheet import SystemTwist
from .maps import EfficiencyMaps, efficiency_maps
from .output import atomic_dir, reserved, target
from .output_pins import output_pin_summary
from .report.files import write_run
from .units import ARCSEC, MPA_PER_PA, PA_PER_MPA

MODES = ("cycle", "detailed")
FIELDS = ("detailed", "structural", "none")
#: Points per pin or ring tooth of the fixed member's outlines drawn over a field.
OUTLINE_POINTS_PER_TOOTH = 128

if TYPE_CHECKING:   # annotations only: each drive imports its own detailed mode
    from .fem.contracts import DetailedSolution


@dataclass(frozen=True, kw_only=True)
class ContactResult:
    """FE load sharing of a case over one meshing period, and the field at its worst
    position (``body``/``displacement`` None without a field)."""
    case_name: str
    mode: str
    load_sharing: LoadSharing
    positions_rad: np.ndarray
    worst: int                      # index of the position with the largest force
    detail: DetailedSolution | None   # at the worst position
    body: Body | None
    displacement: np.ndarray | None
    member_point: np.ndarray        # worst contact in the member's frame, m
    member_name: str                # "disc" | "planet"
    summary: dict
    contact_name: str = "contact"   # "pin" | "tooth" (the drive's words, for labels)
    contacts_name: str = "contacts"  # "pins" | "teeth"
    members: int = 1                # moving members sharing the output torque
    outlines: tuple = ()            # fixed member's outlines, member frame at worst, (2, N) m
    sliced: Any = None              # the face width in slices (SlicedSharing), or None

    def table(self, published=None) -> list:
        """The contact summary's rows, the case's published figures beside.

        Parameters
        ----------
        published : mapping, optional
            The case's ``[published]`` table.

        Returns
        -------
        list of (quantity, unit, {column: value})
            (:func:`toothfem.report.summary.contact_rows`).
        """
        from .report.files import contact_labels
        from .report.summary import contact_rows
        return contact_rows(self.summary, contact_labels(self), published)

    def plot(self) -> dict:
        """The contact's pictures over the period.

        Returns
        -------
        dict
            File name -> matplotlib Figure (:func:`toothfem.report.files.contact_figures`).
        """
        from .report.files import contact_figures
        return contact_figures(self)

    def write(self, folder) -> dict:
        """load_sharing.csv, the pictures, the VTU field and summary.json into an existing
        ``folder``.

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary with its file list (:func:`toothfem.report.files.write_contact`).
        """
        from .report.files import write_contact
        return write_contact(self, folder)


def _output_torque(case: Case, torque_Nm) -> float:
    """The output torque of a contact analysis: given, or the case's operating point."""
    if torque_Nm is not None:
        return float(check_range("torque_Nm", torque_Nm, 0, None, lo_open=True,
                                 error=CaseError))
    return float(operating_point(case)[1])


def contact_analysis(case: Case, *, positions: int = 36, torque_Nm: float | None = None,
                     mode: str = "cycle", pins: str | None = None, field: str = "detailed",
                     progress=None) -> ContactResult:
    """FE load sharing over one meshing period.

    Parameters
    ----------
    case : toothfem.case.Case
    positions : int
        Meshing positions over one period.
    torque_Nm : float, optional
        Reducer output torque [N m]; default the case's operating point. The member carries
        :meth:`~toothfem.fem.drives.Drive.member_torque` of it.
    mode : {"cycle", "detailed"}
        Influence coefficients + Hertz (fast), or two-body FE contact at every position.
    pins : {"conventional", "integral", "rigid"}, optional
        Pin structure of a cycloid drive (default the case's); not for the sine pair.
    field : {"detailed", "structural", "none"}
        Stress field at the worst position (the sine pair has no structural field of its
        own: it always uses the detailed mode).
    progress : callable, optional
        Wraps the iterable of positions (a progress bar).

    Returns
    -------
    ContactResult

    Raises
    ------
    CaseError
        If ``positions`` is outside its range, ``mode``, ``field`` or ``pins`` is unknown,
        or ``pins`` is given for a sine pair.
    """
    case = as_case(case)
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    if mode not in MODES:
        raise CaseError(f"mode = {mode!r} is not one of {list(MODES)}")
    if field not in FIELDS:
        raise CaseError(f"field = {field!r} is not one of {list(FIELDS)}")
    drive = drive_for(case)
    overrides: dict[str, Any] = {}      # the FE model's own options
    if pins is not None:
        choices = drive.fe_options.get("pin_structure")
        if choices is None:
            raise CaseError(f"--pins applies to cycloid drives, not to the {drive.kind} pair")
        if pins not in choices:
            raise CaseError(f"pins = {pins!r} is not one of {list(choices)}")
        overrides["pin_structure"] = pins
    output = _output_torque(case, torque_Nm)
    torque = drive.member_torque(output)
    phis = drive.positions(positions)
    detail = body = u = sliced = None
    if mode == "cycle":
        solver = drive.cycle_solver(positions, **overrides)
        model = solver.model
        ls = solver.solve(torque, progress=progress)
        sliced = sliced_contact(drive, solver, torque, mode)   # face_slices > 1 (issue 43)
        ls = ls if sliced is None else sliced.load_sharing
        worst = int(np.argmax(ls.force.max(axis=1)))
        if field == "structural" and solver.has_structural_field:
            body, u = solver.structural_field(worst, ls)
        elif field != "none":       # the pair's own detailed field
            detail = drive.solve_detailed(model, phis[worst], torque)
    else:
        sliced_contact(drive, None, torque, mode)       # refuses slices in the detailed mode
        model = drive.fe_model(**overrides)
        results = [drive.solve_detailed(model, phi, torque)
                   for phi in (progress or iter)(phis)]
        ls = stack_records([r.load_sharing for r in results])
        worst = int(np.argmax(ls.force.max(axis=1)))
        detail = results[worst]
    if detail is not None and field != "none":
        body, u = detail.member_body, detail.member_displacement
    k = int(np.argmax(ls.force[worst]))
    point = drive.member_frame_point(model, phis[worst], ls.point[worst, k])
    outlines = tuple(drive.member_frame_point(model, phis[worst], o)
                     for o in drive.fixed_outlines(OUTLINE_POINTS_PER_TOOTH)) \
        if body is not None else ()
    many = drive.contacts_name
    summary = {
        "case": case.name, "mode": mode, "positions": int(positions),
        "output_torque_Nm": output, f"{drive.member_name}_torque_Nm": torque,
        **reducer_backlash(case, model.describe()),
        **ls.figures(many),
        f"{many}_in_contact_min": int(ls.contacts_per_position.min()),
        "transmission_error_ripple_arcsec": float(np.ptp(ls.transmission_error) / ARCSEC),
        "torque_equilibrium_max_rel_error": float(np.max(np.abs(ls.torque_residual()))),
        "worst_position_deg": float(np.degrees(phis[worst])),
        "hertz_invalid_contacts": int(np.sum(ls.hertz_invalid)),
        "ph_from_fe_contacts": int(np.sum(ls.pressure_from_fe)),
        **({} if sliced is None else sliced.edge_figures()),
    }
    if torque_Nm is None and not case.operating.output_torque_Nm:
        summary["operating_point_from"] = "analytic loads, power_flow"   # as run's
    si = case.to_si()
    # the reducer, on the same pin structure as the held member (--pins)
    system = drive.system_model(drive.supports(si.supports), phis.size, **overrides)
    summary.update(reducer_te(system, output))
    if summary.get("interference_before_load_um", 0) > 0:
        summary.update(assembly_preload(system, si.material))
    found = limits.rated_torque(si, output) + limits.contact_pressure(
        f"the {drive.contact_name} contacts, one {drive.member_name} held",
        summary["max_ph_MPa"], si.material)
    found += limits.contact_pressure(f"the {drive.contact_name} contacts in the reducer",
                                     summary["max_ph_reducer_MPa"], si.material)
    pins_out, pins_found = output_pin_summary(system, si, output)   # K-H-V, the sine pair
    summary.update(pins_out)
    summary["warnings"] = [w.as_dict() for w in found + pins_found]
    if mode == "cycle" and detail is not None:
        fd = detail.load_sharing.force[0]
        summary["detailed_check_at_worst_position"] = {
            "max_force_N": float(fd.max()),
            "max_ph_MPa": float(detail.load_sharing.ph.max() / PA_PER_MPA),
            "max_force_ratio_detailed_to_cycle": float(fd.max() / ls.force[worst].max()),
            "dofs": int(detail.dofs)}
    return ContactResult(case_name=case.name, mode=mode, load_sharing=ls, positions_rad=phis,
                         worst=worst, detail=detail, body=body, displacement=u,
                         member_point=point, member_name=drive.member_name, summary=summary,
                         contact_name=drive.contact_name, contacts_name=many,
                         members=drive.members, outlines=outlines, sliced=sliced)


def reducer_te(system, output_torque_Nm: float) -> dict:
    """The transmission error of the whole reducer at an output torque over one pitch,
    and the pin contacts' part of it, from the system model (the one TE every command
    names, docs/stiffness.md).

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
        The drive's system model over the pitch's positions.
    output_torque_Nm : float
        [N m].

    Returns
    -------
    dict
        ``transmission_error_reducer_arcsec`` (mean), its ``..._ripple_arcsec`` (peak to
        peak) and ``transmission_error_reducer_mesh_arcsec`` (the mesh's part, mean); the
        largest contact force and Hertz pressure over every member as the system carries
        them (``max_force_reducer_N``, ``max_ph_reducer_MPa``: each member free on its
        supports, the split solved).
    """
    twist = SystemTwist(system)
    point = twist.at(output_torque_Nm)
    states = twist.states(output_torque_Nm)
    records = [system.member_record(j, states) for j in range(system.discs)]
    arcsec = 1 / ARCSEC
    worst = max(range(len(records)), key=lambda j: float(np.max(records[j].ph)))
    return {"max_force_reducer_N": float(max(np.max(r.force) for r in records)),
            "max_ph_reducer_MPa": float(max(np.max(r.ph) for r in records)) * MPA_PER_PA,
            "max_ph_reducer_contact": {"member": worst + 1,
                                       **durability.peak_contact(records[worst])},
            "transmission_error_reducer_arcsec": float(point.total.mean() * arcsec),
            "transmission_error_reducer_ripple_arcsec": float(np.ptp(point.total) * arcsec),
            "transmission_error_reducer_mesh_arcsec": float(point.paths["mesh"].mean()
                                                            * arcsec),
            "transmission_error_reducer_definition": TE_DEFINITION}


def assembly_preload(system, material) -> dict:
    """The pin forces an interfering disc carries before any load, from the system model
    at a vanishing output torque (every pin of both flanks a candidate), with their Hertz
    pressure; a warning where that pressure passes the material's contact-fatigue limit
    (the disc is preloaded into fatigue before it carries anything), a refusal where it
    passes the static limit (it cannot be put on its pins without denting them).

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
        The drive's system model over the pitch's positions.
    material : toothfem.si.MaterialSI
        Its contact-stress limits.

    Returns
    -------
    dict
        ``preload_force_max_N``, ``preload_ph_max_MPa`` (over the positions and discs).

    Raises
    ------
    CaseError
        Where the preload's Hertz pressure passes ``material.static_contact_stress_MPa``
        (ISO 76:2006).
    """
    import warnings

    states = SystemTwist(system).states(0.0, 1)
    force, ph = 0.0, 0.0
    for j in range(system.discs):
        rec = system.member_record(j, states)
        force, ph = max(force, float(np.max(rec.force))), max(ph, float(np.max(rec.ph)))
    what = (f"the disc's interference with its pins before load presses them with up to "
            f"{force:.4g} N, P_h {ph * MPA_PER_PA:.4g} MPa, before any load (`toothfem check` "
            "names the pins)")
    if ph > material.static_contact_stress_Pa:
        raise CaseError(f"{what}: beyond the static limit "
                        f"{material.static_contact_stress_Pa * MPA_PER_PA:g} MPa (ISO 76:2006, "
                        "material.static_contact_stress_MPa): the disc cannot be put on its "
                        "pins without denting them")
    if ph > material.allowable_contact_stress_Pa:
        warnings.warn(f"{what}: beyond the contact-fatigue limit "
                      f"{material.allowable_contact_stress_Pa * MPA_PER_PA:g} MPa (ISO 281:2007, "
                      "material.allowable_contact_stress_MPa)", stacklevel=2)
    return {"preload_force_max_N": force, "preload_ph_max_MPa": ph * MPA_PER_PA}


def stack_records(records):
    """One LoadSharing of several one-position records (concatenated over positions).

    Parameters
    ----------
    records : sequence of LoadSharing
        One position each, in order.

    Returns
    -------
    LoadSharing
        The arrays concatenated along the position axis; scalars from the first record.
    """
    first = records[0]
    out = {}
    for f in dataclasses.fields(first):
        vals = [getattr(r, f.name) for r in records]
        out[f.name] = np.concatenate(vals, axis=0) if isinstance(vals[0], np.ndarray) \
            else vals[0]
    return type(first)(**out)


def efficiency_summary(case, speed, torque, oil_temp=None, loads="analytic",
                       method="power_flow", memo=None) -> dict:
    """The efficiency record of one operating point as a plain mapping (the JSON).

    Parameters
    ----------
    case : toothfem.case.Case
        The case.
    speed : float
        Input speed [rpm].
    torque : float
        Output torque [N m].
    oil_temp : float, optional
        Oil temperature [deg C]; None: the lubricant's reference.
    loads : {"analytic", "fem"}
        The meshing table's load source.
    method : {"power_flow", "rv_split_power"}
        As :func:`toothfem.efficiency.evaluation.evaluate`.
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met.

    Returns
    -------
    dict
        Efficiency [-], powers and losses [W], loss shares [-], mesh efficiencies and
        notes.
    """
    e = evaluate(case, speed, torque, oil_temp, loads=loads, method=method, memo=memo)
    shares = e.shares()
    return {
        "case": case.name, "loads": e.loads, "method": e.method,
        "input_speed_rpm": float(speed), "output_torque_Nm": float(torque),
        "oil_temp_C": oil_temp,
        "efficiency": float(e.efficiency[0]),
        "input_power_W": float(e.input_power_W[0]),
        "output_power_W": float(e.output_power_W[0]),
        "losses": {k: float(v[0]) for k, v in e.losses_W.items()},
        "loss_sources": loss_sources(drive_for(case), e.losses_W),
        "loss_shares": {k: float(v[0]) for k, v in shares.items()},
        "mesh_efficiency": {k: float(v[0]) for k, v in e.mesh_efficiency.items()},
        "notes": list(e.notes),
        "warnings": [w.as_dict() for w in e.warnings],
    }


@dataclass(frozen=True, kw_only=True)
class RunResult:
    """What ``run_case`` computed and where it wrote it."""
    out: Path
    report: Path
    contact: ContactResult | None
    efficiency: dict               # {source: efficiency_summary(...)} at the operating point
    speed_rpm: float
    output_torque_Nm: float
    case: Case | None = None       # the case the run analysed
    durability: dict | None = None  # {"life", "strength", "heat"}: toothfem.durability
    warning_lines: tuple | None = None  # RunAnalysis.warnings, what report.md lists

    @property
    def warnings(self) -> list:
        """Every limit the run's results pass, one line each (contact, efficiency, heat,
        strength, the measured points' gaps), each said once: report.md's list."""
        if self.warning_lines is not None:
            return list(self.warning_lines)
        return limits.run_warnings(self.contact.summary if self.contact else None,
                                   self.efficiency, self.durability or {})


def run_case(case: Case | str | Path, out, *, positions: int = 36, field: str = "structural",
             fem: bool = True, progress=None,
             as_built: int = durability.AS_BUILT_RINGS, stage=None) -> RunResult:
    """The whole pipeline of a case with its report.

    Parameters
    ----------
    case : toothfem.case.Case or path
        The case (a path is loaded).
    out : path
        Output folder, written atomically (a failed run leaves none).
    positions : int
        Meshing positions over one period of the FE contact.
    field : {"detailed", "structural", "none"}
        Stress field at the worst position.
    fem : bool
        Run the FE contact, and the efficiency with FE loads beside the analytic one.
    progress : callable, optional
        Wraps the iterable of positions (a progress bar).
    as_built : int
        Reducers built within the case's ``[tolerances]`` solved beside the nominal
        (:func:`toothfem.durability.as_built_summary`; 0: none).
    stage : callable, optional
        ``stage(name)`` is a context manager around each stage of the run
        (:func:`toothfem.bars.stage`: its time on stderr); default silent.

    Returns
    -------
    RunResult
        Contact result, efficiency at the operating point, and the report's path
        (``out/report.md`` with its PNGs, CSV tables and VTU fields; the same with every
        input, assumption and warning as one self-contained page: ``out/report.html``).
    """

    case_file = None if isinstance(case, Case) else case
    case = as_case(case)
    out = target(out)
    with reserved(out):        # checked and held before computing: a second run is refused
        run = analyse_run(case, positions=positions, field=field, fem=fem, progress=progress,
                          as_built=as_built, stage=stage)
        with (stage or no_stage)("report files"), atomic_dir(out) as tmp:
            run.write(tmp, case_file)
    return RunResult(out=out, report=out / "report.md", contact=run.contact,
                     efficiency=run.efficiency, speed_rpm=run.speed_rpm,
                     output_torque_Nm=run.output_torque_Nm, case=case,
                     durability=run.durability, warning_lines=tuple(run.warnings))


@dataclass(frozen=True, kw_only=True)
class RunAnalysis:
    """What ``run_case`` computes, before anything is written (the writer:
    :func:`toothfem.report.files.write_run`).

    Attributes
    ----------
    case : toothfem.case.Case
    contact : ContactResult or None
        The FE contact (None without ``fem``).
    datasheet : toothfem.datasheet.StiffnessResult or None
        The datasheet from the FE contact and the supports (None without ``fem``).
    efficiency : dict
        {load source: :func:`efficiency_summary`} at the operating point, with the RV
        paper's split-power method for a case with [rv].
    durability : dict
        {"heat", "life", "strength"} summaries (:mod:`toothfem.durability`).
    speed_rpm, output_torque_Nm : float
        The operating point.
    maps : toothfem.maps.EfficiencyMaps
        The efficiency over the operating range (curves and maps).
    """
    case: Case
    contact: ContactResult | None
    datasheet: StiffnessResult | None
    efficiency: dict
    durability: dict
    speed_rpm: float
    output_torque_Nm: float
    maps: EfficiencyMaps

    @property
    def warnings(self) -> list:
        """Every limit the run's results pass, one line each (:func:`limits.run_warnings`),
        with each measured efficiency of the case that misses the model."""
        return limits.run_warnings(None if self.contact is None else self.contact.summary,
                                   self.efficiency, self.durability,
                                   limits.measured_efficiency(self.case.measured,
                                                              self.maps.measured_model))

    def table(self) -> list:
        """The run's efficiency rows (a column per load source and method), then the
        contact's, the case's published figures beside.

        Returns
        -------
        list of (quantity, unit, {column: value})
        """
        from .report.summary import efficiency_rows
        rows = efficiency_rows(self.efficiency, self.case.published)
        return rows + ([] if self.contact is None else self.contact.table(self.case.published))

    def write(self, folder, case_file=None) -> None:
        """Every file of ``toothfem run`` into an existing, empty ``folder``
        (:func:`toothfem.report.files.write_run`).

        Parameters
        ----------
        folder : path
        case_file : path, optional
            The case file, named in the reports.
        """
        write_run(self, Path(folder), case_file)


def analyse_run(case: Case, *, positions: int = 36, field: str = "structural",
                fem: bool = True, progress=None,
                as_built: int = durability.AS_BUILT_RINGS, stage=None) -> RunAnalysis:
    """Every analysis of ``toothfem run``, as records (nothing written).

    Parameters
    ----------
    case : toothfem.case.Case
    positions, field, fem, progress, as_built, stage
        As :func:`run_case`.

    Returns
    -------
    RunAnalysis
    """
    stage = stage or no_stage
    contact = datasheet = None
    if fem:
        with stage("contact (FE of the disc and the system model)"):
            contact = contact_analysis(case, positions=positions, field=field,
                                       progress=progress)
        # the datasheet: stiffness, lost motion, backlash, loaded TE, member split
        with stage("datasheet (rigidity, lost motion, backlash, TE over the full period)"):
            datasheet = stiffness_analysis(case, positions=positions)
    # efficiency at the operating point, analytic and FE loads side by side; the run's
    # analyses share each load table (one memo, passed)
    memo = LoadsMemo()
    speed, torque = operating_point(case)
    sources = ["analytic"] + (["fem"] if fem else [])
    with stage("efficiency at the operating point"):
        results = {s: efficiency_summary(case, speed, torque, loads=s, memo=memo)
                   for s in sources}
        if case.rv is not None:       # the RV paper method beside ours
            results["rv_split_power"] = efficiency_summary(case, speed, torque,
                                                          method="rv_split_power")
    if not case.operating.output_torque_Nm:     # said beside each (toothfem efficiency)
        for r in results.values():
            r["operating_point_from"] = "analytic loads, power_flow"
    # life, strength and heat beside the efficiency, from the FE loads where the FE has
    # run (the strength from its contact result)
    loads = "fem" if fem else "analytic"
    with stage("heat balance, bearing life, contact strength"):
        dur = {"heat": durability.thermal_summary(case, speed, torque, loads=loads, memo=memo),
               "life": durability.life_summary(
                   case, known=None if datasheet is None else datasheet.bearings),
               "strength": durability.strength_summary(case, contact=contact, memo=memo)}
    dur["as_built"] = {}
    if fem and as_built:
        with stage(f"as built: {as_built} reducers within [tolerances] (system model)"):
            dur["as_built"] = durability.as_built_summary(case, rings=as_built,
                                                          progress=progress is not None)
    with stage("efficiency maps over the operating range"):
        maps = efficiency_maps(case, speed, torque, sources, memo)
    return RunAnalysis(case=case, contact=contact, datasheet=datasheet, efficiency=results,
                       durability=dur, speed_rpm=float(speed), output_torque_Nm=float(torque),
                       maps=maps)
