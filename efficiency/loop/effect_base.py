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
from collections.abc import Callable

import numpy as np

from ...errors import ToothfemError, check_range
from ...fem.drives import drive_for
from ...si import si_of
from ..evaluation import evaluate
from .engine import Parameter  # noqa: F401  (the effects' parameters: the engine's record)

# ---------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True)
class Points:
    """Operating points: input speed [rpm], output torque [N m], oil temperature [deg C]
    or None (the lubricant's reference), operating time [h] or None; arrays of shape (M,)."""
    speed_rpm: np.ndarray
    torque_Nm: np.ndarray
    oil_temp_C: np.ndarray | None = None
    time_h: np.ndarray | None = None

    @classmethod
    def of(cls, data) -> Points:
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

    def oil_or_reference(self, case) -> np.ndarray:
        """The oil temperatures the model takes at the points.

        Parameters
        ----------
        case : toothfem.case.Case
            Its lubricant's reference temperature stands for a missing column.

        Returns
        -------
        numpy.ndarray
            (M,) [deg C]: the column, or the reference temperature where the data have
            none.
        """
        if self.oil_temp_C is not None:
            return np.asarray(self.oil_temp_C, float)
        return np.full(len(self), float(case.lubricant.reference_temperature_C))


@dataclass(frozen=True, eq=False)
class Effect:
    """A physical effect of the catalog (module docstring). ``values`` are tuples in the
    order of ``parameters``."""
    name: str
    summary: str
    equation: str
    citation: str
    parameters: tuple
    case_fields: tuple
    set_fields: Callable          # (case, values) -> case with the effect's fields set
    declared_by: Callable         # (case) -> str | None: the declaring field, if any
    not_applicable: Callable | None = None   # (case, points) -> reason | None
    acts_on: str | None = None               # the component of the layout it needs
                                             # (DriveRecord.components); None: every layout
    loss_route: Callable | None = None       # (case) -> True if the effect is a loss term
    extra_loss: Callable | None = None       # (case, points, evaluation, values, prep) -> W
    prepare: Callable | None = None          # (case, points) -> prepared tables
    linear_in: Callable | None = None        # (case) -> loss component proportional to the
                                             # (single) parameter, or None
    true_points: Callable | None = None      # (case, points, values) -> the points the
                                             # reducer ran at, where the data's columns
                                             # misread them (a sensor offset, a warm-up)
    reading: Callable | None = None          # (t1, t2, values) -> (t1, t2) as the rig's
                                             # torque meters read them [N m]
    bounds_for: Callable | None = None       # (case, points) -> ((lo, hi, typical[,
                                             # starts]), ...): bounds that depend on the
                                             # case and data
    direct_test: str = ""                    # a measurement that shows this effect
                                             # whatever the operating points

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
        layout = si_of(case).layout
        if self.acts_on is not None and self.acts_on not in layout.components:
            return (f"acts on the {self.acts_on.replace('_', ' ')}, which {layout.label} "
                    "does not have")
        if self.not_applicable is not None:
            why = self.not_applicable(case, points)
            if why:
                return why
        if self.bounds_for is not None:
            try:
                self.bound_to(case, points)
            except ToothfemError as exc:
                return str(exc)
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

    def bound_to(self, case, points) -> Effect:
        """This effect with the bounds its physics puts on its parameters for this case and
        data (``bounds_for``; the effect itself where it has none).

        Parameters
        ----------
        case : toothfem.case.Case
            The case the effect would act on.
        points : Points
            The operating points.

        Returns
        -------
        Effect
            A copy whose parameters' bounds, typical values and starts (clipped into the
            bounds) are the case's and data's.
        """
        if self.bounds_for is None:
            return self
        params = []
        for p, (lo, hi, typ, *starts) in zip(self.parameters, self.bounds_for(case, points)):
            lo, hi = max(float(lo), p.lo), min(float(hi), p.hi)
            if not lo < hi:
                raise ToothfemError(f"{self.name}.{p.name}: no room for the parameter with "
                                    f"this case and data (bounds {lo:.4g} to {hi:.4g} "
                                    f"{p.unit})")
            starts = tuple(dict.fromkeys(min(hi, max(lo, float(s)))
                                         for s in (starts[0] if starts else p.starts)))
            params.append(dataclasses.replace(p, lo=lo, hi=hi, starts=starts,
                                              typical=float(typ)))
        return dataclasses.replace(self, parameters=tuple(params))

    @property
    def misreads_torque_only(self) -> bool:
        """Whether the effect only changes what the torque meters read: the model's
        evaluation does not depend on its values."""
        return (self.reading is not None and self.true_points is None
                and not self.case_fields)

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
            cache=None, memo=None) -> Prediction:
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
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        The loads the calling fit has met (each drive's table computed once for it).

    Returns
    -------
    Prediction
        Efficiency [-], output power and losses [W] at the points, and the model's notes.
    """
    assignment = assignment or {}
    prepared = {} if prepared is None else prepared
    model_case = case
    fields: list[tuple[str, tuple[float, ...]]] = []
    scale: dict[str, float] = {}
    for eff, values in assignment.items():
        if eff.route(case) != "model" or eff.misreads_torque_only:
            continue
        comp = eff.linear_component(case)
        if comp is not None:
            ref = eff.reference
            scale[comp] = scale.get(comp, 1.0) * float(values[0]) / ref[0]
            values = ref
        model_case = eff.apply(model_case, values)
        fields.append((eff.name, tuple(float(v) for v in values)))
    key = tuple(sorted(fields))
    ran = true_points(case, points, assignment)
    ev = None if cache is None else cache.get(key)
    if ev is None:
        ev = evaluate(model_case, ran.speed_rpm, ran.torque_Nm, ran.oil_temp_C, loads=loads,
                      memo=memo)
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
    eta = read(case, ran, p_out / (p_out + sum(losses.values())), assignment)
    return Prediction(eta, p_out, losses, ev.notes)


def true_points(case, points: Points, assignment) -> Points:
    """The operating points the reducer ran at: the data's columns with every misreading
    of ``assignment`` (``Effect.true_points``: a sensor's offset, a warm-up it did not see)
    undone.

    Parameters
    ----------
    case : toothfem.case.Case
        The case (its lubricant's reference temperature stands for a missing column).
    points : Points
        The points as the data give them.
    assignment : dict of Effect to sequence of float
        {Effect: values}.

    Returns
    -------
    Points
        The points as run (``points`` itself when no effect misreads them).
    """
    for eff, values in assignment.items():
        if eff.true_points is not None:
            points = eff.true_points(case, points, tuple(values))
    return points


def read(case, ran: Points, efficiency, assignment):
    """The efficiency as the rig's torque meters read it, T2_read / (|i| T1_read), from
    the reducer's own at the points it ran at (``Effect.reading``: a meter's zero offset).

    Parameters
    ----------
    case : toothfem.case.Case
        Gives the ratio i.
    ran : Points
        The points as run (:func:`true_points`).
    efficiency : numpy.ndarray
        (M,) the reducer's efficiency there.
    assignment : dict of Effect to sequence of float
        {Effect: values}.

    Returns
    -------
    numpy.ndarray
        (M,) the efficiency as read (``efficiency`` itself when no effect misreads it).
    """
    readers = [(e, v) for e, v in assignment.items() if e.reading is not None]
    if not readers:
        return efficiency
    i = abs(case.ratio())
    t2 = np.asarray(ran.torque_Nm, float)
    t1 = t2 / (i * efficiency)
    for eff, values in readers:
        t1, t2 = eff.reading(t1, t2, tuple(values))
    return t2 / (i * t1)


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
        A section's dataclass (e.g. :class:`toothfem.case_running.Friction`).
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
