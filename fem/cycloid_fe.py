"""Finite-element load sharing of a cycloid disc on its pins: cycle mode and detailed mode.

Both modes work in the disc frame (disc centre at the origin, the disc held at its
crank-bearing holes by a rigid coupling that turns by the unknown transmission error beta)
and return a :class:`~toothfem.fem.load_sharing.LoadSharing`. Friction is neglected in the
solve (frictionless normal contact); the friction forces are small against the normal
forces (mu ~ 0.05) and are accounted for in the efficiency model.

Pins (conventional structure): each pin is an elastic disc of radius rz held over the outer
half of its boundary by the housing groove (treated as rigid). Contact is plane strain per
unit face width; forces are reported over the face width.

Cycle mode (sweeps): for each position the candidate contacts are the pins whose normal can
carry the torque. The disc's influence coefficients at the candidate points come from one
sparse factorisation of a disc mesh refined along the short profile windows that the
contact points sweep over one meshing period (a pin's contact point moves by 1/Za of the
crank angle along the profile). A unit load is a Hertzian strip of reference half-width
b_ref; the displacement is its work-conjugate patch average. The Hertz local approach then
corrects each diagonal term from b_ref to the contact's own half-width b(F):
delta(b) - delta(b_ref) = -(2 (1 - nu^2) / (pi E)) F ln(b / b_ref) (half-space strip,
docs/fem.md). The pin's compliance comes from an FE table over the contact angle with the
same correction. The complementarity problem with the torque balance is solved for each
iterate of b(F) until the forces settle.

Detailed mode (verification, stress plots): both bodies meshed with the contact zones of
the current position refined to a fraction of the Hertz half-width and conforming, the
nodal contact forces solved on the condensed two-body system (fem.contact).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .hertz import hertz_line
from ..errors import ToothfemError, check_range
from ..geometry import cycloid as cy
from . import contact
from .cache import content_key
from .elastic import Body, SameMaterial, plane_modulus
from .load_sharing import LoadSharing, hertz_fields
from .mesh import Refinement, mesh_rings

#: Candidate pins: moment arm below this fraction of r_a on the load-carrying side (a pin
#: with an arm of the wrong sign separates under the rigid rotation).
CANDIDATE_ARM_REL = 0.02
#: Iterations of the Hertz local approach (b depends on F) and their tolerance.
LOCAL_MAX_ITER, LOCAL_RTOL = 50, 1e-9


#: conventional: pins in housing grooves (elastic pins held on their outer half);
#: integral: pins one piece with the housing (clamped at its outer radius);
#: rigid: rigid fixed pins, only the disc deforms (the CalculiX peer's model; cycle mode).
PIN_STRUCTURES = ("conventional", "integral", "rigid")


@dataclass(frozen=True)
class CycloidFEModel(SameMaterial):
    """A disc, its pins and material; torques in N m over the face width."""
    geometry: cy.CycloidGeometry
    holes: cy.DiscHolesSI
    youngs_modulus: float
    poisson_ratio: float
    face_width: float
    pin_structure: str = "conventional"
    plane: str = "strain"
    housing_outer_radius: float | None = None   # integral structure: clamped outer edge, m

    def __post_init__(self):
        check_range("youngs_modulus", self.youngs_modulus, 0, None, lo_open=True)
        check_range("face_width", self.face_width, 0, None, lo_open=True)
        if self.pin_structure not in PIN_STRUCTURES:
            raise ToothfemError(f"pin_structure = {self.pin_structure!r} is not one of "
                                f"{list(PIN_STRUCTURES)}")
        if self.pin_structure == "integral":
            g = self.geometry
            check_range("housing_outer_radius", self.housing_outer_radius,
                        g.pin_circle_radius_m + g.pin_radius_m, None, lo_open=True)
        if self.holes.crank_hole_count < 1:
            raise ToothfemError("the disc needs crank holes (crank_hole_count >= 1) to be held")



def model_from_case(case, pin_structure=None) -> CycloidFEModel:
    """The FE model of a cycloid case; ``pin_structure`` overrides the case's."""
    st = case.cycloid
    return CycloidFEModel(st.geometry(), st.holes_si(), case.material.youngs_modulus_GPa * 1e9,
                          case.material.poisson_ratio, st.face_width_mm * 1e-3,
                          pin_structure or st.pin_structure, "strain",
                          st.housing_outer_radius_mm * 1e-3)


def disc_torque(case) -> float:
    """Torque on one disc: disc_load_factor * output torque / disc_count (seed Eq. 6)."""
    st = case.cycloid
    return st.disc_load_factor * case.operating.output_torque_Nm / st.disc_count


# ---------------------------------------------------------------------------------------
# Shared geometry helpers (disc frame)

@dataclass(frozen=True)
class _Position:
    """Candidate contacts of one crank angle in the disc frame."""
    phi: float
    pins: np.ndarray          # (C,) pin indices
    pin_centre: np.ndarray    # (2, C)
    psi: np.ndarray           # (C,) profile parameter of the nominal contact
    point: np.ndarray         # (2, C) contact point on the disc profile
    normal: np.ndarray        # (2, C) outward normal of the disc (from disc into pin)
    arm: np.ndarray           # (C,) moment arm, MeshingState sign (carrying: < 0)
    gamma: np.ndarray         # (C,) contact angle on the pin from the housing-centre direction
    gap: np.ndarray           # (C,) initial clearance
    r_eq: np.ndarray          # (C,) equivalent radius
    r_disc: np.ndarray        # (C,) signed curvature radius of the disc profile


def _positions(model: CycloidFEModel, phis, state=None):
    g = model.geometry
    gen = g.generating()
    state = state or cy.meshing(g, phis)
    r_a = g.disc_pitch_radius_m
    out = []
    for p, phi in enumerate(state.position_rad):
        pins = np.flatnonzero(state.moment_arm[p] < CANDIDATE_ARM_REL * r_a)
        c_house = cy.pin_centres(g)[:, pins]
        c_disc = cy.to_disc_frame(g, [phi], c_house[:, None, :])[:, 0, :]
        psi0 = 2 * math.pi * pins / g.pin_count + phi / g.lobe_count
        psi, _ = cy.foot_point(gen, c_disc, psi0)
        point = cy.working_profile(gen, psi)
        normal = -cy.inward_normal(gen, psi)
        # contact angle on the pin, in the housing frame (the groove is fixed there)
        towards = -c_house / np.hypot(*c_house)
        d = _rotate(-normal, -phi / g.lobe_count)
        gamma = np.arctan2(towards[0] * d[1] - towards[1] * d[0], np.sum(towards * d, axis=0))
        out.append(_Position(float(phi), pins, c_disc, psi, point, normal,
                             state.moment_arm[p, pins], gamma, state.gap[p, pins],
                             state.equivalent_radius[p, pins], state.radius_moving[p, pins]))
    return out, state


def _rotate(v, a):
    c, s = np.cos(a), np.sin(a)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _disc_rings(model: CycloidFEModel, inserts=(), base_per_lobe=48):
    """Disc outline sampled on the exact profile: ``base_per_lobe`` points per lobe, with
    each array of profile parameters in ``inserts`` (a contact zone) put in place of the
    coarse samples it covers (a half-step margin: no sliver segment beside a zone); plus
    the hole circles."""
    g = model.geometry
    gen = g.generating()
    base = np.linspace(0, 2 * math.pi, g.lobe_count * base_per_lobe, endpoint=False)
    margin = 0.5 * (base[1] - base[0])
    keep = np.ones(base.size, bool)
    for psi in inserts:
        lo, hi = np.min(psi) - margin, np.max(psi) + margin
        keep &= ~(np.mod(base - lo, 2 * math.pi) <= hi - lo)
    psi = np.sort(np.mod(np.concatenate([base[keep]] + list(inserts)), 2 * math.pi))
    psi = psi[np.concatenate([[True], np.diff(psi) > 1e-12])]
    rings, names = [cy.working_profile(gen, psi)], ["profile"]
    for x, y, r, label in model.holes.circles():
        n = max(48, int(2 * math.pi * r / (0.02 * g.pin_circle_radius_m)))
        t = np.linspace(0, 2 * math.pi, n, endpoint=False)
        rings.append(np.stack([x + r * np.cos(t), y + r * np.sin(t)]))
        names.append(label)
    return rings, names


def _window(gen, lo, hi, spacing):
    """Profile parameters from lo to hi at most ``spacing`` apart along the curve."""
    mid = 0.5 * (lo + hi)
    speed = np.hypot(*(cy.working_profile(gen, mid + 1e-7)
                       - cy.working_profile(gen, mid - 1e-7))) / 2e-7
    n = max(int(math.ceil((hi - lo) * speed / spacing)), 2)
    return np.linspace(lo, hi, n + 1)


def _held_nodes(body_mesh, labels):
    return np.unique(np.concatenate([body_mesh.ring_nodes(n) for n in labels]))


# ---------------------------------------------------------------------------------------
# Pin compliance table (conventional pin held on its outer half)

@dataclass(eq=False)
class PinModel:
    """One pin (radius rz, centre at the origin, housing on the +x side) held over its
    outer half; compliance along the inward normal at contact angle gamma (measured from
    -x, the direction toward the housing centre), for Hertzian strips of half-width b."""
    radius: float
    youngs_modulus: float
    poisson_ratio: float
    b_ref: float
    plane: str = "strain"
    angles: np.ndarray = field(default_factory=lambda: np.linspace(-0.5 * math.pi,
                                                                   0.5 * math.pi, 37))

    @cached_property
    def body(self):
        r = self.radius
        h = self.b_ref / 5
        t = np.linspace(0, 2 * math.pi, 2 * max(int(math.pi * r / h), 64), endpoint=False)
        ring = r * np.stack([np.cos(t), np.sin(t)])
        inner = np.cos(t) < 0.05            # the half facing the disc, refined
        ring = ring[:, inner | (np.arange(t.size) % 8 == 0)]
        bm = mesh_rings([ring], size_max=r / 6,
                        refinements=[Refinement(ring[:, ring[0] < 0], h, 2 * self.b_ref,
                                                r / 2)])
        p = bm.mesh.p
        held = bm.ring_nodes("outer")
        held = held[p[0, held] > 0]
        return Body(bm, self.youngs_modulus, self.poisson_ratio, held, self.plane)

    @cached_property
    def table(self) -> np.ndarray:
        """Compliance at b_ref for each angle in ``angles`` (m per N/m)."""
        pts = self.radius * np.stack([-np.cos(self.angles), -np.sin(self.angles)])
        normals = -pts / self.radius              # load pushes the pin surface inward
        loads = patch_loads(self.body, "outer", pts, normals, self.b_ref)
        return np.array([c[0, 0] for c in self.body.flexibility(loads, [1] * pts.shape[1])])

    def compliance(self, gamma, b):
        """C(gamma, b) = C_table(gamma) - (2/(pi E')) ln(b / b_ref)."""
        c_ref = np.interp(gamma, self.angles, self.table)
        e_p = plane_modulus(self.youngs_modulus, self.poisson_ratio, self.plane)
        return c_ref + strip_width_correction(b, self.b_ref, e_p)


def patch_loads(body, ring, points, normals, b_ref):
    """Unit loads (N_dofs, K): Hertzian strips of half-width ``b_ref`` centred at each point
    along ``normals`` over the body's ``ring`` boundary nodes (vertices and midsides);
    the same vectors measure the work-conjugate mean normal displacement."""
    from scipy.sparse import coo_matrix

    sl = contact.slave_surface(body, body.body_mesh.rings[ring])
    rows, cols, vals = [], [], []
    for k in range(points.shape[1]):
        d = np.hypot(*(sl.points - points[:, k:k + 1]))
        near = np.flatnonzero(d < b_ref)
        if near.size < 3:
            raise ToothfemError(f"the mesh does not resolve the load patch b_ref = {b_ref:.3g} m "
                                f"at ({points[0, k]:.6g}, {points[1, k]:.6g}) m")
        w = sl.weights[near] * np.sqrt(1 - (d[near] / b_ref) ** 2)
        w /= w.sum()
        for comp in (0, 1):
            rows.append(sl.dofs[comp, near])
            cols.append(np.full(near.size, k))
            vals.append(w * normals[comp, k])
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(body.basis.N, points.shape[1])).tocsc()


# ---------------------------------------------------------------------------------------
# Integral pin housing: one body, the pins machined into its bore

#: Angular steps of the housing's outline (rad): on the pin arcs (radius rz) and on the
#: arcs of radius Rz between them (chord sag 1.9 um and 1 um for the pin-housing drive).
HOUSING_STEP, HOUSING_BORE_STEP = math.radians(5), math.radians(0.5)


def housing_rings(model: CycloidFEModel, zones: dict, transform=None):
    """(inner toothed ring, outer circle) of the integral housing.

    The inner boundary is the circle of radius Rz with the inner half of every pin circle
    protruding from it; ``zones`` maps a pin index to angles t (housing frame, around the pin
    centre) that must be vertices. ``transform(points) -> points`` maps the housing frame to
    the frame of the caller (the disc frame in the detailed mode)."""
    g = model.geometry
    rz, big_r = g.pin_radius_m, g.pin_circle_radius_m
    alpha = math.acos(-rz / (2 * big_r))       # pin circle meets the circle of radius Rz
    pts = []
    for j in range(g.pin_count):
        a_c = 2 * math.pi * j / g.pin_count
        c = big_r * np.array([math.cos(a_c), math.sin(a_c)])
        t0, t1 = a_c - alpha, a_c + alpha - 2 * math.pi     # going round the inner side
        n = max(int((t0 - t1) / HOUSING_STEP), 8)
        t = np.linspace(t0, t1, n + 1)
        if j in zones:     # zone angles brought into this arc's range (t1, t0)
            z = np.sort(t1 + np.mod(np.asarray(zones[j]) - t1, 2 * math.pi))[::-1]
            if z[0] >= t0 or z[-1] <= t1:
                raise ToothfemError(f"contact zone on pin {j} leaves the pin's inner arc")
            step = (t0 - t1) / n
            t = np.concatenate([t[t > z[0] + 0.5 * step], z, t[t < z[-1] - 0.5 * step]])
        pts.append(c[:, None] + rz * np.stack([np.cos(t), np.sin(t)]))
        # arc of radius Rz to where the next pin's circle meets it
        end = pts[-1][:, -1]
        a_n = 2 * math.pi * (j + 1) / g.pin_count
        start = big_r * np.array([math.cos(a_n), math.sin(a_n)]) + rz * np.array(
            [math.cos(a_n - alpha), math.sin(a_n - alpha)])
        a_end = math.atan2(end[1], end[0])
        a_start = a_end + np.mod(math.atan2(start[1], start[0]) - a_end, 2 * math.pi)
        m = max(int((a_start - a_end) / HOUSING_BORE_STEP), 1)
        arc = np.linspace(a_end, a_start, m + 1)[1:-1]
        pts.append(big_r * np.stack([np.cos(arc), np.sin(arc)]))
    inner = np.concatenate(pts, axis=1)
    r_out = model.housing_outer_radius
    t = np.linspace(0, 2 * math.pi, 360, endpoint=False)
    outer = r_out * np.stack([np.cos(t), np.sin(t)])
    if transform is not None:
        inner, outer = transform(inner), transform(outer)
    return inner, outer


def housing_body(model, zones, refinements, keep_below, transform=None):
    inner, outer = housing_rings(model, zones, transform)
    bm = mesh_rings([outer, inner], size_max=model.geometry.pin_circle_radius_m / 25,
                    refinements=refinements, names=["outer", "teeth"], keep_below=keep_below)
    return Body(bm, model.youngs_modulus, model.poisson_ratio, bm.ring_nodes("outer"),
                model.plane)


# ---------------------------------------------------------------------------------------
# Cycle mode

#: Bump when the discretisation behind the influence tables changes (mesh sizes, patches,
#: pin table angles): it is part of :meth:`CycleSolver.cache_key`, so old files go unused.
TABLES_VERSION = 1


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

    @cached_property
    def _geometry(self):
        """(candidate contacts per position, MeshingState): kinematics only, no mesh."""
        return _positions(self.model, self.positions_rad)

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
        # windows: the span of each pin's contact parameter over the positions + patch
        windows = {}
        for p in pos:
            for j, s in zip(p.pins, p.psi):
                lo, hi = windows.get(j, (s, s))
                windows[j] = (min(lo, s), max(hi, s))
        pad = 3 * self.b_ref / g.pin_circle_radius_m
        win = [(lo - pad, hi + pad) for lo, hi in windows.values()]
        h = self.b_ref / self.elements_per_bref
        rings, names = _disc_rings(self.model, [_window(g.generating(), lo, hi, h)
                                                for lo, hi in win])
        centres = np.concatenate([p.point for p in pos], axis=1)
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
            for p_idx, p in enumerate(pos):
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

    def influence(self, p: int):
        """(C, C) disc compliance at position p's candidates (patch b_ref), per unit length;
        computed with every position not yet known in one block solve, and kept (a new
        torque costs no new solve)."""
        if p in self._influence:
            return self._influence[p]
        pos, state, disc, housing = self._setup
        todo = [k for k in range(len(pos)) if k not in self._influence]
        sizes = [pos[k].pins.size for k in todo]
        loads = patch_loads(disc, "profile", np.concatenate([pos[k].point for k in todo], 1),
                            np.concatenate([pos[k].normal for k in todo], 1), self.b_ref)
        blocks = disc.flexibility(loads, sizes)
        if self.model.pin_structure == "integral":
            lh = patch_loads(housing, "teeth",
                             np.concatenate([state.point[k, pos[k].pins].T for k in todo], 1),
                             np.concatenate([state.normal[k, pos[k].pins].T for k in todo], 1),
                             self.b_ref / 2)
            blocks = [c + ch for c, ch in zip(blocks, housing.flexibility(lh, sizes))]
        self._influence.update(zip(todo, blocks))
        return self._influence[p]

    def cache_key(self) -> str:
        """Hash of what the influence tables depend on: geometry, holes, material, pin
        structure, plane, positions, b_ref and mesh density. Not the torque, and not the
        face width (the tables are per unit length)."""
        m = self.model
        return content_key("CycleSolver", TABLES_VERSION, m.geometry, m.holes,
                           m.youngs_modulus, m.poisson_ratio, m.pin_structure, m.plane,
                           m.housing_outer_radius if m.pin_structure == "integral" else None,
                           np.asarray(self.positions_rad, float), self.b_ref,
                           self.elements_per_bref)

    def tables(self) -> dict:
        """The torque-independent arrays of the solve: ``influence_<p>`` (C_p, C_p) for
        every position and, for conventional pins, ``pin_table``. Taken from ``cache``
        when it holds them (no mesh, no factorisation), else computed and stored there."""
        if self.equal_springs is not None:
            raise ToothfemError("the equal-springs limit has no influence tables")
        n = len(self._geometry[0])
        if self.cache is not None and len(self._influence) < n:
            hit = self.cache.load(self.cache_key())
            if hit is not None:
                try:
                    self.adopt(hit)
                except ToothfemError:      # stale or foreign file: recompute, overwrite
                    self._influence.clear()
        computed = len(self._influence) < n or (self._pin is not None
                                                and "table" not in vars(self._pin))
        out = {f"influence_{p}": self.influence(p) for p in range(n)}
        if self._pin is not None:
            out["pin_table"] = self._pin.table
        if computed and self.cache is not None:
            self.cache.store(self.cache_key(), out)
        return out

    def adopt(self, tables) -> None:
        """Use ``tables`` (as returned by :meth:`tables`, e.g. from another process) instead
        of computing them; refused (ToothfemError) if they do not fit these positions."""
        pos = self._geometry[0]
        for p, q in enumerate(pos):
            c = np.asarray(tables.get(f"influence_{p}", np.empty(0)), float)
            if c.shape != (q.pins.size, q.pins.size) or not np.all(np.isfinite(c)):
                raise ToothfemError(f"influence table of position {p} does not fit: shape "
                                    f"{c.shape}, expected {(q.pins.size, q.pins.size)}")
        if len(tables) != len(pos) + (self._pin is not None):
            raise ToothfemError(f"{len(tables)} tables for {len(pos)} positions")
        if self._pin is not None:
            t = np.asarray(tables.get("pin_table", np.empty(0)), float)
            if t.shape != self._pin.angles.shape:
                raise ToothfemError(f"pin table shape {t.shape} does not fit "
                                    f"{self._pin.angles.shape}")
            self._pin.table = t          # fills the cached_property
        for p in range(len(pos)):
            self._influence[p] = np.asarray(tables[f"influence_{p}"], float)

    def disc_field(self, p: int, load_sharing: LoadSharing):
        """(disc Body, displacement dofs) at position p under the solved contact forces
        (Hertz strips of b_ref pressing along the inward normal), disc frame."""
        pos, _, disc, _ = self._setup
        q = pos[p]
        f = load_sharing.force[p, q.pins] / self.model.face_width
        loads = patch_loads(disc, "profile", q.point, -q.normal, self.b_ref)
        return disc, disc.solve(loads @ f)

    def solve(self, torque: float, progress=None) -> LoadSharing:
        """Load sharing at every position for the disc torque (N m)."""
        check_range("torque", torque, 0, None, lo_open=True)
        if self.cache is not None and self.equal_springs is None:
            self.tables()
        (pos, state), pin = self._geometry, self._pin
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
                sol = self._solve_position(p, q, q_load, pin)
            force[p, q.pins] = sol.force * m.face_width
            gap[p, q.pins] = sol.gap
            beta[p] = sol.rigid
        return _record("cycle", m, state, force, gap, beta, torque)

    def _solve_position(self, p, q, q_load, pin):
        """Complementarity at one position, iterated on the Hertz half-widths b(F)."""
        m = self.model
        e_p = m.e_plane
        c_disc = self.influence(p)
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


def strip_width_correction(b, b_ref, e_plane):
    """Compliance change (m per N/m) of a half-space loaded by a Hertzian strip of
    half-width b instead of b_ref: -(2/(pi E')) ln(b/b_ref) (docs/derivations.md, 6)."""
    return -(2 / (math.pi * e_plane)) * np.log(np.asarray(b) / b_ref)


def _seed_guess(q: _Position, q_load):
    w = np.where(q.arm < 0, -q.arm, 0.0)
    return w * q_load / np.sum(w * -q.arm)


def _half_width(lam, r_eq, e_star, q_load, arm):
    """Hertz half-width per candidate; unloaded ones get the width of a mean load."""
    mean = q_load / np.sum(np.abs(arm[arm < 0])) if np.any(arm < 0) else q_load
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


# ---------------------------------------------------------------------------------------
# Detailed mode

#: Slave zone half-width per estimated Hertz half-width (the contact must end inside it),
#: and the safety factor on the seed's force when estimating that half-width.
DETAILED_ZONE_REL, DETAILED_FORCE_MARGIN = 1.6, 1.6


@dataclass(frozen=True)
class DetailedResult:
    """One position of the detailed mode: the load sharing plus the pressure profiles."""
    load_sharing: LoadSharing
    slave_points: list          # per candidate pin: (2, M) disc-frame points
    pressure: list              # per candidate pin: (M,) Pa
    pins: np.ndarray            # candidate pin indices
    dofs: int
    disc: object = None         # the disc Body (disc frame)
    disc_displacement: np.ndarray = None


def solve_detailed(model: CycloidFEModel, crank_angle_rad: float, torque: float,
                   elements_per_halfwidth: int = 6) -> DetailedResult:
    """Two-body FE contact at one crank angle with the contact zones refined and conforming.

    The zone sizes come from the seed's force estimate times a margin; after the solve the
    contact must end inside each slave zone (checked; ContactError otherwise).
    """
    check_range("torque", torque, 0, None, lo_open=True)
    if model.pin_structure == "rigid":
        raise ToothfemError("the detailed mode models elastic pins (conventional or integral)")
    g = model.geometry
    gen = g.generating()
    (q,), state = _positions(model, [crank_angle_rad])
    q_load = torque / model.face_width
    f_est = _seed_guess(q, q_load) * DETAILED_FORCE_MARGIN
    b_zone = float(np.max(hertz_line(np.max(f_est), np.abs(q.r_eq), model.e_star)[1]))
    h = b_zone / elements_per_halfwidth
    rz = g.pin_radius_m
    theta_d = -crank_angle_rad / g.lobe_count
    housing_centre = _rotate(-g.eccentricity_m * np.array([math.cos(crank_angle_rad),
                                                           math.sin(crank_angle_rad)]), -theta_d)
    pin_rings, disc_psi, zone_angles = [], [], []
    for k in range(q.pins.size):
        c, n = q.pin_centre[:, k], q.normal[:, k]
        a0 = math.atan2(-n[1], -n[0])                # direction of the contact on the pin
        half = 3 * b_zone / rz
        n_zone = int(math.ceil(2 * half * rz / h))
        t_zone = a0 + np.linspace(-half, half, n_zone + 1)
        t_rest = a0 + np.linspace(half, 2 * math.pi - half, 73)[1:-1]
        t = np.concatenate([t_zone, t_rest])
        ring = c[:, None] + rz * np.stack([np.cos(t), np.sin(t)])
        pin_rings.append(ring)
        zone_angles.append(t_zone)
        psi, _ = cy.foot_point(gen, ring[:, :n_zone + 1], np.full(n_zone + 1, q.psi[k]))
        disc_psi.append(psi)
    # disc outline: coarse samples, with each zone replaced by the pins' projections
    rings, names = _disc_rings(model, disc_psi)
    refine = [Refinement(q.point, h, 2 * b_zone, 60 * b_zone)]
    disc_mesh = mesh_rings(rings, size_max=g.pin_circle_radius_m / 25, refinements=refine,
                           names=names, keep_below=2 * h)
    held = _held_nodes(disc_mesh, [nm for nm in names if nm.startswith("crank")])
    disc = Body(disc_mesh, model.youngs_modulus, model.poisson_ratio, held, model.plane)
    # slave bodies: one per pin (conventional) or the housing with every pin (integral)
    kps = q.pin_centre - rz * q.normal
    refine_pins = [Refinement(kps, h, 2 * b_zone, 40 * b_zone)]
    groups = []                     # (body, [facets of each candidate pin])
    if model.pin_structure == "integral":
        c_t, s_t = math.cos(-theta_d), math.sin(-theta_d)
        centre_h = g.eccentricity_m * np.array([math.cos(crank_angle_rad),
                                                math.sin(crank_angle_rad)])

        def to_disc(x):             # housing frame -> disc frame
            d = x - centre_h[:, None]
            return np.stack([c_t * d[0] - s_t * d[1], s_t * d[0] + c_t * d[1]])
        zones = {int(j): t + theta_d for j, t in zip(q.pins, zone_angles)}
        housing = housing_body(model, zones, refine_pins, 2 * h, to_disc)
        p = housing.mesh.p
        f_all = housing.body_mesh.rings["teeth"]
        mid = 0.5 * (p[:, housing.mesh.facets[0, f_all]] + p[:, housing.mesh.facets[1, f_all]])
        groups.append((housing, [f_all[np.hypot(*(mid - kps[:, k:k + 1]))
                                       < DETAILED_ZONE_REL * b_zone]
                                 for k in range(q.pins.size)]))
    else:
        for k, ring in enumerate(pin_rings):
            c = q.pin_centre[:, k]
            pm = mesh_rings([ring], size_max=rz / 4, refinements=refine_pins, keep_below=2 * h)
            p = pm.mesh.p
            outward = (c - housing_centre) / np.hypot(*(c - housing_centre))
            bnodes = pm.ring_nodes("outer")
            held_pin = bnodes[np.sum((p[:, bnodes] - c[:, None]) * outward[:, None], axis=0) > 0]
            pin = Body(pm, model.youngs_modulus, model.poisson_ratio, held_pin, model.plane)
            f = pm.rings["outer"]
            mid = 0.5 * (p[:, pm.mesh.facets[0, f]] + p[:, pm.mesh.facets[1, f]])
            groups.append((pin, [f[np.hypot(*(mid - kps[:, k:k + 1]))
                                   < DETAILED_ZONE_REL * b_zone]]))
    slaves, h_blocks, master_pts, normals = [], [], [], []
    dofs = disc.basis.N
    k = 0
    for body, facet_sets in groups:
        group_dofs, group_normals = [], []
        for f in facet_sets:
            sl = contact.slave_surface(body, f)
            psi, _ = cy.foot_point(gen, sl.points, np.full(sl.points.shape[1], q.psi[k]))
            nrm = -cy.inward_normal(gen, psi)
            group_dofs.append(sl.dofs)
            group_normals.append(nrm)
            slaves.append(sl)
            master_pts.append(cy.working_profile(gen, psi))
            normals.append(nrm)
            k += 1
        loads = contact.nodal_load_matrix(body.basis.N, np.concatenate(group_dofs, axis=1),
                                          np.concatenate(group_normals, axis=1))
        h_blocks.append(contact.flexibility(body, loads))
        dofs += body.basis.N
    proj = np.concatenate(master_pts, axis=1)
    nrm = np.concatenate(normals, axis=1)
    pts = np.concatenate([s.points for s in slaves], axis=1)
    from scipy.linalg import block_diag

    # evaluate the disc at the polygon point, a hair inside (the element finder needs it)
    on_mesh = contact.nearest_on_boundary(disc_mesh, "profile", proj) - 1e-6 * h * nrm
    hmat = block_diag(*h_blocks) + contact.flexibility(disc, disc.point_load_matrix(on_mesh, nrm))
    g0 = np.sum((pts - proj) * nrm, axis=0)
    c_rot = -(proj[0] * nrm[1] - proj[1] * nrm[0])          # -n . (k x x) = -(x x n)
    sol = contact.solve_contact(hmat, g0, c_rot, q_load)
    u_disc = disc.solve(-(disc.point_load_matrix(on_mesh, nrm) @ sol.force))
    # per pin
    zb = g.pin_count
    force = np.zeros((1, zb))
    gap = np.where(np.isfinite(state.gap), state.gap, np.inf).copy()
    pressures, start = [], 0
    arm_fe = state.moment_arm.copy()
    for k, sl in enumerate(slaves):
        lam = sol.force[start:start + sl.points.shape[1]]
        edge = np.concatenate([np.flatnonzero(lam > 0)])
        if edge.size and np.any(np.hypot(*(sl.points[:, edge] - (q.pin_centre[:, k]
                                - rz * q.normal[:, k])[:, None])) > 0.95 * DETAILED_ZONE_REL * b_zone):
            raise contact.ContactError(f"pin {q.pins[k]}: the contact reaches the edge of the "
                                       "refined zone; raise DETAILED_FORCE_MARGIN")
        force[0, q.pins[k]] = lam.sum() * model.face_width
        if lam.sum() > 0:   # the moment arm of the resultant of the nodal forces
            arm_fe[0, q.pins[k]] = np.sum(lam * c_rot[start:start + lam.size]) / lam.sum()
        gap[0, q.pins[k]] = 0.0 if lam.sum() > 0 else np.min(sol.gap[start:start + lam.size])
        pressures.append(sl.pressure(lam))
        start += lam.size
    rec = _record("detailed", model, state, force, gap, np.array([sol.rigid]), torque)
    # P_h: Hertz's on the FE force where its assumptions hold, the FE peak where they fail
    # (b not small against the radii); the FE profiles stay in DetailedResult.pressure.
    _, _, invalid = hertz_fields(force, model.face_width, state.equivalent_radius,
                                 model.e_star, (state.radius_moving, state.radius_fixed))
    ph = rec.ph.copy()
    for k, pr in enumerate(pressures):
        if invalid[0, q.pins[k]]:
            ph[0, q.pins[k]] = float(np.max(pr))
    import dataclasses

    rec = dataclasses.replace(rec, ph=ph, pressure_from_fe=invalid, moment_arm=arm_fe)
    return DetailedResult(rec, [s.points for s in slaves], pressures, q.pins, dofs, disc, u_disc)
