"""Profiles, meshing kinematics and train ratios (installed as ``toothfem.geometry``)."""
from .kinematics import MeshingState  # noqa: F401
