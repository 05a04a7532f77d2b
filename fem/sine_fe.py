"""Finite-element load sharing of the sine-profile pair (planet inside a fixed ring): cycle
mode and detailed mode.

The pair is nearly conformal: over one tooth pitch several tooth pairs lie within a few um
of each other, and near the pitch point the equivalent radius runs from tens of mm to tens
of m, so the contact widths (0.1-1 mm) are not small against the flank (about 1.6 mm long)
nor against its curvature radii (0.5-50 mm). Hertz's half-space formula fails there; the
pressure must come from a contact surface discretised with many points.

Bodies (plane strain per unit face width, P2 triangles on gmsh meshes, frictionless normal
contact, small displacements):
- planet: the toothed profile (sine paper Eq. 1) around a bore of radius
  ``planet_bore_radius`` held by a rigid coupling whose rotation beta (the unknown of the
  torque balance) is the transmission error; the coupling mirrors the eccentric bearing and
  the output pins, which together hold the planet's centre and its rotation;
- ring: the conjugate profile (the envelope) inside a rim of radius ``ring_outer_radius``,
  clamped there.

Cycle mode (sweeps). Each body's toothed boundary carries a periodic grid of hat functions
(piecewise-linear pressure shape functions of spacing s, uniform in arc length, N per
tooth). The structure of either body is invariant under a turn by one tooth pitch (an
annulus held at a circle, a ring clamped at a circle), so the influence of every hat on
every other follows from the loads on the hats of one tooth: one factorisation and N
back-substitutions per body, on a mesh refined along three teeth (the loaded tooth and its
neighbours, s/2 along the surface; the boundary vertices are the hat nodes). Readouts
within the refined teeth are work-conjugate (the same hat weights), farther ones are point
values (the field is smooth there on the scale s). At each crank angle the contact
unknowns are the planet hats of the candidate teeth whose initial gap to the ring is below
``select_gap``: the gap of each is the exact normal distance of its centre from the ring
profile (geometry.sine), its rigid coefficient its moment arm about the planet centre.
The ring sees the same pressure transported onto its surface, represented on its own hat
grid by linear interpolation (a mortar-like projection: force and first moment kept
exactly). The complementarity problem with the torque balance (fem.contact.solve_contact)
then finds the contact set and the width and shape of each contact patch: the local
approach is the FE's own, no half-space formula is used. Per meshing candidate (a flank
of a planet tooth, as in :func:`toothfem.geometry.sine.meshing`) the force is the sum of
its hats, the moment arm that of the resultant; the half-width and P_h come from Hertz's
formulas on that force where Hertz's assumptions hold and from the FE pressure where they
fail (``pressure_from_fe``). They fail at every contact of the prototype: besides b not
small against the radii near the tips, the separation the elastic approach must close is
g0(x) + beta l(x), and the moment arm l(x) of the normal varies along the curved flank,
so the load's own rotation beta (the TE) curves it 1.7-8.7 times more than 1/R_eq does
(docs/fem_sine.md).

Detailed mode (verification). Both bodies meshed at one crank angle with every contact
zone refined and conforming (the ring's boundary vertices at the projections of the
planet's), the P2 nodal contact forces solved on the two-body system condensed onto the
planet's zone nodes (fem.contact), the same rigid rotation and torque balance.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import ToothfemError, check_range
from ..geometry import sine
from ..geometry.vectors import perp, rotate
from . import contact
from .cache import content_key
from .elastic import Body, SameMaterial
from .load_sharing import LoadSharing, hertz_fields
from .mesh import Refinement, mesh_rings

#: Hat spacing along the surfaces in the cycle mode (m): 1/4 to 1/40 of the contact
#: half-widths met at the prototype's load (0.1-1 mm); the mesh is s/2 along the surface.
DEFAULT_SPACING = 35e-6
#: Planet hats whose initial gap to the ring is below this (m) are contact unknowns; it is
#: doubled (up to SELECT_GAP_MAX) when a hat in contact had an initial gap above
#: SELECT_MARGIN times it, so that the selection never limits the contact set.
DEFAULT_SELECT_GAP, SELECT_GAP_MAX, SELECT_MARGIN = 6e-6, 120e-6, 0.6
#: Mesh away from the refined stretches, per element size e along them (e = s/2 in the
#: cycle mode): boundary segments of COARSE_STEP_REL e on the rest of the toothed boundary
#: (0.15 mm at e = 12.5 um: chord sag <= 6 um at the planet's 0.5 mm tip radius, far from
#: any contact), elements of up to SIZE_MAX_REL e inside (1 mm); so one parameter refines
#: the whole mesh in a convergence study. Circles: CIRCLE_POINTS segments.
COARSE_STEP_REL, SIZE_MAX_REL, CIRCLE_POINTS = 12, 80, 360
#: Hertz's quadratic gap x^2/(2 R_eq) must match the exact loaded separation g0 + beta l
#: at x = +-b (symmetric second difference) within this fraction of it, else the contact
#: is flagged hertz_invalid (the rotation term or a varying curvature dominates).
HERTZ_GAP_RTOL = 0.25
#: Arc-length table points per tooth: cumulative trapezoid, sigma(phi) within 0.12 nm of an
#: adaptive quadrature (4e-8 of the tooth's 3.3 mm), spline inversion phi(sigma(phi)) back
#: to 2e-15 rad (measured on the prototype).
ARC_TABLE_POINTS = 2049


# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SineFEModel(SameMaterial):
    """The sine pair, its material and the two supports (SI units)."""
    pair: sine.SineGearPair
    youngs_modulus: float
    poisson_ratio: float
    planet_bore_radius: float
    ring_outer_radius: float
    plane: str = "strain"
    candidates: int = sine.DEFAULT_CANDIDATES

    def __post_init__(self):
        if not isinstance(self.pair, sine.SineGearPair):
            raise ToothfemError(f"pair = {self.pair!r} is not a SineGearPair")
        check_range("youngs_modulus", self.youngs_modulus, 0, None, lo_open=True)
        check_range("poisson_ratio", self.poisson_ratio, -1, 0.5, lo_open=True, hi_open=True)
        p = self.pair
        root = p.planet_pitch_radius_m - p.tooth_height_m
        check_range("planet_bore_radius", self.planet_bore_radius, 0, 0.95 * root,
                    lo_open=True, why="the bore must lie inside the planet's root circle "
                    "(r1 - a) with a rim of at least 5 % of it")
        phi = np.linspace(-math.pi, math.pi, 65) / p.planet_teeth
        ring_root = float(np.max(np.hypot(*sine.ring_profile(p, phi))))
        check_range("ring_outer_radius", self.ring_outer_radius, 1.05 * ring_root, None,
                    lo_open=True, why="the rim must lie outside the ring's tooth spaces "
                    f"(radius {ring_root:.6g} m) with a rim of at least 5 % of it")
        if isinstance(self.candidates, bool) or int(self.candidates) != self.candidates:
            raise ToothfemError(f"candidates = {self.candidates!r} must be an integer")
        check_range("candidates", self.candidates, 1, (p.planet_teeth - 1) // 4,
                    why="teeth taken on each side of the pitch point")
        if self.plane not in ("strain", "stress"):
            raise ToothfemError(f"plane = {self.plane!r} is not one of ['strain', 'stress']")

    @property
    def face_width(self) -> float:
        return self.pair.face_width_m

    def describe(self) -> dict:
        """The model's supports as a report shows them."""
        return {"planet_bore_radius_mm": self.planet_bore_radius * 1e3,
                "ring_outer_radius_mm": self.ring_outer_radius * 1e3}



#: Ring rim per module outside the ring's pitch circle when the case gives none (the
#: default outline of geometry.sine.ring_polygon); ASSUMPTION, the paper gives no housing.
RING_RIM_MODULES = 5.0


def model_from_pair(pair, material, output_mechanism=None, *,
                    planet_bore_radius_m: float | None = None,
                    ring_outer_radius_m: float | None = None, **kw) -> SineFEModel:
    """The FE model of a sine pair (SI records: :class:`toothfem.si.MaterialSI`,
    :class:`toothfem.si.OutputMechanismSI` or None); ``kw`` are :class:`SineFEModel`'s.

    Defaults (ASSUMPTIONS, the paper gives neither): the planet is held at the inner edge
    of its output-pin holes, R_w - (r_x + a0) (19.75 mm for the prototype; the holes
    themselves are not modelled: a solid web, stiffer than the real one), or at r1/2
    without an output mechanism; the ring is clamped at r2 + 5 m.
    """
    if planet_bore_radius_m is None:
        om = output_mechanism
        if om is not None:
            planet_bore_radius_m = om.pin_hole_circle_radius_m - om.pin_radius_m \
                - pair.centre_distance_m
        else:
            planet_bore_radius_m = 0.5 * pair.planet_pitch_radius_m
    if ring_outer_radius_m is None:
        ring_outer_radius_m = pair.ring_pitch_radius_m + RING_RIM_MODULES * pair.module_m
    return SineFEModel(pair=pair, youngs_modulus=material.youngs_modulus_Pa,
                       poisson_ratio=material.poisson_ratio,
                       planet_bore_radius=float(planet_bore_radius_m),
                       ring_outer_radius=float(ring_outer_radius_m), **kw)


# ---------------------------------------------------------------------------------------
# toothed boundaries: arc length and the periodic hat grid

@dataclass(eq=False)
class _Toothed:
    """A toothed boundary X(phi) of period dphi in phi (one tooth), ``teeth`` teeth round
    the body; tooth d covers phi in [phi0 + d dphi, phi0 + (d+1) dphi) and is tooth 0 turned
    by d * ``turn``. Both profiles run counter-clockwise with phi; ``inward``: +1 if the
    material lies on the left (inside the curve: the planet), -1 on the right (the ring,
    whose profile bounds a hole). ``exterior``: the curve is the body's outer boundary."""
    curve: object            # phi (N,) -> (points (2, N), d1 (2, N))
    dphi: float
    teeth: int
    turn: float
    phi0: float
    inward: int

    @property
    def exterior(self) -> bool:
        return self.inward > 0

    @cached_property
    def _table(self):
        from scipy.integrate import cumulative_trapezoid
        from scipy.interpolate import CubicSpline

        phi = self.phi0 + np.linspace(0, self.dphi, ARC_TABLE_POINTS)
        speed = np.hypot(*self.curve(phi)[1])
        sigma = cumulative_trapezoid(speed, phi, initial=0.0)
        return CubicSpline(sigma, phi), CubicSpline(phi, sigma), float(sigma[-1])

    @property
    def length(self) -> float:
        """Arc length of one tooth (m)."""
        return self._table[2]

    def phi_of_sigma(self, sigma):
        """Curve parameter at arc length sigma from phi0 (any tooth: sigma may exceed a
        tooth's length)."""
        inv, _, length = self._table
        sigma = np.asarray(sigma, float)
        d = np.floor(sigma / length)
        return inv(sigma - d * length) + d * self.dphi

    def sigma_of_phi(self, phi):
        _, fwd, length = self._table
        phi = np.asarray(phi, float)
        d = np.floor((phi - self.phi0) / self.dphi)
        return fwd(phi - d * self.dphi) + d * length

    def point(self, sigma):
        return self.curve(self.phi_of_sigma(sigma))[0]

    def inward_normal(self, sigma):
        """Unit normal into the material at arc length sigma."""
        d1 = self.curve(self.phi_of_sigma(sigma))[1]
        return self.inward * perp(d1) / np.hypot(*d1)


def _planet_toothed(pair) -> _Toothed:
    def curve(phi):
        c = sine.planet_curve(pair, phi)
        return c.point, c.d1
    z1 = pair.planet_teeth
    return _Toothed(curve, 2 * math.pi / z1, z1, 2 * math.pi / z1, -math.pi / z1, +1)


def _ring_toothed(pair) -> _Toothed:
    def curve(phi):
        c = sine.ring_curve(pair, phi)
        return c.point, c.d1
    z1, z2 = pair.planet_teeth, pair.ring_teeth
    return _Toothed(curve, 2 * math.pi / z1, z2, 2 * math.pi / z2, -math.pi / z1, -1)


def ring_foot(pair, points):
    """(ring parameter phi2, signed normal gap, unit ring normal into the free space (2, N))
    of ring-frame points (2, N): the foot of the perpendicular on the ring profile."""
    K = np.asarray(points, float)
    f2, _ = sine.foot_point(pair, K)
    c = sine.ring_curve(pair, f2)
    n = perp(c.d1) / np.hypot(*c.d1)
    return f2, np.sum((K - c.point) * n, axis=0), n


# ---------------------------------------------------------------------------------------
# one body with its periodic hat grid and influence table

@dataclass(eq=False)
class _GridBody:
    """A body whose toothed boundary carries a hat grid of N hats per tooth, spacing
    s = length/N; hat k of tooth d is centred at arc length (d N + k) s.

    ``influence[d + D][i, j]``: approach (m, along the inward normal, hat-weighted) at hat
    j of tooth d per unit force (N/m) spread as hat i of tooth 0 (pressure hat_i / s)."""
    body: Body | None          # None when the tables came from the disk cache
    toothed: _Toothed
    n_hats: int
    influence: np.ndarray     # (2D+1, N, N)
    reach: int                # D

    @property
    def spacing(self) -> float:
        return self.toothed.length / self.n_hats

    def matrix(self, idx_a, idx_b=None):
        """Compliance between global hat indices (tooth * N + k), (len(a), len(b))."""
        idx_b = idx_a if idx_b is None else idx_b
        n = self.n_hats
        da, ka = np.divmod(np.asarray(idx_a), n)
        db, kb = np.divmod(np.asarray(idx_b), n)
        dd = db[None, :] - da[:, None]
        if np.any(np.abs(dd) > self.reach):
            raise ToothfemError("contact hats farther apart than the influence table reaches")
        return self.influence[dd + self.reach, ka[:, None], kb[None, :]]


def _outline(toothed: _Toothed, inserts, coarse_step: float):
    """Closed outline of the toothed boundary (2, M): samples about ``coarse_step`` (m)
    apart, with each array of parameters in ``inserts`` (a refined stretch, ascending) put
    in place of the samples it covers (half a step of margin: no sliver segment)."""
    span = toothed.dphi * toothed.teeth
    per_tooth = max(int(math.ceil(toothed.length / coarse_step)), 8)
    coarse = toothed.phi0 + np.linspace(0, span, toothed.teeth * per_tooth, endpoint=False)
    step = toothed.dphi / per_tooth
    keep = np.ones(coarse.size, bool)
    for ins in inserts:
        lo, hi = ins[0] - 0.5 * step, ins[-1] + 0.5 * step
        keep &= np.mod(coarse - lo, span) > hi - lo
    phi = np.concatenate([coarse[keep]] + list(inserts))
    # order along the boundary from a point away from every insert
    ref = np.mean(np.concatenate(list(inserts))) + 0.5 * span if inserts else toothed.phi0
    phi = phi[np.argsort(np.mod(phi - ref, span))]
    return toothed.curve(phi)[0]


def _circle(radius, n=CIRCLE_POINTS):
    t = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return radius * np.stack([np.cos(t), np.sin(t)])


def _boundary_chain(body_mesh, ring: str, pts):
    """Mesh vertex of each of ``pts`` (2, M, consecutive along the boundary) and the facet
    between each consecutive pair (M-1,)."""
    from scipy.spatial import cKDTree

    mesh = body_mesh.mesh
    nodes = body_mesh.ring_nodes(ring)
    dist, k = cKDTree(mesh.p[:, nodes].T).query(pts.T)
    scale = np.max(np.hypot(*np.diff(pts, axis=1)))
    if np.max(dist) > 1e-6 * scale:
        raise ToothfemError("the mesh did not keep the refined boundary vertices")
    verts = nodes[k]
    f = body_mesh.rings[ring]
    lookup = {tuple(sorted(e)): i for e, i in zip(mesh.facets[:, f].T, f)}
    try:
        facets = np.array([lookup[tuple(sorted(e))] for e in zip(verts[:-1], verts[1:])])
    except KeyError:
        raise ToothfemError("a refined boundary segment was split by the mesher") from None
    return verts, facets


def _hat_loads(body: Body, verts, facets, inward: int, n_hats: int):
    """(N_dofs, n_hats) load vectors of unit-amplitude hats on a chain of boundary
    vertices at half the hat spacing, run counter-clockwise: hat h is 1 at vertex 2h + 2,
    1/2 at the two next, 0 at +-2; each presses along the facet's normal into the
    material (``inward`` as in :class:`_Toothed`). P2 edge functions integrate a linear
    (a, b) over a facet of length L to a L/6 and b L/6 at its ends and (a + b) L/3 at its
    midside (exact)."""
    from scipy.sparse import coo_matrix

    mesh, basis = body.mesh, body.basis
    seg = mesh.p[:, verts[1:]] - mesh.p[:, verts[:-1]]
    length = np.hypot(*seg)
    normal = inward * perp(seg) / length
    h = np.repeat(np.arange(n_hats), 4)
    f = 2 * h + 2 + np.tile([-2, -1, 0, 1], n_hats)       # facet f joins vertex f and f+1
    a = np.tile([0.0, 0.5, 1.0, 0.5], n_hats)
    b = np.tile([0.5, 1.0, 0.5, 0.0], n_hats)
    ln = length[f]
    rows, cols, vals = [], [], []
    for dofs, w in ((basis.nodal_dofs[:, verts[f]], a * ln / 6),
                    (basis.nodal_dofs[:, verts[f + 1]], b * ln / 6),
                    (basis.facet_dofs[:, facets[f]], (a + b) * ln / 3)):
        for comp in (0, 1):
            rows.append(dofs[comp])
            cols.append(h)
            vals.append(w * normal[comp, f])
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(basis.N, n_hats)).tocsc()


def _grid_body(toothed: _Toothed, other_rings, names, held: str, spacing: float,
               model: SineFEModel, reach: int) -> _GridBody:
    """Mesh a body refined along teeth -1, 0, 1, factorise it once and tabulate the hat
    influence of tooth 0 on teeth -reach..reach."""
    n = max(int(round(toothed.length / spacing)), 8)
    s = toothed.length / n
    # fine vertices at s/2 over teeth -1..1 and one hat spacing beyond (hat supports)
    sig = -toothed.length - s + 0.5 * s * np.arange(6 * n + 5)
    fine_phi = toothed.phi_of_sigma(sig)
    fine = toothed.curve(fine_phi)[0]
    outline = _outline(toothed, [fine_phi], COARSE_STEP_REL * 0.5 * s)
    rings = [outline] + list(other_rings) if toothed.exterior else list(other_rings) + [outline]
    bm = mesh_rings(rings, size_max=SIZE_MAX_REL * 0.5 * s,
                    refinements=[Refinement(fine, 0.5 * s, s, 40 * s)],
                    names=names, keep_below=0.75 * s)
    body = Body(bm, model.youngs_modulus, model.poisson_ratio, bm.ring_nodes(held),
                model.plane)
    verts, facets = _boundary_chain(bm, "profile", fine)
    # hats of teeth -1, 0, 1: centres at fine vertices 2, 4, ..., 6n
    loads = _hat_loads(body, verts, facets, toothed.inward, 3 * n)
    u = body.solve(loads[:, n:2 * n].toarray())
    table = np.empty((2 * reach + 1, n, n))
    near = (loads.T @ u) / s**2                           # (3n, n): readouts, loads
    for d in (-1, 0, 1):
        table[d + reach] = near[(d + 1) * n:(d + 2) * n].T
    k = np.arange(n)
    for d in range(-reach, reach + 1):
        if abs(d) <= 1:
            continue
        sg = (d * n + k) * s
        pts = toothed.point(sg)
        nrm = toothed.inward_normal(sg)
        pts = contact.nearest_on_boundary(bm, "profile", pts) + 1e-3 * s * nrm
        probe = body.point_load_matrix(pts, nrm)        # (N_dofs, n): reads u . n
        table[d + reach] = (probe.T @ u).T / s           # point value ~ hat average
    return _GridBody(body, toothed, n, table, reach)


# ---------------------------------------------------------------------------------------
# Cycle mode

@dataclass(frozen=True)
class PositionResult:
    """One crank angle of the cycle mode: the contact hats and their solution.

    ``hat``: global planet hat indices (tooth * N + k) of the contact unknowns (H,);
    ``point`` (2, H) ring frame; ``force`` (H,) N/m; ``pressure`` (H,) Pa (force over the
    hat's integral s); ``column`` (H,) the meshing candidate each hat belongs to (-1: none);
    ``sigma`` (H,) arc length along the planet profile (m)."""
    crank_angle: float
    hat: np.ndarray
    point: np.ndarray
    sigma: np.ndarray
    g0: np.ndarray
    arm: np.ndarray
    force: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    column: np.ndarray
    rotation: float
    iterations: int
    select_gap: float
    hat_moment: float = 0.0     # second moment of one hat about its centre / its area, m^2


#: Bump when the discretisation behind the hat tables changes (part of the cache key).
TABLES_VERSION = 1


@dataclass(eq=False)
class CycleSolver:
    """Influence coefficients of both bodies on their hat grids from one factorisation
    each; contact at any crank angle from those tables (module docstring).

    ``cache`` (a :class:`toothfem.fem.cache.DiskCache`, or None) keeps each body's hat table
    on disk under a key of what it depends on (pair, material, supports, plane, spacing,
    reach; not the torque): a solver for a known design meshes and factorises nothing."""
    model: SineFEModel
    positions_rad: np.ndarray
    spacing: float = DEFAULT_SPACING
    select_gap: float = DEFAULT_SELECT_GAP
    cache: object = None

    def __post_init__(self):
        self.positions_rad = np.atleast_1d(np.asarray(self.positions_rad, float))
        for x in self.positions_rad:
            check_range("positions_rad", x)
        m = self.model.pair.module_m
        check_range("spacing", self.spacing, 0.002 * m, 0.2 * m, why="hat spacing along the "
                    "surfaces: 1/500 to 1/5 of the module")
        check_range("select_gap", self.select_gap, 0, SELECT_GAP_MAX, lo_open=True)

    #: the hat grids give no stress field of their own (the detailed mode does).
    has_structural_field = False

    def prepare(self) -> None:
        """Build (or read from the cache) both bodies' hat tables now."""
        self.planet, self.ring

    @property
    def reach(self) -> int:
        """Teeth between any two contact hats, at most (candidates on both sides, the ring
        tooth a hat projects onto, one for the shift of the pitch point)."""
        return 2 * self.model.candidates + 3

    @cached_property
    def planet(self) -> _GridBody:
        m = self.model
        return self._cached("planet", _planet_toothed(m.pair),
                            lambda t: _grid_body(t, [_circle(m.planet_bore_radius)],
                                                 ["profile", "bore"], "bore", self.spacing, m,
                                                 self.reach))

    @cached_property
    def ring(self) -> _GridBody:
        m = self.model
        return self._cached("ring", _ring_toothed(m.pair),
                            lambda t: _grid_body(t, [_circle(m.ring_outer_radius)],
                                                 ["rim", "profile"], "rim", self.spacing, m,
                                                 self.reach))

    def cache_key(self, which: str) -> str:
        """Hash of what a body's hat table depends on (not the torque, not the face
        width: the tables are per unit length)."""
        m = self.model
        pair = dataclasses.replace(m.pair, face_width_m=1.0)     # per unit length
        support = m.planet_bore_radius if which == "planet" else m.ring_outer_radius
        return content_key("SineCycleSolver", TABLES_VERSION, which, pair, m.youngs_modulus,
                           m.poisson_ratio, support, m.plane, self.spacing, self.reach)

    def _cached(self, which, toothed, build) -> _GridBody:
        if self.cache is None:
            return build(toothed)
        key = self.cache_key(which)
        hit = self.cache.load(key)
        if hit is not None and "influence" in hit:
            table = np.asarray(hit["influence"], float)
            n = table.shape[1] if table.ndim == 3 else 0
            if table.shape == (2 * self.reach + 1, n, n) and n >= 8 \
                    and np.all(np.isfinite(table)):
                return _GridBody(None, toothed, n, table, self.reach)
        grid = build(toothed)                   # missing, stale or corrupt: compute, store
        self.cache.store(key, {"influence": grid.influence})
        return grid

    @cached_property
    def states(self):
        return sine.meshing(self.model.pair, self.positions_rad,
                            candidates=self.model.candidates)

    def solve_position(self, chi: float, torque: float) -> PositionResult:
        """Contact at crank angle ``chi`` (rad) under the planet torque (N m)."""
        check_range("torque", torque, 0, None, lo_open=True)
        check_range("chi", chi)
        sel_gap = self.select_gap
        while True:
            res = self._solve(float(chi), torque / self.model.face_width, sel_gap)
            loaded = res.force > 0
            # the contact stays inside the selection, and no hat left out (initial gap
            # above sel_gap) can be closed by the rigid rotation
            if (np.max(res.g0[loaded]) <= SELECT_MARGIN * sel_gap
                    and res.rotation * np.max(np.abs(res.arm)) <= sel_gap):
                return res
            if 2 * sel_gap > SELECT_GAP_MAX:
                raise contact.ContactError(
                    f"crank angle {math.degrees(chi):.4f} deg: contact reaches hats with an "
                    f"initial gap of {np.max(res.g0[loaded]) * 1e6:.1f} um; the load is too "
                    "high for the candidate teeth (raise candidates)")
            sel_gap *= 2

    def _solve(self, chi, q_load, sel_gap) -> PositionResult:
        pair = self.model.pair
        pl, rg = self.planet, self.ring
        n, s = pl.n_hats, pl.spacing
        k = self.model.candidates
        j0 = int(np.round(chi * pair.ring_teeth / (2 * math.pi)))
        hats = (j0 - k) * n + np.arange((2 * k + 1) * n)
        sigma = hats * s
        centre, theta = sine.planet_pose(pair, chi)
        pts = rotate(pl.toothed.point(sigma), theta[0]) + centre
        f2, g0, nrm = ring_foot(pair, pts)
        sel = g0 < sel_gap
        if not np.any(sel):
            raise contact.ContactError(f"crank angle {math.degrees(chi):.4f} deg: no planet "
                                       "hat within the selection gap")
        hats, sigma, pts, f2, g0, nrm = (hats[sel], sigma[sel], pts[:, sel], f2[sel], g0[sel],
                                         nrm[:, sel])
        rel = pts - centre
        arm = rel[0] * nrm[1] - rel[1] * nrm[0]
        # ring: the transported hats on the ring grid by linear interpolation, T^T H_r T
        # with two weights per hat (1 - a on ring hat j, a on j + 1)
        u = rg.toothed.sigma_of_phi(f2) / rg.spacing
        j = np.floor(u).astype(int)
        a = u - j
        hmat = pl.matrix(hats)
        for wa, ja in ((1 - a, j), (a, j + 1)):
            for wb, jb in ((1 - a, j), (a, j + 1)):
                hmat += wa[:, None] * wb[None, :] * rg.matrix(ja, jb)
        hmat = 0.5 * (hmat + hmat.T)
        sol = contact.solve_contact(hmat, g0, arm, q_load)
        column = self._columns(chi, hats)
        return PositionResult(chi, hats, pts, sigma, g0, arm, sol.force, sol.force / s,
                              sol.gap, column, sol.rigid, sol.iterations, sel_gap, s**2 / 6)

    def _columns(self, chi, hats):
        j0 = int(np.round(chi * self.model.pair.ring_teeth / (2 * math.pi)))
        tooth, cell = np.divmod(hats, self.planet.n_hats)
        return _flank_columns(j0, self.model.candidates, tooth, cell >= self.planet.n_hats / 2)

    def solve(self, torque: float, progress=None) -> LoadSharing:
        """Load sharing at every position for the planet torque (N m)."""
        check_range("torque", torque, 0, None, lo_open=True)
        it = range(self.positions_rad.size)
        if progress is not None:
            it = progress(it)
        results = [self.solve_position(self.positions_rad[p], torque) for p in it]
        return _record("cycle", self.model, self.states, results, torque, self.planet.toothed)


def _flank_columns(j0, k, tooth, upper):
    """Column of sine.meshing (tooth j0-k+i, flank -1/+1 -> 2i, 2i+1) of points on planet
    tooth ``tooth`` (its window from root to root), on flank +1 where ``upper`` (beyond the
    tip). A loaded zone is not always around a flank's own gap minimum: the profiles are
    so nearly conformal that a flank whose gap falls all the way to the neighbouring
    flank's conjugate contact (meshing gap inf) carries load too."""
    return 2 * (np.asarray(tooth) - (j0 - k)) + np.asarray(upper).astype(int)


def _record(method, model: SineFEModel, state, results, torque, toothed) -> LoadSharing:
    """Stack per-position contact solutions into a LoadSharing over the meshing columns.

    Per loaded column: the force is the sum of its nodal or hat forces, the moment arm and
    point those of the resultant; the curvature radii are taken at the resultant's point
    (a column without a gap minimum of its own has its meshing point at a flank end).
    P_h and b: Hertz's on the force where Hertz holds, else the FE peak and the
    second-moment half-width b^2 = 4 int x^2 p / int p (``pressure_from_fe``). The gap of
    a column with no contact unknown is its initial gap closed by the rigid rotation only
    (beta l; the elastic part is left out)."""
    pair, width = model.pair, model.face_width
    n_pos, n_col = state.moment_arm.shape
    force = np.zeros((n_pos, n_col))
    arm = state.moment_arm.copy()
    point = state.point.copy()
    r_p, r_r = state.radius_moving.copy(), state.radius_fixed.copy()
    gap = np.where(np.isfinite(state.gap), state.gap, np.inf)
    beta = np.array([r.rotation for r in results])
    fe_peak = np.zeros((n_pos, n_col))
    fe_b = np.zeros((n_pos, n_col))
    sig_c = np.full((n_pos, n_col), np.nan)
    untouched = np.ones((n_pos, n_col), bool)
    for p, r in enumerate(results):
        if np.any((r.column < 0) | (r.column >= n_col)):
            raise ToothfemError("a contact hat lies outside the candidate teeth")
        if np.any(r.force[(r.column < 2) | (r.column >= n_col - 2)] > 0):
            raise contact.ContactError(
                f"crank angle {math.degrees(r.crank_angle):.4f} deg: the outermost candidate "
                "teeth carry load; raise SineFEModel.candidates")
        for c in np.unique(r.column):
            k = r.column == c
            lam = r.force[k]
            untouched[p, c] = False
            tot = lam.sum()
            if tot <= 0:
                gap[p, c] = np.min(r.gap[k])
                continue
            force[p, c] = tot * width
            arm[p, c] = np.sum(lam * r.arm[k]) / tot
            point[p, c] = (r.point[:, k] @ lam) / tot
            sc = np.sum(lam * r.sigma[k]) / tot
            sig_c[p, c] = sc
            fe_peak[p, c] = np.max(r.pressure[k])
            fe_b[p, c] = 2 * math.sqrt(np.sum(lam * (r.sigma[k] - sc) ** 2) / tot
                                       + r.hat_moment)
            gap[p, c] = 0.0
        gap[p, untouched[p]] = gap[p, untouched[p]] + beta[p] * arm[p, untouched[p]]
    loaded = force > 0
    if np.any(loaded):
        phi1 = toothed.phi_of_sigma(sig_c[loaded])
        r_p[loaded] = 1 / sine.planet_curve(pair, phi1).curvature
        f2, _, _ = ring_foot(pair, point[loaded].T)
        r_r[loaded] = 1 / sine.ring_curve(pair, f2).curvature
    with np.errstate(divide="ignore", invalid="ignore"):
        r_eq = 1 / (1 / r_p + 1 / r_r)
    b, ph, invalid = hertz_fields(force, width, r_eq, model.e_star, (r_p, r_r))
    if np.any(loaded & ~invalid):
        sel = loaded & ~invalid
        invalid[sel] = _hertz_gap_fails(model, toothed, state.position_rad, beta, sel, sig_c,
                                        b, r_eq)
    from_fe = loaded & invalid
    b = np.where(from_fe, fe_b, b)
    ph = np.where(from_fe, fe_peak, ph)
    return LoadSharing(
        method=method, position_rad=state.position_rad, contact_id=state.contact_id,
        force=force, point=point, moment_arm=arm, half_width=b, ph=ph, gap=gap,
        transmission_error=beta, torque=float(torque), face_width=width,
        pressure_from_fe=from_fe, equivalent_radius=r_eq, hertz_invalid=invalid)


def _hertz_gap_fails(model, toothed, positions, beta, sel, sig_c, b, r_eq):
    """Hertz's quadratic gap against the exact loaded one. The separation that the elastic
    approach must close is g0(x) + beta l(x): the initial gap plus the planet's rigid
    rotation beta times the moment arm l(x) of the normal at x, which varies along a
    curved flank (its second derivative is not small against 1/R_eq for these nearly
    conformal profiles). The symmetric second difference of that separation over +-b about
    the resultant, s(x+b) + s(x-b) - 2 s(x), must be b^2/R_eq within HERTZ_GAP_RTOL (a
    linear part, a tilt, cancels)."""
    pair = model.pair
    pp, cc = np.nonzero(sel)
    out = np.zeros(pp.size, bool)
    for i, (p, c) in enumerate(zip(pp, cc)):
        centre, theta = sine.planet_pose(pair, positions[p])
        sg = sig_c[p, c] + b[p, c] * np.array([-1.0, 0.0, 1.0])
        pts = rotate(toothed.point(sg), theta[0]) + centre
        _, g, n = ring_foot(pair, pts)
        rel = pts - centre
        sep = g + beta[p] * (rel[0] * n[1] - rel[1] * n[0])
        second = sep[0] + sep[2] - 2 * sep[1]
        hertz = b[p, c] ** 2 / r_eq[p, c]
        out[i] = abs(second - hertz) > HERTZ_GAP_RTOL * hertz
    return out


# ---------------------------------------------------------------------------------------
# Detailed mode

#: Element size along the contact zones (m): 7 elements over the half-width of the
#: lightest loaded contacts of the prototype (0.1 mm), 20-30 over the others.
DETAILED_ELEMENT = 15e-6
#: Contact zones: the loaded side (moment arm < 0) of the candidate teeth where the initial
#: gap is below this (m); doubled (up to SELECT_GAP_MAX) when the contact reaches nodes of
#: initial gap above SELECT_MARGIN of it or the surfaces overlap outside the zones.
DETAILED_ZONE_GAP = 3.5e-6
#: Spacing (m) of the points outside the zones where the loaded gap is checked, and the
#: overlap (fraction of the largest rigid approach beta |l|) that counts as a miss.
CHECK_SPACING, CHECK_OVERLAP_REL = 50e-6, 1e-2
#: Samples (element sizes) added at each end of a zone, so that it ends in open gap.
ZONE_PAD = 3


@dataclass(frozen=True)
class DetailedResult:
    """One crank angle of the detailed mode: the load sharing and the nodal solution."""
    load_sharing: LoadSharing
    nodes: PositionResult       # slave nodes: points, forces, pressures (patch-averaged)
    dofs: int
    planet: Body                # planet frame (centre at the origin, unturned)
    planet_displacement: np.ndarray
    ring: Body                  # ring frame
    ring_displacement: np.ndarray
    zone_gap: float
    min_gap_outside: float      # m, loaded gap at the check points outside the zones

    @property
    def member_body(self):
        """The moving member's Body (the planet), as every drive's detailed result names it."""
        return self.planet

    @property
    def member_displacement(self):
        return self.planet_displacement


def solve_detailed(model: SineFEModel, crank_angle_rad: float, torque: float,
                   element_size: float = DETAILED_ELEMENT,
                   zone_gap: float = DETAILED_ZONE_GAP) -> DetailedResult:
    """Two-body FE contact at one crank angle with every contact zone refined (element size
    ``element_size``) and conforming; the zones are found from the geometry (module
    constants) and grown until the contact lies inside them."""
    check_range("crank_angle_rad", crank_angle_rad)
    check_range("torque", torque, 0, None, lo_open=True)
    m = model.pair.module_m
    check_range("element_size", element_size, 0.002 * m, 0.1 * m,
                why="element size along the contact zones: 1/500 to 1/10 of the module")
    check_range("zone_gap", zone_gap, 0, SELECT_GAP_MAX, lo_open=True)
    while True:
        res = _detailed(model, float(crank_angle_rad), torque, element_size, zone_gap)
        nodes = res.nodes
        loaded = nodes.force > 0
        rigid = res.nodes.rotation * np.max(np.abs(nodes.arm))
        if (np.max(nodes.g0[loaded]) <= SELECT_MARGIN * zone_gap
                and res.min_gap_outside >= -CHECK_OVERLAP_REL * rigid):
            return res
        if 2 * zone_gap > SELECT_GAP_MAX:
            raise contact.ContactError(
                f"crank angle {math.degrees(crank_angle_rad):.4f} deg: the contact does not "
                f"stay inside zones of initial gap up to {zone_gap * 1e6:.0f} um")
        zone_gap *= 2


def _runs(mask):
    """(start, stop) index pairs of the runs of True in a 1-D mask."""
    d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def _detailed(model, chi, torque, h, zone_gap) -> DetailedResult:
    pair = model.pair
    pt, rt = _planet_toothed(pair), _ring_toothed(pair)
    k = model.candidates
    j0 = int(np.round(chi * pair.ring_teeth / (2 * math.pi)))
    centre, theta = sine.planet_pose(pair, chi)
    th, centre = float(theta[0]), centre[:, 0]

    def placed(p):                   # planet frame -> ring frame
        return rotate(p, th) + centre[:, None]

    n_tooth = int(math.ceil(pt.length / h))
    step = pt.length / n_tooth
    sig = ((j0 - k) * n_tooth + np.arange((2 * k + 1) * n_tooth)) * step
    kp = placed(pt.point(sig))
    _, g0, nrm = ring_foot(pair, kp)
    rel = kp - centre[:, None]
    arm = rel[0] * nrm[1] - rel[1] * nrm[0]
    zones = []
    for a, b in _runs((g0 < zone_gap) & (arm < 0)):
        a, b = max(a - ZONE_PAD, 0), min(b + ZONE_PAD, sig.size)
        if zones and a <= zones[-1][1]:
            zones[-1] = (zones[-1][0], b)
        else:
            zones.append((a, b))
    if not zones:
        raise contact.ContactError(f"crank angle {math.degrees(chi):.4f} deg: no loaded-side "
                                   f"flank within {zone_gap * 1e6:.1f} um")
    zone_phi = [pt.phi_of_sigma(sig[a:b]) for a, b in zones]
    zone_pts = [pt.curve(ph)[0] for ph in zone_phi]
    ring_phi = [ring_foot(pair, placed(zp))[0] for zp in zone_pts]
    allz = np.concatenate(zone_pts, axis=1)
    size_max, coarse = SIZE_MAX_REL * h, COARSE_STEP_REL * h
    refine = [Refinement(allz, h, 2 * h, 40 * h)]
    pm = mesh_rings([_outline(pt, zone_phi, coarse), _circle(model.planet_bore_radius)], size_max,
                    refine, names=["profile", "bore"], keep_below=1.5 * h)
    planet = Body(pm, model.youngs_modulus, model.poisson_ratio, pm.ring_nodes("bore"),
                  model.plane)
    ring_pts = np.concatenate([rt.curve(f)[0] for f in ring_phi], axis=1)
    rm = mesh_rings([_circle(model.ring_outer_radius), _outline(rt, ring_phi, coarse)], size_max,
                    [Refinement(ring_pts, h, 2 * h, 40 * h)], names=["rim", "profile"],
                    keep_below=1.5 * h)
    ring = Body(rm, model.youngs_modulus, model.poisson_ratio, rm.ring_nodes("rim"),
                model.plane)
    facets = np.concatenate([_boundary_chain(pm, "profile", zp)[1] for zp in zone_pts])
    slave = contact.slave_surface(planet, facets)
    kp = placed(slave.points)
    _, g0, nrm = ring_foot(pair, kp)
    foot = kp - g0 * nrm
    rel = kp - centre[:, None]
    arm = rel[0] * nrm[1] - rel[1] * nrm[0]
    load_p = contact.nodal_load_matrix(planet.basis.N, slave.dofs, rotate(nrm, -th))
    on_ring = contact.nearest_on_boundary(rm, "profile", foot) - 1e-6 * h * nrm
    load_r = ring.point_load_matrix(on_ring, nrm)
    hmat = contact.flexibility(planet, load_p) + contact.flexibility(ring, load_r)
    sol = contact.solve_contact(hmat, g0, arm, torque / model.face_width)
    u_p = planet.solve(load_p @ sol.force)
    u_r = ring.solve(-(load_r @ sol.force))
    # planet parameter of each node (star-shaped profile: the polar angle), its column
    phi = np.arctan2(slave.points[1], slave.points[0])
    ref = j0 * pt.dphi
    phi = ref + np.mod(phi - ref + math.pi, 2 * math.pi) - math.pi
    sigma = pt.sigma_of_phi(phi)
    tooth = np.floor(sigma / pt.length).astype(int)
    column = _flank_columns(j0, k, tooth, sigma - tooth * pt.length >= 0.5 * pt.length)
    nodes = PositionResult(chi, np.arange(slave.points.shape[1]), kp, sigma, g0, arm,
                           sol.force, slave.pressure(sol.force), sol.gap, column, sol.rigid,
                           sol.iterations, zone_gap)
    # loaded gap outside the zones: every CHECK_SPACING on the candidate teeth
    n_chk = int(math.ceil(pt.length / CHECK_SPACING))
    sc = ((j0 - k) * n_chk + np.arange((2 * k + 1) * n_chk)) * (pt.length / n_chk)
    inside = np.zeros(sc.size, bool)
    for a, b in zones:
        inside |= (sc >= sig[a]) & (sc <= sig[b - 1])
    sc = sc[~inside]
    pc = pt.point(sc)
    kc = placed(pc)
    _, gc, nc = ring_foot(pair, kc)
    relc = kc - centre[:, None]
    armc = relc[0] * nc[1] - relc[1] * nc[0]
    pc_in = contact.nearest_on_boundary(pm, "profile", pc) + 1e-3 * h * pt.inward_normal(sc)
    up = planet.point_load_matrix(pc_in, rotate(nc, -th)).T @ u_p
    rc_in = contact.nearest_on_boundary(rm, "profile", kc - gc * nc) - 1e-3 * h * nc
    ur = ring.point_load_matrix(rc_in, nc).T @ u_r
    loaded_gap = gc + sol.rigid * armc + up - ur
    state = sine.meshing(pair, [chi], candidates=k)
    rec = _record("detailed", model, state, [nodes], torque, pt)
    return DetailedResult(rec, nodes, planet.basis.N + ring.basis.N, planet, u_p, ring, u_r,
                          zone_gap, float(np.min(loaded_gap)) if sc.size else np.inf)
