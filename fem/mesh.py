"""Triangle meshes of 2D bodies with gmsh, read into scikit-fem.

A body is given as closed rings of points (the exterior first, then holes), each ring's
vertices lying exactly on the body's true boundary. gmsh meshes the polygon with a size
field that is fine near the refinement points (the contact zones) and coarse elsewhere. In
a contact zone the ring's vertices are kept as the only boundary nodes (``keep_below``), so
the zone is conforming when the master's vertices sit at the projections of the slave's;
rings are sampled densely there (:func:`refine_ring`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ToothfemError, check_range
from ..signals import handlers_kept

if TYPE_CHECKING:
    from skfem import MeshTri


class MeshError(ToothfemError):
    """The mesh generator failed or was given an impossible size."""


@dataclass(frozen=True)
class Refinement:
    """Mesh size ``size_min`` within ``dist_min`` of ``points`` (2, K), growing linearly to
    ``size_max`` at ``dist_max``."""
    points: np.ndarray
    size_min: float
    dist_min: float
    dist_max: float

    def __post_init__(self):
        check_range("size_min", self.size_min, 0, None, lo_open=True, error=MeshError)
        check_range("dist_max", self.dist_max, self.dist_min, None, lo_open=True,
                    error=MeshError)


@dataclass(frozen=True)
class BodyMesh:
    """A meshed body: the skfem mesh and, per ring name, its boundary facet indices."""
    mesh: MeshTri
    rings: dict = field(default_factory=dict)   # name -> (F,) facet indices

    def ring_nodes(self, name: str) -> np.ndarray:
        """Vertex indices on a ring.

        Parameters
        ----------
        name : str
            A key of :attr:`rings`.

        Returns
        -------
        numpy.ndarray
            The ring's vertex indices, sorted and unique.
        """
        return np.unique(self.mesh.facets[:, self.rings[name]])


def refine_ring(ring: np.ndarray, centres, spacing: float, radius: float, curve=None):
    """Insert vertices so that within ``radius`` of each centre the spacing along the ring is
    at most ``spacing``. With ``curve`` (a function mapping (2, N) points to their exact
    projections on the true boundary) the new vertices are snapped onto it.

    Parameters
    ----------
    ring : numpy.ndarray
        (2, N) closed ring of vertices [m].
    centres : array_like
        (2, K) refinement centres [m].
    spacing : float
        Largest vertex spacing near a centre [m].
    radius : float
        Reach of the refinement around each centre [m].
    curve : callable or None
        (2, N) points -> their exact projections on the true boundary [m].

    Returns
    -------
    numpy.ndarray
        (2, N') the refined ring [m].
    """
    ring = np.asarray(ring, float)
    centres = np.asarray(centres, float).reshape(2, -1)
    a, b = ring, np.roll(ring, -1, axis=1)
    seg = np.hypot(*(b - a))
    mid = 0.5 * (a + b)
    d = np.min(np.hypot(mid[0][:, None] - centres[0][None], mid[1][:, None] - centres[1][None]),
               axis=1)
    n_sub = np.where(d < radius + seg, np.ceil(seg / spacing).astype(int), 1)
    out = []
    for k in range(ring.shape[1]):
        t = np.arange(n_sub[k]) / n_sub[k]
        out.append(a[:, k:k + 1] + (b - a)[:, k:k + 1] * t)
    pts = np.concatenate(out, axis=1)
    if curve is not None:
        pts = curve(pts)
    return pts


#: A ring segment shorter than this fraction of the smallest element size the size field
#: allows on it is a single edge (below 1: gmsh's own rule, a curve whose length in local
#: element sizes is under one, is then met with room for its integration's round-off).
SINGLE_EDGE_REL = 0.99


def _single_edges(ring, size_max, refinements, keep_below):
    """(N,) bool: the segments of ``ring`` (2, N) that are single element edges: shorter
    than ``keep_below``, or shorter than the smallest element size that the size field of
    :func:`mesh_rings` takes anywhere on them (gmsh makes those single edges too; saying so
    spares it their 1D meshing, and the mesh is the same). The size field is gmsh's
    Threshold of each refinement, min'd with ``size_max``: its smallest value on a segment
    is at a distance from the refinement points of at least the midpoint's less half the
    length."""
    from scipy.spatial import cKDTree

    ring = np.asarray(ring, float)
    step = np.roll(ring, -1, axis=1) - ring
    length = np.hypot(*step)
    mid = ring + 0.5 * step
    size = np.full(length.size, float(size_max))
    for ref in refinements:
        d, _ = cKDTree(np.asarray(ref.points, float).reshape(2, -1).T).query(mid.T)
        r = np.clip((np.maximum(d - 0.5 * length, 0.0) - ref.dist_min)
                    / (ref.dist_max - ref.dist_min), 0.0, 1.0)
        size = np.minimum(size, ref.size_min + r * (size_max - ref.size_min))
    single = length < SINGLE_EDGE_REL * size
    return single | (length < keep_below) if keep_below is not None else single


def _initialize_keeping_handlers(gmsh):
    """``gmsh.initialize`` with Python's signal handlers kept. Not interruptible: gmsh
    would set SIGINT to the default action, and may do so only on the main thread; with
    Python's handlers a Ctrl-C or SIGTERM while gmsh meshes raises as soon as the mesher
    returns, and the output folder is cleaned up (issues 14, 27)."""
    with handlers_kept():
        gmsh.initialize(interruptible=False)


def mesh_rings(rings, size_max: float, refinements=(), names=None,
               keep_below: float | None = None) -> BodyMesh:
    """Mesh the region bounded by ``rings`` with gmsh.

    Parameters
    ----------
    rings : sequence of array_like
        (2, N) closed rings [m], the exterior then the holes.
    size_max : float
        Largest element size [m], > 0.
    refinements : sequence of Refinement
        Finer sizes near points (the contact zones).
    names : sequence of str or None
        A name per ring (default "outer", "hole0", ...).
    keep_below : float or None
        Ring segments shorter than this [m] stay single element edges (their end vertices
        are the only boundary nodes there: conforming contact zones); longer ones gmsh
        divides to the size field.

    Returns
    -------
    BodyMesh
        Linear triangles (quadratic fields use ElementTriP2 on it), boundary facets by ring
        name.

    Raises
    ------
    MeshError
        For ``size_max`` <= 0, or when gmsh fails or produces no triangles.
    """
    import gmsh
    from skfem import MeshTri

    check_range("size_max", size_max, 0, None, lo_open=True, error=MeshError)
    names = names or ["outer"] + [f"hole{k}" for k in range(len(rings) - 1)]
    _initialize_keeping_handlers(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("body")
        geo = gmsh.model.geo
        loops, ring_lines = [], []
        for ring in rings:
            ring = np.asarray(ring, float)
            pts = [geo.addPoint(x, y, 0.0) for x, y in ring.T]
            lines = [geo.addLine(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]
            for ln, single in zip(lines, _single_edges(ring, size_max, refinements,
                                                       keep_below)):
                if single:
                    geo.mesh.setTransfiniteCurve(ln, 2)
            loops.append(geo.addCurveLoop(lines))
            ring_lines.append(lines)
        geo.addPlaneSurface(loops)
        geo.synchronize()
        fields = []
        fm = gmsh.model.mesh.field
        for ref in refinements:
            # added and synchronised after the surface: one synchronisation for all was
            # measured to change the integral housing's mesh
            ref_pts = np.asarray(ref.points, float).reshape(2, -1)
            tags = [geo.addPoint(x, y, 0.0) for x, y in ref_pts.T]
            geo.synchronize()
            f_d = fm.add("Distance")
            fm.setNumbers(f_d, "PointsList", tags)
            f_t = fm.add("Threshold")
            fm.setNumber(f_t, "InField", f_d)
            fm.setNumber(f_t, "SizeMin", ref.size_min)
            fm.setNumber(f_t, "SizeMax", size_max)
            fm.setNumber(f_t, "DistMin", ref.dist_min)
            fm.setNumber(f_t, "DistMax", ref.dist_max)
            fields.append(f_t)
        f_c = fm.add("Constant")
        fm.setNumber(f_c, "VIn", size_max)
        fields.append(f_c)
        f_min = fm.add("Min")
        fm.setNumbers(f_min, "FieldsList", fields)
        fm.setAsBackgroundMesh(f_min)
        for opt in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
                    "Mesh.MeshSizeFromCurvature"):
            gmsh.option.setNumber(opt, 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)   # Frontal-Delaunay
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        _, _, enodes = gmsh.model.mesh.getElements(2, -1)
        if not enodes:
            raise MeshError("gmsh produced no triangles (self-intersecting rings?)")
        line_nodes = {}
        for k, (name, lines) in enumerate(zip(names, ring_lines)):
            # one physical group per ring: its nodes in one call, not one call per segment
            group = gmsh.model.addPhysicalGroup(1, lines, k + 1)
            line_nodes[name] = np.unique(gmsh.model.mesh.getNodesForPhysicalGroup(1, group)[0])
    except MeshError:
        raise
    except Exception as exc:  # gmsh raises plain Exceptions
        raise MeshError(f"gmsh failed: {exc}") from None
    finally:
        with handlers_kept():
            gmsh.finalize()
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(tags.size)
    p = xyz.reshape(-1, 3)[:, :2].T.copy()
    t = index[np.asarray(enodes[0], int).reshape(-1, 3).T]
    used = np.unique(t)
    remap = np.full(p.shape[1], -1)
    remap[used] = np.arange(used.size)
    mesh = MeshTri(np.ascontiguousarray(p[:, used]), np.ascontiguousarray(remap[t]))
    bfacets = mesh.boundary_facets()
    rings_out = {}
    for name, nodes in line_nodes.items():
        on = np.zeros(p.shape[1], bool)
        on[index[nodes.astype(int)]] = True
        on = on[used]
        f = bfacets[np.all(on[mesh.facets[:, bfacets]], axis=0)]
        rings_out[name] = f
    return BodyMesh(mesh, rings_out)

