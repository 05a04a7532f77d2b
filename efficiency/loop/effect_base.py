"""What the effect catalog is made of: parameters, operating points, effects, and the
efficiency with a set of effects applied.

:class:`Effect` records (one per physical effect, :mod:`.effects` builds the catalog),
:class:`Points`, :func:`predict` (the model with effects, linear components scaled without
a new evaluation), and the small helpers the effects are written with (a field's default,
declared-if-changed, setters).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ...errors import ToothfemError, check_range
from ...fem.drives import drive_for
from ..evaluation import evaluate

# ---------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter: name (with unit), bounds and starting values (absolute)."""
    name: str
    unit: str
    lo: float
    hi: float
    starts: tuple            # starting values tried before the fit (absolute)
    typical: float           # scale of the fit (x_scale) and of a signature's step
    doc: str = ""


@dataclass(frozen=True)
class Points:
    """Operating points: input speed [rpm], output torque [N m], oil temperature [deg C]
    or None (the lubricant's reference), operating time [h] or None; arrays of shape (M,)."""
    speed_rpm: np.ndarray
    torque_Nm: np.ndarray
    oil_temp_C: np.ndarray | None = None
    time_h: np.ndarray | None = None

    @classmethod
    def of(cls, data) -> "Points":
        """The operating points of a :class:`~toothfem.efficiency.measured.MeasuredData`."""
        return cls(np.asarray(data.speed_rpm, float), np.asarray(data.torque_Nm, float),
                   None if data.oil_temp_C is None else np.asarray(data.oil_temp_C, float),
                   None if data.time_h is None else np.asarray(data.time_h, float))

    def __len__(self):
        return int(self.speed_rpm.size)


@dataclass(frozen=True, eq=False)
class Effect:
    """A physical effect of the catalog (module docstring). ``values`` are tuples in the
    order of ``parameters``."""
    name: str
    summary: str
    equation: str
    citation: str
    parameters: tuple
    drives: tuple
    case_fields: tuple
    set_fields: Callable          # (case, values) -> case with the effect's fields set
    declared_by: Callable         # (case) -> str | None: the declaring field, if any
    not_applicable: Callable | None = None   # (case, points) -> reason | None
    loss_route: Callable | None = None       # (case) -> True if the effect is a loss term
    extra_loss: Callable | None = None       # (case, points, evaluation, values, prep) -> W
    prepare: Callable | None = None          # (case, points) -> prepared tables
    linear_in: Callable | None = None        # (case) -> loss component proportional to the
                                             # (single) parameter, or None

    def __repr__(self):
        return f"Effect({self.name!r})"

    def apply(self, case, values):
        """The case with this effect's fields set to ``values``."""
        values = tuple(float(v) for v in values)
        if len(values) != len(self.parameters):
            raise ToothfemError(f"{self.name}: {len(values)} values for "
                                f"{len(self.parameters)} parameters")
        for p, v in zip(self.parameters, values):
            check_range(f"{self.name}.{p.name}", v, p.lo, p.hi)
        return self.set_fields(case, values)

    def declared(self, case) -> str | None:
        """The case field that already declares this effect (non-default), or None."""
        return self.declared_by(case)

    def applicable(self, case, points) -> str | None:
        """Why the effect cannot act on this case and data (None: it can)."""
        if case.drive not in self.drives:
            return f"not for drive {case.drive!r} (drives: {', '.join(self.drives)})"
        if self.not_applicable is not None:
            return self.not_applicable(case, points)
        return None

    def route(self, case) -> str:
        """'model': the efficiency model evaluates the field; 'loss': a loss term here."""
        if self.loss_route is not None and self.loss_route(case):
            return "loss"
        return "model"

    def linear_component(self, case) -> str | None:
        """The loss component (a key of the losses) that is exactly proportional to this
        effect's single parameter, nothing else depending on it; None if there is none.
        Such an effect needs no new model evaluation when only its value changes."""
        return None if self.linear_in is None else self.linear_in(case)

    @property
    def reference(self) -> tuple:
        """Values at which a linear effect's component is evaluated, then scaled."""
        return tuple(p.typical for p in self.parameters)


# ---------------------------------------------------------------------------------------
# Predictions with effects


@dataclass(frozen=True)
class Prediction:
    """Efficiency and losses [W] at the points with a set of effects."""
    efficiency: np.ndarray
    output_power_W: np.ndarray
    losses_W: dict
    notes: tuple


def with_effects(case, assignment):
    """The case with every effect of ``assignment`` ({Effect: values}) applied: the case
    a report states (the loss-term effects' fields set as well)."""
    for eff, values in assignment.items():
        case = eff.apply(case, values)
    return case


@dataclass(frozen=True)
class _Losses:
    """What an extra_loss function reads of an evaluation: the losses (after scaling)."""
    losses_W: dict
    output_power_W: np.ndarray


def predict(case, points: Points, assignment=None, prepared=None, *, loads="analytic",
            cache=None) -> Prediction:
    """Efficiency of ``case`` with the effects ``assignment`` ({Effect: values}) at the
    points. ``prepared`` holds the tables of effects that need them ({name: object},
    :func:`prepare`); missing ones are computed here.

    ``cache`` (a dict, optional) keeps model evaluations keyed by the values of the effects
    that need one: an effect with a linear component (:meth:`Effect.linear_component`) is
    evaluated at its reference value and its component scaled, so a change of its value
    alone costs no evaluation (exact: the component is proportional to the parameter)."""
    assignment = assignment or {}
    prepared = {} if prepared is None else prepared
    model_case, key, scale = case, [], {}
    for eff, values in assignment.items():
        if eff.route(case) != "model":
            continue
        comp = eff.linear_component(case)
        if comp is not None:
            ref = eff.reference
            scale[comp] = scale.get(comp, 1.0) * float(values[0]) / ref[0]
            values = ref
        model_case = eff.apply(model_case, values)
        key.append((eff.name, tuple(float(v) for v in values)))
    key = tuple(sorted(key))
    ev = None if cache is None else cache.get(key)
    if ev is None:
        ev = evaluate(model_case, points.speed_rpm, points.torque_Nm, points.oil_temp_C,
                      loads=loads)
        if cache is not None:
            cache[key] = ev
    losses = dict(ev.losses_W)
    for comp, k in scale.items():
        losses[comp] = losses[comp] * k
    view = _Losses(losses, ev.output_power_W)
    for eff, values in assignment.items():
        if eff.route(case) == "loss":
            if eff.prepare is not None and eff.name not in prepared:
                prepared[eff.name] = eff.prepare(case, points)
            extra = eff.extra_loss(model_case, points, view, tuple(values),
                                   prepared.get(eff.name))
            losses[eff.name] = losses.get(eff.name, 0.0) + extra
    p_out = ev.output_power_W
    eta = p_out / (p_out + sum(losses.values()))
    return Prediction(eta, p_out, losses, ev.notes)


def prepare(effects, case, points) -> dict:
    """Tables of the effects that need them for these points ({name: object})."""
    return {e.name: e.prepare(case, points) for e in effects
            if e.prepare is not None and e.route(case) == "loss"
            and e.applicable(case, points) is None}


# ---------------------------------------------------------------------------------------
# Helpers


def default_of(section_cls, name):
    f = {x.name: x for x in dataclasses.fields(section_cls)}[name]
    return f.default


def declared_if_changed(section, name, label):
    """declared_by(case) for a field that is declared when it differs from its default."""
    def declared(case):
        sec = getattr(case, section)
        if sec is None:
            return None
        value = getattr(sec, name)
        if value != default_of(type(sec), name):
            return f"{label} = {value!r}"
        return None
    return declared


def setter(section, name):
    """set_fields(case, values) for one field of one section."""
    def setter(case, values):
        sec = getattr(case, section)
        return dataclasses.replace(case, **{section: dataclasses.replace(sec, **{name: values[0]})})
    return setter


def crank_speed_factor(case) -> float:
    """|crank speed / input speed| of a cycloid or RV drive (1 for a plain K-H-V stage)."""
    return abs(drive_for(case).speeds()["crank"])


def need_cycloid(case, points):
    if case.cycloid is None or case.material is None:
        return "needs the [cycloid] and [material] sections (disc, pins, contact stiffness)"
    return None
