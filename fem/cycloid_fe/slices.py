"""The face width in slices: the disc's contacts with its pins cut along the width into S
slices, each a 2-D plane-strain contact with its own initial gap (the crown's drop and the
disc's tilt at that slice), all slices' loads from one complementarity solve
(docs/face_width.md).

Method. The slicing of ISO/TS 16281:2008 (the roller's contact cut into slices along its
length, each a line contact with its own gap from the profile and the misalignment) and of
the thin-slice gear load distribution (ISO 6336-1:2019 Annex E's K_Hbeta model; Harianto,
Houser, AGMA 98FTM6): each slice s of width w = B/S carries the 2-D problem per unit length
of :class:`~toothfem.fem.cycloid_fe.CycleSolver` (the disc's and the pins' or housing's
compliance from the 2-D FE tables, the Hertz local approach at the slice's own line load),
with the gaps

    g_si = g0_i + d(z_s) - theta z_s (n_i . t) + [H lambda_s]_i + local_i(lambda_s) + beta arm_i

d(z) the crown's drop, theta the imposed tilt, t the in-plane direction of the disc's shift
under the tilt (the direction of the resultant of the pins' forces on the disc: the axis the
two discs' couple turns a disc about, the worst for the loaded pins), beta the disc's turn
(one unknown for every slice: the disc is one rigid body at its holes), and the torque
balance sum_s w sum_i arm_i lambda_si = -T.

Coupling between slices: none through the bodies' compliance (the slices are independent
plane-strain strips, as in ISO/TS 16281 and the thin-slice models); they are coupled only
through the disc's rigid motion (beta, and the imposed tilt). Neglected: the shear transfer
between neighbouring slices, which in 3-D spreads a change of the load along the width over
a length of the order of the contact's depth scale; it makes an independent-slice model
sharper at a step of the gap than 3-D, and it misses the edge singularity of a straight
profile ending at a free face (Johnson 1985, Sec. 5.x) unless the profile is crowned.
The pins are held along their length (conventional pins in grooves, or one piece with the
housing): their per-slice compliance is their 2-D table, no bending between supports.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ...errors import ToothfemError, check_range
from ...geometry import cycloid_mesh as cy
from .. import contact
from ..datasheet.supports import simply_supported_influence
from ..linsolve import one_blas_thread
from ..load_sharing import LoadSharing, check_member_torque, hertz_fields
from .model import LOCAL_MAX_ITER, LOCAL_RTOL
from .record import record

#: The crown's forms along the width (docs/face_width.md).
CROWNING_FORMS = ("circular", "partial", "logarithmic")
#: Slices allowed: 1 (the planar model) to this.
MAX_SLICES = 99
#: Slices whose peak P_h is within this of the largest share it (a straight face without
#: tilt: every slice, the same problem to round-off); ``peak_ph_z_mm`` names the middle one.
PEAK_RTOL = 1e-9


@dataclass(frozen=True)
class FaceSpec:
    """The face width's slicing and its modifications, SI.

    Attributes
    ----------
    slices : int
        S, 1 = the planar model.
    tilt_rad : float
        The disc's imposed tilt about the in-plane axis normal to its pins' resultant [rad].
    crown_m : float
        The crown's drop at each edge of the face [m] (the disc's; the pins straight).
    form : {"circular", "partial", "logarithmic"}
        circular: a circular arc over the whole width (d = c (2z/B)^2); partial: flat over
        ``flat_fraction`` of the width, circular arcs to the drop c at the edges;
        logarithmic: Lundberg's profile for the line load ``crown_load_N_per_m``,
        d = K ln(1 / (1 - (1 - exp(-c/K)) (2z/B)^2)), K = 2 w / (pi E*) (Lundberg 1939;
        Fujiwara and Kawase 2007), truncated so that the drop at the edges is c.
    flat_fraction : float
        The flat middle part of a partial crown, a fraction of the width.
    crown_load_N_per_m : float or None
        The logarithmic profile's design line load [N/m].
    pin_span_m : float or None
        Conventional pins held at their ends, this far apart (symmetric about the face):
        each pin a Timoshenko beam on two simple supports whose deflection couples its
        slices. None: held along their length (in the housing's grooves), no bending.
    """
    slices: int = 1
    tilt_rad: float = 0.0
    crown_m: float = 0.0
    form: str = "circular"
    flat_fraction: float = 0.5
    crown_load_N_per_m: float | None = None
    pin_span_m: float | None = None

    def __post_init__(self):
        check_range("face_slices", self.slices, 1, MAX_SLICES)
        if int(self.slices) != self.slices:
            raise ToothfemError(f"face_slices = {self.slices!r} is outside the valid range: "
                                f"an integer from 1 to {MAX_SLICES}")
        check_range("disc_tilt", self.tilt_rad, -0.05, 0.05)
        check_range("face_crowning", self.crown_m, 0.0, 1e-3)
        check_range("face_crowning_flat_fraction", self.flat_fraction, 0.0, 1.0,
                    hi_open=True)
        if self.form not in CROWNING_FORMS:
            raise ToothfemError(f"face_crowning_form = {self.form!r} is not one of "
                                f"{list(CROWNING_FORMS)}")
        if self.form == "logarithmic" and self.crown_m > 0:
            check_range("face_crowning_load", self.crown_load_N_per_m, 0.0, None,
                        lo_open=True, why="the logarithmic profile's design line load")

    def pin_bending(self, width: float, radius: float, youngs_modulus: float,
                    poisson_ratio: float) -> np.ndarray:
        """The pin's deflection at each slice per unit force on each slice [m/N] (S, S):
        a solid round pin of ``radius`` on two simple supports ``pin_span_m`` apart, the
        face in the middle (fem.datasheet.supports.simply_supported_influence: Euler-
        Bernoulli bending and Timoshenko's shear); zeros without a span.

        Parameters
        ----------
        width : float
            The face width B [m].
        radius : float
            The pin's radius [m].
        youngs_modulus, poisson_ratio : float
            The pin's material [Pa, -].

        Returns
        -------
        numpy.ndarray, shape (S, S)
            [m/N].

        Raises
        ------
        ToothfemError
            For a span shorter than the face width.
        """
        n = int(self.slices)
        if self.pin_span_m is None:
            return np.zeros((n, n))
        check_range("pin_span", self.pin_span_m, width, None,
                    why="the pin's supports outside the face")
        x = self.z(width) + 0.5 * self.pin_span_m
        return simply_supported_influence(x[:, None], x[None, :], self.pin_span_m,
                                          2 * radius, youngs_modulus, poisson_ratio)

    @property
    def modified(self) -> bool:
        """Whether the slices differ (a tilt or a crown)."""
        return bool(self.tilt_rad) or bool(self.crown_m)

    def z(self, width: float) -> np.ndarray:
        """The slices' centres along the width, 0 at the middle.

        Parameters
        ----------
        width : float
            The face width B [m].

        Returns
        -------
        numpy.ndarray, shape (S,)
            [m].
        """
        return ((np.arange(self.slices) + 0.5) / self.slices - 0.5) * width

    def drop(self, z, width: float, e_star: float) -> np.ndarray:
        """The crown's drop [m] at ``z`` [m] (|z| <= width/2).

        Parameters
        ----------
        z : array_like
            Positions along the width, 0 at the middle [m].
        width : float
            The face width B [m].
        e_star : float
            The contact modulus [Pa] (the logarithmic profile's K).

        Returns
        -------
        numpy.ndarray
        """
        u = np.clip(np.abs(2 * np.asarray(z, float) / width), 0.0, 1.0)
        c = self.crown_m
        if c == 0:
            return np.zeros_like(u)
        if self.form == "circular":
            return c * u ** 2
        if self.form == "partial":
            f = self.flat_fraction
            return c * (np.clip(u - f, 0.0, None) / (1 - f)) ** 2
        if self.crown_load_N_per_m is None:        # refused by __post_init__
            raise ToothfemError("face_crowning_load = None: a logarithmic crown needs its "
                                "design line load")
        k = 2 * self.crown_load_N_per_m / (math.pi * e_star)
        # 1 - (1 - exp(-c/K)) u^2, written so that it is exact at the edge (c/K ~ 40)
        return -k * np.log((1 - u ** 2) + u ** 2 * math.exp(-c / k))


@dataclass(frozen=True)
class SlicedSharing:
    """The load sharing of a disc with its face width in slices.

    ``load_sharing`` carries each contact's force summed over the slices and, as its P_h,
    the peak along the width (the half-width beside it that slice's). Per slice: S slices,
    P positions, C = the pins."""
    load_sharing: LoadSharing
    face: FaceSpec
    z: np.ndarray               # (S,) m, slice centres
    slice_width: float          # m
    force: np.ndarray           # (S, P, C) N on each slice
    ph: np.ndarray              # (S, P, C) Pa, Hertz on the slice's line load
    tilt_direction: np.ndarray  # (P, 2) the disc's shift per tilt and z, disc frame
    tilt_moment: np.ndarray     # (P,) N m, the pins' moment on the disc about the tilt axis

    def edge_figures(self) -> dict:
        """The summary's figures of the width.

        Returns
        -------
        dict
            ``face_slices``, ``max_ph_centre_MPa`` (the middle slice's peak over every
            contact and position), ``max_ph_edge_MPa`` (the two edge slices'),
            ``edge_to_centre_ph`` (their ratio), ``peak_ph_z_mm`` (where along the width
            the largest P_h sits, 0 the middle; of equal peaks the one nearest the middle)
            and ``tilt_moment_max_Nm``.
        """
        s = self.z.size
        mid = self.ph[s // 2] if s % 2 else np.maximum(self.ph[s // 2 - 1], self.ph[s // 2])
        edge = np.maximum(self.ph[0], self.ph[-1])
        # where the peak sits: of the slices within round-off of it, the nearest the middle
        top = self.ph.reshape(s, -1).max(axis=1)
        near = np.flatnonzero(top >= top.max() * (1 - PEAK_RTOL))
        at = near[np.argmin(np.abs(self.z[near]))]
        return {"face_slices": int(s),
                "max_ph_centre_MPa": float(mid.max() / 1e6),
                "max_ph_edge_MPa": float(edge.max() / 1e6),
                "edge_to_centre_ph": float(edge.max() / mid.max()),
                "peak_ph_z_mm": float(self.z[at] * 1e3),
                "tilt_moment_max_Nm": float(np.max(np.abs(self.tilt_moment)))}

    def rows(self):
        """Rows of face_width.csv: every slice of every loaded contact.

        Yields
        ------
        tuple
            (position [deg], contact_id, z [mm], force on the slice [N], line load
            [N/mm], P_h [MPa]).
        """
        ls = self.load_sharing
        for p in range(ls.force.shape[0]):
            for c in np.flatnonzero(ls.force[p] > 0):
                for s, z in enumerate(self.z):
                    f = float(self.force[s, p, c])
                    yield (math.degrees(ls.position_rad[p]), int(ls.contact_id[p, c]),
                           float(z) * 1e3, f, f / self.slice_width / 1e3,
                           float(self.ph[s, p, c]) / 1e6)


def tilt_direction(q, q_load: float) -> np.ndarray:
    """The in-plane direction the disc shifts along per unit tilt and z: the resultant of
    the carrying pins' normals weighted by their moment arms (the rigid split's forces),
    disc frame.

    Parameters
    ----------
    q : _Position
        One position's candidates.
    q_load : float
        The torque per length; its sign picks the carrying flank.

    Returns
    -------
    numpy.ndarray, shape (2,)
        A unit vector.
    """
    s = 1.0 if q_load > 0 else -1.0
    w = np.where(s * q.arm < 0, np.abs(q.arm), 0.0)
    r = q.normal @ w
    return r / np.hypot(*r)


def solve_sliced(solver, face: FaceSpec, torque: float, progress=None) -> SlicedSharing:
    """The load sharing of every position with the face width in slices.

    Parameters
    ----------
    solver : toothfem.fem.cycloid_fe.CycleSolver
        The planar cycle solver of the disc (its tables per unit length).
    face : FaceSpec
        The slices, tilt and crown.
    torque : float
        The disc's torque [N m]; its sign loads the flank.
    progress : callable, optional
        Wraps the iterable of positions.

    Returns
    -------
    SlicedSharing

    Raises
    ------
    ToothfemError
        For a zero torque, or a solver in the equal-springs limit (no tables).
    toothfem.fem.contact.ContactError
        If the Hertz local approach does not settle.
    """
    check_member_torque(torque, "disc")
    if solver.equal_springs is not None:
        raise ToothfemError("the equal-springs limit has no influence tables to slice")
    side = 1 if torque > 0 else -1
    m = solver.model
    width, n_s = m.face_width, int(face.slices)
    z = face.z(width)
    drop = face.drop(z, width, m.e_star)
    pos = solver.candidates(side)
    state = cy.meshing(m.geometry, solver.positions_rad)
    if face.pin_span_m is not None and m.pin_structure != "conventional":
        raise ToothfemError(f"pin_span = {face.pin_span_m!r} m applies to conventional pins, "
                            f"not to pin_structure = {m.pin_structure!r}")
    bending = width * face.pin_bending(width, m.geometry.pin_radius_m, m.youngs_modulus,
                                       m.poisson_ratio)
    q_load = torque / width
    n_p, zb = len(pos), m.geometry.pin_count
    force = np.zeros((n_s, n_p, zb))
    gap = np.where(np.isfinite(state.gap), state.gap, np.inf)
    gap = np.repeat(gap[None], n_s, axis=0)
    beta, moment, direction = np.zeros(n_p), np.zeros(n_p), np.zeros((n_p, 2))
    it = range(n_p) if progress is None else progress(range(n_p))
    with one_blas_thread():
        for p in it:
            q = pos[p]
            t = tilt_direction(q, q_load)
            g0 = q.gap[None, :] + drop[:, None] - face.tilt_rad * z[:, None] * (t @ q.normal)
            with contact.naming_load(f"disc torque {torque:g} N m, position {p}"):
                lam, g, beta[p] = _solve_position(solver, p, q, q_load, side, g0, bending)
            force[:, p, q.pins] = lam * (width / n_s)
            gap[:, p, q.pins] = g
            direction[p] = t
            # the pins push the disc along -n: their moment about the tilt axis
            moment[p] = -np.sum(z[:, None] * force[:, p, q.pins] * (t @ q.normal))
    total = record("cycle", m, state, force.sum(axis=0), np.min(gap, axis=0), beta, torque)
    w_s = width / n_s
    fields = [hertz_fields(force[s], w_s, state.equivalent_radius, m.e_star,
                           (state.radius_moving, state.radius_fixed)) for s in range(n_s)]
    ph = np.stack([f[1] for f in fields])
    hw = np.stack([f[0] for f in fields])
    at = np.argmax(ph, axis=0)
    total = dataclasses.replace(
        total, ph=np.max(ph, axis=0),
        half_width=np.take_along_axis(hw, at[None], axis=0)[0],
        hertz_invalid=np.any(np.stack([f[2] for f in fields]), axis=0))
    return SlicedSharing(total, face, z, w_s, force, ph, direction, moment)


def _solve_position(solver, p, q, q_load, side, g0, bending):
    """Every slice of one position in one solve (:func:`slice_solve` on the planar
    solver's table and local law at that position)."""
    try:
        return slice_solve(solver.influence(p, side), solver.local_law(q, q_load), g0, q.arm,
                           q_load, bending)
    except contact.ContactError as exc:
        raise contact.ContactError(f"{exc} at crank angle {math.degrees(q.phi):.3f} "
                                   "deg") from None


def slice_solve(h, law, g0, arm, q_load: float, bending=None):
    """The slices of one position in one complementarity solve, iterated on the local
    law (the Hertz half-widths b(F) of every slice) to the planar mode's tolerance.

    Unknowns mu = lambda / S (the balance sum_s w arm.lambda_s = -T reads arm.mu summed =
    -T/B with the planar solver's q_load): gaps g0 + S blockdiag(H + local) mu + beta arm
    + the pins' bending, B w(z_s; z_t) mu_t on each pin (its force on slice t is B mu_t).

    Parameters
    ----------
    h : numpy.ndarray, shape (C, C)
        The bodies' compliance per unit length [m per N/m] (the planar influence table).
    law : callable
        lam (S, C) [N/m] -> (S, C) each contact's local compliance [m per N/m] (a secant).
    g0 : numpy.ndarray, shape (S, C)
        The slices' initial gaps [m].
    arm : numpy.ndarray, shape (C,)
        The gap's change per unit rigid unknown (the moment arms) [m per rad].
    q_load : float
        The load on the rigid unknown per length of the face [N m/m].
    bending : numpy.ndarray, shape (S, S), optional
        B times a contact's body deflection at slice s per force on slice t [m per N/m]
        (the pins' bending), the same for every contact.

    Returns
    -------
    lam : numpy.ndarray, shape (S, C)
        The slices' line loads [N/m].
    gap : numpy.ndarray, shape (S, C)
        The remaining gaps [m].
    beta : float
        The rigid unknown.

    Raises
    ------
    toothfem.fem.contact.ContactError
        If the local law does not settle.
    """
    n_s, n_c = g0.shape
    big = n_s * np.kron(np.eye(n_s), h)
    if bending is not None:
        big = big + np.kron(bending, np.eye(n_c))
    arm_all = np.tile(arm, n_s)
    s = 1.0 if q_load > 0 else -1.0
    w = np.where(s * arm < 0, -s * arm, 0.0)
    lam = np.tile(w * q_load / np.sum(w * -arm), (n_s, 1))
    active = None
    diag = np.arange(n_s * n_c)
    for _ in range(LOCAL_MAX_ITER):
        mat = big.copy()
        mat[diag, diag] += n_s * law(lam).ravel()
        sol = contact.solve_contact(mat, g0.ravel(), arm_all, q_load, active=active)
        new = n_s * sol.force.reshape(n_s, n_c)
        done = np.max(np.abs(new - lam)) <= LOCAL_RTOL * np.max(new)
        lam, active = new, sol.active
        if done:
            return lam, sol.gap.reshape(n_s, n_c), sol.rigid
    raise contact.ContactError("the local approach of the slices did not settle")


#: The crown search's resolution [m] and its upper bound, a fraction of the face width
#: (a 10 mm face: 100 um, far beyond any crown that still carries load at the middle).
CROWN_RESOLUTION_M, CROWN_MAX_REL = 0.05e-6, 0.01


def edge_crown(solver, torque: float, face: FaceSpec) -> tuple[float, SlicedSharing]:
    """The least crown of ``face.form`` that keeps the edge slices' P_h at or below the
    middle slice's (the largest over every contact and position) at ``torque`` and
    ``face.tilt_rad`` (the rated torque and the worst as-built tilt: issue 43's design).

    The edge-to-middle ratio falls as the crown grows (the crown only opens the edges'
    gaps): bisection on the drop to :data:`CROWN_RESOLUTION_M`.

    Parameters
    ----------
    solver : toothfem.fem.cycloid_fe.CycleSolver
    torque : float
        The disc's torque [N m].
    face : FaceSpec
        The slices, the tilt and the crown's form (its drop is what is sought).

    Returns
    -------
    crown_m : float
        The drop at the edges [m] (0 where the straight face already keeps the edges
        below the middle).
    sliced : SlicedSharing
        The load sharing with that crown.

    Raises
    ------
    ToothfemError
        For fewer than 3 slices (no middle apart from the edges), or no crown up to
        CROWN_MAX_REL of the width that does it.
    """
    if face.slices < 3:
        raise ToothfemError(f"face_slices = {face.slices} is outside the valid range for a "
                            "crown design: 3 or more (edges and a middle)")

    def run(c):
        r = solve_sliced(solver, dataclasses.replace(face, crown_m=c), torque)
        return r, r.edge_figures()["edge_to_centre_ph"] <= 1.0

    r, ok = run(0.0)
    if ok:
        return 0.0, r
    lo, hi = 0.0, CROWN_MAX_REL * solver.model.face_width
    best, ok = run(hi)
    if not ok:
        raise ToothfemError(f"no crown up to {hi * 1e6:.0f} um keeps the edges below the "
                            "middle (disc_tilt too large for this face)")
    while hi - lo > CROWN_RESOLUTION_M:
        mid = 0.5 * (lo + hi)
        r, ok = run(mid)
        if ok:
            hi, best = mid, r
        else:
            lo = mid
    return hi, best
