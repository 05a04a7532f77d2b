"""The :class:`Drive` interface that both reducers implement."""
from __future__ import annotations

import abc
from functools import cached_property

import numpy as np

from ...errors import CaseError, check_range
from ..hertz import reduced_modulus
from ..cache import DiskCache, default_dir
from ..load_sharing import LoadSharing, analytic_split

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

    #: "cycloid" or "sine": the key of per-drive tables elsewhere (loss models, labels).
    kind: str = ""
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

    @property
    def material(self):
        """:class:`toothfem.si.MaterialSI` of both members (each drive's ``material_si``)."""
        return self.material_si

    @abc.abstractmethod
    def speeds(self) -> dict:
        """Speeds for a unit input speed: ``input``, ``crank``, ``member`` (disc or planet),
        ``output`` (carrier or planet's output), signed as in :mod:`toothfem.geometry.train`."""

    @abc.abstractmethod
    def meshing(self, positions_rad, crank_speed_rad_s: float = 1.0):
        """:class:`~toothfem.geometry.kinematics.MeshingState` at the crank angles, the fixed
        member at rest (the sliding speeds the friction loss needs)."""

    @abc.abstractmethod
    def fe_model(self, **overrides):
        """The FE model of the pair (``overrides`` are the model's own options)."""

    @abc.abstractmethod
    def _new_cycle_solver(self, model, positions_rad, cache, **options):
        """A cycle-mode solver of ``model`` at the positions (``options``: the solver's)."""

    @property
    @abc.abstractmethod
    def analytic_in_mesh_gap_m(self) -> float:
        """Unloaded gap within which a contact shares the load in the analytic split."""

    @abc.abstractmethod
    def solve_detailed(self, model, position_rad: float, member_torque_Nm: float):
        """Two-body FE contact at one position (verification, stress fields)."""

    @abc.abstractmethod
    def profiles(self, points_per_tooth: int):
        """(profiles, checks): {name: (2, N) closed outline in its member's frame [m]} and
        the checks of the outlines as a report shows them."""

    @abc.abstractmethod
    def member_frame_point(self, model, position_rad: float, point):
        """``point`` (2,) or points (2, N) of the housing frame in the moving member's own
        frame at one crank angle [m]."""

    @abc.abstractmethod
    def fixed_outlines(self, points_per_tooth: int = 48) -> list:
        """Outlines of the fixed member's contact surfaces in the housing frame: a list of
        closed (2, N) polylines [m] (each pin's circle; the ring's tooth profile), for
        pictures of the moving member among them."""

    @property
    def two_stage(self) -> bool:
        """A 2K-V (RV-type) train: a spur first stage drives the cranks (default: no)."""
        return False

    @abc.abstractmethod
    def supports(self, declared):
        """The supports in series with the mesh (:class:`toothfem.fem.datasheet.supports.
        Supports`) from the case's :class:`toothfem.si.SupportsSI`, the drive's own
        assumptions where it gives none."""

    @abc.abstractmethod
    def member_support_twists(self, supports, member_torque, resultant, positions_rad):
        """Output twist [rad] of one member's own supports at each position: {path: (P,)}.

        ``member_torque`` (P,) N m, signed; ``resultant`` (P, 2) the contact resultant on
        the member [N, housing frame]; ``positions_rad`` (P,) crank angles."""

    def coupled_compliance(self, supports) -> dict:
        """{path: (M, M)} twist of member j [rad] per N m on member i through parts the
        members share (a drive without such parts: {})."""
        return {}

    def output_compliance(self, supports) -> dict:
        """{path: rad per N m of output torque} of parts every member's path runs through
        (the carrier is the datasheet's own)."""
        return {}

    # -- the reducer as built (toothfem tolerance) ------------------------------------------
    @abc.abstractmethod
    def sample_deviation(self, tolerances, rng):
        """One built stage's deviations (:mod:`toothfem.fem.deviations`) drawn from
        ``tolerances`` (:class:`toothfem.si.TolerancesSI`) with the generator ``rng``."""

    @property
    @abc.abstractmethod
    def pairing_period_pitches(self) -> int:
        """Meshing periods after which every fixed tooth (pin) has met every moving tooth
        (lobe) in every place: a built stage's errors repeat only then."""

    @property
    def full_period_pitches(self) -> int:
        """Meshing periods after which the whole model repeats (disc holes included)."""
        return 1

    def member_offsets(self, per_pitch: int) -> tuple:
        """Index of each member's configuration on the grid of
        ``per_pitch`` positions per meshing period over :attr:`full_period_pitches`
        periods, relative to the first member's (one member: (0,))."""
        return (0,)

    # -- shared by every drive ------------------------------------------------------------
    def positions(self, n_positions: int = DEFAULT_POSITIONS) -> np.ndarray:
        """``n_positions`` crank angles evenly over one meshing period, the period's end
        excluded (the one position grid of every analysis)."""
        n = n_positions
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) and int(n) != n:
            raise CaseError(f"n_positions = {n!r} must be an integer")
        check_range("n_positions", n, 1, MAX_POSITIONS, error=CaseError)
        return np.arange(int(n)) * (self.period_rad / int(n))

    def member_torque(self, output_torque_Nm, *, peak: bool = True):
        """Torque on one moving member [N m] for a reducer output torque [N m]: the one
        torque rule.

        ``peak`` True (contact, strength): ``load_factor * T / members`` (the pin-housing
        paper's Eq. 6 with its disc load factor); False (losses): the even share
        ``T / members``, whose sum over the members is the output torque.
        """
        t = np.asarray(output_torque_Nm, float)
        bad = ~np.isfinite(t) | (t <= 0)
        if np.any(bad):
            check_range("output_torque_Nm", float(t[bad].flat[0]), 0, None, lo_open=True,
                        error=CaseError)
        share = t / self.members
        out = self.load_factor * share if peak else share
        return float(out) if out.ndim == 0 else out

    @cached_property
    def e_star_Pa(self) -> float:
        """Hertz's contact modulus E* of the pair (one material)."""
        m = self.material
        return float(reduced_modulus(m.youngs_modulus_Pa, m.poisson_ratio,
                                     m.youngs_modulus_Pa, m.poisson_ratio))

    def analytic_split(self, state, member_torque_Nm: float) -> LoadSharing:
        """The seeds' analytic load split on ``state`` at a member torque (see
        :func:`toothfem.fem.load_sharing.analytic_split`)."""
        return analytic_split(state, member_torque_Nm, self.face_width_m, self.e_star_Pa,
                              self.analytic_in_mesh_gap_m, weight=self.analytic_weight)

    def cycle_solver(self, n_positions: int = DEFAULT_POSITIONS, *, cache=True,
                     solver_options: dict | None = None, pitch: int = 0, **overrides):
        """The FE cycle-mode solver over :meth:`positions` (``n_positions``), built once per
        design and options in this process; ``pitch`` m puts the positions m meshing
        periods on (the same contacts m lobes on against the disc holes).

        ``cache``: True, the user's disk cache (:func:`toothfem.fem.cache.default_dir`);
        a :class:`~toothfem.fem.cache.DiskCache`; or None/False for none.
        ``solver_options`` go to the solver (e.g. the cycloid's ``equal_springs``);
        ``overrides`` go to :meth:`fe_model` (e.g. ``pin_structure``).
        """
        if cache is True:
            cache = DiskCache(default_dir())
        elif cache is False:
            cache = None
        options = dict(solver_options or {})
        key = (self, int(n_positions), tuple(sorted(overrides.items())),
               tuple(sorted(options.items())), None if cache is None else str(cache.directory),
               int(pitch))
        solver = _SOLVERS.get(key)
        if solver is None:
            phis = self.positions(n_positions) + int(pitch) * self.period_rad
            solver = self._new_cycle_solver(self.fe_model(**overrides), phis, cache,
                                            **options)
            if len(_SOLVERS) >= SOLVERS_KEPT:
                _SOLVERS.pop(next(iter(_SOLVERS)))
            _SOLVERS[key] = solver
        return solver


#: Cycle solvers kept in memory per process (each holds its influence tables, tens of MB):
#: enough for the designs of one command or one sweep task group.
SOLVERS_KEPT = 4
_SOLVERS: dict = {}

