"""What every piece of the system model shares (docs/stiffness.md, "The system model"):
the parts it names, its records (a member's slot, a solved state), the coordinate vector
by named blocks, e_z x v, a contact set made stiffer, and the stiffness of a part made
rigid. The shared core
(:class:`toothfem.fem.drives.assembly.CycloidSystem`), its output paths
(:mod:`toothfem.fem.system.paths`) and its friction (:mod:`toothfem.fem.system.friction`)
build on these.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..cycloid_fe.cycle import CycleSolver as CycloidCycleSolver
    from ..sine_fe.cycle import CycleSolver as SineCycleSolver

#: The parts of the model (the ``rigid`` option's names), as the outputs of a 2K-V drive
#: name their share of the twist; a path may name them otherwise
#: (:attr:`toothfem.fem.system.paths.OutputPath.group_names`).
GROUPS = ("crank bearings", "support bearings", "crankshaft bending", "crankshaft torsion",
          "spur mesh")
#: The stiffness of a part made rigid for a limit case [N/m or N m/rad]: 1e5 times the
#: stiffest part of a reducer (a pin contact, ~1e9 N/m): its compliance is 1e-5 of the
#: others', and the saddle system's round-off stays near 1e-8 of the coordinates.
RIGID_STIFFNESS = 1e14
#: A linear part made rigid is this many times stiffer than it is (its share of the
#: compliance falls to 1e-5 of its own; a rotation's stiffness is not in N/m).
RIGID_FACTOR = 1e5


@dataclass(frozen=True)
class DiscSlot:
    """Disc j in the system: its phase, axial place, the grid offset of its configuration
    (``Drive.member_offsets``), the turn beta_j about the housing centre from that
    configuration of the first disc to where it stands, and its cycle solver."""
    index: int
    phase_rad: float
    axial_m: float
    offset: int
    beta_rad: float
    solver: CycloidCycleSolver | SineCycleSolver


@dataclass(frozen=True)
class SystemState:
    """The system at one crank angle and output torque."""
    output_torque_Nm: float
    position_rad: float
    twist_rad: float                 # the output flange's rotation
    pin_force_N: np.ndarray          # (discs, Zb) by pin number (a built stage solved at
                                     # pitch=m: pin j stands for pin j + m)
    disc_torque_Nm: np.ndarray       # (discs,) moment of each disc's pin forces about it
    contacts: np.ndarray             # (discs,) pins that carry
    bearing_force_N: dict            # name -> (2,) force on the inner ring, housing frame
    output_pin_force_N: np.ndarray | None   # K-H-V: (discs, output pins) [N]
    paths_rad: dict                  # group -> its part of the twist (sum: twist)
    equilibrium: object = field(repr=False, default=None)
    friction_Nm: dict = field(default_factory=dict)   # source -> friction torque on the output
    mesh: tuple = field(repr=False, default=())      # each member's MeshSolution

    @property
    def friction_torque_Nm(self) -> float:
        """The friction torque the output meets as the twist grows here [N m]."""
        return float(sum(self.friction_Nm.values()))


def perp(v) -> np.ndarray:
    """e_z x v, the plane vector turned by +90 deg.

    Parameters
    ----------
    v : array_like, shape (2,) or (2, N)

    Returns
    -------
    numpy.ndarray
        (-v_y, v_x), the shape of ``v``.
    """
    v = np.asarray(v, float)
    return np.stack([-v[1], v[0]])


class Coordinates:
    """Named slices of the coordinate vector."""

    def __init__(self):
        self.n = 0
        self.index = {}

    def add(self, name: str, size: int = 1) -> slice:
        """A new named block of coordinates.

        Parameters
        ----------
        name : str
        size : int

        Returns
        -------
        slice
            Its place in the coordinate vector.
        """
        sl = slice(self.n, self.n + size)
        self.index[name] = sl
        self.n += size
        return sl

    def row(self, terms) -> np.ndarray:
        """One deformation row.

        Parameters
        ----------
        terms : dict of str to float or array_like
            Coefficient of each named block (a scalar, or an array of the block's size).

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        r = np.zeros(self.n)
        for name, c in terms.items():
            r[self.index[name]] += c
        return r


def softened(base, local, factor: float):
    """A contact set's flexibility ``factor`` times as stiff: its flexibility over the
    factor (the FE tables and the local law alike).

    Parameters
    ----------
    base : numpy.ndarray or None
        (C, C) [m/N], as :class:`toothfem.fem.system.solve.ContactSet` takes it.
    local : callable or None
        lam [N] -> (C,) [m/N].
    factor : float
        > 0; 1 gives ``base`` and ``local`` themselves.

    Returns
    -------
    base, local
        Scaled.
    """
    if factor == 1.0:
        return base, local
    base = None if base is None else base / factor
    if local is None:
        return base, None

    def scaled(lam):
        return local(lam) / factor
    return base, scaled
