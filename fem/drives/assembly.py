"""The system model of a reducer: every disc (or sine planet) a rigid body on its teeth
(the FE contact, :mod:`toothfem.fem.system.mesh`) and its bearings, the shafts that carry
the eccentrics on their support bearings, bending and twisting, and the path to the output
(docs/stiffness.md, "The system model"). Two layouts of one model:

- 2K-V (RV): n crankshafts at radius R_c on the carrier (the output), each through a crank
  hole of every disc, turned by the spur first stage from the sun (held: the catalogue's
  input held);
- K-H-V: one input shaft on the axis with an eccentric per disc in the disc's centre bore
  (held: input held), the output flange's pins (or rollers) in holes through the discs,
  contacts with clearance; the sine pair is this layout with one planet in its ring.

Coordinates (small displacements, housing frame, at one crank angle):

- ``out``: the output flange's rotation, where the torque acts; ``carrier``: the carrier's
  rotation at the cranks (one coordinate with ``out`` unless the case declares a carrier
  stiffness; K-H-V: the output flange);
- per disc j: its translation (x, y) and rotation theta about its centre;
- per shaft k: its move against its frame (the carrier; K-H-V: the housing) at its two
  support bearings (s1, s2), its rotation against that frame at the eccentrics (psi_e)
  and, 2K-V, at its gear (psi_g), and the bending deflection w_kj at each disc's plane
  against the line through its supports.

Kinematics. Shaft k's axis sits at A_k (2K-V: radius R_c, moving with the carrier; K-H-V:
the origin) and disc j's eccentric on it is E_j = e u(phi_j), turning with the shaft's
absolute rotation. The journal of shaft k at disc j moves by

    [carrier x A_k] + (1 - z_j) s1_k + z_j s2_k + w_kj + ([carrier] + psi_e,k) x E_j

(x: e_z cross; z_j = a_j / L the disc's axial place on the span; the bracketed terms 2K-V
only), and the disc's bearing seat on it by d_j + theta_j x A_k (the seat sits A_k from
the disc's centre). 2K-V: the spur mesh of crank k's planet with the sun, sun held,
deforms by r_b,planet (psi_g,k - (z_sun / z_planet) carrier): with nothing deformed every
crank turns (1 + z_sun/z_planet) times the output angle. K-H-V: the input shaft's torsion
between its eccentrics and the held input, psi_e. Output pin k of a K-H-V drive (centre
P_k, radius r) in disc j's hole (centre P_k + E_j, radius r + e + clearance) touches along
n = -E_j / e; its gap changes by -n . (out x P_k - d_j - theta_j x P_k).

Elements: the crank (eccentric) bearings (rollers one by one, with play), the support
bearings (assumed from the shaft's diameter unless declared), the shafts' bending
(Euler-Bernoulli + Timoshenko shear between simple supports) and torsion (over half the
span), the spur mesh (ISO 6336-1's mean mesh stiffness), the carrier (the case's
stiffness, else rigid). Contacts: each disc's pins, through the FE influence tables of the
cycle mode at the disc's true configuration (its pitch and phase:
``Drive.member_offsets``; both flanks), gap change -n . d_j + l theta_j per pin; K-H-V:
the output pins, Palmgren's line contact at the hole (and at the roller's bore) and the
pins' bending between the output flange and their support ring.

Limits (this version): the carrier's (output flange's) translation is held (rigid main
bearings); the planet gear's force on its crank is not applied to the support bearings;
the disc body between its bore and its output pins' holes is rigid (the FE tables hold
the bore); friction is not in the solve.
"""
from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ...geometry.vectors import rotate
from ..datasheet import supports as sp
from ..system import elements as el
from ..contact import ContactError
from ..system.mesh import MeshSolution
from ..system.solve import ContactSet, Element, Linear, closing_motion, rest, solve

if TYPE_CHECKING:
    from ..cycloid_fe.cycle import CycleSolver as CycloidCycleSolver
    from ..sine_fe.cycle import CycleSolver as SineCycleSolver
    from ..system.tables import PitchTables

#: ISO 6336-1:2019 Sec. 9: the mean mesh stiffness of spur gears of steel, c_gamma_alpha
#: ~ 20 N/(mm um) per mm of face width [N/m per m].
SPUR_MESH_STIFFNESS_N_PER_M2 = 20e9
#: ASSUMPTION: each crank's two support bearings are tapered roller bearings sized on the
#: crank: 14 rollers of 0.55 d long at 15 deg (a 302-series bearing on a 17 mm bore:
#: 14-15 rollers, effective length about 9.5 mm, e = 0.35, i.e. alpha ~ 14 deg).
SUPPORT_ROLLERS, SUPPORT_LENGTH_REL, SUPPORT_ANGLE_DEG = 14, 0.55, 15.0


#: The parts of the model (the ``rigid`` option's names), as the outputs of a 2K-V drive
#: name their share of the twist; a K-H-V drive's names (KHV_NAMES) for the same parts.
GROUPS = ("crank bearings", "support bearings", "crankshaft bending", "crankshaft torsion",
          "spur mesh")
KHV_NAMES = {"crank bearings": "eccentric bearings", "support bearings": "input bearings",
             "crankshaft bending": "input shaft bending",
             "crankshaft torsion": "input shaft torsion"}
#: The parts whose stiffness ``stiffness_scale`` may scale: the element groups, the
#: members' contacts with the fixed teeth ("mesh": the FE tables and the local approach
#: together), a K-H-V drive's output pins, and a declared carrier stiffness.
SCALABLE = GROUPS + ("mesh", "output pins", "carrier")
#: The output pins' secant flexibility is taken at no less than this fraction of a typical
#: pin load (Palmgren's approach ~ Q^0.9 has an infinite secant compliance at zero load).
OUTPUT_LOAD_FLOOR = 1e-3


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
class PathFriction:
    """Coulomb friction in the quasi-static path (docs/stiffness.md, "Friction"): what
    resists the elastic micro-slips of a slow twist test. At creep speeds no film forms, so
    sliding contacts take their boundary coefficient.

    ``pin_disc``: the pin contacts' sliding; ``pin_groove``: conventional pins in their
    grooves (a pin that turns more easily in its groove than the disc slides on it rolls:
    the smaller coefficient acts); ``bearing``: the rolling bearings' friction moment
    mu F d / 2 (SKF's simplified model, d the bore); ``output_pin``: the output pins in
    their holes (with rollers: the roller's sleeve on its pin); ``output_torque_Nm``: a
    load-independent friction torque on the output (its seal)."""
    pin_disc: float
    pin_groove: float
    bearing: float
    output_pin: float
    output_torque_Nm: float = 0.0

    def __post_init__(self):
        for name in ("pin_disc", "pin_groove", "bearing", "output_pin", "output_torque_Nm"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise CaseError(f"friction {name} = {v!r}: >= 0 and finite")


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


class CycloidSystem:
    """The system model of a drive (2K-V or K-H-V cycloid, the K-H-V sine pair) over the
    positions of one meshing period.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        A 2K-V drive (``first_teeth`` set) or a K-H-V drive with its ``output`` pins; its
        ``system_mesh`` is the members' contact.
    supports : toothfem.fem.datasheet.supports.Supports
    n_positions : int
        Positions per pin pitch.
    cache : bool or DiskCache or None
        The FE tables' disk cache (``Drive.cycle_solver``).
    pin_spring_m_per_N : float, optional
        Rigid bodies on equal contact springs instead of the FE (the hand models' limit):
        the compliance of every pin contact [m/N].
    rigid : tuple of str
        Element groups made rigid (any of GROUPS): a limit case or a sensitivity check.
    crank_bearing_play_m : float
        Diametral play of the crank (eccentric) bearings [m] (< 0: preload).
    crank_bearing_stiffness_N_per_m : float, optional
        Linear isotropic crank bearings instead of the roller law (the hand models' limit).
    pitch : int
        Puts the positions that many pin pitches on (the discs' FE tables at that pitch).
    phases_rad : sequence of float, optional
        Each disc's eccentric phase (default 2 pi j / discs, the balanced layout).
    pitch_samples : int, optional
        Every disc's influence tables at any pitch (``solve(pitch=)``) filled from this
        many sampled pitches (:class:`toothfem.fem.system.tables.PitchTables`; a mesh
        whose tables cover every tooth needs none); None: the tables of the positions'
        own pitch (``pitch`` above) at every pitch.
    stiffness_scale : dict of str to float, optional
        Part (any of SCALABLE) -> factor on its stiffness (its compliance divided by it):
        a part stiffer or softer than its model, e.g. fitted to a rig. A part made
        ``rigid`` stays rigid.

    Notes
    -----
    A built stage's crank eccentricity errors (``deviation.crank_eccentricity_m`` and
    ``crank_phase_rad``, one per crank or per crank and disc,
    :class:`toothfem.fem.deviations.CycloidDeviation`) enter where the eccentric does:
    crank k's eccentric at disc j stands at E_j + de_k u(phi_j + theta_k), so the bearing
    between it and the disc's seat is deformed by de_k u(phi_j + theta_k) with every body
    at rest (``Element.offset``). Unequal cranks force each disc to a compromise pose
    through the crank bearings' play and stiffness; the cranks turn against the carrier,
    so the pose goes round at that order. An error of one eccentric alone turns the
    output: the TE ripples at that order. A crank's error on both its eccentrics pushes
    discs at 180 deg opposite ways: their turns cancel in the TE's first harmonic and the
    split between the discs ripples instead. Equal errors on every crank (one phase) move
    each disc by de u(phi_j + theta) with no bearing deformed: the deviation's
    ``eccentricity`` (the pins' gaps shifted) on a 2K-V drive; a K-H-V drive's output pins
    see the disc's move too (their holes' clearance closes by de), which ``eccentricity``
    leaves out. The error's lever in the crank's rotation (psi x (E + dE) instead of
    psi x E) is second order and left out, as ``eccentricity`` does.
    """

    def __init__(self, drive, supports, n_positions: int = 36, *, cache=True, pitch: int = 0,
                 phases_rad=None, pitch_samples: int | None = None,
                 pin_spring_m_per_N: float | None = None, rigid: tuple = (),
                 crank_bearing_play_m: float = 0.0,
                 crank_bearing_stiffness_N_per_m: float | None = None,
                 stiffness_scale: dict | None = None):
        self.khv = not drive.two_stage
        if self.khv and drive.output is None:
            raise CaseError("a K-H-V drive needs [output_mechanism]: its output pins are "
                            "the path of the torque")
        self.mesh = drive.system_mesh(pin_spring_m_per_N)
        self.drive, self.supports = drive, supports
        self.n_positions = int(n_positions)
        self.zb = self.mesh.labels
        if self.khv:
            self.cranks, self.r_c, self.sun_over_planet = 1, 0.0, 0.0
        else:
            h = drive.stage.holes
            self.cranks, self.r_c = h.crank_hole_count, h.crank_hole_circle_radius_m
            self.sun_over_planet = drive.first_teeth[0] / drive.first_teeth[1]
        self.discs = drive.members
        phases = [2 * math.pi * j / self.discs for j in range(self.discs)] \
            if phases_rad is None else [float(x) for x in phases_rad]
        if len(phases) != self.discs:
            raise CaseError(f"phases_rad has {len(phases)} values for {self.discs} discs")
        offsets = drive.member_offsets(self.n_positions, [x / (2 * math.pi) for x in phases])
        step = drive.period_rad / self.n_positions
        axial = drive.member_axial_positions_m(supports)
        slots = []
        for j in range(self.discs):
            solver = drive.cycle_solver(self.n_positions, cache=cache,
                                        offset=offsets[j] + int(pitch) * self.n_positions,
                                        solver_options=self.mesh.solver_options)
            phase = phases[j]
            beta = math.remainder(phase - offsets[j] * step, 2 * math.pi)   # pitch: none
            if abs(beta * self.zb / (2 * math.pi) - round(beta * self.zb / (2 * math.pi))) \
                    > 1e-6:
                raise CaseError(f"disc {j + 1}: its configuration is not a whole number of "
                                "pin pitches from the first disc's")
            slots.append(DiscSlot(j, phase, float(axial[j]), int(offsets[j]), beta, solver))
        self.slots = tuple(slots)
        self.pitch_tables = None
        if pitch_samples is not None:
            if int(pitch):
                raise CaseError("pitch_samples fills the tables over the full period: give "
                                "the pitch to solve(), not to the model")
            filled: dict[int, PitchTables | None] = {}
            tables = tuple(filled.setdefault(s.offset, self.mesh.pitch_tables(
                self.n_positions, s.offset, cache, int(pitch_samples))) for s in slots)
            self.pitch_tables = None if None in tables else tables
        m = drive.material_si
        span = supports.crankshaft_span_m
        d = supports.crankshaft_diameter_m
        if self.khv:
            om = drive.output
            self.output_pin_bending = sp.simply_supported_influence(
                axial[:, None], axial[None, :], span, 2 * om.pin_radius_m,
                m.youngs_modulus_Pa, m.poisson_ratio)
        self._bending_base = np.kron(np.linalg.inv(sp.simply_supported_influence(
            axial[:, None], axial[None, :], span, d, m.youngs_modulus_Pa, m.poisson_ratio)),
            np.eye(2))
        self._torsion_base = 1.0 / sp.torsion_compliance(0.5 * span, d, m.youngs_modulus_Pa,
                                                         m.poisson_ratio)
        self._set_laws(rigid=tuple(rigid), crank_bearing_play_m=crank_bearing_play_m,
                       crank_bearing_stiffness_N_per_m=crank_bearing_stiffness_N_per_m,
                       stiffness_scale=stiffness_scale)
        self._coords = self._coordinates()

    def _set_laws(self, *, rigid, crank_bearing_play_m, crank_bearing_stiffness_N_per_m,
                  stiffness_scale) -> None:
        """The elements' laws from the options (the constructor's and :meth:`variant`'s);
        the elements kept per crank angle are dropped."""
        unknown = set(rigid) - set(GROUPS)
        if unknown:
            raise CaseError(f"rigid = {sorted(unknown)!r}: not parts of the model "
                            f"({list(GROUPS)})")
        scale = dict(stiffness_scale or {})
        unknown = set(scale) - set(SCALABLE)
        if unknown:
            raise CaseError(f"stiffness_scale = {sorted(unknown)!r}: not parts of the model "
                            f"({list(SCALABLE)})")
        for name, f in scale.items():
            if not (math.isfinite(f) and f > 0):
                raise CaseError(f"stiffness_scale[{name!r}] = {f!r}: > 0 and finite")
        if not math.isfinite(crank_bearing_play_m):
            raise CaseError(f"crank_bearing_play_m = {crank_bearing_play_m!r}: finite")
        self._rigid_asked = tuple(rigid)
        self.rigid = tuple(rigid)
        self.stiffness_scale = scale
        self.crank_bearing_play_m = float(crank_bearing_play_m)
        self.crank_bearing_stiffness_N_per_m = crank_bearing_stiffness_N_per_m
        supports, drive = self.supports, self.drive
        self.crank_bearing = el.RollerBearing(supports.bearing_roller_count,
                                              supports.bearing_roller_length_m,
                                              play_m=crank_bearing_play_m) \
            if crank_bearing_stiffness_N_per_m is None else \
            el.linear(crank_bearing_stiffness_N_per_m * np.eye(2))
        d = supports.crankshaft_diameter_m
        self.support_bearing = el.RollerBearing(
            SUPPORT_ROLLERS, SUPPORT_LENGTH_REL * d,
            contact_angle_rad=math.radians(SUPPORT_ANGLE_DEG))
        self.bending_stiffness = self._bending_base
        self.torsion_stiffness = self._torsion_base
        fs = None if self.khv else drive.first_stage
        if fs is None:               # no spur stage, or no module: the mesh taken rigid
            self.rigid = self.rigid + ("spur mesh",)
            self.planet_base_radius, self.spur_stiffness = 1.0, RIGID_STIFFNESS / RIGID_FACTOR
        else:
            self.planet_base_radius = 0.5 * fs.module_m * fs.planet_teeth * \
                math.cos(fs.pressure_angle_rad)
            self.spur_stiffness = SPUR_MESH_STIFFNESS_N_PER_M2 * fs.face_width_m
        self.carrier_stiffness = supports.carrier_stiffness_Nm_per_rad
        self._kept_elements: dict[float, list[Element]] = {}
        # part -> its (scaled) law, one object per part
        self._laws: dict[str, Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]] = {}

    def variant(self, *, rigid: tuple | None = None, crank_bearing_play_m: float | None = None,
                crank_bearing_stiffness_N_per_m: float | None = None,
                stiffness_scale: dict | None = None) -> CycloidSystem:
        """This system with other element options, on the same discs, tables and positions
        (no table is read again: what a fit that varies the parts calls many times).

        Parameters
        ----------
        rigid, crank_bearing_play_m, crank_bearing_stiffness_N_per_m, stiffness_scale
            As the constructor's; None keeps this system's (``stiffness_scale={}``: none).

        Returns
        -------
        CycloidSystem
        """
        out = copy.copy(self)
        out._set_laws(
            rigid=self._rigid_asked if rigid is None else tuple(rigid),
            crank_bearing_play_m=self.crank_bearing_play_m if crank_bearing_play_m is None
            else crank_bearing_play_m,
            crank_bearing_stiffness_N_per_m=self.crank_bearing_stiffness_N_per_m
            if crank_bearing_stiffness_N_per_m is None else crank_bearing_stiffness_N_per_m,
            stiffness_scale=self.stiffness_scale if stiffness_scale is None
            else stiffness_scale)
        return out

    def group(self, part: str) -> str:
        """The outputs' name of a part of GROUPS in this layout.

        Parameters
        ----------
        part : str
            One of GROUPS.

        Returns
        -------
        str
        """
        return KHV_NAMES.get(part, part) if self.khv else part

    # -- assembly ---------------------------------------------------------------------
    def _coordinates(self) -> Coordinates:
        c = Coordinates()
        c.add("out")
        if self.carrier_stiffness:
            c.add("carrier")
        else:
            c.index["carrier"] = c.index["out"]
        for j in range(self.discs):
            c.add(f"disc{j}", 3)
        for k in range(self.cranks):
            c.add(f"s1_{k}", 2)
            c.add(f"s2_{k}", 2)
            c.add(f"psi_e{k}")
            if not self.khv:
                c.add(f"psi_g{k}")
            c.add(f"w{k}", 2 * self.discs)
        return c

    def _eccentric(self, phi: float, s: DiscSlot) -> np.ndarray:
        """E_j (2,) [m], housing frame."""
        return self.mesh.eccentricity_m * np.array(
            [math.cos(phi + s.phase_rad), math.sin(phi + s.phase_rad)])

    def _disc_turn(self, s: DiscSlot, p: int) -> float:
        """Disc ``s``'s rotation at position p [rad], housing frame: the K-H-V pose of its
        configuration turned by its beta."""
        return self.mesh.turn_ratio * float(s.solver.positions_rad[p]) + s.beta_rad

    def _output_normal(self, phi: float, s: DiscSlot) -> np.ndarray:
        """(2,) the K-H-V output pins' contact normal in disc ``s``'s holes, -E_j/e."""
        return -self._eccentric(phi, s) / self.mesh.eccentricity_m

    def _elements(self, phi: float) -> list:
        """The elements at crank angle phi (kept: every torque at a position uses them)."""
        kept = self._kept_elements.get(phi)
        if kept is None:
            kept = self._kept_elements[phi] = self._build_elements(phi)
        return kept

    def _with_crank_errors(self, elements, phi: float, deviation, pitch: int = 0) -> list:
        """``elements`` with a built stage's crank eccentricity errors as the crank
        bearings' forced deformations: crank k's eccentric at disc j off its place by
        de_kj u(phi_j + theta_kj) (the class's Notes; errors (cranks,) or (cranks, discs));
        the elements themselves where the deviation has none.

        ``pitch`` m: the state m meshing periods on, solved in pitch 0's frame (the stage
        turned back by m periods): the errors' directions are pitch 0's, and the cranks
        stand where pitch 0's did, each moved on by the carrier's turn against that frame,
        (turn ratio - 1) m period; that must be a whole number of crank spacings (the
        crank at place k is then crank k - that number).

        Raises
        ------
        CaseError
            For errors of another shape, or a pitch that does not bring the cranks back
            onto the cranks' places.
        """
        de = np.asarray(getattr(deviation, "crank_eccentricity_m", ()), float)
        if de.size == 0 or not np.any(de):
            return elements
        theta = np.asarray(getattr(deviation, "crank_phase_rad", ()), float)
        theta = np.zeros(de.shape) if theta.size == 0 else theta
        shape = (self.cranks, self.discs)
        try:
            de = np.broadcast_to(de.reshape(de.shape + (1,) * (2 - de.ndim)), shape)
            theta = np.broadcast_to(theta.reshape(theta.shape + (1,) * (2 - theta.ndim)),
                                    shape)
        except ValueError:
            raise CaseError(f"crank_eccentricity_m {np.shape(deviation.crank_eccentricity_m)}"
                            f" and crank_phase_rad {np.shape(deviation.crank_phase_rad)}: "
                            f"one value per crank ({self.cranks}) or per crank and "
                            f"{self.drive.member_name} {shape}") from None
        turn = (self.mesh.turn_ratio - 1.0) * int(pitch) * self.drive.period_rad
        moved = turn * self.cranks / (2 * math.pi)
        if self.cranks > 1 and abs(moved - round(moved)) > 1e-9:
            raise CaseError(f"pitch {int(pitch)}: the carrier turns {math.degrees(turn):.6g} "
                            "deg against pitch 0's frame, not a whole number of crank "
                            "spacings; solve crank errors at the positions' own pitch")
        moved = int(round(moved)) if self.cranks > 1 else 0
        offsets = {}
        for k in range(self.cranks):
            c = (k - moved) % self.cranks           # the crank standing at place k
            for s in self.slots:
                a = phi + s.phase_rad + theta[c, s.index]
                offsets[self._bearing_name(k, s.index)] = de[c, s.index] * np.array(
                    [math.cos(a), math.sin(a)])
        return [replace(e, offset=offsets[e.name]) if e.name in offsets else e
                for e in elements]

    def _build_elements(self, phi: float) -> list:
        c, out = self._coords, []
        n = c.n
        carrier_angle = self.mesh.turn_ratio * phi    # the discs and the output together
        for k in range(self.cranks):
            a_k = rotate(self.r_c * np.array([1.0, 0.0]), 2 * math.pi * k / self.cranks
                         + carrier_angle)
            for s in self.slots:
                e_j = self._eccentric(phi, s)
                z = s.axial_m / self.supports.crankshaft_span_m
                b = np.zeros((2, n))
                if not self.khv:
                    b[:, c.index["carrier"]] += (perp(a_k) + perp(e_j))[:, None]
                b[:, c.index[f"s1_{k}"]] += (1 - z) * np.eye(2)
                b[:, c.index[f"s2_{k}"]] += z * np.eye(2)
                w = c.index[f"w{k}"]
                b[:, w.start + 2 * s.index: w.start + 2 * s.index + 2] += np.eye(2)
                b[:, c.index[f"psi_e{k}"]] += perp(e_j)[:, None]
                dj = c.index[f"disc{s.index}"]
                b[:, dj.start:dj.start + 2] -= np.eye(2)
                b[:, dj.start + 2] -= perp(a_k)
                out.append(Element(self._bearing_name(k, s.index),
                                   self.group("crank bearings"), b,
                                   self._law("crank bearings", self.crank_bearing, 2)))
            for name in ("s1", "s2"):
                b = np.zeros((2, n))
                b[:, c.index[f"{name}_{k}"]] = np.eye(2)
                out.append(Element(self._support_name(k, "ab"[name == "s2"]),
                                   self.group("support bearings"), b,
                                   self._law("support bearings", self.support_bearing, 2)))
            b = np.zeros((2 * self.discs, n))
            b[:, c.index[f"w{k}"]] = np.eye(2 * self.discs)
            shaft = "input shaft" if self.khv else f"crankshaft {k + 1}"
            out.append(Element(f"{shaft} bending", self.group("crankshaft bending"), b,
                               self._law("crankshaft bending",
                                         el.linear(self.bending_stiffness), 2 * self.discs)))
            twist = {f"psi_e{k}": 1.0} if self.khv else {f"psi_e{k}": 1.0, f"psi_g{k}": -1.0}
            out.append(Element(f"{shaft} torsion", self.group("crankshaft torsion"),
                               c.row(twist)[None, :],
                               self._law("crankshaft torsion",
                                         el.linear(self.torsion_stiffness), 1)))
            if not self.khv:
                r_b = self.planet_base_radius
                out.append(Element(f"spur mesh {k + 1}", "spur mesh",
                                   c.row({f"psi_g{k}": r_b,
                                          "carrier": -r_b * self.sun_over_planet})[None, :],
                                   self._law("spur mesh", el.linear(self.spur_stiffness), 1)))
        if self.carrier_stiffness:
            out.append(Element("carrier", "carrier", c.row({"out": 1.0, "carrier": -1.0})[None],
                               self._law("carrier", el.linear(self.carrier_stiffness), 1)))
        return out

    def _law(self, part: str, law, size: int):
        """The law of a part: ``law`` scaled by its ``stiffness_scale``, or rigid
        (:meth:`_maybe_rigid`); one object per part (the solver evaluates the elements of
        one law together)."""
        if part not in self._laws:
            self._laws[part] = self._maybe_rigid(
                part, el.scaled(law, self.stiffness_scale.get(part, 1.0)), size)
        return self._laws[part]

    def _maybe_rigid(self, group, law, size: int):
        """``law``, or a rigid one of ``size`` where ``group`` is made rigid: a linear law
        RIGID_FACTOR times stiffer, a bearing RIGID_STIFFNESS."""
        if group not in self.rigid:
            return law
        if isinstance(law, Linear):
            return el.linear(law.k * RIGID_FACTOR)
        return el.linear(np.eye(size) * RIGID_STIFFNESS)

    def _pins(self, p: int, side: int, torque: float, deviation=None, pitch: int = 0,
              geometry=None):
        """(ContactSet, MeshContacts) of each member's mesh at position p
        (:mod:`toothfem.fem.system.mesh`): a built stage's ``deviation``, ``pitch``
        meshing periods on; ``geometry``: the disc with other modifications, on these
        tables (the design search). The gap changes by -n . d_j + arm theta_j."""
        c, out = self._coords, []
        for s in self.slots:
            mc = self.mesh.contacts(
                s, p, side, torque, self._disc_turn(s, p), deviation=deviation, pitch=pitch,
                shift=self._shift(s), geometry=geometry,
                tables=None if self.pitch_tables is None else self.pitch_tables[s.index])
            gmat = np.zeros((mc.g0.size, c.n))
            dj = c.index[f"disc{s.index}"]
            gmat[:, dj.start:dj.start + 2] = -mc.normal.T
            gmat[:, dj.start + 2] = mc.arm
            base, local = _softened(mc.base, mc.local, self.stiffness_scale.get("mesh", 1.0))
            out.append((ContactSet(f"mesh {self.drive.member_name} {s.index + 1}", "mesh", mc.g0,
                                   gmat, base, local), mc))
        return out

    def _output_pins(self, phi: float, torque: float) -> ContactSet:
        """The K-H-V output pins in every disc's holes: one contact per pin and disc along
        n = -E_j/e, gap the holes' clearance; flexibility: Palmgren's line contact at the
        hole (and at the roller's bore) per contact, the pins' bending coupling the discs
        on one pin."""
        om, c = self.drive.output, self._coords
        n_o, r_w = om.pin_count, om.pin_hole_circle_radius_m
        e = self.mesh.eccentricity_m
        centres = self._output_centres(phi)
        rows, g0, normals = [], [], []
        hole = om.hole_radius_m if om.hole_radius_m is not None else om.contact_radius_m + e
        clearance = hole - om.contact_radius_m - e
        clearance = 0.0 if abs(clearance) < 1e-12 else clearance      # mm -> m round-off
        for s in self.slots:
            n = self._output_normal(phi, s)
            dj = c.index[f"disc{s.index}"]
            for k in range(n_o):
                r = np.zeros(c.n)
                r[c.index["out"]] = -n @ perp(centres[:, k])
                r[dj.start:dj.start + 2] = n
                r[dj.start + 2] = n @ perp(centres[:, k])
                rows.append(r)
                normals.append(n)
                g0.append(clearance)
        nrm = np.array(normals)                                              # (M n_o, 2)
        disc = np.repeat(np.arange(self.discs), n_o)
        pin = np.tile(np.arange(n_o), self.discs)
        same_pin = pin[:, None] == pin[None, :]
        bending = np.where(same_pin, self.output_pin_bending[np.ix_(disc, disc)], 0.0) \
            * (nrm @ nrm.T)
        width = self.drive.face_width_m
        contacts = 1 if om.roller_radius_m is None else 2
        mean = abs(torque) / (0.5 * n_o * r_w * self.discs)                  # a typical load

        def local(lam):             # Palmgren's secant, per contact
            q = np.maximum(np.abs(np.asarray(lam, float)), OUTPUT_LOAD_FLOOR * mean)
            return contacts * sp.roller_approach(q, width) / q
        bending, local = _softened(bending, local, self.stiffness_scale.get("output pins", 1.0))
        return ContactSet("output pins", "output pins", np.array(g0), np.array(rows),
                          bending, local)

    # -- solving ------------------------------------------------------------------------
    def closing_rotation(self, p: int, side: int, *, deviation=None, pitch: int = 0,
                         geometry=None) -> float:
        """The output's rotation that closes the clearances on one flank, every part rigid:
        the mechanism's motion under a torque of sign ``side`` until it is blocked
        (:func:`toothfem.fem.system.solve.closing_motion`); the backlash is the two
        flanks' difference. Input held: a 2K-V drive's cranks turn (1 + z_s/z_p) times the
        output angle, so a clearance d closes at d / (e (Za + 1 + z_s/z_p)).

        Parameters
        ----------
        p : int
            Position index.
        side : {1, -1}
            The flank.
        deviation, pitch, geometry
            A built stage and another modification (as :meth:`solve`).

        Returns
        -------
        float
            [rad], signed by ``side``; of the other sign where the flank already overlaps
            (an interference: the backlash comes out negative).
        """
        phi = float(self.slots[0].solver.positions_rad[p])
        c = self._coords
        sets = [cs for cs, _ in self._pins(p, side, side, deviation, pitch, geometry)]
        if self.khv:
            sets.append(self._output_pins(phi, side))
        q = np.zeros(c.n)
        q[c.index["out"]] = side
        elements = self._with_crank_errors(self._elements(phi), phi, deviation, pitch)
        # the rigid parts' pose with the cranks' errors (none: at rest)
        u0 = rest(c.n, elements)
        _, motion = closing_motion(c.n, elements, np.concatenate([cs.g for cs in sets]),
                                   np.concatenate([cs.g0 for cs in sets]), q, u=u0,
                                   signed=True)
        return float(motion[c.index["out"]][0] + u0[c.index["out"]][0])

    def solve(self, output_torque_Nm: float, p: int, *, side: int | None = None,
              start=None, friction: PathFriction | None = None, deviation=None,
              pitch: int = 0, geometry=None) -> SystemState:
        """The system at position p under an output torque (input held).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], nonzero and finite; its sign loads the flank.
        p : int
            Position index in the pitch.
        side : {1, -1}, optional
            The flank the contacts' half-widths are taken for; the torque's sign by default.
        start : SystemState, optional
            A nearby solution to start from (the previous torque step).
        friction : PathFriction, optional
            Coefficients of the friction torque the state reports (``friction_Nm``).
        deviation : toothfem.fem.deviations.CycloidDeviation, optional
            A built stage: its pins, discs and eccentricity off their drawing (the initial
            gaps shifted; the tables the nominal disc's).
        pitch : int
            The built stage's pin pitches on from the position (a deviation's pins and
            lobes meet there).
        geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
            The disc with other modifications (micrometres from the tables' disc: its
            initial gaps on these tables, as the design search takes them).

        Returns
        -------
        SystemState

        Raises
        ------
        CaseError
            For a zero or non-finite torque.
        toothfem.fem.contact.ContactError
            If the equilibrium is not found (the message names the torque and position).
        """
        t = float(output_torque_Nm)
        if t == 0 or not math.isfinite(t):
            raise CaseError(f"output_torque_Nm = {t!r}: nonzero and finite")
        side = int(math.copysign(1, t)) if side is None else side
        phi = float(self.slots[0].solver.positions_rad[p])
        c = self._coords
        elements = self._with_crank_errors(self._elements(phi), phi, deviation, pitch)
        q = np.zeros(c.n)
        q[c.index["out"]] = t
        while True:
            pins = self._pins(p, side, t, deviation, pitch, geometry)
            sets = [cs for cs, _ in pins]
            if self.khv:
                sets.append(self._output_pins(phi, t))
            eq = self._equilibrium(elements, sets, q, start, t, phi, friction is not None)
            # a mesh that selects its candidates (the sine pair's hats) widens the
            # selection until the contact lies inside it
            if not any(self.mesh.widen(p, pitch, mc, eq.forces[cs.name], eq.gaps[cs.name])
                       for cs, mc in pins):
                break
        force = np.zeros((self.discs, self.zb))
        torque = np.zeros(self.discs)
        contacts = np.zeros(self.discs, int)
        for s, (cs, qq) in zip(self.slots, pins):
            lam = eq.forces[cs.name]
            np.add.at(force[s.index], qq.label, lam)
            torque[s.index] = -float(qq.arm @ lam)
            contacts[s.index] = int(np.sum(force[s.index] > 0))
        bearings = {e.name: eq.element_force[e.name] for e in elements
                    if e.group in (self.group("crank bearings"), self.group("support bearings"))}
        out_pins = eq.forces["output pins"].reshape(self.discs, -1) if self.khv else None
        lost = {} if friction is None else self._friction(p, phi, pins, sets, eq, friction)
        solved = tuple(MeshSolution(mc, eq.forces[cs.name], eq.gaps[cs.name],
                                    float(eq.u[c.index[f"disc{s.index}"]][2]))
                       for s, (cs, mc) in zip(self.slots, pins))
        return SystemState(output_torque_Nm=t, position_rad=phi,
                           twist_rad=float(eq.u[c.index["out"]][0]), pin_force_N=force,
                           disc_torque_Nm=torque, contacts=contacts,
                           bearing_force_N=bearings, output_pin_force_N=out_pins,
                           paths_rad={k: v / t for k, v in eq.work.items()}, equilibrium=eq,
                           friction_Nm=lost, mesh=solved)

    def member_record(self, j: int, states, meshing=None):
        """Member j's load sharing over the positions of ``states`` (one SystemState per
        position, in order): its contact forces with Hertz's (or the FE's) pressure, the
        reducer's TE, the member's mean torque (:meth:`toothfem.fem.system.mesh.PinMesh.
        record`).

        Parameters
        ----------
        j : int
            Member index.
        states : list of SystemState
        meshing : toothfem.geometry.kinematics.MeshingState, optional
            The first member's meshing at the positions, if known.

        Returns
        -------
        toothfem.fem.load_sharing.LoadSharing
        """
        return self.mesh.record(self.slots[j], [s.mesh[j] for s in states],
                                [s.twist_rad for s in states],
                                float(np.mean([s.disc_torque_Nm[j] for s in states])), meshing)

    def _equilibrium(self, elements, sets, q, start, t, phi, rate):
        """:func:`solve` from a nearby state ``start`` where it fits, else from rest (the
        message names the torque and the crank angle); ``rate``: with its tangent."""
        c = self._coords
        u0 = active0 = lam0 = None
        if start is not None and start.equilibrium is not None:
            u0, lam0 = start.equilibrium.u, start.equilibrium.forces
            if any(lam0.get(cs.name, np.zeros(0)).size != cs.g0.size for cs in sets):
                lam0 = None
            else:
                active0 = {name: f > 0 for name, f in lam0.items()}
        try:
            try:
                return solve(c.n, elements, sets, q, u0=u0, active0=active0, lam0=lam0,
                             rate=rate)
            except ContactError:
                if u0 is None:
                    raise
                # a start far from here (another torque's contacts) can lead the active
                # set astray: from rest
                return solve(c.n, elements, sets, q, rate=rate)
        except ContactError as exc:
            raise ContactError(f"{exc} (output torque {t:g} N m, crank angle "
                               f"{math.degrees(phi):.4g} deg)") from None

    def _friction(self, p, phi, pins, sets, eq, fr: PathFriction) -> dict:
        """Friction torque [N m] on the output per source: each friction pair's force (mu
        times its normal force, or its bearing's moment) times its slip per unit output
        twist, the slips from the tangent at this state (``Equilibrium.rate``)."""
        c = self._coords
        v = eq.rate / eq.rate[c.index["out"]][0]          # per unit output twist
        out = {}
        mu = self.mesh.sliding_coefficient(fr)
        total = 0.0
        for s, (cs, mc) in zip(self.slots, pins):
            dj = v[c.index[f"disc{s.index}"]]
            vel = dj[:2, None] + dj[2] * perp(mc.point)    # the member at each contact
            total += mu * float(eq.forces[cs.name] @ np.abs(np.sum(perp(mc.normal) * vel, 0)))
        out[f"{self.drive.contact_name} contacts"] = total
        journal = self.mesh.journal_radius_m(self.supports)
        bear = supp = 0.0
        for k in range(self.cranks):
            psi = v[c.index[f"psi_e{k}"]][0]
            for s in self.slots:        # the crank turns against the disc
                rel = psi - v[c.index[f"disc{s.index}"]][2] \
                    + (0.0 if self.khv else v[c.index["carrier"]][0])
                force = eq.element_force[self._bearing_name(k, s.index)]
                bear += fr.bearing * np.hypot(*force) * journal * abs(rel)
            for end in "ab":            # the crank turns against its frame
                force = eq.element_force[self._support_name(k, end)]
                supp += fr.bearing * np.hypot(*force) * 0.5 \
                    * self.supports.crankshaft_diameter_m * abs(psi)
        out[self.group("crank bearings")] = float(bear)
        out[self.group("support bearings")] = float(supp)
        if self.khv:
            om = self.drive.output
            centres = self._output_centres(phi)
            slip = []
            for s in self.slots:        # the pin (roller) against its hole, tangentially
                t = perp(self._output_normal(phi, s))
                dj = v[c.index[f"disc{s.index}"]]
                rel = v[c.index["out"]][0] * perp(centres) - dj[:2, None] \
                    - dj[2] * perp(centres)
                slip.append(np.abs(t @ rel))
            lever = 1.0 if om.roller_radius_m is None else om.pin_radius_m / om.roller_radius_m
            out["output pins"] = fr.output_pin * lever * float(
                eq.forces["output pins"] @ np.concatenate(slip))
        out["output seal"] = fr.output_torque_Nm
        return out

    def _shift(self, s: DiscSlot) -> int:
        """Pins from the first disc's labels to disc ``s``'s own (its turn beta)."""
        return int(round(s.beta_rad * self.zb / (2 * math.pi)))

    def _bearing_name(self, k: int, j: int) -> str:
        return (f"eccentric bearing disc {j + 1}" if self.khv else
                f"crank bearing {k + 1} disc {j + 1}")

    def _support_name(self, k: int, end: str) -> str:
        return f"input bearing {end}" if self.khv else f"support bearing {k + 1}{end}"

    def _output_centres(self, phi: float) -> np.ndarray:
        """(2, n_o) the output pins' centres [m] at crank angle phi."""
        om = self.drive.output
        angle = 2 * math.pi * np.arange(om.pin_count) / om.pin_count + self.mesh.turn_ratio * phi
        return om.pin_hole_circle_radius_m * np.stack([np.cos(angle), np.sin(angle)])


def _softened(base, local, factor: float):
    """(base, local) of a contact set ``factor`` times as stiff: its flexibility over the
    factor (the FE tables and the local law alike); themselves for a factor of 1."""
    if factor == 1.0:
        return base, local
    base = None if base is None else base / factor
    if local is None:
        return base, None

    def scaled(lam):
        return local(lam) / factor
    return base, scaled


#: The stiffness of a part made rigid for a limit case [N/m or N m/rad]: 1e5 times the
#: stiffest part of a reducer (a pin contact, ~1e9 N/m): its compliance is 1e-5 of the
#: others', and the saddle system's round-off stays near 1e-8 of the coordinates.
RIGID_STIFFNESS = 1e14
#: A linear part made rigid is this many times stiffer than it is (its share of the
#: compliance falls to 1e-5 of its own; a rotation's stiffness is not in N/m).
RIGID_FACTOR = 1e5

