"""The hysteresis loop and the catalogue figures of a reducer (docs/stiffness.md).

The loop runs the output torque from 0 to +T, down to -T and back to +T (the catalogue's
test, input held). A twist model with friction in its path (the system model) answers on
the branch the torque comes along (+1 rising, -1 falling): loading and unloading differ
and the loop has width; without friction both branches are the elastic curve and the
loop's only width is the backlash, at zero torque.

Definitions (Nabtesco's RV catalogues; strain-wave catalogues alike):
- torsional rigidity [N m/arcmin]: (T100 - T50) / (theta(T100) - theta(T50)) on the
  loading branch, the slope b/a between 50 % and 100 % of the rated torque, each direction
  and their mean;
- three-segment stiffness: the slopes over 0-25 %, 25-50 %, 50-100 % on the loading branch
  (from the zero-torque end of each branch, so the backlash is not in the first segment);
- lost motion [arcmin]: the twist between the midpoints of the loop's width at +3 % and at
  -3 % of the rated torque;
- hysteresis loss [arcmin]: the loop's width at zero torque (coming down from +T less
  coming up from -T);
- backlash [arcmin]: the elastic curve's theta(0 from +) - theta(0 from -), the two
  closing rotations of the clearances;
- compliances in series: each path's twist change between 50 % and 100 % per N m on the
  elastic curve, and its share of their sum (the inverse rigidity).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ...errors import CaseError, check_range
from .supports import Supports
from .twist import ARCMIN, TwistPoint

if TYPE_CHECKING:
    from ..drives.base import Drive

#: Catalogue points, fractions of the rated torque: lost motion at +-3 % (Nabtesco RV
#: catalogues), rigidity between 50 and 100 %, three segments 0-25-50-100 %.
LOST_MOTION_FRACTION = 0.03
RIGIDITY_FRACTIONS = (0.5, 1.0)
SEGMENT_FRACTIONS = (0.0, 0.25, 0.5, 1.0)
#: Fewest torque steps from 0 to +T: 25 % of T must be a step of the loop.
MIN_STEPS, MAX_STEPS = 4, 400
#: Fewest contacts that must carry at the largest torque of the loop at every position:
#: with one the mesh has not closed the modification's clearance (the curve is backlash).
MIN_CONTACTS_AT_MAX = 2
#: What the summary says of a loop without friction in its path.
FRICTIONLESS = "not modelled (frictionless contact): the loop's width is the backlash"


class TwistCurve(Protocol):
    """What the datasheet reads of a twist model: the twist at any output torque over the
    positions, the drive and its supports.
    :class:`~toothfem.fem.system.datasheet.SystemTwist` (the system model) is one; one with
    a ``friction_description`` (str) has the summary say it (else FRICTIONLESS).
    """

    @property
    def drive(self) -> Drive:
        """The drive: its ``member_name`` and ``contact_name`` label the figures."""
        ...

    @property
    def supports(self) -> Supports:
        """The supports in series with the mesh (their ``describe()`` goes on the sheet)."""
        ...

    @property
    def positions_rad(self) -> np.ndarray:
        """The crank angles the twist is taken at [rad], shape (P,)."""
        ...

    def at(self, output_torque_Nm: float, side: int = 1, branch: int = 0) -> TwistPoint:
        """The twist at a signed output torque.

        Parameters
        ----------
        output_torque_Nm : float
            [N m], either sign.
        side : {1, -1}
            At zero torque, the flank the limit comes from.
        branch : {0, 1, -1}
            The torque rising (+1) or falling (-1) to this value; 0 the elastic curve (a
            model without friction in its path answers the elastic curve on both).

        Returns
        -------
        TwistPoint
            ``total`` and its ``paths`` (P,) [rad], the loaded ``contacts`` (P,).
        """
        ...


def loop_torques(torque_max_Nm: float, steps: int) -> np.ndarray:
    """Output torques of the loop: 0 -> +T -> -T -> +T in steps of T/steps.

    Parameters
    ----------
    torque_max_Nm : float
        T [N m], > 0.
    steps : int
        MIN_STEPS to MAX_STEPS.

    Returns
    -------
    numpy.ndarray, shape (5 steps + 1,)
        [N m] (41 points for 8 steps).

    Raises
    ------
    CaseError
        For a torque or a step count out of range.
    """
    check_range("torque_max_Nm", torque_max_Nm, 0, None, lo_open=True, error=CaseError)
    if isinstance(steps, bool) or int(steps) != steps:
        raise CaseError(f"steps = {steps!r} must be an integer")
    check_range("steps", steps, MIN_STEPS, MAX_STEPS, error=CaseError,
                why="torque steps from 0 to the largest torque")
    n = int(steps)
    up = np.arange(0, n + 1)
    down = np.arange(n - 1, -n - 1, -1)
    back = np.arange(-n + 1, n + 1)
    return np.concatenate([up, down, back]) * (torque_max_Nm / n)


@dataclass(frozen=True, kw_only=True)
class Loop:
    """The hysteresis loop: per torque step the twist averaged over the positions and its
    range, and the loaded contacts (mean over the positions)."""
    torque_Nm: np.ndarray
    twist_arcmin: np.ndarray
    twist_min_arcmin: np.ndarray
    twist_max_arcmin: np.ndarray
    contacts: np.ndarray

    def rows(self):
        """The loop's table, one row per torque step.

        Returns
        -------
        iterator of tuple
            (torque_Nm, twist_arcmin, twist_min_arcmin, twist_max_arcmin, contacts).
        """
        return zip(self.torque_Nm, self.twist_arcmin, self.twist_min_arcmin,
                   self.twist_max_arcmin, self.contacts)


@dataclass(frozen=True, kw_only=True)
class Datasheet:
    """The catalogue figures of a drive from its FE contact and supports."""
    rated_torque_Nm: float
    rated_torque_assumed: bool
    loop: Loop
    rigidity_Nm_per_arcmin: float
    rigidity_by_direction: tuple            # (positive, negative) N m/arcmin
    segment_stiffness_Nm_per_arcmin: tuple  # (0-25 %, 25-50 %, 50-100 %), both directions' mean
    lost_motion_arcmin: float
    backlash_arcmin: float
    hysteresis_loss_arcmin: float
    window: dict                            # near zero torque: torque_Nm (3,), rising and
                                            # falling twist_arcmin (3,) at -3 %, 0, +3 %
    compliance_arcmin_per_Nm: dict          # path -> secant compliance 50-100 %
    supports: dict                          # Supports.describe(): values and assumed flags
    positions: int
    member_name: str
    contact_name: str
    extra: dict = field(default_factory=dict)   # TE and split summaries when computed
    friction: str = FRICTIONLESS

    @property
    def compliance_shares(self) -> dict:
        total = sum(self.compliance_arcmin_per_Nm.values())
        return {k: v / total for k, v in self.compliance_arcmin_per_Nm.items()}

    def summary(self) -> dict:
        """Plain mapping (summary.json).

        Returns
        -------
        dict
            The figures with their units in the keys, the supports, the contacts at the
            rated torque and the ``extra`` summaries.
        """
        out = {
            "rated_torque_Nm": self.rated_torque_Nm,
            "rated_torque_assumed": self.rated_torque_assumed,
            "torsional_rigidity_Nm_per_arcmin": self.rigidity_Nm_per_arcmin,
            "torsional_rigidity_positive_Nm_per_arcmin": self.rigidity_by_direction[0],
            "torsional_rigidity_negative_Nm_per_arcmin": self.rigidity_by_direction[1],
            "stiffness_0_25_Nm_per_arcmin": self.segment_stiffness_Nm_per_arcmin[0],
            "stiffness_25_50_Nm_per_arcmin": self.segment_stiffness_Nm_per_arcmin[1],
            "stiffness_50_100_Nm_per_arcmin": self.segment_stiffness_Nm_per_arcmin[2],
            "lost_motion_arcmin": self.lost_motion_arcmin,
            "backlash_arcmin": self.backlash_arcmin,
            "hysteresis_loss_arcmin": self.hysteresis_loss_arcmin,
            "compliances_arcmin_per_Nm": dict(self.compliance_arcmin_per_Nm),
            "compliance_shares": self.compliance_shares,
            "supports": self.supports,
            "positions": self.positions,
            f"{plural(self.contact_name)}_in_contact_at_rated_torque": float(
                self.loop.contacts[int(np.argmax(self.loop.torque_Nm))]),
            "friction_hysteresis": self.friction,
        }
        out.update(self.extra)
        return out


#: Plural of a drive's contact name in column names.
PLURALS = {"tooth": "teeth"}


def plural(name: str) -> str:
    """Plural of a contact name (PLURALS, else an added s).

    Parameters
    ----------
    name : str
        E.g. "pin" or "tooth".

    Returns
    -------
    str
    """
    return PLURALS.get(name, name + "s")


def _slope(model: TwistCurve, t_lo: float, t_hi: float, side: int) -> float:
    """(t_hi - t_lo) / (theta(t_hi) - theta(t_lo)) [N m/rad] on the loading branch of
    ``side`` (torques as magnitudes, signed by ``side``; the branch: their magnitude
    rising)."""
    a = model.at(side * t_lo, side, branch=side).total.mean()
    b = model.at(side * t_hi, side, branch=side).total.mean()
    return (t_hi - t_lo) / (side * (b - a))


def loop_branches(torques) -> np.ndarray:
    """The branch of each point of the loop: +1 where the torque rose to it, -1 where it
    fell (the first point: +1).

    Parameters
    ----------
    torques : array_like, shape (N,)
        [N m], :func:`loop_torques`.

    Returns
    -------
    numpy.ndarray of int, shape (N,)
    """
    t = np.asarray(torques, float)
    return np.concatenate([[1], np.where(np.diff(t) >= 0, 1, -1)])


def stuck_after_reversals(branches, twist) -> np.ndarray:
    """The loop's twist with the contacts stuck after each reversal: on a falling branch no
    more than at the reversal, on a rising one no less, until the branch's own curve
    passes that value (the play operator of a Coulomb element with rigid stick; without
    friction the branch curves are continuous and nothing changes).

    Parameters
    ----------
    branches : sequence of int
        Each point's branch (+1 rising, -1 falling).
    twist : sequence of float
        The branches' own twist at the points.

    Returns
    -------
    numpy.ndarray
        The twist with the contacts stuck.
    """
    out = np.array(twist, float)
    tip = None
    for i in range(1, out.size):
        if branches[i] != branches[i - 1]:
            tip = out[i - 1]                    # the reversal
        if tip is not None:
            out[i] = min(out[i], tip) if branches[i] < 0 else max(out[i], tip)
    return out


def datasheet(model: TwistCurve, rated_torque_Nm: float, *, rated_assumed: bool = False,
              torque_max_Nm: float | None = None, steps: int = 8) -> Datasheet:
    """The hysteresis loop and the catalogue figures.

    Parameters
    ----------
    model : TwistCurve
        The drive's twist over its positions (both torque signs).
    rated_torque_Nm : float
        Rated output torque [N m] (the catalogue's reference), > 0.
    rated_assumed : bool
        The rating is the case's operating torque, not a declared rating.
    torque_max_Nm : float, optional
        Largest torque of the loop [N m]; default the rated torque.
    steps : int
        Torque steps from 0 to the largest torque (>= 4).

    Returns
    -------
    Datasheet

    Raises
    ------
    CaseError
        For a rating, torque or step count out of range, or a largest torque that leaves
        fewer than MIN_CONTACTS_AT_MAX contacts at some position.
    """
    rated = check_range("rated_torque_Nm", rated_torque_Nm, 0, None, lo_open=True,
                        error=CaseError)
    t_max = rated if torque_max_Nm is None else torque_max_Nm
    torques = loop_torques(t_max, steps)
    _check_closed(model, t_max)
    points, side = [], 1
    for t, branch in zip(torques, loop_branches(torques)):
        if t != 0:
            side = 1 if t > 0 else -1           # zero: the flank the path comes from
        points.append(model.at(t, side, branch=int(branch)))
    deg = lambda x: x / ARCMIN  # noqa: E731
    branches = loop_branches(torques)
    loop = Loop(torque_Nm=torques,
                twist_arcmin=stuck_after_reversals(branches, [deg(p.total.mean()) for p in points]),
                twist_min_arcmin=stuck_after_reversals(branches, [deg(p.total.min()) for p in points]),
                twist_max_arcmin=stuck_after_reversals(branches, [deg(p.total.max()) for p in points]),
                contacts=np.array([float(np.mean(p.contacts)) for p in points]))
    lo, hi = (f * rated for f in RIGIDITY_FRACTIONS)
    rig = tuple(_slope(model, lo, hi, s) * ARCMIN for s in (1, -1))
    seg = []
    for a, b in zip(SEGMENT_FRACTIONS[:-1], SEGMENT_FRACTIONS[1:]):
        seg.append(0.5 * ARCMIN * sum(_slope(model, a * rated, b * rated, s) for s in (1, -1)))
    lost = lost_motion_arcmin(model, rated)
    backlash = backlash_arcmin(model)
    t_lm = LOST_MOTION_FRACTION * rated
    window = {"torque_Nm": np.array([-t_lm, 0.0, t_lm])}
    for name, branch, zero_side in (("rising_arcmin", 1, -1), ("falling_arcmin", -1, 1)):
        window[name] = np.array([deg(model.at(t, s, branch=branch).total.mean()) for t, s in
                                 ((-t_lm, -1), (0.0, zero_side), (t_lm, 1))])
    loss = float(window["falling_arcmin"][1] - window["rising_arcmin"][1])
    compliance = {}
    for name in model.at(hi, 1).paths:
        per_side = [side * (model.at(side * hi, side).paths[name].mean()
                            - model.at(side * lo, side).paths[name].mean()) / (hi - lo)
                    for side in (1, -1)]
        compliance[name] = deg(0.5 * sum(per_side))
    d = model.drive
    return Datasheet(rated_torque_Nm=float(rated), rated_torque_assumed=bool(rated_assumed),
                     loop=loop, rigidity_Nm_per_arcmin=0.5 * sum(rig),
                     rigidity_by_direction=rig, segment_stiffness_Nm_per_arcmin=tuple(seg),
                     lost_motion_arcmin=float(lost), backlash_arcmin=float(backlash),
                     hysteresis_loss_arcmin=loss, window=window,
                     friction=getattr(model, "friction_description", FRICTIONLESS),
                     compliance_arcmin_per_Nm=compliance,
                     supports=model.supports.describe(),
                     positions=int(model.positions_rad.size), member_name=d.member_name,
                     contact_name=d.contact_name)


def lost_motion_arcmin(model: TwistCurve, rated_torque_Nm: float) -> float:
    """Lost motion: the twist between the midpoints of the loop's width at +3 % and at -3 %
    of the rated torque (LOST_MOTION_FRACTION), each on its own flank; without friction the
    two branches coincide.

    Parameters
    ----------
    model : TwistCurve
    rated_torque_Nm : float
        [N m].

    Returns
    -------
    float
        [arcmin].
    """
    t_lm = LOST_MOTION_FRACTION * rated_torque_Nm

    def mid(t, side):
        return 0.5 * sum(model.at(t, side, branch=b).total.mean() for b in (1, -1))
    return float((mid(t_lm, 1) - mid(-t_lm, -1)) / ARCMIN)


def backlash_arcmin(model: TwistCurve) -> float:
    """Backlash: the mean twist at zero torque coming from + less that coming from -, the
    two flanks' closing rotations.

    Parameters
    ----------
    model : TwistCurve

    Returns
    -------
    float
        [arcmin].
    """
    return float((model.at(0.0, 1).total.mean() - model.at(0.0, -1).total.mean()) / ARCMIN)


def _check_closed(model: TwistCurve, t_max: float) -> None:
    """The loop's largest torque must close the modification's clearance to at least
    MIN_CONTACTS_AT_MAX contacts at every position (else the curve shows only backlash)."""
    for side in (1, -1):
        n = int(np.min(model.at(side * t_max, side).contacts))
        if n < MIN_CONTACTS_AT_MAX:
            back = backlash_arcmin(model)
            raise CaseError(
                f"torque_max_Nm = {t_max:g} is outside the valid range for this design: it "
                f"leaves {n} {model.drive.contact_name} in contact at some position (at "
                f"least {MIN_CONTACTS_AT_MAX}); the modification opens a backlash of "
                f"{back:.3g} arcmin that this torque does not close")
