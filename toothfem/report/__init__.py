"""The reporting layer: every picture and Markdown rendering; takes result records, never
computes physics.

``toothfem.report.plots``: drawings and efficiency charts; ``toothfem.report.contact``: load
sharing and stress fields; ``toothfem.report.loop``: the measured-data loop's residual plots
and report.md text. matplotlib and pyvista are imported inside the functions that draw
(Agg backend, off-screen), so ``import toothfem`` stays light.
"""


def pyplot():
    """matplotlib.pyplot on the off-screen Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
