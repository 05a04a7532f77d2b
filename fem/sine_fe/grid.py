"""Toothed boundaries by arc length and each body with its periodic hat grid and influence
table (fem/sine_fe/__init__.py)."""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...errors import ToothfemError
from ...geometry import sine
from ...geometry.vectors import perp
from .. import contact
from ..elastic import Body
from ..mesh import Refinement, mesh_rings
from .model import SineFEModel

#: Arc-length table points per tooth: cumulative trapezoid, sigma(phi) within 0.12 nm of an
#: adaptive quadrature (4e-8 of the tooth's 3.3 mm), spline inversion phi(sigma(phi)) back
#: to 2e-15 rad (measured on the prototype).
ARC_TABLE_POINTS = 2049

#: Mesh away from the refined stretches, per element size e along them (e = s/2 in the
#: cycle mode): boundary segments of COARSE_STEP_REL e on the rest of the toothed boundary
#: (0.15 mm at e = 12.5 um: chord sag <= 6 um at the planet's 0.5 mm tip radius, far from
#: any contact), elements of up to SIZE_MAX_REL e inside (1 mm); so one parameter refines
#: the whole mesh in a convergence study. Circles: CIRCLE_POINTS segments.
COARSE_STEP_REL, SIZE_MAX_REL, CIRCLE_POINTS = 12, 80, 360

# ---------------------------------------------------------------------------------------
# toothed boundaries: arc length and the periodic hat grid

@dataclass(eq=False)
class _Toothed:
    """A toothed boundary X(phi) of period dphi in phi (one tooth), ``teeth`` teeth round
    the body; tooth d covers phi in [phi0 + d dphi, phi0 + (d+1) dphi) and is tooth 0 turned
    by d * ``turn``. Both profiles run counter-clockwise with phi; ``inward``: +1 if the
    material lies on the left (inside the curve: the planet), -1 on the right (the ring,
    whose profile bounds a hole). ``exterior``: the curve is the body's outer boundary."""
    curve: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]   # phi (N,) -> (points, d1) (2, N)
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
    """The foot of the perpendicular from ring-frame points on the ring profile.

    Parameters
    ----------
    pair : toothfem.geometry.sine.SineGearPair
        The pair.
    points : array_like, shape (2, N)
        Points in the ring frame [m].

    Returns
    -------
    phi2 : numpy.ndarray, shape (N,)
        Ring parameter of the foot [rad].
    gap : numpy.ndarray, shape (N,)
        Signed normal gap [m].
    normal : numpy.ndarray, shape (2, N)
        Unit ring normal into the free space.
    """
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
