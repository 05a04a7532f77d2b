"""The files of ``toothfem size``: the sized case (sized_case.toml, every sized key with
its rule), sizing.json, report.md, and the table on screen."""
from __future__ import annotations

import json
from pathlib import Path

from .summary import markdown as md_table

#: The columns: our figure for the sized reducer, the maker's (the target), and theirs
#: apart.
OURS, MAKER = "sized reducer", "maker / limit"

#: (figures key, quantity, unit) in the table's order.
_FIGURES = (
    ("torsional_rigidity_Nm_per_arcmin", "torsional rigidity (50-100 % of rated)",
     "N m/arcmin"),
    ("lost_motion_arcmin", "lost motion at +-3 % of rated (nominal)", "arcmin"),
    ("backlash_arcmin", "backlash (nominal)", "arcmin"),
    ("unit_l10_h", "unit L10 at the rated point (every bearing)", "h"),
    ("max_ph_MPa", "largest Hertz pressure in the reducer at rated torque", "MPa"),
    ("axial_length_mm", "axial length (discs, support bearings, first stage)", "mm"),
    ("housing_diameter_mm", "pin housing's outer diameter", "mm"),
)


def rows(summary: dict) -> list:
    """The sized reducer's figures beside the maker's, the as-built backlash, then each
    sized key.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.sizing.SizingResult.summary`.

    Returns
    -------
    list of (str, str, dict)
        Rows of :func:`toothfem.report.summary.text`.
    """
    f = summary["figures"]
    out = [(what, unit, {OURS: f[key][0], MAKER: f[key][1]})
           for key, what, unit in _FIGURES if key in f]
    built = f.get("as_built_backlash_arcmin")
    if built:
        n = built["rings"]
        out += [(f"as built ({n} reducers): backlash median", "arcmin",
                 {OURS: built["median_arcmin"]}),
                ("  P5 / P95", "arcmin",
                 {OURS: f"{built['p5_arcmin']:.3g} / {built['p95_arcmin']:.3g}"}),
                ("  reducers that interfere", "%", {OURS: 100 * built["interfering_share"],
                                                    MAKER: 5.0})]
    for c in summary["choices"]:
        unit = c["key"].rsplit("_", 1)[-1] if c["key"].endswith("_mm") else ""
        out.append((c["key"], unit, {OURS: c["value"]}))
    return out


def markdown(summary: dict) -> str:
    """report.md: the table, the binding figures, each choice's rule and the rounds.

    Parameters
    ----------
    summary : dict
        :meth:`toothfem.sizing.SizingResult.summary`.

    Returns
    -------
    str
    """
    lines = [f"# {summary['case']}: sized to the datasheet", ""]
    lines.append("Every target met inside the envelope." if summary["feasible"] else
                 "**Not every target fits the envelope:**")
    lines += [f"- {b}" for b in summary["binding"]] + [""]
    lines += md_table(rows(summary)) + ["", "## The rule of each choice", ""]
    lines += [f"- `{c['key']}` = {c['value']:g}: {c['rule']} ({c['source']})"
              for c in summary["choices"]]
    lines += ["", "## The search on the system model", ""]
    for i, r in enumerate(summary["rounds"], 1):
        dims = ", ".join(f"{k} {v:g}" for k, v in r["dimensions"].items())
        lines.append(f"{i}. {dims}: rigidity {r['rigidity_Nm_per_arcmin']:.4g} N m/arcmin, "
                     f"unit L10 {r['unit_l10_h']:.4g} h ({r['limiting']}), P_h "
                     f"{r['max_ph_MPa']:.4g} MPa"
                     + (f"; missed: {', '.join(r['missed'])}" if r["missed"] else ""))
    return "\n".join(lines) + "\n"


def write_sizing(result, folder) -> dict:
    """sized_case.toml, sizing.json and report.md into an existing ``folder``.

    Parameters
    ----------
    result : toothfem.sizing.SizingResult
    folder : str or pathlib.Path

    Returns
    -------
    dict
        The summary with the ``files`` written.
    """
    folder = Path(folder)
    (folder / "sized_case.toml").write_text(result.text)
    summary = {**result.summary(), "files": ["sized_case.toml", "sizing.json", "report.md"]}
    (folder / "sizing.json").write_text(json.dumps(summary, indent=2))
    (folder / "report.md").write_text(markdown(summary))
    return summary
