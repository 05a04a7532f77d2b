"""Friction laws, losses and gear-train power flow (installed as ``toothfem.efficiency``).

``predict(case, speed_rpm, torque_Nm, oil_temp_C=None)`` is the vectorised prediction API;
``evaluate`` returns every loss component (efficiency/model.py)."""
from .model import evaluate, predict  # noqa: F401
