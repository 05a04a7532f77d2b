"""Linear elasticity of one 2D body with scikit-fem (quadratic triangles).

A :class:`Body` holds the mesh, the P2 basis, the material and the stiffness with its
supports, and solves for many load cases from one sparse factorisation (fem.linsolve):
displacements (:meth:`Body.solve`) and condensed flexibilities (:meth:`Body.flexibility`).
Plane strain by default, plane stress as an option.
"""
from __future__ import annotations

import functools

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .hertz import reduced_modulus
from . import linsolve
from ..errors import ToothfemError, check_range

if TYPE_CHECKING:
    from .mesh import BodyMesh


def lame_parameters(youngs_modulus, poisson_ratio, plane: str = "strain"):
    """Lame parameters; in plane stress lambda* = 2 lambda mu / (lambda + 2 mu).

    Parameters
    ----------
    youngs_modulus : float
        E [Pa].
    poisson_ratio : float
        nu [-].
    plane : {"strain", "stress"}
        The 2D idealisation.

    Returns
    -------
    lam, mu : float
        lambda (lambda* in plane stress) and mu [Pa].

    Raises
    ------
    ToothfemError
        For another ``plane``.
    """
    e, nu = float(youngs_modulus), float(poisson_ratio)
    lam = e * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e / (2 * (1 + nu))
    if plane == "stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    elif plane != "strain":
        raise ToothfemError(f"plane = {plane!r} is not one of ['strain', 'stress']")
    return lam, mu


def plane_modulus(youngs_modulus, poisson_ratio, plane: str = "strain") -> float:
    """E/(1 - nu^2) in plane strain, E in plane stress: the modulus of 2D contact formulas.

    Parameters
    ----------
    youngs_modulus, poisson_ratio : float
        E [Pa] and nu [-].
    plane : {"strain", "stress"}
        Anything but "strain" is taken as stress.

    Returns
    -------
    float
        The plane modulus [Pa].
    """
    e, nu = float(youngs_modulus), float(poisson_ratio)
    return e / (1 - nu**2) if plane == "strain" else e


#: Edges of the P2 triangle in scikit-fem's local order (ElementTriP2: dofs 3, 4, 5 at the
#: midpoints of vertices 0-1, 1-2, 0-2).
P2_EDGES = ((0, 1), (1, 2), (0, 2))
#: Barycentric coordinates of the edge midpoints: the 3-point rule with weights area/3 is
#: exact for quadratics (Strang & Fix 1973, Table 4.1), and the integrand of the P2
#: stiffness (products of linear gradients) is one.
MIDPOINT_RULE = np.array([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]])


def p2_gradients(mesh):
    """Gradients of the six P2 shape functions at the edge midpoints of every triangle.

    Vertex functions l_k (2 l_k - 1), edge functions 4 l_a l_b in barycentric coordinates
    l_k, whose gradients are constant on an affine triangle.

    Parameters
    ----------
    mesh : skfem.MeshTri
        Linear triangles, vertices ``p`` (2, N) [m].

    Returns
    -------
    grads : numpy.ndarray
        (n_elements, 3 points, 6 functions, 2) [1/m].
    areas : numpy.ndarray
        (n_elements,) triangle areas [m^2].
    """
    x = mesh.p[:, mesh.t]                                   # (2, 3, E)
    e1, e2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    det = e1[0] * e2[1] - e1[1] * e2[0]
    # grad l1 = perp(e2) / det, grad l2 = -perp(e1) / det, grad l0 = -(grad l1 + grad l2)
    g1 = np.stack([e2[1], -e2[0]]) / det
    g2 = np.stack([-e1[1], e1[0]]) / det
    dl = np.stack([-(g1 + g2), g1, g2], axis=1).transpose(2, 1, 0)     # (E, 3, 2)
    lam = MIDPOINT_RULE                                                # (Q, 3)
    grads = [(4 * lam[:, k, None, None] - 1) * dl[None, :, k] for k in range(3)]
    grads += [4 * (lam[:, b, None, None] * dl[None, :, a] + lam[:, a, None, None] * dl[None, :, b])
              for a, b in P2_EDGES]
    return np.stack(grads, axis=2).transpose(1, 0, 2, 3), 0.5 * np.abs(det)


def stiffness_matrix(basis, lam, mu):
    """Stiffness of isotropic linear elasticity on a P2 vector basis (scikit-fem's dof
    numbering, components interleaved), vectorised over the elements; equal to scikit-fem's
    ``asm(linear_elasticity(lam, mu), basis)`` to round-off (tests/test_linsolve.py).

    K[(i,c),(j,d)] = int lam d_c phi_i d_d phi_j + mu (d_d phi_i d_c phi_j
    + delta_cd grad phi_i . grad phi_j), from sigma(u) : eps(v) with
    sigma = lam tr(eps) I + 2 mu eps.

    Parameters
    ----------
    basis : skfem.Basis
        ElementVector(ElementTriP2()) on a MeshTri [m].
    lam, mu : float
        Lame parameters [Pa] (:func:`lame_parameters`).

    Returns
    -------
    scipy.sparse.csc_matrix
        (N_dofs, N_dofs) [Pa]: forces per unit thickness [N/m] per displacement [m].
    """
    from scipy.sparse import coo_matrix

    grad, area = p2_gradients(basis.mesh)
    w = area[:, None] / len(MIDPOINT_RULE)
    g = grad.reshape(grad.shape[0], grad.shape[1], 12)      # (E, Q, 6 x 2)
    m = np.matmul((g * w[:, :, None]).transpose(0, 2, 1), g).reshape(-1, 6, 2, 6, 2)
    k = lam * m + mu * m.transpose(0, 1, 4, 3, 2)
    dots = np.einsum("eiaja->eij", m)
    k[:, :, 0, :, 0] += mu * dots
    k[:, :, 1, :, 1] += mu * dots
    dofs = basis.element_dofs.T.astype(np.int32)           # (E, 12); int32: half the memory
    n_el = dofs.shape[0]
    rows = np.broadcast_to(dofs[:, :, None], (n_el, 12, 12))
    cols = np.broadcast_to(dofs[:, None, :], (n_el, 12, 12))
    return coo_matrix((k.reshape(n_el, 12, 12).ravel(), (rows.ravel(), cols.ravel())),
                      shape=(basis.N, basis.N)).tocsc()


class _Material(Protocol):
    """What :class:`SameMaterial` reads of the model it is mixed into."""

    @property
    def youngs_modulus(self) -> float: ...

    @property
    def poisson_ratio(self) -> float: ...

    @property
    def plane(self) -> str: ...


class SameMaterial:
    """Moduli of two bodies of one isotropic material (mixin for the FE models: needs
    ``youngs_modulus``, ``poisson_ratio`` and ``plane``)."""

    @functools.cached_property
    def e_star(self: _Material) -> float:
        """Hertz's reduced modulus E* of the pair (Johnson 1985); kept (read per contact
        solve)."""
        return float(reduced_modulus(self.youngs_modulus, self.poisson_ratio,
                                     self.youngs_modulus, self.poisson_ratio))

    @property
    def e_plane(self: _Material) -> float:
        return plane_modulus(self.youngs_modulus, self.poisson_ratio, self.plane)


@dataclass(eq=False)
class Body:
    """An elastic body: mesh (BodyMesh), material, support (clamped vertex indices).

    Lengths in m, moduli in Pa; the out-of-plane thickness is 1 m (forces per unit length).
    """
    body_mesh: BodyMesh
    youngs_modulus: float
    poisson_ratio: float
    clamped_nodes: np.ndarray
    plane: str = "strain"
    solver: str | None = None     # fem.linsolve backend; None: $TOOTHFEM_SOLVER or fastest

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
        lam, mu = lame_parameters(self.youngs_modulus, self.poisson_ratio, self.plane)
        return stiffness_matrix(self.basis, lam, mu)

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
    def factor(self) -> linsolve.Factor:
        """The factorisation of the stiffness on the free dofs (fem.linsolve)."""
        free, _ = self._dofs
        return linsolve.factorize(self.stiffness[free][:, free], self.solver)

    def solve(self, loads):
        """Displacements for load vectors with the supports held.

        Parameters
        ----------
        loads : array_like
            (N_dofs,) or (N_dofs, k) nodal forces [N/m] (per unit thickness).

        Returns
        -------
        numpy.ndarray
            Displacements [m], the shape of ``loads``.
        """
        loads = np.asarray(loads, float)
        one = loads.ndim == 1
        loads = loads.reshape(loads.shape[0], -1)
        free, _ = self._dofs
        u = np.zeros_like(loads)
        u[free] = self.factor.solve(loads[free])
        return u[:, 0] if one else u

    def flexibility(self, loads, blocks=None):
        """loads^T K^-1 loads for sparse unit loads (N_dofs, k) with the supports held (the
        loads on held dofs do no work) (:meth:`fem.linsolve.Factor.flexibility`).

        Parameters
        ----------
        loads : sparse (N_dofs, k)
            Unit loads.
        blocks : sequence of int or None
            Column counts summing to k.

        Returns
        -------
        numpy.ndarray or list of numpy.ndarray
            (k, k) [m per (N/m)], or with ``blocks`` the list of the diagonal blocks only.

        Raises
        ------
        ToothfemError
            When ``blocks`` do not sum to k.
        """
        from scipy.sparse import csr_matrix

        free, _ = self._dofs
        loads = csr_matrix(loads)
        pattern = abs(loads)
        # loads on neighbouring nodes reach nearly the same rows of the factor: coupled
        # through the stiffness, they are solved together (fem.linsolve)
        coupling = pattern.T @ abs(self.stiffness) @ pattern
        return self.factor.flexibility(loads[free], blocks, coupling)

    def point_load_matrix(self, points, directions):
        """Load vectors of unit forces at points, distributed to the dofs by the P2 shape
        functions at each point; the same matrix transposed maps a displacement field to its
        components along ``directions`` at ``points``.

        Parameters
        ----------
        points : array_like
            (2, K) positions [m].
        directions : array_like
            (2, K) force directions (unit vectors).

        Returns
        -------
        scipy.sparse.csc_matrix
            (N_dofs, K) load vectors, per unit force [-].
        """
        points = np.asarray(points, float).reshape(2, -1)
        d = np.asarray(directions, float).reshape(2, -1)
        k = points.shape[1]
        probes = self.basis.probes(points).tocsr()     # (2K, N): x rows then y rows
        from scipy.sparse import diags

        return (diags(d[0]) @ probes[:k] + diags(d[1]) @ probes[k:]).T.tocsc()
