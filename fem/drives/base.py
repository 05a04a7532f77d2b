"""The :class:`Drive` interface that both reducers implement."""
from __future__ import annotations

import abc
import math
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError, check_range, checked_array
from ..hertz import reduced_modulus
from ..cache import DiskCache, default_dir, kept_solver
from ..load_sharing import LoadSharing, analytic_split
from ..contracts import CycleSolver, DetailedSolution, ReducerModel

if TYPE_CHECKING:
    from ...layout import Layout
    from ...si import MaterialSI
    from ..system.paths import OutputPath

#: Meshing positions per period when a caller gives none: 10 deg of crank per position on a
#: 40-pin drive, enough for the load per pin to converge (docs/fem.md).
DEFAULT_POSITIONS = 36
#: Most positions per period the solvers accept (0.1 % of a period apart).
MAX_POSITIONS = 3600


class Drive(abc.ABC):
    """A meshing stage: the moving member(s) (cycloid discs or the sine planet) against the
    fixed member (pin ring or ring gear), with the train around it.

    Subclasses are frozen dataclasses of SI records, so a drive is hashable and a solver
    built for it is cached per design.
    """

    #: "cycloid" or "sine": the meshing stage, as its case section and the mesh efficiency
    #: are named (labels only; consumers ask :attr:`layout`, never branch on it).
    kind: str = ""
    #: The layout it belongs to (:class:`toothfem.layout.Layout`), what every consumer asks
    #: instead of branching on the drive (a field outside the drive's equality and hash).
    layout: Layout
    #: How the torque reaches the output (:class:`toothfem.fem.system.paths.OutputPath`):
    #: the train's speeds, the members' torque and the system model ask it.
    path: OutputPath
    #: what the moving member and a contact are called in outputs ("disc", "pin", "pins";
    #: "planet", "tooth", "teeth"): labels and summary keys, never a branch.
    member_name: str = ""
    contact_name: str = ""
    contacts_name: str = ""
    #: the seed's rule of the analytic split (toothfem.fem.load_sharing.SPLIT_WEIGHTS).
    analytic_weight: str = ""
    #: options of :meth:`fe_model` with their choices (e.g. the cycloid's pin structure).
    fe_options: dict = {}
    #: solver options of a cycle solver that serves both torque signs (the cycloid refines
    #: both flanks of each lobe; the sine pair's hat grids cover both flanks already).
    both_sides_options: dict = {}
    #: solver options of a cycle solver whose every solve has both flanks as candidates at
    #: once (an idle flank that a built stage's deviations close takes load too).
    both_flanks_options: dict = {}

    # -- what every drive provides ------------------------------------------------------
    @property
    @abc.abstractmethod
    def period_rad(self) -> float:
        """Crank angle of one meshing period [rad]."""

    @property
    @abc.abstractmethod
    def members(self) -> int:
        """Moving members that share the output torque (discs; 1 planet)."""

    @property
    @abc.abstractmethod
    def load_factor(self) -> float:
        """Peak member torque over the even share (the seed's disc load factor; 1)."""

    @property
    @abc.abstractmethod
    def face_width_m(self) -> float:
        """Face width of the contacts [m]."""

    #: Both members' material (each implementation's field; ``material`` reads it).
    material_si: MaterialSI

    @property
    def material(self) -> MaterialSI:
        return self.material_si

    @abc.abstractmethod
    def speeds(self) -> dict:
        """Speeds of the train's parts for a unit input speed.

        Returns
        -------
        dict of str to float
            ``input``, ``crank``, ``member`` (disc or planet), ``output`` (carrier or
            planet's output) [-, per unit input speed], signed as in
            :mod:`toothfem.geometry.train`.
        """

    @abc.abstractmethod
    def meshing(self, positions_rad, crank_speed_rad_s: float = 1.0):
        """Rigid-body meshing at the crank angles, the fixed member at rest.

        Parameters
        ----------
        positions_rad : array_like, shape (P,)
            Crank angles [rad].
        crank_speed_rad_s : float
            Crank speed [rad/s] (scales the sliding speeds the friction loss needs).

        Returns
        -------
        toothfem.geometry.kinematics.MeshingState
        """

    @abc.abstractmethod
    def fe_model(self, **overrides):
        """The FE model of the pair.

        Parameters
        ----------
        **overrides
            The model's own options (:attr:`fe_options` names the choices).

        Returns
        -------
        object
            The drive's FE model (``CycloidFEModel`` or ``SineFEModel``).
        """

    @abc.abstractmethod
    def _new_cycle_solver(self, model, positions_rad, cache, **options) -> CycleSolver:
        """A cycle-mode solver of ``model`` at the positions (``options``: the solver's)."""

    @property
    @abc.abstractmethod
    def analytic_in_mesh_gap_m(self) -> float:
        """Unloaded gap within which a contact shares the load in the analytic split."""

    @abc.abstractmethod
    def solve_detailed(self, model, position_rad: float,
                       member_torque_Nm: float) -> DetailedSolution:
        """Two-body FE contact at one position (verification, stress fields).

        Parameters
        ----------
        model : object
            From :meth:`fe_model`.
        position_rad : float
            Crank angle [rad].
        member_torque_Nm : float
            Torque on the moving member [N m], nonzero.

        Returns
        -------
        toothfem.fem.contracts.DetailedSolution
            The mode's result: its ``load_sharing`` (one position), ``member_body`` and
            ``member_displacement``.
        """

    @abc.abstractmethod
    def profiles(self, points_per_tooth: int):
        """The members' outlines for pictures and DXF.

        Parameters
        ----------
        points_per_tooth : int
            Samples per lobe or tooth.

        Returns
        -------
        profiles : dict of str to numpy.ndarray
            name -> (2, N) closed outline in its member's frame [m].
        checks : dict
            The checks of the outlines as a report shows them.
        """

    @abc.abstractmethod
    def member_frame_point(self, model, position_rad: float, point):
        """Housing-frame points in the moving member's own frame.

        Parameters
        ----------
        model : object
            The FE model whose geometry places the member.
        position_rad : float
            The crank's angle [rad].
        point : array_like, shape (2,) or (2, N)
            Housing frame [m].

        Returns
        -------
        numpy.ndarray
            Same shape as ``point`` [m], member frame.
        """

    @abc.abstractmethod
    def fixed_outlines(self, points_per_tooth: int = 48) -> list:
        """Outlines of the fixed member's contact surfaces in the housing frame.

        For pictures of the moving member among them.

        Parameters
        ----------
        points_per_tooth : int
            Samples per pin or ring tooth.

        Returns
        -------
        list of numpy.ndarray
            Closed (2, N) polylines [m] (each pin's circle; the ring's tooth profile).
        """

    def te_orders(self) -> dict:
        """Orders per output revolution at which a transmission-error ripple is expected
        (the naming of a measured TE spectrum, toothfem.efficiency.loop.te.spectrum).

        The generic orders, from :meth:`speeds` and :attr:`period_rad` only: the output
        revolution (1), the input revolution (|i|), the crank revolution (each fixed tooth
        meets the loaded zone once per crank turn against the fixed member: the fixed
        teeth's errors), the crank against the moving member (each moving tooth meets the
        loaded zone once per such turn: the moving teeth's errors), and the mesh (one
        meshing period per :attr:`period_rad` of crank). A drive names them in its own
        terms.

        Returns
        -------
        dict of str to float
            name -> order [per output revolution]; names of equal orders are joined by
            " = " into one entry.
        """
        w = self.speeds()
        out = abs(w["output"])
        crank = abs(w["crank"]) / out
        return _merged_orders([
            ("output revolution", 1.0), ("input revolution", abs(w["input"]) / out),
            ("crank revolution", crank),
            (f"crank against the {self.member_name}", abs(w["crank"] - w["member"]) / out),
            ("mesh", 2 * np.pi / self.period_rad * crank)])

    @abc.abstractmethod
    def supports(self, declared):
        """The supports of the system model: the eccentric (crank) bearings, the crankshafts
        or the input shaft, the carrier.

        Parameters
        ----------
        declared : toothfem.si.SupportsSI
            The case's supports; the drive's own assumptions fill what it leaves out.

        Returns
        -------
        toothfem.fem.datasheet.supports.Supports
        """

    def coupled_compliance(self, supports) -> dict:
        """Twist of each member per torque on another through parts the members share: what
        decides whether a layout splits the torque evenly by its symmetry
        (:func:`toothfem.fem.datasheet.transmission.even_by_layout`).

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports

        Returns
        -------
        dict of str to numpy.ndarray
            path -> (M, M) twist of member j [rad] per N m on member i (a drive without
            such parts: {}).
        """
        return {}

    # -- the reducer as built (toothfem tolerance) ------------------------------------------
    @abc.abstractmethod
    def sample_deviation(self, tolerances, rng):
        """One built stage's deviations.

        Parameters
        ----------
        tolerances : toothfem.si.TolerancesSI
            The zones drawn from and their ``distribution``.
        rng : numpy.random.Generator

        Returns
        -------
        object
            The drive's record of :mod:`toothfem.fem.deviations`, as its cycle solver
            takes it.
        """

    @property
    @abc.abstractmethod
    def pairing_period_pitches(self) -> int:
        """Meshing periods after which every fixed tooth (pin) has met every moving tooth
        (lobe) in every place: a built stage's errors repeat only then."""

    @property
    def full_period_pitches(self) -> int:
        """Meshing periods after which the whole model repeats (disc holes included)."""
        return 1

    @abc.abstractmethod
    def nominal_deviation(self):
        """The drive's record of :mod:`toothfem.fem.deviations` with every deviation zero
        (the stage as drawn), to put chosen deviations into (``dataclasses.replace``).

        Returns
        -------
        object
        """

    def crank_period_pitches(self) -> int:
        """Meshing periods per turn of the crank against the output (carrier): a crank's
        own errors (its eccentricity, its bearing) repeat after these.

        Returns
        -------
        int
            2 pi / period_rad x |w_crank| / |w_crank - w_output| (a 2K-V drive: Za pin
            pitches).

        Raises
        ------
        CaseError
            If it is not a whole number of periods.
        """
        w = self.speeds()
        n = 2 * math.pi / self.period_rad * abs(w["crank"]) / abs(w["crank"] - w["output"])
        if abs(n - round(n)) > 1e-6:
            raise CaseError(f"the crank turns against the output in {n:.6g} meshing "
                            "periods, not a whole number")
        return int(round(n))

    def deviation_period_pitches(self, deviation) -> int:
        """Meshing periods after which a built stage's model repeats: the full period
        (:attr:`full_period_pitches`) without deviation or with deviations that are alike
        at every tooth (an eccentricity error); the pairing period with any other; with
        crank eccentricity errors, the path's period of them (``path.with_crank_period``).

        Parameters
        ----------
        deviation : object or None
            The drive's record of :mod:`toothfem.fem.deviations`.

        Returns
        -------
        int
        """
        k = self.full_period_pitches
        if deviation is None:
            return k
        k = self.path.with_crank_period(k, self, deviation)
        uniform = {"eccentricity", "crank_eccentricity_m", "crank_phase_rad"}
        for name, value in vars(deviation).items():
            if name not in uniform and np.any(np.asarray(value, float)):
                return math.lcm(k, self.pairing_period_pitches)
        return k

    def member_offsets(self, per_pitch: int, turns=None) -> tuple:
        """Where each member's configuration stands on the full-period grid.

        Parameters
        ----------
        per_pitch : int
            Positions per meshing period; the grid spans :attr:`full_period_pitches`
            periods.
        turns : sequence of float, optional
            Each member's phase in turns (default the drive's own layout).

        Returns
        -------
        tuple of int
            Grid index of each member relative to the first member's (one member: (0,)).
        """
        return (0,)

    def member_axial_positions_m(self, supports) -> np.ndarray:
        """The members side by side, centred between the crankshaft's (input shaft's)
        support bearings [m] (M,).

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports
            Its crankshaft span.

        Returns
        -------
        numpy.ndarray
        """
        w, n = self.face_width_m, self.members
        return 0.5 * supports.crankshaft_span_m + (np.arange(n) - 0.5 * (n - 1)) * w

    def system_mesh(self, pin_spring_m_per_N=None):
        """The member's contact with the fixed teeth as the system model takes it
        (:mod:`toothfem.fem.system.mesh`).

        Parameters
        ----------
        pin_spring_m_per_N : float, optional
            Equal contact springs instead of the FE, where the drive has that limit.

        Returns
        -------
        object
        """
        raise CaseError(f"drive '{self.kind}' has no system model")

    @abc.abstractmethod
    def system_model(self, supports, n_positions: int, **options) -> ReducerModel:
        """The system model of the whole reducer around the contact (docs/stiffness.md):
        every analysis of the reducer (datasheet, TE, split, bearing loads, tolerances)
        asks it.

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports
        n_positions : int
            Positions per meshing period.
        **options
            Go to the model (``cache``, ``pitch``, limits).

        Returns
        -------
        toothfem.fem.contracts.ReducerModel

        Raises
        ------
        CaseError
            Where the case lacks a part the model needs (the sine pair's output pins).
        """

    # -- shared by every drive ------------------------------------------------------------
    def positions(self, n_positions: int = DEFAULT_POSITIONS) -> np.ndarray:
        """Crank angles evenly over one meshing period (every analysis's position grid).

        Parameters
        ----------
        n_positions : int
            How many, 1 to MAX_POSITIONS.

        Returns
        -------
        numpy.ndarray, shape (n_positions,)
            [rad], from 0, the period's end excluded.

        Raises
        ------
        CaseError
            For a count that is not an integer or outside the range.
        """
        n = n_positions
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) and int(n) != n:
            raise CaseError(f"n_positions = {n!r} must be an integer")
        check_range("n_positions", n, 1, MAX_POSITIONS, error=CaseError)
        return np.arange(int(n)) * (self.period_rad / int(n))

    def member_torque(self, output_torque_Nm, *, peak: bool = True):
        """Torque on one moving member for a reducer output torque: the one torque rule.

        Parameters
        ----------
        output_torque_Nm : float or array_like
            Output torque [N m], > 0.
        peak : bool
            True (contact, strength): ``load_factor`` times the even share (the
            pin-housing paper's Eq. 6 with its disc load factor); False (losses): the
            even share of the members' torque (:meth:`members_torque`) over the members.

        Returns
        -------
        float or numpy.ndarray
            Member torque [N m], shaped as the input.

        Raises
        ------
        CaseError
            For a torque that is not finite and positive.
        """
        t = checked_array("output_torque_Nm", output_torque_Nm, 0, lo_open=True,
                          error=CaseError)
        share = self.members_torque(t) / self.members
        out = self.load_factor * share if peak else share
        return float(out) if out.ndim == 0 else out

    def members_torque(self, output_torque_Nm):
        """The moving members' torque together for an output torque, from the power flow
        (the fixed teeth's moment on the members): the output torque itself where the
        members are the output (K-H-V, the sine planet).

        Parameters
        ----------
        output_torque_Nm : float or numpy.ndarray
            [N m].

        Returns
        -------
        float or numpy.ndarray
            [N m].
        """
        return output_torque_Nm

    @cached_property
    def e_star_Pa(self) -> float:
        """Hertz's contact modulus E* of the pair (one material)."""
        m = self.material
        return float(reduced_modulus(m.youngs_modulus_Pa, m.poisson_ratio,
                                     m.youngs_modulus_Pa, m.poisson_ratio))

    def analytic_split(self, state, member_torque_Nm: float) -> LoadSharing:
        """The seeds' analytic load split (:func:`toothfem.fem.load_sharing.analytic_split`).

        Parameters
        ----------
        state : toothfem.geometry.kinematics.MeshingState
        member_torque_Nm : float
            Torque on the moving member [N m].

        Returns
        -------
        LoadSharing
            Method "analytic", the drive's weight rule and in-mesh gap.
        """
        return analytic_split(state, member_torque_Nm, self.face_width_m, self.e_star_Pa,
                              self.analytic_in_mesh_gap_m, weight=self.analytic_weight)

    def cycle_solver(self, n_positions: int = DEFAULT_POSITIONS, *, cache=True,
                     solver_options: dict | None = None, pitch: int = 0, offset: int = 0,
                     **overrides) -> CycleSolver:
        """The FE cycle-mode solver over :meth:`positions`, built once per design and
        options in this process.

        Parameters
        ----------
        n_positions : int
            Positions per meshing period.
        cache : bool or DiskCache or None
            True, the user's disk cache (:func:`toothfem.fem.cache.default_dir`); a
            :class:`~toothfem.fem.cache.DiskCache`; or None/False for none.
        solver_options : dict, optional
            Go to the solver (e.g. the cycloid's ``equal_springs``).
        pitch : int
            m puts the positions m meshing periods on (the same contacts m lobes on
            against the disc holes).
        offset : int
            Puts the positions that many grid steps (period / n_positions) further on (a
            member whose configuration falls between the pitches: the system model).
        **overrides
            Go to :meth:`fe_model` (e.g. ``pin_structure``).

        Returns
        -------
        object
            The drive's ``CycleSolver`` (shared with earlier callers of the same key).

        Raises
        ------
        CaseError
            For a position count outside the range (:meth:`positions`).
        """
        if cache is True:
            cache = DiskCache(default_dir())
        elif cache is False:
            cache = None
        options = dict(solver_options or {})
        key = (self, int(n_positions), tuple(sorted(overrides.items())),
               tuple(sorted(options.items())), None if cache is None else str(cache.directory),
               int(pitch), int(offset))
        phis = self.positions(n_positions) + (int(pitch) + int(offset) / int(n_positions)) \
            * self.period_rad
        return kept_solver(key, lambda: self._new_cycle_solver(
            self.fe_model(**overrides), phis, cache, **options))


def _merged_orders(pairs) -> dict:
    """{name: order} of (name, order) pairs, rounded to 1e-9; equal orders' names joined."""
    names: list[str] = []
    orders: list[float] = []
    for name, q in pairs:
        q = round(float(q), 9)
        if q in orders:
            names[orders.index(q)] += f" = {name}"
        else:
            names.append(name)
            orders.append(q)
    return dict(zip(names, orders))
