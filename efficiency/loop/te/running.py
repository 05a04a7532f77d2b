"""The datasheet a running TE rig gives without any model: rigidity and lost motion from the
hysteresis widths (docs/te_rig.md, "Running recordings").

Under a brake that opposes the motion, the output torque T twists the reducer one way when
it runs forward and the other way backward; the width w(T) = TE forward less TE backward is
twice the elastic twist plus what does not depend on the torque's size (play and friction):

    w(T) = 2 T / k + LM

so the slope of the widths against the torque over the linear part gives the rigidity k and
the intercept the lost-motion intercept LM (the width at zero torque the linear part
extrapolates to: play and friction; a catalogue's lost motion is read at +-3 % of the rated
torque on a staircase, which a running rig does not run). Near zero the contacts are not
all closed and the reducer is softer: the low-torque secant 2 T1 / (w(T1) - w(0)) between
the lowest two torques and the softening (how far the measured width at the lowest torque
lies below the line) say how much.

The linear part: the torques from :data:`LINEAR_FROM` of the largest one up (at least three
torques), fitted by weighted least squares with each width's sigma (the recordings' own
scatter, :func:`.observations.width_sigma`); the slope's and the intercept's standard errors
from the fit (scaled by the reduced chi-square where it exceeds one, as the scatter about
the line then says more than the sigmas).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ....errors import MeasuredDataError
from ....units import ARCMIN, ARCSEC
from .observations import width_sigma

#: The linear part of w(T) starts at this fraction of the largest torque recorded (the
#: catalogues' rigidity is read from 50 to 100 % of the rated torque; a running rig's
#: torques reach further down, and the contacts close well below a quarter of the rating).
LINEAR_FROM = 0.25
#: Torques the linear fit needs at least.
LINEAR_POINTS = 3
_ARCSEC_PER_ARCMIN = ARCMIN / ARCSEC


@dataclass(frozen=True, kw_only=True)
class RunningDatasheet:
    """The model-free reading of the widths (module docstring)."""
    rigidity_Nm_per_arcmin: float
    rigidity_sigma_Nm_per_arcmin: float
    lost_motion_intercept_arcmin: float
    lost_motion_intercept_sigma_arcmin: float
    low_torque_secant_Nm_per_arcmin: float   # between the two lowest torques; NaN: < 2
    softening_arcmin: float          # the line less the measured width at the lowest
                                     # torque (> 0: softer near zero than the line)
    lowest_width_arcmin: float       # the measured width at the lowest torque
    linear_from_Nm: float
    torques_Nm: tuple                # every torque with a width
    widths_arcmin: tuple
    sigmas_arcmin: tuple
    fitted: tuple                    # bool per torque: in the linear fit
    chi2_reduced: float

    def width_arcmin(self, torque_Nm) -> np.ndarray:
        """The line 2 T / k + LM [arcmin].

        Parameters
        ----------
        torque_Nm : array_like
            Output torque [N m].

        Returns
        -------
        numpy.ndarray
        """
        return 2 * np.asarray(torque_Nm, float) / self.rigidity_Nm_per_arcmin \
            + self.lost_motion_intercept_arcmin

    def summary(self) -> dict:
        """Plain JSON types.

        Returns
        -------
        dict
        """
        return {"rigidity_Nm_per_arcmin": self.rigidity_Nm_per_arcmin,
                "rigidity_sigma_Nm_per_arcmin": self.rigidity_sigma_Nm_per_arcmin,
                "lost_motion_intercept_arcmin": self.lost_motion_intercept_arcmin,
                "lost_motion_intercept_sigma_arcmin": self.lost_motion_intercept_sigma_arcmin,
                "low_torque_secant_Nm_per_arcmin": self.low_torque_secant_Nm_per_arcmin,
                "softening_arcmin": self.softening_arcmin,
                "lowest_width_arcmin": self.lowest_width_arcmin,
                "linear_from_Nm": self.linear_from_Nm,
                "torques_Nm": list(self.torques_Nm), "widths_arcmin": list(self.widths_arcmin),
                "sigmas_arcmin": list(self.sigmas_arcmin), "fitted": list(self.fitted),
                "chi2_reduced": self.chi2_reduced}

    def lines(self) -> list:
        """What a rig engineer reads first, one line each.

        Returns
        -------
        list of str
        """
        return [f"rigidity from the running widths: {self.rigidity_Nm_per_arcmin:.4g} "
                f"+- {self.rigidity_sigma_Nm_per_arcmin:.2g} N m/arcmin (w = 2 T / k + LM "
                f"from {self.linear_from_Nm:.4g} N m up)",
                f"lost-motion intercept (width at zero torque, play and friction): "
                f"{self.lost_motion_intercept_arcmin:.4g} +- "
                f"{self.lost_motion_intercept_sigma_arcmin:.2g} arcmin",
                f"width at {self.torques_Nm[0]:.4g} N m: "
                f"{self.lowest_width_arcmin:.4g} arcmin, {self.softening_arcmin:.3g} arcmin "
                "below the line (softer near zero); low-torque secant "
                f"{self.low_torque_secant_Nm_per_arcmin:.4g} N m/arcmin"]


def running_datasheet(torques_Nm, widths_arcsec, sigmas_arcsec) -> RunningDatasheet:
    """Rigidity and lost-motion intercept from hysteresis widths at several torques.

    Parameters
    ----------
    torques_Nm : sequence of float
        Output torque of each width (its size: the brake opposes the motion both ways).
    widths_arcsec : sequence of float
        Forward less backward mean TE [arcsec].
    sigmas_arcsec : sequence of float
        Each width's standard error [arcsec], > 0.

    Returns
    -------
    RunningDatasheet

    Raises
    ------
    MeasuredDataError
        Fewer than LINEAR_POINTS finite widths at distinct torques in the linear part, or a
        slope that is not positive (widths that do not grow with the torque).
    """
    t = np.abs(np.asarray(torques_Nm, float))
    w = np.asarray(widths_arcsec, float) / _ARCSEC_PER_ARCMIN
    s = np.asarray(sigmas_arcsec, float) / _ARCSEC_PER_ARCMIN
    ok = np.isfinite(t) & np.isfinite(w) & np.isfinite(s) & (s > 0)
    t, w, s = t[ok], w[ok], s[ok]
    order = np.argsort(t)
    t, w, s = t[order], w[order], s[order]
    if t.size == 0:
        raise MeasuredDataError("no hysteresis width with a torque and a sigma: no rigidity")
    start = LINEAR_FROM * float(t.max())
    lin = t >= start
    if np.unique(t[lin]).size < LINEAR_POINTS:
        raise MeasuredDataError(
            f"{np.unique(t[lin]).size} torques from {start:.4g} N m ({LINEAR_FROM:g} of the "
            f"largest) up: the rigidity needs {LINEAR_POINTS}")
    a = np.column_stack([2 * t[lin], np.ones(lin.sum())]) / s[lin, None]
    b = w[lin] / s[lin]
    (c, lm), *_ = np.linalg.lstsq(a, b, rcond=None)
    dof = max(int(lin.sum()) - 2, 1)
    chi2 = float(np.sum((a @ [c, lm] - b) ** 2) / dof)
    cov = np.linalg.inv(a.T @ a) * max(chi2, 1.0)
    if not c > 0:
        raise MeasuredDataError(
            f"the widths fall with the torque from {start:.4g} N m up (slope {2 * c:.3g} "
            "arcmin per N m): no rigidity (is the brake opposing the motion both ways?)")
    k = 1.0 / c
    secant = (2 * (t[1] - t[0]) / (w[1] - w[0]) if t.size >= 2 and w[1] > w[0]
              else math.nan)
    return RunningDatasheet(
        rigidity_Nm_per_arcmin=float(k),
        rigidity_sigma_Nm_per_arcmin=float(math.sqrt(cov[0, 0]) / c ** 2),
        lost_motion_intercept_arcmin=float(lm),
        lost_motion_intercept_sigma_arcmin=float(math.sqrt(cov[1, 1])),
        low_torque_secant_Nm_per_arcmin=float(secant),
        softening_arcmin=float(2 * t[0] * c + lm - w[0]), lowest_width_arcmin=float(w[0]),
        linear_from_Nm=float(start), torques_Nm=tuple(map(float, t)),
        widths_arcmin=tuple(map(float, w)), sigmas_arcmin=tuple(map(float, s)),
        fitted=tuple(map(bool, lin)), chi2_reduced=chi2)


def from_figures(figures) -> RunningDatasheet:
    """:func:`running_datasheet` of TE figures' conditions (their torques, widths and
    width sigmas: :func:`.observations.width_sigma`).

    Parameters
    ----------
    figures : toothfem.efficiency.loop.te.figures.TeFigures

    Returns
    -------
    RunningDatasheet
    """
    rows = [(c.condition.output_torque_Nm, c.width_arcsec, width_sigma(c, figures))
            for c in figures.conditions if c.condition.output_torque_Nm is not None]
    if not rows:
        raise MeasuredDataError("no TE condition has an output torque: no rigidity")
    return running_datasheet(*zip(*rows))


#: A model's reading misses the measured one when they differ by more than this many of
#: the measured reading's standard errors (3: a 0.3 % chance for a model that is right).
MISS_SIGMAS = 3.0


def misses(measured: RunningDatasheet, model: RunningDatasheet) -> list:
    """What the model's widths cannot reach, one line each (none when both readings agree
    within :data:`MISS_SIGMAS` standard errors): the rigidity and the lost-motion intercept
    the measured widths need against the model's, and by what factor or how much.

    Parameters
    ----------
    measured, model : RunningDatasheet

    Returns
    -------
    list of str
    """
    out = []
    k_m, k = measured.rigidity_Nm_per_arcmin, model.rigidity_Nm_per_arcmin
    if abs(k - k_m) > MISS_SIGMAS * measured.rigidity_sigma_Nm_per_arcmin:
        out.append(f"the widths need a rigidity of {k_m:.4g} N m/arcmin; the model after the "
                   f"loop gives {k:.4g}: its compliance would have to change by "
                   f"{k / k_m:.3g}x, which no fitted effect reaches")
    lm_m, lm = measured.lost_motion_intercept_arcmin, model.lost_motion_intercept_arcmin
    if abs(lm - lm_m) > MISS_SIGMAS * measured.lost_motion_intercept_sigma_arcmin:
        out.append(f"the widths need a lost-motion intercept of {lm_m:.4g} arcmin; the model "
                   f"after the loop gives {lm:.4g} ({lm_m - lm:+.3g} arcmin of play or "
                   "friction missing)")
    return out
