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
