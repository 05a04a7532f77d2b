"""Detailed mode of the cycloid disc: two-body FE contact with the zones of one position
refined (fem/cycloid_fe/__init__.py)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..hertz import hertz_line
from ...errors import ToothfemError
from ...geometry.vectors import rotate
from .. import contact
from ..elastic import Body
from ..load_sharing import LoadSharing, check_member_torque
from ..mesh import Refinement, mesh_rings
from .built_stage import pin_moves
from .cycle import _seed_guess
from .record import record
from . import flanks as fl
from .model import CycloidFEModel, _held_nodes, _positions, _Position, housing_body

# ---------------------------------------------------------------------------------------
# Detailed mode

#: Slave zone half-width per estimated Hertz half-width (the contact must end inside it),
#: and the safety factor on the seed's force when estimating that half-width.
DETAILED_ZONE_REL, DETAILED_FORCE_MARGIN = 1.6, 1.6
#: A conventional pin's mesh: elements of h to b_zone from its contact point, graded to
#: rz/4 at 20 b_zone. Against 2 b_zone and 40 b_zone (the integral housing's, which stays:
#: its wide body moves the forces by 3 % with this grading) the pin forces move by under
#: 4e-4 of the largest, the transmission error by 3.5e-4 and the FE peak pressure by 3e-4
#: at three crank angles of the pin-housing drive, with a third fewer dofs.
PIN_REFINED_REL, PIN_GRADED_REL = 1.0, 20.0


@dataclass(frozen=True, kw_only=True)
class DetailedResult:
    """One position of the detailed mode: the load sharing plus the pressure profiles."""
    load_sharing: LoadSharing
    slave_points: list          # per candidate pin: (2, M) disc-frame points
    pressure: list              # per candidate pin: (M,) Pa
    pins: np.ndarray            # candidate pin indices
    dofs: int
    disc: Body | None = None    # the disc (disc frame)
    disc_displacement: np.ndarray | None = None

    @property
    def member_body(self):
        """The moving member's Body (the disc), as every drive's detailed result names it."""
        return self.disc

    @property
    def member_displacement(self):
        return self.disc_displacement


#: The detailed mode's choices of candidate pins (solve_detailed's ``flanks``).
FLANKS = ("loaded", "both")


def solve_detailed(model: CycloidFEModel, crank_angle_rad: float, torque: float,
                   elements_per_halfwidth: int = 6, deviation=None,
                   force_margin: float = DETAILED_FORCE_MARGIN,
                   flanks: str = "loaded") -> DetailedResult:
    """Two-body FE contact at one crank angle with the contact zones refined and conforming.

    The zone sizes come from the seed's force estimate times a margin; after the solve the
    contact must end inside each slave zone (checked).

    The disc is the modified disc of the case: equidistant and move-distance in its
    generating profile, a rotation modification as the two turned flanks
    (:mod:`toothfem.fem.cycloid_fe.flanks`: meshed in the pose where the loaded flank lies
    where the unmodified one did; the transmission error counts from the nominal pose).

    Parameters
    ----------
    model : CycloidFEModel
        With elastic pins (conventional or integral).
    crank_angle_rad : float
        Crank angle [rad].
    torque : float
        Disc torque [N m], nonzero; a negative one loads the other flank of each lobe.
    elements_per_halfwidth : int
        Element size in the zones: the estimated Hertz half-width over this.
    deviation : toothfem.fem.deviations.CycloidDeviation, optional
        The pins moved and resized in the meshes themselves (conventional pins; the check
        of the cycle mode's gap shifts, docs/tolerance.md); profile deviations are the
        cycle mode's only.
    force_margin : float
        The largest pin force over the seed's, for the zone sizes (deviations of a few
        micrometres can load a pin several times the seed's force).
    flanks : {"loaded", "both"}
        Candidate pins: those whose moment arm can carry the torque (the cycle mode's
        default), or every pin, each on the flank it faces (an idle flank that closes, as
        with interference, takes load: the cycle mode's ``sides=(0,)``). Both flanks
        mesh the disc with twice the zones, which moves single pin forces by up to 6 %
        (docs/fem.md, issue 28): the default stays with the loaded flank.

    Returns
    -------
    DetailedResult
        The load sharing of the one position and the FE pressure profiles.

    Raises
    ------
    ToothfemError
        For a zero or non-finite torque, rigid pins, ``flanks`` not one of
        :data:`FLANKS`, or a deviation the mode cannot mesh (profile deviations, integral
        pins).
    toothfem.fem.contact.ContactError
        If the contact reaches the edge of a refined zone (raise ``force_margin``).
    """
    check_member_torque(torque, "disc")
    if model.pin_structure == "rigid":
        raise ToothfemError("the detailed mode models elastic pins (conventional or integral)")
    if flanks not in FLANKS:
        raise ToothfemError(f"flanks = {flanks!r} is not one of {list(FLANKS)}")
    g = model.geometry
    gen = g.generating()
    # a negative torque loads the other flank of each lobe
    side = 1 if torque > 0 else -1
    (q,), state = _positions(model, [crank_angle_rad], side=0 if flanks == "both" else side)
    turns = fl.flank_turn(g, side, q.arm)
    nominal, q = q, _on_flanks(gen, q, turns)
    # a rotation modification: each pin meets the part of a turned flank that bounds the
    # disc. One whose foot point falls past the corner where the two turned flanks meet
    # faces the other flank there: projected on it (the exact intersection's gap, as the
    # cycle mode has it: at 1 deg on the pin-housing drive the pins facing the tip corner
    # stand 36-319 um clear). One off both faces the corner itself: it keeps its flank's
    # contact zone, its gap raised to the exact intersection's (``corner_gap``), the
    # cycle mode's gap for every pin
    corner_gap = np.full(q.pins.size, np.nan)
    keep = fl.bounds_disc(g, side, q.psi, turns)
    if not keep.all():
        first = turns
        turns = np.where(keep, turns, np.where(turns == 0, 2 * side * g.rotation_rad, 0.0))
        q = _on_flanks(gen, nominal, turns)
        off = ~fl.bounds_disc(g, side, q.psi, turns)
        if off.any():
            turns = np.where(off, first, turns)
            q = _on_flanks(gen, nominal, turns)
            corner_gap[off] = nominal.gap[off]
    centres, radii = q.pin_centre, np.full(q.pins.size, g.pin_radius_m)
    if deviation is not None:
        if model.pin_structure != "conventional" or np.any(deviation.profile != 0):
            raise ToothfemError("the detailed mode moves and resizes conventional pins only "
                                "(profile deviations: the cycle mode)")
        move, grow = pin_moves(model, q, deviation)
        centres, radii = centres + move, radii + grow
    q_load = torque / model.face_width
    f_est = _seed_guess(q, q_load) * force_margin
    b_zone = float(np.max(hertz_line(np.max(f_est), np.abs(q.r_eq), model.e_star)[1]))
    h = b_zone / elements_per_halfwidth
    theta_d = -crank_angle_rad / g.lobe_count
    housing_centre = rotate(-g.eccentricity_m * np.array([math.cos(crank_angle_rad),
                                                          math.sin(crank_angle_rad)]), -theta_d)
    pin_rings, disc_psi, zone_angles = [], [], []
    for k in range(q.pins.size):
        c, n, rz = centres[:, k], q.normal[:, k], radii[k]
        a0 = math.atan2(-n[1], -n[0])                # direction of the contact on the pin
        half = 3 * b_zone / rz
        n_zone = int(math.ceil(2 * half * rz / h))
        t_zone = a0 + np.linspace(-half, half, n_zone + 1)
        t_rest = a0 + np.linspace(half, 2 * math.pi - half, 73)[1:-1]
        t = np.concatenate([t_zone, t_rest])
        ring = c[:, None] + rz * np.stack([np.cos(t), np.sin(t)])
        pin_rings.append(ring)
        zone_angles.append(t_zone)
        psi, _, _ = fl.project(gen, ring[:, :n_zone + 1], turns[k],
                               np.full(n_zone + 1, q.psi[k]))
        disc_psi.append((psi, turns[k]))
    # disc outline: coarse samples, with each zone replaced by the pins' projections
    rings, names = fl.disc_rings(model, side, disc_psi)
    refine = [Refinement(q.point, h, 2 * b_zone, 60 * b_zone)]
    disc_mesh = mesh_rings(rings, size_max=g.pin_circle_radius_m / 25, refinements=refine,
                           names=names, keep_below=2 * h)
    held = _held_nodes(disc_mesh, model.held_rings(names))
    disc = Body(disc_mesh, model.youngs_modulus, model.poisson_ratio, held, model.plane)
    # slave bodies: one per pin (conventional) or the housing with every pin (integral)
    kps = centres - radii * q.normal
    # separate (conventional) pins are graded sooner (the constants)
    refined, graded = ((PIN_REFINED_REL, PIN_GRADED_REL)
                       if model.pin_structure == "conventional" else (2, 40))
    refine_pins = [Refinement(kps, h, refined * b_zone, graded * b_zone)]
    groups = []                     # (body, [facets of each candidate pin])
    if model.pin_structure == "integral":
        c_t, s_t = math.cos(-theta_d), math.sin(-theta_d)
        centre_h = g.eccentricity_m * np.array([math.cos(crank_angle_rad),
                                                math.sin(crank_angle_rad)])

        def to_disc(x):             # housing frame -> disc frame
            d = x - centre_h[:, None]
            return np.stack([c_t * d[0] - s_t * d[1], s_t * d[0] + c_t * d[1]])
        zones = {int(j): t + theta_d for j, t in zip(q.pins, zone_angles)}
        housing = housing_body(model, zones, refine_pins, 2 * h, to_disc)
        p = housing.mesh.p
        f_all = housing.body_mesh.rings["teeth"]
        mid = 0.5 * (p[:, housing.mesh.facets[0, f_all]] + p[:, housing.mesh.facets[1, f_all]])
        groups.append((housing, [f_all[np.hypot(*(mid - kps[:, k:k + 1]))
                                       < DETAILED_ZONE_REL * b_zone]
                                 for k in range(q.pins.size)]))
    else:
        for k, ring in enumerate(pin_rings):
            c = centres[:, k]
            pm = mesh_rings([ring], size_max=radii[k] / 4, refinements=refine_pins, keep_below=2 * h)
            p = pm.mesh.p
            outward = (c - housing_centre) / np.hypot(*(c - housing_centre))
            bnodes = pm.ring_nodes("outer")
            held_pin = bnodes[np.sum((p[:, bnodes] - c[:, None]) * outward[:, None], axis=0) > 0]
            pin = Body(pm, model.youngs_modulus, model.poisson_ratio, held_pin, model.plane)
            f = pm.rings["outer"]
            mid = 0.5 * (p[:, pm.mesh.facets[0, f]] + p[:, pm.mesh.facets[1, f]])
            groups.append((pin, [f[np.hypot(*(mid - kps[:, k:k + 1]))
                                   < DETAILED_ZONE_REL * b_zone]]))
    slaves, h_blocks, master_pts, normals = [], [], [], []
    dofs = disc.basis.N
    k = 0
    for body, facet_sets in groups:
        group_dofs, group_normals = [], []
        for f in facet_sets:
            sl = contact.slave_surface(body, f)
            _, master, nrm = fl.project(gen, sl.points, turns[k],
                                        np.full(sl.points.shape[1], q.psi[k]))
            group_dofs.append(sl.dofs)
            group_normals.append(nrm)
            slaves.append(sl)
            master_pts.append(master)
            normals.append(nrm)
            k += 1
        loads = contact.nodal_load_matrix(body.basis.N, np.concatenate(group_dofs, axis=1),
                                          np.concatenate(group_normals, axis=1))
        h_blocks.append(body.flexibility(loads))
        dofs += body.basis.N
    proj = np.concatenate(master_pts, axis=1)
    nrm = np.concatenate(normals, axis=1)
    pts = np.concatenate([s.points for s in slaves], axis=1)
    from scipy.linalg import block_diag

    # evaluate the disc at the polygon point, a hair inside (the element finder needs it)
    on_mesh = contact.nearest_on_boundary(disc_mesh, "profile", proj) - 1e-6 * h * nrm
    load_d = disc.point_load_matrix(on_mesh, nrm)
    hmat = block_diag(*h_blocks) + disc.flexibility(load_d)
    g0 = np.sum((pts - proj) * nrm, axis=0)
    start = 0
    for k, sl in enumerate(slaves):     # a pin facing the corner: the exact gap
        n_k = sl.points.shape[1]
        if np.isfinite(corner_gap[k]):
            lift = corner_gap[k] - np.min(g0[start:start + n_k])
            g0[start:start + n_k] += max(lift, 0.0)
        start += n_k
    c_rot = -(proj[0] * nrm[1] - proj[1] * nrm[0])          # -n . (k x x) = -(x x n)
    sol = contact.solve_contact(hmat, g0, c_rot, q_load)
    u_disc = disc.solve(-(load_d @ sol.force))
    # per pin
    zb = g.pin_count
    force = np.zeros((1, zb))
    gap = np.where(np.isfinite(state.gap), state.gap, np.inf).copy()
    pressures, start = [], 0
    arm_fe = state.moment_arm.copy()
    for k, sl in enumerate(slaves):
        lam = sol.force[start:start + sl.points.shape[1]]
        edge = np.concatenate([np.flatnonzero(lam > 0)])
        if edge.size and np.any(np.hypot(*(sl.points[:, edge] - kps[:, k:k + 1]))
                                > 0.95 * DETAILED_ZONE_REL * b_zone):
            raise contact.ContactError(f"pin {q.pins[k]}: the contact reaches the edge of the "
                                       "refined zone; raise force_margin")
        force[0, q.pins[k]] = lam.sum() * model.face_width
        if lam.sum() > 0:   # the moment arm of the resultant of the nodal forces
            arm_fe[0, q.pins[k]] = np.sum(lam * c_rot[start:start + lam.size]) / lam.sum()
        gap[0, q.pins[k]] = 0.0 if lam.sum() > 0 else np.min(sol.gap[start:start + lam.size])
        pressures.append(sl.pressure(lam))
        start += lam.size
    # the solve's rotation counts from the meshed pose, turned side Delta delta
    rec = record("detailed", model, state, force, gap,
                  np.array([sol.rigid + fl.frame_turn(g, side)]), torque)
    # P_h: Hertz's on the FE force where its assumptions hold, the FE peak where they fail
    # (b not small against the radii); the FE profiles stay in DetailedResult.pressure.
    invalid = rec.hertz_invalid
    ph = rec.ph.copy()
    for k, pr in enumerate(pressures):
        if invalid[0, q.pins[k]]:
            ph[0, q.pins[k]] = float(np.max(pr))

    rec = dataclasses.replace(rec, ph=ph, pressure_from_fe=invalid, moment_arm=arm_fe)
    return DetailedResult(load_sharing=rec, slave_points=[s.points for s in slaves],
                          pressure=pressures, pins=q.pins, dofs=dofs, disc=disc,
                          disc_displacement=u_disc)


def _on_flanks(gen, q: _Position, turns) -> _Position:
    """The candidates' contact points, normals and parameters on the profile each one
    faces (turned by ``turns``, the detailed mode's frame: :func:`flanks.flank_turn`)."""
    moved = np.flatnonzero(turns)
    if not moved.size:
        return q
    psi, point, normal = q.psi.copy(), q.point.copy(), q.normal.copy()
    for k in moved:
        psi[k:k + 1], point[:, k:k + 1], normal[:, k:k + 1] = fl.project(
            gen, q.pin_centre[:, k:k + 1], turns[k], q.psi[k:k + 1])
    return dataclasses.replace(q, psi=psi, point=point, normal=normal)
