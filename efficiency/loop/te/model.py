"""The model side of TE and hysteresis recordings (issue 24, items 3 and 5): what the
system model of the whole reducer (:mod:`toothfem.fem.system`) records on a rig, with
effects a fit can vary (docs/te_model.md).

**Effects** (:class:`Effects`, SI, every default the case as drawn; the records are
:mod:`.model_records`'):

- ``crank_bearing_play_m``: the crank (eccentric) bearings' diametral play;
- ``crank_eccentricity_m``, ``crank_phase_rad``: each crank's eccentricity error and its
  direction from the eccentric's, (cranks,) or (cranks, discs) for each eccentric alone
  (:class:`toothfem.fem.deviations.CycloidDeviation`);
- ``stiffness_scale``: a factor on the stiffness of parts of the model, by the names of
  :data:`toothfem.fem.drives.assembly.SCALABLE` (the element groups of ``CycloidSystem``:
  ``crank bearings``, ``support bearings``, ``crankshaft bending``, ``crankshaft
  torsion``, ``spur mesh``; the contacts ``mesh`` and ``output pins``; ``carrier``);
- ``equidistant_modification_m``, ``move_distance_modification_m``: the disc's profile
  clearance (the case's ``[cycloid]`` keys, in m) on the nominal disc's FE tables, as the
  design search takes another modification (a few micrometres from the tables' disc);
- ``pin_radius_m`` (one value: every pin; or one per pin) and ``pin_offset_m`` (2, Zb):
  the pins' radius change and centre offsets (``CycloidDeviation.pin_radius`` and
  ``pin_offset``);
- ``pin_ring_m``: the pins' centres off their places in orders round the ring,
  ``{"radial_2": a, "tangential_1": b}`` [m] (the drive's ``pin_ring_offsets``: order 1
  tangential the ring's cumulative pitch error, order 2 radial its ovality), added to
  ``pin_offset_m``;
- ``friction_scale``: a factor on every coefficient of the path friction
  (:func:`toothfem.efficiency.no_load.path_friction`) and on the output's seal torque; 0 the
  elastic curve.

**What a rig records.**

- The hysteresis loop (:meth:`RecordingModel.hysteresis` -> :class:`ModelLoop`): the
  torque staircase 0 -> +T -> -T -> +T, input held, with the path friction's play
  operator, by the datasheet's machinery (:class:`toothfem.fem.system.datasheet.
  SystemTwist`, :func:`toothfem.fem.datasheet.sheet.datasheet`): the twist of each step
  averaged over the positions of one pin pitch (the input held at ``loop_pitch``), and the
  catalogue figures by the datasheet's definitions.
- The TE over the full period (:meth:`RecordingModel.te` -> :class:`ModelTe`), the
  datasheet's TE (:func:`toothfem.fem.system.datasheet.period_te`, what ``system_te``
  runs): at each output torque T the forward run at +T (the output driven against a brake
  of T) and the backward run at -T (the brake reversed with the motion), elastic states
  under T plus the running losses (:meth:`RecordingModel.running_loss_torque_Nm`: every
  loss of the efficiency model at the case's input speed as a torque on the output, scaled
  by ``friction_scale``), so that the width at zero torque holds the friction beside the
  play (the path friction of the micro-slips belongs to the staircase). The period is the effects' own
  (:meth:`toothfem.fem.drives.base.Drive.deviation_period_pitches`: a 2K-V crank's errors
  repeat per turn of the crank against the carrier, the pins' per pin, the lobes' per
  lobe), sampled at ``samples`` pitches (each solved at every position of its pitch) and
  filled by a Fourier series in the pitch (exact where ``samples`` covers the period).
  Pin errors stretch the period to a whole output revolution: a pin ring's orders are
  sampled at :func:`ring_samples` pitches by default (their ripple reaches the second
  multiple of the pin passing and its side bands), single pins over the whole period
  (a pin's load rises and falls within a pitch: no series short of it holds it,
  ``benchmarks/pin_offset_response.py``).
- The orders per output revolution that name a spectrum's peaks: :func:`te_orders`, the
  drive's :meth:`~toothfem.fem.drives.base.Drive.te_orders`.

**Cost** (this 2-core machine, FE tables from the disk cache, 4 positions per pitch, the
default 7 sampled pitches, a kept :class:`RecordingModel`; docs/te_model.md has the
table): rv40e 0.21 s per loop with friction, 0.07 s per TE torque (both directions);
cycloid_khv 0.31 s and 0.08 s. A new sampled pitch builds its FE tables once (1.5-2 s
each here, then in the disk cache); pin errors stretch the period to a whole output
revolution, so their TE needs many sampled pitches (2 q + 1 for an order q; 79 on rv40e
for order 39: 1.4 s).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...no_load import path_friction
from ....errors import CaseError, ToothfemError
from ....fem.datasheet.sheet import stuck_after_reversals, datasheet, loop_branches
from ....fem.datasheet.transmission import sampled_pitches
from ....fem.datasheet.twist import ARCMIN, ZERO_TORQUE_NM
from ....fem.drives import drive_for
from ....fem.contracts import ReducerModel
from ....fem.linsolve import one_blas_thread
from ....fem.system.datasheet import SystemTwist, period_te
from ...evaluation import rated_output_torque
from .workers import DirectionWorkers
from .model_records import (Effects, ModelLoop, ModelRecordings, ModelTe, ring_order,
                            ring_samples)

#: Positions per pin pitch of the loop's and the TE's systems: the loop's twist is their
#: mean and the TE's pin-mesh ripple is sampled by them; 4 keeps a model call near 0.2 s
#: (the loop's figures move by 1e-4 relative from 4 to 36 positions on rv40e; the mesh
#: ripple's amplitude needs about 12).
DEFAULT_POSITIONS = 4
#: Sampled pitches over the TE's period: the Fourier fill resolves up to order 3 of the
#: period, so a 2K-V crank's error (one turn of the crank against the carrier per period)
#: shows its first three harmonics.
DEFAULT_TE_SAMPLES = 7
#: The running losses at zero output torque are the efficiency model's at this fraction of
#: the rated torque (it refuses a zero torque; at 0.1 % the load-dependent losses are 0.1 %
#: of the rated point's, the no-load losses whole).
NO_LOAD_FRACTION = 1e-3
#: Torque steps from 0 to +T of the datasheet's loop (its figures: rigidity from 50 to
#: 100 % needs 25 % steps at least).
DEFAULT_STEPS = 4
#: The staircase of :class:`ModelLoop`, fractions of the largest torque: fine steps near
#: zero (lost motion at 3 %, a rig's backlash fit up to 10 %), then 25-50-75-100 % (the
#: rigidity's 50 and 100 %).
STAIRCASE_FRACTIONS = (0.0, 0.03, 0.06, 0.1, 0.25, 0.5, 0.75, 1.0)
#: The TE's states under one set of effects start the next call's solves where every value
#: is within this fraction of the other's (:func:`_near`).
NEAR_REL = 0.1
#: Processes a model may solve its TE in: one, or one per direction of rotation.
WORKERS = (1, 2)


class RecordingModel:
    """The system model of a case set up once for many calls (a fit): its drive, supports,
    rating, path friction and one system per pin pitch used, whose FE tables stay in
    memory; each call puts its effects on them (:meth:`CycloidSystem.variant`).

    Parameters
    ----------
    case : toothfem.case.Case or path
    positions : int
        Positions per pin pitch (DEFAULT_POSITIONS).
    te_samples : int
        Sampled pitches over the TE's period (DEFAULT_TE_SAMPLES).
    cache : bool or toothfem.fem.cache.DiskCache
        The FE tables' disk cache (True: the user's).
    workers : {1, 2}
        2: the TE's two directions solved side by side in two processes of their own
        (:class:`~.workers.DirectionWorkers`, started at the first TE; the same numbers;
        :meth:`close` or ``with`` stops them); 1: in this process.
    warm_starts : bool
        Each TE solve from the last call's state where the effects are near, else from
        the torque before (:meth:`runs`: what a fit's many calls want; the same equilibria
        to the solver's tolerance); False: every call from cold starts, as the datasheet's
        TE solves (its numbers bit for bit).
    **system_options
        Go to every :class:`toothfem.fem.drives.assembly.CycloidSystem` (e.g.
        ``pin_spring_m_per_N``: equal contact springs instead of the FE, ``rigid``).

    Raises
    ------
    CaseError
        For a drive without a system model, or no rating or operating torque.
    ToothfemError
        For ``workers`` not in WORKERS.
    """

    def __init__(self, case, *, positions: int = DEFAULT_POSITIONS,
                 te_samples: int = DEFAULT_TE_SAMPLES, cache=True, workers: int = 1,
                 warm_starts: bool = False, **system_options):
        if workers not in WORKERS:
            raise ToothfemError(f"workers = {workers!r} is outside the valid range "
                             f"{list(WORKERS)}")
        self.case = _a_case(case)
        self.si = self.case.to_si()
        self.drive = drive_for(self.case)
        self.supports = self.drive.supports(self.si.supports)
        self.rated_torque_Nm, self.rated_assumed = rated_output_torque(self.si)
        self.friction = path_friction(self.si, self.drive)
        self.positions = int(positions)
        self.te_samples = int(te_samples)
        self.cache = cache
        self.system_options = dict(system_options)
        self._systems: dict[int, ReducerModel] = {}
        self._losses: dict[float, float] = {}
        # (direction, torque, pitches, solved on) -> the last TE's states there, by system
        self._warm: dict[tuple, dict] = {}
        self._warm_effects: dict[int, Effects] = {}     # direction -> the last call's
        self.warm_starts = bool(warm_starts)
        if self.system(0) is None:
            raise CaseError(f"a {self.drive.kind} drive without [output_mechanism] has no "
                            "system model: no modelled recordings")
        self._workers = None if workers == 1 else DirectionWorkers(
            type(self), self.case, dict(positions=self.positions, te_samples=self.te_samples,
                                        cache=cache, warm_starts=self.warm_starts,
                                        **self.system_options))

    def close(self) -> None:
        """Stop the TE's processes (``workers=2``); the model then solves in this one."""
        if self._workers is not None:
            self._workers.close()
            self._workers = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def system(self, pitch: int = 0, effects: Effects | None = None):
        """The system over one pin pitch, ``pitch`` pitches on (kept), with the effects'
        options.

        Parameters
        ----------
        pitch : int
            In [0, full period).
        effects : Effects, optional

        Returns
        -------
        toothfem.fem.contracts.ReducerModel
        """
        m = int(pitch)
        if m not in self._systems:
            self._systems[m] = self.drive.system_model(self.supports, self.positions,
                                                       cache=self.cache, pitch=m,
                                                       **self.system_options)
        base = self._systems[m]
        if effects is None:
            return base
        return base.variant(**effects.system_options())

    def path_friction(self, effects: Effects):
        """The case's path friction scaled by ``effects.friction_scale`` (None at 0).

        Parameters
        ----------
        effects : Effects

        Returns
        -------
        toothfem.fem.drives.assembly.PathFriction or None
        """
        s = float(effects.friction_scale)
        if s == 0:
            return None
        f = self.friction
        return dataclasses.replace(f, pin_disc=s * f.pin_disc, pin_groove=s * f.pin_groove,
                                   bearing=s * f.bearing, output_pin=s * f.output_pin,
                                   output_torque_Nm=s * f.output_torque_Nm)

    def running_loss_torque_Nm(self, torque_Nm: float, effects: Effects) -> float:
        """The running reducer's losses at the output torque as a torque on the output
        [N m]: the efficiency model's losses (every mesh, bearing, seal and churning loss,
        :func:`toothfem.efficiency.evaluation.evaluate`, analytic loads, the lubricant's
        reference temperature) at the case's input speed, over the output speed, times
        ``effects.friction_scale``. ASSUMPTION: the whole loss loads the elastic path (the
        losses on the output side of the compliant parts load it less), so the width it
        adds is an upper bound.

        Parameters
        ----------
        torque_Nm : float
            >= 0.
        effects : Effects

        Returns
        -------
        float
        """
        scale = float(effects.friction_scale)
        if scale == 0:
            return 0.0
        t = max(float(torque_Nm), NO_LOAD_FRACTION * self.rated_torque_Nm)
        if t not in self._losses:
            from ...evaluation import evaluate

            e = evaluate(self.case, self.case.operating.input_speed_rpm, t)
            self._losses[t] = float(sum(np.sum(v) for v in e.losses_W.values())
                                    * t / np.sum(e.output_power_W))
        return scale * self._losses[t]

    def te_orders(self) -> dict:
        """The drive's named orders per output revolution (:meth:`Drive.te_orders`).

        Returns
        -------
        dict of str to float
        """
        return self.drive.te_orders()

    def hysteresis(self, effects: Effects | None = None, *, steps: int = DEFAULT_STEPS,
                   fractions=STAIRCASE_FRACTIONS, torque_max_Nm: float | None = None,
                   loop_pitch: int = 0) -> ModelLoop:
        """The hysteresis staircase and the catalogue figures under the effects.

        Parameters
        ----------
        effects : Effects, optional
            Default: the case as drawn.
        steps : int
            Torque steps of the datasheet's loop (its figures).
        fractions : sequence of float
            The staircase's steps from 0 to 1, rising, fractions of the largest torque.
        torque_max_Nm : float, optional
            The largest torque; default the rated torque.
        loop_pitch : int
            The pin pitch the input is held at (its positions averaged): with a 2K-V
            crank's errors the loop depends on where the crank stands.

        Returns
        -------
        ModelLoop

        Raises
        ------
        CaseError
            For a largest torque that does not close the clearance (``datasheet``), or
            fractions that do not rise from 0 to 1.
        """
        effects = Effects() if effects is None else effects
        fr = np.asarray(fractions, float)
        if fr.size < 2 or fr[0] != 0 or fr[-1] != 1 or np.any(np.diff(fr) <= 0):
            raise CaseError(f"fractions = {list(fr)}: rising from 0 to 1")
        # the pitch's own tables (modulo the full period), solved whole periods on
        held = int(loop_pitch)
        own = held % self.drive.full_period_pitches
        system = self.system(own, effects)
        twist = SystemTwist(system, friction=self.path_friction(effects),
                            deviation=effects.deviation(self.drive),
                            geometry=effects.geometry(self.drive),
                            pitches=None if held == own else
                            np.full(self.positions, held - own))
        rated = self.rated_torque_Nm
        sheet = datasheet(twist, rated, rated_assumed=self.rated_assumed,
                          torque_max_Nm=torque_max_Nm, steps=steps)
        t_max = rated if torque_max_Nm is None else float(torque_max_Nm)
        up = list(fr)
        down = list(fr[-2::-1]) + list(-fr[1:])
        rise = list(-fr[-2::-1]) + list(fr[1:])
        torques = np.array(up + down + rise) * t_max
        branches = loop_branches(torques)
        points, side = [], 1
        for t, b in zip(torques, branches):
            if t != 0:
                side = 1 if t > 0 else -1          # zero: the flank the path comes from
            points.append(twist.at(t, side, branch=int(b)))
        arcmin = lambda f: stuck_after_reversals(branches, [f(p.total) / ARCMIN for p in points])  # noqa: E731
        mean, lo, hi = arcmin(np.mean), arcmin(np.min), arcmin(np.max)
        n = fr.size
        falling = slice(n - 1, 3 * n - 2)         # +T -> -T
        rising = slice(3 * n - 3, 5 * n - 4)      # -T -> +T
        return ModelLoop(
            case_name=self.case.name, effects=effects, rated_torque_Nm=float(rated),
            torque_Nm=torques, branch=branches, twist_arcmin=mean, twist_min_arcmin=lo,
            twist_max_arcmin=hi, rising_torque_Nm=torques[rising],
            rising_twist_arcmin=mean[rising], falling_torque_Nm=torques[falling],
            falling_twist_arcmin=mean[falling],
            rigidity_Nm_per_arcmin=sheet.rigidity_Nm_per_arcmin,
            lost_motion_arcmin=sheet.lost_motion_arcmin,
            hysteresis_loss_arcmin=sheet.hysteresis_loss_arcmin,
            backlash_arcmin=sheet.backlash_arcmin, positions=self.positions,
            loop_pitch=int(loop_pitch))

    def te(self, effects: Effects | None = None, torques_Nm=(None,), *,
           samples: int | None = None) -> tuple:
        """The TE over the effects' period at each output torque, both directions.

        Parameters
        ----------
        effects : Effects, optional
            Default: the case as drawn.
        torques_Nm : sequence of float or None
            Output torques T >= 0 [N m] (forward at +T, backward at -T; 0 the clearance's
            closing from each side); None the rated torque.
        samples : int, optional
            Sampled pitches over the period (default ``te_samples``; the whole period when
            it is as long or longer).

        Returns
        -------
        tuple of ModelTe
            One per torque.

        Raises
        ------
        CaseError
            For a negative or non-finite torque.
        """
        effects = Effects() if effects is None else effects
        torques = []
        for t in torques_Nm:
            t = self.rated_torque_Nm if t is None else float(t)
            if not (math.isfinite(t) and t >= 0):
                raise CaseError(f"output torque {t!r} N m: >= 0 and finite (forward at +T, "
                                "backward at -T)")
            torques.append(t)
        if self._workers is not None:
            forward, backward = self._workers.runs(effects, torques, samples)
        else:
            forward, backward = (self.runs(effects, torques, sign, samples=samples)
                                 for sign in (1, -1))
        drive = self.drive
        period, pitches, _ = self._sampled(effects, samples)
        speeds = drive.speeds()
        out_per_crank = abs(speeds["output"] / speeds["crank"])
        out = []
        for t, (fwd, split_f), (bwd, split_b) in zip(torques, forward, backward):
            out.append(ModelTe(
                case_name=self.case.name, effects=effects, output_torque_Nm=t,
                crank_angle_rad=fwd.crank_angle_rad, output_angle_rad=fwd.output_angle_rad,
                te_forward_rad=fwd.te_rad, te_backward_rad=bwd.te_rad,
                share_forward=None if split_f is None else split_f.share,
                share_backward=None if split_b is None else split_b.share,
                period_pitches=int(period), sampled_pitches=tuple(pitches),
                per_pitch=self.positions,
                period_output_rad=float(period * drive.period_rad * out_per_crank)))
        return tuple(out)

    def _sampled(self, effects: Effects, samples: int | None) -> tuple:
        """(the effects' period [pitches], the sampled pitches, the deviation)."""
        deviation = effects.deviation(self.drive)
        period = self.drive.deviation_period_pitches(deviation)
        pitches = sampled_pitches(period, self.default_samples(effects, period)
                                  if samples is None else samples)
        return period, pitches, deviation

    def runs(self, effects: Effects, torques_Nm, sign: int, *,
             samples: int | None = None) -> list:
        """One direction's TE over the effects' period at each output torque (what
        :meth:`te` puts together, in this process or in its workers'): each torque under
        its running losses; with ``warm_starts`` its positions solved from this
        direction's last call at that torque where the effects are near (:func:`_near`: a
        fit's steps), else from the torque before (a continuation along the torques), and
        without, each pitch's positions from cold, one from the other.

        Parameters
        ----------
        effects : Effects
        torques_Nm : sequence of float
            Output torques T >= 0 [N m], checked.
        sign : {1, -1}
            Forward (the output driven against a brake of T) or backward (-T).
        samples : int, optional
            As :meth:`te`.

        Returns
        -------
        list of (LoadedTE, MemberSplit or None)
            One per torque (:func:`toothfem.fem.system.datasheet.period_te`).
        """
        drive = self.drive
        geometry = effects.geometry(drive)
        period, pitches, deviation = self._sampled(effects, samples)
        full = drive.full_period_pitches
        systems = [self.system(m % full, effects) for m in pitches]
        on = [m - m % full for m in pitches]
        near = _near(self._warm_effects.get(sign), effects)
        self._warm_effects[sign] = effects
        out, previous = [], None          # the last torque's states
        with one_blas_thread():           # once for every solve (each would set it again)
            for t in torques_Nm:
                path = t + self.running_loss_torque_Nm(t, effects)
                signed = sign * (path if path > 0 else ZERO_TORQUE_NM)
                key = (sign, t, tuple(pitches), tuple(on))
                warm = dict((near and self._warm.get(key)) or previous or {}) \
                    if self.warm_starts else None
                loaded, split, _ = period_te(iter(systems), pitches, signed,
                                             full_period=period, deviation=deviation,
                                             geometry=geometry, solve_pitches=on, warm=warm)
                if warm is not None:
                    self._warm[key] = previous = warm
                out.append((loaded, split))
        return out

    def default_samples(self, effects: Effects, period: int) -> int:
        """The sampled pitches :meth:`te` takes by default: ``te_samples``; a pin ring's
        orders :func:`ring_samples`; single pins the whole period.

        Parameters
        ----------
        effects : Effects
        period : int
            The effects' period [pitches].

        Returns
        -------
        int
        """
        if np.any(np.asarray(effects.pin_offset_m, float)):
            return period
        orders = [ring_order(k)[1] for k, v in effects.pin_ring_m.items() if v]
        if orders:
            zb = self.drive.nominal_deviation().pin_radius.size
            return max(self.te_samples, min(period, ring_samples(zb, max(orders))))
        return self.te_samples

    def recordings(self, effects: Effects | None = None, te_torques_Nm=(None,), *,
                   samples: int | None = None, **loop_options) -> ModelRecordings:
        """:meth:`hysteresis` and :meth:`te` under one set of effects.

        Parameters
        ----------
        effects : Effects, optional
        te_torques_Nm : sequence of float or None
            As :meth:`te`.
        samples : int, optional
            As :meth:`te`.
        **loop_options
            Go to :meth:`hysteresis`.

        Returns
        -------
        ModelRecordings
        """
        return ModelRecordings(loop=self.hysteresis(effects, **loop_options),
                               te=self.te(effects, te_torques_Nm, samples=samples))


def model_recordings(case, effects: Effects | None = None, te_torques_Nm=(None,), *,
                     positions: int = DEFAULT_POSITIONS,
                     te_samples: int = DEFAULT_TE_SAMPLES, cache=True,
                     system_options: dict | None = None, **loop_options) -> ModelRecordings:
    """The modelled loop and TE of a case under effects, in one call (a fit that calls
    many times keeps a :class:`RecordingModel`).

    Parameters
    ----------
    case : toothfem.case.Case or path
    effects : Effects, optional
    te_torques_Nm : sequence of float or None
        Output torques of the TE [N m] (None: the rated torque).
    positions, te_samples, cache
        As :class:`RecordingModel`.
    system_options : dict, optional
        :class:`RecordingModel`'s ``**system_options``.
    **loop_options
        Go to :meth:`RecordingModel.hysteresis`.

    Returns
    -------
    ModelRecordings
    """
    model = RecordingModel(case, positions=positions, te_samples=te_samples, cache=cache,
                           **(system_options or {}))
    return model.recordings(effects, te_torques_Nm, **loop_options)


def te_orders(case) -> dict:
    """The named orders per output revolution of a case's drive, to name a spectrum's
    peaks (:meth:`toothfem.fem.drives.base.Drive.te_orders`; a 2K-V crank's own errors
    ripple at its turn against the carrier, Zb per output revolution, which it names
    with the pins' passing).

    Parameters
    ----------
    case : toothfem.case.Case or path

    Returns
    -------
    dict of str to float
    """
    return drive_for(_a_case(case)).te_orders()


def _numbers(effects: Effects) -> tuple:
    """(what the effects set, their values): every field flattened, the mappings by key."""
    keys: list[tuple] = []
    values: list[float] = []
    for f in dataclasses.fields(effects):
        v = getattr(effects, f.name)
        if isinstance(v, dict):
            items = sorted(v.items())
            keys.append((f.name, tuple(k for k, _ in items)))
            values += [float(x) for _, x in items]
        elif v is None:
            keys.append((f.name, None))
        else:
            a = np.asarray(v, float).ravel()
            keys.append((f.name, a.size))
            values += a.tolist()
    return tuple(keys), np.array(values)


def _near(a: Effects | None, b: Effects) -> bool:
    """Whether the TE's states under effects ``a`` are a good start for ``b``'s: the same
    effects set, each value within NEAR_REL of the other's (a fit's finite-difference and
    trust-region steps; from much farther, e.g. a play of 0 to 5 um, Newton's steps from
    the other state took twice the steps of a start from rest)."""
    if a is None:
        return False
    (ka, va), (kb, vb) = _numbers(a), _numbers(b)
    return ka == kb and bool(np.all(np.abs(va - vb) <= NEAR_REL * np.maximum(np.abs(va),
                                                                             np.abs(vb))))


def _a_case(case):
    """A loaded case (``toothfem.load_case``), or the CaseError that says to load it: the
    loop works on the case's own record, whose fields its effects set."""
    if not hasattr(case, "to_si") or not hasattr(case, "drive"):
        raise CaseError(f"case = {case!r} is not a loaded case: load it with "
                        "toothfem.load_case first")
    return case
