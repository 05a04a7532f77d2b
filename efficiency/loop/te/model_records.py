"""The records of the system model's recordings (docs/te_model.md): the :class:`Effects` a
fit varies (:mod:`.model` puts them on the case's system model) and what a rig records, the
hysteresis staircase (:class:`ModelLoop`) and the TE over its period (:class:`ModelTe`);
a pin ring's order from its key, and the pitches its TE needs.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ....errors import CaseError
from ....fem.datasheet.transmission import harmonic_amplitudes
from ....fem.datasheet.twist import ARCSEC

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
