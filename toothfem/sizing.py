"""Sizing a 2K-V (RV) reducer to its maker's datasheet inside the catalogue envelope
(``toothfem size``; docs/sizing.md).

The tooth geometry (pins, lobes, pin circle, eccentricity, pin radius) and the first stage's
teeth are the case's; the sizing chooses what sets the datasheet: the first stage's module
and so the crank circle, the crank holes and their needle sets, the disc width, the
crankshafts and their span, the carrier's pillars, and the profile modification that keeps
the reducers built within ``[tolerances]`` from interfering. Each choice has a rule
(:class:`toothfem.sizing_rules.Choice`); the search is verified on the system model: every
round builds the candidate, solves it (rigidity, every bearing's life at the rated point,
the largest Hertz pressure of the reducer) and, where a target is missed, grows the part
that closes it by the closed forms of that verification (ISO 281 life with the loads held,
the carrier's compliance in series), then solves again. Where the envelope cannot hold a
target, the result says which figure binds and by how much (``binding``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .case import Case, as_case, parse_case_text, with_keys
from .errors import CaseError
from .sizing_rules import sizing_choices
from .sizing_rules import (CRANK_COUNTS, HOLE_STEP_MM, INTERFERING_MAX, MAX_ROUNDS,
                           MOD_STEP_MM, PLATE_SHARE, RING_POSITIONS, RINGS, SHOULDER_MM,
                           WEB_PER_ROOM, WIDTH_MAX_PER_RADIUS, WIDTH_STEP_MM,
                           axial_stack_mm, crank_room_mm, iso54_module, largest_crank_hole_mm,
                           pillar_diameter_mm, round_to_step, support_bearing_mm)
from .units import ARCMIN, M_PER_MM

@dataclass(frozen=True, kw_only=True)
class Targets:
    """The datasheet to meet (the case's ``[published]``, the rated point)."""
    rated_torque_Nm: float
    rated_output_speed_rpm: float
    rated_life_h: float
    rigidity_Nm_per_arcmin: float
    momentary_torque_Nm: float
    backlash_arcmin: float | None = None
    lost_motion_arcmin: float | None = None


@dataclass(frozen=True, kw_only=True)
class Round:
    """One verification on the system model: the candidate's dimensions and figures."""
    dimensions: dict
    rigidity_Nm_per_arcmin: float
    unit_l10_h: float
    limiting: str
    max_ph_MPa: float
    lost_motion_arcmin: float
    compliance_shares: dict
    missed: tuple


@dataclass(frozen=True, kw_only=True)
class SizingResult:
    """The sized reducer: its ``choices``, the ``rounds`` of the search, the final
    ``figures`` beside the ``targets``, the ``binding`` figures (empty when every target is
    met inside the envelope) and the sized ``case``."""
    case_name: str
    targets: Targets
    choices: tuple
    rounds: tuple
    figures: dict
    binding: tuple
    case: Case
    text: str = field(repr=False, default="")

    @property
    def feasible(self) -> bool:
        """Every target met inside the envelope."""
        return not self.binding

    def summary(self) -> dict:
        """The sizing as sizing.json holds it.

        Returns
        -------
        dict
        """
        from dataclasses import asdict
        return {"case": self.case_name, "feasible": self.feasible,
                "binding": list(self.binding), "targets": asdict(self.targets),
                "figures": self.figures,
                "choices": [asdict(c) for c in self.choices],
                "rounds": [asdict(r) for r in self.rounds]}

    def table(self) -> list:
        """The datasheet beside the targets, and each choice.

        Returns
        -------
        list of (quantity, unit, {column: value})
            (:func:`toothfem.report.sizing.rows`).
        """
        from .report.sizing import rows
        return rows(self.summary())

    def write(self, folder) -> dict:
        """sized_case.toml, sizing.json and report.md into an existing ``folder``.

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary with the files written (:func:`toothfem.report.sizing.write_sizing`).
        """
        from .report.sizing import write_sizing
        return write_sizing(self, folder)


# -- the targets --------------------------------------------------------------------------
def targets_of(case: Case) -> Targets:
    """The datasheet a case's ``[published]`` table states.

    Parameters
    ----------
    case : Case

    Returns
    -------
    Targets

    Raises
    ------
    CaseError
        Naming the first figure the sizing needs and the table lacks.
    """
    pub = case.published
    op = case.operating
    need = ("rated_torque_Nm", "rated_output_speed_rpm", "rated_life_h",
            "torsional_rigidity_Nm_per_arcmin")
    for key in need:
        if key not in pub:
            raise CaseError(f"published.{key} is required by toothfem size (the datasheet "
                            f"sized to: {', '.join(need)})")
    momentary = pub.get("momentary_torque_Nm",
                        None if op is None else op.momentary_torque_Nm)
    if momentary is None:
        raise CaseError("published.momentary_torque_Nm (or operating.momentary_torque_Nm) "
                        "is required by toothfem size: the pillars carry it")
    return Targets(rated_torque_Nm=float(pub["rated_torque_Nm"]),
                   rated_output_speed_rpm=float(pub["rated_output_speed_rpm"]),
                   rated_life_h=float(pub["rated_life_h"]),
                   rigidity_Nm_per_arcmin=float(pub["torsional_rigidity_Nm_per_arcmin"]),
                   momentary_torque_Nm=float(momentary),
                   backlash_arcmin=pub.get("backlash_arcmin"),
                   lost_motion_arcmin=pub.get("lost_motion_arcmin"))


# -- the search ---------------------------------------------------------------------------
@dataclass
class _Design:
    """The sized dimensions [mm] (and the modification), mutable during the search."""
    module: float
    circle: float
    crank_hole: float
    width: float
    pillar_hole: float
    cranks: int = 2
    equidistant: float = 0.0

    def shaft(self, eccentricity_mm: float) -> float:
        """The crankshaft through its journal: the hole less two needle rollers (a quarter
        of the hole's radius each, fem/datasheet/supports.py) less twice the
        eccentricity, to 0.1 mm below."""
        from .fem.datasheet.supports import ROLLER_DIAMETER_REL
        journal = 2 * self.crank_hole * (1 - ROLLER_DIAMETER_REL)
        return round_to_step(journal - 2 * eccentricity_mm, 0.1, "down")

    def span(self, discs: int, eccentricity_mm: float) -> float:
        """Between the support bearings' centres: the discs, a wall each side, half a
        bearing width each side."""
        _, _, b = support_bearing_mm(self.shaft(eccentricity_mm))
        return discs * self.width + 2 * SHOULDER_MM + b


def _stage(case: Case):
    """The case's [cycloid] section (size_reducer has checked it is there)."""
    if case.cycloid is None or case.material is None:
        raise CaseError("[cycloid] and [material] are required by toothfem size")
    return case.cycloid, case.material


def _edits(d: _Design, case: Case) -> dict:
    """{section: {key: value}} of a design."""
    cyc, _ = _stage(case)
    e = cyc.eccentricity_mm
    return {"first_stage": {"module_mm": d.module, "planet_count": d.cranks},
            "cycloid": {"face_width_mm": d.width,
                        "equidistant_modification_mm": round(d.equidistant, 6)},
            "cycloid.disc_holes": {"crank_hole_count": d.cranks,
                                   "pillar_hole_count": d.cranks,
                                   "crank_hole_circle_radius_mm": d.circle,
                                   "crank_hole_radius_mm": d.crank_hole,
                                   "pillar_hole_circle_radius_mm": d.circle,
                                   "pillar_hole_radius_mm": d.pillar_hole},
            "supports": {"crankshaft_diameter_mm": d.shaft(e),
                         "crankshaft_span_mm": d.span(cyc.disc_count, e)}}


def _text_of(source: str, d: _Design, case: Case, notes: dict | None = None) -> str:
    text = source
    for section, values in _edits(d, case).items():
        text = with_keys(text, section, values, notes=notes, note="toothfem size",
                         create=True)
    return text


#: Positions over one meshing period of the verification's pressure solve: run's and
#: contact's (so the sized datasheet's pressure is theirs).
PH_POSITIONS = 36


def reducer_ph_MPa(case: Case, torque_Nm: float, positions: int = PH_POSITIONS) -> float:
    """The largest Hertz pressure of any disc's pin contacts in the reducer (the system
    model: every disc free on its supports, the split between them solved) at an output
    torque, over one meshing period.

    Parameters
    ----------
    case : Case
    torque_Nm : float
        Output torque [N m].
    positions : int
        Positions over one meshing period.

    Returns
    -------
    float
        [MPa].
    """
    from .fem.drives import drive_for
    from .pipeline import reducer_te
    drive = drive_for(case)
    system = drive.system_model(drive.supports(case.to_si().supports), positions)
    return reducer_te(system, torque_Nm)["max_ph_reducer_MPa"]     # contact's and run's


def _release() -> None:
    """Drop what the last design's solves keep in memory (influence tables of every pitch:
    a large reducer's run to gigabytes over a search's rounds)."""
    import gc

    from .fem.cache import release_solvers
    from .tolerance import release_models
    release_solvers()
    release_models()
    gc.collect()


def _verify(text: str, targets: Targets) -> tuple:
    """The candidate on the system model: (case, its figures)."""
    _release()
    from .datasheet import stiffness_analysis
    from .efficiency.bearings import reducer_life
    case = parse_case_text(text)
    speed = targets.rated_output_speed_rpm * abs(case.ratio())
    sheet = stiffness_analysis(case, te_samples=1, te_positions=2, friction=False).summary
    life = reducer_life(case, duty=[(targets.rated_torque_Nm, speed, 1.0)])
    return case, {"rigidity_Nm_per_arcmin": float(sheet["torsional_rigidity_Nm_per_arcmin"]),
                  "lost_motion_arcmin": float(sheet["lost_motion_arcmin"]),
                  "compliance_shares": {k: float(v) for k, v in
                                        sheet["compliance_shares"].items()},
                  "unit_l10_h": float(life.l10_h), "limiting": life.limiting,
                  "groups": life.groups,
                  "max_ph_MPa": reducer_ph_MPa(case, targets.rated_torque_Nm)}


def _missed(fig: dict, targets: Targets, allowable_MPa: float) -> tuple:
    """The targets a verification misses, each in words with its figure."""
    out = []
    if fig["unit_l10_h"] < targets.rated_life_h:
        out.append(f"unit L10 {fig['unit_l10_h']:.4g} h < {targets.rated_life_h:g} h")
    if fig["rigidity_Nm_per_arcmin"] < targets.rigidity_Nm_per_arcmin:
        out.append(f"rigidity {fig['rigidity_Nm_per_arcmin']:.4g} < "
                   f"{targets.rigidity_Nm_per_arcmin:g} N m/arcmin")
    if fig["max_ph_MPa"] > allowable_MPa:
        out.append(f"P_h {fig['max_ph_MPa']:.4g} > {allowable_MPa:g} MPa")
    return tuple(out)


def _predicted_life(source: str, d: _Design, case: Case, fig: dict) -> float:
    """The unit L10 of design ``d`` with the bearing loads of the verification ``fig``
    held: each group's set life scaled by (C_new / C_old)^p (ISO 281), the reducer's by
    :func:`~toothfem.efficiency.bearings.first_failure`."""
    from .efficiency.bearing_set import reducer_bearings
    from .efficiency.bearings import LIFE_EXPONENT, WEIBULL_SLOPE, first_failure
    from .fem.drives import drive_for
    cand = parse_case_text(_text_of(source, d, case))
    si = cand.to_si()
    rating = {b.name: b.dynamic_rating_N for b in reducer_bearings(si, drive_for(si))}
    sets = []
    for g in fig["groups"]:
        if not math.isfinite(g.l10_set_h):
            continue
        p = LIFE_EXPONENT[g.bearing_type]
        sets.append(g.l10_set_h * (rating[g.name] / g.dynamic_rating_N) ** p)
    return first_failure(sets, WEIBULL_SLOPE["needle"])


def _carrier_Nm_per_arcmin(d: _Design, case: Case, pillars: int) -> float:
    from .fem.datasheet.supports import PILLAR_GAP_M, pillar_carrier_stiffness
    cyc, m = _stage(case)
    e = cyc.eccentricity_mm
    dia = 2 * (d.pillar_hole * M_PER_MM - e * M_PER_MM - PILLAR_GAP_M)
    k = pillar_carrier_stiffness(pillars, d.circle * M_PER_MM, dia,
                                 cyc.disc_count * d.width * M_PER_MM,
                                 m.youngs_modulus_GPa * 1e9, m.poisson_ratio,
                                 plate_share=PLATE_SHARE)
    return k * ARCMIN


def _worst_stack_mm(tol) -> float:
    """The largest closure of one pin's gap the zones allow together (each at its limit):
    a start of the modification above every ring's interference."""
    return (tol.pin_position_mm / 2 + max(abs(tol.pin_diameter_lower_mm),
                                          abs(tol.pin_diameter_upper_mm)) / 2
            + tol.pin_circle_radius_mm + tol.disc_profile_mm + tol.eccentricity_mm
            + tol.crank_hole_position_mm / 2)


def as_built(case: Case, rings: int = RINGS, seed: int = 0) -> dict:
    """The backlash of ``rings`` reducers built within the case's ``[tolerances]`` (the
    system model, :func:`toothfem.tolerance.tolerance_analysis`): its median, P5, P95,
    the share that interferes (backlash < 0) and the nominal.

    Parameters
    ----------
    case : Case
    rings : int
    seed : int

    Returns
    -------
    dict
    """
    from .tolerance import tolerance_analysis
    _release()
    res = tolerance_analysis(case, samples=rings, seed=seed, share_samples=0,
                             positions=RING_POSITIONS, progress=False)
    b = np.asarray(res.samples["backlash_arcmin"], float)
    return {"rings": int(b.size), "nominal_arcmin": float(res.nominal["backlash_arcmin"]),
            "median_arcmin": float(np.median(b)), "p5_arcmin": float(np.percentile(b, 5)),
            "p95_arcmin": float(np.percentile(b, 95)),
            "interfering_share": float(np.mean(b < 0)), "samples": b}


def size_reducer(case, source_text: str, *, progress=None) -> SizingResult:
    """Size a 2K-V reducer to the datasheet of its ``[published]`` table inside its
    ``[envelope]`` (module docstring).

    Parameters
    ----------
    case : Case or path
        drive = "rv" with [cycloid], [first_stage], [envelope] and the [published] figures
        of :func:`targets_of`.
    source_text : str
        The case file's text; the sized case is it with the sized keys set.
    progress : callable, optional
        Called with one line per round of the search.

    Returns
    -------
    SizingResult

    Raises
    ------
    CaseError
        For a case that is not a 2K-V reducer with the sections and figures above.
    """
    case = as_case(case)
    say = progress or (lambda line: None)
    if case.cycloid is None or case.first_stage is None:      # the cranks and their planets
        raise CaseError(f"drive = {case.drive!r}: toothfem size sizes a 2K-V (RV) reducer "
                        "(drive = \"rv\" with [cycloid] and [first_stage])")
    env = case.envelope
    if env is None:
        raise CaseError("[envelope] is required by toothfem size (outer_diameter_mm, "
                        "length_mm: the catalogue's outline)")
    targets = targets_of(case)
    cyc, fs, mat = case.cycloid, case.first_stage, case.material
    holes = cyc.disc_holes
    if holes.crank_hole_count < 1:
        raise CaseError("cycloid.disc_holes.crank_hole_count = 0: toothfem size needs the "
                        "crank count (one planet per crank)")
    discs = cyc.disc_count
    R, e, rp = cyc.pin_circle_radius_mm, cyc.eccentricity_mm, cyc.pin_radius_mm
    root = R - rp - e
    bore = max(holes.centre_bore_radius_mm, env.centre_bore_diameter_mm / 2)
    z1, z2 = fs.sun_teeth, fs.planet_teeth
    allowable = mat.allowable_contact_stress_MPa
    notes: dict = {}
    binding: list = []

    # the crank circle: the first stage's centre distance, midway in the disc's web
    module = iso54_module((bore + root) / (z1 + z2))
    circle = module * (z1 + z2) / 2
    notes["module_mm"] = (f"ISO 54 series I module nearest {(bore + root) / (z1 + z2):.4g}"
                          f" mm, the crank circle m (z1 + z2) / 2 = {circle:.4g} mm midway "
                          f"between the bore {bore:g} mm and the root {root:.4g} mm")
    room = crank_room_mm(circle, bore, root)
    spur_w = fs.face_width_mm if fs.face_width_mm is not None else 10 * module
    housing = cyc.housing_outer_radius_mm
    if 2 * housing > env.outer_diameter_mm:
        binding.append(f"envelope.outer_diameter_mm = {env.outer_diameter_mm:g}: the pin "
                       f"housing needs {2 * housing:.4g} mm ({2 * housing - env.outer_diameter_mm:.3g}"
                       " mm more; cycloid.housing_outer_radius_mm)")

    def pillar_for(width, pillars):
        dia = pillar_diameter_mm(targets.momentary_torque_Nm, pillars, circle,
                                 discs * width, mat.yield_strength_MPa)
        return round_to_step(dia / 2 + e + 0.5, HOLE_STEP_MM, "up"), dia

    def search(k):
        """The rounds with k cranks (and as many pillars): (design, figures, rounds)."""
        pillars = k
        rounds: list = []

        def pillar_min(width):
            return pillar_for(width, pillars)

        def length_ok(d):
            _, _, b_sup = support_bearing_mm(d.shaft(e))
            return (axial_stack_mm(discs, d.width, b_sup, spur_w) <= env.length_mm + 1e-9
                    and d.width <= WIDTH_MAX_PER_RADIUS * R + 1e-9)

        width = max(round_to_step(0.1 * R, WIDTH_STEP_MM, "up"), WIDTH_STEP_MM)
        d = _Design(module=module, circle=circle, width=width, cranks=k,
                    crank_hole=round_to_step(0.42 * room, HOLE_STEP_MM, "down"),
                    pillar_hole=pillar_min(width)[0])
        fig: dict = {}
        for r in range(MAX_ROUNDS):
            d.pillar_hole = max(d.pillar_hole, pillar_min(d.width)[0])
            text = _text_of(source_text, d, case)
            _, fig = _verify(text, targets)
            missed = _missed(fig, targets, allowable)
            rounds.append(Round(dimensions=dict(vars(d)), missed=missed, **{
                k_: fig[k_] for k_ in ("rigidity_Nm_per_arcmin", "unit_l10_h", "limiting",
                                       "max_ph_MPa", "lost_motion_arcmin",
                                       "compliance_shares")}))
            say(f"size: {k} cranks, round {r + 1}: crank hole {d.crank_hole:g} mm, "
                f"width {d.width:g} mm, "
                f"pillar hole {d.pillar_hole:g} mm: rigidity {fig['rigidity_Nm_per_arcmin']:.4g} "
                f"N m/arcmin, unit L10 {fig['unit_l10_h']:.4g} h, P_h {fig['max_ph_MPa']:.4g} MPa"
                + (f"; missed: {', '.join(missed)}" if missed else "; every target met"))
            if not missed:
                break
            grown = False
            if fig["unit_l10_h"] < targets.rated_life_h or fig["max_ph_MPa"] > allowable:
                best = None
                w = d.width
                while True:
                    trial = _Design(**{**vars(d), "width": w})
                    if not length_ok(trial):
                        break
                    hmax = largest_crank_hole_mm(circle, bore, root, k,
                                                 max(d.pillar_hole, pillar_min(w)[0]))
                    h = d.crank_hole
                    while h <= hmax + 1e-9:
                        trial = _Design(**{**vars(d), "width": w, "crank_hole": h,
                                           "pillar_hole": max(d.pillar_hole, pillar_min(w)[0])})
                        life = _predicted_life(source_text, trial, case, fig)
                        ph = fig["max_ph_MPa"] * math.sqrt(d.width / w)
                        if best is None or life > best[0]:
                            best = (life, trial)
                        if life >= targets.rated_life_h and ph <= allowable:
                            best = (life, trial)
                            break
                        h += HOLE_STEP_MM
                    if best is not None and best[0] >= targets.rated_life_h and \
                            fig["max_ph_MPa"] * math.sqrt(d.width / best[1].width) <= allowable:
                        break
                    w += WIDTH_STEP_MM
                if best is not None and vars(best[1]) != vars(d):
                    d, grown = best[1], True
            if not grown and fig["rigidity_Nm_per_arcmin"] < targets.rigidity_Nm_per_arcmin:
                k_all = fig["rigidity_Nm_per_arcmin"]
                c_car = fig["compliance_shares"].get("carrier", 0.0) / k_all
                k_car = _carrier_Nm_per_arcmin(d, case, pillars)
                pmax = min(largest_crank_hole_mm(circle, bore, root, k, d.crank_hole),
                           round_to_step((1 - WEB_PER_ROOM) * room, HOLE_STEP_MM, "down"))
                p = d.pillar_hole + HOLE_STEP_MM
                while p <= pmax + 1e-9:
                    trial = _Design(**{**vars(d), "pillar_hole": p})
                    c_new = c_car * k_car / _carrier_Nm_per_arcmin(trial, case, pillars)
                    if 1 / (1 / k_all - c_car + c_new) >= targets.rigidity_Nm_per_arcmin:
                        break
                    p += HOLE_STEP_MM
                p = min(p, pmax)
                if p > d.pillar_hole:
                    d.pillar_hole, grown = p, True
            if not grown:
                break
        return d, fig, rounds

    rounds: list = []
    best = None
    skipped: list = []
    for k in CRANK_COUNTS:
        try:
            d, fig, tried = search(k)
        except CaseError as exc:          # a layout the system model cannot place
            skipped.append(f"{k} cranks not tried: {exc}")
            say(f"size: {skipped[-1]}")
            continue
        rounds += tried
        if best is None or (len(_missed(fig, targets, allowable)), -fig["unit_l10_h"]) < \
                (len(_missed(best[1], targets, allowable)), -best[1]["unit_l10_h"]):
            best = (d, fig)
        if not _missed(fig, targets, allowable):
            break
    if best is None:
        raise CaseError(f"no crank count to size ({CRANK_COUNTS})")
    d, fig = best
    pillars = d.cranks

    final_missed = _missed(fig, targets, allowable)
    for m_ in final_missed:
        binding.append(f"{m_} with {d.cranks} cranks: the largest crank hole the web allows "
                       f"({WEB_PER_ROOM:g} of the room kept), the widest disc envelope.length_mm"
                       f" = {env.length_mm:g} and {WIDTH_MAX_PER_RADIUS:g} of the pin circle "
                       "allow, and the largest pillar between the holes"
                       + "".join(f"; {x}" for x in skipped))

    # the modification: P5 of the as-built backlash at 0
    text = _text_of(source_text, d, case)
    built = None
    if case.to_si().tolerances.active():
        start = round_to_step(_worst_stack_mm(case.tolerances), MOD_STEP_MM, "up")
        d.equidistant = start
        first = as_built(parse_case_text(_text_of(source_text, d, case)))
        per_mm = first["nominal_arcmin"] / start
        shift = first["samples"] - first["nominal_arcmin"]
        d.equidistant = round_to_step(max(-float(np.percentile(shift, 5)), 0.0) / per_mm,
                               MOD_STEP_MM, "up")
        for _ in range(4):
            built = as_built(parse_case_text(_text_of(source_text, d, case)))
            if built["interfering_share"] <= INTERFERING_MAX and built["median_arcmin"] >= 0:
                break
            d.equidistant += MOD_STEP_MM
        assert built is not None        # the loop ran
        say(f"size: modification {d.equidistant * 1000:.4g} um: as built, backlash median "
            f"{built['median_arcmin']:.3g} arcmin, {100 * built['interfering_share']:.3g} % "
            f"of {built['rings']} rings interfere")
    choices = sizing_choices(d, case, targets, circle, room, bore, root, pillars, spur_w,
                       pillar_for(d.width, pillars)[1], built, notes["module_mm"])
    notes = {c.key.rsplit(".", 1)[1]: "sized: " + c.rule for c in choices}
    text = _text_of(source_text, d, case, notes)
    sized = parse_case_text(text)
    figures = _figures(sized, targets, fig, built, d, spur_w, env)
    return SizingResult(case_name=case.name, targets=targets, choices=tuple(choices),
                        rounds=tuple(rounds), figures=figures, binding=tuple(binding),
                        case=sized, text=text)


def _figures(sized, targets, fig, built, d, spur_w, env) -> dict:
    """The sized reducer's datasheet beside the maker's, and its envelope: the case as
    written (its modification too), the same figures `stiffness` and `run` print."""
    from .datasheet import stiffness_analysis
    from .efficiency.bearings import reducer_life
    _release()
    sheet = stiffness_analysis(sized, te_samples=1, te_positions=2).summary
    speed = targets.rated_output_speed_rpm * abs(sized.ratio())
    life = reducer_life(sized, duty=[(targets.rated_torque_Nm, speed, 1.0)])
    fig = {"unit_l10_h": float(life.l10_h), "limiting": life.limiting,
           "max_ph_MPa": reducer_ph_MPa(sized, targets.rated_torque_Nm)}
    e = sized.cycloid.eccentricity_mm
    _, _, b_sup = support_bearing_mm(d.shaft(e))
    out = {
        "torsional_rigidity_Nm_per_arcmin": [float(sheet["torsional_rigidity_Nm_per_arcmin"]),
                                             targets.rigidity_Nm_per_arcmin],
        "lost_motion_arcmin": [float(sheet["lost_motion_arcmin"]), targets.lost_motion_arcmin],
        "backlash_arcmin": [float(sheet["backlash_arcmin"]), targets.backlash_arcmin],
        "unit_l10_h": [fig["unit_l10_h"], targets.rated_life_h],
        "max_ph_MPa": [fig["max_ph_MPa"], sized.material.allowable_contact_stress_MPa],
        "axial_length_mm": [axial_stack_mm(sized.cycloid.disc_count, d.width, b_sup, spur_w),
                            env.length_mm],
        "housing_diameter_mm": [2 * sized.cycloid.housing_outer_radius_mm,
                                env.outer_diameter_mm],
        "limiting_bearing": fig["limiting"],
    }
    if built is not None:
        out["as_built_backlash_arcmin"] = {k: built[k] for k in (
            "median_arcmin", "p5_arcmin", "p95_arcmin", "interfering_share", "rings")}
    return out
