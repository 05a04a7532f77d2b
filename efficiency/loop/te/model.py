"""The model side of TE and hysteresis recordings (issue 24, items 3 and 5): what the
system model of the whole reducer (:mod:`toothfem.fem.system`) records on a rig, with
effects a fit can vary (docs/te_model.md).

**Effects** (:class:`Effects`, SI, every default the case as drawn):

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
  of T) and the backward run at -T (the brake reversed with the motion), frictionless
  elastic states (the rotating mesh's friction is not in the solve; the path friction
  belongs to the staircase). The period is the effects' own
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
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ...no_load import path_friction
from ....errors import CaseError
from ....fem.datasheet.sheet import stuck_after_reversals, datasheet, loop_branches
from ....fem.datasheet.transmission import harmonic_amplitudes, sampled_pitches
from ....fem.datasheet.twist import ARCMIN, ARCSEC, ZERO_TORQUE_NM
from ....fem.drives import drive_for
from ....fem.contracts import ReducerModel
from ....fem.system.datasheet import SystemTwist, period_te
from ...evaluation import rated_output_torque

#: Positions per pin pitch of the loop's and the TE's systems: the loop's twist is their
#: mean and the TE's pin-mesh ripple is sampled by them; 4 keeps a model call near 0.2 s
#: (the loop's figures move by 1e-4 relative from 4 to 36 positions on rv40e; the mesh
#: ripple's amplitude needs about 12).
DEFAULT_POSITIONS = 4
#: Sampled pitches over the TE's period: the Fourier fill resolves up to order 3 of the
#: period, so a 2K-V crank's error (one turn of the crank against the carrier per period)
#: shows its first three harmonics.
DEFAULT_TE_SAMPLES = 7
#: Torque steps from 0 to +T of the datasheet's loop (its figures: rigidity from 50 to
#: 100 % needs 25 % steps at least).
DEFAULT_STEPS = 4
#: The staircase of :class:`ModelLoop`, fractions of the largest torque: fine steps near
#: zero (lost motion at 3 %, a rig's backlash fit up to 10 %), then 25-50-75-100 % (the
#: rigidity's 50 and 100 %).
STAIRCASE_FRACTIONS = (0.0, 0.03, 0.06, 0.1, 0.25, 0.5, 0.75, 1.0)
#: Kinds of a pin ring's orders (:attr:`Effects.pin_ring_m` keys ``"<kind>_<order>"``).
RING_KINDS = ("radial", "tangential")
#: Sampled pitches per order of the highest ripple a pin ring's error gives (2 Zb + its
#: order): twice the Fourier series' need, as its ripple above that order would fold onto
#: the fitted ones. Measured on RV-40E (Zb = 40, benchmarks/pin_ring_response.py): at
#: 4 x 82 + 1 = 329 pitches (325 for order 1) every fitted row within 0.5 % of the whole
#: period's (1560 pitches), at 241 within 1.2 %, at 161 up to 14 % off.
RING_SAMPLES_PER_ORDER = 4
#: The case's [cycloid] modification keys the effects set -> the geometry's field.
MODIFICATIONS = {"equidistant_modification_m": "equidistant_m",
                 "move_distance_modification_m": "move_distance_m"}


@dataclass(frozen=True, kw_only=True)
class Effects:
    """Effects a fit varies, SI (the module docstring); the defaults are the case as drawn.
    Arrays may be given as sequences; ``stiffness_scale`` as a mapping part -> factor."""
    crank_bearing_play_m: float = 0.0
    crank_eccentricity_m: ArrayLike = ()
    crank_phase_rad: ArrayLike = ()
    stiffness_scale: dict = field(default_factory=dict)
    equidistant_modification_m: float | None = None
    move_distance_modification_m: float | None = None
    pin_radius_m: ArrayLike = 0.0
    pin_offset_m: ArrayLike = ()
    pin_ring_m: dict = field(default_factory=dict)
    friction_scale: float = 1.0

    def __post_init__(self):
        for name in ("crank_bearing_play_m", "friction_scale"):
            v = getattr(self, name)
            if not math.isfinite(v):
                raise CaseError(f"{name} = {v!r}: finite")
        if self.friction_scale < 0:
            raise CaseError(f"friction_scale = {self.friction_scale!r}: >= 0")
        for name in ("crank_eccentricity_m", "crank_phase_rad", "pin_radius_m",
                     "pin_offset_m"):
            if not np.all(np.isfinite(np.asarray(getattr(self, name), float))):
                raise CaseError(f"{name}: every value finite")
        for name in MODIFICATIONS:
            v = getattr(self, name)
            if v is not None and not math.isfinite(v):
                raise CaseError(f"{name} = {v!r}: finite")
        for key, v in self.pin_ring_m.items():
            ring_order(key)
            if not math.isfinite(v):
                raise CaseError(f"pin_ring_m[{key!r}] = {v!r}: finite")

    def describe(self) -> dict:
        """The effects that differ from the drawing, for a header or a summary.

        Returns
        -------
        dict of str to float or list
            Field name (unit in it) -> value (arrays as lists).
        """
        out: dict[str, float | list[float] | dict[str, float]] = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if f.default is not dataclasses.MISSING:
                default = f.default
            elif f.default_factory is not dataclasses.MISSING:
                default = f.default_factory()
            else:
                raise TypeError(f"Effects.{f.name} has no default")   # every field has one
            if isinstance(v, dict):
                if v:
                    out[f.name] = {k: float(x) for k, x in v.items()}
            elif v is None:
                continue
            elif np.ndim(v) or np.size(v) != 1:
                if np.size(v) and np.any(np.asarray(v, float)):
                    out[f.name] = np.asarray(v, float).tolist()
            elif float(v) != default:
                out[f.name] = float(v)
        return out

    def system_options(self) -> dict:
        """The system model's options these effects set (:meth:`CycloidSystem.variant`).

        Returns
        -------
        dict
        """
        return {"crank_bearing_play_m": float(self.crank_bearing_play_m),
                "stiffness_scale": {k: float(v) for k, v in self.stiffness_scale.items()}}

    def deviation(self, drive):
        """The built stage these effects describe, or None (the stage as drawn: the solve
        is then exactly the nominal one).

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive

        Returns
        -------
        object or None
            The drive's record of :mod:`toothfem.fem.deviations`.

        Raises
        ------
        CaseError
            For an effect the drive's deviation has no place for, or arrays of another
            shape than its pins.
        """
        put = {}
        crank = np.asarray(self.crank_eccentricity_m, float)
        if crank.size and np.any(crank):
            put["crank_eccentricity_m"] = crank
            phase = np.asarray(self.crank_phase_rad, float)
            put["crank_phase_rad"] = np.zeros(crank.shape) if phase.size == 0 else phase
        radius = np.asarray(self.pin_radius_m, float)
        offset = np.asarray(self.pin_offset_m, float)
        ring = {k: v for k, v in self.pin_ring_m.items() if v}
        pins = radius.size and np.any(radius)
        moved = (offset.size and np.any(offset)) or ring
        if not (put or pins or moved):
            return None
        nominal = drive.nominal_deviation()
        if pins or moved:
            if "pins" not in drive.layout.components:
                raise CaseError(f"pin_radius_m, pin_offset_m, pin_ring_m: this drive has no "
                                f"{drive.contacts_name} to move (a {drive.kind} drive)")
            zb = nominal.pin_radius.size
            if pins:
                if radius.size not in (1, zb):
                    raise CaseError(f"pin_radius_m has {radius.size} values: one, or one per "
                                    f"pin ({zb})")
                put["pin_radius"] = np.broadcast_to(radius.ravel(), (zb,)).copy()
            if moved:
                if offset.size and offset.shape != (2, zb):
                    raise CaseError(f"pin_offset_m has the shape {offset.shape}: (2, {zb})")
                put["pin_offset"] = offset.copy() if offset.size else np.zeros((2, zb))
                for key, v in ring.items():
                    kind, order = ring_order(key)
                    put["pin_offset"] += drive.pin_ring_offsets(order, **{f"{kind}_m": v})
        return dataclasses.replace(nominal, **put)

    def geometry(self, drive):
        """The disc with the effects' profile modification, on the nominal tables, or None
        (the case's own).

        Parameters
        ----------
        drive : toothfem.fem.drives.Drive

        Returns
        -------
        object or None
            The drive's geometry record with its modifications replaced.

        Raises
        ------
        CaseError
            For a drive without such a modification.
        """
        put = {MODIFICATIONS[k]: float(getattr(self, k)) for k in MODIFICATIONS
               if getattr(self, k) is not None}
        if not put:
            return None
        fields = {f for f, _ in drive.layout.design_keys.values()}   # the layout's own
        if not set(put) <= fields:
            asked = ", ".join(k for k in MODIFICATIONS if getattr(self, k) is not None)
            raise CaseError(f"{asked}: a {drive.kind} drive has no such profile modification")
        g = drive.geometry
        new = dataclasses.replace(g, **put)
        return None if new == g else new


@dataclass(frozen=True, kw_only=True)
class ModelLoop:
    """The modelled hysteresis staircase (input held, the path friction's play operator)
    and its catalogue figures by the datasheet's definitions."""
    case_name: str
    effects: Effects
    rated_torque_Nm: float
    torque_Nm: np.ndarray            # (S,) the staircase 0 -> +T -> -T -> +T
    branch: np.ndarray               # (S,) +1 the torque rising to the step, -1 falling
    twist_arcmin: np.ndarray         # (S,) mean over the positions
    twist_min_arcmin: np.ndarray     # (S,) over the positions
    twist_max_arcmin: np.ndarray     # (S,)
    rising_torque_Nm: np.ndarray     # the last rising branch, -T -> +T
    rising_twist_arcmin: np.ndarray
    falling_torque_Nm: np.ndarray    # the falling branch, +T -> -T
    falling_twist_arcmin: np.ndarray
    rigidity_Nm_per_arcmin: float
    lost_motion_arcmin: float
    hysteresis_loss_arcmin: float
    backlash_arcmin: float
    positions: int
    loop_pitch: int

    def figures(self) -> dict:
        """The catalogue figures, the keys of :meth:`toothfem.fem.datasheet.sheet.
        Datasheet.summary`.

        Returns
        -------
        dict of str to float
        """
        return {"torsional_rigidity_Nm_per_arcmin": self.rigidity_Nm_per_arcmin,
                "lost_motion_arcmin": self.lost_motion_arcmin,
                "hysteresis_loss_arcmin": self.hysteresis_loss_arcmin,
                "backlash_arcmin": self.backlash_arcmin}


@dataclass(frozen=True, kw_only=True)
class ModelTe:
    """The modelled TE at one output torque over the effects' period (N = pitches x
    positions per pitch), both directions; the TE is the output's lag behind its kinematic
    position (positive forward)."""
    case_name: str
    effects: Effects
    output_torque_Nm: float          # T >= 0: forward at +T, backward at -T
    crank_angle_rad: np.ndarray      # (N,) from the period's start
    output_angle_rad: np.ndarray     # (N,)
    te_forward_rad: np.ndarray       # (N,)
    te_backward_rad: np.ndarray      # (N,)
    share_forward: np.ndarray | None     # (M, N) each member's share of the torque
    share_backward: np.ndarray | None
    period_pitches: int
    sampled_pitches: tuple
    per_pitch: int
    period_output_rad: float         # the output angle of the period

    @property
    def output_angle_deg(self) -> np.ndarray:
        return np.degrees(self.output_angle_rad)

    @property
    def te_forward_arcsec(self) -> np.ndarray:
        return self.te_forward_rad / ARCSEC

    @property
    def te_backward_arcsec(self) -> np.ndarray:
        return self.te_backward_rad / ARCSEC

    @property
    def width_arcsec(self) -> float:
        """The hysteresis width, forward mean TE less backward mean [arcsec]."""
        return float((self.te_forward_rad.mean() - self.te_backward_rad.mean()) / ARCSEC)

    def spectrum(self, direction: int = 1):
        """The TE's harmonics over the period (its whole-period DFT: exact at the orders
        of the period, multiples of 2 pi / period_output_rad).

        Parameters
        ----------
        direction : {1, -1}
            Forward or backward.

        Returns
        -------
        orders : numpy.ndarray
            Per output revolution.
        amplitude_arcsec : numpy.ndarray
        """
        te = self.te_forward_rad if direction > 0 else self.te_backward_rad
        orders, amp = harmonic_amplitudes(te, self.period_output_rad)
        return orders, amp / ARCSEC

    def amplitude_arcsec(self, order: float, direction: int = 1) -> float:
        """The TE's amplitude at one order per output revolution [arcsec]: its harmonic
        of the period, 0 where the order is not one (the TE holds none there).

        Parameters
        ----------
        order : float
        direction : {1, -1}

        Returns
        -------
        float
        """
        orders, amp = self.spectrum(direction)
        h = order * self.period_output_rad / (2 * math.pi)
        if abs(h - round(h)) > 1e-6 or round(h) < 1 or round(h) > orders.size:
            return 0.0
        return float(amp[int(round(h)) - 1])


@dataclass(frozen=True, kw_only=True)
class ModelRecordings:
    """What :func:`model_recordings` gives: the loop (None where not recorded) and the TE
    at each torque."""
    loop: ModelLoop | None
    te: tuple


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
    **system_options
        Go to every :class:`toothfem.fem.drives.assembly.CycloidSystem` (e.g.
        ``pin_spring_m_per_N``: equal contact springs instead of the FE, ``rigid``).

    Raises
    ------
    CaseError
        For a drive without a system model, or no rating or operating torque.
    """

    def __init__(self, case, *, positions: int = DEFAULT_POSITIONS,
                 te_samples: int = DEFAULT_TE_SAMPLES, cache=True, **system_options):
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
        if self.system(0) is None:
            raise CaseError(f"a {self.drive.kind} drive without [output_mechanism] has no "
                            "system model: no modelled recordings")

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
        drive = self.drive
        deviation = effects.deviation(drive)
        geometry = effects.geometry(drive)
        period = drive.deviation_period_pitches(deviation)
        full = drive.full_period_pitches
        pitches = sampled_pitches(period, self.default_samples(effects, period)
                                  if samples is None else samples)
        systems = [self.system(m % full, effects) for m in pitches]
        on = [m - m % full for m in pitches]
        speeds = drive.speeds()
        out_per_crank = abs(speeds["output"] / speeds["crank"])
        out = []
        for t in torques_Nm:
            t = self.rated_torque_Nm if t is None else float(t)
            if not (math.isfinite(t) and t >= 0):
                raise CaseError(f"output torque {t!r} N m: >= 0 and finite (forward at +T, "
                                "backward at -T)")
            runs = []
            for sign in (1, -1):
                signed = sign * (t if t > 0 else ZERO_TORQUE_NM)
                runs.append(period_te(iter(systems), pitches, signed, full_period=period,
                                      deviation=deviation, geometry=geometry,
                                      solve_pitches=on))
            (fwd, split_f, _), (bwd, split_b, _) = runs
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


def ring_order(key: str) -> tuple[str, int]:
    """A pin ring's order from its key in :attr:`Effects.pin_ring_m`.

    Parameters
    ----------
    key : str
        ``"<kind>_<order>"``, kind one of :data:`RING_KINDS`, order >= 1.

    Returns
    -------
    kind : str
    order : int

    Raises
    ------
    CaseError
        For another key.
    """
    kind, _, order = str(key).rpartition("_")
    if kind not in RING_KINDS or not order.isdigit() or int(order) < 1:
        raise CaseError(f"pin_ring_m key {key!r}: '<kind>_<order>', kind one of "
                        f"{', '.join(RING_KINDS)}, order a whole number >= 1")
    return kind, int(order)


def ring_samples(pins: int, order: int) -> int:
    """Sampled pitches that hold a pin ring's error of one order round the ring: its
    ripple reaches 2 Zb + order per output revolution (the second multiple of the pin
    passing and its side bands), sampled :data:`RING_SAMPLES_PER_ORDER` times per order.

    Parameters
    ----------
    pins : int
        Zb.
    order : int
        The ring's order.

    Returns
    -------
    int
    """
    return RING_SAMPLES_PER_ORDER * (2 * int(pins) + int(order)) + 1


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


def _a_case(case):
    """A loaded case (``toothfem.load_case``), or the CaseError that says to load it: the
    loop works on the case's own record, whose fields its effects set."""
    if not hasattr(case, "to_si") or not hasattr(case, "drive"):
        raise CaseError(f"case = {case!r} is not a loaded case: load it with "
                        "toothfem.load_case first")
    return case
