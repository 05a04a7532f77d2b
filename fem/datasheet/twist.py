"""Output twist of a drive at an output torque of either sign: the FE mesh (both flanks)
and the supports in series (docs/stiffness.md).

The twist of the output against the housing, input held, is the sum along the load path
of one member: the mesh rotation of the cycle solver (the rigid unknown beta, clearances
closed and elastic approach included), the member's own supports (crank or eccentric
bearings, output pins: ``Drive.member_support_twists``), the parts the members share
(crankshaft bending, ``Drive.coupled_compliance``), the parts every path runs through
(crankshaft torsion, ``Drive.output_compliance``) and the carrier (the case's stiffness, or
rigid). The members share the output torque evenly here (``Drive.member_torque(peak=
False)``); :mod:`toothfem.fem.datasheet.transmission` computes their split.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import CaseError

#: One arc minute and one arc second [rad].
ARCMIN = math.pi / (180 * 60)
ARCSEC = ARCMIN / 60
#: A contact counts as closed at zero torque when the rigid rotation leaves it a gap below
#: this fraction of the largest gap it closes (rounding of the exact clearances).
CLOSED_GAP_REL = 1e-9
#: The limit of zero torque is the FE solution at this output torque [N m] of the flank's
#: sign: its elastic part is below 1e-6 of the twist at 100 N m (linear-ish in the torque),
#: while the rigid closing rotation of the clearances is all there (the sine pair's flanks
#: close where their gap has no minimum of its own, so no gap table gives that rotation).
ZERO_TORQUE_NM = 1e-4


@dataclass(frozen=True, kw_only=True)
class TwistPoint:
    """The twist at one output torque, per position: ``paths`` {name: (P,) rad} whose sum
    is ``total``; ``contacts`` (P,) loaded contacts of the member."""
    output_torque_Nm: float
    total: np.ndarray
    paths: dict
    contacts: np.ndarray
    load_sharing: object = None     # the mesh's LoadSharing (None at zero torque)


def closing_rotation(state, side: int) -> np.ndarray:
    """Rigid rotation of the member that closes its first contact on one flank.

    The twist in the limit of zero torque: side * min gap/|l| over the contacts with
    side * l < 0 (MeshingState convention).

    Parameters
    ----------
    state : toothfem.geometry.kinematics.MeshingState
        Its gaps and moment arms l.
    side : {1, -1}
        Sign of the torque whose flank closes.

    Returns
    -------
    numpy.ndarray, shape (P,)
        [rad], signed.

    Raises
    ------
    CaseError
        If a position has no contact on that flank.
    """
    arm = state.moment_arm
    carry = (side * arm < 0) & np.isfinite(state.gap)
    ratio = np.where(carry, state.gap / np.where(carry, np.abs(arm), 1.0), np.inf)
    theta = np.min(ratio, axis=1)
    if not np.all(np.isfinite(theta)):
        raise CaseError("a meshing position has no contact on the flank of a "
                        f"{'positive' if side > 0 else 'negative'} torque")
    return side * theta


def resultant(load_sharing, state) -> np.ndarray:
    """Resultant contact force on the member: forces along the MeshingState normals.

    Parameters
    ----------
    load_sharing : LoadSharing
        Forces (P, C) [N].
    state : toothfem.geometry.kinematics.MeshingState
        Normals (P, C, 2), fixed -> moving member.

    Returns
    -------
    numpy.ndarray, shape (P, 2)
        [N], housing frame.
    """
    return np.sum(load_sharing.force[:, :, None] * state.normal, axis=1)


class TwistModel:
    """The twist of a drive at any output torque over a set of positions.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    solver
        The drive's cycle solver at ``solver.positions_rad`` serving both torque signs
        (``Drive.cycle_solver(..., solver_options=drive.both_sides_options)``).
    solve_options : dict, optional
        Passed to every ``solver.solve`` (a built reducer's ``deviation`` and ``pitches``).
    state : toothfem.geometry.kinematics.MeshingState, optional
        ``drive.meshing`` at the solver's positions, if the caller has it.
    """

    def __init__(self, drive, supports, solver, solve_options: dict | None = None,
                 state=None):
        self.drive = drive
        self.supports = supports
        self.solver = solver
        self.solve_options = dict(solve_options or {})
        self.positions_rad = np.asarray(solver.positions_rad, float)
        self.state = drive.meshing(self.positions_rad) if state is None else state
        coupled = drive.coupled_compliance(supports)
        # even split: member 0 sees every member's torque T/M through the shared parts
        self._coupled = {k: float(np.sum(v[0])) for k, v in coupled.items()}
        self._output = dict(drive.output_compliance(supports))
        if supports.carrier_stiffness_Nm_per_rad:
            self._output["carrier"] = 1.0 / supports.carrier_stiffness_Nm_per_rad
        self._memo = {}

    @property
    def path_names(self) -> list:
        """Every path of the twist, the mesh first."""
        z = self.at(0.0, side=1)
        return list(z.paths)

    @property
    def member_path_names(self) -> list:
        """The member's own paths: the mesh and its own supports (not the shared parts)."""
        n = self.positions_rad.size
        own = self.drive.member_support_twists(self.supports, np.zeros(n), np.zeros((n, 2)),
                                               self.positions_rad)
        return ["mesh", *own]

    def member_torque(self, output_torque_Nm: float) -> float:
        """Even share of a signed output torque on one member.

        Parameters
        ----------
        output_torque_Nm : float
            Signed [N m].

        Returns
        -------
        float
            [N m], the output torque's sign.
        """
        t = float(output_torque_Nm)
        return math.copysign(self.drive.member_torque(abs(t), peak=False), t)

    def at(self, output_torque_Nm: float, side: int = 1) -> TwistPoint:
        """The twist at a signed output torque (kept: each torque is solved once).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign.
        side : {1, -1}
            At zero torque, the flank the limit comes from (the rigid closing rotation,
            every support unloaded); ignored otherwise.

        Returns
        -------
        TwistPoint
        """
        t = float(output_torque_Nm)
        key = (t, side if t == 0 else 0)
        if key not in self._memo:
            self._memo[key] = self._zero(side) if t == 0 else self._loaded(t)
        return self._memo[key]

    def _zero(self, side: int) -> TwistPoint:
        """The mesh rotation at ZERO_TORQUE_NM of the flank's sign, every support at rest."""
        near = self._loaded(side * ZERO_TORQUE_NM)
        n = self.positions_rad.size
        paths = {name: np.zeros(n) for name in near.paths}
        paths["mesh"] = near.paths["mesh"]
        return TwistPoint(output_torque_Nm=0.0, total=paths["mesh"].copy(), paths=paths,
                          contacts=near.contacts)

    def _supports(self, t: float, tm: float, force) -> dict:
        """{path: (P,) rad} of every support at output torque t, member torque tm and the
        member's contact resultant ``force`` (P, 2)."""
        n = self.positions_rad.size
        out = dict(self.drive.member_support_twists(self.supports, np.full(n, tm), force,
                                                    self.positions_rad))
        out.update({name: np.full(n, c * tm) for name, c in self._coupled.items()})
        out.update({name: np.full(n, c * t) for name, c in self._output.items()})
        return out

    def _loaded(self, t: float) -> TwistPoint:
        tm = self.member_torque(t)
        ls = self.solver.solve(tm, **self.solve_options)
        paths = {"mesh": np.asarray(ls.transmission_error, float)}
        paths.update(self._supports(t, tm, resultant(ls, self.state)))
        total = np.sum(np.stack(list(paths.values())), axis=0)
        return TwistPoint(output_torque_Nm=t, total=total, paths=paths,
                          contacts=ls.contacts_per_position, load_sharing=ls)
