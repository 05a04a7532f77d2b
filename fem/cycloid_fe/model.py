"""The cycloid FE model: the disc and its pins or integral housing as bodies, the disc-frame
geometry of the candidate contacts, the pin compliance table (fem/cycloid_fe/__init__.py)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ...errors import ToothfemError, check_range
from ...geometry import cycloid_mesh as cy
from ...geometry.cycloid import CycloidGeometry, inward_normal, working_profile
from ...geometry.cycloid_backlash import before_load
from ...geometry.cycloid_distance import foot_point
from ...geometry.vectors import rotate
from .. import contact
from ..elastic import Body, SameMaterial, plane_modulus
from ..mesh import Refinement, mesh_rings
from ...geometry.disc import DiscHolesSI


#: Candidate pins: moment arm below this fraction of r_a on the load-carrying side (a pin
#: with an arm of the wrong sign separates under the rigid rotation).
CANDIDATE_ARM_REL = 0.02
#: Iterations of the Hertz local approach (b depends on F) and their tolerance.
LOCAL_MAX_ITER, LOCAL_RTOL = 50, 1e-9


#: Crank angles over one meshing period at which the model describes the disc before load.
BEFORE_LOAD_POSITIONS = 36


#: conventional: pins in housing grooves (elastic pins held on their outer half);
#: integral: pins one piece with the housing (clamped at its outer radius);
#: rigid: rigid fixed pins, only the disc deforms (the CalculiX peer's model; cycle mode).
PIN_STRUCTURES = ("conventional", "integral", "rigid")


@dataclass(frozen=True, kw_only=True)
class CycloidFEModel(SameMaterial):
    """A disc, its pins and material; torques in N m over the face width."""
    geometry: CycloidGeometry
    holes: DiscHolesSI
    youngs_modulus: float
    poisson_ratio: float
    face_width: float
    pin_structure: str = "conventional"
    plane: str = "strain"
    housing_outer_radius: float | None = None   # integral structure: clamped outer edge, m

    def describe(self) -> dict:
        """The model's choices as a report shows them, and the disc on its pins before load.

        Returns
        -------
        dict
            ``pin_structure`` and, over one meshing period (:data:`BEFORE_LOAD_POSITIONS`
            crank angles), :func:`toothfem.geometry.cycloid_backlash.before_load` of the
            modified disc: backlash of both flanks, clearance or interference before load
            (um, which pins, which flank).
        """
        g = self.geometry
        phis = np.linspace(0.0, 2 * math.pi / g.pin_count, BEFORE_LOAD_POSITIONS,
                           endpoint=False)
        return {"pin_structure": self.pin_structure, **before_load(g, phis)}

    def __post_init__(self):
        check_range("youngs_modulus", self.youngs_modulus, 0, None, lo_open=True)
        check_range("face_width", self.face_width, 0, None, lo_open=True)
        if self.pin_structure not in PIN_STRUCTURES:
            raise ToothfemError(f"pin_structure = {self.pin_structure!r} is not one of "
                                f"{list(PIN_STRUCTURES)}")
        if self.pin_structure == "integral":
            g = self.geometry
            check_range("housing_outer_radius", self.housing_outer_radius,
                        g.pin_circle_radius_m + g.pin_radius_m, None, lo_open=True)
        if self.holes.crank_hole_count < 1 and self.holes.centre_bore_radius_m <= 0:
            raise ToothfemError("the disc needs crank holes (crank_hole_count >= 1, a 2K-V "
                                "drive) or a centre bore (centre_bore_radius_mm > 0, a K-H-V "
                                "drive's eccentric bearing) to be held")

    def held_rings(self, names) -> list:
        """The hole rings that hold the disc in the FE (a rigid coupling): its crank holes
        (2K-V: the crank bearings carry it), else its centre bore (K-H-V: the eccentric
        bearing). The system model moves that coupling as the disc's rigid body.

        Parameters
        ----------
        names : sequence of str
            The mesh's ring names.

        Returns
        -------
        list of str
        """
        kind = "crank" if self.holes.crank_hole_count >= 1 else "centre_bore"
        return [n for n in names if n.startswith(kind)]



# ---------------------------------------------------------------------------------------
# Shared geometry helpers (disc frame)

@dataclass(frozen=True)
class _Position:
    """Candidate contacts of one crank angle in the disc frame."""
    phi: float
    pins: np.ndarray          # (C,) pin indices
    pin_centre: np.ndarray    # (2, C)
    psi: np.ndarray           # (C,) profile parameter of the nominal contact
    point: np.ndarray         # (2, C) contact point on the disc profile
    normal: np.ndarray        # (2, C) outward normal of the disc (from disc into pin)
    arm: np.ndarray           # (C,) moment arm, MeshingState sign (carrying: < 0)
    gamma: np.ndarray         # (C,) contact angle on the pin from the housing-centre direction
    gap: np.ndarray           # (C,) initial clearance
    r_eq: np.ndarray          # (C,) equivalent radius
    r_disc: np.ndarray        # (C,) signed curvature radius of the disc profile


def _positions(model: CycloidFEModel, phis, state=None, side: int = 1):
    """Candidate contacts per crank angle for a disc torque of sign ``side``: +1 the pins
    with moment arm below CANDIDATE_ARM_REL r_a (MeshingState sign: carrying a positive
    torque), -1 those above -CANDIDATE_ARM_REL r_a (the other flank of each lobe), 0 every
    pin.

    Points, normals and profile parameters are those of the generating profile without
    the rotation modification: with one, they are the loaded flank's in the pose where the
    disc has turned by side Delta delta (0: +1) and that flank lies where the unmodified
    one did; ``gap`` is g0 of :func:`toothfem.geometry.cycloid_mesh.clearance_exact`
    linearised about that pose (docs/derivations.md 8)."""
    g = model.geometry
    gen = g.generating()
    state = state or cy.meshing(g, phis)
    r_a = g.disc_pitch_radius_m
    # a rotation modification: every candidate's gap linearised about the pose where the
    # flank of this torque sign lies where the unmodified one did (docs/derivations.md 8)
    gaps = cy.clearance_exact(g, state.position_rad, side or 1) if g.rotation_rad \
        else state.gap
    out = []
    for p, phi in enumerate(state.position_rad):
        pins = np.flatnonzero(side * state.moment_arm[p] < CANDIDATE_ARM_REL * r_a)
        c_house = cy.pin_centres(g)[:, pins]
        c_disc = cy.to_disc_frame(g, [phi], c_house[:, None, :])[:, 0, :]
        psi0 = 2 * math.pi * pins / g.pin_count + phi / g.lobe_count
        psi, _ = foot_point(gen, c_disc, psi0)
        point = working_profile(gen, psi)
        normal = -inward_normal(gen, psi)
        # contact angle on the pin, in the housing frame (the groove is fixed there)
        towards = -c_house / np.hypot(*c_house)
        d = rotate(-normal, -phi / g.lobe_count)
        gamma = np.arctan2(towards[0] * d[1] - towards[1] * d[0], np.sum(towards * d, axis=0))
        out.append(_Position(float(phi), pins, c_disc, psi, point, normal,
                             state.moment_arm[p, pins], gamma, gaps[p, pins],
                             state.equivalent_radius[p, pins], state.radius_moving[p, pins]))
    return out, state


def _disc_rings(model: CycloidFEModel, inserts=(), base_per_lobe=48):
    """Disc outline sampled on the exact profile: ``base_per_lobe`` points per lobe, with
    each array of profile parameters in ``inserts`` (a contact zone) put in place of the
    coarse samples it covers (a half-step margin: no sliver segment beside a zone); plus
    the hole circles."""
    g = model.geometry
    gen = g.generating()
    base = np.linspace(0, 2 * math.pi, g.lobe_count * base_per_lobe, endpoint=False)
    margin = 0.5 * (base[1] - base[0])
    keep = np.ones(base.size, bool)
    for psi in inserts:
        lo, hi = np.min(psi) - margin, np.max(psi) + margin
        keep &= ~(np.mod(base - lo, 2 * math.pi) <= hi - lo)
    psi = np.sort(np.mod(np.concatenate([base[keep]] + list(inserts)), 2 * math.pi))
    psi = psi[np.concatenate([[True], np.diff(psi) > 1e-12])]
    rings, names = [working_profile(gen, psi)], ["profile"]
    for x, y, r, label in model.holes.circles():
        n = max(48, int(2 * math.pi * r / (0.02 * g.pin_circle_radius_m)))
        t = np.linspace(0, 2 * math.pi, n, endpoint=False)
        rings.append(np.stack([x + r * np.cos(t), y + r * np.sin(t)]))
        names.append(label)
    return rings, names


def _window(gen, lo, hi, spacing):
    """Profile parameters from lo to hi at most ``spacing`` apart along the curve."""
    mid = 0.5 * (lo + hi)
    speed = np.hypot(*(working_profile(gen, mid + 1e-7)
                       - working_profile(gen, mid - 1e-7))) / 2e-7
    n = max(int(math.ceil((hi - lo) * speed / spacing)), 2)
    return np.linspace(lo, hi, n + 1)


def _held_nodes(body_mesh, labels):
    return np.unique(np.concatenate([body_mesh.ring_nodes(n) for n in labels]))


# ---------------------------------------------------------------------------------------
# Pin compliance table (conventional pin held on its outer half)

#: The pin table's mesh: elements of b_ref/5 along the loaded half and to a depth of
#: b_ref/2, graded to r/6 at a depth of 10 b_ref. Measured against the former mesh (b_ref/5
#: to a depth of 2 b_ref, graded to r/2; 81.5k dofs against 29k here) on the pin-housing
#: drive: the table differs by under 0.4 % at every contact angle a drive uses (the noise
#: of the patch loads' sampling: b_ref/8 moves it as much), the cycle's pin forces by
#: under 1e-4 of the largest, the transmission error by 2e-4.
PIN_ELEMENTS_PER_BREF, PIN_REFINED_DEPTH_REL, PIN_GRADED_DEPTH_REL = 5, 0.5, 10.0


@dataclass(eq=False)
class PinModel:
    """One pin (radius rz, centre at the origin, housing on the +x side) held over its
    outer half; compliance along the inward normal at contact angle gamma (measured from
    -x, the direction toward the housing centre), for Hertzian strips of half-width b."""
    radius: float
    youngs_modulus: float
    poisson_ratio: float
    b_ref: float
    plane: str = "strain"
    angles: np.ndarray = field(default_factory=lambda: np.linspace(-0.5 * math.pi,
                                                                   0.5 * math.pi, 37))

    @cached_property
    def body(self):
        r = self.radius
        h = self.b_ref / PIN_ELEMENTS_PER_BREF
        t = np.linspace(0, 2 * math.pi, 2 * max(int(math.pi * r / h), 64), endpoint=False)
        ring = r * np.stack([np.cos(t), np.sin(t)])
        inner = np.cos(t) < 0.05            # the half facing the disc, refined
        ring = ring[:, inner | (np.arange(t.size) % 8 == 0)]
        bm = mesh_rings([ring], size_max=r / 6,
                        refinements=[Refinement(ring[:, ring[0] < 0], h,
                                                PIN_REFINED_DEPTH_REL * self.b_ref,
                                                PIN_GRADED_DEPTH_REL * self.b_ref)])
        p = bm.mesh.p
        held = bm.ring_nodes("outer")
        held = held[p[0, held] > 0]
        return Body(bm, self.youngs_modulus, self.poisson_ratio, held, self.plane)

    @cached_property
    def table(self) -> np.ndarray:
        """Compliance at b_ref for each angle in ``angles`` (m per N/m)."""
        pts = self.radius * np.stack([-np.cos(self.angles), -np.sin(self.angles)])
        normals = -pts / self.radius              # load pushes the pin surface inward
        loads = patch_loads(self.body, "outer", pts, normals, self.b_ref)
        return np.array([c[0, 0] for c in self.body.flexibility(loads, [1] * pts.shape[1])])

    def compliance(self, gamma, b):
        """C(gamma, b) = C_table(gamma) - (2/(pi E')) ln(b / b_ref).

        Parameters
        ----------
        gamma : array_like
            Contact angles on the pin [rad] from the direction toward the housing centre.
        b : array_like
            Hertz half-widths [m].

        Returns
        -------
        numpy.ndarray
            Compliance along the inward normal [m per N/m], the broadcast shape.
        """
        c_ref = np.interp(gamma, self.angles, self.table)
        e_p = plane_modulus(self.youngs_modulus, self.poisson_ratio, self.plane)
        return c_ref + strip_width_correction(b, self.b_ref, e_p)


def patch_loads(body, ring, points, normals, b_ref):
    """Unit loads: Hertzian strips of half-width ``b_ref`` centred at each point along
    ``normals`` over the body's ``ring`` boundary nodes (vertices and midsides); the same
    vectors measure the work-conjugate mean normal displacement.

    Parameters
    ----------
    body : toothfem.fem.elastic.Body
        The loaded body.
    ring : str
        Name of the boundary ring carrying the strips.
    points : numpy.ndarray, shape (2, K)
        Strip centres [m].
    normals : numpy.ndarray, shape (2, K)
        Load directions (unit).
    b_ref : float
        Strip half-width [m].

    Returns
    -------
    scipy.sparse.csc_matrix, shape (N_dofs, K)
        One unit load per column.

    Raises
    ------
    ToothfemError
        If fewer than three boundary nodes lie within ``b_ref`` of a point.
    """
    from scipy.sparse import coo_matrix
    from scipy.spatial import cKDTree

    sl = contact.slave_surface(body, body.body_mesh.rings[ring])
    # the surface nodes near each point, found at once (a k-d tree; a radius a hair over
    # b_ref, then the exact test below, so that round-off in the tree drops no node)
    candidates = cKDTree(sl.points.T).query_ball_point(np.asarray(points, float).T,
                                                       b_ref * (1 + 1e-9))
    rows, cols, vals = [], [], []
    for k, found in enumerate(candidates):
        found = np.sort(np.asarray(found, int))
        d = np.hypot(*(sl.points[:, found] - points[:, k:k + 1]))
        near, d = found[d < b_ref], d[d < b_ref]
        if near.size < 3:
            raise ToothfemError(f"the mesh does not resolve the load patch b_ref = {b_ref:.3g} m "
                                f"at ({points[0, k]:.6g}, {points[1, k]:.6g}) m")
        w = sl.weights[near] * np.sqrt(1 - (d / b_ref) ** 2)
        w /= w.sum()
        for comp in (0, 1):
            rows.append(sl.dofs[comp, near])
            cols.append(np.full(near.size, k))
            vals.append(w * normals[comp, k])
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(body.basis.N, points.shape[1])).tocsc()


# ---------------------------------------------------------------------------------------
# Integral pin housing: one body, the pins machined into its bore

#: Angular steps of the housing's outline (rad): on the pin arcs (radius rz) and on the
#: arcs of radius Rz between them (chord sag 1.9 um and 1 um for the pin-housing drive).
HOUSING_STEP, HOUSING_BORE_STEP = math.radians(5), math.radians(0.5)


def housing_rings(model: CycloidFEModel, zones: dict, transform=None):
    """(inner toothed ring, outer circle) of the integral housing.

    The inner boundary is the circle of radius Rz with the inner half of every pin circle
    protruding from it.

    Parameters
    ----------
    model : CycloidFEModel
        The drive (integral pin structure: ``housing_outer_radius`` set).
    zones : dict of int to array_like
        Pin index -> angles t [rad] (housing frame, around the pin centre) that must be
        vertices.
    transform : callable, optional
        ``transform(points) -> points`` maps the housing frame to the frame of the caller
        (the disc frame in the detailed mode).

    Returns
    -------
    inner, outer : numpy.ndarray, shape (2, N)
        The two rings [m].

    Raises
    ------
    ToothfemError
        If a zone leaves its pin's inner arc.
    """
    g = model.geometry
    rz, big_r = g.pin_radius_m, g.pin_circle_radius_m
    alpha = math.acos(-rz / (2 * big_r))       # pin circle meets the circle of radius Rz
    pts = []
    for j in range(g.pin_count):
        a_c = 2 * math.pi * j / g.pin_count
        c = big_r * np.array([math.cos(a_c), math.sin(a_c)])
        t0, t1 = a_c - alpha, a_c + alpha - 2 * math.pi     # going round the inner side
        n = max(int((t0 - t1) / HOUSING_STEP), 8)
        t = np.linspace(t0, t1, n + 1)
        if j in zones:     # zone angles brought into this arc's range (t1, t0)
            z = np.sort(t1 + np.mod(np.asarray(zones[j]) - t1, 2 * math.pi))[::-1]
            if z[0] >= t0 or z[-1] <= t1:
                raise ToothfemError(f"contact zone on pin {j} leaves the pin's inner arc")
            step = (t0 - t1) / n
            t = np.concatenate([t[t > z[0] + 0.5 * step], z, t[t < z[-1] - 0.5 * step]])
        pts.append(c[:, None] + rz * np.stack([np.cos(t), np.sin(t)]))
        # arc of radius Rz to where the next pin's circle meets it
        end = pts[-1][:, -1]
        a_n = 2 * math.pi * (j + 1) / g.pin_count
        start = big_r * np.array([math.cos(a_n), math.sin(a_n)]) + rz * np.array(
            [math.cos(a_n - alpha), math.sin(a_n - alpha)])
        a_end = math.atan2(end[1], end[0])
        a_start = a_end + np.mod(math.atan2(start[1], start[0]) - a_end, 2 * math.pi)
        m = max(int((a_start - a_end) / HOUSING_BORE_STEP), 1)
        arc = np.linspace(a_end, a_start, m + 1)[1:-1]
        pts.append(big_r * np.stack([np.cos(arc), np.sin(arc)]))
    inner = np.concatenate(pts, axis=1)
    r_out = model.housing_outer_radius
    t = np.linspace(0, 2 * math.pi, 360, endpoint=False)
    outer = r_out * np.stack([np.cos(t), np.sin(t)])
    if transform is not None:
        inner, outer = transform(inner), transform(outer)
    return inner, outer


def housing_body(model, zones, refinements, keep_below, transform=None):
    """The integral housing as an elastic body, clamped at its outer circle.

    Parameters
    ----------
    model : CycloidFEModel
        The drive (integral pin structure).
    zones : dict of int to array_like
        As :func:`housing_rings`.
    refinements : list of toothfem.fem.mesh.Refinement
        Mesh refinements (contact zones).
    keep_below : float
        Ring segments shorter than this [m] stay single element edges (conforming contact
        zones; :func:`toothfem.fem.mesh.mesh_rings`).
    transform : callable, optional
        As :func:`housing_rings`.

    Returns
    -------
    toothfem.fem.elastic.Body
        Rings named "outer" (held) and "teeth".
    """
    inner, outer = housing_rings(model, zones, transform)
    bm = mesh_rings([outer, inner], size_max=model.geometry.pin_circle_radius_m / 25,
                    refinements=refinements, names=["outer", "teeth"], keep_below=keep_below)
    return Body(bm, model.youngs_modulus, model.poisson_ratio, bm.ring_nodes("outer"),
                model.plane)

def strip_width_correction(b, b_ref, e_plane):
    """Compliance change of a half-space loaded by a Hertzian strip of half-width b instead of
    b_ref: -(2/(pi E')) ln(b/b_ref) (docs/derivations.md, 6).

    Parameters
    ----------
    b : array_like
        Strip half-width [m].
    b_ref : float
        Reference half-width [m].
    e_plane : float
        Plane modulus E' [Pa].

    Returns
    -------
    numpy.ndarray
        Compliance change [m per N/m], shape of ``b``.
    """
    return -(2 / (math.pi * e_plane)) * np.log(np.asarray(b) / b_ref)
