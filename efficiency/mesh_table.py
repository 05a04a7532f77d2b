"""The loaded contacts of one meshing period, from either load source.

A :class:`MeshTable` flattens the contacts that carry load over (position, contact) with
their kinematics at unit crank speed and their loads at a few member torques; the friction
loss is then a vectorised sum over it at any operating point. ``loads='analytic'`` takes
the seeds' split, ``loads='fem'`` the FE cycle solver of the drive (its influence tables in
the disk cache).
"""
from __future__ import annotations

import contextlib
import math
from contextvars import ContextVar
from dataclasses import dataclass, replace

import numpy as np

from ..errors import CaseError
from ..fem.datasheet.transmission import DEFAULT_SAMPLES, even_by_layout, even_split
from ..fem.system.datasheet import system_te

LOADS = ("analytic", "fem")

#: Torques, as fractions of the case's declared torque on the member, at which the FE load
#: sharing is tabulated (fixed by the case, not by the points asked for, so a point's result
#: does not depend on the other points of the call); outside the range F/T is held at the end
#: value and the notes say so.
FE_TORQUE_FRACTIONS = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0)
#: How an FE load table shows its progress: None (quietly), or a progress-bar factory
#: called as ``bar(total=..., desc=..., unit=...)`` that returns a context manager with an
#: ``update()`` method (tqdm's signature). The command line sets it for one command
#: (:func:`fe_progress`): the table's solves take seconds to a minute, deep in the
#: efficiency model.
FE_PROGRESS: ContextVar = ContextVar("FE_PROGRESS", default=None)


@dataclass(frozen=True, kw_only=True)
class MeshTable:
    """Loaded contacts of one meshing period, flattened over (position, contact).

    Velocities are for a crank speed of 1 rad/s (they scale with it); loads are known at
    ``torques`` (N m on the moving member) and interpolated as F/T and P_h/sqrt(T), which
    is exact for the analytic split (one torque) and for a fixed contact set.
    """
    loads: str
    n_positions: int
    torques: np.ndarray            # (K,)
    force: np.ndarray              # (K, N) N
    ph: np.ndarray                 # (K, N) Pa
    position: np.ndarray           # (N,) position index
    vs: np.ndarray                 # (N,) |sliding speed| at unit crank speed, m/s
    ve: np.ndarray                 # (N,) |entraining speed| at unit crank speed, m/s
    r_eq: np.ndarray               # (N,) m
    normal: np.ndarray             # (N, 2) fixed -> moving member
    centre: np.ndarray             # (P, 2) centre of the moving member, m
    face_width: float
    pressure_from_fe: np.ndarray   # (N,) bool
    hertz_invalid: np.ndarray      # (N,) bool

    def at(self, torque):
        """Contact forces and peak pressures at moving-member torques, interpolated as F/T and
        P_h/sqrt(T) (held at the end values outside ``torques``).

        Parameters
        ----------
        torque : array_like, shape (M,)
            Torques on the moving member [N m].

        Returns
        -------
        force : numpy.ndarray, shape (M, N)
            Contact forces [N].
        ph : numpy.ndarray, shape (M, N)
            Peak Hertz pressures [Pa].
        """
        t = np.asarray(torque, float)[:, None]
        if self.torques.size == 1:
            f1 = self.force[0] / self.torques[0]
            p1 = self.ph[0] / math.sqrt(self.torques[0])
            return t * f1, np.sqrt(t) * p1
        f_t = self.force / self.torques[:, None]
        p_t = self.ph / np.sqrt(self.torques)[:, None]
        tt = np.clip(t[:, 0], self.torques[0], self.torques[-1])
        f = np.stack([np.interp(tt, self.torques, f_t[:, j]) for j in range(f_t.shape[1])], 1)
        p = np.stack([np.interp(tt, self.torques, p_t[:, j]) for j in range(p_t.shape[1])], 1)
        return t * f, np.sqrt(t) * p

    def resultant(self, force):
        """Resultant contact force on the moving member at each position.

        Parameters
        ----------
        force : numpy.ndarray, shape (M, N)
            Contact forces [N] (:meth:`at`).

        Returns
        -------
        numpy.ndarray, shape (M, P, 2)
            Resultant [N], housing frame, fixed -> moving member.
        """
        m, p = force.shape[0], self.n_positions
        # each point's contacts summed into their positions in the contacts' order (a
        # bincount adds as np.add.at does, one after the other, at a tenth of its time)
        cell = (np.arange(m)[:, None] * p + self.position[None, :]).ravel()
        out = np.empty((m, p, 2))
        for k in range(2):
            out[:, :, k] = np.bincount(cell, weights=(force * self.normal[:, k]).ravel(),
                                       minlength=m * p).reshape(m, p)
        return out

    def scaled(self, ratio):
        """The table with the loads of each position scaled: forces by ``ratio`` there,
        peak pressures by its square root (Hertz's line contact).

        Parameters
        ----------
        ratio : array_like, shape (P,)
            Factor at each position of the period [-], > 0.

        Returns
        -------
        MeshTable
        """
        r = np.asarray(ratio, float)[self.position]
        return replace(self, force=self.force * r, ph=self.ph * np.sqrt(r))


def table_from_records(state, records, loads):
    """A :class:`MeshTable` from load-sharing records.

    Parameters
    ----------
    state : toothfem.geometry.kinematics.MeshingState
        Kinematics of the period at unit crank speed (the records' positions).
    records : sequence of toothfem.fem.load_sharing.LoadSharing
        Load sharing at increasing member torques (any source: analytic, FE, another
        contact model).
    loads : str
        Name of the load source, kept on the table.

    Returns
    -------
    MeshTable
    """
    loaded = np.zeros(state.shape, bool)
    for r in records:
        loaded |= r.force > 0
    pos, con = np.nonzero(loaded)
    return MeshTable(
        loads=loads, n_positions=state.shape[0],
        torques=np.array([r.torque for r in records]),
        force=np.stack([r.force[pos, con] for r in records]),
        ph=np.stack([r.ph[pos, con] for r in records]),
        position=pos, vs=np.abs(state.sliding_velocity[pos, con]),
        ve=np.abs(state.entrainment_velocity[pos, con]),
        r_eq=np.abs(state.equivalent_radius[pos, con]),
        normal=state.normal[pos, con], centre=np.asarray(state.centre),
        face_width=records[0].face_width,
        pressure_from_fe=np.any([r.pressure_from_fe[pos, con] for r in records], axis=0),
        hertz_invalid=np.any([r.hertz_invalid[pos, con] for r in records], axis=0))


def mesh_table(drive, loads: str = "analytic", n_positions: int = 36,
               torque_ref: float | None = None) -> MeshTable:
    """The meshing table of a drive over one period.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    loads : {"analytic", "fem"}
        The seeds' split at unit torque, or the FE cycle solver at
        ``FE_TORQUE_FRACTIONS`` of ``torque_ref``.
    n_positions : int
        Positions over the period.
    torque_ref : float, optional
        Reference member torque [N m] of the FE table (required for ``loads='fem'``).

    Returns
    -------
    MeshTable

    Raises
    ------
    CaseError
        If ``loads`` is not one of :data:`LOADS`, or ``loads='fem'`` without
        ``torque_ref``.
    """
    if loads not in LOADS:
        raise CaseError(f"loads = {loads!r} is not one of {list(LOADS)}")
    state = drive.meshing(drive.positions(n_positions), 1.0)
    if loads == "analytic":
        recs = [drive.analytic_split(state, 1.0)]
    else:
        if torque_ref is None:
            raise CaseError("loads = 'fem' needs torque_ref (the FE table's reference "
                            "member torque [N m])")
        recs = _fe_records(drive.cycle_solver(n_positions),
                           [f * torque_ref for f in FE_TORQUE_FRACTIONS], n_positions)
    return table_from_records(state, recs, loads)


def fe_member_split(drive, supports, output_torque_Nm: float, n_positions: int):
    """The FE split of the output torque between the members, its solvers counted on the
    :data:`FE_PROGRESS` bar when one is set: even where the layout makes it so
    (:func:`toothfem.fem.datasheet.transmission.even_by_layout`, nothing solved), else from
    the system model (:func:`toothfem.fem.system.datasheet.system_te`).

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    output_torque_Nm : float
        Output torque of the split [N m].
    n_positions : int
        Positions per pitch (the FE load table's).

    Returns
    -------
    toothfem.fem.datasheet.transmission.MemberSplit or None
        None for one member.
    """
    bar = FE_PROGRESS.get()
    counted = None
    if bar is not None:
        def counted(pitches):           # the bar appears only if the split is solved
            with bar(total=len(pitches), desc="FE member split", unit="solver") as shown:
                yield from _counted(shown, pitches)
    if drive.members == 1:
        return None
    if even_by_layout(drive, supports, n_positions):
        return even_split(drive, output_torque_Nm, n_positions)
    return system_te(drive, supports, output_torque_Nm, samples=DEFAULT_SAMPLES,
                     per_pitch=n_positions, progress=counted)[1]   # the split


#: Film and friction arrays a :class:`LoadsMemo` keeps (three (M, N) arrays each: 17 MB
#: at 4913 points of 142 contacts).
FILMS_KEPT = 4


class LoadsMemo:
    """The loads one computation has met (a run, a heat balance, a fit), kept by that
    computation and passed as an argument (``evaluate(..., memo=)``): each drive's mesh
    table and FE split is computed once for it, and nothing is kept between computations
    (no module-level cache).
    """

    def __init__(self):
        self._tables: dict = {}
        self._splits: dict = {}
        self._films: dict = {}

    def film(self, key, compute):
        """The mesh contacts' film and friction arrays of one set of inputs
        (:func:`toothfem.efficiency.contact_friction.contact_mu`), computed once: a fit's
        evaluations that change a loss beside the contacts (a drag, the churning, the
        boundary friction) meet the same contacts again. The last :data:`FILMS_KEPT` are
        kept.

        Parameters
        ----------
        key : hashable
            The inputs' fingerprint.
        compute : callable
            ``compute()`` gives the arrays.

        Returns
        -------
        object
            ``compute()``'s result (shared: not to be written to).
        """
        if key in self._films:
            self._films[key] = self._films.pop(key)          # the most recent last
        else:
            self._films[key] = compute()
            while len(self._films) > FILMS_KEPT:
                del self._films[next(iter(self._films))]
        return self._films[key]

    def table(self, drive, loads: str, n_positions: int, torque_ref: float | None = None):
        """:func:`mesh_table`, computed once per drive, load source, positions and
        reference torque.

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive
        loads : {"analytic", "fem"}
        n_positions : int
        torque_ref : float, optional
            [N m] on the member (the FE table's).

        Returns
        -------
        MeshTable
        """
        key = (drive, loads, int(n_positions), torque_ref)
        if key not in self._tables:
            self._tables[key] = mesh_table(drive, loads, n_positions, torque_ref)
        return self._tables[key]

    def split(self, drive, supports, output_torque_Nm: float, n_positions: int):
        """:func:`fe_member_split`, computed once per drive, supports, torque and positions.

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive
        supports : toothfem.fem.datasheet.supports.Supports
        output_torque_Nm : float
            [N m].
        n_positions : int

        Returns
        -------
        toothfem.fem.datasheet.transmission.MemberSplit or None
        """
        key = (drive, supports, float(output_torque_Nm), int(n_positions))
        if key not in self._splits:
            self._splits[key] = fe_member_split(drive, supports, output_torque_Nm, n_positions)
        return self._splits[key]


@contextlib.contextmanager
def fe_progress(bar):
    """Within this context, FE load tables report their positions to ``bar``.

    Parameters
    ----------
    bar : callable
        A progress-bar factory such as tqdm (:data:`FE_PROGRESS`).

    Yields
    ------
    None
        Control, with ``bar`` set until the context exits.
    """
    token = FE_PROGRESS.set(bar)
    try:
        yield
    finally:
        FE_PROGRESS.reset(token)


def _fe_records(solver, torques, n_positions):
    """The cycle solver's load sharing at each torque, the positions counted on the
    :data:`FE_PROGRESS` bar when one is set (the first torque also builds the solver's
    meshes and tables)."""
    bar = FE_PROGRESS.get()
    if bar is None:
        return [solver.solve(t) for t in torques]
    with bar(total=len(torques) * n_positions, desc="FE load table", unit="position") as shown:
        return [solver.solve(t, progress=lambda items: _counted(shown, items))
                for t in torques]


def _counted(shown, items):
    """``items``, one at a time, each counted on the bar ``shown`` once it is done."""
    for item in items:
        yield item
        shown.update()


def fe_reference(declared_member_torque, member_torque, notes) -> float:
    """Reference member torque of the FE table: the case's declared torque on the member,
    else the largest asked for; a note where points fall outside the table.

    Parameters
    ----------
    declared_member_torque : float or None
        The case's declared torque on the member [N m].
    member_torque : numpy.ndarray, shape (M,)
        Member torques asked for [N m].
    notes : list of str
        A note is appended here when a point falls outside the table's range.

    Returns
    -------
    float
        The reference torque [N m].
    """
    ref = declared_member_torque or float(np.max(member_torque))
    lo, hi = FE_TORQUE_FRACTIONS[0] * ref, FE_TORQUE_FRACTIONS[-1] * ref
    out = (member_torque < lo) | (member_torque > hi)
    if np.any(out):
        notes.append(f"{int(out.sum())} point(s) outside the FE load table's member-torque "
                     f"range {lo:.3g}-{hi:.3g} N m: the load split of the nearest end is "
                     "scaled to them")
    return ref
