"""The output path of a reducer whose members sit on eccentrics: what carries the members'
torque to the output and what turns their eccentrics (docs/stiffness.md, "The system
model"). The drive's train and the one system model
(:class:`toothfem.fem.drives.assembly.CycloidSystem`) ask their path for everything that
differs between the layouts; each path is written once:

- :class:`PinsInHoles` (K-H-V cycloid drives, the sine pair): one input shaft on the axis
  with an eccentric per member in the member's centre bore, held at its end (the input
  held); the output flange's pins (or rollers) in holes through the members, contacts with
  clearance (:mod:`toothfem.fem.system.output_pins`);
- :class:`Cranks` (2K-V, RV): n crankshafts at radius R_c on the carrier (the output),
  each through a crank hole of every disc, turned by a spur planet on the held sun.

A path is a frozen record of its case's SI sections, a field of its drive that the layout
builds (:mod:`toothfem.layouts`). What it adds to one system model (the output pins'
bending, the spur mesh's law) it keeps on that model (:meth:`OutputPath.laws`). The hooks'
defaults add nothing: a path overrides what it has.
"""
from __future__ import annotations

import abc
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ...errors import CaseError
from ...geometry.train import khv_speeds, rv_speeds
from . import elements as el
from .output_pins import pin_bending, pin_contacts, pin_friction
from .parts import RIGID_FACTOR, RIGID_STIFFNESS, perp
from .solve import Element

if TYPE_CHECKING:
    from ...si import OutputMechanismSI, SpurStageSI

#: ISO 6336-1:2019 Sec. 9: the mean mesh stiffness of spur gears of steel, c_gamma_alpha
#: ~ 20 N/(mm um) per mm of face width [N/m per m].
SPUR_MESH_STIFFNESS_N_PER_M2 = 20e9


class OutputPath(abc.ABC):
    """What the drive's train and the system model ask of an output path.

    Shafts k carry the members' eccentrics; the model names their elements by the formats
    ``BEARING`` (shaft k's eccentric bearing in member j: ``{k}``, ``{j}``, from 1),
    ``SUPPORT`` (its support bearing at ``{end}``, a or b) and ``SHAFT``, and the parts of
    :data:`toothfem.fem.system.parts.GROUPS` by ``group_names`` (where the path names them
    otherwise). ``output_mechanism``: the output pins in the members' holes, if any.
    """

    BEARING: ClassVar[str]
    SUPPORT: ClassVar[str]
    SHAFT: ClassVar[str]
    group_names: ClassVar[Mapping[str, str]] = MappingProxyType({})
    output_mechanism: OutputMechanismSI | None = None

    # -- the train (the drive asks) ----------------------------------------------------
    @abc.abstractmethod
    def speeds(self, moving_teeth: int, fixed_teeth: int) -> dict:
        """Speeds of the train's parts for a unit input speed.

        Parameters
        ----------
        moving_teeth, fixed_teeth : int
            The members' lobes (teeth) and the fixed pins (ring teeth).

        Returns
        -------
        dict of str to float
            ``input``, ``crank``, ``member``, ``output`` [-, per unit input speed], signed
            as in :mod:`toothfem.geometry.train`.
        """

    def members_torque_per_output(self, speeds: dict, moving_teeth: int,
                                  fixed_teeth: int) -> float:
        """The members' torque together per output torque, from the power flow (1: the
        members carry the output torque to the output themselves).

        Parameters
        ----------
        speeds : dict
            :meth:`speeds`.
        moving_teeth, fixed_teeth : int

        Returns
        -------
        float
        """
        return 1.0

    @abc.abstractmethod
    def eccentric_race_radius_m(self, holes) -> float:
        """The eccentric bearings' outer raceway in a disc [m].

        Parameters
        ----------
        holes : toothfem.geometry.disc.DiscHolesSI

        Returns
        -------
        float
        """

    def te_orders(self, speeds: dict) -> list:
        """The path's own orders of a transmission-error ripple, beside the drive's.

        Parameters
        ----------
        speeds : dict
            :meth:`speeds`.

        Returns
        -------
        list of (str, float)
            (name, order per output revolution); none by default.
        """
        return []

    def with_crank_period(self, pitches: int, drive, deviation) -> int:
        """``pitches`` made a whole number of the period of a built stage's crank errors
        (on one shaft on the axis they are alike at every tooth: ``pitches``).

        Parameters
        ----------
        pitches : int
        drive : toothfem.fem.drives.Drive
        deviation : object
            The drive's record of :mod:`toothfem.fem.deviations`.

        Returns
        -------
        int
        """
        return pitches

    # -- the system model (CycloidSystem asks) -----------------------------------------
    @abc.abstractmethod
    def shafts(self, drive) -> tuple[int, float]:
        """The shafts that carry the eccentrics.

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive

        Returns
        -------
        count : int
        circle_radius_m : float
            Their axes' distance from the reducer's axis [m].
        """

    def laws(self, system) -> None:
        """The path's own parts on ``system``, with each set of its options (a part the
        path takes rigid joins ``system.rigid``).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        """
        return None                     # none of its own by default

    def shaft_coordinates(self, k: int) -> tuple:
        """Shaft k's coordinates beside its supports' moves, its rotation at the eccentrics
        (``psi_e{k}``) and its bending.

        Parameters
        ----------
        k : int

        Returns
        -------
        tuple of str
            One coordinate each; none by default.
        """
        return ()

    def frame_terms(self, a_k, e_j) -> dict:
        """The journal's move with the shafts' frame: coordinate -> its coefficient (2,)
        in the eccentric bearing's deformation (none: the housing).

        Parameters
        ----------
        a_k, e_j : numpy.ndarray, shape (2,)
            The shaft's axis and the eccentric on it [m], housing frame.

        Returns
        -------
        dict of str to numpy.ndarray
        """
        return {}

    def frame_rate(self, v, coords) -> float:
        """The shafts' frame's rotation per unit output twist (the housing: 0).

        Parameters
        ----------
        v : numpy.ndarray
            The coordinates' rate per unit output twist.
        coords : toothfem.fem.system.parts.Coordinates

        Returns
        -------
        float
        """
        return 0.0

    def torsion_terms(self, k: int) -> dict:
        """Shaft k's twist between its eccentrics and where it is held (its end: psi_e).

        Parameters
        ----------
        k : int

        Returns
        -------
        dict of str to float
            Coordinate -> coefficient.
        """
        return {f"psi_e{k}": 1.0}

    def shaft_elements(self, system, k: int) -> list:
        """Shaft k's elements beside its bearings, bending and torsion (none by default).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        k : int

        Returns
        -------
        list of toothfem.fem.system.solve.Element
        """
        return []

    def contacts(self, system, phi: float, torque: float) -> list:
        """The path's contacts at crank angle phi, after the members' (none by default).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        phi : float
            [rad].
        torque : float
            The output torque [N m] (its size sets a secant's floor).

        Returns
        -------
        list of toothfem.fem.system.solve.ContactSet
        """
        return []

    def friction(self, system, phi: float, v, eq, friction) -> dict:
        """The path's own friction torques on the output [N m] (none by default).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        phi : float
            [rad].
        v : numpy.ndarray
            The coordinates' rate per unit output twist.
        eq : toothfem.fem.system.solve.Equilibrium
        friction : toothfem.fem.system.friction.PathFriction

        Returns
        -------
        dict of str to float
        """
        return {}


@dataclass(frozen=True)
class PinsInHoles(OutputPath):
    """K-H-V (and the sine pair): the output flange's pins (or rollers) in holes through the
    members (:mod:`toothfem.fem.system.output_pins`); one input shaft on the axis carries
    an eccentric per member and twists between them and the held input. Without an
    ``output_mechanism``: the K-H-V train alone (its system model is refused)."""
    output_mechanism: OutputMechanismSI | None = None

    BEARING = "eccentric bearing disc {j}"
    SUPPORT = "input bearing {end}"
    SHAFT = "input shaft"
    group_names = MappingProxyType({
        "crank bearings": "eccentric bearings", "support bearings": "input bearings",
        "crankshaft bending": "input shaft bending", "crankshaft torsion": "input shaft torsion"})

    def speeds(self, moving_teeth: int, fixed_teeth: int) -> dict:
        """:func:`~toothfem.geometry.train.khv_speeds`: the crank turns with the input,
        the output with the members.

        Parameters
        ----------
        moving_teeth, fixed_teeth : int

        Returns
        -------
        dict of str to float
        """
        w = khv_speeds(moving_teeth, fixed_teeth)
        return {"input": 1.0, "crank": 1.0, "member": w["moving"], "output": w["moving"]}

    def eccentric_race_radius_m(self, holes) -> float:
        """The centre bore.

        Parameters
        ----------
        holes : toothfem.geometry.disc.DiscHolesSI

        Returns
        -------
        float
        """
        return holes.centre_bore_radius_m

    def shafts(self, drive) -> tuple[int, float]:
        """The input shaft on the axis.

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive

        Returns
        -------
        (1, 0.0)
        """
        return 1, 0.0

    def laws(self, system) -> None:
        """The output pins' bending (``system.output_pin_bending``,
        :func:`~toothfem.fem.system.output_pins.pin_bending`).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem

        Raises
        ------
        CaseError
            Without output pins.
        """
        system.output_pin_bending = pin_bending(system, self._pins())

    def contacts(self, system, phi: float, torque: float) -> list:
        """The output pins in the members' holes
        (:func:`~toothfem.fem.system.output_pins.pin_contacts`).

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        phi, torque : float

        Returns
        -------
        list of toothfem.fem.system.solve.ContactSet
        """
        return [pin_contacts(system, self._pins(), phi, torque)]

    def friction(self, system, phi: float, v, eq, friction) -> dict:
        """``output pins``: the pins against their holes
        (:func:`~toothfem.fem.system.output_pins.pin_friction`).

        Parameters
        ----------
        system, phi, v, eq, friction
            As :meth:`OutputPath.friction`.

        Returns
        -------
        dict
        """
        return {"output pins": pin_friction(system, self._pins(), phi, v, eq, friction)}

    def _pins(self) -> OutputMechanismSI:
        if self.output_mechanism is None:
            raise CaseError("a K-H-V drive needs [output_mechanism]: its output pins are "
                            "the path of the torque")
        return self.output_mechanism


@dataclass(frozen=True)
class Cranks(OutputPath):
    """2K-V (RV): n crankshafts at radius R_c on the carrier (the output), each through a
    crank hole of every disc and turned by its spur planet on the held sun; ``teeth``
    (sun, planet) of that first stage, its ``first_stage`` (None: the spur mesh rigid).
    The shafts' frame is the carrier: the journal at disc j also moves by
    carrier x (A_k + E_j), and the crank's rotation at its gear (``psi_g``) is a
    coordinate. The spur mesh deforms by r_b,planet (psi_g,k - (z_sun / z_planet)
    carrier): with nothing deformed every crank turns (1 + z_sun/z_planet) times the
    output angle."""
    teeth: tuple[int, int]
    first_stage: SpurStageSI | None = None

    BEARING = "crank bearing {k} disc {j}"
    SUPPORT = "support bearing {k}{end}"
    SHAFT = "crankshaft {k}"

    @property
    def sun_over_planet(self) -> float:
        """z_sun / z_planet."""
        return self.teeth[0] / self.teeth[1]

    def speeds(self, moving_teeth: int, fixed_teeth: int) -> dict:
        """:func:`~toothfem.geometry.train.rv_speeds`: the crank is the planet, the output
        the carrier.

        Parameters
        ----------
        moving_teeth, fixed_teeth : int

        Returns
        -------
        dict of str to float
        """
        w = rv_speeds(*self.teeth, moving_teeth, fixed_teeth)
        return {"input": 1.0, "crank": w["planet"], "member": w["disc"],
                "output": w["carrier"]}

    def members_torque_per_output(self, speeds: dict, moving_teeth: int,
                                  fixed_teeth: int) -> float:
        """The pins turn the discs against the cranks: (1 - 1/i)(Za/Zb), the output torque
        less what the spur stage carries, over the pins' lever (the system model's pin
        moments agree to 1e-6, tests/test_system.py).

        Parameters
        ----------
        speeds : dict
        moving_teeth, fixed_teeth : int

        Returns
        -------
        float
        """
        i = abs(1.0 / speeds["output"])
        return (1 - 1 / i) * moving_teeth / fixed_teeth

    def eccentric_race_radius_m(self, holes) -> float:
        """The crank hole.

        Parameters
        ----------
        holes : toothfem.geometry.disc.DiscHolesSI

        Returns
        -------
        float
        """
        return holes.crank_hole_radius_m

    def te_orders(self, speeds: dict) -> list:
        """``first-stage mesh``: the sun's teeth per turn of the input against the carrier.

        Parameters
        ----------
        speeds : dict

        Returns
        -------
        list of (str, float)
        """
        return [("first-stage mesh", self.teeth[0] * abs(speeds["input"] - speeds["output"])
                 / abs(speeds["output"]))]

    def with_crank_period(self, pitches: int, drive, deviation) -> int:
        """With crank eccentricity errors, also a whole number of the crank's turns against
        the carrier (each crank's own error repeats once per such turn,
        :meth:`toothfem.fem.drives.Drive.crank_period_pitches`).

        Parameters
        ----------
        pitches : int
        drive : toothfem.fem.drives.Drive
        deviation : object

        Returns
        -------
        int
        """
        crank = np.asarray(getattr(deviation, "crank_eccentricity_m", ()), float)
        if np.any(crank):
            return math.lcm(pitches, drive.crank_period_pitches())
        return pitches

    def shafts(self, drive) -> tuple[int, float]:
        """One crank per crank hole, on the holes' circle.

        Parameters
        ----------
        drive : toothfem.fem.drives.CycloidDrive

        Returns
        -------
        (int, float)
        """
        h = drive.stage.holes
        return h.crank_hole_count, h.crank_hole_circle_radius_m

    def laws(self, system) -> None:
        """The spur mesh: ISO 6336-1's mean mesh stiffness on the planet's base radius
        (``system.spur_stiffness``, ``system.planet_base_radius``); without a first stage
        taken rigid.

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        """
        fs = self.first_stage
        if fs is None:
            system.rigid = system.rigid + ("spur mesh",)
            system.planet_base_radius = 1.0
            system.spur_stiffness = RIGID_STIFFNESS / RIGID_FACTOR
        else:
            system.planet_base_radius = 0.5 * fs.module_m * fs.planet_teeth * \
                math.cos(fs.pressure_angle_rad)
            system.spur_stiffness = SPUR_MESH_STIFFNESS_N_PER_M2 * fs.face_width_m

    def shaft_coordinates(self, k: int) -> tuple:
        """The crank's rotation at its gear, ``psi_g{k}``.

        Parameters
        ----------
        k : int

        Returns
        -------
        tuple of str
        """
        return (f"psi_g{k}",)

    def frame_terms(self, a_k, e_j) -> dict:
        """carrier x (A_k + E_j).

        Parameters
        ----------
        a_k, e_j : numpy.ndarray, shape (2,)

        Returns
        -------
        dict of str to numpy.ndarray
        """
        return {"carrier": perp(a_k) + perp(e_j)}

    def frame_rate(self, v, coords) -> float:
        """The carrier's.

        Parameters
        ----------
        v : numpy.ndarray
        coords : toothfem.fem.system.parts.Coordinates

        Returns
        -------
        float
        """
        return v[coords.index["carrier"]][0]

    def torsion_terms(self, k: int) -> dict:
        """Between the eccentrics and the gear: psi_e - psi_g.

        Parameters
        ----------
        k : int

        Returns
        -------
        dict of str to float
        """
        return {f"psi_e{k}": 1.0, f"psi_g{k}": -1.0}

    def shaft_elements(self, system, k: int) -> list:
        """The spur mesh of crank k's planet with the held sun.

        Parameters
        ----------
        system : toothfem.fem.drives.assembly.CycloidSystem
        k : int

        Returns
        -------
        list of toothfem.fem.system.solve.Element
        """
        r_b = system.planet_base_radius
        return [Element(f"spur mesh {k + 1}", "spur mesh",
                        system.coords.row({f"psi_g{k}": r_b,
                                           "carrier": -r_b * self.sun_over_planet})[None, :],
                        system.law("spur mesh", el.linear(system.spur_stiffness), 1))]
