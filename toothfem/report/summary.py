"""Summaries an engineer reads first: small tables of a contact analysis, an efficiency
evaluation and a whole run, with the case's ``[published]`` figures beside ours.

Each table is a list of rows ``(quantity, unit, {column: value})``; :func:`text` renders it
for the terminal and :func:`markdown` for report.md, so the CLI and the report say the same.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..quantities import CONTACT

#: The papers' names of the figures a case may publish, by our summary key: a case's
#: ``[published]`` value under one of these names is shown beside ours.
PUBLISHED_NAMES = {
    "{contacts}_in_contact_max": ("{contacts}_in_contact",),
    "max_ph_MPa": ("max_contact_stress_MPa", "max_ph_MPa"),
    "max_force_N": ("max_force_N",),
    "efficiency": ("efficiency", "efficiency_computed"),
    "losses.sun_planet_mesh": ("loss_L1_W",),
    "losses.cycloid_mesh": ("loss_L2_W",),
}

#: Why a figure of ours differs from the published one, by the case's ``[published]`` key:
#: stated only where the difference is understood; report.html shows "no reason recorded"
#: for a compared figure without one (toothfem.report.html).
PUBLISHED_REASONS: dict = {
    "max_contact_stress_MPa": (
        "a peak contact pressure needs elements much smaller than the Hertz half-width "
        "(about 0.025 mm at these loads; ours: refined contact zones, Hertz-verified within "
        "2 %); the pin-housing paper's 0.8 mm mesh spreads a pin's force over about one "
        "element, F / (L h) = 250 N / (10 mm x 0.8 mm) = 31 MPa (L the case's assumed face "
        "width), the order of its 45.96 MPa"),
}

#: The column of the published figures and what it means (their conditions are the paper's).
PUBLISHED = "published"
PUBLISHED_NOTE = ("published: the paper's figure as the case file's [published] table quotes "
                  "it, at the paper's own conditions (see the case file)")


def _published(key: str, published: Mapping[str, Any], words: dict):
    """The case's published value for our ``key``, or None."""
    names = PUBLISHED_NAMES.get(key, ())
    if key.startswith("loss_shares."):
        names = ("loss_share_" + key.split(".", 1)[1],)
    for name in names:
        name = name.format(**words)
        if name in published:
            return published[name]
    return None


def contact_rows(summary: dict, labels, published: Mapping[str, Any] | None = None) -> list:
    """The contact summary as rows, the case's published figures beside.

    Parameters
    ----------
    summary : dict
        :attr:`toothfem.pipeline.ContactResult.summary`.
    labels : toothfem.report.contact.ContactLabels
        The drive's words and the torques.
    published : mapping, optional
        The case's ``[published]`` table.

    Returns
    -------
    list of (quantity, unit, {column: value})
    """
    words = {"contact": labels.contact, "contacts": labels.contacts, "member": labels.member}
    rows = [("output torque", "N m", {"ours": labels.output_torque_Nm}),
            (f"torque on {'the' if labels.members == 1 else 'each'} {labels.member}", "N m",
             {"ours": labels.member_torque_Nm})]
    for q in CONTACT:
        template, key = q.key, q.key_for(words)
        if key in summary and summary[key] not in (None, []):
            value = summary[key]
            if key == "interference_pins":      # with their flanks
                value = ", ".join(f"{j} ({f})" for j, f in
                                  zip(value, summary.get("interference_flanks", ())))
            cols = {"ours": value}
            pub = _published(template, published or {}, words)
            if pub is not None:
                cols[PUBLISHED] = pub
            rows.append((q.label_for(words), q.unit_symbol(words), cols))
    return rows


def efficiency_rows(results: dict, published: Mapping[str, Any] | None = None) -> list:
    """Efficiency summaries side by side (one column per load source or method).

    Parameters
    ----------
    results : dict
        Column name -> :func:`toothfem.pipeline.efficiency_summary` mapping.
    published : mapping, optional
        The case's ``[published]`` table.

    Returns
    -------
    list of (quantity, unit, {column: value})
        Efficiency [%], input and output power [W], each loss [W] and its share [%].
    """
    published = published or {}

    def row(what, unit, key, get, scale=1.0):
        cols = {src: get(r) * scale for src, r in results.items() if get(r) is not None}
        pub = _published(key, published, {})
        if pub is not None:
            cols[PUBLISHED] = pub * scale
        return what, unit, cols

    rows = [row("efficiency", "%", "efficiency", lambda r: r["efficiency"], 100.0),
            row("input power", "W", "input_power_W", lambda r: r["input_power_W"]),
            row("output power", "W", "output_power_W", lambda r: r["output_power_W"])]
    names = list(dict.fromkeys(k for r in results.values() for k in r["losses"]))
    for n in names:
        rows.append(row(f"loss: {n}", "W", f"losses.{n}", lambda r, n=n: r["losses"].get(n)))
    for n in names:
        rows.append(row(f"share: {n}", "% of input", f"loss_shares.{n}",
                        lambda r, n=n: r["loss_shares"].get(n), 100.0))
    return rows


def _cell(v) -> str:
    if v is None:
        return "–"
    if isinstance(v, (bool, int)):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return "–"
        return f"{v:.4g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.2e}"
    return str(v)


def _columns(rows) -> list:
    return list(dict.fromkeys(c for _, _, cols in rows for c in cols))


#: The widest a terminal table runs [columns]: a longer quantity name is cut at a word
#: with a reference [n] to its full name in the legend below the table, a longer title
#: wrapped (issue 41).
WIDTH = 100
#: The shortest a cut quantity name gets [characters] (a table whose number columns leave
#: less is wider than WIDTH).
MIN_LABEL = 16


def _shortened(labels: list, budget: int) -> tuple:
    """(labels cut to ``budget`` at a word with a reference [n], {[n]: full label})."""
    out: list = []
    refs: dict = {}
    for label in labels:
        if len(label) <= budget:
            out.append(label)
            continue
        ref = f" [{len(refs) + 1}]"
        indent = label[:len(label) - len(label.lstrip())]
        room = budget - len(ref)
        cut = label[:room + 1].rsplit(" ", 1)[0] if " " in label[len(indent):room + 1] \
            else label[:room]
        if cut.count("(") > cut.count(")"):         # not a bracket left open
            cut = cut[:cut.rfind("(")]
        out.append(cut.rstrip(" ,:;(") + ref)
        refs[ref.strip()] = label.strip()
    return out, refs


def _wrapped(line: str, width: int, indent: str = "") -> list:
    import textwrap
    return textwrap.wrap(line, width, subsequent_indent=indent, break_on_hyphens=False) or [""]


def wrapped(line: str, width: int = WIDTH, indent: str = "    ") -> str:
    """A line of a table's legend (a source, a note) wrapped at ``width``, the lines after
    the first indented.

    Parameters
    ----------
    line : str
    width : int
    indent : str

    Returns
    -------
    str
    """
    return "\n".join(_wrapped(line, width, indent))


def text(rows, title: str = "", width: int = WIDTH, legend: dict | None = None) -> str:
    """The rows as an aligned plain-text table (the terminal's summary), at most ``width``
    columns where its numbers leave room: a longer quantity name cut at a word with a
    reference [n] to its full name, listed below the table; a longer title wrapped.

    Parameters
    ----------
    rows : sequence of (str, str, dict)
        (quantity, unit, {column: value}).
    title : str
        A first line, if given.
    width : int
        The widest line [columns].
    legend : dict, optional
        Short name -> full name of the rows' own short names, listed below the table.

    Returns
    -------
    str
        The table.
    """
    cols = _columns(rows)
    head = ["quantity", "unit", *cols]
    body = [[what, unit, *(_cell(vals.get(c)) for c in cols)] for what, unit, vals in rows]
    widths = [max(len(r[i]) for r in [head, *body]) for i in range(len(head))]
    refs: dict = {}
    over = sum(widths) + 2 * (len(widths) - 1) - width
    if over > 0:
        labels, refs = _shortened([r[0] for r in body], max(MIN_LABEL, widths[0] - over))
        body = [[label, *r[1:]] for label, r in zip(labels, body)]
        widths[0] = max(len(r[0]) for r in [head, *body])
    fmt = lambda r: "  ".join(  # noqa: E731
        (x.ljust(w) if i < 2 else x.rjust(w)) for i, (x, w) in enumerate(zip(r, widths)))
    lines = [w for part in title.splitlines() for w in _wrapped(part, width, "  ")] \
        if title else []
    lines += [fmt(head), fmt(["-" * w for w in widths])]
    lines += [fmt(r) for r in body]
    for name, full in [*(legend or {}).items(), *refs.items()]:
        lines += _wrapped(f"{name}: {full}", width, "    ")
    if PUBLISHED in cols:
        lines += _wrapped(PUBLISHED_NOTE, width, "  ")
    return "\n".join(lines)


def markdown(rows) -> list:
    """The rows as a Markdown table (lines of report.md).

    Parameters
    ----------
    rows : sequence of (str, str, dict)
        (quantity, unit, {column: value}).

    Returns
    -------
    list of str
        The lines.
    """
    cols = _columns(rows)
    out = ["| quantity | unit | " + " | ".join(cols) + " |",
           "|---|---|" + "---|" * len(cols)]
    out += [f"| {what} | {unit} | " + " | ".join(_cell(vals.get(c)) for c in cols) + " |"
            for what, unit, vals in rows]
    if PUBLISHED in cols:
        out += ["", f"_{PUBLISHED_NOTE}_"]
    return out
