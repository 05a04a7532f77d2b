"""Detailed mode of the sine pair: two-body FE contact with every zone of one crank angle
refined (fem/sine_fe/__init__.py)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import check_range
from ...geometry import sine
from ...geometry.vectors import rotate
from .. import contact
from ..elastic import Body
from ..load_sharing import LoadSharing, check_member_torque
from ..mesh import Refinement, mesh_rings
from .cycle import (_flank_columns, PositionResult, _record, SELECT_GAP_MAX,
                    SELECT_MARGIN)
from .grid import (COARSE_STEP_REL, SIZE_MAX_REL, _boundary_chain, _circle, _outline,
                   _planet_toothed, _ring_toothed, ring_foot)
from .model import SineFEModel
from ...units import UM_PER_M

# ---------------------------------------------------------------------------------------
# Detailed mode

#: Element size along the contact zones (m): 7 elements over the half-width of the
#: lightest loaded contacts of the prototype (0.1 mm), 20-30 over the others.
DETAILED_ELEMENT = 15e-6
#: Contact zones: the loaded side (moment arm < 0) of the candidate teeth where the initial
#: gap is below this (m); doubled (up to SELECT_GAP_MAX) when the contact reaches nodes of
#: initial gap above SELECT_MARGIN of it or the surfaces overlap outside the zones.
DETAILED_ZONE_GAP = 3.5e-6
#: Spacing (m) of the points outside the zones where the loaded gap is checked, and the
#: overlap (fraction of the largest rigid approach beta |l|) that counts as a miss.
CHECK_SPACING, CHECK_OVERLAP_REL = 50e-6, 1e-2
#: Samples (element sizes) added at each end of a zone, so that it ends in open gap.
ZONE_PAD = 3


@dataclass(frozen=True, kw_only=True)
class DetailedResult:
    """One crank angle of the detailed mode: the load sharing and the nodal solution."""
    load_sharing: LoadSharing
    nodes: PositionResult       # slave nodes: points, forces, pressures (patch-averaged)
    dofs: int
    planet: Body                # planet frame (centre at the origin, unturned)
    planet_displacement: np.ndarray
    ring: Body                  # ring frame
    ring_displacement: np.ndarray
    zone_gap: float
    min_gap_outside: float      # m, loaded gap at the check points outside the zones

    @property
    def member_body(self):
        """The moving member's Body (the planet), as every drive's detailed result names it."""
        return self.planet

    @property
    def member_displacement(self):
        return self.planet_displacement


def solve_detailed(model: SineFEModel, crank_angle_rad: float, torque: float,
                   element_size: float = DETAILED_ELEMENT,
                   zone_gap: float = DETAILED_ZONE_GAP) -> DetailedResult:
    """Two-body FE contact at one crank angle with every contact zone refined (element size
    ``element_size``) and conforming; the zones are found from the geometry (module
    constants) and grown until the contact lies inside them.

    Parameters
    ----------
    model : SineFEModel
        The pair, material and supports.
    crank_angle_rad : float
        Crank angle chi [rad].
    torque : float
        Torque carried by the planet [N m] over the face width, either sign, nonzero.
    element_size : float
        Element size along the contact zones [m], 1/500 to 1/10 of the module.
    zone_gap : float
        Initial gap [m] below which a flank is a contact zone, (0, SELECT_GAP_MAX].

    Returns
    -------
    DetailedResult
        The load sharing, the nodal solution and both bodies.

    Raises
    ------
    ToothfemError
        If an argument is outside its range (the torque zero).
    toothfem.fem.contact.ContactError
        If the contact does not stay inside zones of initial gap up to SELECT_GAP_MAX.
    """
    check_range("crank_angle_rad", crank_angle_rad)
    check_member_torque(torque, "planet")
    m = model.pair.module_m
    check_range("element_size", element_size, 0.002 * m, 0.1 * m,
                why="element size along the contact zones: 1/500 to 1/10 of the module")
    check_range("zone_gap", zone_gap, 0, SELECT_GAP_MAX, lo_open=True)
    while True:
        res = _detailed(model, float(crank_angle_rad), torque, element_size, zone_gap)
        nodes = res.nodes
        loaded = nodes.force > 0
        rigid = abs(res.nodes.rotation) * np.max(np.abs(nodes.arm))
        if (np.max(nodes.g0[loaded]) <= SELECT_MARGIN * zone_gap
                and res.min_gap_outside >= -CHECK_OVERLAP_REL * rigid):
            return res
        if 2 * zone_gap > SELECT_GAP_MAX:
            raise contact.ContactError(
                f"crank angle {math.degrees(crank_angle_rad):.4f} deg: the contact does not "
                f"stay inside zones of initial gap up to {zone_gap * UM_PER_M:.0f} um")
        zone_gap *= 2


def _runs(mask):
    """(start, stop) index pairs of the runs of True in a 1-D mask."""
    d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def _detailed(model, chi, torque, h, zone_gap) -> DetailedResult:
    pair = model.pair
    pt, rt = _planet_toothed(pair), _ring_toothed(pair)
    k = model.candidates
    j0 = int(np.round(chi * pair.ring_teeth / (2 * math.pi)))
    centre, theta = sine.planet_pose(pair, chi)
    th, centre = float(theta[0]), centre[:, 0]

    def placed(p):                   # planet frame -> ring frame
        return rotate(p, th) + centre[:, None]

    n_tooth = int(math.ceil(pt.length / h))
    step = pt.length / n_tooth
    sig = ((j0 - k) * n_tooth + np.arange((2 * k + 1) * n_tooth)) * step
    kp = placed(pt.point(sig))
    _, g0, nrm = ring_foot(pair, kp)
    rel = kp - centre[:, None]
    arm = rel[0] * nrm[1] - rel[1] * nrm[0]
    zones: list[tuple[int, int]] = []
    side = 1.0 if torque > 0 else -1.0      # a negative torque loads the other flanks
    for a, b in _runs((g0 < zone_gap) & (side * arm < 0)):
        a, b = max(a - ZONE_PAD, 0), min(b + ZONE_PAD, sig.size)
        if zones and a <= zones[-1][1]:
            zones[-1] = (zones[-1][0], b)
        else:
            zones.append((a, b))
    if not zones:
        raise contact.ContactError(f"crank angle {math.degrees(chi):.4f} deg: no loaded-side "
                                   f"flank within {zone_gap * UM_PER_M:.1f} um")
    zone_phi = [pt.phi_of_sigma(sig[a:b]) for a, b in zones]
    zone_pts = [pt.curve(ph)[0] for ph in zone_phi]
    ring_phi = [ring_foot(pair, placed(zp))[0] for zp in zone_pts]
    allz = np.concatenate(zone_pts, axis=1)
    size_max, coarse = SIZE_MAX_REL * h, COARSE_STEP_REL * h
    refine = [Refinement(allz, h, 2 * h, 40 * h)]
    pm = mesh_rings([_outline(pt, zone_phi, coarse), _circle(model.planet_bore_radius)], size_max,
                    refine, names=["profile", "bore"], keep_below=1.5 * h)
    planet = Body(pm, model.youngs_modulus, model.poisson_ratio, pm.ring_nodes("bore"),
                  model.plane)
    ring_pts = np.concatenate([rt.curve(f)[0] for f in ring_phi], axis=1)
    rm = mesh_rings([_circle(model.ring_outer_radius), _outline(rt, ring_phi, coarse)], size_max,
                    [Refinement(ring_pts, h, 2 * h, 40 * h)], names=["rim", "profile"],
                    keep_below=1.5 * h)
    ring = Body(rm, model.youngs_modulus, model.poisson_ratio, rm.ring_nodes("rim"),
                model.plane)
    facets = np.concatenate([_boundary_chain(pm, "profile", zp)[1] for zp in zone_pts])
    slave = contact.slave_surface(planet, facets)
    kp = placed(slave.points)
    _, g0, nrm = ring_foot(pair, kp)
    foot = kp - g0 * nrm
    rel = kp - centre[:, None]
    arm = rel[0] * nrm[1] - rel[1] * nrm[0]
    load_p = contact.nodal_load_matrix(planet.basis.N, slave.dofs, rotate(nrm, -th))
    on_ring = contact.nearest_on_boundary(rm, "profile", foot) - 1e-6 * h * nrm
    load_r = ring.point_load_matrix(on_ring, nrm)
    hmat = planet.flexibility(load_p) + ring.flexibility(load_r)
    sol = contact.solve_contact(hmat, g0, arm, torque / model.face_width)
    u_p = planet.solve(load_p @ sol.force)
    u_r = ring.solve(-(load_r @ sol.force))
    # planet parameter of each node (star-shaped profile: the polar angle), its column
    phi = np.arctan2(slave.points[1], slave.points[0])
    ref = j0 * pt.dphi
    phi = ref + np.mod(phi - ref + math.pi, 2 * math.pi) - math.pi
    sigma = pt.sigma_of_phi(phi)
    tooth = np.floor(sigma / pt.length).astype(int)
    column = _flank_columns(j0, k, tooth, sigma - tooth * pt.length >= 0.5 * pt.length)
    nodes = PositionResult(crank_angle=chi, hat=np.arange(slave.points.shape[1]), point=kp,
                           sigma=sigma, g0=g0, arm=arm, force=sol.force,
                           pressure=slave.pressure(sol.force), gap=sol.gap, column=column,
                           rotation=sol.rigid, iterations=sol.iterations, select_gap=zone_gap)
    # loaded gap outside the zones: every CHECK_SPACING on the candidate teeth
    n_chk = int(math.ceil(pt.length / CHECK_SPACING))
    sc = ((j0 - k) * n_chk + np.arange((2 * k + 1) * n_chk)) * (pt.length / n_chk)
    inside = np.zeros(sc.size, bool)
    for a, b in zones:
        inside |= (sc >= sig[a]) & (sc <= sig[b - 1])
    sc = sc[~inside]
    pc = pt.point(sc)
    kc = placed(pc)
    _, gc, nc = ring_foot(pair, kc)
    relc = kc - centre[:, None]
    armc = relc[0] * nc[1] - relc[1] * nc[0]
    pc_in = contact.nearest_on_boundary(pm, "profile", pc) + 1e-3 * h * pt.inward_normal(sc)
    up = planet.point_load_matrix(pc_in, rotate(nc, -th)).T @ u_p
    rc_in = contact.nearest_on_boundary(rm, "profile", kc - gc * nc) - 1e-3 * h * nc
    ur = ring.point_load_matrix(rc_in, nc).T @ u_r
    loaded_gap = gc + sol.rigid * armc + up - ur
    state = sine.meshing(pair, [chi], candidates=k)
    rec = _record("detailed", model, state, [nodes], torque, pt)
    return DetailedResult(load_sharing=rec, nodes=nodes, dofs=planet.basis.N + ring.basis.N,
                          planet=planet, planet_displacement=u_p, ring=ring,
                          ring_displacement=u_r, zone_gap=zone_gap,
                          min_gap_outside=float(np.min(loaded_gap)) if sc.size else np.inf)
