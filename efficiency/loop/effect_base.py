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
        """The operating points of a :class:`~toothfem.efficiency.measured.MeasuredData`.

        Parameters
        ----------
        data : MeasuredData
            Measured rows (speed [rpm], output torque [N m], oil temperature [deg C] and time
            [h] if given).

        Returns
        -------
        Points
            The same points as float arrays (M,).
        """
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
        """The case with this effect's fields set to ``values``.

        Parameters
        ----------
        case : toothfem.case.Case
            The case (its units, e.g. mm).
        values : sequence of float
            One value per entry of ``parameters``, in the parameter's unit.

        Returns
        -------
        toothfem.case.Case
            A copy with the fields set.

        Raises
        ------
        ToothfemError
            If the number of values is wrong or a value leaves its parameter's bounds.
        """
        values = tuple(float(v) for v in values)
        if len(values) != len(self.parameters):
            raise ToothfemError(f"{self.name}: {len(values)} values for "
                                f"{len(self.parameters)} parameters")
        for p, v in zip(self.parameters, values):
            check_range(f"{self.name}.{p.name}", v, p.lo, p.hi)
        return self.set_fields(case, values)

    def declared(self, case) -> str | None:
        """The case field that already declares this effect (non-default), or None.

        Parameters
        ----------
        case : toothfem.case.Case
            Whose fields are looked at.

        Returns
        -------
        str or None
            "field = value", or None.
        """
        return self.declared_by(case)

    def applicable(self, case, points) -> str | None:
        """Why the effect cannot act on this case and data (None: it can).

        Parameters
        ----------
        case : toothfem.case.Case
            The case the effect would act on (its drive and sections).
        points : Points
            The operating points.

        Returns
        -------
        str or None
            The reason, or None.
        """
        if case.drive not in self.drives:
            return f"not for drive {case.drive!r} (drives: {', '.join(self.drives)})"
        if self.not_applicable is not None:
            return self.not_applicable(case, points)
        return None

    def route(self, case) -> str:
        """'model': the efficiency model evaluates the field; 'loss': a loss term here.

        Parameters
        ----------
        case : toothfem.case.Case
            Decides the route where an effect's route depends on it.

        Returns
        -------
        str
            "model" or "loss".
        """
        if self.loss_route is not None and self.loss_route(case):
            return "loss"
        return "model"

    def linear_component(self, case) -> str | None:
        """The loss component (a key of the losses) that is exactly proportional to this
        effect's single parameter, nothing else depending on it; None if there is none.
        Such an effect needs no new model evaluation when only its value changes.

        Parameters
        ----------
        case : toothfem.case.Case
            The case whose losses the model evaluates.

        Returns
        -------
        str or None
            The key, or None.
        """
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
    """The case with every effect of ``assignment`` applied: the case a report states (the
    loss-term effects' fields set as well).

    Parameters
    ----------
    case : toothfem.case.Case
        The case before the effects (its own units, e.g. mm).
    assignment : dict of Effect to sequence of float
        {Effect: values}.

    Returns
    -------
    toothfem.case.Case
        The case with the fields set.

    Raises
    ------
    ToothfemError
        As :meth:`Effect.apply`.
    """
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
    """Efficiency of ``case`` with the effects ``assignment`` at the points.

    An effect with a linear component (:meth:`Effect.linear_component`) is evaluated at its
    reference value and its component scaled, so a change of its value alone costs no
    evaluation (exact: the component is proportional to the parameter).

    Parameters
    ----------
    case : toothfem.case.Case
        The case the model evaluates, before the effects.
    points : Points
        The M operating points.
    assignment : dict of Effect to sequence of float, optional
        {Effect: values}; None: the model alone.
    prepared : dict, optional
        The tables of effects that need them ({name: object}, :func:`prepare`); missing
        ones are computed here and added.
    loads : {"analytic", "fem"}
        The meshing table's load source.
    cache : dict, optional
        Keeps model evaluations keyed by the values of the effects that need one.

    Returns
    -------
    Prediction
        Efficiency [-], output power and losses [W] at the points, and the model's notes.
    """
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
    """Tables of the effects that need them for these points.

    Parameters
    ----------
    effects : iterable of Effect
        The effects (those that do not apply are skipped).
    case : toothfem.case.Case
        The case the tables are made for.
    points : Points
        The operating points.

    Returns
    -------
    dict
        {name: object}.
    """
    return {e.name: e.prepare(case, points) for e in effects
            if e.prepare is not None and e.route(case) == "loss"
            and e.applicable(case, points) is None}


# ---------------------------------------------------------------------------------------
# Helpers


def default_of(section_cls, name):
    """The default of a field of a case section.

    Parameters
    ----------
    section_cls : type
        A section's dataclass (e.g. :class:`toothfem.case_sections.Friction`).
    name : str
        The field.

    Returns
    -------
    object
        The field's default (``dataclasses.MISSING`` if it has none).
    """
    f = {x.name: x for x in dataclasses.fields(section_cls)}[name]
    return f.default


def declared_if_changed(section, name, label):
    """declared_by(case) for a field that is declared when it differs from its default.

    Parameters
    ----------
    section : str
        The case section's attribute name.
    name : str
        The field.
    label : str
        How the result names the field.

    Returns
    -------
    callable
        ``declared(case) -> str or None``: "label = value" where the field differs from its
        default, else None.
    """
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
    """set_fields(case, values) for one field of one section.

    Parameters
    ----------
    section : str
        Attribute of the case holding the section ("friction", "lubricant", ...).
    name : str
        The field the effect's single value goes to.

    Returns
    -------
    callable
        ``setter(case, values) -> case`` with the field set to ``values[0]``.
    """
    def setter(case, values):
        sec = getattr(case, section)
        return dataclasses.replace(case, **{section: dataclasses.replace(sec, **{name: values[0]})})
    return setter


def crank_speed_factor(case) -> float:
    """|crank speed / input speed| of a cycloid or RV drive (1 for a plain K-H-V stage).

    Parameters
    ----------
    case : toothfem.case.Case
        Its drive gives the speeds.

    Returns
    -------
    float
        The factor [-].
    """
    return abs(drive_for(case).speeds()["crank"])


def need_cycloid(case, points):
    """Why a cycloid effect cannot act: the case lacks [cycloid] or [material].

    Parameters
    ----------
    case : toothfem.case.Case
        Checked for the two sections.
    points : Points
        The operating points (unused; the ``not_applicable`` signature).

    Returns
    -------
    str or None
        The reason, or None.
    """
    if case.cycloid is None or case.material is None:
        return "needs the [cycloid] and [material] sections (disc, pins, contact stiffness)"
    return None
