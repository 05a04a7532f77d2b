"""toothfem: tooth-contact analysis and efficiency of precision robot reducers.

Subpackages: ``toothfem.geometry`` (profiles, kinematics, train ratios), ``toothfem.fem``
(finite-element contact), ``toothfem.efficiency`` (friction, losses, gear trains).

``toothfem.load_case`` and the names below are imported on first use (PEP 562), and so is
a subpackage or module named as an attribute (``toothfem.fem`` after ``import toothfem``):
``import toothfem`` alone, as the console script does before it knows the command, loads
neither numpy nor the FE.
"""
from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING

__version__ = "0.1.0"

#: The package's face: name -> the module that defines it.
_EXPORTS = {"Case": ".case", "load_case": ".case", "parse_case": ".case",
            "CaseError": ".errors", "GeometryError": ".errors", "ToothfemError": ".errors"}
__all__ = ["__version__", *_EXPORTS]

if TYPE_CHECKING:       # what the names are, for type checkers and readers
    from .case import Case, load_case, parse_case  # noqa: F401
    from .errors import CaseError, GeometryError, ToothfemError  # noqa: F401


def __getattr__(name: str):
    """A name of _EXPORTS, or a submodule, imported on first use (then kept here)."""
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    elif not name.startswith("__") and importlib.util.find_spec(f"{__name__}.{name}"):
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted({*globals(), *_EXPORTS})
