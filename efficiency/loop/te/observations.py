"""What a fit compares: the recordings' figures as rows of :class:`~.problem.Observations`,
and the model's recordings on the same rows (docs/te_rig.md, "The loop").

Rows, each with its own uncertainty from the recordings themselves:

- **the hysteresis loop**: the twist of each branch (rising, falling) at the staircase's
  torques (fractions of the rated torque, both signs) where the recording covers them,
  less the rows' mean (an encoder's zero is arbitrary); sigma from the scatter of the
  binned curve (the second differences' median absolute deviation, robust to the knee at
  zero torque), never below :data:`TWIST_SIGMA_FLOOR_ARCMIN`;
- **the TE ripple**: at each torque level, the amplitude at each named order (the drive's
  :meth:`~toothfem.fem.drives.base.Drive.te_orders` and their multiples) of the forward
  and backward spectra; the model's amplitude A is read as the amplitude a spectrum shows
  for A in its noise, sqrt(A^2 + s^2 pi / 2) (:func:`expected_amplitude`), sigma the
  noise's s (the spectrum's median amplitude away from the named orders / sqrt(2 ln 2),
  Rayleigh);
- **the hysteresis width** of the rotating TE at each torque level (forward less backward
  mean): sigma from the recordings' scatter (:func:`width_sigma`: between windows, within
  one, or the runs' level scatter about the offsets' fit), never an assumed floor.

The fold groups of the held-out error are the torque levels (hysteresis rows by |T|), so a
fold holds out whole torques.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .problem import Observations
from ....errors import MeasuredDataError

#: The loop's rows: these fractions of the rated torque, each sign, each branch (the
#: staircase's own fractions past the knee: lost motion at 3 %, the backlash fit to 10 %,
#: the rigidity's 50 and 100 %).
LOOP_FRACTIONS = (0.03, 0.1, 0.25, 0.5, 0.75, 1.0)
#: Floor of a loop row's sigma [arcmin]: 0.1 arcsec, a rig's encoder resolution (a 2^21
#: count encoder resolves 0.6 arcsec; averaging a bin resolves less, not nothing).
TWIST_SIGMA_FLOOR_ARCMIN = 0.1 / 60
#: Multiples of each named order fitted (the first two: a ripple's shape beyond them is
#: in the noise of a rig's spectrum).
ORDER_MULTIPLES = (1, 2)
#: Half-width of the search for a named order's bin [orders]: the spectrum's resolution is
#: 1/revolutions; a named order falls within half a bin of its own.
ORDER_SEARCH = 0.5
#: Rayleigh: the median of the amplitude of pure noise is s sqrt(2 ln 2), its mean
#: s sqrt(pi / 2) (s the standard deviation of each quadrature).
RAYLEIGH_MEDIAN = math.sqrt(2 * math.log(2))


@dataclass(frozen=True)
class Row:
    """What one observation is: its kind and where it is taken."""
    kind: str                 # "twist" | "amplitude" | "width"
    torque_Nm: float
    branch: int = 0           # twist: +1 rising, -1 falling
    order: float = 0.0        # amplitude: per output revolution
    direction: int = 0        # amplitude: +1 forward, -1 backward
    noise_arcsec: float = 0.0  # amplitude: the spectrum's s


@dataclass(frozen=True, kw_only=True)
class Layout:
    """The rows of a set of observations and how the model fills them."""
    rows: tuple               # Row
    te_torques_Nm: tuple      # the TE's torque levels the model must compute
    rated_torque_Nm: float
    loop_rows: np.ndarray     # indices of the twist rows (centred together)
    loop_mean_arcmin: float = 0.0   # the measured twist rows' mean, taken off them


def width_sigma(condition, te) -> float:
    """A width row's sigma [arcsec], from the recordings' own scatter: the larger of the
    condition's width sigma (its two levels' standard errors, between windows or within
    one: :func:`.figures.level_sigma`) and the runs' level scatter about the offsets' fit
    (which several runs of one condition show); NaN where neither is a positive number (the
    row is then left out, never weighed by an assumed floor).

    Parameters
    ----------
    condition : toothfem.efficiency.loop.te.figures.ConditionFigures
    te : toothfem.efficiency.loop.te.figures.TeFigures

    Returns
    -------
    float
    """
    found = [v for v in (condition.width_sigma_arcsec, te.level_scatter_arcsec)
             if math.isfinite(v) and v > 1e-9]
    return max(found) if found else math.nan


def expected_amplitude(a, s):
    """The mean amplitude a spectrum reads for a ripple of amplitude ``a`` in noise of
    quadrature standard deviation ``s``: the Rice distribution's mean, by its large- and
    small-amplitude limits joined (s sqrt(pi/2) at a = 0, sqrt(a^2 + s^2) for a >> s):
    sqrt(a^2 + s^2 pi / 2) (within 4 % of the exact mean everywhere).

    Parameters
    ----------
    a, s : float or array_like
        [arcsec].

    Returns
    -------
    numpy.ndarray
    """
    return np.sqrt(np.asarray(a, float) ** 2 + np.asarray(s, float) ** 2 * math.pi / 2)


def _curve(curves, branch: int, torque: float):
    """The measured twist of ``branch`` at ``torque`` [arcmin] from the binned flanks, and
    the flank's sigma; None outside the flank's bins."""
    flank = 1 if torque > 0 else -1
    for c in curves:
        if c.branch == branch and c.flank == flank and c.torque_Nm.size >= 3:
            t = np.asarray(c.torque_Nm, float)
            if not (t.min() <= torque <= t.max()):
                return None
            return float(np.interp(torque, t, c.twist_arcmin)), _scatter(c.twist_arcmin)
    return None


def _scatter(y) -> float:
    """The noise of a binned curve's values [its unit]: the second differences' median
    absolute deviation, 1.4826 MAD / sqrt(6) (white noise of variance v gives second
    differences of variance 6 v), at least the floor."""
    d2 = np.diff(np.asarray(y, float), 2)
    if d2.size < 3:
        return TWIST_SIGMA_FLOOR_ARCMIN
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return max(1.4826 * mad / math.sqrt(6), TWIST_SIGMA_FLOOR_ARCMIN)


def _noise_arcsec(spectrum, orders) -> float:
    """The quadrature noise s of a spectrum: its median amplitude away from the named orders
    and below the highest of them (orders 0.5 on), over the Rayleigh median factor."""
    q = spectrum.orders
    amp = np.asarray(spectrum.amplitude_arcsec, float)
    top = max(orders) * max(ORDER_MULTIPLES) + 1
    keep = (q >= 0.5) & (q <= top)
    for o in orders:
        for m in ORDER_MULTIPLES:
            keep &= np.abs(q - m * o) > 2 * spectrum.resolution_orders
    if not keep.any():
        return float("nan")
    return float(np.median(amp[keep])) / RAYLEIGH_MEDIAN


def _amplitude(spectrum, order: float) -> float | None:
    """The spectrum's largest amplitude within ORDER_SEARCH bins of ``order`` [arcsec];
    None beyond its Nyquist order."""
    q = spectrum.orders
    if order > q[-1]:
        return None
    near = np.abs(q - order) <= ORDER_SEARCH * spectrum.resolution_orders + 1e-12
    if not near.any():
        near = np.abs(q - order) == np.min(np.abs(q - order))
    return float(np.max(np.asarray(spectrum.amplitude_arcsec, float)[near]))


def observations(rated_torque_Nm: float, *, loop=None, te=None, orders=None):
    """The rows a fit compares, from the model-free figures.

    Parameters
    ----------
    rated_torque_Nm : float
        The loop's fractions are of it.
    loop : toothfem.efficiency.loop.te.hysteresis.HysteresisFigures, optional
        A hysteresis recording's figures (its binned branch curves).
    te : toothfem.efficiency.loop.te.figures.TeFigures, optional
        TE recordings' figures per condition (each condition's torque is needed).
    orders : dict, optional
        name -> order per output revolution (the drive's ``te_orders()``); needed with
        ``te``.

    Returns
    -------
    observations : Observations
    layout : Layout
        The rows, for :func:`model_rows`.

    Raises
    ------
    MeasuredDataError
        Where neither gives a row, or a TE condition has no torque.
    """
    values, sigma, group, labels, rows = [], [], [], [], []
    if loop is not None:
        for frac in LOOP_FRACTIONS:
            for sign in (1, -1):
                t = sign * frac * rated_torque_Nm
                for branch in (1, -1):
                    got = _curve(loop.curves, branch, t)
                    if got is None:
                        continue
                    values.append(got[0])
                    sigma.append(got[1])
                    group.append(f"loop {frac:g}")
                    labels.append(f"twist [arcmin], {'rising' if branch > 0 else 'falling'}"
                                  f" branch at {t:.4g} N m")
                    rows.append(Row(kind="twist", torque_Nm=t, branch=branch))
    torques = []
    if te is not None:
        if not orders:
            raise ValueError("orders: the drive's named orders are needed with TE figures")
        named = sorted(set(orders.values()))
        for c in te.conditions:
            t = c.condition.output_torque_Nm
            if t is None:
                raise MeasuredDataError(f"a TE condition has no output torque ({c.files}): "
                                        "the fit needs the torque of every recording")
            torques.append(abs(float(t)))
            for d in (c.forward, c.backward):
                if d is None or d.spectrum is None:
                    continue
                s = _noise_arcsec(d.spectrum, named)
                if not math.isfinite(s) or s <= 0:
                    continue
                for o in named:
                    for m in ORDER_MULTIPLES:
                        a = _amplitude(d.spectrum, m * o)
                        if a is None:
                            continue
                        values.append(a)
                        sigma.append(s)
                        group.append(f"te {abs(t):.6g}")
                        labels.append(f"TE amplitude [arcsec] at order {m * o:g} "
                                      f"({'forward' if d.direction > 0 else 'backward'}), "
                                      f"{abs(t):.4g} N m")
                        rows.append(Row(kind="amplitude", torque_Nm=abs(float(t)),
                                        order=m * o, direction=d.direction, noise_arcsec=s))
            s = width_sigma(c, te)
            if math.isfinite(c.width_arcsec) and math.isfinite(s):
                values.append(c.width_arcsec)
                sigma.append(s)
                group.append(f"te {abs(t):.6g}")
                labels.append(f"TE hysteresis width [arcsec], {abs(t):.4g} N m")
                rows.append(Row(kind="width", torque_Nm=abs(float(t))))
    if not rows:
        raise MeasuredDataError("no observation: the recordings cover none of the loop's "
                                "torques and hold no TE spectrum")
    loop_rows = np.array([i for i, r in enumerate(rows) if r.kind == "twist"], int)
    measured = np.array(values, float)
    loop_mean = float(measured[loop_rows].mean()) if loop_rows.size else 0.0
    measured[loop_rows] -= loop_mean
    obs = Observations(values=measured, sigma=np.array(sigma, float), group=np.array(group),
                       labels=tuple(labels), kinds=tuple(r.kind for r in rows))
    layout = Layout(rows=tuple(rows), te_torques_Nm=tuple(sorted(set(torques))),
                    rated_torque_Nm=float(rated_torque_Nm), loop_rows=loop_rows,
                    loop_mean_arcmin=loop_mean)
    return obs, layout


def model_rows(layout: Layout, recordings, *, centred: bool = True) -> np.ndarray:
    """The model's values on the layout's rows.

    Parameters
    ----------
    layout : Layout
    recordings : toothfem.efficiency.loop.te.model.ModelRecordings
        Its loop (when the layout has twist rows) and its TE at ``layout.te_torques_Nm``
        in that order.

    centred : bool
        The twist rows centred as the measured ones are (False: the model's own zero).

    Returns
    -------
    numpy.ndarray
        In the rows' units.
    """
    te = {round(t, 9): m for t, m in zip(layout.te_torques_Nm, recordings.te or ())}
    out = np.empty(len(layout.rows))
    loop = recordings.loop
    for i, r in enumerate(layout.rows):
        if r.kind == "twist":
            if r.branch > 0:
                t, th = loop.rising_torque_Nm, loop.rising_twist_arcmin
            else:
                t, th = loop.falling_torque_Nm, loop.falling_twist_arcmin
            order = np.argsort(t)
            out[i] = float(np.interp(r.torque_Nm, np.asarray(t)[order],
                                     np.asarray(th)[order]))
        elif r.kind == "amplitude":
            a = te[round(r.torque_Nm, 9)].amplitude_arcsec(r.order, r.direction)
            out[i] = float(expected_amplitude(a, r.noise_arcsec))
        else:
            out[i] = te[round(r.torque_Nm, 9)].width_arcsec
    if centred and layout.loop_rows.size:
        out[layout.loop_rows] -= out[layout.loop_rows].mean()
    return out
