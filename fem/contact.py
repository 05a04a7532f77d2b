"""Frictionless contact with a rigid-body unknown: the complementarity solver and the
two-body condensation used by the detailed mode.

Formulation (small displacements). Candidate contact points i on the slave surface (body A)
are paired with their projections on the master surface (body B); ``n_i`` is the master's
outward unit normal (from B into A). With contact forces lambda_i >= 0 (on A along +n_i, on
B along -n_i) and one rigid-body unknown r (a rotation or translation of one body) the gaps
are

    g = g0 + H lambda + r c,     H = H_A + H_B  (condensed flexibilities, SPD)

and equilibrium of the rigid unknown reads  sum_i c_i lambda_i + Q = 0, Q being the external
generalised force (torque or force) on that unknown. The contact set is found, not assumed:

    lambda >= 0,  g >= 0,  lambda_i g_i = 0,  c . lambda = -Q

This is the KKT system of min 1/2 l.H.l + g0.l subject to l >= 0, c.l = -Q, with r the
multiplier of the equality. :func:`solve_contact` solves it by a primal-dual active set
(semismooth Newton; Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865), which
terminates in a few iterations for SPD H.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .linsolve import one_blas_thread
from ..errors import ToothfemError

if TYPE_CHECKING:
    from scipy.sparse import csr_matrix


class ContactError(ToothfemError):
    """The contact problem has no solution (e.g. no candidate can carry the load) or did not
    converge."""


@contextlib.contextmanager
def naming_load(load: str):
    """A ContactError raised in the block, restated with the load that caused it.

    Parameters
    ----------
    load : str
        The load in the caller's words ("disc torque 1e+12 N m, position 3").

    Yields
    ------
    None
    """
    try:
        yield
    except ContactError as exc:
        raise ContactError(f"{exc} (at {load})") from None


@dataclass(frozen=True)
class ContactSolution:
    force: np.ndarray       # (n,) lambda, N per unit thickness (or N)
    gap: np.ndarray         # (n,) remaining gap, m
    rigid: float            # r, the rigid-body unknown (rad or m)
    active: np.ndarray      # (n,) bool, in contact
    iterations: int


MAX_ITERATIONS = 200
#: The candidates that touch first under the rigid motion start the active set: those whose
#: gap there is within FIRST_TOUCH_RTOL of the largest initial gap (round-off of the
#: subtraction g0 + r c, a few ulp of the gaps, far below any real clearance) plus
#: FIRST_TOUCH_ATOL [m or rad] for all-zero gaps (unmodified profiles).
FIRST_TOUCH_RTOL, FIRST_TOUCH_ATOL = 1e-9, 1e-15


def solve_contact(h, g0, c, q, *, max_iter: int = MAX_ITERATIONS,
                  active=None) -> ContactSolution:
    """Solve g = g0 + H l + r c >= 0, l >= 0, l.g = 0, c.l = -q for (l, r).

    The dense systems run on one BLAS thread (:func:`fem.linsolve.one_blas_thread`).

    Parameters
    ----------
    h : array_like
        (n, n) SPD flexibility [m per (N/m)].
    g0 : array_like
        (n,) initial gaps [m].
    c : array_like
        (n,) gap change per unit rigid unknown [m per rad, or m per m].
    q : float
        External generalised force on the rigid unknown [N m/m or N/m], nonzero.
    max_iter : int
        Active-set iterations allowed.
    active : array_like of bool or None
        (n,) the set to start from (a nearby problem's solution), else the candidates that
        touch first under the rigid motion.

    Returns
    -------
    ContactSolution
        Forces, gaps, rigid unknown, active set and iteration count.

    Raises
    ------
    ContactError
        When ``q`` is zero, no candidate can balance ``q`` (all c_i of the wrong sign), the
        system is singular or the active set cycles.
    """
    with one_blas_thread():
        if active is not None:
            try:
                return _active_set(h, g0, c, q, max_iter, active)
            except ContactError:        # a start that cycles: from the first touch
                pass
        return _active_set(h, g0, c, q, max_iter)


def _active_set(h, g0, c, q, max_iter, start=None) -> ContactSolution:
    h = np.asarray(h, float)
    g0 = np.asarray(g0, float)
    c = np.asarray(c, float)
    n = g0.size
    if q == 0:
        raise ContactError("the load q is zero: the rigid unknown is not determined")
    able = c * np.sign(-q) > 0          # candidates whose force can balance q
    if not np.any(able):
        raise ContactError("no contact candidate can carry the load: every moment arm "
                           "(or direction) has the wrong sign")
    if start is not None and np.any(np.asarray(start) & able):
        active = np.asarray(start, bool).copy()
    else:       # the candidates that touch first under the rigid motion
        r_first = np.min(-g0[able] / c[able]) if q < 0 else np.max(-g0[able] / c[able])
        active = able & (g0 + r_first * c <= np.max(np.abs(g0)) * FIRST_TOUCH_RTOL
                         + FIRST_TOUCH_ATOL)
    for it in range(1, max_iter + 1):  # noqa: B007 - it is read after the loop (iterations)
        idx = np.flatnonzero(active)
        k = idx.size
        mat = np.zeros((k + 1, k + 1))
        mat[:k, :k] = h[np.ix_(idx, idx)]
        mat[:k, k] = c[idx]
        mat[k, :k] = c[idx]
        rhs = np.concatenate([-g0[idx], [-q]])
        try:
            sol = np.linalg.solve(mat, rhs)
        except np.linalg.LinAlgError:
            raise ContactError("singular contact system (duplicate candidates?)") from None
        lam = np.zeros(n)
        lam[idx] = sol[:k]
        r = sol[k]
        gap = g0 + h @ lam + r * c
        new = np.where(active, lam > 0, gap < 0)
        if np.array_equal(new, active):
            break
        if not np.any(new):
            new = active & (lam >= np.max(lam))
        active = new
    else:
        raise ContactError(f"contact active set did not settle in {max_iter} iterations")
    gap = np.where(active, 0.0, gap)
    return ContactSolution(lam, gap, float(r), active, it)


@dataclass(frozen=True)
class SlaveSurface:
    """The P2 boundary nodes (vertices and edge midpoints) of a body's candidate zone."""
    points: np.ndarray      # (2, M) positions, m
    dofs: np.ndarray        # (2, M) x and y dof indices in the body's basis
    weights: np.ndarray     # (M,) integral of the node's shape function along the surface, m
    adjacency: csr_matrix   # (M, M), 1 between neighbouring nodes along the surface

    def pressure(self, force):
        """Contact pressure at each node from nodal forces (N/m) -> Pa.

        Each node's force over its boundary weight, averaged with half of each neighbour's
        (p_i = (F_i + F_adj/2) / (w_i + w_adj/2)). The plain ratio F_i/w_i alternates
        between vertex and midside nodes by 2-4 % under collocated P2 node-to-surface
        contact (measured on the Hertz cases, docs/fem.md); the patch average removes the
        alternation and biases a resolved Hertz peak by O((h/b)^2).

        Parameters
        ----------
        force : array_like
            (M,) nodal contact forces [N/m].

        Returns
        -------
        numpy.ndarray
            (M,) contact pressure [Pa].
        """
        force = np.asarray(force, float)
        return ((force + 0.5 * (self.adjacency @ force))
                / (self.weights + 0.5 * (self.adjacency @ self.weights)))


def slave_surface(body, facets) -> SlaveSurface:
    """Slave points of ``facets`` with their boundary weights: a P2 shape function
    integrates to h/6 over a facet of length h at each end and 2h/3 at its midpoint.
    Dividing a nodal contact force by this weight gives the pressure (DESIGN: the
    consistent boundary mass would overshoot the peak).

    Parameters
    ----------
    body : Body
        The slave body (fem.elastic).
    facets : array_like
        Boundary facet indices of the candidate zone.

    Returns
    -------
    SlaveSurface
        The zone's P2 nodes (vertices, then edge midpoints) with dofs, weights [m] and
        adjacency.
    """
    mesh, basis = body.mesh, body.basis
    facets = np.asarray(facets)
    ends = mesh.facets[:, facets]
    length = np.hypot(*(mesh.p[:, ends[1]] - mesh.p[:, ends[0]]))
    verts, inv = np.unique(ends, return_inverse=True)
    inv = inv.reshape(ends.shape)
    w_vert = np.zeros(verts.size)
    np.add.at(w_vert, inv[0], length / 6)
    np.add.at(w_vert, inv[1], length / 6)
    mid_pts = 0.5 * (mesh.p[:, ends[0]] + mesh.p[:, ends[1]])
    points = np.concatenate([mesh.p[:, verts], mid_pts], axis=1)
    dofs = np.concatenate([basis.nodal_dofs[:, verts], basis.facet_dofs[:, facets]], axis=1)
    weights = np.concatenate([w_vert, 2 * length / 3])
    from scipy.sparse import coo_matrix

    mids = verts.size + np.arange(facets.size)
    rows = np.concatenate([inv[0], mids, inv[1], mids])
    cols = np.concatenate([mids, inv[0], mids, inv[1]])
    adjacency = coo_matrix((np.ones(rows.size), (rows, cols)),
                           shape=(points.shape[1],) * 2).tocsr()
    return SlaveSurface(points, dofs, weights, adjacency)


@dataclass(frozen=True)
class CondensedPair:
    """A two-body contact condensed onto the slave points."""
    slave: SlaveSurface
    master_points: np.ndarray   # (2, M) projections on the master surface
    normal: np.ndarray          # (2, M) master outward normal (from B into A)
    g0: np.ndarray              # (M,) initial gap
    h: np.ndarray               # (M, M) flexibility H_A + H_B, m per (N/m)
    c: np.ndarray               # (M,) gap change per unit rigid unknown


def nearest_on_boundary(body_mesh, ring: str, points) -> np.ndarray:
    """Nearest point of each of ``points`` (2, M) on the polygonal boundary ``ring`` of a
    mesh. Used to evaluate the master body's field at a projection computed on the exact
    curve, which may sit a chord's sag outside the polygon.

    Only the facets that can hold it are tried: the nearest facet midpoint bounds the
    distance, and a facet lies within half its length of its midpoint (a k-d tree finds
    those within the bound plus the longest half-length); ties go to the lowest facet.

    Parameters
    ----------
    body_mesh : BodyMesh
        The mesh with its named rings (fem.mesh).
    ring : str
        The boundary ring's name.
    points : array_like
        (2, M) points [m].

    Returns
    -------
    numpy.ndarray
        (2, M) nearest boundary points [m].
    """
    from scipy.spatial import cKDTree

    mesh = body_mesh.mesh
    f = body_mesh.rings[ring]
    a = mesh.p[:, mesh.facets[0, f]]
    b = mesh.p[:, mesh.facets[1, f]]
    points = np.asarray(points, float)
    ab = b - a
    ab2 = np.sum(ab * ab, axis=0)
    tree = cKDTree((a + 0.5 * ab).T)
    bound, _ = tree.query(points.T)
    reach = bound + 0.5 * np.sqrt(np.max(ab2))
    out = np.empty_like(points)
    for i, near in enumerate(tree.query_ball_point(points.T, reach * (1 + 1e-9))):
        near = np.sort(near)
        d = points[:, i:i + 1] - a[:, near]
        t = np.clip((ab[0, near] * d[0] + ab[1, near] * d[1]) / ab2[near], 0, 1)
        q = a[:, near] + ab[:, near] * t
        out[:, i] = q[:, np.argmin(np.sum((q - points[:, i:i + 1]) ** 2, axis=0))]
    return out


def nodal_load_matrix(n_dofs: int, dofs, normals):
    """Unit nodal forces along normals at M nodes; the transpose reads a displacement along
    the same normals.

    Parameters
    ----------
    n_dofs : int
        Dofs of the body's basis.
    dofs : array_like
        (2, M) x and y dof indices of the nodes.
    normals : array_like
        (2, M) unit force directions.

    Returns
    -------
    scipy.sparse.csc_matrix
        (n_dofs, M) load vectors, per unit force [-].
    """
    from scipy.sparse import coo_matrix

    dofs = np.asarray(dofs)
    m = dofs.shape[1]
    return coo_matrix((np.concatenate([normals[0], normals[1]]),
                       (np.concatenate([dofs[0], dofs[1]]), np.tile(np.arange(m), 2))),
                      shape=(n_dofs, m)).tocsc()


def condense_pair(body_a, slave: SlaveSurface, body_b, project_b, rigid_a=None, rigid_b=None):
    """Condense body A (slave points) against body B (master surface) onto the slave points.

    Parameters
    ----------
    body_a, body_b : Body
        The slave and master bodies (fem.elastic).
    slave : SlaveSurface
        A's candidate points (:func:`slave_surface`).
    project_b : callable
        points (2, M) [m] -> (projections (2, M) [m], outward normals (2, M)) on B's true
        surface.
    rigid_a, rigid_b : callable or None
        x (2, M) [m] -> displacement (2, M) of the body per unit rigid unknown [m per rad,
        or m per m] (None: the body does not take part in it).

    Returns
    -------
    CondensedPair
        Initial gaps, flexibility H_A + H_B and rigid-unknown column at the slave points.
    """
    proj, n = project_b(slave.points)
    g0 = np.sum((slave.points - proj) * n, axis=0)
    m = g0.size
    loads_a = nodal_load_matrix(body_a.basis.N, slave.dofs, n)
    h = body_a.flexibility(loads_a) + body_b.flexibility(body_b.point_load_matrix(proj, n))
    c = np.zeros(m)
    if rigid_a is not None:
        c += np.sum(n * rigid_a(slave.points), axis=0)
    if rigid_b is not None:
        c -= np.sum(n * rigid_b(proj), axis=0)
    return CondensedPair(slave, proj, n, g0, h, c)
