"""The datasheet of a case from the contact model, as Python calls: ``stiffness_analysis``
(hysteresis, rigidity, lost motion, backlash, compliances in series, loaded TE, the split
between the members), what ``toothfem stiffness`` and the run report call (their files:
``toothfem.report.stiffness.write_stiffness``; fem/datasheet/ holds the mechanics;
docs/stiffness.md)."""
from __future__ import annotations

from dataclasses import dataclass


from .case import Case, as_case
from .errors import CaseError, check_range
from .fem.datasheet.sheet import Datasheet, datasheet, loop_torques
from .fem.datasheet.transmission import LoadedTE, MemberSplit
from .fem.drives import MAX_POSITIONS, drive_for
from .efficiency import rated_output_torque
from .efficiency.no_load import path_friction
from .fem.system.datasheet import BearingLoads, SystemTwist, system_te

#: The one transmission error every command names (docs/stiffness.md, "One transmission
#: error").
TE_DEFINITION = ("the output's lag behind its kinematic position, input held at each crank "
                 "angle, under the output torque: the system model of the whole reducer")
#: The maker's figures the datasheet shows beside ours (the case's ``[published]``, same
#: names: the catalogue's lost motion is at +-3 % of the rated torque, as ours).
MAKER_FIGURES = ("torsional_rigidity_Nm_per_arcmin", "lost_motion_arcmin", "backlash_arcmin")
#: Full-period sampling of the loaded TE by default: cycle solvers over the period and
#: positions per pitch of each (fem/datasheet/transmission.py; one factorisation each).
TE_SAMPLES, TE_PER_PITCH = 6, 12


@dataclass(frozen=True, kw_only=True)
class StiffnessResult:
    """The datasheet of a case (hysteresis loop and catalogue figures), its loaded TE over
    the full period, the split between the members (None for one member) and every
    bearing's load over the period."""
    case_name: str
    sheet: Datasheet
    te: LoadedTE
    split: MemberSplit | None       # None for one member
    summary: dict
    bearings: BearingLoads

    def table(self) -> list:
        """The datasheet's rows, as every table shows them.

        Returns
        -------
        list of (str, str)
            Quantity with its unit, and the formatted value
            (:func:`toothfem.report.stiffness.datasheet_rows`).
        """
        from .report.stiffness import datasheet_rows
        return datasheet_rows(self.summary)

    def plot(self) -> dict:
        """The datasheet's pictures.

        Returns
        -------
        dict
            File name -> matplotlib Figure (:func:`toothfem.report.stiffness.
            stiffness_figures`).
        """
        from .report.stiffness import stiffness_figures
        return stiffness_figures(self)

    def write(self, folder) -> dict:
        """The datasheet's files into an existing ``folder`` (CSV, PNG, summary.json).

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary with the names of the files written
            (:func:`toothfem.report.stiffness.write_stiffness`).
        """
        from .report.stiffness import write_stiffness
        return write_stiffness(self, folder)


def stiffness_analysis(case: Case, *, torque_max_Nm: float | None = None, steps: int = 8,
                       positions: int = 36, te_torque_Nm: float | None = None,
                       te_samples: int = TE_SAMPLES, te_positions: int = TE_PER_PITCH,
                       friction: bool = True) -> StiffnessResult:
    """Torsional stiffness, hysteresis, lost motion, loaded TE and member split of a case
    (docs/stiffness.md).

    Parameters
    ----------
    case : toothfem.case.Case
    torque_max_Nm : float, optional
        Largest torque of the loop [N m]; default the rated torque (``[operating]
        rated_torque_Nm``, else the operating torque, marked assumed).
    steps : int
        Torque steps from 0 to the largest torque (the loop has 5 steps + 1 points).
    positions : int
        Meshing positions over one period of the loop's cycle solver.
    te_torque_Nm : float, optional
        Output torque of the loaded TE and the split; default the rated torque.
    te_samples, te_positions : int
        Cycle solvers over the full period, and positions per pitch of each.
    friction : bool
        Friction in the quasi-static path (:func:`path_friction`): the loop's width and
        the hysteresis loss; False: the elastic curve.

    Returns
    -------
    StiffnessResult

    Raises
    ------
    CaseError
        If ``positions`` is outside its range, ``torque_max_Nm`` is not positive, or the
        case declares neither a rated nor an operating torque and none is given.
    """
    case = as_case(case)
    check_range("positions", positions, 1, MAX_POSITIONS, error=CaseError)
    loop_torques(1.0, steps)                   # steps refused before any work
    drive = drive_for(case)
    si = case.to_si()
    rated, assumed = rated_output_torque(si)
    if torque_max_Nm is not None:
        check_range("torque_max_Nm", torque_max_Nm, 0, None, lo_open=True, error=CaseError)
    supports = drive.supports(si.supports)
    system = drive.system_model(supports, positions)       # the whole reducer
    twist = SystemTwist(system, friction=path_friction(si, drive) if friction else None)
    te, split, bearings = system_te(drive, supports, te_torque_Nm or rated,
                                    samples=te_samples, per_pitch=te_positions)
    sheet = datasheet(twist, rated, rated_assumed=assumed, torque_max_Nm=torque_max_Nm,
                      steps=steps)
    summary = {"case": case.name, "drive": drive.kind, **sheet.summary(), **te.summary(),
               "te_definition": TE_DEFINITION,
               **({} if split is None else split.summary()), **bearings.summary()}
    if split is not None:
        summary["member_load_factor_case"] = drive.load_factor
    maker = {key: float(case.published[key]) for key in MAKER_FIGURES
             if key in case.published}
    if maker:
        summary["maker"] = maker
    return StiffnessResult(case_name=case.name, sheet=sheet, te=te, split=split,
                           summary=summary, bearings=bearings)


