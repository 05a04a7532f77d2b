"""Reducer efficiency at arrays of operating points: the prediction API.

``evaluate(case, speed_rpm, torque_Nm, oil_temp_C)`` returns the losses in watts of each
component (:mod:`toothfem.efficiency.drive_losses`) at arrays of operating points;
``predict`` returns the efficiency alone; ``operating_point`` the case's declared point.
The efficiency is ``P_out / (P_out + sum of losses)``. docs/efficiency.md has the equations
and checks.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..case_checks import SPEED_RPM, TORQUE_NM
from ..errors import CaseError, ToothfemError, check_range, checked_array
from ..fem.drives import drive_for
from . import rv_paper
from .drive_losses import OperatingPoints
from .. import limits
from .lubricant import viscosity_factor
from .mesh_table import LOADS, LoadsMemo
from ..si import si_of
from ..units import W_PER_KW, rpm_to_rad_s

METHODS = ("power_flow", "rv_split_power")
#: Positions per meshing period the efficiency model accepts: at least 4 to see the load
#: move between contacts, at most 720 (0.5 deg of crank on a 1-tooth period).
POSITIONS_RANGE = (4, 720)
#: Fixed-point iterations and tolerance of the output torque for a declared input torque.
OPERATING_MAX_ITER, OPERATING_RTOL = 50, 1e-10


@dataclass(frozen=True, kw_only=True)
class Efficiency:
    """Losses of every component at M operating points (arrays of shape (M,))."""
    speed_rpm: np.ndarray
    torque_Nm: np.ndarray
    oil_temp_C: np.ndarray | None
    output_power_W: np.ndarray
    losses_W: dict
    loads: str
    method: str
    notes: tuple = ()
    mesh_efficiency: dict = field(default_factory=dict)   # per stage, (M,)
    warnings: tuple = ()           # toothfem.limits.Exceeded: limits the points pass

    @property
    def input_power_W(self) -> np.ndarray:
        return self.output_power_W + sum(self.losses_W.values())

    @property
    def efficiency(self) -> np.ndarray:
        return self.output_power_W / self.input_power_W

    def shares(self) -> dict:
        """Each loss as a fraction of the input power (the sine paper's 'loss shares').

        Returns
        -------
        dict of str to numpy.ndarray
            component -> (M,) share [-]; with the efficiency they sum to 1.
        """
        p = self.input_power_W
        return {k: v / p for k, v in self.losses_W.items()}


def _points(speed_rpm, torque_Nm, oil_temp_C):
    """The operating points as flat float arrays, each refused naming its argument: not a
    number (strings and bools included), not finite, or outside the case keys' ranges
    (input speed SPEED_RPM, output torque above zero up to TORQUE_NM's top); the oil
    temperature is checked against the lubricant's law where it is used."""
    n = np.atleast_1d(checked_array("speed_rpm", speed_rpm, 0.0, lo_open=True,
                                    hi=SPEED_RPM[1], error=CaseError))
    t = np.atleast_1d(checked_array("torque_Nm", torque_Nm, 0.0, lo_open=True,
                                    hi=TORQUE_NM[1], error=CaseError))
    temp = None if oil_temp_C is None else np.atleast_1d(
        checked_array("oil_temp_C", oil_temp_C, error=CaseError))
    try:
        n, t, *rest = np.broadcast_arrays(n, t, *([] if temp is None else [temp]))
    except ValueError:
        raise ToothfemError(f"speed_rpm {n.shape}, torque_Nm {t.shape} and oil_temp_C "
                            f"{None if temp is None else temp.shape} do not broadcast") from None
    temp = rest[0] if rest else None
    return n.astype(float).ravel(), t.astype(float).ravel(), \
        None if temp is None else temp.ravel()


def evaluate(case, speed_rpm, torque_Nm, oil_temp_C=None, *, loads="analytic",
             method="power_flow", positions=36, table=None, memo=None) -> Efficiency:
    """Losses of every component of ``case`` at the operating points.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    speed_rpm, torque_Nm : array_like
        Input speed [rpm] and output torque [N m]; broadcast together.
    oil_temp_C : array_like, optional
        Oil temperature [deg C]; None for the lubricant's reference temperature.
    loads : {"analytic", "fem"}
        The seeds' load split or the FE cycle solver's.
    method : {"power_flow", "rv_split_power"}
        The friction model of every component, or the RV paper's split-power method
        with the declared mesh efficiency (RV cases only).
    positions : int
        Meshing positions over one period.
    table : toothfem.efficiency.mesh_table.MeshTable, optional
        The loaded contacts to use instead of those of ``loads`` (a built reducer's,
        :func:`~toothfem.efficiency.mesh_table.table_from_records`).
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling computation has met (each table computed once for it); None:
        this call's own.

    Returns
    -------
    Efficiency
        Losses [W] per component, efficiency, notes on the laws' validity, the limits
        the points pass (``warnings``: the output torque above the rating, the mesh's
        film ratio below 1 or 0.1).

    Raises
    ------
    CaseError
        For an unknown load source or method, positions out of range, a speed or torque
        not above zero, or the split-power method with a temperature or FE loads.
    ToothfemError
        If the operating-point arrays do not broadcast.
    """
    if loads not in LOADS:
        raise CaseError(f"loads = {loads!r} is not one of {list(LOADS)}")
    if method not in METHODS:
        raise CaseError(f"method = {method!r} is not one of {list(METHODS)}")
    if isinstance(positions, bool) or int(positions) != positions:
        raise CaseError(f"positions = {positions!r} must be an integer")
    check_range("positions", positions, *POSITIONS_RANGE, error=CaseError)
    si = si_of(case)
    n, t, temp = _points(speed_rpm, torque_Nm, oil_temp_C)
    record = dict(speed_rpm=n, torque_Nm=t, oil_temp_C=temp)
    if method == "rv_split_power":
        if temp is not None or loads != "analytic":
            raise CaseError("method = 'rv_split_power' takes the declared mesh efficiency: "
                            "oil_temp_C and loads = 'fem' do not apply to it")
        res = rv_paper.split_power_losses(si, rpm_to_rad_s(n), t)
        return Efficiency(**record, output_power_W=res.output_power_W,
                          losses_W=res.losses_W, loads="analytic", method=method,
                          notes=res.notes, mesh_efficiency=res.mesh_efficiency,
                          warnings=tuple(limits.rated_torque(si, t)))
    drive = drive_for(si)
    points = OperatingPoints(
        input_speed_rad_s=rpm_to_rad_s(n), output_torque_Nm=t,
        viscosity_factor=viscosity_factor(si.lubricant, temp) * np.ones_like(n),
        loads=loads, n_positions=int(positions), table=table,
        memo=LoadsMemo() if memo is None else memo)
    res = drive.layout.loss_model(si, drive, points)
    return Efficiency(**record, output_power_W=res.output_power_W, losses_W=res.losses_W,
                      loads=loads, method=method, notes=res.notes,
                      mesh_efficiency=res.mesh_efficiency,
                      warnings=tuple(limits.rated_torque(si, t))
                      + limits.worst(res.limits))


def predict(case, speed_rpm, torque_Nm, oil_temp_C=None, **kw) -> np.ndarray:
    """Efficiency (0..1) of ``case`` at arrays of operating points.

    Parameters
    ----------
    case, speed_rpm, torque_Nm, oil_temp_C, **kw
        As :func:`evaluate`.

    Returns
    -------
    numpy.ndarray
        The efficiency, shape of the broadcast inputs.

    Raises
    ------
    CaseError
        Where :func:`evaluate` refuses the points or options.
    """
    eta = evaluate(case, speed_rpm, torque_Nm, oil_temp_C, **kw).efficiency
    return eta.reshape(np.broadcast_shapes(np.shape(speed_rpm), np.shape(torque_Nm),
                                           np.shape(oil_temp_C) if oil_temp_C is not None
                                           else ()))


def operating_point(case, **kw):
    """The case's declared operating point.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    **kw
        As :func:`evaluate` (load source, positions).

    Returns
    -------
    speed_rpm, output_torque_Nm : float
        The declared input speed [rpm] and output torque [N m]: the declared output torque,
        or the output torque that the declared input torque or power gives through the
        model's own efficiency (fixed point T2 = i T1 eta(T2)).

    Raises
    ------
    CaseError
        If [operating] declares no torque or power, or the declared input does not
        overcome the load-independent losses.
    """
    si = si_of(case)
    op = si.operating
    speed = op.input_speed_rpm
    if op.output_torque_Nm:
        return speed, op.output_torque_Nm
    lossless = si.declared_output_torque_Nm()
    if lossless is None:
        raise CaseError("[operating] needs output_torque_Nm, input_torque_Nm or input_power_kW")
    kw = {"memo": LoadsMemo(), **kw}          # every evaluation at one drive's loads
    t2 = lossless
    for _ in range(OPERATING_MAX_ITER):       # contraction: eta varies slowly with torque
        new = lossless * float(evaluate(si, speed, t2, **kw).efficiency[0])
        if abs(new - t2) < OPERATING_RTOL * t2:
            return speed, new
        t2 = new
    # the contraction rate is 1 - eta: slow where the load-independent losses take much of
    # the input; a bracketed root of T2 - i T1 eta(T2) on (0, i T1] instead
    return speed, _output_torque_root(si, lossless, kw)


#: The bracket's lower end, a fraction of the lossless output torque i T1.
ROOT_BRACKET_LO = 1e-9


def _output_torque_root(si, t_lossless, kw) -> float:
    """Output torque T2 in (0, i T1) with T2 = i T1 eta(T2) (brentq); CaseError naming the
    declared input when even a vanishing output needs more than it (the no-load losses
    exceed the input power: the reducer does not turn)."""
    from scipy.optimize import brentq

    op = si.operating
    speed = op.input_speed_rpm

    def residual(t2):
        return t2 - t_lossless * float(evaluate(si, speed, t2, **kw).efficiency[0])

    lo = ROOT_BRACKET_LO * t_lossless
    if residual(lo) >= 0:
        key, value = (("input_torque_Nm", op.input_torque_Nm) if op.input_torque_Nm
                      else ("input_power_kW", op.input_power_W / W_PER_KW))
        raise CaseError(f"operating.{key} = {value!r} does not overcome the load-independent "
                        f"losses at {speed:g} rpm: no output torque")
    return float(brentq(residual, lo, t_lossless, rtol=OPERATING_RTOL))


def rated_output_torque(case, **kw) -> tuple[float, bool]:
    """The reducer's rated output torque, else the operating output torque taken as it.

    A case without ``operating.rated_torque_Nm`` is rated at the output torque its
    operating point gives (:func:`operating_point`: the declared output torque, or the
    declared input through the model's efficiency), the same figure ``run`` reports, never
    the lossless ``|i| T1``.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    **kw
        As :func:`operating_point`.

    Returns
    -------
    torque_Nm : float
        [N m].
    assumed : bool
        True when the case names no rating.

    Raises
    ------
    CaseError
        When the case declares neither a rating nor an operating torque or power.
    """
    si = si_of(case)
    if si.operating.rated_torque_Nm:
        return float(si.operating.rated_torque_Nm), False
    if si.declared_output_torque_Nm() is None:
        raise CaseError("operating.rated_torque_Nm is required (the case declares no "
                        "operating torque or power either)")
    return float(operating_point(si, **kw)[1]), True
