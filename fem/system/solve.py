"""The quasi-static equilibrium of a planar assembly of rigid bodies, elastic elements and
unilateral contacts (docs/stiffness.md, "The system model").

Generalised coordinates u (n,): the small displacements of the bodies (translations [m],
rotations [rad]). Elements (bearings, shafts, gear meshes) each see a deformation
``delta_e = B_e u`` and answer with their conjugate force ``f_e(delta_e)`` and tangent
``K_e``; their internal force is ``F(u) = sum_e B_e^T f_e``. Contacts (disc on pins, output
pins in their holes) have gaps

    g = g0 + H(lambda) lambda + G u >= 0,   lambda >= 0,   lambda . g = 0,

H the condensed flexibility of the bodies at the contacts (the FE influence tables with
each contact's Hertz approach at its own force), G the gap change per coordinate. A contact
force pushes the bodies apart, so it does the virtual work lambda . G du, and equilibrium
under the external generalised forces Q reads

    F(u) - G^T lambda - Q = 0.

On an active set A (the contacts that carry) the Newton step solves the symmetric saddle
system [[K, -G_A^T], [-G_A, -H_AA]]; an inactive contact whose gap closes joins A, an active
one whose force turns negative leaves it (semismooth Newton, the primal-dual active set of
Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865, with the element forces
linearised at each step). H depends on lambda only through each contact's own local law
(the Hertz half-width, Palmgren's power): the step takes the approach H(lambda) lambda's
tangent, H + diag(lambda_i dH_ii/dlambda_i), so it is Newton's in the forces as well.

Work balance. Taking the solution itself as the virtual displacement,
``Q . u = sum_e f_e . B_e u + lambda . H lambda + lambda . g0`` exactly (the gaps of the
carrying contacts are zero): the output's twist times its torque is the sum of each
element's force times its deformation, the contacts' elastic approach and the clearance
they closed. :attr:`Equilibrium.work` keeps these terms, so the twist splits into parts
that add up to it at any load, linear or not. An element with a forced deformation
(``Element.offset``: a part off its drawing) counts its force times the bodies' part of
its deformation, B_e u, so the parts still add up to the twist exactly.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..contact import ContactError
from ..linsolve import one_blas_thread

#: Newton iterations allowed (the contacts' flexibilities updated at each), and the active
#: set's iterations per Newton step.
MAX_NEWTON, MAX_ACTIVE_SET = 100, 400
#: Newton's step is converged when the coordinates moved by less than this fraction of
#: their size and the contact forces by less than this fraction of the largest (the
#: elements' laws are smooth: the step then falls quadratically; the Hertz half-widths
#: move the flexibilities at first order in the force).
RTOL = 1e-8
#: A contact's force or gap within this fraction of the largest of them is zero (a
#: degenerate pair: touching without force).
DEGENERATE_RTOL = 1e-10
#: A set of contacts that leaves a body free is passed through with this vanishing stiffness
#: on every coordinate, a fraction of the largest stiffness (the free body moves until it
#: meets contacts; a set it settles on holds every body, so no solution carries it).
HOLD_REL = 1e-9
#: Newton's step is taken for quadratic (the next step predicted from the last two) once
#: the step is below this fraction of the coordinates and forces.
QUADRATIC_FROM = 1e-3
#: A settled active set whose Newton step stops falling (round-off of parts made rigid)
#: is converged once the step is below this fraction of the coordinates.
STALL_RTOL = 1e-7
#: From rest, the elements take secant steps until a step is this fraction of the
#: coordinates (then Newton's).
SECANT_UNTIL = 0.1
#: Relative force step of the contacts' approach tangent (a forward difference of a
#: logarithmic or power law: its error is this fraction of the tangent's change, far below
#: the step's own).
APPROACH_STEP = 1e-6
#: Singular values below this fraction of the largest are a mechanism (a motion that
#: deforms no element).
MECHANISM_RTOL = 1e-10


@dataclass(frozen=True)
class Element:
    """An elastic element: deformation ``B @ u + offset`` (d,), law ``law(delta) -> (f (d,),
    K (d, d))``, ``group`` the compliance it is reported under. ``offset`` (d,) is a
    deformation forced on the element with every body at rest (a part off its drawing: an
    eccentric off its place pushes its bearing's rings against each other by that much);
    None: none."""
    name: str
    group: str
    b: np.ndarray
    law: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    offset: np.ndarray | None = None

    def deformation(self, u) -> np.ndarray:
        """delta = B u + offset at the coordinates u.

        Parameters
        ----------
        u : numpy.ndarray, shape (n,)

        Returns
        -------
        numpy.ndarray, shape (d,)
        """
        d = self.b @ u
        return d if self.offset is None else d + self.offset


@dataclass(frozen=True)
class ContactSet:
    """Unilateral contacts of one kind: initial gaps g0 (c,) [m], the gap change per
    coordinate G (c, n), and their flexibility at contact forces lam [N],
    H(lam) = ``base`` + diag(``local(lam)``) [m/N]: the bodies' fixed influence (c, c)
    and each contact's own local law (c,) as a secant (its approach local_i(lam_i) lam_i,
    e.g. Hertz's, Palmgren's; elementwise, so it takes forces (..., c) at once). Both None:
    rigid contacts."""
    name: str
    group: str
    g0: np.ndarray
    g: np.ndarray
    base: np.ndarray | None = None
    local: Callable[[np.ndarray], np.ndarray] | None = None

    def local_terms(self, lam):
        """The local law's secant and its own-force rate at the forces lam (the diagonal
        H adds to ``base``).

        Parameters
        ----------
        lam : array_like, shape (c,)
            Contact forces [N].

        Returns
        -------
        local : numpy.ndarray, shape (c,)
            [m/N] (zeros without a local law).
        rate : numpy.ndarray, shape (c,)
            lam_i d local_i / d lam_i [m/N], what the approach's tangent adds to the
            secant's diagonal (a relative forward difference; none without force).
        """
        lam = np.asarray(lam, float)
        if self.local is None:
            return np.zeros(lam.size), np.zeros(lam.size)
        local, up = self.local(np.stack([lam, lam * (1 + APPROACH_STEP)]))
        return local, np.where(lam > 0, (up - local) / APPROACH_STEP, 0.0)


@dataclass(frozen=True)
class Equilibrium:
    """A solved state: coordinates ``u`` (n,), each contact set's forces [N] and gaps [m],
    each element's force and deformation, and the work of each group [J]
    (``sum(work.values()) == Q . u``); ``rate``: du per unit growth of the load's
    magnitude at this state (the tangent system with the carrying contacts held), what the
    friction in the quasi-static path slips by."""
    u: np.ndarray
    forces: dict
    gaps: dict
    element_force: dict
    element_deformation: dict
    work: dict = field(default_factory=dict)
    iterations: int = 0
    rate: np.ndarray | None = None


def _each_element(elements, u) -> dict:
    """{name: (force, deformation)} of every element at u (what the outputs report); the
    elements of one law evaluated together."""
    groups: dict[int, list[Element]] = {}
    for e in elements:
        groups.setdefault(id(e.law), []).append(e)
    out = {}
    for same in groups.values():
        d = np.stack([e.deformation(u) for e in same])   # (G, d)
        f = same[0].law(d)[0] if not isinstance(same[0].law, Linear) else \
            np.einsum("ij,gj->gi", same[0].law.k, d)
        out.update({e.name: (f[i], d[i]) for i, e in enumerate(same)})
    return out


def solve(n: int, elements, contacts, q, *, u0=None, active0=None,
          lam0=None, rate: bool = True) -> Equilibrium:
    """Equilibrium of the assembly under the generalised forces ``q``.

    Parameters
    ----------
    n : int
        Number of coordinates.
    elements : sequence of Element
    contacts : sequence of ContactSet
    q : array_like, shape (n,)
        External generalised forces [N or N m].
    u0 : array_like, optional
        Start (a nearby state, e.g. the previous torque step).
    active0 : dict of str to bool array, optional
        The contacts to start from per set; else the candidates that touch first as the
        load moves the assembly (:func:`closing_motion`).
    lam0 : dict of str to array, optional
        Contact forces to take the first flexibilities at (a nearby state's).
    rate : bool
        Also the tangent ``Equilibrium.rate`` (one more solve; what friction reads).

    Returns
    -------
    Equilibrium

    Raises
    ------
    ContactError
        If the active set cycles, the system is singular (a coordinate nothing holds) or
        the contact flexibilities do not settle.
    """
    q = np.asarray(q, float)
    g0 = np.concatenate([c.g0 for c in contacts]) if contacts else np.zeros(0)
    gmat = np.concatenate([c.g for c in contacts], axis=0) if contacts else np.zeros((0, n))
    sizes = np.cumsum([0] + [c.g0.size for c in contacts])
    m = g0.size
    u = np.zeros(n) if u0 is None else np.asarray(u0, float).copy()
    lam = np.zeros(m) if lam0 is None else np.concatenate(
        [np.asarray(lam0[c.name], float) for c in contacts])
    active = None if active0 is None else np.concatenate(
        [np.asarray(active0[c.name], bool) for c in contacts])
    linear, forced, nonlinear = _split_linear(elements, n)
    if u0 is None:
        u = rest(n, elements)
    last = np.inf
    with one_blas_thread():
        h, d = _flexibility(contacts, lam, sizes)
        if active is None:
            active = closing_motion(n, elements, gmat, g0, q, u)[0]
        secant = u0 is None
        last_rel = (np.inf, np.inf)
        for it in range(1, MAX_NEWTON + 1):  # noqa: B007 - it is read after the loop (iterations)
            f_int, kt = _internal(linear, forced, nonlinear, u, n, secant)
            # the contacts' approach H(lam) lam linearised at lam: H + D, D its diagonal's
            # own-force derivative lam_i dH_ii/dlam_i (the Hertz and Palmgren laws), so the
            # step is Newton's in the forces too
            before = active
            u_new, lam_new, active = _linear_step(n, kt, q - f_int + kt @ u, gmat,
                                                  g0 - d * lam, h + np.diag(d), active)
            step = np.max(np.abs(u_new - u))
            change = np.max(np.abs(lam_new - lam), initial=0.0)
            u, lam = u_new, lam_new
            size = max(np.max(np.abs(u)), 1e-300)
            rel = (step / size, change / max(np.max(lam, initial=0.0), 1e-300))
            newton = not secant and np.array_equal(before, active)
            # from rest, the first step finds bearings inside their play at their holding
            # stiffness and throws the bodies far; Newton on a power law comes back from
            # there by only 1 - 1/a a step (a = 10/9: ten steps a decade), the secant in
            # one: secant steps until the step is within SECANT_UNTIL of the size
            secant = secant and step > SECANT_UNTIL * size
            if rel[1] <= RTOL and (rel[0] <= RTOL
                                   or (step >= 0.5 * last and rel[0] <= STALL_RTOL)):
                break
            # Newton's steps on a settled active set fall quadratically, s_k+1 ~ s_k^3 /
            # s_k-1^2: the next one would be below RTOL, so this iterate is converged
            if newton and all(r <= QUADRATIC_FROM and r ** 3 <= RTOL * p ** 2
                              for r, p in zip(rel, last_rel)):
                break
            last, last_rel = step, rel
            h, d = _flexibility(contacts, lam, sizes)
        else:
            raise ContactError(f"the system did not settle in {MAX_NEWTON} Newton steps")
    du_rate: np.ndarray | None
    if rate:
        _, kt = _internal(linear, forced, nonlinear, u, n)
        tangent = h + np.diag(d)
        du_rate = _rate(n, kt, gmat[active], tangent[np.ix_(active, active)],
                        q / np.linalg.norm(q))
    else:
        du_rate = None
    per = _each_element(elements, u)
    gap = g0 + h @ lam + gmat @ u
    gap = np.where(active, 0.0, gap)
    work: dict[str, float] = {}
    for e in elements:
        f = per[e.name][0]
        work[e.group] = work.get(e.group, 0.0) + float(f @ (e.b @ u))
    for k, c in enumerate(contacts):
        sl = slice(sizes[k], sizes[k + 1])
        work[c.group] = work.get(c.group, 0.0) + float(lam[sl] @ (h[sl, sl] @ lam[sl]))
        closed = float(lam[sl] @ c.g0)
        if closed:
            work[c.group + " clearance"] = work.get(c.group + " clearance", 0.0) + closed
    return Equilibrium(
        u=u, forces={c.name: lam[sizes[k]:sizes[k + 1]] for k, c in enumerate(contacts)},
        gaps={c.name: gap[sizes[k]:sizes[k + 1]] for k, c in enumerate(contacts)},
        element_force={k: v[0] for k, v in per.items()},
        element_deformation={k: v[1] for k, v in per.items()}, work=work,
        iterations=it, rate=du_rate)


def _rate(n, kt, ga, haa, dq) -> np.ndarray:
    """du for the load increment dq with the carrying contacts held (the tangent)."""
    return _saddle(n, kt, ga, haa, dq, np.zeros(ga.shape[0]))[:n]


def _saddle(n, kt, ga, haa, rhs_u, rhs_g) -> np.ndarray:
    """(u, lambda_A) of [[K, -G_A^T], [-G_A, -H_AA]] (u, lambda_A) = (rhs_u, rhs_g),
    equilibrated (stiffnesses of 1e3-1e15 N/m against flexibilities of 1e-10 m/N)."""
    k = ga.shape[0]
    mat = np.zeros((n + k, n + k))
    mat[:n, :n] = kt
    mat[:n, n:] = -ga.T
    mat[n:, :n] = -ga
    mat[n:, n:] = -haa
    d = np.abs(np.diag(mat))
    d = 1.0 / np.sqrt(np.where(d > 0, d, 1.0))
    try:
        sol = d * np.linalg.solve(mat * d[:, None] * d[None, :],
                                  np.concatenate([rhs_u, rhs_g]) * d)
    except np.linalg.LinAlgError:
        sol = np.full(n + k, np.nan)
    if not np.all(np.isfinite(sol)):
        raise ContactError("singular system: a body or coordinate that nothing holds "
                           f"({k} contacts carry)")
    return sol


def _flexibility(contacts, lam, sizes):
    """(H (m, m), rate (m,)) of every contact set at the forces lam: each set's ``base``
    with its local secant on the diagonal (:meth:`ContactSet.local_terms`), written into
    one matrix."""
    m = int(sizes[-1])
    h, local, rate = np.zeros((m, m)), np.zeros(m), np.zeros(m)
    for k, c in enumerate(contacts):
        sl = slice(sizes[k], sizes[k + 1])
        if c.base is not None:
            h[sl, sl] = c.base
        local[sl], rate[sl] = c.local_terms(lam[sl])
    h[np.diag_indices(m)] += local
    return h, rate


def closing_motion(n, elements, gmat, g0, q, u=None, signed=False):
    """The contacts that close as the load moves the assembly as a mechanism, one after
    another, and the motion that closes them: the motions that deform no element and open
    no contact already closed (the null space of every element's B and the closed
    contacts' G rows) projected on the load give the direction v; each open contact's gap
    closes at the ratio -g_i / (G v)_i; the smallest ratio's contacts close, and the motion
    goes on in what remains free until the load moves nothing (a disc turning its output
    pins closes its ring pins next). The rigid limit of the solution at a vanishing load:
    its output coordinate is the closing rotation of the clearances (the backlash's half).

    Parameters
    ----------
    n : int
        Number of coordinates.
    elements : sequence of Element
    gmat : numpy.ndarray, shape (m, n)
        The contacts' gap change per coordinate.
    g0 : numpy.ndarray, shape (m,)
        Initial gaps [m].
    q : numpy.ndarray, shape (n,)
        The load's direction.
    u : numpy.ndarray, optional
        Where to start (default at rest).
    signed : bool
        Let the first contacts close at a negative ratio where they overlap already (an
        interference: the motion is then how far the load's flank is already closed, < 0);
        else an overlapping contact closes at once.

    Returns
    -------
    active : numpy.ndarray of bool, shape (m,)
        The contacts closed.
    motion : numpy.ndarray, shape (n,)
        The mechanism's motion until the last of them closed.

    Raises
    ------
    ContactError
        If a body turns freely (no contact closes) or the load moves nothing.
    """
    rows = np.concatenate([e.b for e in elements], axis=0) if elements else np.zeros((0, n))
    gap = g0 + (0.0 if u is None else gmat @ u)
    active = np.zeros(g0.size, bool)
    motion = np.zeros(n)
    scale = np.max(np.abs(g0), initial=0.0)
    for _ in range(g0.size + 1):
        a = np.concatenate([rows, gmat[active]], axis=0)
        a = a / np.maximum(np.linalg.norm(a, axis=1), 1e-300)[:, None]
        _, sv, vt = np.linalg.svd(a) if a.size else (None, np.zeros(0), np.eye(n))
        rank = int(np.sum(sv > MECHANISM_RTOL * (sv[0] if sv.size else 1.0)))
        null = vt[rank:]
        v = null.T @ (null @ q)
        if np.linalg.norm(v) <= MECHANISM_RTOL * np.linalg.norm(q) * (1 + np.linalg.norm(v)):
            break
        rate = gmat @ v
        closing = ~active & (rate < -MECHANISM_RTOL * np.max(np.abs(rate), initial=0.0))
        if not np.any(closing):
            raise ContactError("no contact closes under the load: a body or the output "
                               "turns freely")
        reach = gap if signed and not np.any(active) else np.maximum(gap, 0.0)
        ratio = np.where(closing, reach / np.where(closing, -rate, 1.0), np.inf)
        first = np.min(ratio)
        gap = gap + first * rate
        motion = motion + first * v
        active |= closing & (gap <= 1e-9 * scale + 1e-15)
    if not np.any(active):
        raise ContactError("the load moves no mechanism: nothing for the contacts to carry")
    return active, motion


def rest(n: int, elements) -> np.ndarray:
    """The coordinates where no element is deformed: zero, or with forced deformations
    (``Element.offset``) the least-squares (smallest) u with B_e u = -offset_e for every
    element (where the offsets are not compatible, e.g. cranks of unequal eccentricity on
    rigid bearings, the compromise the least squares make). The solve's start from rest.

    Parameters
    ----------
    n : int
        Number of coordinates.
    elements : sequence of Element

    Returns
    -------
    numpy.ndarray, shape (n,)
    """
    if all(e.offset is None for e in elements):
        return np.zeros(n)
    rows = np.concatenate([e.b for e in elements], axis=0)
    rhs = np.concatenate([-(np.zeros(e.b.shape[0]) if e.offset is None else e.offset)
                          for e in elements])
    return np.linalg.lstsq(rows, rhs, rcond=None)[0]


#: Splits of element lists kept (:func:`_split_linear`): a system's elements at a position
#: are one list for every torque solved there.
SPLITS_KEPT = 256
_SPLITS: dict = {}


def _split_linear(elements, n):
    """(K of the linear elements summed (n, n), the constant force of their forced
    deformations sum B^T K offset (n,), the other elements grouped by their law:
    [(law, B stacked (G, d, n), offsets stacked (G, d))], evaluated together); kept for
    the same elements (the same objects: an Element is frozen, and the entry holds them,
    so their ids are not reused while it is kept), whose split is the same arrays."""
    key = (n, *map(id, elements))
    kept = _SPLITS.get(key)
    if kept is not None:
        return kept[1]
    out = _split(elements, n)
    if len(_SPLITS) >= SPLITS_KEPT:
        _SPLITS.pop(next(iter(_SPLITS)), None)
    _SPLITS[key] = (tuple(elements), out)
    return out


def _split(elements, n):
    """:func:`_split_linear`, computed."""
    k = np.zeros((n, n))
    forced = np.zeros(n)
    groups: dict = {}
    for e in elements:
        off = np.zeros(e.b.shape[0]) if e.offset is None else np.asarray(e.offset, float)
        if isinstance(e.law, Linear):
            k += e.b.T @ e.law.k @ e.b
            if e.offset is not None:
                forced += e.b.T @ (e.law.k @ off)
        else:
            g = groups.setdefault(id(e.law), (e.law, [], []))
            g[1].append(e.b)
            g[2].append(off)
    return k, forced, [(law, np.stack(bs), np.stack(offs))
                       for law, bs, offs in groups.values()]


def _internal(k_linear, forced, nonlinear, u, n, secant=False):
    """(F(u), K(u)) of every element: the linear ones' sum (and their forced deformations'
    constant force), the others by law at B u + offset, batched; ``secant``: each law's
    tangent over its ``homogeneity`` a (a law f(t delta) = t^a f(delta) has K delta = a f:
    K / a is its secant)."""
    force = k_linear @ u + forced
    stiff = k_linear.copy()
    for law, b, off in nonlinear:
        f, k = law(b @ u + off)                         # (G, d), (G, d, d)
        if secant:
            k = k / getattr(law, "homogeneity", 1.0)
        flat = b.reshape(-1, n)
        force += flat.T @ f.ravel()
        stiff += flat.T @ (k @ b).reshape(-1, n)
    return force, stiff


class Linear:
    """A linear law f = K delta; the solver assembles it once per solve.

    Parameters
    ----------
    stiffness : array_like, shape (d, d) or scalar
        K [N/m, N m/rad, ...].
    """

    def __init__(self, stiffness):
        self.k = np.atleast_2d(np.asarray(stiffness, float))

    def __call__(self, delta):
        """(f, K) at the deformation.

        Parameters
        ----------
        delta : array_like, shape (d,)

        Returns
        -------
        f : numpy.ndarray, shape (d,)
        k : numpy.ndarray, shape (d, d)
        """
        return self.k @ delta, self.k


def _linear_step(n, kt, rhs_u, gmat, g0, h, active):
    """(u, lambda, active) of K u - G^T lambda = rhs_u, g = g0 + H lambda + G u >= 0,
    lambda >= 0, lambda g = 0 (one Newton step's complementarity problem), from the
    active set ``active``: the primal-dual active set, every violated contact swapped at
    once; where that fails (many nearly equal contacts, as a pressure grid's, swing
    between signs and leave a body free), the cautious set from the same start: the
    negative forces leave, and only the most violated gap joins at a time."""
    try:
        return _active_set(n, kt, rhs_u, gmat, g0, h, active, cautious=False)
    except ContactError:
        return _active_set(n, kt, rhs_u, gmat, g0, h, active, cautious=True)


def _active_set(n, kt, rhs_u, gmat, g0, h, active, cautious):
    """:func:`_linear_step` with one strategy."""
    m = g0.size
    seen = set()
    hold = HOLD_REL * np.max(np.abs(np.diag(kt)), initial=1.0) * np.eye(n)
    for _ in range(MAX_ACTIVE_SET * (4 if cautious else 1)):
        idx = np.flatnonzero(active)
        held = False
        try:
            sol = _saddle(n, kt, gmat[idx], h[np.ix_(idx, idx)], rhs_u, g0[idx])
        except ContactError:
            # a set that leaves a body free (the active set passes through one as contacts
            # change): a vanishing stiffness on every coordinate moves the free body until
            # the contacts it meets join the set; a settled set never needs it
            sol = _saddle(n, kt + hold, gmat[idx], h[np.ix_(idx, idx)], rhs_u, g0[idx])
            held = True
        u = sol[:n]
        lam = np.zeros(m)
        lam[idx] = sol[n:]
        gap = g0 + h @ lam + gmat @ u
        if held:
            new = np.where(active, lam > 0, gap < 0)
            if np.array_equal(new, active):
                raise ContactError("singular system: a body or coordinate that nothing "
                                   f"holds ({idx.size} contacts carry)")
            active = new
            continue
        # a contact that touches without force (lambda = gap = 0, a degenerate pair) stays
        # as it is: round-off must not toss it in and out
        tol_lam = DEGENERATE_RTOL * np.max(np.abs(lam), initial=0.0)
        tol_gap = DEGENERATE_RTOL * np.max(np.abs(gap), initial=0.0)
        new = np.where(active, lam > -tol_lam, gap < -tol_gap)
        if np.array_equal(new, active):
            return u, np.maximum(lam, 0.0), active
        if cautious:
            leave = active & ~new
            new = active & ~leave
            if not np.any(leave):
                new[int(np.argmin(np.where(active, np.inf, gap)))] = True
        if not np.any(new):
            new = active & (lam >= np.max(lam))
        key = new.tobytes()
        if key in seen:          # cycling: move the worst violator only (Murty's rule)
            new = active.copy()
            viol = np.where(active, np.minimum(lam, 0.0), np.minimum(gap, 0.0))
            worst = int(np.argmin(viol / np.maximum(np.abs(viol).max(), 1e-300)))
            new[worst] = not active[worst]
        seen.add(key)
        active = new
    raise ContactError("the contact active set cycles")
