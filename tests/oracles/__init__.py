"""Test oracles: the papers' methods reproduced literally, to check the production model
(``toothfem.efficiency``) against, not part of the installed package.

* ``sine_paper`` -- Lu & Xu, "Transmission efficiency of one tooth difference sine tooth
  profile planetary reducer", Heliyon 10 (2024) e26300: the mesh efficiency per meshing
  position and the readings of its Eqs. 15-25;
* ``mesh_loss`` -- that paper's Eq. 21 loss summed over a load-sharing record;
* ``power_flow`` -- the general virtual-power flow of Chen & Angeles, J. Mech. Des. 129
  (2007) 107-113, for any one-degree-of-freedom train.

Tests import them as ``from tests.oracles import sine_paper``; a script outside tests/
puts the repository root on sys.path first (benchmarks/sine_mesh_reading.py does).
"""
