"""Archard wear of lubricated steel contacts: the volume law, the wear coefficient by
lubrication regime, the run-in of the roughness, and the conforming-contact (pin-on-disc)
hand model (docs/wear.md). SI units: m, N, Pa, m^3.

Archard's law (J.F. Archard, "Contact and rubbing of flat surfaces", J. Appl. Phys. 24
(1953) 981-988): the volume a surface loses sliding a distance s under a normal load F is

    V = K F s / H

with H the hardness (flow pressure) of the worn surface and K the dimensionless wear
coefficient. Written locally (the depth at a point of the surface): dh = K p ds / H, p
the local pressure and ds the sliding distance while the point is under the load. The
volume is exact for any pressure distribution; where the depth goes is the contact's
geometry.

The wear coefficient by regime: wear needs asperity contact, so K falls with the share of
the load the asperities carry, f (efficiency/mixed_film.py: Johnson, Greenwood & Poon 1972
with plastically flattened Gaussian asperities): K = K_b f(lambda, P_h, H). This is the
load-sharing wear model of M. Priest & C.M. Taylor ("Automobile engine tribology -
approaching the surface", Wear 241 (2000) 193-203): the boundary wear law applied to the
asperities' load. K_b, the boundary coefficient, is not known for a given reducer to
better than orders of magnitude: the mild wear of lubricated steel spans K = 1e-10 to 1e-6
by the film, the additives and the surfaces (I.M. Hutchings & P. Shipway, *Tribology*,
2nd ed., 2017, ch. 5), the dimensional coefficient k = K/H = 5.4e-16 m^2/N of A. Flodin &
S. Andersson ("Simulation of mild wear in spur gears", Wear 207 (1997) 16-23; K = 3.7e-6
at 700 HV) its upper end for gears in boundary lubrication. DEFAULT_K = 1e-8 is an
ASSUMPTION, the middle of the range (a rig's long-run data fits it: the loops' wear effect).
The regimes are named by the film ratio lambda = h_c/sigma
(Tallian): boundary below 1, mixed to 3, full film above (f < 1 % there).

Run-in: the asperity tips wear first, so the composite roughness falls as the worn depth
grows to the order of the roughness itself (the truncated-Gaussian picture of Y.-R. Jeng,
Z.-W. Lin & S.-H. Shyu, "Changes of surface topography during running-in process",
J. Tribol. 126 (2004) 620-625): sigma(h) = sigma_r + (sigma_0 - sigma_r) exp(-h/sigma_0);
the film ratio rises, f and K fall. In boundary lubrication (f = 1 whatever lambda) the
new surface still wears faster while its tips carry the load at their flow pressure over a
smaller real area: K(h) = K (1 + (R - 1) exp(-h/sigma_0)). RUN_IN_ROUGHNESS_RATIO
sigma_r/sigma_0 = 0.5 and RUN_IN_WEAR_RATIO R = 10 are ASSUMPTIONS (ground steel runs in
to 0.3-0.8 of its Rq in the source's data; R is the order of the ratio of the published RV
wear test's early and late rates, so the shape of that comparison is not independent).

The conforming contact (the pin-on-disc rig: a cylindrical pin of radius R, its axis along
the track, loaded against the disc; its tip always under the load): the pin wears flat,
the flat's width w(h) = max(2a, 2 sqrt(2 R h)) grows with the worn depth h (a the Hertz
half-width), the mean pressure F/(b w) falls, dh/ds = K F / (H b w(h)): the depth grows as
s^(2/3) once the flat is wider than the Hertz band (:func:`conforming_depth`). A contact
whose load moves over the worn surface (a disc's flank under its pins, a bearing race under
its rollers) loses the same volume per pass whatever its width (the pressure falls as the
band widens, the time under it grows alike): its depth is the volume over the area the
contact sweeps, with no conformity run-in.
"""
from __future__ import annotations

import math

import numpy as np

from .mixed_film import asperity_load_share
from ..errors import CaseError, check_range

#: Flodin & Andersson (1997): the dimensional wear coefficient k = K/H of hardened steel in
#: boundary-lubricated sliding [m^2/N] (their spur-gear mild-wear simulation).
FLODIN_K_M2_PER_N = 5.4e-16
#: The dimensionless coefficient's valid range (mild wear of lubricated steel 1e-10 to 1e-6,
#: module docstring; 0 switches wear off; above 1e-3 nothing mild is left).
K_RANGE = (0.0, 1e-3)
#: Film ratios bounding the regimes (Tallian: boundary below 1, full film from 3; the
#: friction model's LAMBDA_FULL_FILM).
LAMBDA_BOUNDARY, LAMBDA_FULL = 1.0, 3.0
REGIMES = ("boundary", "mixed", "full film")
#: ASSUMPTION: the run-in roughness as a share of the new (module docstring).
RUN_IN_ROUGHNESS_RATIO = 0.5
#: ASSUMPTION: a new surface's wear coefficient over its run-in one (module docstring).
RUN_IN_WEAR_RATIO = 10.0
#: ASSUMPTION: the default K_b of a grease- or oil-lubricated reducer's hardened steel
#: contacts (module docstring).
DEFAULT_K = 1e-8


def boundary_coefficient(hardness_Pa: float) -> float:
    """The default boundary wear coefficient K_b = k H (Flodin & Andersson's k).

    Parameters
    ----------
    hardness_Pa : float
        H [Pa].

    Returns
    -------
    float
        K_b [-] (3.7e-6 at 700 HV).
    """
    return FLODIN_K_M2_PER_N * float(hardness_Pa)


def check_coefficient(k: float, name: str = "wear_coefficient") -> float:
    """A wear coefficient within K_RANGE, else a CaseError naming it.

    Parameters
    ----------
    k : float
    name : str
        Its name in the message.

    Returns
    -------
    float
    """
    return float(check_range(name, k, *K_RANGE, error=CaseError,
                             why="Archard's dimensionless K (mild wear of lubricated steel "
                                 "1e-10 to 1e-6; 0: no wear)"))


def archard_volume(k, force_N, distance_m, hardness_Pa):
    """Archard's worn volume V = K F s / H.

    Parameters
    ----------
    k : array_like
        K [-].
    force_N, distance_m : array_like
        F [N], s [m].
    hardness_Pa : float
        H [Pa].

    Returns
    -------
    numpy.ndarray
        V [m^3].
    """
    return np.asarray(k, float) * np.asarray(force_N, float) * np.asarray(distance_m, float) \
        / float(hardness_Pa)


def regime(lam) -> np.ndarray:
    """The lubrication regime of each film ratio.

    Parameters
    ----------
    lam : array_like
        lambda = h_c / sigma [-].

    Returns
    -------
    numpy.ndarray of str
        One of REGIMES each.
    """
    lam = np.asarray(lam, float)
    return np.where(lam < LAMBDA_BOUNDARY, REGIMES[0],
                    np.where(lam < LAMBDA_FULL, REGIMES[1], REGIMES[2]))


def run_in_factor(depth_m, sigma0_m: float, ratio: float = RUN_IN_WEAR_RATIO):
    """The new surface's excess wear: K(h) = K (1 + (R - 1) exp(-h / sigma_0)), R the
    run-in ratio, falling to K once the pair has worn its asperities' height.

    Parameters
    ----------
    depth_m : array_like
        The pair's worn depth [m].
    sigma0_m : float
        Its new composite roughness [m], > 0.
    ratio : float
        R >= 1.

    Returns
    -------
    numpy.ndarray
        The factor on K [-].
    """
    h = np.maximum(np.asarray(depth_m, float), 0.0)
    return 1.0 + (ratio - 1.0) * np.exp(-h / sigma0_m)


def wear_coefficient(k_boundary: float, lam, ph_Pa, hardness_Pa: float) -> np.ndarray:
    """K by regime: K_b times the asperities' share of the load (Priest & Taylor 2000).

    Parameters
    ----------
    k_boundary : float
        K_b [-].
    lam : array_like
        Film ratio [-] (inf: no asperity contact).
    ph_Pa : array_like
        Peak Hertz pressure [Pa].
    hardness_Pa : float
        H [Pa].

    Returns
    -------
    numpy.ndarray
        K [-], the broadcast shape (K_b where lambda -> 0, -> 0 in full film).
    """
    return float(k_boundary) * asperity_load_share(lam, ph_Pa, hardness_Pa)


def run_in_roughness(sigma0_m: float, depth_m, ratio: float = RUN_IN_ROUGHNESS_RATIO):
    """The composite roughness after a worn depth (module docstring).

    Parameters
    ----------
    sigma0_m : float
        New composite RMS roughness [m], > 0.
    depth_m : array_like
        Worn depth of the pair [m], >= 0.
    ratio : float
        sigma_r / sigma_0, in (0, 1].

    Returns
    -------
    numpy.ndarray
        sigma [m].
    """
    h = np.maximum(np.asarray(depth_m, float), 0.0)
    return sigma0_m * (ratio + (1.0 - ratio) * np.exp(-h / sigma0_m))


def conforming_volume(depth_m, width_m: float, radius_m: float, half_width_m: float):
    """Volume worn off a cylindrical pin tip of radius R and width b down to a flat at
    depth h, the flat at least the Hertz band 2a wide (module docstring).

    Integrates dV = b w(h) dh, w(h) = max(2a, 2 sqrt(2 R h)): V = 2 a b h up to
    h_a = a^2 / (2 R), then V(h_a) + (4/3) b sqrt(2 R) (h^1.5 - h_a^1.5).

    Parameters
    ----------
    depth_m : array_like
        h [m], >= 0.
    width_m, radius_m, half_width_m : float
        b, R, a [m].

    Returns
    -------
    numpy.ndarray
        V [m^3].
    """
    h = np.maximum(np.asarray(depth_m, float), 0.0)
    ha = half_width_m ** 2 / (2.0 * radius_m)
    flat = 2.0 * half_width_m * width_m * np.minimum(h, ha)
    grown = (4.0 / 3.0) * width_m * math.sqrt(2.0 * radius_m) \
        * (np.maximum(h, ha) ** 1.5 - ha ** 1.5)
    return flat + grown


def conforming_depth(volume_m3, width_m: float, radius_m: float, half_width_m: float):
    """The worn depth of the conforming pin tip that has lost a volume: the inverse of
    :func:`conforming_volume` in closed form.

    Parameters
    ----------
    volume_m3 : array_like
        V [m^3], >= 0.
    width_m, radius_m, half_width_m : float
        b, R, a [m].

    Returns
    -------
    numpy.ndarray
        h [m].
    """
    v = np.maximum(np.asarray(volume_m3, float), 0.0)
    ha = half_width_m ** 2 / (2.0 * radius_m)
    va = 2.0 * half_width_m * width_m * ha
    below = v / (2.0 * half_width_m * width_m)
    above = (ha ** 1.5 + np.maximum(v - va, 0.0)
             / ((4.0 / 3.0) * width_m * math.sqrt(2.0 * radius_m))) ** (2.0 / 3.0)
    return np.where(v <= va, below, above)


def conforming_pressure(force_N: float, depth_m, width_m: float, radius_m: float,
                        half_width_m: float):
    """The mean pressure on the worn flat, F / (b w(h)): what falls as the contact
    conforms.

    Parameters
    ----------
    force_N : float
    depth_m : array_like
    width_m, radius_m, half_width_m : float

    Returns
    -------
    numpy.ndarray
        [Pa].
    """
    h = np.maximum(np.asarray(depth_m, float), 0.0)
    w = np.maximum(2.0 * half_width_m, 2.0 * np.sqrt(2.0 * radius_m * h))
    return float(force_N) / (width_m * w)


def integrate_conforming(k: float, force_N: float, distances_m, hardness_Pa: float,
                         width_m: float, radius_m: float, half_width_m: float) -> np.ndarray:
    """The conforming pin's depth at each sliding distance, stepped as the wear model
    steps its clearances: dh = K p(h) ds / H with the pressure at the step's midpoint
    (a predictor step, then the corrector: second order).

    Parameters
    ----------
    k : float
        K [-].
    force_N : float
    distances_m : array_like
        Increasing sliding distances [m], the first the start (depth 0).
    hardness_Pa, width_m, radius_m, half_width_m : float

    Returns
    -------
    numpy.ndarray
        h [m] at each distance.
    """
    s = np.asarray(distances_m, float)
    h = np.zeros(s.size)

    def rate(depth):
        return k * float(conforming_pressure(force_N, depth, width_m, radius_m,
                                             half_width_m)) / hardness_Pa

    for i in range(1, s.size):
        ds = s[i] - s[i - 1]
        mid = h[i - 1] + 0.5 * ds * rate(h[i - 1])
        h[i] = h[i - 1] + ds * rate(mid)
    return h
