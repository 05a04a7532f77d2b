"""The split of the output torque between members that carry it side by side (the discs of
a cycloid or RV drive; docs/stiffness.md).

Each member is a load path from the output to the housing: its own path (its mesh and its
own bearings) twists by f_j(T_j) under its torque T_j, and the parts the members share (the
crankshafts) add (S T)_j, S their coupled compliance. The members turn the output alike:
f_j(T_j) + (S T)_j = theta for every loaded member, sum T_j = T. Each f_j rises with T_j,
so the torques are unique; a member whose flank stays open at theta carries nothing.
:func:`member_torques` finds them by Newton's method for any f_j: a table interpolated
linearly (the full-period split, fem/datasheet/transmission.py) or the FE itself (the
hysteresis loop, fem/datasheet/twist.py).
"""
from __future__ import annotations

import numpy as np

#: Member torques, as multiples of the even share T/M, at which each member's own path is
#: tabulated for the full-period split (those above M, the whole output torque, are
#: dropped). Between them the twist is interpolated linearly: the mesh's twist is concave in
#: the torque (the Hertzian and the closing contacts stiffen it), and at these spacings the
#: chord departs from the curve by at most 0.41 % of the twist from 0.05 T/M up, 0.15 % from
#: 0.2 T/M up (the pin-housing drive and its three-disc variant, measured; tests/test_split.py
#: checks the twists the split balances against direct FE solves).
SPLIT_LEVELS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.35,
                1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0)
#: Newton steps allowed for one split (a piecewise-linear table ends once each member's
#: torque is on its final segment; the FE's secant steps settle in a few).
SPLIT_ITERATIONS = 50


def split_levels(members: int) -> tuple:
    """The SPLIT_LEVELS a member of ``members`` can reach (T_j <= T, i.e. <= M T/M).

    Parameters
    ----------
    members : int
        M.

    Returns
    -------
    tuple of float
        Multiples of the even share, rising from 0.
    """
    return tuple(r for r in SPLIT_LEVELS if r <= members)


def coupled_matrix(drive, supports) -> np.ndarray:
    """The shared parts' compliance between the members, every part summed.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports

    Returns
    -------
    numpy.ndarray, shape (M, M)
        S [rad/(N m)]: member j turns by ``S[j] @ T`` under the member torques T.
    """
    m = drive.members
    return sum(drive.coupled_compliance(supports).values(), np.zeros((m, m)))


def even_coupling(coupling) -> bool:
    """Whether the shared parts load every member alike under the even split (equal row
    sums of S): with the members' own paths alike too, T/M each is then the split.

    Parameters
    ----------
    coupling : numpy.ndarray, shape (M, M)
        S [rad/(N m)].

    Returns
    -------
    bool
    """
    rows = np.asarray(coupling, float).sum(axis=1)
    return bool(np.allclose(rows, rows[0], rtol=1e-12, atol=0.0))


def table_paths(torques, twists):
    """The own paths of a table, interpolated linearly (extrapolated beyond the last).

    Parameters
    ----------
    torques : numpy.ndarray, shape (L,)
        Member torques, rising from 0 [N m].
    twists : numpy.ndarray, shape (M, L)
        Each member's own twist at them [rad], rising.

    Returns
    -------
    callable
        ``paths(x) -> (f (M,), slope (M,))`` at member torques x (M,) [rad, rad/(N m)].
    """
    torques = np.asarray(torques, float)
    rows = np.arange(twists.shape[0])

    def paths(x):
        seg = np.clip(np.searchsorted(torques, x, side="right") - 1, 0, torques.size - 2)
        slope = ((twists[rows, seg + 1] - twists[rows, seg])
                 / (torques[seg + 1] - torques[seg]))
        return twists[rows, seg] + slope * (x - torques[seg]), slope
    return paths


def member_torques(paths, coupling, total: float, unloaded, *, start=None,
                   tol: float = 1e-12):
    """Member torques T_j >= 0 with sum ``total`` that turn every loaded member alike:
    f_j(T_j) + (S T)_j = theta where T_j > 0, and f_j(0) + (S T)_j >= theta where T_j = 0
    (that member's flank stays open). Newton's method with an active set.

    Parameters
    ----------
    paths : callable
        ``paths(x) -> (f, slope)``, each (M,): the own paths' twists at member torques x
        [rad] and their slopes [rad/(N m)] (:func:`table_paths`, or the FE's).
    coupling : numpy.ndarray, shape (M, M)
        S [rad/(N m)].
    total : float
        T [N m], > 0.
    unloaded : numpy.ndarray, shape (M,)
        f_j(0) [rad], each member's twist as its flank closes.
    start : numpy.ndarray, shape (M,), optional
        First guess (a neighbour's split), default T/M each.
    tol : float
        Settled when no torque moves by more than ``tol * total`` in a step.

    Returns
    -------
    x : numpy.ndarray, shape (M,)
        T_j [N m].
    theta : float
        The common twist [rad].

    Raises
    ------
    RuntimeError
        If Newton's method has not settled in SPLIT_ITERATIONS steps.
    """
    m = len(unloaded)
    x = np.full(m, total / m) if start is None else np.clip(start, 0.0, total)
    free = np.ones(m, bool)
    for _ in range(SPLIT_ITERATIONS):
        f, slope = paths(x)
        idx = np.flatnonzero(free)
        n = idx.size
        a = np.zeros((n + 1, n + 1))
        a[:n, :n] = coupling[np.ix_(idx, idx)] + np.diag(slope[idx])
        a[:n, n] = -1.0
        a[n, :n] = 1.0
        sol = np.linalg.solve(a, np.concatenate([slope[idx] * x[idx] - f[idx], [total]]))
        new = np.zeros(m)
        new[idx] = sol[:n]
        theta = sol[n]
        if np.any(new < 0):                     # the most unloaded member's flank opens
            free[idx[np.argmin(sol[:n])]] = False
            x = np.clip(new, 0.0, total)
            continue
        # an open member whose unloaded twist is below theta picks load up again
        opened = ~free & (np.asarray(unloaded) + coupling @ new < theta)
        if np.any(opened):
            free |= opened
            x = new
            continue
        if np.max(np.abs(new - x)) <= tol * total:
            return new, theta
        x = new
    raise RuntimeError(f"the member split did not settle in {SPLIT_ITERATIONS} Newton steps "
                       f"(torques {x.tolist()} N m)")
