"""The TE ripple's spectrum in orders of the output revolution, and its peaks named.

:func:`te_spectrum` takes one sweep (output angle, TE), unwraps the angle, puts the samples
on a uniform angle grid over the largest whole number R of output revolutions the sweep
covers, by a cubic spline through the samples (a rig's encoder samples in time, so the
angle steps are not even; the grid has the recording's own density, and a spline's error
falls as the fourth power of the samples per ripple cycle, where a straight line between
samples loses 4 % of an order sampled 8.5 times a cycle at uneven steps), removes the mean
and (from two revolutions on) a drift, the straight line through the means of each
revolution (a thermal drift would leak into the low orders; a line fitted to the samples
themselves would take a share of every ripple), applies the window and takes the FFT.
The orders are k / R: the **resolution is 1/R of an order** (one revolution: whole orders
only), up to the Nyquist order, half the samples per revolution. The amplitude is
single-sided and window-corrected: a ripple A sin(q phi) at an order q on the grid reads A
in its bin. An order sampled fewer than about 8 times a cycle reads low by the spline's
error (at uneven steps 8 % at 2.6 samples a cycle).

Windows (:data:`WINDOWS`): ``"hann"`` (default) keeps the leakage of an order off the grid
(an RV drive's input revolution order i is not always whole, 36.57 for i = 36.57) within
two bins either side, so the power summed over those five bins over the window's
equivalent noise bandwidth (1.5 bins) is A^2 whatever the order's place between bins;
it needs two tones 2/R orders apart to tell them apart (Zc = 39 and Zp = 40 need R >= 2).
``"rect"`` (no window) resolves tones one bin apart (R = 1 tells 39 from 40): every bin above
the noise floor is a peak, exact for the orders on the grid (whole orders over whole
revolutions, the orders of a K-H-V drive); an order off the grid leaks into its neighbours
and far (-36 % in its nearest bin at half a bin off) and shows as several peaks.

A spectrum's peaks (:func:`find_peaks`) are the local maxima of the power over the window's
lobe (+-2 bins Hann; rect: each bin) at least :data:`PEAK_FLOOR_FACTOR` times the median
amplitude (the noise floor); each peak's amplitude is sqrt(lobe power / ENBW) and its order
the power centroid of the lobe (better than the resolution for a peak above the noise).
:func:`name_peaks` labels a peak with every named order (``{name: order}``, e.g. a drive's
:meth:`~toothfem.fem.drives.base.Drive.te_orders`) whose multiple m x order (m = 1 to
:data:`MAX_MULTIPLE`) lies within the tolerance of the peak's order, the nearest first.

Spectra of several sweeps of one condition and direction (:func:`combine_spectra`) are
power-averaged on the coarsest grid among them (a finer spectrum's power summed into the
coarse bins, which keeps each tone's total power), so sweeps of different lengths combine.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ....errors import MeasuredDataError
from ....units import ARCSEC

#: window -> (equivalent noise bandwidth [bins], half-width of the lobe a tone's power is
#: summed over [bins]): periodic Hann (ENBW 1.5; 99.9 % of a tone's power within +-2 bins
#: wherever it falls between bins), rectangular (ENBW 1; its own bin: a tone on the grid
#: is in one bin, and its neighbour one bin on may be another tone).
WINDOWS = {"hann": (1.5, 2), "rect": (1.0, 0)}
#: Orders kept of each spectrum by default: above the mesh order Zp Zc of common cycloid
#: stages (40 x 39 = 1560) and their first-stage mesh; a sweep sampled more coarsely keeps
#: up to its Nyquist order.
DEFAULT_MAX_ORDER = 2000.0
#: Fewest samples per output revolution of the uniform grid (the recording's own density is
#: used when it is higher).
MIN_SAMPLES_PER_REVOLUTION = 8
#: A peak is a lobe maximum at least this many times the median amplitude of the spectrum
#: (the noise floor): for Gaussian noise the amplitude is Rayleigh-distributed and a bin of
#: noise alone exceeds 5 x its median with probability 2^-25 (3e-8), so a spectrum of
#: 10^5 bins shows no false peak in 300.
PEAK_FLOOR_FACTOR = 5.0
#: Most peaks kept (the largest), enough for the named orders and their multiples.
MAX_PEAKS = 40
#: A peak is named by a named order (or a multiple) within this many orders: the centroid
#: of a lobe above the noise is within a few hundredths of an order of its tone; 0.2 keeps
#: orders one apart (Zc = 39, Zp = 40) distinct.
NAMING_TOLERANCE_ORDERS = 0.2
#: ... but never less than this fraction of the spectrum's resolution (1 / revolutions), so
#: that a one-revolution spectrum, whose peaks sit on whole orders, still names an order
#: that falls between them.
NAMING_TOLERANCE_RESOLUTION = 0.5
#: Multiples of a named order labelled (2x, 3x, 4x): the harmonics of a profile or pitch
#: error that are usually above the noise of a TE rig.
MAX_MULTIPLE = 4
#: A sweep must cover this many whole output revolutions for a spectrum.
MIN_REVOLUTIONS = 1


@dataclass(frozen=True, kw_only=True)
class Spectrum:
    """Single-sided amplitude spectrum of the TE over whole output revolutions (bin k at
    order k / revolutions)."""
    amplitude_arcsec: np.ndarray    # (K,) window-corrected (a ripple on the grid reads its
                                    # amplitude in its bin); float32 to keep many
    revolutions: int                # whole output revolutions of each transform (combined:
                                    # the coarsest)
    samples_per_revolution: int     # of the uniform grid (combined: the fewest)
    window: str
    sweeps: int = 1                 # sweeps power-averaged into it
    mean_arcsec: float = math.nan   # mean TE over the whole revolutions of the uniform
                                    # grid (whole orders integrate out exactly); combined:
                                    # the mean of the sweeps' means

    @property
    def orders(self) -> np.ndarray:
        """(K,) order of each bin [per output revolution]: k / revolutions."""
        return np.arange(self.amplitude_arcsec.size) / self.revolutions

    @property
    def resolution_orders(self) -> float:
        """Spacing of the orders [-]: 1 / revolutions."""
        return 1.0 / self.revolutions

    @property
    def nyquist_order(self) -> float:
        """Highest order the grid resolves [-]: samples per revolution / 2."""
        return 0.5 * self.samples_per_revolution

    @property
    def enbw_bins(self) -> float:
        """The window's equivalent noise bandwidth [bins]."""
        return WINDOWS[self.window][0]


@dataclass(frozen=True, kw_only=True)
class Peak:
    """A spectral peak and the named orders it matches, the nearest first."""
    order: float                    # power centroid of the lobe [per output revolution]
    amplitude_arcsec: float         # sqrt(lobe power / ENBW)
    names: tuple = ()               # labels ("pin passing (Zp)", "2x lobe passing (Zc)")
    offsets_orders: tuple = ()      # peak order less each match's order, same order as names

    @property
    def name(self) -> str:
        """The labels joined by " / "; "" when the peak matches no named order."""
        return " / ".join(self.names)


def _check_window(window: str) -> None:
    if window not in WINDOWS:
        raise MeasuredDataError(f"window = {window!r} is not one of {sorted(WINDOWS)}")


def te_spectrum(angle_rad, te_rad, *, max_order: float = DEFAULT_MAX_ORDER,
                window: str = "hann", detrend: bool = True) -> Spectrum:
    """The spectrum of one sweep over its whole output revolutions (module docstring).

    Parameters
    ----------
    angle_rad : array_like, shape (N,)
        Output angle [rad], in the order recorded; rising or falling (a backward sweep),
        wrapped at a full turn or not; the steps need not be even.
    te_rad : array_like, shape (N,)
        Transmission error [rad].
    max_order : float
        Orders kept, up to this (and the grid's Nyquist order).
    window : {"hann", "rect"}
        :data:`WINDOWS`.
    detrend : bool
        Remove a drift first (from two revolutions on): the least-squares line through the
        means of each revolution; the mean is always removed.

    Returns
    -------
    Spectrum

    Raises
    ------
    MeasuredDataError
        For fewer than MIN_REVOLUTIONS whole revolutions, mismatched or non-finite input,
        or an unknown window.
    """
    _check_window(window)
    a = np.asarray(angle_rad, float).ravel()
    y = np.asarray(te_rad, float).ravel()
    if a.shape != y.shape or a.size < 2:
        raise MeasuredDataError(f"angle and TE must be two arrays of one length >= 2 (have "
                                f"{a.size} and {y.size})")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(y))):
        raise MeasuredDataError("angle and TE must be finite")
    a = np.unwrap(a)
    x = a - a[0]
    if x[-1] < 0:                                   # a backward sweep: its own sense
        x = -x
    x, inverse = np.unique(x, return_inverse=True)  # sorted; a repeated angle: the mean
    if x.size < y.size:
        y = np.bincount(inverse, y) / np.bincount(inverse)
    if x.size < 4:
        raise MeasuredDataError(f"the sweep has {x.size} distinct angles; a spectrum needs 4")
    x0 = x[0]
    # a sweep sampled every step over whole turns ends a step short of them (0 to 359.9 deg
    # at 0.1 deg is one revolution): its span plus one step is what it covers
    step = float(np.median(np.diff(x)))
    turns = int(math.floor((x[-1] - x0 + step) / (2 * math.pi) + 1e-9))
    if turns < MIN_REVOLUTIONS:
        raise MeasuredDataError(f"the sweep covers {(x[-1] - x0 + step) / (2 * math.pi):.3g} "
                                f"output "
                                f"revolutions; a spectrum needs {MIN_REVOLUTIONS} whole")
    inside = int(np.searchsorted(x, x0 + turns * 2 * math.pi, side="right"))
    per_rev = max(MIN_SAMPLES_PER_REVOLUTION, int(round(inside / turns)))
    n = turns * per_rev
    grid = x0 + np.arange(n) * (2 * math.pi / per_rev)
    u = CubicSpline(x, y)(grid)
    mean = float(u.mean())
    u = u - mean
    if detrend and turns >= 2:
        # the drift: a line through the means of each revolution (whole orders cancel in
        # them; a line fitted to the samples would take a share of every ripple, which
        # leaks as a sawtooth into the low orders)
        rev = np.arange(turns) - 0.5 * (turns - 1)
        slope = np.dot(rev, u.reshape(turns, per_rev).mean(axis=1)) / np.dot(rev, rev)
        u = u - slope * ((np.arange(n) - 0.5 * (n - 1)) / per_rev)
    w = _window(window, n)
    spec = np.abs(np.fft.rfft(u * w)) * (2.0 / w.sum())
    spec[0] *= 0.5
    keep = np.arange(spec.size) / turns <= max_order
    return Spectrum(amplitude_arcsec=(spec[keep] / ARCSEC).astype(np.float32),
                    revolutions=turns, samples_per_revolution=per_rev, window=window,
                    mean_arcsec=mean / ARCSEC)


def _window(window: str, n: int) -> np.ndarray:
    """The periodic window of n samples (a whole number of revolutions: periodic, not
    symmetric, so that a ripple on the grid falls in one bin and its two neighbours)."""
    if window == "rect":
        return np.ones(n)
    return 0.5 - 0.5 * np.cos(2 * math.pi * np.arange(n) / n)


def combine_spectra(spectra) -> Spectrum:
    """Power average of spectra of one condition and direction on the coarsest grid among
    them (a finer spectrum's power summed into the coarse bins k/R_c +- 1/(2 R_c)).

    Parameters
    ----------
    spectra : sequence of Spectrum
        One window; at least one.

    Returns
    -------
    Spectrum
        ``sweeps`` the total of theirs; up to the smallest highest order among them.

    Raises
    ------
    MeasuredDataError
        For no spectrum or mixed windows.
    """
    spectra = list(spectra)
    if not spectra:
        raise MeasuredDataError("no spectrum to combine")
    windows = {s.window for s in spectra}
    if len(windows) > 1:
        raise MeasuredDataError(f"spectra of different windows ({sorted(windows)}) cannot "
                                "be combined")
    if len(spectra) == 1:
        return spectra[0]
    turns = min(s.revolutions for s in spectra)
    top = min((s.amplitude_arcsec.size - 1) / s.revolutions for s in spectra)
    size = int(math.floor(top * turns + 1e-9)) + 1
    power = np.zeros(size)
    weight = 0
    for s in spectra:
        p = np.asarray(s.amplitude_arcsec, float) ** 2
        if s.revolutions == turns:
            power += s.sweeps * p[:size]
        else:
            j = np.rint(np.asarray(s.orders) * turns).astype(int)
            ok = j < size
            power += s.sweeps * np.bincount(j[ok], p[ok], minlength=size)[:size]
        weight += s.sweeps
    return Spectrum(amplitude_arcsec=np.sqrt(power / weight).astype(np.float32),
                    revolutions=turns,
                    samples_per_revolution=min(s.samples_per_revolution for s in spectra),
                    window=spectra[0].window, sweeps=weight,
                    mean_arcsec=float(np.mean([s.mean_arcsec for s in spectra])))


def find_peaks(spectrum: Spectrum, *, floor_factor: float = PEAK_FLOOR_FACTOR,
               max_peaks: int = MAX_PEAKS, min_amplitude_arcsec: float = 0.0) -> tuple:
    """The spectrum's peaks above its noise floor (module docstring).

    Parameters
    ----------
    spectrum : Spectrum
    floor_factor : float
        A peak is at least this many times the median amplitude.
    max_peaks : int
        The largest this many are kept.
    min_amplitude_arcsec : float
        Nor smaller than this [arcsec].

    Returns
    -------
    tuple of Peak
        By order, unnamed.
    """
    amp = np.asarray(spectrum.amplitude_arcsec, float)
    if amp.size < 3:
        return ()
    power = amp ** 2
    enbw, half = WINDOWS[spectrum.window]
    floor = float(np.median(amp[1:]))
    threshold = max(floor_factor * floor, min_amplitude_arcsec)
    padded = np.concatenate([np.zeros(half), power, np.zeros(half)])
    peaks = []
    for k in np.flatnonzero(amp >= threshold):
        if k == 0:
            continue                                # the mean: removed, not a ripple
        lobe = padded[k:k + 2 * half + 1]           # bins k - half .. k + half
        if not (power[k] >= lobe.max() and power[k] > lobe[:half].max(initial=0.0)):
            continue
        lo, hi = max(k - half, 1), min(k + half, amp.size - 1)
        p = power[lo:hi + 1]
        total = float(p.sum())
        order = float(np.dot(np.arange(lo, hi + 1), p) / total) / spectrum.revolutions
        peaks.append(Peak(order=order, amplitude_arcsec=math.sqrt(total / enbw)))
    peaks.sort(key=lambda pk: -pk.amplitude_arcsec)
    return tuple(sorted(peaks[:max_peaks], key=lambda pk: pk.order))


def naming_tolerance(spectrum: Spectrum, tolerance_orders: float = NAMING_TOLERANCE_ORDERS
                     ) -> float:
    """The tolerance a spectrum's peaks are named within.

    Parameters
    ----------
    spectrum : Spectrum
    tolerance_orders : float
        The stated tolerance [orders].

    Returns
    -------
    float
        max(tolerance_orders, NAMING_TOLERANCE_RESOLUTION x resolution) [orders].
    """
    return max(float(tolerance_orders), NAMING_TOLERANCE_RESOLUTION * spectrum.resolution_orders)


def name_peaks(peaks, named_orders: dict, *, tolerance_orders: float = NAMING_TOLERANCE_ORDERS,
               max_multiple: int = MAX_MULTIPLE) -> tuple:
    """Label each peak with the named orders (and multiples) it matches.

    Parameters
    ----------
    peaks : sequence of Peak
    named_orders : dict of str to float
        name -> order per output revolution (> 0).
    tolerance_orders : float
        A match lies within this many orders of the peak's order (see
        :func:`naming_tolerance` for a spectrum's).
    max_multiple : int
        Multiples 1 to this are tried; the label of m > 1 is ``"{m}x {name}"``.

    Returns
    -------
    tuple of Peak
        The peaks with ``names`` and ``offsets_orders`` filled, the nearest match first.

    Raises
    ------
    MeasuredDataError
        For an order that is not a positive number.
    """
    named = {}
    for name, q in (named_orders or {}).items():
        try:
            q = float(q)
        except (TypeError, ValueError):
            q = math.nan
        if not (math.isfinite(q) and q > 0):
            raise MeasuredDataError(f"named order {name!r} = {named_orders[name]!r} must be "
                                    "a positive number")
        named[str(name)] = q
    out = []
    for pk in peaks:
        found = []
        for name, q in named.items():
            for m in range(1, int(max_multiple) + 1):
                off = pk.order - m * q
                if abs(off) <= tolerance_orders:
                    found.append((abs(off), name if m == 1 else f"{m}x {name}", off))
        found.sort()
        out.append(Peak(order=pk.order, amplitude_arcsec=pk.amplitude_arcsec,
                        names=tuple(f[1] for f in found),
                        offsets_orders=tuple(f[2] for f in found)))
    return tuple(out)


def named_peaks(spectrum: Spectrum, named_orders: dict | None = None, *,
                tolerance_orders: float = NAMING_TOLERANCE_ORDERS,
                max_multiple: int = MAX_MULTIPLE, **peak_options) -> tuple:
    """:func:`find_peaks` then :func:`name_peaks` within :func:`naming_tolerance`.

    Parameters
    ----------
    spectrum : Spectrum
    named_orders : dict of str to float, optional
        name -> order; None: the peaks unnamed.
    tolerance_orders : float
        The stated tolerance [orders].
    max_multiple : int
        As :func:`name_peaks`.
    **peak_options
        Go to :func:`find_peaks`.

    Returns
    -------
    tuple of Peak
    """
    peaks = find_peaks(spectrum, **peak_options)
    if not named_orders:
        return peaks
    return name_peaks(peaks, named_orders,
                      tolerance_orders=naming_tolerance(spectrum, tolerance_orders),
                      max_multiple=max_multiple)


def drive_orders(drive) -> dict:
    """The named orders of a drive (its :meth:`~toothfem.fem.drives.base.Drive.te_orders`).

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
        E.g. ``drive_for(load_case("cases/rv40e.toml"))``.

    Returns
    -------
    dict of str to float
        name -> order per output revolution.
    """
    return dict(drive.te_orders())
