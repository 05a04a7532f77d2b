"""Strength of the meshing stage: contact stress and the member's stress field.

* Contact: the largest Hertz pressure P_h over the meshing period (peak member torque)
  against the material's contact fatigue limit (``material.allowable_contact_stress_MPa``,
  1500 MPa: the contact stress of ISO 281:2007's fatigue load limit for through-hardened
  bearing steel) and its static limit (``material.static_contact_stress_MPa``, 4000 MPa:
  ISO 76:2006 for roller contacts, a permanent deformation of 1e-4 of the roller
  diameter). Safety factor S = limit / P_h,max.
* Member (disc or planet): the largest von Mises stress of the FE field (nodal stresses of
  :func:`toothfem.fem.export.stress_at_nodes`) against the yield strength, and the largest
  at the hole edges (the inner boundaries: crank and pillar holes, the centre bore)
  against the fatigue limit: a hole edge sees its stress come and go once per crank turn,
  taken here as fully reversed (conservative; the contact zone's own fatigue is the
  contact check above).

A factor below 1 gives a one-line warning in :attr:`Strength.warnings`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fem.export import stress_at_nodes
from ..units import PA_PER_MPA

@dataclass(frozen=True, kw_only=True)
class Strength:
    """Safety factors of the contact and of the member (None where not computed)."""
    ph_max_Pa: float
    contact_fatigue_safety: float
    contact_static_safety: float
    von_mises_max_Pa: float | None = None
    von_mises_holes_Pa: float | None = None
    yield_safety: float | None = None
    fatigue_safety: float | None = None
    warnings: tuple = ()


def safety_factor(limit, stress):
    """limit / stress (inf for a zero stress).

    Parameters
    ----------
    limit : float
        The allowable stress [Pa].
    stress : float
        The stress [Pa].

    Returns
    -------
    float
        The safety factor [-].
    """
    return float("inf") if stress <= 0 else float(limit / stress)


#: The inner boundaries (holes) are told from the outer profile by the largest gap in the
#: radii of the boundary nodes about the body's centroid; a gap below this share of the
#: outer radius means the body has no hole.
HOLE_GAP_SHARE = 0.05


def hole_edge_nodes(mesh) -> np.ndarray:
    """Vertex indices on the inner boundaries (holes) of a 2-D mesh, by the largest gap in
    the boundary nodes' radii about the centroid (empty if there is no clear gap).

    Parameters
    ----------
    mesh : skfem.Mesh
        A 2-D mesh (``p`` (2, N)).

    Returns
    -------
    numpy.ndarray
        Indices into ``mesh.p``.
    """
    nodes = np.asarray(mesh.boundary_nodes())
    centre = mesh.p.mean(axis=1, keepdims=True)
    r = np.linalg.norm(mesh.p[:, nodes] - centre, axis=0)
    radii = np.sort(r)
    if radii.size < 2:
        return np.array([], int)
    gaps = np.diff(radii)
    k = int(np.argmax(gaps))
    if gaps[k] < HOLE_GAP_SHARE * radii[-1]:
        return np.array([], int)
    return nodes[r <= radii[k]]


def member_stress(body, displacement):
    """(largest von Mises stress, largest at the hole edges or None) of an FE field [Pa].

    Parameters
    ----------
    body : toothfem.fem.elastic.Body
    displacement : numpy.ndarray
        The body's P2 displacement dofs.

    Returns
    -------
    tuple of float
    """
    vm = stress_at_nodes(body, displacement)["von_mises"]
    holes = hole_edge_nodes(body.mesh)
    return float(vm.max()), (float(vm[holes].max()) if holes.size else None)


def strength(si, ph_max_Pa, body=None, displacement=None, member="member") -> Strength:
    """Safety factors of the contact (largest P_h) and, with an FE field, of the member.

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Its ``material`` holds the limits.
    ph_max_Pa : float
        Largest Hertz (or FE) contact pressure over the period [Pa].
    body, displacement : optional
        The member's FE body and displacement at the worst position.
    member : str
        What the member is called in the warnings ("disc", "planet").

    Returns
    -------
    Strength
    """
    m = si.material
    s_c = safety_factor(m.allowable_contact_stress_Pa, ph_max_Pa)
    s_0 = safety_factor(m.static_contact_stress_Pa, ph_max_Pa)
    vm_max = vm_holes = s_y = s_f = None
    if body is not None:
        vm_max, vm_holes = member_stress(body, displacement)
        s_y = safety_factor(m.yield_strength_Pa, vm_max)
        if vm_holes is not None:
            s_f = safety_factor(m.fatigue_limit_Pa, vm_holes)
    notes = []
    checks = ((s_c, f"contact fatigue: P_h,max = {ph_max_Pa / PA_PER_MPA:.0f} MPa exceeds "
                    f"material.allowable_contact_stress_MPa = "
                    f"{m.allowable_contact_stress_Pa / PA_PER_MPA:g}"),
              (s_0, f"static contact: P_h,max = {ph_max_Pa / PA_PER_MPA:.0f} MPa exceeds "
                    f"material.static_contact_stress_MPa = "
                    f"{m.static_contact_stress_Pa / PA_PER_MPA:g}"),
              (s_y, f"{member} yield: von Mises {0 if vm_max is None else vm_max / PA_PER_MPA:.0f} MPa "
                    f"exceeds material.yield_strength_MPa = {m.yield_strength_Pa / PA_PER_MPA:g}"),
              (s_f, f"{member} fatigue at the hole edges: von Mises "
                    f"{0 if vm_holes is None else vm_holes / PA_PER_MPA:.0f} MPa exceeds "
                    f"material.fatigue_limit_MPa = {m.fatigue_limit_Pa / PA_PER_MPA:g}"))
    for s, text in checks:
        if s is not None and s < 1:
            notes.append(f"safety factor {s:.2f} < 1, {text}")
    return Strength(ph_max_Pa=float(ph_max_Pa), contact_fatigue_safety=s_c,
                    contact_static_safety=s_0, von_mises_max_Pa=vm_max,
                    von_mises_holes_Pa=vm_holes, yield_safety=s_y, fatigue_safety=s_f,
                    warnings=tuple(notes))
