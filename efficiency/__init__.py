"""Friction laws, losses and efficiency (installed as ``toothfem.efficiency``).

``predict(case, speed_rpm, torque_Nm, oil_temp_C=None)`` is the vectorised prediction API;
``evaluate`` returns every loss component; ``operating_point`` the case's declared point
(efficiency/evaluation.py). Modules by job: lubricant (viscosity, churning), mesh_table
(the loaded contacts of a period), contact_friction (mu per contact, sliding loss),
drive_losses (every component of each drive), spur (the first stage), rv_paper (the RV
paper's method), friction (the laws), loop/ (measured data)."""
from .evaluation import (Efficiency, evaluate, operating_point, predict,  # noqa: F401
                         rated_output_torque)
