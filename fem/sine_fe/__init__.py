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
from .cycle import (DEFAULT_SELECT_GAP, DEFAULT_SPACING, HERTZ_GAP_RTOL, SELECT_GAP_MAX,
                    SELECT_MARGIN, TABLES_VERSION, CycleSolver, PositionResult)
from .detailed import (DETAILED_ELEMENT, DETAILED_ZONE_GAP, ZONE_PAD, DetailedResult,
                       solve_detailed)
from .grid import ARC_TABLE_POINTS, CIRCLE_POINTS, COARSE_STEP_REL, SIZE_MAX_REL, ring_foot
from .model import RING_RIM_MODULES, SineFEModel, model_from_pair

__all__ = ["ARC_TABLE_POINTS", "CIRCLE_POINTS", "COARSE_STEP_REL", "DEFAULT_SELECT_GAP",
           "DEFAULT_SPACING", "DETAILED_ELEMENT", "DETAILED_ZONE_GAP", "HERTZ_GAP_RTOL",
           "RING_RIM_MODULES", "SELECT_GAP_MAX", "SELECT_MARGIN", "SIZE_MAX_REL",
           "TABLES_VERSION", "ZONE_PAD", "CycleSolver", "DetailedResult", "PositionResult",
           "SineFEModel", "model_from_pair", "ring_foot", "solve_detailed"]
