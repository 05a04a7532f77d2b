"""Finite-element load sharing of a cycloid disc on its pins: cycle mode and detailed mode.

Both modes work in the disc frame (disc centre at the origin, the disc held at its
crank-bearing holes by a rigid coupling that turns by the unknown transmission error beta)
and return a :class:`~toothfem.fem.load_sharing.LoadSharing`. Friction is neglected in the
solve (frictionless normal contact); the friction forces are small against the normal
forces (mu ~ 0.05) and are accounted for in the efficiency model.

Pins (conventional structure): each pin is an elastic disc of radius rz held over the outer
half of its boundary by the housing groove (treated as rigid). Contact is plane strain per
unit face width; forces are reported over the face width.

Cycle mode (sweeps): for each position the candidate contacts are the pins whose normal can
carry the torque. The disc's influence coefficients at the candidate points come from one
sparse factorisation of a disc mesh refined along the short profile windows that the
contact points sweep over one meshing period (a pin's contact point moves by 1/Za of the
crank angle along the profile). A unit load is a Hertzian strip of reference half-width
b_ref; the displacement is its work-conjugate patch average. The Hertz local approach then
corrects each diagonal term from b_ref to the contact's own half-width b(F):
delta(b) - delta(b_ref) = -(2 (1 - nu^2) / (pi E)) F ln(b / b_ref) (half-space strip,
docs/fem.md). The pin's compliance comes from an FE table over the contact angle with the
same correction. The complementarity problem with the torque balance is solved for each
iterate of b(F) until the forces settle.

Detailed mode (verification, stress plots): both bodies meshed with the contact zones of
the current position refined to a fraction of the Hertz half-width and conforming, the
nodal contact forces solved on the condensed two-body system (fem.contact).
"""
from .cycle import TABLES_VERSION, CycleSolver
from .detailed import DETAILED_FORCE_MARGIN, DETAILED_ZONE_REL, DetailedResult, solve_detailed
from .model import (CANDIDATE_ARM_REL, HOUSING_BORE_STEP, HOUSING_STEP, LOCAL_MAX_ITER,
                    LOCAL_RTOL, PIN_STRUCTURES, CycloidFEModel, PinModel, housing_body,
                    housing_rings, patch_loads, strip_width_correction)

__all__ = ["CANDIDATE_ARM_REL", "DETAILED_FORCE_MARGIN", "DETAILED_ZONE_REL", "HOUSING_BORE_STEP",
           "HOUSING_STEP", "LOCAL_MAX_ITER", "LOCAL_RTOL", "PIN_STRUCTURES", "TABLES_VERSION",
           "CycleSolver", "CycloidFEModel", "DetailedResult", "PinModel", "housing_body",
           "housing_rings", "patch_loads", "solve_detailed", "strip_width_correction"]
