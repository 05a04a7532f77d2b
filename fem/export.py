"""Stress fields of a solved body and their export to VTU (meshio).

The fields are SI inside (:func:`stress_at_nodes`: Pa); the VTU is written in millimetres
and megapascals like every other file of toothfem, each field's unit in its name:
points [mm], ``displacement_mm``, ``sxx_MPa``, ``syy_MPa``, ``sxy_MPa``, ``szz_MPa``,
``von_mises_MPa``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .elastic import lame_parameters
from ..units import MM_PER_M, MPA_PER_PA

#: Millimetres per metre: the VTU's points and displacement are in mm.
VTU_MM_PER_M = MM_PER_M
#: Megapascals per pascal: the VTU's stresses are in MPa.
VTU_MPA_PER_PA = MPA_PER_PA


def stress_at_nodes(body, u):
    """Nodal (vertex) stresses of a P2 displacement ``u`` by L2 projection onto P1.

    Plane strain: szz = lambda (exx + eyy).

    Parameters
    ----------
    body : toothfem.fem.elastic.Body
        The solved body (its basis, material and plane state).
    u : numpy.ndarray, shape (N_dofs,)
        Displacement [m].

    Returns
    -------
    dict of str to numpy.ndarray
        sxx, syy, sxy, szz and von_mises [Pa], each (N_vertices,).
    """
    from skfem import ElementTriP1

    lam, mu = lame_parameters(body.youngs_modulus, body.poisson_ratio, body.plane)
    grad = body.basis.interpolate(u).grad          # (2, 2, nel, nqp)
    exx, eyy = grad[0, 0], grad[1, 1]
    exy = 0.5 * (grad[0, 1] + grad[1, 0])
    tr = exx + eyy
    s = {"sxx": 2 * mu * exx + lam * tr, "syy": 2 * mu * eyy + lam * tr, "sxy": 2 * mu * exy,
         "szz": lam * tr if body.plane == "strain" else 0 * tr}
    s["von_mises"] = np.sqrt(0.5 * ((s["sxx"] - s["syy"]) ** 2 + (s["syy"] - s["szz"]) ** 2
                                    + (s["szz"] - s["sxx"]) ** 2) + 3 * s["sxy"] ** 2)
    p1 = body.basis.with_element(ElementTriP1())
    out = {k: p1.project(v) for k, v in s.items()}
    # the L2 projection of a steep positive field undershoots slightly below zero
    out["von_mises"] = np.maximum(out["von_mises"], 0.0)
    return out


def to_meshio(body, u, extra_point_data=None):
    """meshio.Mesh of the body's triangles in mm with displacement [mm] and stresses [MPa],
    each field's unit in its name (module docstring).

    Parameters
    ----------
    body : toothfem.fem.elastic.Body
        The solved body [m].
    u : numpy.ndarray, shape (N_dofs,)
        Displacement [m].
    extra_point_data : dict of str to numpy.ndarray, optional
        More vertex fields, each (N_vertices, ...), written as given: name each with its
        unit.

    Returns
    -------
    meshio.Mesh
        Triangles (the P2 mesh's vertices [mm], z = 0) with ``displacement_mm`` and the
        stresses ``sxx_MPa``, ``syy_MPa``, ``sxy_MPa``, ``szz_MPa``, ``von_mises_MPa``.
    """
    import meshio

    mesh = body.mesh
    pts = np.vstack([mesh.p, np.zeros(mesh.p.shape[1])]).T
    disp = np.zeros_like(pts)
    disp[:, 0] = u[body.basis.nodal_dofs[0]]
    disp[:, 1] = u[body.basis.nodal_dofs[1]]
    data = {"displacement_mm": disp * VTU_MM_PER_M}
    data.update({f"{k}_MPa": v * VTU_MPA_PER_PA for k, v in stress_at_nodes(body, u).items()})
    data.update(extra_point_data or {})
    return meshio.Mesh(pts * VTU_MM_PER_M, [("triangle", mesh.t.T.copy())], point_data=data)


def write_vtu(path, body, u, extra_point_data=None) -> Path:
    """Write the body's mesh [mm], displacement [mm] and stresses [MPa] as a VTU file, each
    field's unit in its name (:func:`to_meshio`).

    Parameters
    ----------
    path : str or pathlib.Path
        File to write (the suffix picks meshio's format: .vtu).
    body : toothfem.fem.elastic.Body
        The solved body.
    u : numpy.ndarray, shape (N_dofs,)
        Displacement [m].
    extra_point_data : dict of str to numpy.ndarray, optional
        More vertex fields.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    to_meshio(body, u, extra_point_data).write(path)
    return path
