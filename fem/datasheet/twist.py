"""Output twist of a drive at an output torque of either sign: the FE mesh (both flanks)
and the supports in series (docs/stiffness.md).

The twist of the output against the housing, input held, is the sum along the load path
of one member: the mesh rotation of the cycle solver (the rigid unknown beta, clearances
closed and elastic approach included), the member's own supports (crank or eccentric
bearings, output pins: ``Drive.member_support_twists``), the parts the members share
(crankshaft bending, ``Drive.coupled_compliance``), the parts every path runs through
(crankshaft torsion, ``Drive.output_compliance``) and the carrier (the case's stiffness, or
rigid). Every member stands at the first member's configuration here (one pitch's
positions; :mod:`toothfem.fem.datasheet.transmission` takes their different configurations
over the full period): they share the output torque evenly
(``Drive.member_torque(peak=False)``) unless the crankshafts load them unalike (three discs:
the middle one at mid-span), and then the member torques that turn every member alike on
the position-mean twist are found from the FE (:mod:`toothfem.fem.datasheet.split`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ...units import ARCMIN, ARCSEC  # noqa: F401  (the datasheet's angles, re-exported)
from .split import even_coupling, member_torques

if TYPE_CHECKING:
    from ..load_sharing import LoadSharing

#: A contact counts as closed at zero torque when the rigid rotation leaves it a gap below
#: this fraction of the largest gap it closes (rounding of the exact clearances).
CLOSED_GAP_REL = 1e-9
#: The limit of zero torque is the FE solution at this output torque [N m] of the flank's
#: sign: its elastic part is below 1e-6 of the twist at 100 N m (linear-ish in the torque),
#: while the rigid closing rotation of the clearances is all there (the sine pair's flanks
#: close where their gap has no minimum of its own, so no gap table gives that rotation).
ZERO_TORQUE_NM = 1e-4
#: The loop's split where the crankshafts load the members unalike: the first slope's step
#: (a fraction of the even share) and the settling tolerance (a fraction of the torque; a
#: twist error of the same order, far below the 4 digits reported).
SPLIT_STEP, SPLIT_TOL = 0.02, 1e-7


@dataclass(frozen=True, kw_only=True)
class TwistPoint:
    """The twist at one output torque, per position: ``paths`` {name: (P,) rad} whose sum
    is ``total``; ``contacts`` (P,) loaded contacts of the member."""
    output_torque_Nm: float
    total: np.ndarray
    paths: dict
    contacts: np.ndarray
    load_sharing: LoadSharing | None = None     # the mesh's (None at zero torque)
    member_torques_Nm: tuple = ()   # (M,) the members' torques [N m], signed


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
        self._coupled = {k: np.asarray(v, float)
                         for k, v in drive.coupled_compliance(supports).items()}
        m = drive.members
        self._coupling = sum(self._coupled.values(), np.zeros((m, m)))    # S, every part
        self._even = m == 1 or even_coupling(self._coupling)
        self._output = dict(drive.output_compliance(supports))
        if supports.carrier_stiffness_Nm_per_rad:
            self._output["carrier"] = 1.0 / supports.carrier_stiffness_Nm_per_rad
        self._memo: dict[tuple[float, int], TwistPoint] = {}
        # (torque, side) -> (paths, LoadSharing or None, contacts (P,)): :meth:`_own`
        self._own_memo: dict[tuple[float, int],
                             tuple[dict[str, np.ndarray], LoadSharing | None, np.ndarray]] = {}
        # (shares (M,), slopes (M,)): Newton's next start
        self._last_split: tuple[np.ndarray, np.ndarray] | None = None

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

    def at(self, output_torque_Nm: float, side: int = 1, branch: int = 0) -> TwistPoint:
        """The twist at a signed output torque (kept: each torque is solved once).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign.
        side : {1, -1}
            At zero torque, the flank the limit comes from (the rigid closing rotation,
            every support unloaded); ignored otherwise.
        branch : {0, 1, -1}
            The way the torque came; ignored (no friction in these load paths: both
            branches are the elastic curve).

        Returns
        -------
        TwistPoint
            The first member's paths at its torque, the shared parts under every member's.
        """
        t = float(output_torque_Nm)
        key = (t, side if t == 0 else 0)
        if key not in self._memo:
            m = self.drive.members
            if t == 0:
                x = np.zeros(m)
            elif self._even:
                x = np.full(m, self.member_torque(t))
            else:
                x = self._split(t)
            flank = side if t == 0 else int(math.copysign(1, t))
            own, ls, contacts = self._own(float(x[0]), flank if x[0] == 0 else 0)
            paths = dict(own)
            n = self.positions_rad.size
            paths.update({name: np.full(n, s[0] @ x) for name, s in self._coupled.items()})
            paths.update(self.through(t))
            self._memo[key] = TwistPoint(
                output_torque_Nm=t, total=np.sum(np.stack(list(paths.values())), axis=0),
                paths=paths, contacts=contacts, load_sharing=ls,
                member_torques_Nm=tuple(float(v) for v in x))
        return self._memo[key]

    def own(self, member_torque_Nm: float, side: int = 1) -> dict:
        """One member's own paths, its mesh and its own supports, at its torque.

        Parameters
        ----------
        member_torque_Nm : float
            [N m], either sign.
        side : {1, -1}
            At zero torque, the flank the limit comes from (the mesh's closing rotation,
            the supports at rest); ignored otherwise.

        Returns
        -------
        dict
            {path: (P,) rad}, the mesh first.
        """
        tm = float(member_torque_Nm)
        return self._own(tm, side if tm == 0 else 0)[0]

    def through(self, output_torque_Nm: float) -> dict:
        """The parts every member's path runs through (crank torsion, the carrier).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign.

        Returns
        -------
        dict
            {path: (P,) rad}.
        """
        n = self.positions_rad.size
        return {name: np.full(n, c * float(output_torque_Nm))
                for name, c in self._output.items()}

    def _own(self, tm: float, side: int):
        """(paths, LoadSharing or None, contacts (P,)) of one member at torque tm, kept."""
        key = (tm, side)
        if key not in self._own_memo:
            if tm == 0:      # the mesh at ZERO_TORQUE_NM of output torque, supports at rest
                near, _, contacts = self._own(self.member_torque(side * ZERO_TORQUE_NM), 0)
                paths = {name: np.zeros_like(v) for name, v in near.items()}
                paths["mesh"] = near["mesh"]
                self._own_memo[key] = (paths, None, contacts)
            else:
                n = self.positions_rad.size
                ls = self.solver.solve(tm, **self.solve_options)
                paths = {"mesh": np.asarray(ls.transmission_error, float)}
                paths.update(self.drive.member_support_twists(
                    self.supports, np.full(n, tm), resultant(ls, self.state),
                    self.positions_rad))
                self._own_memo[key] = (paths, ls, ls.contacts_per_position)
        return self._own_memo[key]

    def _split(self, t: float) -> np.ndarray:
        """Member torques (M,) at output torque t where the crankshafts load the members
        unalike: Newton's method on each member's position-mean twist from the FE, slopes
        by secants (a 2 % step first), starting from the last split found."""
        m = self.drive.members
        sign, total = math.copysign(1.0, t), abs(t)
        side = int(sign)

        def mean(x):
            return sign * float(sum(v.mean() for v in self.own(sign * x, side).values()))

        shares, slope = self._last_split or (np.full(m, 1.0 / m), np.full(m, np.nan))
        slope = slope.copy()
        last: dict[int, tuple[float, float]] = {}     # member -> (torque, twist) of the last step

        def paths(x):
            f = np.array([mean(v) for v in x])
            for j, (v, fj) in enumerate(zip(x, f)):
                if j in last and abs(last[j][0] - v) > 1e-9 * total:
                    slope[j] = (fj - last[j][1]) / (v - last[j][0])
                elif not np.isfinite(slope[j]):
                    h = SPLIT_STEP * total / m
                    slope[j] = (mean(v + h) - fj) / h
                last[j] = (v, fj)
            return f, slope.copy()

        x, _ = member_torques(paths, self._coupling, total, np.full(m, mean(0.0)),
                              start=shares * total, tol=SPLIT_TOL)
        self._last_split = (x / total, slope)
        return sign * x
