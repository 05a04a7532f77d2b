"""Cycle mode of the cycloid disc: influence coefficients from one factorisation, the Hertz
local approach (:mod:`.local_approach`) and the complementarity solve per position
(fem/cycloid_fe/__init__.py); a built stage's gaps: :mod:`.built_stage`; the record:
:mod:`.record`."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...errors import ToothfemError
from ...geometry import cycloid_mesh as cy
from ...geometry.cycloid import CycloidGeometry
from .. import contact
from ..cache import DiskCache, content_key
from ..elastic import Body
from ..linsolve import one_blas_thread
from ..load_sharing import LoadSharing, check_member_torque, position_pitches
from ..mesh import Refinement, mesh_rings
from .built_stage import deviation_gaps
from .local_approach import local_law
from .model import (LOCAL_MAX_ITER, LOCAL_RTOL, CycloidFEModel, PinModel, _disc_rings,
                    _held_nodes, _Position, _positions, _window, housing_body, patch_loads)
from .record import record

# ---------------------------------------------------------------------------------------
# Cycle mode

#: Initial gap [m] of a candidate that a modified profile cannot reach (no contact point on
#: its working profile): far beyond any elastic approach.
MODIFIED_GAP_FAR = 1e-3
#: The solver's choices of flanks (CycleSolver.sides).
SIDES = ((1,), (1, -1), (0,))
#: Bump when the discretisation behind the influence tables changes (mesh sizes, patches,
#: pin table angles): it is part of :meth:`CycleSolver.cache_key`, so old files go unused.
TABLES_VERSION = 2


@dataclass(eq=False)
class CycleSolver:
    """Influence coefficients of the disc for a set of positions from one factorisation.

    ``cache`` (a :class:`toothfem.fem.cache.DiskCache`, or None) keeps the torque-independent
    tables on disk under :meth:`cache_key`: a solver for a design already in it builds no
    mesh and factorises nothing. Without it nothing is read or written."""
    model: CycloidFEModel
    positions_rad: np.ndarray
    b_ref: float = 1e-4
    elements_per_bref: int = 5
    equal_springs: float | None = None   # rigid bodies with equal contact springs (m per N/m)
    cache: DiskCache | None = None       # the influence tables' disk cache
    #: torque signs the solver serves: (1,) the positive torque only (the carrying flank of
    #: the MeshingState convention); (1, -1) both flanks, the mesh refined along both, each
    #: torque on its own flank; (0,) both flanks at once, every pin a candidate whatever
    #: the torque (an idle flank that closes, as in a built stage with interference, takes
    #: load: docs/tolerance.md).
    sides: tuple = (1,)

    def __post_init__(self):
        self.sides = tuple(int(s) for s in self.sides)
        if self.sides not in SIDES:
            raise ToothfemError(f"sides = {self.sides!r} is not one of {list(SIDES)}")

    @property
    def _tabled(self) -> tuple:
        """The sides with tables of their own ((0,): one set, filed under side 1)."""
        return (1,) if self.sides == (0,) else self.sides

    @cached_property
    def _geometry(self):
        """(candidate contacts per position, MeshingState): kinematics only, no mesh."""
        return _positions(self.model, self.positions_rad, side=0 if self.sides == (0,) else 1)

    @cached_property
    def _other_side(self):
        """Candidate contacts per position for a negative torque (the other flank)."""
        return _positions(self.model, self.positions_rad, self._geometry[1], side=-1)[0]

    def _candidates(self, side: int):
        """Candidate contacts per position for a torque of sign ``side``."""
        if self.sides == (0,):
            if side < 0 and self.model.geometry.rotation_rad:
                return self._both_flanks_negative
            return self._geometry[0]
        if side not in self.sides:
            raise ToothfemError("a negative torque loads the other flank: build the solver "
                                "with sides=(1, -1)")
        return self._geometry[0] if side > 0 else self._other_side

    @cached_property
    def _both_flanks_negative(self):
        """Every pin a candidate, the gaps linearised for a negative torque (a rotation
        modification: about the pose where the negative torque's flank is turned back)."""
        gaps = cy.clearance_exact(self.model.geometry, self.positions_rad, -1)
        return [dataclasses.replace(q, gap=gaps[p, q.pins])
                for p, q in enumerate(self._geometry[0])]

    @cached_property
    def _pin(self):
        """The conventional pin's compliance model (None for the other structures)."""
        if self.model.pin_structure != "conventional":
            return None
        return PinModel(self.model.geometry.pin_radius_m, self.model.youngs_modulus,
                        self.model.poisson_ratio, self.b_ref / 2, self.model.plane)

    @cached_property
    def _setup(self):
        pos, state = self._geometry
        if self.equal_springs is not None:
            return pos, state, None, None
        g = self.model.geometry
        every = [q for side in self._tabled for q in self._candidates(side)]
        # windows: the span of each pin's contact parameter over the positions + patch
        # (a pin may touch each flank: one window per pin and side)
        windows: dict = {}
        for side in self._tabled:
            for p in self._candidates(side):
                for j, s in zip(p.pins, p.psi):
                    lo, hi = windows.get((j, side), (s, s))
                    windows[(j, side)] = (min(lo, s), max(hi, s))
        pad = 3 * self.b_ref / g.pin_circle_radius_m
        win = _merged([(j, lo - pad, hi + pad) for (j, _), (lo, hi) in windows.items()])
        h = self.b_ref / self.elements_per_bref
        rings, names = _disc_rings(self.model, [_window(g.generating(), lo, hi, h)
                                                for lo, hi in win])
        centres = np.concatenate([p.point for p in every], axis=1)
        bm = mesh_rings(rings, size_max=g.pin_circle_radius_m / 25,
                        refinements=[Refinement(centres, h, self.b_ref, 20 * self.b_ref)],
                        names=names)
        held = _held_nodes(bm, self.model.held_rings(names))
        disc = Body(bm, self.model.youngs_modulus, self.model.poisson_ratio, held,
                    self.model.plane)
        if self.model.pin_structure == "integral":
            # windows on the housing teeth: the contact direction on each pin (housing frame)
            hb = self.b_ref / 2
            tz: dict = {}
            pts_h: list = []
            for p_idx, p in enumerate(every):
                p_idx = p_idx % len(pos)
                k_h = state.point[p_idx, p.pins].T
                c_h = cy.pin_centres(g)[:, p.pins]
                pts_h.append(k_h)
                ang = np.arctan2(k_h[1] - c_h[1], k_h[0] - c_h[0])
                for j, a in zip(p.pins, ang):   # near a_j + pi: keep each pin's angles together
                    a_j = 2 * math.pi * j / g.pin_count + math.pi
                    tz.setdefault(j, []).append(a_j + math.remainder(a - a_j, 2 * math.pi))
            zones = {}
            for j, a in tz.items():
                lo, hi = min(a) - 3 * hb / g.pin_radius_m, max(a) + 3 * hb / g.pin_radius_m
                n = max(int(math.ceil((hi - lo) * g.pin_radius_m / (hb / 5))), 2)
                zones[j] = np.linspace(lo, hi, n + 1)
            centres = np.concatenate(pts_h, axis=1)
            pin = housing_body(self.model, zones,
                               [Refinement(centres, hb / 5, hb, 20 * hb)], keep_below=hb / 2)
        else:
            pin = self._pin
        return pos, state, disc, pin

    @cached_property
    def _influence(self):
        return {}

    def influence(self, p: int, side: int = 1):
        """Disc compliance at one position's candidates (patch b_ref), per unit length.

        Computed with every position of that side not yet known in one block solve, and
        kept (a new torque costs no new solve).

        Parameters
        ----------
        p : int
            Index into ``positions_rad``.
        side : {1, -1}
            Sign of the torque whose flank is loaded (ignored for ``sides=(0,)``).

        Returns
        -------
        numpy.ndarray, shape (C, C)
            Approach per unit force per length [m per N/m] of candidate i under a unit
            patch load at candidate j.
        """
        side = 1 if self.sides == (0,) else side
        key = p if side > 0 else (p, side)
        if key in self._influence:
            return self._influence[key]
        _, state, disc, housing = self._setup
        cand = self._candidates(side)
        keys = [k if side > 0 else (k, side) for k in range(len(cand))]
        todo = [k for k, kk in enumerate(keys) if kk not in self._influence]
        sizes = [cand[k].pins.size for k in todo]
        loads = patch_loads(disc, "profile", np.concatenate([cand[k].point for k in todo], 1),
                            np.concatenate([cand[k].normal for k in todo], 1), self.b_ref)
        blocks = disc.flexibility(loads, sizes)
        if self.model.pin_structure == "integral":
            lh = patch_loads(housing, "teeth",
                             np.concatenate([state.point[k, cand[k].pins].T for k in todo], 1),
                             np.concatenate([state.normal[k, cand[k].pins].T for k in todo], 1),
                             self.b_ref / 2)
            blocks = [c + ch for c, ch in zip(blocks, housing.flexibility(lh, sizes))]
        self._influence.update(zip([keys[k] for k in todo], blocks))
        return self._influence[key]

    def cache_key(self) -> str:
        """Hash of what the influence tables depend on.

        Returns
        -------
        str
            :func:`toothfem.fem.cache.content_key` of the geometry, holes, material, pin
            structure, plane, positions, b_ref and mesh density. Not the torque, and not
            the face width (the tables are per unit length).
        """
        m = self.model
        # both flanks refine another mesh; the one-sided key stays as it was
        sides = () if self.sides == (1,) else (self.sides,)
        return content_key("CycleSolver", TABLES_VERSION, m.geometry, m.holes,
                           m.youngs_modulus, m.poisson_ratio, m.pin_structure, m.plane,
                           m.housing_outer_radius if m.pin_structure == "integral" else None,
                           np.asarray(self.positions_rad, float), self.b_ref,
                           self.elements_per_bref, *sides)

    def _table_keys(self):
        """(table name, position, side) of every influence table."""
        n = len(self._geometry[0])
        return [(f"influence_{p}" if side > 0 else f"influence_neg_{p}", p, side)
                for side in self._tabled for p in range(n)]

    def tables(self) -> dict:
        """The torque-independent arrays of the solve.

        Taken from ``cache`` when it holds them (no mesh, no factorisation), else computed
        and stored there.

        Returns
        -------
        dict of str to numpy.ndarray
            ``influence_<p>`` (C_p, C_p) for every position (``influence_neg_<p>`` for the
            other flank) and, for conventional pins, ``pin_table``.

        Raises
        ------
        ToothfemError
            For a solver in the equal-springs limit (it has no tables).
        """
        if self.equal_springs is not None:
            raise ToothfemError("the equal-springs limit has no influence tables")
        keys = self._table_keys()
        n = len(keys)
        if self.cache is not None and len(self._influence) < n:
            hit = self.cache.load(self.cache_key())
            if hit is not None:
                try:
                    self.adopt(hit)
                except ToothfemError:      # stale or foreign file: recompute, overwrite
                    self._influence.clear()
        computed = len(self._influence) < n or (self._pin is not None
                                                and "table" not in vars(self._pin))
        out = {name: self.influence(p, side) for name, p, side in keys}
        if self._pin is not None:
            out["pin_table"] = self._pin.table
        if computed and self.cache is not None:
            self.cache.store(self.cache_key(), out)
        return out

    def adopt(self, tables) -> None:
        """Use given tables instead of computing them.

        Parameters
        ----------
        tables : mapping of str to array_like
            As returned by :meth:`tables`, e.g. from another process or the disk cache.

        Raises
        ------
        ToothfemError
            If they do not fit these positions (shape, count, a non-finite entry).
        """
        keys = self._table_keys()
        for name, p, side in keys:
            q = self._candidates(side)[p]
            c = np.asarray(tables.get(name, np.empty(0)), float)
            if c.shape != (q.pins.size, q.pins.size) or not np.all(np.isfinite(c)):
                raise ToothfemError(f"influence table of position {p} does not fit: shape "
                                    f"{c.shape}, expected {(q.pins.size, q.pins.size)}")
        if len(tables) != len(keys) + (self._pin is not None):
            raise ToothfemError(f"{len(tables)} tables for {len(keys)} positions and sides")
        if self._pin is not None:
            t = np.asarray(tables.get("pin_table", np.empty(0)), float)
            if t.shape != self._pin.angles.shape:
                raise ToothfemError(f"pin table shape {t.shape} does not fit "
                                    f"{self._pin.angles.shape}")
            self._pin.table = t          # fills the cached_property
        for name, p, side in keys:
            self._influence[p if side > 0 else (p, side)] = np.asarray(tables[name], float)

    #: the cycle mode smears its loads over the disc (no contact-zone stress): see
    #: :meth:`structural_field`.
    has_structural_field = True

    def prepare(self) -> None:
        """Build (or read from the cache) every torque-independent table now."""
        self.tables()

    def structural_field(self, p: int, load_sharing: LoadSharing):
        """The disc's displacement at one position under the solved contact forces.

        Parameters
        ----------
        p : int
            Index into ``positions_rad``.
        load_sharing : LoadSharing
            A result of :meth:`solve`; its forces press as Hertz strips of b_ref along
            the inward normal.

        Returns
        -------
        disc : toothfem.fem.elastic.Body
        u : numpy.ndarray
            Displacement dofs [m], disc frame.
        """
        _, _, disc, _ = self._setup
        q = self._candidates(1 if load_sharing.torque > 0 else -1)[p]
        f = load_sharing.force[p, q.pins] / self.model.face_width
        loads = patch_loads(disc, "profile", q.point, -q.normal, self.b_ref)
        return disc, disc.solve(loads @ f)

    def solve(self, torque: float, progress=None, *, deviation=None,
              pitches=None, geometry=None) -> LoadSharing:
        """Load sharing at every position for one disc torque.

        Parameters
        ----------
        torque : float
            Disc torque [N m]; a negative torque loads the other flank (a solver built
            with ``sides=(1, -1)``).
        progress : callable, optional
            Wraps the iterable of positions (e.g. a progress bar).
        deviation : toothfem.fem.deviations.CycloidDeviation, optional
            Shifts the initial gaps of the candidates
            (:func:`~toothfem.fem.cycloid_fe.built_stage.deviation_gaps`), the influence
            tables unchanged.
        pitches : array_like of int, shape (P,), optional
            Puts position p that many pin pitches on, where other pins and lobes take the
            contacts' places (the tables of pitch 0: the holes' effect on the disc's
            compliance at the other pitches is left out).
        geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
            Another modification of this disc (micrometres from this one) solved with this
            disc's tables: its initial gaps at these candidates (``toothfem design``).

        Returns
        -------
        LoadSharing
            Method "cycle"; it keeps the labels of pitch 0 (pin j stands for pin j +
            pitch).

        Raises
        ------
        ToothfemError
            For a zero or non-finite torque, a torque sign the solver was not built for,
            ``pitches`` of another shape, or a ``geometry`` that differs in more than its
            modifications.
        toothfem.fem.contact.ContactError
            If the Hertz local approach does not settle.
        """
        check_member_torque(torque, "disc")
        side = 1 if torque > 0 else -1
        pos = self._candidates(side)
        if self.cache is not None and self.equal_springs is None:
            self.tables()
        state = self._geometry[1]
        m = self.model
        q_load = torque / m.face_width
        zb = m.geometry.pin_count
        n_pos = len(pos)
        pitches = position_pitches(pitches, n_pos)
        force = np.zeros((n_pos, zb))
        gap = np.where(np.isfinite(state.gap), state.gap, np.inf).copy()
        beta = np.zeros(n_pos)
        if geometry is not None:
            pos = [dataclasses.replace(q, gap=g) for q, g in
                   zip(pos, self.modified_gaps(geometry, side))]
        it = range(n_pos) if progress is None else progress(range(n_pos))
        with one_blas_thread():
            for p in it:
                with contact.naming_load(f"disc torque {torque:g} N m, position {p}"):
                    self._solve_one(p, pos[p], q_load, side, deviation, pitches[p], force,
                                    gap, beta)
        return record("cycle", m, state, force, gap, beta, torque)

    def modified_gaps(self, geometry, side: int) -> list:
        """Initial gaps of another modification of the disc at this solver's candidates,
        per position (a pin the other profile cannot reach: MODIFIED_GAP_FAR); the last
        geometry's kept, both flanks (a design candidate is solved at several torques and
        deviations, and its backlash closes each position's two flanks in turn).

        Parameters
        ----------
        geometry : toothfem.geometry.cycloid.CycloidGeometry
            This disc with other modifications.
        side : {1, -1}
            The torque's sign.

        Returns
        -------
        list of numpy.ndarray
            (C_p,) gaps [m] of each position's candidates.

        Raises
        ------
        ToothfemError
            For a geometry that differs in more than its modifications.
        """
        # (geometry, {side: gaps per position}) of the last geometry asked for
        kept: tuple[CycloidGeometry, dict[int, list[np.ndarray]]] | None = \
            self.__dict__.get("_modified")
        if kept is not None and kept[0] == geometry and side in kept[1]:
            return kept[1][side]
        g = self.model.geometry
        if (geometry.pin_count, geometry.pin_circle_radius_m, geometry.eccentricity_m,
                geometry.pin_radius_m) != (g.pin_count, g.pin_circle_radius_m,
                                           g.eccentricity_m, g.pin_radius_m):
            raise ToothfemError("geometry differs from the solver's disc in more than its "
                                "modifications")
        gaps = cy.clearance_exact(geometry, self.positions_rad, side)
        gaps = np.where(np.isfinite(gaps), gaps, MODIFIED_GAP_FAR)
        out = [gaps[p, q.pins] for p, q in enumerate(self._candidates(side))]
        if kept is None or kept[0] != geometry:     # another geometry: its flanks go
            kept = self.__dict__["_modified"] = (geometry, {})
        kept[1][side] = out
        return out

    def _solve_one(self, p, q, q_load, side, deviation, pitch, force, gap, beta):
        """Position p into the rows of ``force``, ``gap`` and ``beta``."""
        m = self.model
        g0 = q.gap if deviation is None else \
            q.gap + deviation_gaps(m, q, deviation, pitch)
        if self.equal_springs is not None:     # rigid-body limit: H = k I, linear
            sol = contact.solve_contact(np.eye(q.pins.size) * self.equal_springs, g0, q.arm,
                                        q_load)
        else:
            sol = self._solve_position(p, q, q_load, side, g0)
        force[p, q.pins] = sol.force * m.face_width
        gap[p, q.pins] = sol.gap
        beta[p] = sol.rigid

    def compliance(self, p: int, q: _Position, lam, q_load: float, side: int = 1):
        """Contact flexibility of one position's candidates at given forces: the disc's
        (and integral housing's) influence table plus each contact's local approach
        (:meth:`local_compliance`) on the diagonal.

        Parameters
        ----------
        p : int
            Index into ``positions_rad``.
        q : _Position
            That position's candidates (:meth:`candidates`).
        lam : array_like, shape (C,)
            Contact forces per length [N/m].
        q_load : float
            The member torque per length [N m/m] (its sign picks the carrying flank).
        side : {1, -1}
            The flank of the tables.

        Returns
        -------
        numpy.ndarray, shape (C, C)
            [m per N/m].
        """
        return self.influence(p, side) + np.diag(self.local_compliance(q, lam, q_load))

    def local_compliance(self, q: _Position, lam, q_load: float) -> np.ndarray:
        """Each candidate's local approach per force at given forces, what the influence
        tables leave out: the Hertz approach at its half-width b(F) and, for conventional
        pins, the pin's own compliance (a secant: the approach is this times the force).

        Parameters
        ----------
        q : _Position
            One position's candidates (:meth:`candidates`).
        lam : array_like, shape (..., C)
            Contact forces per length [N/m] the half-widths are taken at (an unloaded
            candidate: the width of the mean load).
        q_load : float
            The member torque per length [N m/m] (its sign picks the carrying flank).

        Returns
        -------
        numpy.ndarray, shape (..., C)
            [m per N/m].
        """
        return self.local_law(q, q_load)(lam)

    def local_law(self, q: _Position, q_load: float):
        """:meth:`local_compliance` of one position's candidates as a function of the
        forces alone (what does not depend on them taken once;
        :func:`~toothfem.fem.cycloid_fe.local_approach.local_law`).

        Parameters
        ----------
        q : _Position
        q_load : float
            The member torque per length [N m/m].

        Returns
        -------
        callable
            lam (..., C) [N/m] -> (..., C) [m per N/m].
        """
        return local_law(self.model, self._pin, self.b_ref, q, q_load)

    def candidates(self, side: int = 1) -> list:
        """The candidate contacts of every position for a torque of sign ``side``.

        Parameters
        ----------
        side : {1, -1}
            The torque's sign (ignored by a solver of both flanks, ``sides=(0,)``).

        Returns
        -------
        list of _Position
            Disc frame; one per entry of ``positions_rad``.
        """
        return self._candidates(1 if self.sides == (0,) else side)

    def _solve_position(self, p, q, q_load, side, g0):
        """Complementarity at one position, iterated on the Hertz half-widths b(F)."""
        lam, active = _seed_guess(q, q_load), None
        for _ in range(LOCAL_MAX_ITER):
            sol = contact.solve_contact(self.compliance(p, q, lam, q_load, side), g0, q.arm,
                                        q_load, active=active)
            done = np.max(np.abs(sol.force - lam)) <= LOCAL_RTOL * np.max(sol.force)
            lam, active = sol.force, sol.active
            if done:
                return sol
        raise contact.ContactError("the Hertz local approach did not settle at "
                                   f"crank angle {math.degrees(q.phi):.3f} deg")


def _merged(windows):
    """[(lo, hi)] of the windows [(pin, lo, hi)] with the overlapping windows of one pin
    joined (a pin near the tip or root is a candidate for both torque signs); one window
    per pin, as a one-sided solver has, stays as it is."""
    out: dict = {}
    for j, lo, hi in windows:
        spans = out.setdefault(j, [])
        for k, (a, b) in enumerate(spans):
            if lo <= b and a <= hi:
                spans[k] = (min(a, lo), max(b, hi))
                break
        else:
            spans.append((lo, hi))
    return [w for spans in out.values() for w in spans]


def _seed_guess(q: _Position, q_load):
    """Forces proportional to the moment arm on the flank that carries ``q_load``."""
    s = 1.0 if q_load > 0 else -1.0
    w = np.where(s * q.arm < 0, -s * q.arm, 0.0)
    return w * q_load / np.sum(w * -q.arm)
