"""Bearing loads over the meshing cycle and their basic rating life (ISO 281).

Loads, from the contact forces of the drive's meshing table (the analytic split or the FE
cycle solver, magnitude and direction at every position) at the peak member torque (the
more loaded disc: ``drive.member_torque(T, peak=True)``):

* eccentric bearings of a 2K-V drive (the crank bearings in the disc's k holes at radius
  R_c): each takes an even share of the pin resultant R and of the disc torque T,
  F_i = -R/k + T/(k R_c) t_i (t_i the hole's tangent); the holes turn with the disc, R with
  the crank, so over a crank turn's many repetitions every angle between them occurs and
  the load is sampled over that angle (:data:`RELATIVE_ANGLE_SAMPLES`).
* the eccentric bearing of a K-H-V drive (sine planet, plain cycloid): the member's
  equilibrium with the pins-in-holes output, |R - sum Q e| (sine paper Eqs. 26-32,
  docs/derivations.md 7).
* the main (output) bearing pair: the output mechanism's net force (K-H-V: sum Q along e;
  2K-V: the discs' resultants, which cancel for two discs half a turn apart), external
  radial load (fixed in the housing, so sampled over the angle as above), external moment
  over the rows' span, external axial load on one row.

Life (ISO 281:2007): L10 = (C/P)^p 10^6 revolutions, p = 3 for ball, 10/3 for roller
bearings; a load varying over the cycle and a duty cycle of speeds and time shares give the
mean equivalent load P_m = (sum P_i^p n_i q_i / sum n_i q_i)^(1/p) (ISO 281:2007, Sec. on
variable operating conditions; for ball bearings the cubic mean), and L10h = L10 /
(60 sum n_i q_i). The life of a set of z equally loaded bearings (the reducer fails when
the first does) is L z^(-1/e), e the Weibull slope (10/9 ball, 9/8 roller: Lundberg &
Palmgren 1947/1952, the basis of ISO 281).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError, check_range
from ..fem.drives import drive_for
from ..geometry import cycloid_mesh as cym
from .envelope import envelope
from .mesh_table import mesh_table
from ..si import si_of
from ..units import rad_s_to_rpm, rpm_to_rad_s

#: Life exponent p of ISO 281 by bearing type (3 ball, 10/3 roller).
LIFE_EXPONENT = {"ball": 3.0, "angular_ball": 3.0, "cylindrical": 10 / 3, "tapered": 10 / 3,
                 "needle": 10 / 3}
#: Weibull slope e of the life distribution (Lundberg & Palmgren): 10/9 ball, 9/8 roller.
WEIBULL_SLOPE = {"ball": 10 / 9, "angular_ball": 10 / 9, "cylindrical": 9 / 8,
                 "tapered": 9 / 8, "needle": 9 / 8}
#: ISO 281 dynamic equivalent load of a single-row angular contact ball bearing with a
#: 40 deg contact angle (ISO 281:2007, Table 3): P = F_r while F_a/F_r <= e, else
#: X F_r + Y F_a.
ANGULAR_BALL_40 = {"e": 1.14, "X": 0.35, "Y": 0.57}
#: Samples of the angle between a load that turns with the crank and one fixed to the
#: disc or the housing (uniform over a turn).
RELATIVE_ANGLE_SAMPLES = 64
#: Revolutions of the basic rating life L10 per (C/P)^p (ISO 281).
MILLION = 1e6


@dataclass(frozen=True, kw_only=True)
class BearingLoads:
    """Load on one bearing of a group over one meshing period at one output torque.

    ``force_N`` (P, 2): the force on one bearing at each position (for the crank bearings,
    the hole on +x of the disc frame), housing frame; ``load_N`` (P, S): its magnitude at
    every sampled relative angle (S = 1 where nothing turns against the load);
    ``equivalent_N``: the ISO 281 p-mean over all of them; ``max_N``.
    """
    name: str
    count: int
    bearing_type: str
    force_N: np.ndarray
    load_N: np.ndarray
    equivalent_N: float
    max_N: float


def _pmean(values, p) -> float:
    return float(np.mean(np.asarray(values, float) ** p) ** (1.0 / p))


def _turning(a, b):
    """(..., S) magnitudes |a u - b v| over the angle between the unit vectors u, v."""
    psi = (np.arange(RELATIVE_ANGLE_SAMPLES) + 0.5) * 2 * math.pi / RELATIVE_ANGLE_SAMPLES
    a, b = np.asarray(a, float)[..., None], np.asarray(b, float)[..., None]
    return np.sqrt(np.maximum(a ** 2 + b ** 2 - 2 * a * b * np.cos(psi), 0.0))


def crank_held_loads(si, drive, table, r, t_member):
    """2K-V: hole k of n (circle R_c) takes -F/n + T/(n R_c) t_k, the contact resultant F
    and the member's torque T shared evenly; ((P, 2) load, (P, S) magnitudes over the
    relative turn).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    table : toothfem.efficiency.mesh_table.MeshTable
        The loaded contacts over one meshing period.
    r : numpy.ndarray, shape (P, 2)
        The contact resultant on the member at each position [N].
    t_member : numpy.ndarray
        The member's torque [N m].

    Returns
    -------
    (numpy.ndarray (P, 2), numpy.ndarray (P, S))
        The load on one crank bearing [N] and its magnitude over the relative turn [N].
    """
    h = si.cycloid.holes
    k, r_c = h.crank_hole_count, h.crank_hole_circle_radius_m
    b = t_member / (k * r_c)
    _, rot = cym.disc_pose(si.cycloid.geometry, drive.positions(table.n_positions))
    tangent = np.stack([-np.sin(rot), np.cos(rot)], axis=1)     # hole on +x
    return -r / k + b * tangent, _turning(np.linalg.norm(r, axis=1) / k, np.full(len(r), b))


def pin_held_loads(si, drive, table, r, t_member):
    """Output pins in the member's holes (K-H-V, the sine planet): the eccentric bearing
    takes the contact resultant less the pins' sum Q along the eccentricity (Lu & Xu 2024,
    Eq. 26); ((P, 2) load, (P, 1) its magnitude).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    table : toothfem.efficiency.mesh_table.MeshTable
        The loaded contacts over one meshing period.
    r : numpy.ndarray, shape (P, 2)
        The contact resultant on the member at each position [N].
    t_member : numpy.ndarray
        The member's torque [N m].

    Returns
    -------
    (numpy.ndarray (P, 2), numpy.ndarray (P, 1))
        The load on the eccentric bearing [N] and its magnitude [N].
    """
    om = si.output_mechanism
    if om is None:
        raise CaseError("a K-H-V drive needs [output_mechanism] (pins in holes) for the "
                        "load on its eccentric bearing")
    sum_q = 4 * t_member / (math.pi * om.pin_hole_circle_radius_m)      # Eq. 26
    e_dir = table.centre / np.linalg.norm(table.centre, axis=1)[:, None]
    vec = r - sum_q * e_dir
    return vec, np.linalg.norm(vec, axis=1)[:, None]


def carrier_force(si, drive, table, t_member):
    """2K-V: the discs' pin resultants reach the carrier, (M, P, 2).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    table : toothfem.efficiency.mesh_table.MeshTable
        The loaded contacts over one meshing period.
    t_member : numpy.ndarray
        The member's torque [N m].

    Returns
    -------
    numpy.ndarray, shape (M, P, 2)
        The force one member puts on the main bearings [N].
    """
    force, _ = table.at(t_member)
    return -table.resultant(force)


def output_pin_force(si, drive, table, t_member):
    """The pins-in-holes output takes sum Q along the eccentricity, (M, P, 2).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    table : toothfem.efficiency.mesh_table.MeshTable
        The loaded contacts over one meshing period.
    t_member : numpy.ndarray
        The member's torque [N m].

    Returns
    -------
    numpy.ndarray, shape (M, P, 2)
        The force one member puts on the main bearings [N].
    """
    e_dir = table.centre / np.linalg.norm(table.centre, axis=1)[:, None]
    sum_q = 4 * t_member / (math.pi * si.output_mechanism.pin_hole_circle_radius_m)
    return sum_q[:, None, None] * e_dir[None]


def eccentric_loads(si, drive, table, output_torque_Nm) -> BearingLoads:
    """Loads of one eccentric bearing over the period (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    table : toothfem.efficiency.mesh_table.MeshTable
        The period's contacts (any load source).
    output_torque_Nm : float
        Reducer output torque [N m]; the member carries its peak share.

    Returns
    -------
    BearingLoads

    Raises
    ------
    CaseError
        If a K-H-V drive has no [output_mechanism].
    """
    env = envelope(si, drive)
    t_member = drive.member_torque(output_torque_Nm, peak=True)
    force, _ = table.at(np.array([t_member]))
    r = table.resultant(force)[0]                                   # (P, 2)
    p = LIFE_EXPONENT[env.eccentric_type]
    vec, load = drive.layout.eccentric_loads(si, drive, table, r, t_member)
    return BearingLoads(name="eccentric", count=env.eccentric_count,
                        bearing_type=env.eccentric_type, force_N=vec, load_N=load,
                        equivalent_N=_pmean(load, p), max_N=float(load.max()))


def main_loads(si, drive, table, output_torque_Nm) -> BearingLoads:
    """Loads of the more loaded row of the main bearing pair (module docstring); the
    equivalent load by ISO 281 (``ANGULAR_BALL_40`` for angular contact ball bearings).

    Parameters
    ----------
    si, drive, table, output_torque_Nm
        As :func:`eccentric_loads`.

    Returns
    -------
    BearingLoads

    Raises
    ------
    CaseError
        If an external moment is declared without ``bearings.main_span_mm``, or an external
        axial load on a main bearing type other than 'angular_ball'.
    """
    b = si.bearings
    rows, force, radial = _main_rows(si, drive, table, np.array([float(output_torque_Nm)]))
    p = LIFE_EXPONENT[b.main_type]
    return BearingLoads(name="main", count=rows, bearing_type=b.main_type, force_N=force[0],
                        load_N=radial[0], equivalent_N=_pmean(radial[0], p),
                        max_N=float(radial[0].max()))


def _main_rows(si, drive, table, output_torque_Nm):
    """(rows, (M, P, 2) force on a row, (M, P, S) its equivalent load over the relative
    turn) of the main pair at M output torques (:func:`main_loads`)."""
    b = si.bearings
    env = envelope(si, drive)
    t_member = np.asarray(drive.member_torque(output_torque_Nm, peak=True), float)
    vec = drive.layout.main_row_force(si, drive, table, t_member)     # (M, P, 2)
    n = drive.members          # the members' forces, a 1/n turn apart (rounded: two
    turn = np.round(sum(       # discs half a turn apart cancel exactly)
        np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        for a in 2 * math.pi * np.arange(n) / n), 12)
    vec = vec @ turn.T
    rows = env.main_count
    radial = _turning(np.linalg.norm(vec, axis=-1) / rows,
                      np.full(vec.shape[:-1], b.external_radial_load_N / rows))
    moment = b.tilting_moment_Nm
    if moment > 0:
        if b.main_span_m is None:
            raise CaseError(f"bearings.external_moment_Nm = {b.external_moment_Nm!r} with the "
                            "offsets' moment, "
                            f"{moment:.6g} N m in all, needs bearings.main_span_mm (the rows' "
                            "load centres)")
        radial = radial + moment / b.main_span_m
    axial = b.external_axial_load_N
    if axial > 0:
        if b.main_type != "angular_ball":
            raise CaseError(f"bearings.external_axial_load_N = {axial!r} needs main_type = "
                            f"'angular_ball' (ISO 281 X, Y of a 40 deg contact), not "
                            f"{b.main_type!r}")
        f = ANGULAR_BALL_40
        with np.errstate(divide="ignore"):
            heavy = axial > f["e"] * radial
        radial = np.where(heavy, f["X"] * radial + f["Y"] * axial, radial)
    return rows, vec / rows, radial


def main_bearing_load(si, drive, table, output_torque_Nm):
    """Sum of the main bearing rows' loads at M output torques, each averaged over the
    cycle (:func:`main_loads`): what their load-dependent friction takes [N].

    Parameters
    ----------
    si, drive, table
        As :func:`eccentric_loads`.
    output_torque_Nm : numpy.ndarray, shape (M,)
        [N m].

    Returns
    -------
    numpy.ndarray, shape (M,)
        [N].
    """
    t = np.atleast_1d(np.asarray(output_torque_Nm, float))
    rows, _, radial = _main_rows(si, drive, table, t)
    return rows * radial.reshape(len(t), -1).mean(axis=1)


def rating_life_revolutions(rating_N, load_N, exponent):
    """Basic rating life L10 [revolutions], ISO 281: (C/P)^p 10^6.

    Parameters
    ----------
    rating_N : float
        Basic dynamic load rating C [N].
    load_N : array_like
        Dynamic equivalent load P [N].
    exponent : float
        p: 3 ball, 10/3 roller.

    Returns
    -------
    numpy.ndarray
        L10 in revolutions (inf where P = 0).

    Raises
    ------
    CaseError
        If the dynamic load rating is not positive.
    """
    check_range("dynamic load rating C [N]", rating_N, 0.0, None, lo_open=True,
                error=CaseError)
    with np.errstate(divide="ignore"):
        return MILLION * (rating_N / np.asarray(load_N, float)) ** exponent


def mean_equivalent_load(loads_N, speeds_rpm, shares, exponent) -> float:
    """ISO 281 mean equivalent load over a duty cycle, (sum P_i^p n_i q_i / sum n_i q_i)^(1/p).

    Parameters
    ----------
    loads_N, speeds_rpm, shares : array_like
        Equivalent load P_i [N], speed n_i [rpm] and share of time q_i of each row.
    exponent : float
        p of the life law.

    Returns
    -------
    float
        P_m [N].
    """
    p_i = np.asarray(loads_N, float)
    w = np.abs(np.asarray(speeds_rpm, float)) * np.asarray(shares, float)
    return float((np.sum(p_i ** exponent * w) / np.sum(w)) ** (1.0 / exponent))


def _duty(si):
    """(output torque [N m], input speed [rad/s], share) rows: the duty cycle, else the
    operating point."""
    if si.duty_cycle:
        return [(d.output_torque_Nm, d.input_speed_rad_s, d.time_share) for d in si.duty_cycle]
    t = si.declared_output_torque_Nm()
    if t is None:
        raise CaseError("[operating] needs an output torque (or input torque or power) or a "
                        "[[duty_cycle]] for the bearing life")
    return [(t, si.operating.input_speed_rad_s, 1.0)]


def maker_rated_life_h(rated_life_h, rated_torque_Nm, rated_output_speed_rpm, rows) -> float:
    """A maker's rated life scaled to a duty cycle by the roller law (Nabtesco RV-E
    catalogue, life of the reducer): L_h = K (N0/N_m) (T0/T_m)^(10/3), T_m the 10/3-mean
    of the output torque weighted by output speed and time, N_m the mean output speed.

    Parameters
    ----------
    rated_life_h, rated_torque_Nm, rated_output_speed_rpm : float
        K [h], T0 [N m], N0 [rpm] (RV-40E: 6000 h, 412 N m, 15 rpm).
    rows : sequence of (output torque [N m], output speed [rpm], share)

    Returns
    -------
    float
        L_h [h].
    """
    t = np.array([r[0] for r in rows], float)
    n = np.abs(np.array([r[1] for r in rows], float))
    q = np.array([r[2] for r in rows], float)
    t_m = mean_equivalent_load(t, n, q, 10 / 3)
    n_m = float(np.dot(n, q))
    return rated_life_h * (rated_output_speed_rpm / n_m) * (rated_torque_Nm / t_m) ** (10 / 3)


#: The system model's bearing names (fem/drives/assembly.py) by the group they belong to.
SYSTEM_GROUPS = (("crank bearing", "crank_bearings"), ("eccentric bearing", "eccentric_bearing"),
                 ("support bearing", "crank_support_bearings"), ("input bearing", "input_bearings"))
#: Sampled pitches over the full period, and positions per pitch, of the system model's
#: bearing loads for the life: the crank bearings' load turns against the disc over the
#: period. Measured against 16 x 8 (every bearing's 10/3-mean load): 5 x 4 within 5.4e-4
#: on the RV-40E case and 7.1e-4 on the K-H-V case (0.25 % in life); 8 x 4 within 2.2e-5
#: and 2.1e-3; 4 x 4 is 1e-2 off on the RV-40E (3 % in life). The sampled pitches set the
#: cost (about 1.2 s each: 6.3 s for 5 x 4 on the RV-40E).
LIFE_SAMPLES, LIFE_PER_PITCH = 5, 4
#: The system model's bearing loads already computed in this process, by the parts of the
#: case they depend on and the torque (a pure function of those; a few entries).
_LOADS_MEMO: dict = {}
_LOADS_MEMO_SIZE = 16


@dataclass(frozen=True, kw_only=True)
class GroupLife:
    """ISO 281 life of one group of like bearings over the duty cycle; ``l10_h`` of its
    most loaded bearing, ``l10_set_h`` of the group (the first failure ends it)."""
    name: str
    label: str
    bearing_type: str
    count: int
    dynamic_rating_N: float
    rating_source: str
    equivalent_load_N: float      # P_m of the most loaded bearing
    max_load_N: float
    speed_rpm: float              # mean, relative to its other ring
    l10_h: float
    l10_set_h: float
    a_iso: float | None = None    # of the most loaded bearing (ISO 281 modified life)
    l10m_h: float | None = None   # a_ISO L10 of the most loaded bearing
    l10m_set_h: float | None = None


@dataclass(frozen=True, kw_only=True)
class ReducerLife:
    """Life of every bearing group and of the reducer (its first bearing failure)."""
    groups: tuple
    l10_h: float
    limiting: str
    rows: tuple                   # (output torque [N m], input speed [rpm], share)
    source: str
    l10m_h: float | None = None   # the modified life (bearings.contamination given)


def first_failure(lives, slope) -> float:
    """L10 of bearings in series, the first failure ending them:
    (sum_i L_i^-e)^(-1/e) (Lundberg & Palmgren); an unloaded bearing (inf) adds nothing.

    Parameters
    ----------
    lives : array_like
        Each bearing's L10 (any unit, inf allowed).
    slope : float
        e, the Weibull slope.

    Returns
    -------
    float
        The set's L10 (inf if every bearing's is).
    """
    x = np.asarray(lives, float)
    s = float(np.sum(x[np.isfinite(x)] ** -slope))
    return math.inf if s == 0 else s ** (-1 / slope)


def _a_iso(si, bearing, load_N, speed_rpm):
    """ISO 281's life modification factor of one bearing at its mean load and speed, or
    None without ``bearings.contamination``: the viscosity ratio of the lubricant at its
    reference temperature (the duty cycle's oil temperature is not modelled), e_C the
    middle of Table 13's range, C_u by Annex B's simplified rule
    (:mod:`.life_modification`)."""
    from . import life_modification as lm
    level = None if si.bearings is None else si.bearings.contamination
    if level is None or load_N <= 0:
        return None if level is None else lm.A_ISO_MAX
    d_m = bearing.pitch_diameter_m
    kappa = float(lm.viscosity_ratio(si.lubricant.kinematic_viscosity_m2_s, speed_rpm, d_m))
    e_c = float(lm.contamination_factor(level, d_m))
    c_u = float(lm.fatigue_load_limit_N(bearing.bearing_type, bearing.static_rating_N, d_m))
    return float(lm.a_iso(bearing.bearing_type, min(max(kappa, 0.1), 4.0), e_c, c_u, load_N))


def _system_loads(si, drive, torque_Nm, progress=None) -> dict:
    """Each bearing's loads over the full period from the system model: name -> (N,)."""
    from ..fem.system.datasheet import system_te
    key = (repr((si.drive, si.cycloid, si.sine, si.rv, si.first_stage, si.output_mechanism,
                 si.supports, si.material)), float(torque_Nm))
    if key not in _LOADS_MEMO:
        _, _, loads = system_te(drive, drive.supports(si.supports), torque_Nm,
                                samples=LIFE_SAMPLES, per_pitch=LIFE_PER_PITCH,
                                progress=progress)
        if len(_LOADS_MEMO) >= _LOADS_MEMO_SIZE:
            _LOADS_MEMO.pop(next(iter(_LOADS_MEMO)))
        _LOADS_MEMO[key] = dict(zip(loads.names, loads.load_N))
    return _LOADS_MEMO[key]


def _group_of(name: str) -> str:
    return next(g for prefix, g in SYSTEM_GROUPS if name.startswith(prefix))


def reducer_life(case, *, duty=None, progress=None, known=None) -> ReducerLife:
    """ISO 281 life of every bearing of a reducer over a duty cycle, the
    loads from the system model over the full period (the main bearings' from the
    external loads on the output, :func:`main_loads`; the planar model has no tilt).

    Each bearing: P_m, the p-mean of its load over the period and the duty rows weighted by
    speed and time (:func:`mean_equivalent_load`), L10 = (C/P_m)^p 10^6 revolutions at its
    mean speed. A group, and the reducer, fail with their first bearing:
    L = (sum_i L_i^-e)^(-1/e) (Lundberg & Palmgren), e = 9/8 for the reducer (its
    limiting bearings are rollers).

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    duty : sequence of (torque [N m], input speed [rpm], share), optional
        Default: the case's ``[[duty_cycle]]``, else its operating point.
    progress : callable, optional
        Wraps the iterator over the system model's sampled pitches.
    known : toothfem.fem.system.datasheet.BearingLoads, optional
        Every bearing's loads over the full period the system model already gave at one
        output torque (the datasheet's TE run, :func:`toothfem.fem.system.datasheet.system_te`):
        a duty row at that torque takes them instead of a new solve.

    Returns
    -------
    ReducerLife

    Raises
    ------
    CaseError
        A bearing that does not fit.
    """
    from .bearing_set import reducer_bearings
    si = si_of(case)
    drive = drive_for(si)
    rows = (_duty(si) if duty is None else
            [(float(t), rpm_to_rad_s(float(n)), float(q)) for t, n, q in duty])
    if duty is not None:
        total = sum(q for *_, q in rows)
        check_range("duty time share sum", total, 1 - 1e-3, 1 + 1e-3, error=CaseError)
    bearings = {b.name: b for b in reducer_bearings(si, drive)}
    # group -> {bearing: [(P_m, P_max) per duty row]}
    per_group: dict[str, dict[str, list[tuple[float, float]]]] = {}
    table = mesh_table(drive, "analytic", 36, None)
    for t, _, _ in rows:
        loads = (dict(zip(known.names, known.load_N)) if known is not None
                 and math.isclose(known.output_torque_Nm, t, rel_tol=1e-12)
                 else _system_loads(si, drive, t, progress))
        for name, load in loads.items():
            g = _group_of(name)
            p = LIFE_EXPONENT[bearings[g].bearing_type]
            per_group.setdefault(g, {}).setdefault(name, []).append(
                (_pmean(load, p), float(np.max(load))))
        main = main_loads(si, drive, table, t)
        for r in range(main.count):
            per_group.setdefault("main_bearings", {}).setdefault(
                f"main bearing row {r + 1}", []).append((main.equivalent_N, main.max_N))
    shares = [q for *_, q in rows]
    groups = []
    for g, b in bearings.items():
        per_bearing = per_group.get(g, {})
        names = list(per_bearing)
        p = LIFE_EXPONENT[b.bearing_type]
        if not names:          # carries nothing in the model (an RV's sun: planets balance)
            groups.append(GroupLife(
                name=g, label=b.label, bearing_type=b.bearing_type, count=b.count,
                dynamic_rating_N=b.dynamic_rating_N, rating_source=b.rating_source,
                equivalent_load_N=0.0, max_load_N=0.0,
                speed_rpm=float(np.dot([rad_s_to_rpm(n * b.speed_per_input)
                                        for _, n, _ in rows], shares)),
                l10_h=math.inf, l10_set_h=math.inf))
            continue
        speeds = [rad_s_to_rpm(n * b.speed_per_input) for _, n, _ in rows]   # ISO 281: rpm
        n_m = float(np.dot(speeds, shares))
        lives, p_ms, a_isos = [], [], []
        for n in names:
            p_m = mean_equivalent_load([x for x, _ in per_bearing[n]], speeds, shares, p)
            p_ms.append(p_m)
            lives.append(float(rating_life_revolutions(b.dynamic_rating_N, p_m, p))
                         / (60.0 * n_m))
            a_isos.append(_a_iso(si, b, p_m, n_m))
        modified = None if a_isos[0] is None else [a * x for a, x in zip(a_isos, lives)]
        worst = int(np.argmin(lives))
        groups.append(GroupLife(
            name=g, label=b.label, bearing_type=b.bearing_type, count=len(names),
            dynamic_rating_N=b.dynamic_rating_N, rating_source=b.rating_source,
            equivalent_load_N=max(p_ms), max_load_N=max(m for n in names
                                                         for _, m in per_bearing[n]),
            speed_rpm=n_m, l10_h=float(min(lives)),
            l10_set_h=first_failure(lives, WEIBULL_SLOPE[b.bearing_type]),
            a_iso=a_isos[worst], l10m_h=None if modified is None else float(modified[worst]),
            l10m_set_h=None if modified is None else first_failure(
                modified, WEIBULL_SLOPE[b.bearing_type])))
    unit = first_failure([x.l10_set_h for x in groups], WEIBULL_SLOPE["needle"])
    unit_m = (None if si.bearings is None or si.bearings.contamination is None else
              first_failure([math.inf if x.l10m_set_h is None else x.l10m_set_h
                             for x in groups], WEIBULL_SLOPE["needle"]))
    limiting = min(groups, key=lambda x: x.l10_set_h).name
    return ReducerLife(groups=tuple(groups), l10_h=unit, limiting=limiting,
                       rows=tuple((t, rad_s_to_rpm(n), q) for t, n, q in rows),
                       source="system model (FE pin tables, every bearing's load over the "
                              "full period)", l10m_h=unit_m)
