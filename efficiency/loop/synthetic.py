"""Synthetic rig data: the model plus effects the case does not declare, plus sensor noise.

``generate(case, {"drag_torque": (20.0,)}, ...)`` draws operating points (input speed,
output torque, optionally oil temperature; shuffled, so the measurement order and time do not
follow the grid), evaluates the case with the given catalog effects (and optionally a loss
outside the catalog, e.g. :func:`running_in`), and measures the torques as a rig does:
T1 = T2 / (|i| eta), each torque read with Gaussian noise of standard deviation
accuracy x range (the rig of Y. Lu, L. Xu, "Transmission efficiency of one tooth difference
sine tooth profile planetary reducer", Heliyon 10 (2024) e26300, Sec. 6.4: input sensor
10 N m at 0.1 %, output 100 N m at 0.2 %; :class:`Rig`). The efficiency column is
T2_read / (|i| T1_read).

The accuracy of a torque sensor is read here as one standard deviation, the conservative
reading (a class figure is often a bound nearer 2-3 sigma). With the paper's own ranges the
sine prototype's efficiency is known to +-2.0 points at 28 N m and +-5.4 points at 10 N m
(one sigma; the input torque is 0.16-0.43 N m on a 10 N m sensor); :meth:`Rig.matched` sizes the
sensors to the reducer instead (the next 1-2-5 step above the largest torque), keeping the
paper's accuracy classes.
"""
from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..evaluation import operating_point
from . import effects as fx
from .measured import MeasuredData, sidecar_path, to_csv

#: Relative slack of the 1-2-5 step: a value on a step up to rounding (50 computed as
#: 50.000000001) is that step, not the next.
STEP_125_RTOL = 1e-12
#: Default output-torque range of :func:`generate`: from this fraction of the reference
#: torque up to it (30-100 %, the range of the tests and of the docs/loop.md figures).
TORQUE_RANGE_FRACTION = 0.3


@dataclass(frozen=True, kw_only=True)
class Rig:
    """Two torque sensors: range [N m] and accuracy (fraction of range, one sigma); the
    defaults are the sine prototype's rig (Lu & Xu 2024, Sec. 6.4)."""
    input_range_Nm: float = 10.0
    input_accuracy: float = 0.001
    output_range_Nm: float = 100.0
    output_accuracy: float = 0.002

    @property
    def input_sigma_Nm(self) -> float:
        return self.input_accuracy * self.input_range_Nm

    @property
    def output_sigma_Nm(self) -> float:
        return self.output_accuracy * self.output_range_Nm

    def sensors(self) -> dict:
        """The provenance ``sensors`` table (measured.sensor_sigma reads it).

        Returns
        -------
        dict
            ``input_torque`` and ``output_torque``, each {"range_Nm": [N m], "accuracy": [-]}.
        """
        return {"input_torque": {"range_Nm": self.input_range_Nm,
                                 "accuracy": self.input_accuracy},
                "output_torque": {"range_Nm": self.output_range_Nm,
                                  "accuracy": self.output_accuracy}}

    @classmethod
    def matched(cls, case, max_output_torque_Nm, min_efficiency=0.5) -> Rig:
        """Sensors of the paper's accuracy classes, ranged to the reducer.

        Parameters
        ----------
        case : toothfem.Case
            The reducer (its speed ratio i).
        max_output_torque_Nm : float
            Largest output torque of the test [N m].
        min_efficiency : float
            Lowest efficiency expected; sizes the input sensor for the largest input
            torque T2 / (|i| eta).

        Returns
        -------
        Rig
            Ranges at the next 1-2-5 step above the largest output and input torques,
            accuracies of the paper's rig.
        """
        i = abs(case.ratio())
        return cls(input_range_Nm=_step_125(max_output_torque_Nm / (i * min_efficiency)),
                   output_range_Nm=_step_125(max_output_torque_Nm))


def _step_125(x) -> float:
    """Smallest of 1, 2, 5 x 10^k that is >= x."""
    k = math.floor(math.log10(x))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10.0 ** k >= x * (1 - STEP_125_RTOL):
            return m * 10.0 ** k
    return 10.0 ** (k + 1)  # pragma: no cover


@dataclass(frozen=True)
class RunningIn:
    """A loss outside the catalog: running-in friction that decays with operating time,
    P = f0 P_out exp(-t / tau) [W] at (M,) points, called as ``loss(points, time_h,
    prediction)``; ``description`` says what it is."""
    initial_fraction: float
    time_constant_h: float

    @property
    def description(self) -> str:
        """What the loss is, for the data's header."""
        return (f"running-in loss {self.initial_fraction:g} P_out "
                f"exp(-t/{self.time_constant_h:g} h) (not in the catalog)")

    def __call__(self, points, time_h, prediction):
        """The loss [W].

        Parameters
        ----------
        points : toothfem.efficiency.loop.effect_base.Points
        time_h : numpy.ndarray, shape (M,)
            Operating time [h].
        prediction : toothfem.efficiency.loop.effect_base.Prediction
            Its output power [W].

        Returns
        -------
        numpy.ndarray, shape (M,)
        """
        return self.initial_fraction * prediction.output_power_W * np.exp(
            -time_h / self.time_constant_h)


def running_in(initial_fraction=0.05, time_constant_h=5.0) -> RunningIn:
    """A loss outside the catalog: running-in friction that decays with operating time,
    P = f0 P_out exp(-t / tau).

    Parameters
    ----------
    initial_fraction : float
        f0, the loss at t = 0 as a fraction of the output power.
    time_constant_h : float
        tau [h].

    Returns
    -------
    RunningIn
        ``loss(points, time_h, prediction) -> W`` ((M,) array), with a ``description``.
    """
    return RunningIn(float(initial_fraction), float(time_constant_h))


def operating_points(n_points, *, speed_rpm=(100.0, 1500.0), torque_Nm=(5.0, 28.0),
                     oil_temp_C=None, rng=None):
    """Operating points drawn uniformly over the ranges.

    Parameters
    ----------
    n_points : int
        M, the number of points.
    speed_rpm, torque_Nm : tuple of float
        (low, high) input speed [rpm] and output torque [N m].
    oil_temp_C : tuple of float, optional
        (low, high) oil temperature [deg C]; None: no temperature.
    rng : numpy.random.Generator, optional
        Random source (default seeded with 0).

    Returns
    -------
    tuple
        (speed, torque, temperature or None), (M,) arrays.
    """
    rng = rng or np.random.default_rng(0)
    n = rng.uniform(*speed_rpm, n_points)
    t = rng.uniform(*torque_Nm, n_points)
    temp = None if oil_temp_C is None else rng.uniform(*oil_temp_C, n_points)
    return n, t, temp


def generate(case, effects=None, *, n_points=200, rig=None, speed_rpm=(100.0, 1500.0),
             torque_Nm=None, oil_temp_C=None, hours=20.0, runs=4, extra_loss=None, seed=0,
             catalog=None, loads="analytic", at=None) -> MeasuredData:
    """Synthetic measured data (module docstring).

    Parameters
    ----------
    case : toothfem.Case
        The reducer as declared.
    effects : dict, optional
        {effect name or Effect: parameter values} added to the case for the truth.
    n_points : int
        M, the number of rows.
    rig : Rig, optional
        The torque sensors (default :meth:`Rig.matched`).
    speed_rpm : tuple of float
        (low, high) input speed [rpm].
    torque_Nm : tuple of float, optional
        (low, high) output torque [N m]; default :data:`TORQUE_RANGE_FRACTION` of the
        case's largest measured (else operating) torque up to that torque.
    oil_temp_C : tuple of float, optional
        (low, high) oil temperature [deg C] to draw from; None: no column (the
        lubricant's reference temperature).
    hours : float
        Measurement time [h] spread over the rows in their (shuffled) order.
    runs : int
        Number of runs (``run_id``) the rows are split into, in order.
    extra_loss : callable, optional
        A loss outside the catalog, ``f(points, time_h, prediction) -> W``.
    seed : int
        Seed of the points and of the noise.
    catalog : sequence of effects.Effect, optional
        Catalog the effect names are looked up in (default :func:`effects.catalog`).
    loads : str
        Load sharing of the model, ``"analytic"`` or ``"fem"``.
    at : effects.Points, optional
        Measure at these operating points instead of drawing them (``n_points``, the
        ranges and ``hours`` are then not used; a point without a time is at 0 h).

    Returns
    -------
    MeasuredData
        The read efficiencies with their sigma, input torques, time and run; the truth,
        sensors and noise in its provenance.
    """
    rng = np.random.default_rng(seed)
    cat = catalog or fx.catalog()
    assignment = {}
    for key, values in (effects or {}).items():
        eff = key if isinstance(key, fx.Effect) else fx.by_name(key, cat)
        assignment[eff] = tuple(float(v) for v in values)
    if torque_Nm is None:
        t_ref = max([m.output_torque_Nm for m in case.measured] or [0.0])
        if not t_ref:
            t_ref = operating_point(case)[1]
        torque_Nm = (TORQUE_RANGE_FRACTION * t_ref, t_ref)
    rig = rig or Rig.matched(case, torque_Nm[1])
    if at is None:
        n, t2, temp = operating_points(n_points, speed_rpm=speed_rpm, torque_Nm=torque_Nm,
                                       oil_temp_C=oil_temp_C, rng=rng)
        time_h = np.linspace(0.0, hours, n_points)
    else:
        n, t2, temp = at.speed_rpm, at.torque_Nm, at.oil_temp_C
        n_points = len(at)
        time_h = np.zeros(n_points) if at.time_h is None else np.asarray(at.time_h, float)
    run = np.array([f"run{1 + k * runs // n_points}" for k in range(n_points)], dtype=object)
    points = fx.Points(speed_rpm=n, torque_Nm=t2, oil_temp_C=temp, time_h=time_h)
    pred = fx.predict(case, points, assignment, loads=loads)
    losses = sum(pred.losses_W.values())
    if extra_loss is not None:
        losses = losses + extra_loss(points, time_h, pred)
    # the reducer's efficiency where it ran, then as its torque meters read it
    eta = fx.read(case, fx.true_points(case, points, assignment),
                  pred.output_power_W / (pred.output_power_W + losses), assignment)
    i = abs(case.ratio())
    t1 = t2 / (i * eta)
    t1_read = t1 + rng.normal(0.0, rig.input_sigma_Nm, n_points)
    t2_read = t2 + rng.normal(0.0, rig.output_sigma_Nm, n_points)
    eta_read = t2_read / (i * t1_read)
    sigma = eta_read * np.hypot(rig.input_sigma_Nm / t1_read, rig.output_sigma_Nm / t2_read)
    truth = {e.name: dict(zip((p.name for p in e.parameters), v))
             for e, v in assignment.items()}
    prov = {
        "source": "synthetic (toothfem.efficiency.loop.synthetic.generate)",
        "case": case.name, "seed": seed, "truth": truth,
        "outside_catalog": getattr(extra_loss, "description", None) if extra_loss else None,
        "noise": "Gaussian torque readings, sigma = accuracy x range (one sigma)",
        "sensors": rig.sensors(),
        "true_efficiency_rms_change": None,
    }
    base = fx.predict(case, points, loads=loads).efficiency
    prov["true_efficiency_rms_change"] = float(np.sqrt(np.mean((eta - base) ** 2)))
    return MeasuredData(speed_rpm=n, torque_Nm=t2_read, efficiency=eta_read, oil_temp_C=temp,
                        time_h=time_h, run_id=run, input_torque_Nm=t1_read, sigma=sigma,
                        extra={}, lines=np.arange(2, n_points + 2), rejected=(),
                        provenance=prov, source="synthetic")


def write(data: MeasuredData, path) -> Path:
    """Write ``data`` as CSV with its provenance in the sidecar JSON.

    Parameters
    ----------
    data : MeasuredData
        The record to write.
    path : str or pathlib.Path
        The CSV path (folders are made); the sidecar is ``<stem>.json`` beside it.

    Returns
    -------
    pathlib.Path
        The CSV path.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(to_csv(data))
    sidecar_path(path).write_text(json.dumps(data.provenance, indent=2, default=float) + "\n")
    return path


def reference_scenarios(sine, cycloid) -> dict:
    """The scenarios of the tests and of docs/loop.md: effect name -> (case that does not
    declare it, true parameter values, keywords of :func:`generate`), on the sine prototype
    (``sine``) and the pin-housing cycloid (``cycloid``) cases.

    The sine case declares its bearing and output-pin coefficients (the paper's Table 4);
    each scenario resets only the field of its own effect to the library default, so the
    others stay declared. Churning and mixed lubrication are in the model by default: their
    truths are corrections of the default parameters (twice the churning law; a boundary
    coefficient of 0.15 instead of 0.1). Bearing friction and output-pin friction on the
    sine reducer, and bearing friction and pin sliding on a cycloid, are all losses
    proportional to T n: efficiency data cannot tell them apart, so the pin-sliding case
    declares its bearing coefficient (0.002). The thermal effect needs a sensor: the sine
    rig reads 38-42 C while the oil at the contacts runs 5 K/W x the losses warmer (with the
    rig's time, the warm-up). Effect sizes: several times the rig noise.

    Parameters
    ----------
    sine : toothfem.Case
        The sine prototype case (cases/sine_prototype.toml).
    cycloid : toothfem.Case
        The pin-housing cycloid case (cases/cycloid_pinhousing.toml).

    Returns
    -------
    dict
        effect name -> (case, true values, keywords of :func:`generate`).
    """
    r = dataclasses.replace

    def fric(case, **kw):
        return r(case, friction=r(case.friction, **kw))

    def lub(case, **kw):
        return r(case, lubricant=r(case.lubricant, **kw))

    conventional = r(fric(cycloid, pin_groove_coefficient=0.0, bearing_coefficient=0.002),
                     cycloid=r(cycloid.cycloid, pin_structure="conventional"))
    cyc_kw = {"torque_Nm": (50.0, 167.0)}
    return {
        "drag_torque": (sine, (20.0,), {}),
        "churning": (sine, (2.0,), {"oil_temp_C": (30.0, 80.0)}),
        "viscosity_temperature": (lub(sine, vogel_B_C=1000.0), (1500.0,),
                                  {"oil_temp_C": (20.0, 100.0)}),
        "mixed_lubrication": (cycloid, (0.15,), cyc_kw),
        "bearing_friction": (fric(sine, bearing_coefficient=0.0015), (0.004,), {}),
        "output_mechanism_friction": (fric(sine, output_pin_coefficient=0.05), (0.03,), {}),
        "load_sharing_clearance": (cycloid, (0.003,), cyc_kw),
        "pin_sliding": (conventional, (0.05,), cyc_kw),
        "thermal": (sine, (5.0,), {"oil_temp_C": (38.0, 42.0)}),
    }
