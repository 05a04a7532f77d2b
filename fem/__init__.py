"""Finite-element contact (installed as ``toothfem.fem``): gmsh meshes, P2 plane-strain
elasticity (scikit-fem), the complementarity contact solver, Hertz verification cases, the
cycloid drive's load sharing in cycle and detailed modes (docs/fem.md) and the sine pair's
(docs/fem_sine.md)."""
