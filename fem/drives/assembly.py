"""The system model of a reducer whose members sit on eccentrics (docs/stiffness.md, "The
system model"): every disc (or sine planet) a rigid body on its teeth (the FE contact,
:mod:`toothfem.fem.system.mesh`) and its bearings, the shafts that carry the eccentrics on
their support bearings, bending and twisting, and the path to the output. One core for
every layout; what differs between them is the drive's output path
(:mod:`toothfem.fem.system.paths`): :class:`~toothfem.fem.system.paths.Cranks` (2K-V: n
crankshafts on the carrier, turned by the spur first stage from the held sun) or
:class:`~toothfem.fem.system.paths.PinsInHoles` (K-H-V and the sine pair: one input
shaft on the axis, the output flange's pins in holes through the members).

Coordinates (small displacements, housing frame, at one crank angle):

- ``out``: the output flange's rotation, where the torque acts; ``carrier``: the carrier's
  rotation at the cranks (one coordinate with ``out`` unless the case declares a carrier
  stiffness);
- per disc j: its translation (x, y) and rotation theta about its centre;
- per shaft k: its move against its frame (the carrier; K-H-V: the housing) at its two
  support bearings (s1, s2), its rotation against that frame at the eccentrics (psi_e),
  the path's own (2K-V: at its gear, psi_g) and the bending deflection w_kj at each
  disc's plane against the line through its supports.

Kinematics. Shaft k's axis sits at A_k (radius R_c from the path, 0 on the axis) and disc
j's eccentric on it is E_j = e u(phi_j), turning with the shaft's absolute rotation. The
journal of shaft k at disc j moves by

    (1 - z_j) s1_k + z_j s2_k + w_kj + psi_e,k x E_j + [the frame's turn]

(x: e_z cross; z_j = a_j / L the disc's axial place on the span; the frame's turn from the
path, :meth:`~toothfem.fem.system.paths.OutputPath.frame_terms`: 2K-V carrier x (A_k +
E_j)), and the disc's bearing seat on it by d_j + theta_j x A_k (the seat sits A_k from
the disc's centre). The shaft twists between its eccentrics and where it is held (the
path's :meth:`~toothfem.fem.system.paths.OutputPath.torsion_terms`).

Elements: the crank (eccentric) bearings (rollers one by one, with play), the support
bearings (assumed from the shaft's diameter unless declared), the shafts' bending
(Euler-Bernoulli + Timoshenko shear between simple supports) and torsion (over half the
span), the path's own (2K-V: the spur mesh), the carrier (the case's stiffness, else
rigid). Contacts: each disc's pins, through the FE influence tables of the cycle mode at
the disc's true configuration (its pitch and phase: ``Drive.member_offsets``; both
flanks), gap change -n . d_j + l theta_j per pin; the path's own (K-H-V: the output pins).

Limits (this version): the carrier's (output flange's) translation is held (rigid main
bearings); the planet gear's force on its crank is not applied to the support bearings;
the disc body between its bore and its output pins' holes is rigid (the FE tables hold
the bore); friction is not in the solve (:mod:`toothfem.fem.system.friction` reads it
off the solved state).
"""
from __future__ import annotations

import copy
import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ...geometry.vectors import rotate
from ..datasheet import supports as sp
from ..system import elements as el
from ..contact import ContactError
from ..system.friction import PathFriction, friction_torques
from ..system.mesh import MeshSolution
from ..system.crank_errors import with_crank_errors
from ..system.parts import (GROUPS, RIGID_FACTOR, RIGID_STIFFNESS, Coordinates, DiscSlot,
                            SystemState, perp, softened)
from ..system.solve import ContactSet, Element, Linear, closing_motion, rest, solve

if TYPE_CHECKING:
    from ..system.tables import PitchTables

#: What other modules import from here (the system model's names, wherever they live).
__all__ = ["GROUPS", "SCALABLE", "RIGID_STIFFNESS", "RIGID_FACTOR", "PathFriction",
           "DiscSlot", "SystemState", "CycloidSystem", "SUPPORT_ROLLERS",
           "SUPPORT_LENGTH_REL", "SUPPORT_ANGLE_DEG"]

#: ASSUMPTION: each crank's two support bearings are tapered roller bearings sized on the
#: crank: 14 rollers of 0.55 d long at 15 deg (a 302-series bearing on a 17 mm bore:
#: 14-15 rollers, effective length about 9.5 mm, e = 0.35, i.e. alpha ~ 14 deg).
SUPPORT_ROLLERS, SUPPORT_LENGTH_REL, SUPPORT_ANGLE_DEG = 14, 0.55, 15.0
#: The parts whose stiffness ``stiffness_scale`` may scale: the element groups, the
#: members' contacts with the fixed teeth ("mesh": the FE tables and the local approach
#: together), a K-H-V drive's output pins, and a declared carrier stiffness.
SCALABLE = GROUPS + ("mesh", "output pins", "carrier")


class CycloidSystem:
    """The system model of a drive (2K-V or K-H-V cycloid, the K-H-V sine pair) over the
    positions of one meshing period: the shared core, which asks the drive's output path
    (``drive.path``, :class:`toothfem.fem.system.paths.OutputPath`) for everything that
    differs between the layouts.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        Its ``path`` (2K-V cranks, or K-H-V output pins in the members' holes) and its
        ``system_mesh``, the members' contact.
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
    pin_structure : str, optional
        The pins' FE structure of every member's tables (a cycloid drive's
        ``fe_options["pin_structure"]``, e.g. ``contact --pins``); None: the case's.

    Notes
    -----
    A built stage's crank eccentricity errors enter as the crank bearings' forced
    deformations (:func:`toothfem.fem.system.crank_errors.with_crank_errors`).
    """

    def __init__(self, drive, supports, n_positions: int = 36, *, cache=True, pitch: int = 0,
                 phases_rad=None, pitch_samples: int | None = None,
                 pin_spring_m_per_N: float | None = None, rigid: tuple = (),
                 crank_bearing_play_m: float = 0.0,
                 crank_bearing_stiffness_N_per_m: float | None = None,
                 stiffness_scale: dict | None = None, pin_structure: str | None = None):
        self.path = drive.path
        self.mesh = drive.system_mesh(pin_spring_m_per_N)
        self.drive, self.supports = drive, supports
        self.n_positions = int(n_positions)
        self.zb = self.mesh.labels
        self.cranks, self.r_c = self.path.shafts(drive)
        self.discs = drive.members
        phases = [2 * math.pi * j / self.discs for j in range(self.discs)] \
            if phases_rad is None else [float(x) for x in phases_rad]
        if len(phases) != self.discs:
            raise CaseError(f"phases_rad has {len(phases)} values for {self.discs} discs")
        offsets = drive.member_offsets(self.n_positions, [x / (2 * math.pi) for x in phases])
        step = drive.period_rad / self.n_positions
        axial = drive.member_axial_positions_m(supports)
        slots = []
        fe = {} if pin_structure is None else {"pin_structure": pin_structure}
        for j in range(self.discs):
            solver = drive.cycle_solver(self.n_positions, cache=cache,
                                        offset=offsets[j] + int(pitch) * self.n_positions,
                                        solver_options=self.mesh.solver_options, **fe)
            phase = phases[j]
            beta = math.remainder(phase - offsets[j] * step, 2 * math.pi)   # pitch: none
            if abs(beta * self.zb / (2 * math.pi) - round(beta * self.zb / (2 * math.pi))) \
                    > 1e-6:
                raise CaseError(f"disc {j + 1}: its configuration is not a whole number of "
                                "pin pitches from the first disc's")
            slots.append(DiscSlot(j, phase, float(axial[j]), int(offsets[j]), beta, solver))
        self.slots = tuple(slots)
        # the elements' names: shaft k's eccentric bearing in disc j, its supports a and b
        self.bearing_names = [[self.path.BEARING.format(k=k + 1, j=j + 1)
                               for j in range(self.discs)] for k in range(self.cranks)]
        self.support_names = [{end: self.path.SUPPORT.format(k=k + 1, end=end)
                               for end in "ab"} for k in range(self.cranks)]
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
        self._bending_base = np.kron(np.linalg.inv(sp.simply_supported_influence(
            axial[:, None], axial[None, :], span, d, m.youngs_modulus_Pa, m.poisson_ratio)),
            np.eye(2))
        self._torsion_base = 1.0 / sp.torsion_compliance(0.5 * span, d, m.youngs_modulus_Pa,
                                                         m.poisson_ratio)
        self._set_laws(rigid=tuple(rigid), crank_bearing_play_m=crank_bearing_play_m,
                       crank_bearing_stiffness_N_per_m=crank_bearing_stiffness_N_per_m,
                       stiffness_scale=stiffness_scale)
        self.coords = self._coordinates()

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
        supports = self.supports
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
        self.path.laws(self)
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
        return self.path.group_names.get(part, part)

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
            for name in self.path.shaft_coordinates(k):
                c.add(name)
            c.add(f"w{k}", 2 * self.discs)
        return c

    def eccentric(self, phi: float, s: DiscSlot) -> np.ndarray:
        """Disc ``s``'s eccentric E_j at crank angle phi.

        Parameters
        ----------
        phi : float
            [rad].
        s : DiscSlot

        Returns
        -------
        numpy.ndarray, shape (2,)
            [m], housing frame.
        """
        return self.mesh.eccentricity_m * np.array(
            [math.cos(phi + s.phase_rad), math.sin(phi + s.phase_rad)])

    def _disc_turn(self, s: DiscSlot, p: int) -> float:
        """Disc ``s``'s rotation at position p [rad], housing frame: the K-H-V pose of its
        configuration turned by its beta."""
        return self.mesh.turn_ratio * float(s.solver.positions_rad[p]) + s.beta_rad

    def _elements(self, phi: float) -> list:
        """The elements at crank angle phi (kept: every torque at a position uses them)."""
        kept = self._kept_elements.get(phi)
        if kept is None:
            kept = self._kept_elements[phi] = self._build_elements(phi)
        return kept

    def _build_elements(self, phi: float) -> list:
        c, out, path = self.coords, [], self.path
        n = c.n
        carrier_angle = self.mesh.turn_ratio * phi    # the discs and the output together
        for k in range(self.cranks):
            a_k = rotate(self.r_c * np.array([1.0, 0.0]), 2 * math.pi * k / self.cranks
                         + carrier_angle)
            for s in self.slots:
                e_j = self.eccentric(phi, s)
                z = s.axial_m / self.supports.crankshaft_span_m
                b = np.zeros((2, n))
                for name, coefficient in path.frame_terms(a_k, e_j).items():
                    b[:, c.index[name]] += coefficient[:, None]
                b[:, c.index[f"s1_{k}"]] += (1 - z) * np.eye(2)
                b[:, c.index[f"s2_{k}"]] += z * np.eye(2)
                w = c.index[f"w{k}"]
                b[:, w.start + 2 * s.index: w.start + 2 * s.index + 2] += np.eye(2)
                b[:, c.index[f"psi_e{k}"]] += perp(e_j)[:, None]
                dj = c.index[f"disc{s.index}"]
                b[:, dj.start:dj.start + 2] -= np.eye(2)
                b[:, dj.start + 2] -= perp(a_k)
                out.append(Element(self.bearing_names[k][s.index],
                                   self.group("crank bearings"), b,
                                   self.law("crank bearings", self.crank_bearing, 2)))
            for name in ("s1", "s2"):
                b = np.zeros((2, n))
                b[:, c.index[f"{name}_{k}"]] = np.eye(2)
                out.append(Element(self.support_names[k]["ab"[name == "s2"]],
                                   self.group("support bearings"), b,
                                   self.law("support bearings", self.support_bearing, 2)))
            b = np.zeros((2 * self.discs, n))
            b[:, c.index[f"w{k}"]] = np.eye(2 * self.discs)
            shaft = path.SHAFT.format(k=k + 1)
            out.append(Element(f"{shaft} bending", self.group("crankshaft bending"), b,
                               self.law("crankshaft bending",
                                        el.linear(self.bending_stiffness), 2 * self.discs)))
            out.append(Element(f"{shaft} torsion", self.group("crankshaft torsion"),
                               c.row(path.torsion_terms(k))[None, :],
                               self.law("crankshaft torsion",
                                        el.linear(self.torsion_stiffness), 1)))
            out += path.shaft_elements(self, k)
        if self.carrier_stiffness:
            out.append(Element("carrier", "carrier", c.row({"out": 1.0, "carrier": -1.0})[None],
                               self.law("carrier", el.linear(self.carrier_stiffness), 1)))
        return out

    def law(self, part: str, law, size: int):
        """The law of a part: ``law`` scaled by its ``stiffness_scale``, or rigid
        (:meth:`_maybe_rigid`); one object per part (the solver evaluates the elements of
        one law together).

        Parameters
        ----------
        part : str
            Its name in SCALABLE.
        law : callable
            Its own law (:mod:`toothfem.fem.system.elements`).
        size : int
            Its deformation's size.

        Returns
        -------
        callable
            The law kept for the part (the first call's).
        """
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
        c, out = self.coords, []
        for s in self.slots:
            mc = self.mesh.contacts(
                s, p, side, torque, self._disc_turn(s, p), deviation=deviation, pitch=pitch,
                shift=self._shift(s), geometry=geometry,
                tables=None if self.pitch_tables is None else self.pitch_tables[s.index])
            gmat = np.zeros((mc.g0.size, c.n))
            dj = c.index[f"disc{s.index}"]
            gmat[:, dj.start:dj.start + 2] = -mc.normal.T
            gmat[:, dj.start + 2] = mc.arm
            base, local = softened(mc.base, mc.local, self.stiffness_scale.get("mesh", 1.0))
            out.append((ContactSet(f"mesh {self.drive.member_name} {s.index + 1}", "mesh", mc.g0,
                                   gmat, base, local), mc))
        return out

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
        c = self.coords
        sets = [cs for cs, _ in self._pins(p, side, side, deviation, pitch, geometry)]
        sets += self.path.contacts(self, phi, side)
        q = np.zeros(c.n)
        q[c.index["out"]] = side
        elements = with_crank_errors(self, self._elements(phi), phi, deviation, pitch)
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
        c = self.coords
        elements = with_crank_errors(self, self._elements(phi), phi, deviation, pitch)
        q = np.zeros(c.n)
        q[c.index["out"]] = t
        while True:
            pins = self._pins(p, side, t, deviation, pitch, geometry)
            sets = [cs for cs, _ in pins]
            sets += self.path.contacts(self, phi, t)
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
        out_pins = eq.forces.get("output pins")          # the path's pins, where it has them
        out_pins = None if out_pins is None else out_pins.reshape(self.discs, -1)
        lost = {} if friction is None else friction_torques(self, phi, pins, eq, friction)
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
        c = self.coords
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

    def _shift(self, s: DiscSlot) -> int:
        """Pins from the first disc's labels to disc ``s``'s own (its turn beta)."""
        return int(round(s.beta_rad * self.zb / (2 * math.pi)))
