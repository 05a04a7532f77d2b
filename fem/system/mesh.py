"""The contact of each member (cycloid disc, sine planet) with the fixed teeth (pins, ring)
as the system model takes it: the candidates at a position, their initial gaps, where and
along which normal they touch, the bodies' flexibility from the FE tables, and which pin
or tooth each stands for (docs/stiffness.md, "The system model"). One class per kind of
mesh; everything else about a layout is the system model's own (fem/drives/assembly.py).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from ...geometry.vectors import rotate
from ..contact import ContactError
from ..cycloid_fe.built_stage import deviation_gaps
from ..cycloid_fe.cycle import MODIFIED_GAP_FAR
from ..cycloid_fe.record import record
from ..sine_fe.cycle import DEFAULT_SELECT_GAP, SELECT_GAP_MAX, SELECT_MARGIN, HatContacts
from .tables import PitchTables
from ...units import UM_PER_M


@dataclass(frozen=True)
class MeshContacts:
    """One member's candidate contacts at one position (C of them), housing frame.

    ``normal`` (2, C): the member's outward normal at each (a translation d of the member
    closes the gap by d . normal); ``point`` (2, C): each contact about the member's centre
    [m]; ``arm`` (C,): the gap's change per member rotation [m]; ``g0`` (C,) [m];
    ``base`` (C, C) [m/N] and ``local`` (lam [N] -> (C,) [m/N]) the flexibility (as
    :class:`toothfem.fem.system.solve.ContactSet`); ``label`` (C,): the pin (cycloid) or
    meshing column (sine) each stands for; ``source``: the mesh's own record of them."""
    g0: np.ndarray
    normal: np.ndarray
    point: np.ndarray
    arm: np.ndarray
    base: np.ndarray
    local: object
    label: np.ndarray
    source: object = None


@dataclass(frozen=True)
class MeshSolution:
    """One member's contacts solved at one position: their forces [N] and remaining gaps
    [m], and the member's rotation [rad] (what its record closes the untouched contacts
    by)."""
    contacts: MeshContacts
    force_N: np.ndarray
    gap_m: np.ndarray
    rotation_rad: float


class Mesh:
    """What the system model asks of a kind of mesh (one subclass each): ``contacts`` at
    a position, each member's ``record``, the crank journal's radius, the Coulomb
    coefficient of its sliding, and, where they apply, tables over the pitches and a
    selection that widens. Attributes: ``eccentricity_m``, ``turn_ratio`` (the member's
    rotation per crank angle), ``labels`` (pins or meshing columns), ``solver_options``
    (the cycle solver's)."""

    def pitch_tables(self, n_positions, offset, cache, samples):
        """A member configuration's tables at every pitch; None where the mesh's own
        tables cover every pitch.

        Parameters
        ----------
        n_positions, offset : int
            The member's grid and its offset.
        cache
            The FE tables' disk cache.
        samples : int
            Sampled pitches.

        Returns
        -------
        PitchTables or None
        """
        return None

    def widen(self, p, pitch, mesh: MeshContacts, force, gap) -> bool:
        """Whether the candidates must widen and the position be solved again (a mesh whose
        candidates are every contact: never).

        Parameters
        ----------
        p, pitch : int
            The position and pitch solved.
        mesh : MeshContacts
        force, gap : numpy.ndarray
            The solved forces [N] and gaps [m].

        Returns
        -------
        bool
        """
        return False

    def _kept(self, deviation, key, compute):
        """``compute()`` kept under ``key`` for the last deviation (a built stage's torques
        at a position share what depends on its deviation alone; the next deviation
        drops them)."""
        kept = self.__dict__.setdefault("_kept_for", {})
        if kept.get("deviation", kept) is not deviation:
            kept.clear()
            kept["deviation"] = deviation
        if key not in kept:
            kept[key] = compute()
        return kept[key]


class PinMesh(Mesh):
    """A cycloid disc on its pins: every pin a candidate (both flanks), the disc's FE
    influence tables at the disc's true configuration (its pitch and phase), each pin's
    local Hertz approach and, for conventional pins, the pin's own compliance
    (:meth:`toothfem.fem.cycloid_fe.cycle.CycleSolver.local_compliance`).

    Parameters
    ----------
    drive : toothfem.fem.drives.cycloid.CycloidDrive
    pin_spring_m_per_N : float, optional
        Equal contact springs instead of the FE (the hand models' limit).
    """

    def __init__(self, drive, pin_spring_m_per_N=None):
        self.drive = drive
        self.pin_spring = pin_spring_m_per_N
        g = drive.geometry
        self.eccentricity_m = g.eccentricity_m
        self.labels = g.pin_count
        #: the member's rotation per crank angle (K-H-V pose; its output turns with it)
        self.turn_ratio = -1.0 / drive.stage.lobe_count
        self.solver_options = {**drive.both_flanks_options, **(
            {"equal_springs": pin_spring_m_per_N * drive.face_width_m}
            if pin_spring_m_per_N is not None else {})}
        self._turned = {}        # (disc, position, side, turn) -> its normals and points
        self._read: dict = {}    # id -> each solver whose tables are read or stored

    def journal_radius_m(self, supports) -> float:
        """The crank (eccentric) journal's radius under the crank bearing's rollers.

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports

        Returns
        -------
        float
            [m]: the crank hole's (K-H-V: centre bore's) radius less a roller diameter.
        """
        return self.drive.eccentric_race_radius_m - supports.bearing_roller_diameter_m

    def sliding_coefficient(self, friction) -> float:
        """The mesh's Coulomb coefficient: a conventional pin that turns more easily in its
        groove than the disc slides on it rolls (the smaller coefficient acts).

        Parameters
        ----------
        friction : toothfem.fem.drives.assembly.PathFriction

        Returns
        -------
        float
        """
        if self.drive.stage.pin_structure == "conventional":
            return min(friction.pin_disc, friction.pin_groove)
        return friction.pin_disc

    def pitch_tables(self, n_positions, offset, cache, samples):
        """A disc configuration's tables at every pitch (:class:`PitchTables`: the disc's
        holes sit elsewhere against the pins a pitch on).

        Parameters
        ----------
        n_positions, offset : int
            The disc's grid and its offset.
        cache
            The FE tables' disk cache.
        samples : int
            Sampled pitches.

        Returns
        -------
        PitchTables or None
            None for equal springs.
        """
        if self.pin_spring is not None:
            return None
        return PitchTables(self.drive, n_positions, offset, self.drive.both_flanks_options,
                           cache, samples)

    def contacts(self, slot, p, side, torque, turn, *, deviation=None, pitch=0, shift=0,
                 geometry=None, tables=None) -> MeshContacts:
        """The disc's pins at position p.

        Parameters
        ----------
        slot : toothfem.fem.drives.assembly.DiscSlot
        p : int
            Position index.
        side : {1, -1}
            The flank.
        torque : float
            The output torque [N m] (its member torque sets the unloaded half-widths).
        turn : float
            The disc's rotation from its frame to the housing's [rad].
        deviation : toothfem.fem.deviations.CycloidDeviation, optional
            Every disc ground alike (:func:`deviation_gaps`, at ``pitch + shift``).
        pitch, shift : int
            Pin pitches on; the disc's own labels from the first disc's.
        geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
            Another modification of the disc on these tables.
        tables : PitchTables, optional
            The disc's tables at any pitch (else its solver's own).

        Returns
        -------
        MeshContacts
        """
        s, w = slot.solver, self.drive.face_width_m
        q_load = self.drive.member_torque(abs(torque), peak=False) * side / w
        q = s.candidates(side)[p]
        g0 = q.gap if geometry is None else s.modified_gaps(geometry, side)[p]
        g0 = np.where(np.isfinite(g0), g0, MODIFIED_GAP_FAR)
        if deviation is not None:
            m = int(pitch) + shift
            g0 = g0 + self._kept(deviation, (slot.index, m, p, side),
                                 lambda: deviation_gaps(s.model, q, deviation, m))
        if self.pin_spring is not None:
            base, local = np.eye(q.pins.size) * self.pin_spring, None
        else:
            if tables is None and s.cache is not None and s.equal_springs is None \
                    and id(s) not in self._read:
                s.tables()      # from the disk cache, else computed and stored (as s.solve)
                self._read[id(s)] = s      # held: its id is not another's while kept
            base = (s.influence(p, side) if tables is None else
                    tables.table(p, int(pitch), side)) / w
            law = s.local_law(q, q_load)

            def local(lam):
                return law(np.asarray(lam) / w) / w
        key = (slot.index, p, side, turn)
        if key not in self._turned:
            self._turned[key] = (rotate(q.normal, turn), rotate(q.point, turn))
        normal, point = self._turned[key]
        return MeshContacts(g0=g0, normal=normal, point=point, arm=q.arm, base=base,
                            local=local, label=(q.pins + shift) % self.labels, source=q)

    def record(self, slot, solved, twist, torque: float, meshing=None):
        """The disc's load sharing over the positions from the system's solutions.

        Parameters
        ----------
        slot : toothfem.fem.drives.assembly.DiscSlot
        solved : list of MeshSolution
            The disc's at each position.
        twist : array_like, shape (P,)
            The reducer's TE [rad].
        torque : float
            The disc's torque [N m].
        meshing : toothfem.geometry.kinematics.MeshingState, optional
            The first disc's meshing at the positions (computed if not given).

        Returns
        -------
        toothfem.fem.load_sharing.LoadSharing
            Method "system"; Hertz half-widths and pressures from the forces.
        """
        force = np.zeros((len(solved), self.labels))
        for p, sol in enumerate(solved):
            np.add.at(force[p], sol.contacts.label, sol.force_N)
        model = slot.solver.model
        meshing = self.drive.meshing(slot.solver.positions_rad) if meshing is None \
            else meshing
        return record("system", model, meshing, force, np.full(force.shape, np.inf),
                      np.asarray(twist, float), torque)


class ToothMesh(Mesh):
    """The sine planet in its ring: the contact unknowns are the planet's hats (the cycle
    mode's pressure grid, fem/sine_fe) whose initial gap is below a selection gap, their
    flexibility the two bodies' hat tables (no half-space formula: the grids resolve the
    conformal contact). The selection widens (doubled, up to SELECT_GAP_MAX) until the
    loaded hats lie well inside it and the planet's motion closes no hat left out, as the
    cycle mode's does; the widened gap is kept per position.

    Parameters
    ----------
    drive : toothfem.fem.drives.sine.SineDrive
    """

    def __init__(self, drive):
        self.drive = drive
        pair = drive.pair
        self.eccentricity_m = pair.centre_distance_m
        self.turn_ratio = -pair.tooth_difference / pair.planet_teeth
        self.solver_options = {}
        self._select = {}

    @property
    def labels(self) -> int:
        """Meshing columns (both flanks of the candidate teeth)."""
        return 2 * (2 * self.drive.fe_model().candidates + 1)

    def journal_radius_m(self, supports) -> float:
        """The eccentric's radius under the eccentric bearing's rollers.

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports

        Returns
        -------
        float
            [m]: the output mechanism's eccentric bearing inner radius.
        """
        om = self.drive.output_mechanism
        return om.eccentric_bearing_inner_radius_m

    def sliding_coefficient(self, friction) -> float:
        """The teeth slide on each other: the sliding contacts' coefficient.

        Parameters
        ----------
        friction : toothfem.fem.drives.assembly.PathFriction

        Returns
        -------
        float
            ``friction.pin_disc``.
        """
        return friction.pin_disc

    def contacts(self, slot, p, side, torque, turn, *, deviation=None, pitch=0, shift=0,
                 geometry=None, tables=None) -> MeshContacts:
        """The planet's hats at position p, ``pitch`` meshing periods on, in the housing
        frame of pitch 0 (kept per position: they do not depend on the torque).

        Parameters
        ----------
        slot : toothfem.fem.drives.assembly.DiscSlot
        p : int
            Position index.
        side, torque, turn, shift, tables
            Ignored: the hats cover both flanks in the ring frame.
        deviation : toothfem.fem.deviations.SineDeviation, optional
            The pair as built (:meth:`toothfem.fem.sine_fe.CycleSolver.hat_contacts`).
        pitch : int
            Meshing periods on.
        geometry : None
            The sine pair has no modification to put on its tables.

        Returns
        -------
        MeshContacts
        """
        if geometry is not None:
            raise ContactError("the sine pair has no modification to put on its tables")
        sel = self._select.get((p, int(pitch)), DEFAULT_SELECT_GAP)
        return self._kept(deviation, (slot.index, p, int(pitch), sel),
                          lambda: self._contacts(slot, p, pitch, sel, deviation))

    def _contacts(self, slot, p, pitch, sel, deviation) -> MeshContacts:
        s, w = slot.solver, self.drive.face_width_m
        back = -int(pitch) * self.drive.pair.crank_pitch_rad
        chi = float(s.positions_rad[p]) - back
        h = s.hat_contacts(chi, sel, deviation)
        # the housing frame of pitch 0 (the mesh m periods on is pitch 0's turned by m
        # crank pitches: the system's eccentric and output pins stand at pitch 0's)
        return MeshContacts(g0=h.g0, normal=-rotate(h.normal, back),
                            point=rotate(h.point - h.centre, back), arm=h.arm,
                            base=h.flexibility / w, local=None, label=h.column,
                            source=(chi, h, int(pitch)))

    def record(self, slot, solved, twist, torque: float, meshing=None):
        """The planet's load sharing over the positions from the system's solutions (the
        cycle mode's record: per meshing column, Hertz's or the FE's pressure).

        Parameters
        ----------
        slot : toothfem.fem.drives.assembly.DiscSlot
        solved : list of MeshSolution
            The planet's at each position.
        twist : array_like, shape (P,)
            Not used (each solution's own planet rotation closes the untouched columns).
        torque : float
            The planet's torque [N m].
        meshing : ignored
            (The solver's own meshing states.)

        Returns
        -------
        toothfem.fem.load_sharing.LoadSharing
        """
        s, w = slot.solver, self.drive.face_width_m
        results = []
        for p, sol in enumerate(solved):
            chi, h, m = sol.contacts.source
            r = h.result(chi, sol.force_N / w, sol.gap_m, sol.rotation_rad, 0,
                         s.planet.spacing)
            results.append(s.labelled(r, float(s.positions_rad[p]), m))
        return s.record("system", results, torque)

    def widen(self, p, pitch, mesh: MeshContacts, force, gap) -> bool:
        """Whether the selection must widen: a loaded hat's initial gap above SELECT_MARGIN
        of the selection gap, or a hat at the selection's edge (initial gap above that)
        closed to less than half its initial gap (the bodies' motion reaches the hats left
        out). Then the gap is doubled for this position.

        Parameters
        ----------
        p, pitch : int
            The position and pitch solved.
        mesh : MeshContacts
        force, gap : numpy.ndarray
            The solved forces [N] and gaps [m].

        Returns
        -------
        bool

        Raises
        ------
        toothfem.fem.contact.ContactError
            If it would pass SELECT_GAP_MAX (the load is too high for the candidates).
        """
        _, h, _ = cast("tuple[float, HatContacts, int]", mesh.source)  # _contacts' source
        loaded = force > 0
        edge = mesh.g0 > SELECT_MARGIN * h.select_gap
        if np.max(mesh.g0[loaded], initial=0.0) <= SELECT_MARGIN * h.select_gap \
                and np.all(gap[edge] >= 0.5 * mesh.g0[edge]):
            return False
        if 2 * h.select_gap > SELECT_GAP_MAX:
            raise ContactError(f"the contact reaches hats with an initial gap of "
                               f"{np.max(mesh.g0[loaded]) * UM_PER_M:.1f} um; the load is too "
                               "high for the candidate teeth (raise candidates)")
        self._select[(p, int(pitch))] = 2 * h.select_gap
        return True
