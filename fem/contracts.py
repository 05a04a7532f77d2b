"""The contracts every drive's FE modes keep, as types (docs/architecture.md, "Adding a
drive"): the cycle solver (cycle mode) and the detailed result (detailed mode). The cycloid
and the sine pair implement them (``fem/cycloid_fe``, ``fem/sine_fe``); a new drive's
modes are checked against them by mypy through :class:`toothfem.fem.drives.Drive`, and
``tests/test_registry.py`` checks each shipped drive's at run time.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

if TYPE_CHECKING:
    from .elastic import Body
    from .load_sharing import LoadSharing


@runtime_checkable
class CycleSolver(Protocol):
    """Cycle mode: the load sharing of one moving member at every position of a period,
    on influence tables built once (docs/fem.md).

    Attributes
    ----------
    model : object
        The FE model the solver was built on (``Drive.fe_model``).
    positions_rad : numpy.ndarray
        The crank angles of the positions [rad].
    has_structural_field : bool
        Whether :meth:`structural_field` draws the member's stress field from its tables.
    """
    model: Any
    positions_rad: np.ndarray
    has_structural_field: bool

    def prepare(self) -> None:
        """Build (or read from the disk cache) the influence tables now."""

    def solve(self, torque: float, progress: Any = None, *, deviation: Any = None,
              pitches: Any = None) -> LoadSharing:
        """The load sharing at every position.

        Parameters
        ----------
        torque : float
            Torque on the member [N m]; a negative torque loads the other flank.
        progress : callable, optional
            A progress bar over the positions.
        deviation : object, optional
            A built stage's deviations (``fem.deviations``), as shifts of the initial gaps.
        pitches : array_like of int, optional
            The pitch of each position, where the deviations differ from pitch to pitch.

        Returns
        -------
        toothfem.fem.load_sharing.LoadSharing
        """
        ...

    def structural_field(self, p: int, load_sharing: LoadSharing) -> Any:
        """The member's body and displacement at one position under the solved forces
        (only where ``has_structural_field``; else a ValueError naming the detailed mode).

        Parameters
        ----------
        p : int
            Index into ``positions_rad``.
        load_sharing : toothfem.fem.load_sharing.LoadSharing
            A result of :meth:`solve`.

        Returns
        -------
        (Body, numpy.ndarray)
        """
        ...


@runtime_checkable
class DetailedSolution(Protocol):
    """Detailed mode: the two-body FE contact at one position (verification, stress
    fields).

    Attributes
    ----------
    load_sharing : toothfem.fem.load_sharing.LoadSharing
        The one position's contact forces and pressures.
    dofs : int
        Degrees of freedom of the solve.
    """
    load_sharing: LoadSharing
    dofs: int

    @property
    def member_body(self) -> Body | None:
        """The moving member's body (its own frame), for its stress field."""

    @property
    def member_displacement(self) -> np.ndarray | None:
        """The moving member's nodal displacements [m]."""


@runtime_checkable
class ReducerModel(Protocol):
    """The one model of the whole reducer around the contact (``Drive.system_model``,
    docs/stiffness.md): its bodies, elastic elements and unilateral contacts, solved at one
    position of a meshing period under an output torque, input held. Every analysis of
    the reducer asks it: the datasheet's twist (:class:`toothfem.fem.system.datasheet.
    SystemTwist`), the TE over the full period and the split between the members
    (``system_te``), the bearings' loads, the tolerance ensemble and the design search.

    Attributes
    ----------
    drive : toothfem.fem.drives.Drive
        The drive it was built for.
    supports : toothfem.fem.datasheet.supports.Supports
        The supports it was built on.
    n_positions : int
        Positions per meshing period.
    discs : int
        Moving members (discs, the sine planet).
    slots : tuple
        Each member's place: its cycle solver (``slot.solver``), phase and offset.
    pitch_tables : tuple or None
        Each member's influence tables at every pitch, where the model was built to solve
        any pitch (``pitch_samples``); None otherwise.
    """
    drive: Any
    supports: Any
    n_positions: int
    discs: int
    slots: tuple
    pitch_tables: Any

    def solve(self, output_torque_Nm: float, p: int, *, side: int | None = None,
              start: Any = None, friction: Any = None, deviation: Any = None,
              pitch: int = 0, geometry: Any = None) -> Any:
        """The state at one position under an output torque (input held).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], nonzero; its sign loads the flank.
        p : int
            Position index in the meshing period.
        side : {1, -1}, optional
            The flank the contacts' half-widths are taken for (the torque's sign).
        start : object, optional
            A nearby state to start from.
        friction : object, optional
            The friction coefficients the state's friction torque is reported with.
        deviation : object, optional
            A built stage's deviations (``fem.deviations``).
        pitch : int
            The built stage's meshing periods on from the position.
        geometry : object, optional
            The member with other modifications, on these tables.

        Returns
        -------
        object
            The state: its twist [rad], member torques [N m], contact and bearing forces
            [N], the twist's part in each element.
        """
        ...

    def closing_rotation(self, p: int, side: int, *, deviation: Any = None, pitch: int = 0,
                         geometry: Any = None) -> float:
        """The output's rigid turn that closes the first contact of a flank, every part
        rigid: the zero-torque limit of the twist.

        Parameters
        ----------
        p : int
            Position index.
        side : {1, -1}
            The flank.
        deviation, pitch, geometry
            As :meth:`solve`'s.

        Returns
        -------
        float
            [rad], signed.
        """
        ...

    def member_record(self, j: int, states: Any, meshing: Any = None) -> LoadSharing:
        """Member ``j``'s load sharing over the positions of ``states``.

        Parameters
        ----------
        j : int
            Member index.
        states : list
            One state of :meth:`solve` per position, in order.
        meshing : toothfem.geometry.kinematics.MeshingState, optional
            The first member's meshing at the positions, if known.

        Returns
        -------
        toothfem.fem.load_sharing.LoadSharing
        """
        ...

    def variant(self, **changes: Any) -> ReducerModel:
        """The same model with parts changed, its FE tables shared: what the rig loop's
        effects set.

        Parameters
        ----------
        **changes
            Rigid groups, a bearing's play or stiffness, stiffness scales.

        Returns
        -------
        ReducerModel
        """
        ...
