"""Markdown of life, strength and heat (the mappings of :mod:`toothfem.durability`)."""
from __future__ import annotations


def _num(x, fmt=".4g", none="–"):
    return none if x is None else format(x, fmt)


def as_built_rows(as_built: dict) -> list:
    """The as-built ensemble's rows: each output's nominal, median and P95, and the share
    that interferes (:func:`toothfem.durability.as_built_summary`).

    Parameters
    ----------
    as_built : dict

    Returns
    -------
    list of (str, str, dict)
        Rows of :func:`toothfem.report.summary.text`.
    """
    from ..durability import AS_BUILT_OUTPUTS
    out = [(what, unit, dict(as_built["rows"][key]))
           for key, what, unit in AS_BUILT_OUTPUTS if key in as_built["rows"]]
    out.append(("reducers that interfere (backlash < 0)", "%",
                {"P50": 100 * as_built["interfering_share"]}))
    return out


def markdown(life: dict, strength: dict, heat: dict, rv_teeth=None,
             as_built: dict | None = None) -> list:
    """Lines of report.md: the heat balance, the bearing life (with the maker's rated life
    where the case gives one, beside the RV paper's tooth numbers) and the safety factors.

    Parameters
    ----------
    life, strength, heat : dict
        :func:`~toothfem.durability.life_summary`, ``strength_summary``,
        ``thermal_summary``.
    rv_teeth : tuple of int, optional
        (z1, z2, z4, z5) of an RV case.

    Returns
    -------
    list of str
    """
    out = ["## Life, strength and heat", ""]
    out += [f"Heat balance at the operating point: oil **{heat['equilibrium_oil_temp_C']:.1f} C**"
            f" at an ambient of {heat['ambient_C']:g} C (housing {heat['housing_area_m2']:.3f}"
            f" m², h = {heat['heat_transfer_W_m2K']:.1f} W/(m² K), {heat['losses_W']:.1f} W of"
            f" losses); efficiency there {100 * heat['efficiency']:.2f} %.", ""]
    duty = ", ".join(f"{r['output_torque_Nm']:g} N m at {r['input_speed_rpm']:g} rpm "
                     f"({100 * r['time_share']:g} %)" for r in life["duty_cycle"])
    out += [f"Bearing life (ISO 281, loads: {life['loads']}), duty cycle: {duty}.", "",
            "| bearings | type | count | C [N] | C from | P_m [N] | P_max [N] | n [rpm] |"
            " L10 most loaded [h] | L10 group [h] |", "|---|---|---|---|---|---|---|---|---|---|"]
    for b in life["bearings"].values():
        endless = "not rated" if b["dynamic_rating_N"] is None else "∞ (no load)"
        out.append(f"| {b['label']} | {b['bearing_type']} | {b['count']} | "
                   f"{_num(b['dynamic_rating_N'], '.0f', 'not given')} | "
                   f"{b['rating_source'] or '–'} | "
                   f"{b['equivalent_load_N']:.4g} | {b['max_load_N']:.4g} | "
                   f"{b['mean_speed_rpm']:.4g} | {_num(b['l10_h'], '.4g', endless)} | "
                   f"{_num(b['l10_set_h'], '.4g', endless)} |")
    out += ["", f"The reducer's bearings together (the first failure): L10 "
                f"**{_num(life['unit_l10_h'], '.4g', '∞ or not rated')} h**, limited by "
                f"{life['limiting'] or '–'}.", ""]
    if life.get("unit_l10m_h") is not None:
        modified = "; ".join(
            f"{name} a_ISO {b['a_iso']:.3g}, L10m {_num(b['l10m_set_h'], '.4g', '∞')} h"
            for name, b in life["bearings"].items() if b["a_iso"] is not None)
        out += [f"Modified life (ISO 281 a_ISO, bearings.contamination): {modified}; the "
                f"reducer's L10m {life['unit_l10m_h']:.4g} h.", ""]
    if "main_bearing_tilt" in life:
        t = life["main_bearing_tilt"]
        out += [f"Main bearing pair against a tilting moment ({t['balls_per_row']} balls of "
                f"{t['ball_diameter_mm']:.3g} mm per row on {t['pitch_diameter_mm']:.4g} mm, "
                f"{t['preload_N']:.0f} N preload; assumed: {', '.join(t['assumed'])}): "
                f"allowable moment {t['allowable_moment_Nm']:.4g} N m, momentary "
                f"{t['momentary_moment_Nm']:.4g} N m (ISO 76 static limit), moment rigidity "
                f"{t['moment_rigidity_Nm_per_arcmin']:.4g} N m/arcmin (the pair alone).", ""]
    if "maker" in life:
        m = life["maker"]
        teeth = ("" if rv_teeth is None else
                 "RV paper, Table 1: z1 = {}, z2 = {}, z4 = {}, z5 = {}; ".format(*rv_teeth))
        out += [f"{teeth}maker's rated life {m['rated_life_h']:g} h at {m['rated_torque_Nm']:g}"
                f" N m and {m['rated_output_speed_rpm']:g} rpm output, "
                f"{m['life_at_duty_h']:.4g} h at this duty cycle (reference).", ""]
    if strength.get("note"):
        out += [f"Where the pressures sit: {strength['note']}.", ""]
    out += [f"Strength ({strength['source']}):", "", "| check | value | safety factor |",
            "|---|---|---|",
            f"| contact fatigue, P_h,max | {strength['ph_max_MPa']:.0f} MPa | "
            f"{_num(strength['contact_fatigue_safety'], '.2f')} |",
            f"| static contact | {strength['ph_max_MPa']:.0f} MPa | "
            f"{_num(strength['contact_static_safety'], '.2f')} |",
            f"| member von Mises (yield) | {_num(strength['von_mises_max_MPa'], '.0f')} MPa | "
            f"{_num(strength['yield_safety'], '.2f')} |",
            f"| hole edges von Mises (fatigue) | {_num(strength['von_mises_holes_MPa'], '.0f')} "
            f"MPa | {_num(strength['fatigue_safety'], '.2f')} |", ""]
    if as_built:
        from .summary import markdown as md_table
        out += [f"As built: {as_built['rings']} reducers within [tolerances] through the "
                f"system model ({as_built['positions']} positions each); the share that "
                f"interferes is its own row.", "", *md_table(as_built_rows(as_built)), ""]
    return out + ["Safety factors below 1 are in the report's warnings.", "",
                  "Tables: `durability.json`.", ""]
