"""The reporting layer: every picture, table and Markdown rendering; takes result records,
never computes physics.

``toothfem.report.plots``: drawings and efficiency charts; ``toothfem.report.contact``: load
sharing and transmission error; ``toothfem.report.field``: stress fields;
``toothfem.report.summary``: the tables the commands print and report.md shows;
``toothfem.report.loop``: the measured-data loop's residual plots and report.md text;
``toothfem.report.html``: the one self-contained report.html of each output folder (the
only place HTML is written). matplotlib is imported inside the functions that draw (Agg
backend, off-screen: no display, no VTK window), so ``import toothfem`` stays light.
Every picture's title names the case and the user's quantities with units; legends sit
outside the data.
"""
import re


def pyplot():
    """matplotlib.pyplot on the off-screen Agg backend (imported on first use).

    Returns
    -------
    module
        matplotlib.pyplot.
    """
    import os
    import sys

    if "matplotlib" not in sys.modules and os.environ.get("MPLBACKEND"):
        # matplotlib refuses to import under a backend name it does not know (a stale
        # MPLBACKEND); toothfem draws off-screen whatever the environment names
        os.environ.pop("MPLBACKEND")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


#: Resolution of every PNG [dots per inch]: figures are sized in inches for a page width.
DPI = 120


def save(fig, path, dpi: int = DPI):
    """Write ``fig`` to ``path`` (PNG) and close it (figures are not kept in memory).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or pathlib.Path
        The PNG.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    str or pathlib.Path
        ``path``.
    """
    fig.savefig(path, dpi=dpi, bbox_inches="tight", pad_inches=0.1)   # nothing clipped
    pyplot().close(fig)
    return path


def wrap(text: str, width: int) -> str:
    """``text`` with each of its lines wrapped at ``width`` characters (titles that fit).

    A line is broken at spaces only: never inside a quantity (``P_h 623.3 MPa``), a ripple's
    ``1.89 arcsec peak to peak`` or a ``(cycle mode)``, nor at a hyphen; a word longer than
    ``width`` stays whole.

    Parameters
    ----------
    text : str
        The text, lines separated by newlines.
    width : int
        Characters per line.

    Returns
    -------
    str
        The wrapped text.
    """
    import textwrap

    return "\n".join(textwrap.fill(_PHRASE.sub(_glued, _QUANTITY.sub(_glued, line)),
                                   width, break_on_hyphens=False,
                                   break_long_words=False).replace(NBSP, " ")
                     for line in text.split("\n"))


#: A quantity a title must not break: an optional symbol (``P_h``, ``T``, ``x =``), a number
#: and its unit; its spaces become no-break spaces (textwrap breaks at ASCII whitespace only).
_QUANTITY = re.compile(
    r"(?:\b(?:[A-Za-z]\w*_\w+|[A-Za-z]{1,2}\d?)\s(?:[=<>≤≥]\s)?)?[-+]?\d[\d.,]*(?:e[-+]?\d+)?"
    r"\s(?:N\sm(?:/arcmin)?|N\smm|MPa|GPa|kN|N|mm|um|µm|m|deg|arcmin|arcsec|rpm|kW|W|C|K|%|h|s)"
    r"(?![\w/])")
NBSP = "\u00a0"
#: Phrases a title must not break either (their spaces become no-break spaces too): a
#: ripple's "peak to peak" (with the unit before it: "1.89 arcsec peak to peak"), and a mode
#: in parentheses ("(cycle mode)") that would otherwise leave "mode)" alone on a line.
_PHRASE = re.compile(r"(?:(?<!\w)(?:arcsec|arcmin|um|µm|mm|MPa|N|%)\s+)?"
                     r"\bpeak\s+to\s+peak\b|\((?:cycle|detailed|analytic)\s+mode\)")


def _glued(match) -> str:
    return match.group(0).replace(" ", NBSP)
