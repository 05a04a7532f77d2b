"""Analytic verification cases of the detailed contact solver: Hertz line contact in plane
strain, a cylinder on a flat block and a cylinder in a concave bore.

Both bodies are meshed with P2 triangles, refined in the contact zone with the master
surface's vertices placed at the projections of the slave's vertices (a conforming zone:
non-matching node-to-surface pairs make the nodal forces oscillate by +-10 % at this
resolution, docs/fem.md). The cylinder is held at a central core that moves down as a rigid
body (the unknown of the force balance); the block is clamped at its base.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .hertz import hertz_line, reduced_modulus
from . import contact
from .elastic import Body
from .mesh import Refinement, mesh_rings, refine_ring

#: Block width and height per cylinder radius, and the cylinder's clamped core radius.
BLOCK_WIDTH_REL, BLOCK_HEIGHT_REL, CORE_REL = 4.0, 2.0, 0.2
#: Slave zone half-width per Hertz half-width (the contact must end inside it).
ZONE_REL = 1.6


@dataclass(frozen=True)
class HertzCheck:
    p0_analytic: float      # Pa
    b_analytic: float       # m
    p_max: float            # Pa, FE peak pressure (SlaveSurface.pressure)
    b_fe: float             # m, from the second moment b^2 = 4 int x^2 p / int p
    x: np.ndarray           # (M,) slave point abscissae, m
    pressure: np.ndarray    # (M,) Pa
    force_total: float      # N/m, sum of nodal contact forces
    dofs: int               # total dofs of both bodies
    element_size: float     # m, in the contact zone

    @property
    def p_error(self) -> float:
        return self.p_max / self.p0_analytic - 1

    @property
    def b_error(self) -> float:
        return self.b_fe / self.b_analytic - 1


def _circle(centre, radius):
    c = np.asarray(centre, float).reshape(2, 1)

    def project(p):
        d = p - c
        return c + radius * d / np.hypot(*d)
    return project


def cylinder_contact(radius, e1, nu1, e2, nu2, load_per_length, *, bore_radius=None,
                     elements_per_halfwidth=20, plane="strain") -> HertzCheck:
    """Cylinder pressed onto a flat block or into a concave bore, FE against Hertz.

    Units SI; one unit of thickness. Returns the FE peak pressure and half-width beside
    Hertz's (Johnson, Contact Mechanics, Eq. 4.45).

    Parameters
    ----------
    radius : float
        Cylinder radius [m].
    e1, nu1 : float
        Cylinder's Young's modulus [Pa] and Poisson ratio.
    e2, nu2 : float
        Block's Young's modulus [Pa] and Poisson ratio.
    load_per_length : float
        Load [N/m].
    bore_radius : float, optional
        Radius of the concave bore in the block [m]; None: a flat block.
    elements_per_halfwidth : int
        Elements over Hertz's half-width in the contact zone.
    plane : {"strain", "stress"}
        Plane state.

    Returns
    -------
    HertzCheck
        Analytic and FE pressure and half-width, the pressure profile and the mesh size.
    """
    r1 = float(radius)
    e_star = reduced_modulus(e1, nu1, e2, nu2)
    r_eq = r1 if bore_radius is None else 1.0 / (1.0 / r1 - 1.0 / bore_radius)
    p0, b = hertz_line(load_per_length, r_eq, e_star)
    h = b / elements_per_halfwidth
    origin = np.zeros((2, 1))
    # slave: the cylinder, touching y = 0 at the origin from above
    th = np.linspace(-math.pi / 2, 1.5 * math.pi, 720, endpoint=False)
    c1 = np.array([[0.0], [r1]])
    ring_a = c1 + r1 * np.stack([np.cos(th), np.sin(th)])
    ring_a = refine_ring(ring_a, origin, h, 3 * b, curve=_circle(c1, r1))
    refine = [Refinement(origin, h, 2 * b, 8 * b)]
    size_max = r1 / 8
    mesh_a = mesh_rings([ring_a], size_max, refine, keep_below=2 * h)
    zone = ring_a[:, (np.abs(ring_a[0]) < 3 * b) & (ring_a[1] < r1)]
    zone = zone[:, np.argsort(zone[0])]
    w, hh = BLOCK_WIDTH_REL * r1, BLOCK_HEIGHT_REL * r1
    if bore_radius is None:
        def project_b(p):
            q = p.copy()
            q[1] = 0.0
            return q, np.vstack([np.zeros(p.shape[1]), np.ones(p.shape[1])])
        left = np.linspace(-w / 2, zone[0, 0], 24)[:-1]
        right = np.linspace(zone[0, -1], w / 2, 24)[1:]
        top = np.concatenate([left, zone[0], right])
        rings_b = [np.concatenate([np.array([[-w / 2, w / 2], [-hh, -hh]]),
                                   np.stack([top[::-1], np.zeros(top.size)])], axis=1)]
    else:
        r2 = float(bore_radius)
        c2 = np.array([[0.0], [r2]])
        circ = _circle(c2, r2)

        def project_b(p):
            q = circ(p)
            return q, (c2 - q) / r2
        # bore ring: the zone's radial projections, then a coarse arc round the rest
        zb = circ(zone)
        a_zone = np.arctan2(zb[1] - r2, zb[0])
        a_rest = np.linspace(a_zone[-1], a_zone[0] + 2 * math.pi, 360)[1:-1]
        bore = np.concatenate([zb, c2 + r2 * np.stack([np.cos(a_rest), np.sin(a_rest)])],
                              axis=1)
        top_y = 2 * r2 + 0.5 * r1
        outer = np.array([[-w / 2 - r2, w / 2 + r2, w / 2 + r2, -w / 2 - r2],
                          [-hh, -hh, top_y, top_y]])
        rings_b = [outer, bore]
    mesh_b = mesh_rings(rings_b, size_max, refine, keep_below=2 * h)
    pa = mesh_a.mesh.p
    body_a = Body(mesh_a, e1, nu1, np.flatnonzero(np.hypot(pa[0], pa[1] - r1) < CORE_REL * r1),
                  plane)
    pb = mesh_b.mesh.p
    body_b = Body(mesh_b, e2, nu2, np.flatnonzero(pb[1] < -hh + 1e-9 * r1), plane)
    f = mesh_a.rings["outer"]
    mid = 0.5 * (pa[:, mesh_a.mesh.facets[0, f]] + pa[:, mesh_a.mesh.facets[1, f]])
    f = f[(np.abs(mid[0]) < ZONE_REL * b) & (mid[1] < r1)]
    slave = contact.slave_surface(body_a, f)
    down = lambda x: np.vstack([np.zeros(x.shape[1]), -np.ones(x.shape[1])])  # noqa: E731
    pair = contact.condense_pair(body_a, slave, body_b, project_b, rigid_a=down)
    sol = contact.solve_contact(pair.h, pair.g0, pair.c, load_per_length)
    pressure = slave.pressure(sol.force)
    x = slave.points[0]
    b_fe = math.sqrt(4 * np.sum(x**2 * sol.force) / np.sum(sol.force))
    return HertzCheck(float(p0), float(b), float(np.max(pressure)), b_fe, x, pressure,
                      float(np.sum(sol.force)), body_a.basis.N + body_b.basis.N, h)
