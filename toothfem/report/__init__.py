"""The reporting layer: every picture and Markdown rendering. Takes result records, never
computes physics; matplotlib and pyvista are imported inside the functions that draw."""


def pyplot():
    """matplotlib.pyplot on the off-screen Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
