"""Cycle mode of the sine pair: contact at any crank angle from the hat tables, one
factorisation per body (fem/sine_fe/__init__.py)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...errors import ToothfemError, check_range
from ...geometry import sine
from ...geometry.kinematics import equivalent_radius
from ...geometry.vectors import rotate
from .. import contact
from ..cache import DiskCache, content_key
from ..load_sharing import LoadSharing, check_member_torque, hertz_fields, position_pitches
from .grid import _circle, _grid_body, _GridBody, _planet_toothed, ring_foot, _ring_toothed
from .model import SineFEModel
from ...units import UM_PER_M

#: Hertz's quadratic gap x^2/(2 R_eq) must match the exact loaded separation g0 + beta l
#: at x = +-b (symmetric second difference) within this fraction of it, else the contact
#: is flagged hertz_invalid (the rotation term or a varying curvature dominates).
HERTZ_GAP_RTOL = 0.25

#: Planet hats whose initial gap to the ring is below this (m) are contact unknowns; it is
#: doubled (up to SELECT_GAP_MAX) when a hat in contact had an initial gap above
#: SELECT_MARGIN times it, so that the selection never limits the contact set.
DEFAULT_SELECT_GAP, SELECT_GAP_MAX, SELECT_MARGIN = 6e-6, 120e-6, 0.6

#: Hat spacing along the surfaces in the cycle mode (m): 1/4 to 1/40 of the contact
#: half-widths met at the prototype's load (0.1-1 mm); the mesh is s/2 along the surface.
DEFAULT_SPACING = 35e-6

# ---------------------------------------------------------------------------------------
# Cycle mode

@dataclass(frozen=True, kw_only=True)
class PositionResult:
    """One crank angle of the cycle mode: the contact hats and their solution.

    ``hat``: global planet hat indices (tooth * N + k) of the contact unknowns (H,);
    ``point`` (2, H) ring frame; ``force`` (H,) N/m; ``pressure`` (H,) Pa (force over the
    hat's integral s); ``column`` (H,) the meshing candidate each hat belongs to (-1: none);
    ``sigma`` (H,) arc length along the planet profile (m)."""
    crank_angle: float
    hat: np.ndarray
    point: np.ndarray
    sigma: np.ndarray
    g0: np.ndarray
    arm: np.ndarray
    force: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    column: np.ndarray
    rotation: float
    iterations: int
    select_gap: float
    hat_moment: float = 0.0     # second moment of one hat about its centre / its area, m^2


@dataclass(frozen=True, kw_only=True)
class HatContacts:
    """The contact unknowns of one crank angle (:meth:`CycleSolver.hat_contacts`): planet
    hat indices (H,), arc lengths ``sigma`` (H,) [m], centres ``point`` (2, H) and the
    ring's normal ``normal`` (2, H) at their feet (ring frame, pointing into the planet: a
    planet translation d opens the gap by d . normal), initial gaps ``g0`` (H,) [m],
    moment arms ``arm`` (H,) [m] (the gap's change per planet rotation), the two bodies'
    ``flexibility`` (H, H) [m per N/m], the meshing ``column`` (H,) of each, the
    ``select_gap`` they were chosen with [m] and the planet's ``centre`` (2, 1) the
    points stand about (ring frame, the eccentricity's error included) [m]."""
    hat: np.ndarray
    sigma: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    g0: np.ndarray
    arm: np.ndarray
    flexibility: np.ndarray
    column: np.ndarray
    select_gap: float
    centre: np.ndarray

    def result(self, chi, force, gap, rotation, iterations, spacing) -> PositionResult:
        """The position's record of a solution on these hats.

        Parameters
        ----------
        chi : float
            Crank angle [rad].
        force, gap : numpy.ndarray
            Per hat [N/m], [m].
        rotation : float
            The planet's rotation [rad].
        iterations : int
            Active-set iterations taken.
        spacing : float
            The hats' spacing [m] (pressure = force / spacing).

        Returns
        -------
        PositionResult
        """
        return PositionResult(crank_angle=chi, hat=self.hat, point=self.point,
                              sigma=self.sigma, g0=self.g0, arm=self.arm, force=force,
                              pressure=force / spacing, gap=gap, column=self.column,
                              rotation=rotation, iterations=iterations,
                              select_gap=self.select_gap, hat_moment=spacing**2 / 6)


#: Bump when the discretisation behind the hat tables changes (part of the cache key).
TABLES_VERSION = 1


@dataclass(eq=False)
class CycleSolver:
    """Influence coefficients of both bodies on their hat grids from one factorisation
    each; contact at any crank angle from those tables (module docstring).

    ``cache`` (a :class:`toothfem.fem.cache.DiskCache`, or None) keeps each body's hat table
    on disk under a key of what it depends on (pair, material, supports, plane, spacing,
    reach; not the torque): a solver for a known design meshes and factorises nothing."""
    model: SineFEModel
    positions_rad: np.ndarray
    spacing: float = DEFAULT_SPACING
    select_gap: float = DEFAULT_SELECT_GAP
    cache: DiskCache | None = None

    def __post_init__(self):
        self.positions_rad = np.atleast_1d(np.asarray(self.positions_rad, float))
        for x in self.positions_rad:
            check_range("positions_rad", x)
        m = self.model.pair.module_m
        check_range("spacing", self.spacing, 0.002 * m, 0.2 * m, why="hat spacing along the "
                    "surfaces: 1/500 to 1/5 of the module")
        check_range("select_gap", self.select_gap, 0, SELECT_GAP_MAX, lo_open=True)

    #: the hat grids give no stress field of their own (the detailed mode does).
    has_structural_field = False

    def prepare(self) -> None:
        """Build (or read from the cache) both bodies' hat tables now."""
        _ = self.planet, self.ring      # the cached properties build or read them

    def structural_field(self, p: int, load_sharing: LoadSharing):
        """None here: the hat grids carry no stress field (``has_structural_field`` is
        False; the detailed mode draws the planet's).

        Parameters
        ----------
        p : int
            Index into ``positions_rad``.
        load_sharing : LoadSharing

        Raises
        ------
        ValueError
            Always, naming the detailed mode.
        """
        raise ValueError("the sine pair's cycle mode has no structural field "
                         "(has_structural_field is False): solve the position in the "
                         "detailed mode (Drive.solve_detailed)")

    @property
    def reach(self) -> int:
        """Teeth between any two contact hats, at most (candidates on both sides, the ring
        tooth a hat projects onto, one for the shift of the pitch point)."""
        return 2 * self.model.candidates + 3

    @cached_property
    def planet(self) -> _GridBody:
        m = self.model
        return self._cached("planet", _planet_toothed(m.pair),
                            lambda t: _grid_body(t, [_circle(m.planet_bore_radius)],
                                                 ["profile", "bore"], "bore", self.spacing, m,
                                                 self.reach))

    @cached_property
    def ring(self) -> _GridBody:
        m = self.model
        return self._cached("ring", _ring_toothed(m.pair),
                            lambda t: _grid_body(t, [_circle(m.ring_outer_radius)],
                                                 ["rim", "profile"], "rim", self.spacing, m,
                                                 self.reach))

    def cache_key(self, which: str) -> str:
        """Hash of what a body's hat table depends on.

        Parameters
        ----------
        which : {"planet", "ring"}
            The body.

        Returns
        -------
        str
            :func:`toothfem.fem.cache.content_key` of the pair, material, support, plane,
            spacing and reach (not the torque, not the face width: the tables are per unit
            length).
        """
        m = self.model
        pair = dataclasses.replace(m.pair, face_width_m=1.0)     # per unit length
        support = m.planet_bore_radius if which == "planet" else m.ring_outer_radius
        return content_key("SineCycleSolver", TABLES_VERSION, which, pair, m.youngs_modulus,
                           m.poisson_ratio, support, m.plane, self.spacing, self.reach)

    def _cached(self, which, toothed, build) -> _GridBody:
        if self.cache is None:
            return build(toothed)
        key = self.cache_key(which)
        hit = self.cache.load(key)
        if hit is not None and "influence" in hit:
            table = np.asarray(hit["influence"], float)
            n = table.shape[1] if table.ndim == 3 else 0
            if table.shape == (2 * self.reach + 1, n, n) and n >= 8 \
                    and np.all(np.isfinite(table)):
                return _GridBody(None, toothed, n, table, self.reach)
        grid = build(toothed)                   # missing, stale or corrupt: compute, store
        self.cache.store(key, {"influence": grid.influence})
        return grid

    @cached_property
    def states(self):
        return sine.meshing(self.model.pair, self.positions_rad,
                            candidates=self.model.candidates)

    def solve_position(self, chi: float, torque: float, deviation=None) -> PositionResult:
        """Contact at one crank angle.

        The hats selected as unknowns widen (the selection gap doubled) until the contact
        stays inside them.

        Parameters
        ----------
        chi : float
            Crank angle [rad].
        torque : float
            Planet torque [N m], nonzero; a negative torque loads the other flank of the
            teeth (the hat grids cover both).
        deviation : toothfem.fem.deviations.SineDeviation, optional
            The pair as built (:func:`deviation_gaps`).

        Returns
        -------
        PositionResult

        Raises
        ------
        ToothfemError
            For a zero or non-finite torque or crank angle.
        toothfem.fem.contact.ContactError
            If no hat lies within the selection gap, or the contact reaches hats beyond
            SELECT_GAP_MAX (the load is too high for the candidate teeth).
        """
        check_member_torque(torque, "planet")
        check_range("chi", chi)
        sel_gap = self.select_gap
        while True:
            res = self._solve(float(chi), torque / self.model.face_width, sel_gap, deviation)
            loaded = res.force > 0
            # the contact stays inside the selection, and no hat left out (initial gap
            # above sel_gap) can be closed by the rigid rotation
            if (np.max(res.g0[loaded]) <= SELECT_MARGIN * sel_gap
                    and abs(res.rotation) * np.max(np.abs(res.arm)) <= sel_gap):
                return res
            if 2 * sel_gap > SELECT_GAP_MAX:
                raise contact.ContactError(
                    f"crank angle {math.degrees(chi):.4f} deg: contact reaches hats with an "
                    f"initial gap of {np.max(res.g0[loaded]) * UM_PER_M:.1f} um; the load is too "
                    "high for the candidate teeth (raise candidates)")
            sel_gap *= 2

    def hat_contacts(self, chi: float, sel_gap: float, deviation=None) -> HatContacts:
        """The contact unknowns at one crank angle: the candidate teeth's planet hats whose
        initial gap to the ring is below ``sel_gap``, with their flexibility.

        Parameters
        ----------
        chi : float
            Crank angle [rad].
        sel_gap : float
            Selection gap [m].
        deviation : toothfem.fem.deviations.SineDeviation, optional
            The pair as built (its eccentricity moves the planet; :func:`deviation_gaps`).

        Returns
        -------
        HatContacts

        Raises
        ------
        toothfem.fem.contact.ContactError
            If no hat lies within the selection gap.
        """
        pair = self.model.pair
        pl, rg = self.planet, self.ring
        n, s = pl.n_hats, pl.spacing
        k = self.model.candidates
        j0 = int(np.round(chi * pair.ring_teeth / (2 * math.pi)))
        hats = (j0 - k) * n + np.arange((2 * k + 1) * n)
        sigma = hats * s
        centre, theta = sine.planet_pose(pair, chi)
        if deviation is not None:        # the crank's eccentricity error
            centre = centre + deviation.eccentricity * np.array([[math.cos(chi)],
                                                                 [math.sin(chi)]])
        pts = rotate(pl.toothed.point(sigma), theta[0]) + centre
        f2, g0, nrm = ring_foot(pair, pts)
        if deviation is not None:
            g0 = g0 - deviation_gaps(pair, pl, rg, hats, f2, deviation)
        sel = g0 < sel_gap
        if not np.any(sel):
            raise contact.ContactError(f"crank angle {math.degrees(chi):.4f} deg: no planet "
                                       "hat within the selection gap")
        hats, sigma, pts, f2, g0, nrm = (hats[sel], sigma[sel], pts[:, sel], f2[sel], g0[sel],
                                         nrm[:, sel])
        rel = pts - centre
        arm = rel[0] * nrm[1] - rel[1] * nrm[0]
        # ring: the transported hats on the ring grid by linear interpolation, T^T H_r T
        # with two weights per hat (1 - a on ring hat j, a on j + 1)
        u = rg.toothed.sigma_of_phi(f2) / rg.spacing
        # one ring perimeter of hats: keep the selection's indices together where the
        # ring parameter wraps (a crank angle a whole turn on)
        turn = rg.n_hats * pair.ring_teeth
        u = u[0] + np.mod(u - u[0] + 0.5 * turn, turn) - 0.5 * turn
        j = np.floor(u).astype(int)
        a = u - j
        hmat = pl.matrix(hats)
        for wa, ja in ((1 - a, j), (a, j + 1)):
            for wb, jb in ((1 - a, j), (a, j + 1)):
                hmat += wa[:, None] * wb[None, :] * rg.matrix(ja, jb)
        return HatContacts(hat=hats, sigma=sigma, point=pts, normal=nrm, g0=g0, arm=arm,
                           flexibility=0.5 * (hmat + hmat.T), column=self._columns(chi, hats),
                           select_gap=float(sel_gap), centre=centre)

    def _solve(self, chi, q_load, sel_gap, deviation=None) -> PositionResult:
        h = self.hat_contacts(chi, sel_gap, deviation)
        sol = contact.solve_contact(h.flexibility, h.g0, h.arm, q_load)
        return h.result(chi, sol.force, sol.gap, sol.rigid, sol.iterations,
                        self.planet.spacing)

    def _columns(self, chi, hats):
        j0 = int(np.round(chi * self.model.pair.ring_teeth / (2 * math.pi)))
        tooth, cell = np.divmod(hats, self.planet.n_hats)
        return _flank_columns(j0, self.model.candidates, tooth, cell >= self.planet.n_hats / 2)

    def solve(self, torque: float, progress=None, *, deviation=None,
              pitches=None) -> LoadSharing:
        """Load sharing of the sine pair at every position.

        Parameters
        ----------
        torque : float
            Planet torque [N m], either sign.
        progress : callable, optional
            Wraps the iterable of positions (e.g. a progress bar).
        deviation : toothfem.fem.deviations.SineDeviation, optional
            The pair as built (:meth:`solve_position`).
        pitches : array_like of int, shape (P,), optional
            Puts position p that many meshing periods on (the hat tables cover every
            tooth: exact).

        Returns
        -------
        LoadSharing
            Method "cycle", with the labels of pitch 0: a period on, the mesh is the one of
            pitch 0 turned by 2 pi/z2 with every planet tooth index one up (SineGearPair.
            crank_pitch_rad), so points are turned back and arc lengths put a tooth back.

        Raises
        ------
        ToothfemError
            For a zero or non-finite torque, or ``pitches`` of another shape.
        toothfem.fem.contact.ContactError
            If a position does not solve (:meth:`solve_position`) or the outermost
            candidate teeth carry load.
        """
        check_member_torque(torque, "planet")
        n_pos = self.positions_rad.size
        pitches = position_pitches(pitches, n_pos)
        it = range(n_pos)
        if progress is not None:
            it = progress(it)
        pitch = self.model.pair.crank_pitch_rad
        results = []
        for p in it:
            chi, m = float(self.positions_rad[p]), int(pitches[p])
            with contact.naming_load(f"planet torque {torque:g} N m, position {p}"):
                results.append(self.labelled(self.solve_position(chi + m * pitch, torque,
                                                                 deviation), chi, m))
        return self.record("cycle", results, torque)

    def labelled(self, r: PositionResult, chi: float, m: int) -> PositionResult:
        """A result m meshing periods on put in the labels of pitch 0 at crank angle chi
        (points turned back by m crank pitches, arc lengths m teeth back).

        Parameters
        ----------
        r : PositionResult
        chi : float
            The crank angle of pitch 0 [rad].
        m : int
            Meshing periods on.

        Returns
        -------
        PositionResult
        """
        if not m:
            return r
        pitch = self.model.pair.crank_pitch_rad
        return dataclasses.replace(r, crank_angle=chi, point=rotate(r.point, -m * pitch),
                                   sigma=r.sigma - m * self.planet.n_hats * self.planet.spacing)

    def record(self, method: str, results, torque: float) -> LoadSharing:
        """The load sharing of one result per position (:func:`_record`).

        Parameters
        ----------
        method : str
            "cycle" or "system".
        results : list of PositionResult
            In the labels of pitch 0 (:meth:`labelled`).
        torque : float
            The planet's torque [N m].

        Returns
        -------
        LoadSharing
        """
        return _record(method, self.model, self.states, results, torque, self.planet.toothed)


def deviation_gaps(pair, planet, ring, hats, f2, deviation) -> np.ndarray:
    """Gap closed at each planet hat by the profile deviations.

    The material added on the hat's planet flank and on the ring flank it faces. A flank
    is half a tooth's window of its grid (``n_hats`` per tooth, split at the middle as the
    meshing columns are).

    Parameters
    ----------
    pair : toothfem.geometry.sine.SineGearPair
    planet, ring : _GridBody
        The hat grids of the two bodies.
    hats : numpy.ndarray of int, shape (H,)
        Global planet hat indices (tooth * n_hats + k).
    f2 : numpy.ndarray, shape (H,)
        Ring parameter of each hat's foot [rad] (:func:`ring_foot`).
    deviation : toothfem.fem.deviations.SineDeviation

    Returns
    -------
    numpy.ndarray, shape (H,)
        Closed gap [m] (> 0 closes).
    """
    tooth, cell = np.divmod(hats, planet.n_hats)
    closing = deviation.planet_profile[np.mod(tooth, pair.planet_teeth),
                                       (cell >= planet.n_hats / 2).astype(int)]
    u = np.floor(ring.toothed.sigma_of_phi(f2) / ring.spacing).astype(int)
    r_tooth, r_cell = np.divmod(u, ring.n_hats)
    return closing + deviation.ring_profile[np.mod(r_tooth, pair.ring_teeth),
                                            (r_cell >= ring.n_hats / 2).astype(int)]


def _flank_columns(j0, k, tooth, upper):
    """Column of sine.meshing (tooth j0-k+i, flank -1/+1 -> 2i, 2i+1) of points on planet
    tooth ``tooth`` (its window from root to root), on flank +1 where ``upper`` (beyond the
    tip). A loaded zone is not always around a flank's own gap minimum: the profiles are
    so nearly conformal that a flank whose gap falls all the way to the neighbouring
    flank's conjugate contact (meshing gap inf) carries load too."""
    return 2 * (np.asarray(tooth) - (j0 - k)) + np.asarray(upper).astype(int)


def _record(method, model: SineFEModel, state, results, torque, toothed) -> LoadSharing:
    """Stack per-position contact solutions into a LoadSharing over the meshing columns.

    Per loaded column: the force is the sum of its nodal or hat forces, the moment arm and
    point those of the resultant; the curvature radii are taken at the resultant's point
    (a column without a gap minimum of its own has its meshing point at a flank end).
    P_h and b: Hertz's on the force where Hertz holds, else the FE peak and the
    second-moment half-width b^2 = 4 int x^2 p / int p (``pressure_from_fe``). The gap of
    a column with no contact unknown is its initial gap closed by the rigid rotation only
    (beta l; the elastic part is left out)."""
    pair, width = model.pair, model.face_width
    n_pos, n_col = state.moment_arm.shape
    force = np.zeros((n_pos, n_col))
    arm = state.moment_arm.copy()
    point = state.point.copy()
    r_p, r_r = state.radius_moving.copy(), state.radius_fixed.copy()
    gap = np.where(np.isfinite(state.gap), state.gap, np.inf)
    beta = np.array([r.rotation for r in results])
    fe_peak = np.zeros((n_pos, n_col))
    fe_b = np.zeros((n_pos, n_col))
    sig_c = np.full((n_pos, n_col), np.nan)
    untouched = np.ones((n_pos, n_col), bool)
    for p, r in enumerate(results):
        if np.any((r.column < 0) | (r.column >= n_col)):
            raise ToothfemError("a contact hat lies outside the candidate teeth")
        if np.any(r.force[(r.column < 2) | (r.column >= n_col - 2)] > 0):
            raise contact.ContactError(
                f"crank angle {math.degrees(r.crank_angle):.4f} deg: the outermost candidate "
                "teeth carry load; raise SineFEModel.candidates")
        for c in np.unique(r.column):
            k = r.column == c
            lam = r.force[k]
            untouched[p, c] = False
            tot = lam.sum()
            if tot <= 0:
                gap[p, c] = np.min(r.gap[k])
                continue
            force[p, c] = tot * width
            arm[p, c] = np.sum(lam * r.arm[k]) / tot
            point[p, c] = (r.point[:, k] @ lam) / tot
            sc = np.sum(lam * r.sigma[k]) / tot
            sig_c[p, c] = sc
            fe_peak[p, c] = np.max(r.pressure[k])
            fe_b[p, c] = 2 * math.sqrt(np.sum(lam * (r.sigma[k] - sc) ** 2) / tot
                                       + r.hat_moment)
            gap[p, c] = 0.0
        gap[p, untouched[p]] = gap[p, untouched[p]] + beta[p] * arm[p, untouched[p]]
    loaded = force > 0
    if np.any(loaded):
        phi1 = toothed.phi_of_sigma(sig_c[loaded])
        r_p[loaded] = 1 / sine.planet_curve(pair, phi1).curvature
        f2, _, _ = ring_foot(pair, point[loaded].T)
        r_r[loaded] = 1 / sine.ring_curve(pair, f2).curvature
    r_eq = equivalent_radius(r_p, r_r)
    b, ph, invalid = hertz_fields(force, width, r_eq, model.e_star, (r_p, r_r))
    if np.any(loaded & ~invalid):
        sel = loaded & ~invalid
        invalid[sel] = _hertz_gap_fails(model, toothed, state.position_rad, beta, sel, sig_c,
                                        b, r_eq)
    from_fe = loaded & invalid
    b = np.where(from_fe, fe_b, b)
    ph = np.where(from_fe, fe_peak, ph)
    return LoadSharing(
        method=method, position_rad=state.position_rad, contact_id=state.contact_id,
        force=force, point=point, moment_arm=arm, half_width=b, ph=ph, gap=gap,
        transmission_error=beta, torque=float(torque), face_width=width,
        pressure_from_fe=from_fe, equivalent_radius=r_eq, hertz_invalid=invalid)


def _hertz_gap_fails(model, toothed, positions, beta, sel, sig_c, b, r_eq):
    """Hertz's quadratic gap against the exact loaded one. The separation that the elastic
    approach must close is g0(x) + beta l(x): the initial gap plus the planet's rigid
    rotation beta times the moment arm l(x) of the normal at x, which varies along a
    curved flank (its second derivative is not small against 1/R_eq for these nearly
    conformal profiles). The symmetric second difference of that separation over +-b about
    the resultant, s(x+b) + s(x-b) - 2 s(x), must be b^2/R_eq within HERTZ_GAP_RTOL (a
    linear part, a tilt, cancels)."""
    pair = model.pair
    pp, cc = np.nonzero(sel)
    out = np.zeros(pp.size, bool)
    for i, (p, c) in enumerate(zip(pp, cc)):
        centre, theta = sine.planet_pose(pair, positions[p])
        sg = sig_c[p, c] + b[p, c] * np.array([-1.0, 0.0, 1.0])
        pts = rotate(toothed.point(sg), theta[0]) + centre
        _, g, n = ring_foot(pair, pts)
        rel = pts - centre
        sep = g + beta[p] * (rel[0] * n[1] - rel[1] * n[0])
        second = sep[0] + sep[2] - 2 * sep[1]
        hertz = b[p, c] ** 2 / r_eq[p, c]
        out[i] = abs(second - hertz) > HERTZ_GAP_RTOL * hertz
    return out
