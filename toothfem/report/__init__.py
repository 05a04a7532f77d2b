"""The reporting layer: every picture and Markdown rendering; takes result records, never
computes physics.

``toothfem.report.loop``: the measured-data loop's residual plots and report.md text.
matplotlib is imported inside the functions that draw (Agg backend, off-screen), so
``import toothfem`` stays light.
"""
