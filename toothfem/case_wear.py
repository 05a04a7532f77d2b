"""The case file's ``[wear]`` section: the accuracy life's limit and the wear coefficient
(``toothfem wear``, docs/wear.md). The same frozen dataclass with its schema in the
fields' metadata as :mod:`toothfem.case_sections` (its ``_f`` and ``_Section``)."""
from __future__ import annotations

from dataclasses import dataclass

from .case_sections import _f, _Section


@dataclass(frozen=True)
class Wear(_Section):
    _section = "wear"
    lost_motion_limit_arcmin: float | None = _f(
        0.0, 60.0, lo_open=True, default=None,
        doc="lost motion at the end of the accuracy life: `toothfem wear` prints the hours "
            "the reducer takes to reach it",
        unset="no limit: the hours to one are not printed",
        source="none: the buyer's or maker's specification where the case states it")
    wear_coefficient: float | None = _f(
        0.0, 1e-3, default=None,
        doc="Archard's dimensionless wear coefficient K_b of the contacts in boundary "
            "lubrication (the film ratio's regime scales it down); 0: no wear",
        unset="1e-8",
        source="ASSUMPTION: mild wear of lubricated hardened steel, 1e-10 to 1e-6 (docs/wear.md: "
               "the boundary-lubricated gear steel of A. Flodin & S. Andersson, Wear 207 "
               "(1997) 16-23, 3.7e-6 at 700 HV, its upper end; the RV-40E's published wear "
               "test implies about 5e-10)")
