"""toothfem: tooth-contact analysis and efficiency of precision robot reducers.

Subpackages: ``toothfem.geometry`` (profiles, kinematics, train ratios), ``toothfem.fem``
(finite-element contact), ``toothfem.efficiency`` (friction, losses, gear trains).
"""
__version__ = "0.1.0"

from .case import Case, load_case, parse_case  # noqa: E402,F401
from .errors import CaseError, GeometryError, ToothfemError  # noqa: E402,F401
