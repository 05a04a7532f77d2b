"""Cycle mode of the cycloid disc: influence coefficients from one factorisation, the Hertz
local approach and the complementarity solve per position (fem/cycloid_fe/__init__.py)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..hertz import hertz_line
from ...errors import ToothfemError, check_range
from ...geometry import cycloid as cy
from .. import contact
from ..cache import content_key
from ..elastic import Body
from ..load_sharing import LoadSharing, hertz_fields
from ..mesh import Refinement, mesh_rings
from .model import (LOCAL_MAX_ITER, LOCAL_RTOL, CycloidFEModel, PinModel, _disc_rings,
                    _held_nodes, _Position, _positions, _window, housing_body, patch_loads,
                    strip_width_correction)

# ---------------------------------------------------------------------------------------
# Cycle mode

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
    cache: object = None                 # DiskCache of the influence tables, or None
    #: torque signs the solver serves: (1,) the positive torque only (the carrying flank of
    #: the MeshingState convention); (1, -1) both flanks, the mesh refined along both.
    sides: tuple = (1,)

    def __post_init__(self):
        self.sides = tuple(int(s) for s in self.sides)
        if self.sides not in ((1,), (1, -1)):
            raise ToothfemError(f"sides = {self.sides!r} is not one of [(1,), (1, -1)]")

    @cached_property
    def _geometry(self):
        """(candidate contacts per position, MeshingState): kinematics only, no mesh."""
        return _positions(self.model, self.positions_rad)

    @cached_property
    def _other_side(self):
        """Candidate contacts per position for a negative torque (the other flank)."""
        return _positions(self.model, self.positions_rad, self._geometry[1], side=-1)[0]

    def _candidates(self, side: int):
        """Candidate contacts per position for a torque of sign ``side``."""
        if side not in self.sides:
            raise ToothfemError("a negative torque loads the other flank: build the solver "
                                "with sides=(1, -1)")
        return self._geometry[0] if side > 0 else self._other_side

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
        every = [q for side in self.sides for q in self._candidates(side)]
        # windows: the span of each pin's contact parameter over the positions + patch
        # (a pin may touch each flank: one window per pin and side)
        windows = {}
        for side in self.sides:
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
        held = _held_nodes(bm, [n for n in names if n.startswith("crank")])
        disc = Body(bm, self.model.youngs_modulus, self.model.poisson_ratio, held,
                    self.model.plane)
        if self.model.pin_structure == "integral":
            # windows on the housing teeth: the contact direction on each pin (housing frame)
            hb = self.b_ref / 2
            tz, pts_h = {}, []
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
        """(C, C) disc compliance at position p's candidates for a torque of sign ``side``
        (patch b_ref), per unit length; computed with every position of that side not yet
        known in one block solve, and kept (a new torque costs no new solve)."""
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
        """Hash of what the influence tables depend on: geometry, holes, material, pin
        structure, plane, positions, b_ref and mesh density. Not the torque, and not the
        face width (the tables are per unit length)."""
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
                for side in self.sides for p in range(n)]

    def tables(self) -> dict:
        """The torque-independent arrays of the solve: ``influence_<p>`` (C_p, C_p) for
        every position and, for conventional pins, ``pin_table``. Taken from ``cache``
        when it holds them (no mesh, no factorisation), else computed and stored there."""
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
        """Use ``tables`` (as returned by :meth:`tables`, e.g. from another process) instead
        of computing them; refused (ToothfemError) if they do not fit these positions."""
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
        """(disc Body, displacement dofs) at position p under the solved contact forces
        (Hertz strips of b_ref pressing along the inward normal), disc frame."""
        _, _, disc, _ = self._setup
        q = self._candidates(1 if load_sharing.torque > 0 else -1)[p]
        f = load_sharing.force[p, q.pins] / self.model.face_width
        loads = patch_loads(disc, "profile", q.point, -q.normal, self.b_ref)
        return disc, disc.solve(loads @ f)

    def solve(self, torque: float, progress=None) -> LoadSharing:
        """Load sharing at every position for the disc torque (N m); a negative torque
        loads the other flank (a solver built with ``sides=(1, -1)``)."""
        check_range("torque", torque)
        if torque == 0:
            raise ToothfemError("torque = 0 is outside the valid range: nonzero (the "
                                "rotation of an unloaded disc is not determined)")
        side = 1 if torque > 0 else -1
        pos = self._candidates(side)
        if self.cache is not None and self.equal_springs is None:
            self.tables()
        state, pin = self._geometry[1], self._pin
        m = self.model
        q_load = torque / m.face_width
        zb = m.geometry.pin_count
        n_pos = len(pos)
        force = np.zeros((n_pos, zb))
        gap = np.where(np.isfinite(state.gap), state.gap, np.inf).copy()
        beta = np.zeros(n_pos)
        it = range(n_pos) if progress is None else progress(range(n_pos))
        for p in it:
            q = pos[p]
            if self.equal_springs is not None:     # rigid-body limit: H = k I, linear
                sol = contact.solve_contact(np.eye(q.pins.size) * self.equal_springs, q.gap,
                                            q.arm, q_load)
            else:
                sol = self._solve_position(p, q, q_load, pin, side)
            force[p, q.pins] = sol.force * m.face_width
            gap[p, q.pins] = sol.gap
            beta[p] = sol.rigid
        return _record("cycle", m, state, force, gap, beta, torque)

    def _solve_position(self, p, q, q_load, pin, side=1):
        """Complementarity at one position, iterated on the Hertz half-widths b(F)."""
        m = self.model
        e_p = m.e_plane
        c_disc = self.influence(p, side)
        lam = _seed_guess(q, q_load)
        for _ in range(LOCAL_MAX_ITER):
            b = _half_width(lam, q.r_eq, m.e_star, q_load, q.arm)
            local = strip_width_correction(b, self.b_ref, e_p)
            if m.pin_structure == "integral":       # housing tooth: strip of b_ref/2
                local = local + strip_width_correction(b, self.b_ref / 2, e_p)
            elif m.pin_structure == "conventional":
                local = local + pin.compliance(q.gamma, b)
            sol = contact.solve_contact(c_disc + np.diag(local), q.gap, q.arm, q_load)
            done = np.max(np.abs(sol.force - lam)) <= LOCAL_RTOL * np.max(sol.force)
            lam = sol.force
            if done:
                return sol
        raise contact.ContactError("the Hertz local approach did not settle at "
                                   f"crank angle {math.degrees(q.phi):.3f} deg")




def _merged(windows):
    """[(lo, hi)] of the windows [(pin, lo, hi)] with the overlapping windows of one pin
    joined (a pin near the tip or root is a candidate for both torque signs); one window
    per pin, as a one-sided solver has, stays as it is."""
    out = {}
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


def _half_width(lam, r_eq, e_star, q_load, arm):
    """Hertz half-width per candidate; unloaded ones get the width of a mean load."""
    carry = (arm < 0) if q_load > 0 else (arm > 0)
    mean = abs(q_load) / np.sum(np.abs(arm[carry])) if np.any(carry) else abs(q_load)
    return hertz_line(np.where(lam > 0, lam, mean), np.abs(r_eq), e_star)[1]


def _record(method, model, state, force, gap, beta, torque) -> LoadSharing:
    b, ph, invalid = hertz_fields(force, model.face_width, state.equivalent_radius, model.e_star,
                                  (state.radius_moving, state.radius_fixed))
    return LoadSharing(
        method=method, position_rad=state.position_rad, contact_id=state.contact_id,
        force=force, point=state.point, moment_arm=state.moment_arm, half_width=b, ph=ph,
        gap=np.where(force > 0, 0.0, gap), transmission_error=beta, torque=float(torque),
        face_width=model.face_width, pressure_from_fe=np.zeros_like(invalid),
        equivalent_radius=state.equivalent_radius, hertz_invalid=invalid)
