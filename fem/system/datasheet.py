"""The datasheet from the system model: the twist at any output torque (what
:func:`toothfem.fem.datasheet.sheet.datasheet` reads), and the one transmission error over
the drive's full period with the split between the discs (docs/stiffness.md).

The transmission error is one quantity everywhere: the output's lag behind its kinematic
position at a crank angle, input held at that angle, under the output torque: the system
model's output rotation. Its parts are the work balance's (fem/system/solve.py): the mesh
(the FE contact's approach and the clearances it closes), each bearing group, the shafts'
bending and torsion, the spur mesh, the output pins; they add up to it exactly.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ..datasheet.transmission import (MemberSplit, check_te_inputs, fourier_fill,
                                      loaded_record, sampled_pitches)
from ..datasheet.twist import ARCMIN, ZERO_TORQUE_NM, TwistPoint

if TYPE_CHECKING:        # the layouts' assembly lives with the drives (fem/drives/assembly.py)
    from ..contracts import ReducerModel
    from ..drives.assembly import SystemState

#: Every part of the twist is named after the part; a contact set's closed clearance
#: ("mesh clearance") is reported with the contacts ("mesh").
CLEARANCE_SUFFIX = " clearance"


def path_name(group: str) -> str:
    """The datasheet's path of a work-balance group (a clearance with its contacts).

    Parameters
    ----------
    group : str
        E.g. "mesh clearance".

    Returns
    -------
    str
        E.g. "mesh".
    """
    return group[:-len(CLEARANCE_SUFFIX)] if group.endswith(CLEARANCE_SUFFIX) else group


def system_backlash_arcmin(system: ReducerModel, *, deviation=None, geometry=None,
                           pitches=None) -> float:
    """The backlash, the two flanks' closing rotations of the clearances with every part
    rigid (:meth:`CycloidSystem.closing_rotation`), averaged over the positions.

    Parameters
    ----------
    system : CycloidSystem
    deviation : toothfem.fem.deviations.CycloidDeviation, optional
        A built stage.
    geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
        Another modification of the disc, on the system's tables.
    pitches : array_like of int, optional
        The built stage's pin pitch at each position.

    Returns
    -------
    float
        [arcmin] (< 0: the flanks interfere).
    """
    n = len(system.slots[0].solver.positions_rad)
    out = []
    for p in range(n):
        opts = {"deviation": deviation, "geometry": geometry,
                "pitch": 0 if pitches is None else int(pitches[p])}
        out.append(system.closing_rotation(p, 1, **opts)
                   - system.closing_rotation(p, -1, **opts))
    return float(np.mean(out) / ARCMIN)


def _paths(states) -> dict:
    """{path: (P,) rad} of states at the positions."""
    names = []
    for st in states:
        for g in st.paths_rad:
            if path_name(g) not in names:
                names.append(path_name(g))
    out = {name: np.zeros(len(states)) for name in names}
    for p, st in enumerate(states):
        for g, v in st.paths_rad.items():
            out[path_name(g)][p] += v
    mesh = out.pop("mesh", None)
    return {"mesh": mesh, **out} if mesh is not None else out


class SystemTwist:
    """The twist of the reducer at any output torque over the positions of one pitch, from
    the system model: the twist model :func:`toothfem.fem.datasheet.sheet.datasheet` reads.

    With ``friction`` the twist depends on the way the torque came: on a branch of
    direction s (+1 the torque rising, -1 falling) the elastic system carries
    T_e = T - s T_f(T_e), T_f the friction torque the output meets at T_e
    (:meth:`CycloidSystem.solve`'s ``friction_Nm``, the mean over the positions); at a
    reversal the contacts stick until the torque has changed by 2 T_f (the play operator
    of a Coulomb element with rigid stick: docs/stiffness.md, "Friction").

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    progress : callable, optional
        Wraps each torque's iterator over the positions.
    friction : toothfem.fem.drives.assembly.PathFriction, optional
        None: frictionless (the elastic curve).
    deviation : toothfem.fem.deviations.CycloidDeviation, optional
        A built stage (:meth:`CycloidSystem.solve`).
    pitches : array_like of int, optional
        The built stage's pin pitch at each position.
    reference : SystemTwist, optional
        A twist of the same system and positions (the nominal design of a built ring):
        each torque's solve starts from its states at that torque (a few um away: the
        contacts that carry mostly the same).
    geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
        The disc with other modifications on the system's tables
        (:meth:`CycloidSystem.solve`).
    """

    def __init__(self, system: ReducerModel, progress=None, friction=None, deviation=None,
                 pitches=None, reference: SystemTwist | None = None, geometry=None):
        self.system = system
        self.friction = friction
        self.deviation = deviation
        self.geometry = geometry
        self.pitches = None if pitches is None else np.asarray(pitches, int)
        self.drive = system.drive
        self.supports = system.supports
        self.positions_rad = np.asarray(system.slots[0].solver.positions_rad, float)
        self.progress = progress
        self.reference = reference
        self._memo: dict[float, list[SystemState]] = {}
        self._last: dict[int, list[SystemState]] = {}   # flank -> the last torque's states (a start)

    def states(self, output_torque_Nm: float, side: int = 1) -> list:
        """The system's states at every position (kept: each torque is solved once).

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign; zero is the limit from ``side`` (ZERO_TORQUE_NM of that
            sign: the clearances' closing, the elastic parts some 1e-6 of the rated twist).
        side : {1, -1}
            The flank at zero torque.

        Returns
        -------
        list of SystemState
        """
        t = float(output_torque_Nm)
        flank = side if t == 0 else int(math.copysign(1, t))
        t = flank * ZERO_TORQUE_NM if t == 0 else t
        if t not in self._memo:
            last = self._last.get(flank) if self.reference is None else \
                self.reference.states(t, side)
            it = range(self.positions_rad.size)
            it = it if self.progress is None else self.progress(it)
            self._memo[t] = [self.system.solve(
                t, p, start=None if last is None else last[p], friction=self.friction,
                deviation=self.deviation, geometry=self.geometry,
                pitch=0 if self.pitches is None else int(self.pitches[p])) for p in it]
            self._last[flank] = self._memo[t]
        return self._memo[t]

    @property
    def friction_description(self) -> str:
        """What the summary says of the friction in the path."""
        f = self.friction
        if f is None:
            return "off: frictionless contact, the loop's width is the backlash"
        return (f"Coulomb in the quasi-static path, rigid stick at reversals: pin contacts "
                f"mu {f.pin_disc:g} (grooves {f.pin_groove:g}), bearings mu {f.bearing:g}, "
                f"output pins mu {f.output_pin:g}, {f.output_torque_Nm:.3g} N m on the "
                "output (seal, main bearings)")

    def carried(self, output_torque_Nm: float, branch: int) -> float:
        """T_e, the torque the elastic system carries at the output torque T on a branch:
        T_e = T - branch T_f(T_e): a Newton step from the elastic state at T, then secant
        steps (T_f is a few per cent of T and smooth in it: one or two solves a point).

        Parameters
        ----------
        output_torque_Nm : float
            T [N m].
        branch : {1, -1, 0}
            The torque rising (+1) or falling (-1); 0 or no friction: T itself.

        Returns
        -------
        float
            [N m].
        """
        t = float(output_torque_Nm)
        if not branch or self.friction is None:
            return t

        def residual(te):           # g(T_e) - T_e, g(T_e) = T - branch T_f(T_e)
            side = int(math.copysign(1, te)) if te else -branch
            tf = float(np.mean([s.friction_torque_Nm for s in self.states(te, side)]))
            return t - branch * tf - te, tf

        # from the elastic state at T itself (the loop's own torque, shared by both
        # branches), a Newton step on T_f = c0 + c1 |T_e| (c0 the load-independent part),
        # then secant steps on the residual
        x0 = t
        r0, tf = residual(x0)
        c1 = (tf - self.friction.output_torque_Nm) / abs(x0) if x0 else 0.0
        x1 = x0 + r0 / (1.0 + branch * c1 * math.copysign(1.0, x0))
        for _ in range(FRICTION_ITERATIONS):
            r1, tf = residual(x1)
            if abs(r1) <= FRICTION_RTOL * max(tf, 1e-12):
                return x1
            x0, r0, x1 = x1, r1, (x1 + r1 if r1 == r0 else x1 - r1 * (x1 - x0) / (r1 - r0))
        return self._bisected(t, residual, tf)

    def _bisected(self, t: float, residual, tf: float) -> float:
        """T_e by bisection where the secant steps fail: T_f jumps with T_e where a
        contact opens or a play closes (the loop's knee), and T - branch T_f(T_e) - T_e
        falls with T_e at a slope of about -1 between the jumps, so a bracket about T
        closes on the root, or on the jump that steps over it (the friction is set-valued
        there: the path sticks at that torque)."""
        width = 2.0 * max(abs(tf), self.friction.output_torque_Nm, 1e-9)
        lo, hi = t - width, t + width
        for _ in range(FRICTION_ITERATIONS):
            if residual(lo)[0] > 0 > residual(hi)[0]:
                break
            lo, hi, width = lo - width, hi + width, 2.0 * width
        else:
            raise CaseError(f"the friction torque at {t:g} N m did not settle (friction "
                            "coefficients too large for the drive to turn its output?)")
        for _ in range(BISECTIONS):
            mid = 0.5 * (lo + hi)
            r, tf = residual(mid)
            if abs(r) <= FRICTION_RTOL * max(tf, 1e-12) \
                    or hi - lo <= FRICTION_RTOL * max(tf, 1e-12):
                return mid
            lo, hi = (mid, hi) if r > 0 else (lo, mid)
        return 0.5 * (lo + hi)

    def at(self, output_torque_Nm: float, side: int = 1, branch: int = 0) -> TwistPoint:
        """The twist at a signed output torque.

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign.
        side : {1, -1}
            At zero torque, the flank the limit comes from.
        branch : {0, 1, -1}
            With friction: the torque rising (+1) or falling (-1) to this value; 0 the
            elastic curve (no friction).

        Returns
        -------
        toothfem.fem.datasheet.twist.TwistPoint
            ``paths``: the parts of the work balance; ``contacts``: the first disc's pins
            in contact; ``member_torques_Nm``: each disc's mean torque.
        """
        te = self.carried(output_torque_Nm, branch)
        if te != output_torque_Nm:
            side = int(math.copysign(1, te)) if te else side
        sts = self.states(te, side)
        return TwistPoint(output_torque_Nm=float(output_torque_Nm),
                          total=np.array([s.twist_rad for s in sts]), paths=_paths(sts),
                          contacts=np.array([s.contacts[0] for s in sts]),
                          member_torques_Nm=tuple(float(x) for x in np.mean(
                              [s.disc_torque_Nm for s in sts], axis=0)))


def system_te(drive, supports, output_torque_Nm: float, *, samples: int, per_pitch: int,
              cache=True, progress=None, deviation=None, geometry=None,
              full_period: int | None = None, **options):
    """The transmission error over the full period and the split between the discs, from
    the system model at ``samples`` pitches spread over the period (each a system over one
    pitch, its discs' FE tables at their true configurations) filled by a Fourier series in
    the pitch (:func:`toothfem.fem.datasheet.transmission.fourier_fill`).

    Parameters
    ----------
    drive : toothfem.fem.drives.cycloid.CycloidDrive
    supports : toothfem.fem.datasheet.supports.Supports
    output_torque_Nm : float
        [N m], nonzero.
    samples, per_pitch : int
        Sampled pitches, and positions per pitch of each.
    cache
        The FE tables' disk cache.
    progress : callable, optional
        Wraps the iterator over the sampled pitches.
    deviation : toothfem.fem.deviations.CycloidDeviation, optional
        A built stage, solved at each sampled pitch's true positions
        (:meth:`CycloidSystem.solve`); its period may be longer than the drive's
        (``full_period``, :meth:`toothfem.fem.drives.base.Drive.deviation_period_pitches`).
    geometry : toothfem.geometry.cycloid.CycloidGeometry, optional
        The disc with other modifications on the tables (:meth:`CycloidSystem.solve`).
    full_period : int, optional
        Pitches after which the TE repeats (default ``drive.full_period_pitches``).
    **options
        Go to :class:`CycloidSystem`.

    Returns
    -------
    (LoadedTE, MemberSplit or None, BearingLoads)
        ``mesh_rad``: the mesh's part of the TE (the pin contacts' approach and closed
        clearances, every disc); the split: each disc's torque over the discs' sum; every
        bearing's load over the full period.
    """
    check_te_inputs(output_torque_Nm, samples, per_pitch)
    k = drive.full_period_pitches if full_period is None else int(full_period)
    pitches = sampled_pitches(k, samples)
    # one system at a time (its tables read as it is solved; a bar steps per pitch)
    systems = (drive.system_model(supports, per_pitch, cache=cache, pitch=m, **options)
               for m in (pitches if progress is None else progress(pitches)))
    return period_te(systems, pitches, output_torque_Nm, full_period=k, deviation=deviation,
                     geometry=geometry)


def period_te(systems, pitches, output_torque_Nm: float, *, full_period: int,
              deviation=None, geometry=None, solve_pitches=None, warm: dict | None = None):
    """:func:`system_te` from its systems, one per sampled pitch (built at that pitch, on
    one grid of positions): each position solved from its neighbour's state, the pitches
    filled over the period.

    Parameters
    ----------
    systems : iterable of CycloidSystem
        One per pitch of ``pitches``, in their order, ``CycloidSystem(..., pitch=m)`` (or
        its variants), all on one grid; taken one at a time.
    pitches : sequence of int
        The sampled pitches, distinct, in [0, full_period).
    output_torque_Nm : float
        [N m], nonzero.
    full_period : int
        Pitches after which the TE repeats.
    deviation, geometry
        As :func:`system_te`.
    solve_pitches : sequence of int, optional
        Per system, the pitches on from its own that its positions are solved at
        (:meth:`CycloidSystem.solve`'s ``pitch``: a period longer than the tables' full
        period reuses the systems of the pitch modulo that period, solved whole full
        periods on); default 0 each.
    warm : dict, optional
        System index -> the states (one per position) of a nearby solve of that system
        (another torque's, a variant's a few micrometres away) to start each position from
        instead of its neighbour's; this solve's states are put in it. The same equilibria
        to the solver's tolerance (RTOL) in fewer Newton steps (a fit's evaluations, a
        sweep along torque).

    Returns
    -------
    (LoadedTE, MemberSplit or None, BearingLoads)
        As :func:`system_te`.
    """
    t = float(output_torque_Nm)
    k = int(full_period)
    twist, mesh, shares, bearings = [], [], [], []
    solve_pitches = [0] * len(pitches) if solve_pitches is None else list(solve_pitches)
    for i, (system, on) in enumerate(zip(systems, solve_pitches)):
        drive, per_pitch = system.drive, system.n_positions
        sts, last = [], None
        near = None if warm is None else warm.get(i)
        for p in range(per_pitch):
            last = system.solve(t, p, start=last if near is None else near[p],
                                deviation=deviation, geometry=geometry, pitch=int(on))
            sts.append(last)
        if warm is not None:
            warm[i] = sts
        twist.append([s.twist_rad for s in sts])
        mesh.append(_paths(sts)["mesh"])
        torque = np.array([s.disc_torque_Nm for s in sts])           # (P, M)
        shares.append((torque / torque.sum(axis=1, keepdims=True)).T.ravel())
        names = list(sts[0].bearing_force_N)
        bearings.append(np.array([[np.hypot(*s.bearing_force_N[b]) for s in sts]
                                  for b in names]).ravel())
    fill = lambda v: fourier_fill(pitches, np.array(v), k)  # noqa: E731
    te, mesh_full = fill(twist).ravel(), fill(mesh).ravel()
    m = drive.members
    share = fill(shares).reshape(k, m, per_pitch).transpose(1, 0, 2).reshape(m, -1)
    loaded = loaded_record(drive, t, te, mesh_full, pitches, per_pitch, full_period=k)
    crank = loaded.crank_angle_rad
    load = fill(bearings).reshape(k, len(names), per_pitch).transpose(1, 0, 2)
    loads = BearingLoads(names=tuple(names), load_N=load.reshape(len(names), -1),
                         crank_angle_rad=crank, output_torque_Nm=t)
    if m == 1:
        return loaded, None, loads
    even = bool(np.allclose(share, 1.0 / m, rtol=0, atol=EVEN_SHARE_ATOL))
    return loaded, MemberSplit(share=share, crank_angle_rad=crank, output_torque_Nm=t,
                               offsets=drive.member_offsets(per_pitch),
                               per_pitch=int(per_pitch), even_by_layout=even), loads


@dataclass(frozen=True, kw_only=True)
class BearingLoads:
    """Every bearing's radial load over the full period (N = pitches x per_pitch), from
    the system model at one output torque: what the life and loss models take."""
    names: tuple                     # (B,)
    load_N: np.ndarray               # (B, N) [N]
    crank_angle_rad: np.ndarray      # (N,)
    output_torque_Nm: float

    def summary(self) -> dict:
        """Each bearing's largest and mean load.

        Returns
        -------
        dict
            ``bearing_loads_N``: {name: {"max": N, "mean": N}} at ``bearing_loads_torque_Nm``.
        """
        return {"bearing_loads_torque_Nm": self.output_torque_Nm,
                "bearing_loads_N": {n: {"max": float(np.max(v)), "mean": float(np.mean(v))}
                                    for n, v in zip(self.names, self.load_N)}}


#: The friction torque's fixed point: iterations allowed, and the change of T_e (a
#: fraction of T_f) at which it has settled.
FRICTION_ITERATIONS, FRICTION_RTOL = 50, 1e-3
#: Bisections of the friction's fallback (a bracket of 4 T_f closes to FRICTION_RTOL T_f in
#: 12; the bound only stops a runaway).
BISECTIONS = 60
#: The discs share the torque evenly when no share departs from 1/M by more than this
#: (the round-off of the solve; a layout that splits unevenly departs by percents).
EVEN_SHARE_ATOL = 1e-6
