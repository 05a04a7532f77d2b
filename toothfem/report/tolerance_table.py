"""The tolerance ensemble's percentile tables: report.md's (:func:`summary_rows`, every
percentile in a cell with its interval) and the terminal's (:func:`screen_table`: short
names with the full ones in a legend, a percentile's interval on the row below it, and
only the percentiles the ensemble answers, so that it fits 100 columns)."""
from __future__ import annotations

import math

def number_format(values, unit: str) -> str:
    """The format of an output's numbers: 4 significant digits, an efficiency with enough
    decimals to tell it from 100 % (two significant digits of its distance from 100, at
    least 3 decimals, at most 6).

    Parameters
    ----------
    values : iterable of float or None
        The numbers shown together (nominal, percentiles, their intervals).
    unit : str
        The output's unit ("%": an efficiency).

    Returns
    -------
    str
        A format spec ('.4g', '.3f', '.4f', ...).
    """
    if unit != "%":
        return ".4g"
    gaps = [abs(100 - float(x)) for x in values
            if x is not None and math.isfinite(float(x)) and float(x) != 100]
    if not gaps:
        return ".3f"
    return f".{min(6, max(3, 1 - math.floor(math.log10(min(gaps)))))}f"


def _row_values(result_or_summary_nominal, pct: dict) -> list:
    vals = [result_or_summary_nominal]
    for p in pct.values():
        if p.get("value") is not None:
            vals += [p["value"], *(p.get("ci") or ())]
    return vals


def _tail_of(q: str) -> int:
    return int(q[1:])


def summary_rows(summary: dict, outputs: dict) -> list:
    """The ensemble's key figures as rows of :func:`toothfem.report.summary.text`: each
    output's nominal value and percentiles, in the output's format (an efficiency with
    enough decimals to tell it from 100 %: :func:`number_format`).

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.
    outputs : dict
        Column -> (label, unit) (:data:`toothfem.tolerance_result.OUTPUTS`).

    Returns
    -------
    list of (str, str, dict)
        (label, unit, {"nominal": its text, and per TAIL_COLUMNS the percentile's text with
        its 95 % interval, or the reducers it needs; both tails of a two-sided output}).
    """
    rows = []
    for k, (label, unit) in outputs.items():
        if k not in summary["percentiles"]:
            continue
        pct = summary["percentiles"][k]
        nominal = summary["nominal"][k]
        fmt = number_format(_row_values(nominal, pct), unit)
        cells = {"nominal": format(nominal, fmt)}
        for column in TAIL_COLUMNS:
            parts = [(q, p) for q, p in pct.items() if _column_of(q) == column]
            two = len(parts) > 1
            cells[column] = "; ".join(
                _percentile_text(q, p, fmt) + (
                    (" (low side)" if _tail_of(q) < 50 else " (high side)") if two else "")
                for q, p in parts)
        if k in summary.get("maker", {}):
            cells["maker"] = format(summary["maker"][k], "g")
        rows.append((label, unit, cells))
    return rows


#: The columns of the percentile table: the median and the unfavourable tail.
TAIL_COLUMNS = ("median", "1 in 10 worse than", "1 in 100 worse than")


def _column_of(q: str) -> str:
    return {50: TAIL_COLUMNS[0], 10: TAIL_COLUMNS[1], 90: TAIL_COLUMNS[1],
            1: TAIL_COLUMNS[2], 99: TAIL_COLUMNS[2]}[_tail_of(q)]


def _percentile_text(q: str, p: dict, fmt: str) -> str:
    """'P90 1234 [1200, 1260]', or 'P99: needs 368 reducers'."""
    if p["value"] is None:
        return f"{q}: needs {p['rings_needed']} reducers"
    lo, hi = p["ci"]
    return f"{q} {p['value']:{fmt}} [{lo:{fmt}}, {hi:{fmt}}]"


#: The terminal's short name of each output (its full label in the legend below the
#: table); an output not listed shows its key.
SHORT = {"max_force_N": "max force", "max_ph_MPa": "max P_h",
         "contacts_min": "min contacts", "lost_motion_arcmin": "lost motion",
         "backlash_arcmin": "backlash", "te_mean_arcsec": "TE mean",
         "te_pp_arcsec": "TE p-to-p", "mesh_efficiency_pct": "mesh eff.",
         "total_efficiency_pct": "total eff."}
#: The terminal's column of each percentile column (TAIL_COLUMNS, shorter).
SCREEN_COLUMNS = {"1 in 10 worse than": "1 in 10 worse", "1 in 100 worse than": "1 in 100 worse"}
#: The label of a row holding the 95 % intervals of the row above.
INTERVAL_ROW = "  interval"
#: Its line of the legend.
INTERVAL_LEGEND = ("the 95 % confidence interval of the percentile above it "
                   "(distribution-free: order statistics of the sample)")


def screen_table(summary: dict, outputs: dict) -> tuple:
    """The ensemble's key figures for the terminal (:func:`toothfem.report.summary.text`):
    a short name per output (:data:`SHORT`) with its full label in the legend, its nominal
    value and the percentiles the ensemble answers, each on its row with its 95 % interval
    on the row below (:data:`INTERVAL_ROW`); a two-sided output (the backlash) has a row
    per side. A tail no output answers (too few reducers) is left out and said in the note.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.tolerance_result.ToleranceResult.summary`.
    outputs : dict
        Column -> (label, unit).

    Returns
    -------
    rows : list of (str, str, dict)
    legend : dict
        Short name -> full label.
    note : str
        The percentiles left out and the reducers they need ("" when none is).
    """
    pct_all = {k: summary["percentiles"][k] for k in outputs if k in summary["percentiles"]}
    answered = {_column_of(q) for pct in pct_all.values() for q, p in pct.items()
                if p["value"] is not None}
    columns = [c for c in TAIL_COLUMNS if c in answered]
    missing = {q: p["rings_needed"] for pct in pct_all.values() for q, p in pct.items()
               if _column_of(q) not in answered}
    rows, legend = [], {}
    for k, pct in pct_all.items():
        label, unit = outputs[k]
        short = SHORT.get(k, k)
        legend[short] = label
        fmt = number_format(_row_values(summary["nominal"][k], pct), unit)
        tails = any(_column_of(q) in columns for q in pct if _tail_of(q) != 50)
        sides = ([("low", lambda q: _tail_of(q) <= 50),
                  ("high", lambda q: _tail_of(q) > 50)] if side_of_two(pct) and tails
                 else [("", lambda q: True)])
        for i, (side, on) in enumerate(sides):
            name = short + (f", {side}" if side else "")
            cells = {"nominal": "", "median": ""}         # the nominal and median: once,
            ci = {"nominal": "", "median": ""}            # on the first row
            if i == 0:
                cells["nominal"] = format(summary["nominal"][k], fmt)
            for q, p in pct.items():
                column = _column_of(q)
                if column not in columns or not on(q) or (i and _tail_of(q) == 50):
                    continue
                if p["value"] is None:
                    cells[column] = f"{q}: needs {p['rings_needed']}"
                    continue
                lo, hi = p["ci"]
                prefix = "" if _tail_of(q) == 50 else f"{q} "
                cells[column] = f"{prefix}{p['value']:{fmt}}"
                ci[column] = f"[{lo:{fmt}}, {hi:{fmt}}]"
            if summary.get("maker"):
                maker = summary["maker"].get(k)
                cells["maker"] = "" if i or maker is None else format(maker, "g")
                ci["maker"] = ""
            rows.append((name, unit if i == 0 else "", cells))
            if len(ci) > 1 + ("maker" in ci):
                rows.append((INTERVAL_ROW, "", ci))
    rows = [(name, unit, {SCREEN_COLUMNS.get(c, c): v for c, v in cells.items()})
            for name, unit, cells in rows]
    if any(name == INTERVAL_ROW for name, _, _ in rows):
        legend[INTERVAL_ROW.strip()] = INTERVAL_LEGEND
    note = ""
    if missing:
        by_need: dict = {}
        for q, n in sorted(missing.items(), key=lambda item: abs(50 - _tail_of(item[0]))):
            by_need.setdefault(n, []).append(q)
        note = ("not given (too few built reducers for their 95 % interval): " + "; ".join(
            f"{' and '.join(qs)} need {n}" for n, qs in by_need.items())
            + f" (--samples {max(by_need)})")
    return rows, legend, note


def side_of_two(pct: dict) -> bool:
    """Whether an output's percentiles hold both tails (P10 and P90: the backlash).

    Parameters
    ----------
    pct : dict
        The output's percentiles by name ("P50", "P10", ...).

    Returns
    -------
    bool
    """
    tails = {_tail_of(q) for q in pct}
    return bool(tails & {1, 10}) and bool(tails & {90, 99})
