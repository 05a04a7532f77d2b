"""Linear elasticity of one 2D body with scikit-fem (quadratic triangles).

A :class:`Body` holds the mesh, the P2 basis, the material and the stiffness with its
supports, and solves for many load cases from one sparse LU factorisation
(:meth:`Body.flexibility`). Plane strain by default, plane stress as an option.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .hertz import reduced_modulus
from ..errors import ToothfemError, check_range


def lame_parameters(youngs_modulus, poisson_ratio, plane: str = "strain"):
    """(lambda, mu); in plane stress lambda* = 2 lambda mu / (lambda + 2 mu)."""
    e, nu = float(youngs_modulus), float(poisson_ratio)
    lam = e * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e / (2 * (1 + nu))
    if plane == "stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    elif plane != "strain":
        raise ToothfemError(f"plane = {plane!r} is not one of ['strain', 'stress']")
    return lam, mu


def plane_modulus(youngs_modulus, poisson_ratio, plane: str = "strain") -> float:
    """E/(1 - nu^2) in plane strain, E in plane stress: the modulus of 2D contact formulas."""
    e, nu = float(youngs_modulus), float(poisson_ratio)
    return e / (1 - nu**2) if plane == "strain" else e


class SameMaterial:
    """Moduli of two bodies of one isotropic material (mixin for the FE models: needs
    ``youngs_modulus``, ``poisson_ratio`` and ``plane``)."""

    @property
    def e_star(self) -> float:
        """Hertz's reduced modulus E* of the pair (Johnson 1985)."""
        return float(reduced_modulus(self.youngs_modulus, self.poisson_ratio,
                                     self.youngs_modulus, self.poisson_ratio))

    @property
    def e_plane(self) -> float:
        return plane_modulus(self.youngs_modulus, self.poisson_ratio, self.plane)


@dataclass(eq=False)
class Body:
    """An elastic body: mesh (BodyMesh), material, support (clamped vertex indices).

    Lengths in m, moduli in Pa; the out-of-plane thickness is 1 m (forces per unit length).
    """
    body_mesh: object
    youngs_modulus: float
    poisson_ratio: float
    clamped_nodes: np.ndarray
    plane: str = "strain"

    def __post_init__(self):
        check_range("youngs_modulus", self.youngs_modulus, 0, None, lo_open=True)
        check_range("poisson_ratio", self.poisson_ratio, -1, 0.5, lo_open=True, hi_open=True)
        if len(self.clamped_nodes) == 0:
            raise ToothfemError("clamped_nodes is empty: the body would move as a rigid body")

    @property
    def mesh(self):
        return self.body_mesh.mesh

    @cached_property
    def basis(self):
        from skfem import Basis, ElementTriP2, ElementVector

        return Basis(self.mesh, ElementVector(ElementTriP2()))

    @cached_property
    def stiffness(self):
        from skfem import asm
        from skfem.models.elasticity import linear_elasticity

        lam, mu = lame_parameters(self.youngs_modulus, self.poisson_ratio, self.plane)
        return asm(linear_elasticity(lam, mu), self.basis).tocsc()

    @cached_property
    def _dofs(self):
        """(free dofs, clamped dofs): every dof (vertex and edge) of a clamped vertex's
        facets is held."""
        nodes = np.asarray(self.clamped_nodes)
        mesh = self.mesh
        on = np.zeros(mesh.p.shape[1], bool)
        on[nodes] = True
        facets = np.flatnonzero(np.all(on[mesh.facets], axis=0))
        d = self.basis.get_dofs(facets=facets).all() if facets.size else np.array([], int)
        vd = self.basis.nodal_dofs[:, nodes].ravel()
        clamped = np.unique(np.concatenate([np.asarray(d, int), vd]))
        free = np.setdiff1d(np.arange(self.basis.N), clamped)
        return free, clamped

    @cached_property
    def _lu(self):
        from scipy.sparse.linalg import splu

        free, _ = self._dofs
        # minimum degree on A^T + A with symmetric mode: half the fill of COLAMD on these
        # symmetric FE matrices (12M vs 25M nonzeros at 75k dofs; benchmarks/)
        return splu(self.stiffness[free][:, free].tocsc(), permc_spec="MMD_AT_PLUS_A",
                    options=dict(SymmetricMode=True))

    def solve(self, loads):
        """Displacements (N_dofs, k) for load vectors (N_dofs, k) with the supports held."""
        loads = np.asarray(loads, float)
        one = loads.ndim == 1
        loads = loads.reshape(loads.shape[0], -1)
        free, _ = self._dofs
        u = np.zeros_like(loads)
        u[free] = self._lu.solve(np.ascontiguousarray(loads[free]))
        return u[:, 0] if one else u

    def point_load_matrix(self, points, directions):
        """Load vectors (N_dofs, K) of unit forces at ``points`` (2, K) along ``directions``
        (2, K), distributed to the dofs by the P2 shape functions at each point; the same
        matrix transposed maps a displacement field to its components along ``directions``
        at ``points``."""
        points = np.asarray(points, float).reshape(2, -1)
        d = np.asarray(directions, float).reshape(2, -1)
        k = points.shape[1]
        probes = self.basis.probes(points).tocsr()     # (2K, N): x rows then y rows
        from scipy.sparse import diags

        return (diags(d[0]) @ probes[:k] + diags(d[1]) @ probes[k:]).T.tocsc()
