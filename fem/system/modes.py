"""The system model linearised about a loaded state, and its torsional-lateral modes
(docs/dynamics.md).

Tangent stiffness. At a solved state (fem/system/solve.py) every element answers a small
motion du with its tangent K_e (the rollers of a bearing at their loaded squeeze, a linear
part as it is), and the contacts that carry (force > 0) stay closed with their tangent
flexibility H_A = base_AA + diag(local + lam dlocal/dlam) (the FE influence and each
contact's Hertz or Palmgren approach linearised at its force: the solver's own Newton
matrix); those that do not carry stay open (a vibration smaller than the static approach
and the gaps). Eliminating the contact forces, -G_A du - H_A dlam = 0, gives

    K = sum_e B_e^T K_e B_e + sum_sets G_A^T H_A^-1 G_A,

whose inverse's output entry is the tangent compliance of the datasheet's twist at that
torque (the input held). Friction: the system model's friction is read off the solved
state (fem/system/friction.py), not a stiffness; the carrying contacts are taken to stick
in their normal direction and slide freely along it (no tangential stiffness), the bearings'
play as the static load leaves it (closed on the loaded side).

The input. Held, as in the quasi-static solve (the first stage's sun, or the K-H-V input
shaft's end, fixed). Free: a coordinate of its own, the input's rotation, enters the
deformation of the elements that tie the train to it (the spur mesh where there is one,
else the input shaft's torsion) by c_e = -B_e r, r the train's rigid motion (every other
element undeformed and every carrying contact closed: the null space of their rows) scaled
to turn the output by the train's ratio per unit input; the motor's inertia sits on it.

Modes. The generalised eigenproblem K phi = w^2 M phi (scipy.linalg.eigh) after the
coordinates without mass (the shafts' frames where nothing is lumped) are condensed
statically (exact for massless coordinates: Guyan's reduction with no inertia dropped).
Each mode's strain energy 1/2 phi^T K phi = 1/2 w^2 (mass-normalised) splits exactly into
its elements' 1/2 (B_e phi)^T K_e (B_e phi) and the contact sets' 1/2 (G_A phi)^T H_A^-1
(G_A phi): the shares by group (mesh, crank bearings, supports, crank bending and torsion,
output pins, spur mesh, carrier).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...errors import CaseError
from .datasheet import path_name
from .parts import softened

#: A rigid motion's singular value (relative to the largest) below which the rows leave it
#: free (the train's mechanism with the input's elements removed).
MECHANISM_RTOL = 1e-8
#: A mode whose w^2 is below this fraction of the largest is a rigid-body motion (the
#: whole train turning with the input free and no ground): reported at 0 Hz.
RIGID_RTOL = 1e-10


@dataclass(frozen=True)
class Linearised:
    """The tangent of one solved state: ``k`` (n, n) [N/m, N m/rad ...], each element's
    and contact set's part for the energy split (``parts``: (group, B (d, n), K_e (d, d))),
    the coordinates' names (``names``, one per coordinate) and the play and stick state
    assumed (``assumed``)."""
    k: np.ndarray
    parts: tuple
    names: tuple
    assumed: dict


def coordinate_names(coords, extra=()) -> tuple:
    """One name per coordinate: a block's name, with [x, y, theta] or an index.

    Parameters
    ----------
    coords : toothfem.fem.system.parts.Coordinates
    extra : sequence of str
        Names appended (the free input).

    Returns
    -------
    tuple of str
    """
    names = [""] * coords.n
    for name, sl in coords.index.items():
        size = sl.stop - sl.start
        if names[sl.start]:          # an alias (the carrier on the output)
            continue
        for i in range(size):
            suffix = "" if size == 1 else (("x", "y", "theta")[i] if name.startswith("disc")
                                           and size == 3 else ("x", "y")[i % 2]
                                           + ("" if size == 2 else str(i // 2 + 1)))
            names[sl.start + i] = name + ("" if not suffix else "." + suffix)
    return tuple(names) + tuple(extra)


def _contact_parts(system, state) -> list:
    """(group, G_A, H_A) of every contact set that carries at the state: the members'
    (rebuilt from the state's mesh solutions as the solve built them) and the path's."""
    c = system.coords
    scale = system.stiffness_scale.get("mesh", 1.0)
    out = []
    for s, sol in zip(system.slots, state.mesh):
        mc = sol.contacts
        gmat = np.zeros((mc.g0.size, c.n))
        dj = c.index[f"disc{s.index}"]
        gmat[:, dj.start:dj.start + 2] = -mc.normal.T
        gmat[:, dj.start + 2] = mc.arm
        base, local = softened(mc.base, mc.local, scale)
        out.append(("mesh", gmat, base, local, np.asarray(sol.force_N, float)))
    eq = state.equilibrium
    for cs in system.path.contacts(system, state.position_rad, state.output_torque_Nm):
        out.append((cs.group, cs.g, cs.base, cs.local, np.asarray(eq.forces[cs.name], float)))
    parts = []
    for group, gmat, base, local, lam in out:
        act = lam > 0
        if not np.any(act):
            continue
        h = np.zeros((lam.size, lam.size)) if base is None else np.array(base, float)
        if local is not None:
            sec, up = local(np.stack([lam, lam * (1 + 1e-6)]))
            h[np.diag_indices(lam.size)] += sec + np.where(lam > 0, (up - sec) / 1e-6, 0.0)
        ha = h[np.ix_(act, act)]
        if not np.all(np.isfinite(ha)) or np.linalg.matrix_rank(ha) < ha.shape[0]:
            raise CaseError(f"the {group} contacts have no flexibility (rigid contacts): "
                            "their tangent stiffness is infinite")
        parts.append((group, gmat[act], np.linalg.inv(ha)))
    return parts


def linearise(system, state, *, input_free: bool = False) -> Linearised:
    """The tangent stiffness of a solved state (the module docstring).

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    state : toothfem.fem.system.parts.SystemState
        Solved by ``system.solve`` (nominal: no deviation), with its equilibrium.
    input_free : bool
        Append the input's rotation as a coordinate (else the input is held).

    Returns
    -------
    Linearised

    Raises
    ------
    CaseError
        If the free input's rigid motion is not found (the train locked or loose).
    """
    c, eq = system.coords, state.equilibrium
    # the elements at the state's crank angle: the system keeps them per angle (assembly.py
    # has no public accessor and stands at its 600-line limit)
    elements = system._elements(state.position_rad)
    parts = []
    for e in elements:
        _, k = e.law(e.deformation(eq.u))
        parts.append((path_name(e.group), np.asarray(e.b, float), np.atleast_2d(k)))
    parts += _contact_parts(system, state)
    names = coordinate_names(c)
    if input_free:
        parts = _with_input(system, state, elements, parts)
        names = names + ("input",)
    n = names.__len__()
    k = np.zeros((n, n))
    for _, b, ke in parts:
        k += b.T @ ke @ b
    play = system.crank_bearing_play_m
    assumed = {
        "contacts": "the carrying contacts closed (their tangent flexibility at the static "
                    "force), the open ones open: a vibration below the static approach",
        "friction": "stick: the system model's friction adds no stiffness (it is read off "
                    "the solved state); the contacts slide freely along their surface",
        "bearings": f"rollers at their static squeeze, the crank bearings' diametral play "
                    f"{play * 1e6:g} um as the load closes it",
        "input": "free: the motor's inertia on the input's rotation" if input_free
                 else "held (the first stage's sun or the input shaft's end fixed)"}
    return Linearised(k=k, parts=tuple(parts), names=names, assumed=assumed)


def _input_group(system, elements) -> str:
    """The group of the elements that tie the train to its input: the first stage's spur
    mesh where the model has one, else the input shaft's torsion."""
    groups = {e.group for e in elements}
    return "spur mesh" if "spur mesh" in groups else system.group("crankshaft torsion")


def rigid_motion(system, state, elements=None, parts=None):
    """The train's rigid motion at a solved state, per unit input rotation: every element
    but those tying the train to its input undeformed and every carrying contact closed
    (the null space of their rows), scaled to turn the output by the train's ratio.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    state : toothfem.fem.system.parts.SystemState
    elements, parts : list, optional
        The state's elements and their linearised parts (:func:`linearise`'s), if known.

    Returns
    -------
    r : numpy.ndarray, shape (n,)
        [m, rad per rad of input].
    tied : list of int
        The indices of the elements that tie the train to its input.

    Raises
    ------
    CaseError
        If the train has no single rigid motion, or it does not turn the output.
    """
    if elements is None:
        elements = system._elements(state.position_rad)   # see linearise
    if parts is None:
        parts = [(e.group, np.asarray(e.b, float), None) for e in elements] \
            + _contact_parts(system, state)
    group = _input_group(system, elements)
    tied = [i for i, e in enumerate(elements) if e.group == group]
    rows = [p[1] for i, p in enumerate(parts) if i not in tied]
    a = np.concatenate(rows, axis=0)
    a = a / np.maximum(np.linalg.norm(a, axis=1), 1e-300)[:, None]
    _, sv, vt = np.linalg.svd(a)
    sv = np.concatenate([sv, np.zeros(vt.shape[0] - sv.size)])
    if sv[-1] > MECHANISM_RTOL * sv[0] or sv[-2] <= MECHANISM_RTOL * sv[0]:
        raise CaseError("input = 'free': the carrying contacts and the elements leave the "
                        "train no single rigid motion (the smallest singular values "
                        f"{sv[-2]:.3g}, {sv[-1]:.3g} of {sv[0]:.3g}): use input 'held'")
    r = vt[-1]
    w = system.drive.speeds()
    out = r[system.coords.index["out"]][0]
    if abs(out) < MECHANISM_RTOL * np.max(np.abs(r)):
        raise CaseError("the free input: its rigid motion does not turn the output")
    return r * (w["output"] / w["input"]) / out, tied


def _with_input(system, state, elements, parts) -> list:
    """``parts`` with a column for the input's rotation (the module docstring)."""
    r, tied = rigid_motion(system, state, elements, parts)
    extended = []
    for i, (g, b, ke) in enumerate(parts):
        col = -(b @ r)[:, None] if i in tied else np.zeros((b.shape[0], 1))
        extended.append((g, np.hstack([b, col]), ke))
    return extended


@dataclass(frozen=True)
class Modes:
    """Natural frequencies [Hz] by rising order, mass-normalised shapes (n, modes) on the
    coordinates ``names``, each mode's strain-energy share per group (``shares``: list of
    {group: share}, each summing to 1) and kinetic-energy share per coordinate block
    (``kinetic``)."""
    frequency_Hz: np.ndarray
    shapes: np.ndarray
    names: tuple
    shares: list
    kinetic: list


def block_of(name: str) -> str:
    """The coordinate block a coordinate's name belongs to (``disc0.x`` -> ``disc0``).

    Parameters
    ----------
    name : str

    Returns
    -------
    str
    """
    return name.split(".")[0]


def modes(lin: Linearised, mass: np.ndarray, count: int | None = None) -> Modes:
    """The modes of K phi = w^2 M phi, the massless coordinates condensed.

    Parameters
    ----------
    lin : Linearised
    mass : numpy.ndarray, shape (n, n)
        On the same coordinates (:func:`toothfem.fem.system.inertia.mass_matrix`).
    count : int, optional
        The lowest this many (default all).

    Returns
    -------
    Modes

    Raises
    ------
    CaseError
        If the mass matrix does not match or is not positive on the coordinates with mass.
    """
    k, m = lin.k, np.asarray(mass, float)
    if m.shape != k.shape:
        raise CaseError(f"mass matrix {m.shape} against stiffness {k.shape}")
    heavy = np.diag(m) > 0
    light = ~heavy
    kmm = k[np.ix_(heavy, heavy)]
    if np.any(light):
        kss = k[np.ix_(light, light)]
        ksm = k[np.ix_(light, heavy)]
        back = -np.linalg.solve(kss, ksm)
        kmm = kmm + k[np.ix_(heavy, light)] @ back
    else:
        back = np.zeros((0, int(heavy.sum())))
    kmm = 0.5 * (kmm + kmm.T)
    # equilibrated: masses of kg and inertias of 1e-5 kg m^2 side by side
    d = 1.0 / np.sqrt(np.diag(m)[heavy])
    w2, phi = scipy.linalg.eigh(kmm * d[:, None] * d[None, :],
                                m[np.ix_(heavy, heavy)] * d[:, None] * d[None, :])
    phi = phi * d[:, None]
    count = w2.size if count is None else min(int(count), w2.size)
    w2, phi = w2[:count], phi[:, :count]
    full = np.zeros((k.shape[0], count))
    full[heavy] = phi
    full[light] = back @ phi
    rigid = w2 <= RIGID_RTOL * max(np.max(np.abs(w2)), 1e-300)
    freq = np.where(rigid, 0.0, np.sqrt(np.maximum(w2, 0.0)) / (2 * math.pi))
    shares, kinetic = [], []
    blocks = [block_of(nm) for nm in lin.names]
    for i in range(count):
        v = full[:, i]
        energy: dict[str, float] = {}
        for g, b, ke in lin.parts:
            db = b @ v
            energy[g] = energy.get(g, 0.0) + 0.5 * float(db @ ke @ db)
        total = sum(energy.values())
        shares.append({g: (e / total if total > 0 else 0.0) for g, e in energy.items()})
        kin: dict[str, float] = {}
        mv = m @ v
        for j, blk in enumerate(blocks):
            kin[blk] = kin.get(blk, 0.0) + 0.5 * float(v[j] * mv[j])
        tk = sum(kin.values())
        kinetic.append({b: x / tk for b, x in kin.items()})
    return Modes(frequency_Hz=freq, shapes=full, names=lin.names, shares=shares,
                 kinetic=kinetic)


def output_compliance(lin: Linearised, out_index: int) -> float:
    """The tangent compliance at the output, [K^-1]_out,out [rad/(N m)] (the input as
    ``lin`` has it): the datasheet's twist per torque at this state.

    Parameters
    ----------
    lin : Linearised
    out_index : int

    Returns
    -------
    float
    """
    e = np.zeros(lin.k.shape[0])
    e[out_index] = 1.0
    return float(np.linalg.solve(lin.k, e)[out_index])
