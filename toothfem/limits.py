"""Limits a result can pass, each with its source: one record for every warning a command
prints ("warning: ..."), writes to its JSON and to its report (issue 22). Computing only;
the commands write.

A limit passed is never an error: the figure is still computed, and the warning says the
value, the limit and where the limit comes from.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from .units import MPA_PER_PA

#: Film ratio lambda = h_c / S below which the asperities carry load: boundary
#: lubrication below 1, mixed to about 3 (Hamrock, Schmid & Jacobson, Fundamentals of Fluid
#: Film Lubrication, 2nd ed., 2004, Sec. 1.4: the regimes by the film parameter).
FILM_RATIO_BOUNDARY = 1.0
#: Below this the film carries next to nothing: the contact's friction is the boundary
#: coefficient's alone and the EHL law (Xu 2007, fitted for full films) says nothing of it
#: (docs/efficiency.md, the mixed-film blend: the asperities' share is then above 99 %).
FILM_RATIO_DRY = 0.1


@dataclass(frozen=True)
class Exceeded:
    """A value beyond its limit.

    ``quantity``: what it is (with where: "film ratio of the pin contacts"); ``value`` and
    ``limit`` in ``unit``; ``source``: where the limit comes from (a case key, a standard,
    a catalogue); ``lower``: the limit is a least value (film ratio, life, safety)."""
    quantity: str
    value: float
    limit: float
    unit: str
    source: str
    lower: bool = False

    def __str__(self) -> str:
        side = "below" if self.lower else "above"
        unit = f" {self.unit}" if self.unit else ""
        return (f"{self.quantity}: {self.value:.4g}{unit}, {side} the limit "
                f"{self.limit:.4g}{unit} ({self.source})")

    def as_dict(self) -> dict:
        """The record for JSON, with its one-line ``message``.

        Returns
        -------
        dict
        """
        return {**asdict(self), "message": str(self)}


def above(quantity: str, value, limit, unit: str, source: str) -> Exceeded | None:
    """An upper limit passed, or None (also when there is no limit).

    Parameters
    ----------
    quantity : str
    value, limit : float or None
    unit, source : str

    Returns
    -------
    Exceeded or None
    """
    return _passed(quantity, value, limit, unit, source, lower=False)


def below(quantity: str, value, limit, unit: str, source: str) -> Exceeded | None:
    """A lower limit not reached, or None (also when there is no limit).

    Parameters
    ----------
    quantity : str
    value, limit : float or None
    unit, source : str

    Returns
    -------
    Exceeded or None
    """
    return _passed(quantity, value, limit, unit, source, lower=True)


def _passed(quantity, value, limit, unit, source, lower) -> Exceeded | None:
    if limit is None or value is None or math.isnan(value):
        return None
    if (value >= limit) if lower else (value <= limit or math.isinf(value)):
        return None
    return Exceeded(quantity, float(value), float(limit), unit, source, lower=lower)


def film_ratio(where: str, lowest: float) -> list:
    """The film ratio's two limits (FILM_RATIO_BOUNDARY, FILM_RATIO_DRY): the lower one
    passed, if any.

    Parameters
    ----------
    where : str
        The contacts ("the pin contacts").
    lowest : float
        The least film ratio over them [-].

    Returns
    -------
    list of Exceeded
        At most one.
    """
    for limit, source in ((FILM_RATIO_DRY, "the film carries next to nothing: boundary "
                           "friction alone, outside the EHL law's range (docs/efficiency.md)"),
                          (FILM_RATIO_BOUNDARY, "boundary lubrication: the asperities carry "
                           "load (Hamrock, Schmid & Jacobson 2004, Sec. 1.4)")):
        hit = below(f"film ratio of {where}", lowest, limit, "", source)
        if hit is not None:
            return [hit]
    return []


def worst(found) -> tuple:
    """One record per quantity: the farthest beyond its limit (several members or points
    that pass the same limit say it once).

    Parameters
    ----------
    found : iterable of Exceeded

    Returns
    -------
    tuple of Exceeded
        In the order the quantities first appear.
    """
    out: dict[tuple[str, bool], Exceeded] = {}
    for e in found:
        k = (e.quantity, e.lower)
        if k not in out or (e.value < out[k].value if e.lower else e.value > out[k].value):
            out[k] = e
    return tuple(out.values())


def rated_torque(si, torque_Nm) -> list:
    """The output torque against the case's rated torque (``operating.rated_torque_Nm``)
    and its start/stop and momentary limits; a case that names no rating has no rated
    limit (its operating torque, which the datasheet then rates at, is not one).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    torque_Nm : float or array_like
        Output torque(s) [N m]; the largest magnitude is checked.

    Returns
    -------
    list of Exceeded
    """
    t = float(np.max(np.abs(np.atleast_1d(torque_Nm))))
    op = si.operating
    found = [above("output torque", t, op.rated_torque_Nm, "N m",
                   "operating.rated_torque_Nm, the reducer's rating"),
             above("output torque", t, op.start_stop_torque_Nm, "N m",
                   "operating.start_stop_torque_Nm, allowed only while starting and stopping"),
             above("output torque", t, op.momentary_torque_Nm, "N m",
                   "operating.momentary_torque_Nm, the momentary maximum: the reducer is "
                   "damaged above it")]
    return [h for h in found if h is not None]


def contact_pressure(where: str, ph_MPa: float, material) -> list:
    """A Hertz pressure against the material's allowable (contact fatigue) and, beyond
    it, its static capacity (permanent indentation: the elastic model no longer holds).

    Parameters
    ----------
    where : str
        Which contacts ("the pin contacts in the reducer").
    ph_MPa : float
        The largest P_h [MPa].
    material : toothfem.si.MaterialSI

    Returns
    -------
    list of Exceeded
    """
    found = [above(f"largest Hertz pressure P_h of {where}", ph_MPa,
                   material.allowable_contact_stress_Pa * MPA_PER_PA, "MPa",
                   "material.allowable_contact_stress_MPa, contact fatigue (ISO 281:2007)"),
             above(f"largest Hertz pressure P_h of {where}, beyond the static capacity "
                   "(permanent indentation; the elastic contact model does not hold there)",
                   ph_MPa, material.static_contact_stress_Pa * MPA_PER_PA, "MPa",
                   "material.static_contact_stress_MPa, static contact (ISO 76:2006)")]
    return [h for h in found if h is not None]


def case_temperature(si, drive, temperature_C) -> list:
    """The housing (case surface) temperature against its limit: the case's
    ``thermal.case_temperature_limit_C``, else the layout's default with its source
    (``Layout.case_temperature_limit_C``: a 2K-V drive's, Nabtesco's 60 C; a K-H-V or
    sine drive's, its nitrile seals' 100 C); none where a layout gives none.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    temperature_C : float or array_like
        The lumped heat balance's temperature (oil, parts and housing wall at one) [C];
        the largest is checked.

    Returns
    -------
    list of Exceeded
    """
    t = float(np.max(np.atleast_1d(temperature_C)))
    limit = None if si.thermal is None else si.thermal.case_temperature_limit_C
    source = "thermal.case_temperature_limit_C"
    if limit is None and drive.layout.case_temperature_limit_C is not None:
        limit = drive.layout.case_temperature_limit_C
        source = drive.layout.case_temperature_source
    hit = above("case (oil) temperature of the heat balance", t, limit, "C", source)
    return [hit] if hit else []


#: A measured efficiency farther than this from the model's at its point is warned
#: [percentage points]: twice the largest gap documented between a checked model and its
#: measurement (the RV paper's own model, 1.25 points from its rig; toothfem on the sine
#: prototype 0.07 points: docs/efficiency.md). Beyond it the model lacks an effect the rig
#: has (`toothfem loop` says what each would need to close it).
MEASURED_GAP_POINTS = 2.5


def measured_efficiency(measured, model) -> list:
    """Each measured efficiency of the case against the model's at its point.

    Parameters
    ----------
    measured : sequence of toothfem.case_running.MeasuredPoint
        The case's ``[[measured]]`` points.
    model : sequence of float
        The model's efficiency at each (analytic loads) [-].

    Returns
    -------
    list of Exceeded
        One per point whose gap passes :data:`MEASURED_GAP_POINTS`, the gap's sign and
        the point's source in its quantity.
    """
    found = []
    for m, eta in zip(measured, model):
        gap = 100 * (m.efficiency - float(eta))
        where = f"; {m.source}" if m.source else ""
        hit = above(f"gap of the measured efficiency {100 * m.efficiency:.2f} % "
                    f"({m.input_speed_rpm:g} rpm, {m.output_torque_Nm:g} N m{where}) to the "
                    f"model's {100 * float(eta):.2f} % (analytic loads): {gap:+.1f} points, "
                    "its size", abs(gap), MEASURED_GAP_POINTS, "points",
                    "twice the largest gap of a checked model to its measurement, "
                    "docs/efficiency.md; toothfem loop says what each effect would need")
        if hit:
            found.append(hit)
    return found


def contact_pressure_lines(material) -> list:
    """The contact-pressure limits a picture draws: the allowable (contact fatigue) and the
    static capacity, each with its value [MPa] and its source.

    Parameters
    ----------
    material : toothfem.si.MaterialSI

    Returns
    -------
    list of dict
        {"name", "value", "unit", "source"}.
    """
    return [{"name": "allowable", "value": material.allowable_contact_stress_Pa * MPA_PER_PA,
             "unit": "MPa", "source": "material.allowable_contact_stress_MPa"},
            {"name": "static capacity", "value": material.static_contact_stress_Pa * MPA_PER_PA,
             "unit": "MPa", "source": "material.static_contact_stress_MPa"}]


def run_warnings(contact: dict | None, efficiency: dict, durability: dict,
                 measured: Sequence = ()) -> list:
    """The one list of a run's warnings from its parts' summaries.

    Parameters
    ----------
    contact : dict or None
        The contact summary.
    efficiency : dict
        {source: efficiency summary}.
    durability : dict
        {"heat", "life", "strength"} summaries.
    measured : list of Exceeded
        The measured points' gaps to the model (:func:`measured_efficiency`).

    Returns
    -------
    list of str
        Each message once, in the order the parts ran; a message one part alone found
        (the efficiency's load sources, the heat balance's temperature, which differ)
        says whose it is; one that several parts found alike is said once, bare.
    """
    parts: dict[str, list] = {}          # message -> the parts that found it, in order
    found = [("", w["message"]) for w in (contact or {}).get("warnings", ())]
    for src, r in efficiency.items():
        found += [(f"efficiency ({src})", w["message"]) for w in r.get("warnings", ())]
    found += [("heat balance", w["message"])
              for w in durability.get("heat", {}).get("warnings", ())]
    found += [("", w["message"]) for w in durability.get("life", {}).get("warnings", ())]
    found += [("", w) for w in durability.get("strength", {}).get("warnings", ())]
    found += [("as built", w["message"])
              for w in (durability.get("as_built") or {}).get("warnings", ())]
    found += [("", str(w)) for w in measured]
    for part, message in found:
        parts.setdefault(message, []).append(part)
    # a message one part alone found says whose it is; one several parts found with the
    # same value (the operating point's torque above its rating) is the case's: once, bare
    return [f"{ps[0]}: {m}" if len(ps) == 1 and ps[0] else m for m, ps in parts.items()]


#: The warm-up's duration [h] (efficiency --thermal --duration-h): reducer housings warm up
#: with time constants of about an hour, so 100 h is steady state many times over; the
#: integration's steps grow with the duration (1000 h took 121 s, issue 45).
WARM_UP_H = (0.0, 100.0)
