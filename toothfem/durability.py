"""Life, strength and heat of a case as plain mappings (the JSON of ``toothfem run`` and
``toothfem efficiency --thermal``): calls of :mod:`toothfem.efficiency.bearings`,
:mod:`~toothfem.efficiency.strength` and :mod:`~toothfem.efficiency.thermal`."""
from __future__ import annotations

import math

import numpy as np

from . import limits
from .errors import CaseError, check_range
from .efficiency import bearings as br
from .efficiency import strength as st
from .efficiency import thermal as th
from .efficiency.main_bearing import main_tilt
from .efficiency.mesh_table import LoadsMemo
from .efficiency.evaluation import operating_point
from .fem.drives import drive_for
from .sizing_rules import INTERFERING_MAX
from .units import PA_PER_MPA, S_PER_H

#: [published] keys of a maker's rated life (Nabtesco's K, T0, N0).
MAKER_KEYS = ("rated_life_h", "rated_torque_Nm", "rated_output_speed_rpm")


def _f(x):
    return None if x is None else float(x)


def thermal_summary(case, speed_rpm, torque_Nm, *, loads="analytic", duration_h=None,
                    memo=None) -> dict:
    """The heat balance at one operating point (and the warm-up over ``duration_h``).

    Parameters
    ----------
    case : toothfem.case.Case
    speed_rpm, torque_Nm : float
        Input speed [rpm] and output torque [N m].
    loads : {"analytic", "fem"}
    duration_h : float, optional
        Warm-up from the ambient over this time [h].
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met.

    Returns
    -------
    dict
        Equilibrium oil temperature, heat transfer, housing, efficiency there; the warm-up.
    """
    if duration_h is not None:     # before any work
        check_range("--duration-h", duration_h, *limits.WARM_UP_H, lo_open=True,
                    error=CaseError, why="a warm-up: a reducer's oil settles within a few "
                    "time constants (hours); the time the solver takes grows with it")

    memo = LoadsMemo() if memo is None else memo
    hb = th.heat_balance(case, speed_rpm, torque_Nm, loads=loads, memo=memo)
    h = hb.housing
    out = {
        "ambient_C": h.ambient_C, "housing_area_m2": h.area_m2,
        "heat_capacity_J_K": h.heat_capacity_J_K,
        "mounting": case.to_si().thermal.mounting,
        "flange_conductance_W_K": h.flange_conductance_W_K,
        "equilibrium_oil_temp_C": float(hb.temperature_C[0]),
        "heat_transfer_W_m2K": float(hb.heat_transfer_W_m2K[0]),
        "losses_W": float(hb.losses_W[0]), "efficiency": float(hb.efficiency[0]),
        "iterations": hb.iterations,
        "warnings": [w.as_dict() for w in hb.warnings],
    }
    if duration_h is not None:
        w = th.warm_up(case, speed_rpm, torque_Nm, duration_h * S_PER_H, loads=loads,
                       memo=memo)
        out["time_constant_h"] = w.time_constant_s / S_PER_H
        out["warm_up"] = [{"time_h": float(t / S_PER_H), "oil_temp_C": float(T),
                           "efficiency": float(e)}
                          for t, T, e in zip(w.time_s, w.temperature_C, w.efficiency)]
    return out


def _group(g) -> dict:
    return {"label": g.label, "bearing_type": g.bearing_type, "count": g.count,
            "dynamic_rating_N": _f(g.dynamic_rating_N), "rating_source": g.rating_source,
            "equivalent_load_N": g.equivalent_load_N, "max_load_N": g.max_load_N,
            "mean_speed_rpm": g.speed_rpm, "l10_h": finite(g.l10_h),
            "l10_set_h": finite(g.l10_set_h), "a_iso": g.a_iso,
            "l10m_h": finite(g.l10m_h), "l10m_set_h": finite(g.l10m_set_h)}


def life_summary(case, *, progress=None, known=None) -> dict:
    """ISO 281 life of every bearing over the case's duty cycle (else its operating
    point), from the system model's loads
    (:func:`~toothfem.efficiency.bearings.reducer_life`), the main pair's tilting figures
    (:func:`~toothfem.efficiency.main_bearing.main_tilt`), and the maker's rated life
    scaled to the duty where ``[published]`` gives one (``rated_life_h``,
    ``rated_torque_Nm``, ``rated_output_speed_rpm``).

    Parameters
    ----------
    case : toothfem.case.Case
    progress : callable, optional
        Wraps the system model's sampled pitches.
    known : toothfem.fem.system.datasheet.BearingLoads, optional
        Bearing loads the system model already gave at one torque (the datasheet's).

    Returns
    -------
    dict
        ``bearings``: {group: its life}; ``unit_l10_h`` and ``limiting``: the reducer's
        first bearing failure and the group that sets it.
    """
    drive = drive_for(case)
    res = br.reducer_life(case, progress=progress, known=known)
    groups = {g.name: _group(g) for g in res.groups}
    unit, limiting, rows = res.l10_h, res.limiting, res.rows
    ratio = abs(case.ratio())
    out = {"duty_cycle": [{"output_torque_Nm": t, "input_speed_rpm": n, "time_share": q}
                          for t, n, q in rows],
           "bearings": groups, "unit_l10_h": finite(unit), "limiting": limiting,
           "unit_l10m_h": finite(res.l10m_h), "loads": res.source}
    pub = case.published
    if all(k in pub for k in MAKER_KEYS):
        output_rows = [(t, n / ratio, q) for t, n, q in rows]     # output speeds
        out["maker"] = {
            "rated_life_h": float(pub["rated_life_h"]),
            "rated_torque_Nm": float(pub["rated_torque_Nm"]),
            "rated_output_speed_rpm": float(pub["rated_output_speed_rpm"]),
            "life_at_duty_h": br.maker_rated_life_h(pub["rated_life_h"],
                                                    pub["rated_torque_Nm"],
                                                    pub["rated_output_speed_rpm"], output_rows)}
    si = case.to_si()
    out["main_bearing_tilt"] = tilt = main_tilt(si, drive)
    moment = 0.0 if si.bearings is None else si.bearings.tilting_moment_Nm
    found = [limits.above(
        "external tilting moment on the main bearings", moment, tilt["allowable_moment_Nm"],
        "N m", "the main bearing pair's allowable moment: half the moment at ISO 76's "
        "static limit, 4200 MPa (efficiency/main_bearing.py)")]
    if "maker" in out and unit is not None:
        found.append(limits.below(
            f"L10 of the reducer's bearings (limiting: {limiting})", unit,
            out["maker"]["life_at_duty_h"], "h",
            "the maker's rated life published.rated_life_h scaled to the duty cycle by "
            "the RV-E life formula"))
    out["warnings"] = [w.as_dict() for w in found if w is not None]
    return out


def strength_summary(case, *, contact=None, loads="analytic", positions=36,
                     memo=None) -> dict:
    """Safety factors of the contact and, with an FE contact result, of the member.

    Parameters
    ----------
    case : toothfem.case.Case
    contact : toothfem.pipeline.ContactResult, optional
        Its load sharing (P_h over the period at the peak member torque) and stress field;
        without it, the meshing table's P_h at the operating point's peak member torque.
    loads : {"analytic", "fem"}
        Load source of the meshing table when ``contact`` is None.
    positions : int
        Positions of that table.
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met.

    Returns
    -------
    dict
    """
    si = case.to_si()
    drive = drive_for(si)
    extra: dict = {}
    if contact is not None:
        ph = float(contact.load_sharing.ph.max())
        source = f"FE contact ({contact.mode} mode), one {drive.member_name} held"
        body, u = contact.body, contact.displacement
        ph, source, extra = _larger_pressure(contact, ph, source, drive)
    else:
        torque = operating_point(case)[1]
        t_member = drive.member_torque(torque, peak=True)
        ref = t_member if loads == "fem" else None
        table = (LoadsMemo() if memo is None else memo).table(drive, loads, positions, ref)
        _, p = table.at(np.array([t_member]))
        ph, source, body, u = float(p.max()), f"{loads} loads", None, None
    s = st.strength(si, ph, body, u, member=drive.member_name)
    return {"source": source, "ph_max_MPa": ph / PA_PER_MPA,
            "contact_fatigue_safety": finite(s.contact_fatigue_safety),
            "contact_static_safety": finite(s.contact_static_safety),
            "von_mises_max_MPa": None if s.von_mises_max_Pa is None else s.von_mises_max_Pa / PA_PER_MPA,
            "von_mises_holes_MPa": (None if s.von_mises_holes_Pa is None
                                    else s.von_mises_holes_Pa / PA_PER_MPA),
            "yield_safety": finite(s.yield_safety), "fatigue_safety": finite(s.fatigue_safety),
            **extra, "warnings": list(s.warnings)}


def _how(where: dict) -> str:
    """How a peak pressure was found, for the note: Hertz's, or the FE's where Hertz fails
    (the contact half-width not small against the radii)."""
    if where.get("pressure_from_fe"):
        return "; P_h from the FE: Hertz fails there"
    if where.get("hertz_invalid"):
        return "; Hertz outside its range there"
    return "; Hertz"


def _larger_pressure(contact, ph_held_Pa: float, held_source: str, drive) -> tuple:
    """The larger of the reducer's largest P_h (system model: every member free on its
    supports, the split solved) and the held member's, which it is, and where each sits;
    a note naming both contacts and their curvature where the force and the pressure move
    apart between them (a larger pressure under a smaller force: a smaller radius)."""
    summ = contact.summary
    held = peak_contact(contact.load_sharing)
    reducer_MPa = summ.get("max_ph_reducer_MPa")
    if reducer_MPa is None:
        return ph_held_Pa, held_source, {"ph_held_MPa": ph_held_Pa / PA_PER_MPA,
                                         "judged_on": "held"}
    red = summ.get("max_ph_reducer_contact") or {}
    on_reducer = reducer_MPa * PA_PER_MPA > ph_held_Pa
    extra = {"ph_reducer_MPa": reducer_MPa, "ph_held_MPa": ph_held_Pa / PA_PER_MPA,
             "judged_on": "reducer" if on_reducer else "held",
             "reducer_contact": red, "held_contact": held}
    f_red, f_held = summ.get("max_force_reducer_N"), float(contact.load_sharing.force.max())
    if red and f_red is not None and (f_red - f_held) * (reducer_MPa * PA_PER_MPA
                                                         - ph_held_Pa) < 0:
        c = drive.contact_name
        extra["note"] = (
            f"the reducer's largest P_h {reducer_MPa:.4g} MPa and the held "
            f"{drive.member_name}'s {ph_held_Pa / PA_PER_MPA:.4g} MPa move apart from their "
            f"largest forces ({f_red:.4g} N and {f_held:.4g} N): the reducer's sits at {c} "
            f"{red['contact']} at {red['position_deg']:.3g} deg ({red['force_N']:.4g} N on an "
            f"equivalent radius of {red['equivalent_radius_mm']:.3g} mm{_how(red)}), the held "
            f"one's at {c} {held['contact']} at {held['position_deg']:.3g} deg "
            f"({held['force_N']:.4g} N on {held['equivalent_radius_mm']:.3g} mm{_how(held)})")
    if on_reducer:
        return (reducer_MPa * PA_PER_MPA,
                "the reducer (system model: every member free on its supports), the larger "
                f"of it and {held_source} ({ph_held_Pa / PA_PER_MPA:.4g} MPa)", extra)
    return (ph_held_Pa, f"{held_source}, the larger of it and the reducer's "
                        f"({reducer_MPa:.4g} MPa)", extra)


def peak_contact(sharing) -> dict:
    """Where a load sharing's largest Hertz pressure sits: the contact, the crank angle,
    its force and the equivalent radius of curvature there.

    Parameters
    ----------
    sharing : toothfem.fem.load_sharing.LoadSharing

    Returns
    -------
    dict
        ``contact`` (its index), ``position_deg``, ``force_N``, ``ph_MPa`` and
        ``equivalent_radius_mm``.
    """
    p, c = np.unravel_index(int(np.argmax(sharing.ph)), sharing.ph.shape)
    return {"contact": int(sharing.contact_id[p, c]),
            "position_deg": float(np.degrees(sharing.position_rad[p])),
            "force_N": float(sharing.force[p, c]),
            "pressure_from_fe": bool(sharing.pressure_from_fe[p, c]),
            "hertz_invalid": bool(sharing.hertz_invalid[p, c]),
            "ph_MPa": float(sharing.ph[p, c]) / PA_PER_MPA,
            "equivalent_radius_mm": float(sharing.equivalent_radius[p, c]) * 1e3}


def finite(x):
    """``x`` for strict JSON: None for a missing or unbounded value (a zero load or
    stress: infinite life or safety).

    Parameters
    ----------
    x : float or None
        Any value.

    Returns
    -------
    float or None
        ``x``, or None.
    """
    return None if x is None or not math.isfinite(x) else x


#: The as-built ensemble ``toothfem run`` solves by default: built reducers and positions
#: over the pairing period each (a small one: the median and P95 without their 95 %
#: intervals' precision; ``--as-built`` asks for more).
AS_BUILT_RINGS, AS_BUILT_POSITIONS = 40, 6
#: (output, what it is, unit) of the as-built rows.
AS_BUILT_OUTPUTS = (("backlash_arcmin", "backlash (< 0: the flanks interfere)", "arcmin"),
                    ("lost_motion_arcmin", "lost motion at +-3 % of rated (elastic)", "arcmin"),
                    ("max_force_N", "largest pin force in the reducer", "N"),
                    ("max_ph_MPa", "largest Hertz pressure in the reducer", "MPa"))


def as_built_summary(case, *, rings: int = AS_BUILT_RINGS, progress: bool = False) -> dict:
    """The reducer as built within its ``[tolerances]``: ``rings`` reducers through the
    system model at the operating torque (:func:`toothfem.tolerance.tolerance_analysis`),
    their median and P95 of backlash, lost motion, largest force and Hertz pressure beside
    the nominal, and the share that interferes.

    Parameters
    ----------
    case : toothfem.case.Case
    rings : int
    progress : bool
        A bar on a terminal.

    Returns
    -------
    dict
        ``rings``, ``rows`` {output: {"nominal", "P50", "P95"}}, ``interfering_share``,
        ``warnings`` (a share above :data:`INTERFERING_MAX`; a P95 pressure above the
        allowable); {} without a tolerance zone.
    """
    from .tolerance import release_models, tolerance_analysis
    if not case.to_si().tolerances.active():
        return {}
    try:
        res = tolerance_analysis(case, samples=rings, share_samples=0,
                                 positions=AS_BUILT_POSITIONS, progress=progress)
    finally:
        release_models()           # every pitch's tables: not kept past the run
    rows = {}
    for key, _, _ in AS_BUILT_OUTPUTS:
        v = np.asarray(res.samples[key], float)
        rows[key] = {"nominal": float(res.nominal[key]), "P50": float(np.median(v)),
                     "P95": float(np.percentile(v, 95))}
    b = np.asarray(res.samples["backlash_arcmin"], float)
    share = float(np.mean(b < 0))
    where = f"of {int(b.size)} reducers built within [tolerances] (system model)"
    found = [limits.above(f"share of reducers that interfere (backlash < 0), {where}",
                          100 * share, 100 * INTERFERING_MAX, "%",
                          "the sizing's rule: at most 5 % of units selected or reworked on "
                          "assembly (docs/sizing.md); toothfem size chooses the modification")]
    found += limits.contact_pressure(f"the pin contacts in the reducer, P95 {where}",
                                     rows["max_ph_MPa"]["P95"], case.to_si().material)
    for key in ("backlash_arcmin", "lost_motion_arcmin"):
        if key in case.published:
            rows[key]["maker"] = float(case.published[key])
    return {"rings": int(b.size), "positions": AS_BUILT_POSITIONS, "rows": rows,
            "interfering_share": share,
            "warnings": [w.as_dict() for w in found if w is not None]}
