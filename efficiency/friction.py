"""Tooth-contact friction laws for efficiency estimates.

Small pure functions, SI arguments, vectorised over numpy arrays (inputs broadcast;
all-scalar input gives float output).  Derivations, unit conversions and the sources
checked are in ``docs/derivations.md, section 4``.

Conventions used throughout
---------------------------
* ``E*`` (Johnson, *Contact Mechanics*, 1985): ``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2``;
  this is what :func:`reduced_modulus` returns and what :func:`hertz_line` takes.
* ``E' = 2 E*`` is the modulus of the EHL film formulas (Dowson-Higginson, Hamrock);
  :func:`central_film_thickness_line` and :func:`ehl_xu2007` take ``e_prime``.
  Steel on steel (E = 210 GPa, nu = 0.3): E* = 115 GPa, E' = 231 GPa.
* Velocities at the contact: surface speeds ``u1``, ``u2`` in the rolling direction;
  sliding ``vs = |u1 - u2|``; mean entraining velocity ``ve = (u1 + u2)/2``;
  slide-to-roll ratio ``SR = vs/ve = 2 (u1 - u2)/(u1 + u2)``; sum velocity
  ``v_sum = u1 + u2 = 2 ve`` (Benedict & Kelley use the sum, Xu and the EHL film
  formulas use the mean).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import check_range, checked_array as _array
from ..fem.hertz import float_or_array as _out
from ..units import CP_PER_PA_S, GPA_PER_PA, UM_PER_M

__all__ = [
    "XU2007_COEFFICIENTS",
    "MixedLubricationWarning",
    "FrictionExtrapolationWarning",
    "FrictionResult",
    "RQ_PER_RA",
    "composite_rms_roughness",
    "central_film_thickness_line",
    "minimum_film_thickness_line",
    "ehl_xu2007",
    "benedict_kelley",
    "coulomb",
]

#: Regression coefficients b1..b9 of Xu, Kahraman, Anderson & Maddock (2007), J. Mech.
#: Des. 129(1) 58-68, Eq. for mu(SR, Ph, nu0, S, Ve, R); values as reproduced with these
#: signs in public secondary sources (see docs/derivations.md, section 4).  The sine paper
#: (Lu & Xu 2024, Table 1) prints b1 without its minus sign and rounds to 3 decimals.
XU2007_COEFFICIENTS = (
    -8.916465,   # b1  constant in the exponent
    1.03303,     # b2  exponent of Ph [GPa]
    1.036077,    # b3  exponent of |SR|
    -0.354068,   # b4  coefficient of |SR| Ph log10(nu0)
    2.812084,    # b5  coefficient of exp(-|SR| Ph log10(nu0))
    -0.100601,   # b6  exponent of Ve [m/s]
    0.752755,    # b7  exponent of nu0 [cP = mPa s]
    -0.390958,   # b8  exponent of R [m]
    0.620305,    # b9  coefficient of exp(S), S [um]
)

#: Default full-film threshold on lambda = h_c / S.  Tallian (1972), as quoted by Arana,
#: Larranaga & Ulacia, Proc. IMechE J 233 (2019) 303: partial EHL for 0.5..1 < lambda
#: < 3..4; the lower end of the full-film bound is used.
LAMBDA_FULL_FILM = 3.0

#: Default pressure-viscosity coefficient [1/Pa]: 20 GPa^-1, typical of mineral gear
#: oils at moderate temperature (about 1e-8 .. 3e-8 1/Pa for mineral oils).
ALPHA_MINERAL_OIL = 2.0e-8

#: RMS roughness Rq per arithmetic mean roughness Ra of a ground or honed flank: 1.25
#: (Niemann, Winter & Hoehn, *Maschinenelemente* Bd. 1, 2005); a Gaussian height
#: distribution gives sqrt(pi/2) = 1.2533.
RQ_PER_RA = 1.25

#: E' = 2E* of steel on steel [Pa] (E = 210 GPa, nu = 0.3 both: E' = E/(1 - nu^2) = 230.8 GPa).
E_PRIME_STEEL = 2.3e11

# Benedict & Kelley (1961) constant 3.17e8 is for W [lbf/in], nu0 [cP], velocities [in/s].
_LBF = 4.4482216152605          # N per lbf (exact by definition)
_INCH = 0.0254                  # m per inch (exact)
_LBF_PER_IN = _LBF / _INCH      # N/m per lbf/in
_BK_CONSTANT_US = 3.17e8
#: The same constant for W [N/m], eta0 [Pa s], velocities [m/s]: 0.0296625 m^2/s^2.
BK_CONSTANT_SI = _BK_CONSTANT_US * _INCH**3 / (_LBF_PER_IN * CP_PER_PA_S)


class MixedLubricationWarning(UserWarning):
    """The film ratio lambda is below the full-film range a friction law assumes."""


class FrictionExtrapolationWarning(UserWarning):
    """A regression is evaluated where it gives an unphysical value (e.g. mu <= 0)."""


@dataclass(frozen=True)
class FrictionResult:
    """Result of an EHL friction law.

    ``mu``: friction coefficient [-]; ``film_ratio``: lambda = h_c / S [-] (inf for a
    smooth surface, NaN where unknown); ``film_thickness``: central film h_c [m].
    Floats for scalar input, numpy arrays otherwise.
    """

    mu: np.ndarray | float
    film_ratio: np.ndarray | float
    film_thickness: np.ndarray | float


# --------------------------------------------------------------------------- roughness

def composite_rms_roughness(ra1_m: float, ra2_m: float | None = None) -> float:
    """Composite RMS roughness sigma = sqrt(Rq1^2 + Rq2^2) of two surfaces [m], from their
    arithmetic mean roughness Ra through Rq = :data:`RQ_PER_RA` Ra.

    sigma is the roughness of the film parameter lambda = h/sigma (Tallian 1967; Hamrock,
    Schmid & Jacobson, *Fundamentals of Fluid Film Lubrication*, 2004), which
    :func:`ehl_xu2007` computes with the same S it feeds the regression of Xu, Kahraman,
    Anderson & Maddock (2007). The sources on Xu's S read here say "surface roughness, um"
    and no more (docs/derivations.md, section 4); Lu & Xu (2024) feed the Ra of the flank.
    Two flanks of Ra = 0.4 um give sigma = 0.707 um.

    Parameters
    ----------
    ra1_m : float
        Ra of the first surface [m], >= 0.
    ra2_m : float, optional
        Ra of the second surface [m], >= 0; None: the same as the first.

    Returns
    -------
    float
        sigma [m].

    Raises
    ------
    ToothfemError
        If an Ra is negative or not finite.
    """
    ra1 = float(check_range("ra1_m", ra1_m, 0.0, None))
    ra2 = ra1 if ra2_m is None else float(check_range("ra2_m", ra2_m, 0.0, None))
    return RQ_PER_RA * math.hypot(ra1, ra2)


# --------------------------------------------------------------------------- EHL film

def central_film_thickness_line(ve, eta0, r_eq, w_per_length, *, e_prime=E_PRIME_STEEL,
                                pressure_viscosity=ALPHA_MINERAL_OIL):
    """Central film thickness h_c [m] of an isothermal EHL line contact.

    Dowson & Toyoda (1979), "A central film thickness formula for elastohydrodynamic
    line contacts", Proc. 5th Leeds-Lyon Symp.; also in Hamrock, Schmid & Jacobson,
    *Fundamentals of Fluid Film Lubrication* (2004):
    ``h_c / R = 3.06 U^0.69 G^0.56 W^-0.10`` with ``U = eta0 ve / (E' R)``,
    ``G = alpha E'``, ``W = w / (E' R)``.
    Smooth surfaces, fully flooded, isothermal, Newtonian inlet; no thermal or
    starvation correction.

    Parameters
    ----------
    ve : array_like
        Mean entraining velocity (u1 + u2)/2 [m/s], > 0.
    eta0 : array_like
        Dynamic viscosity at inlet temperature and ambient pressure [Pa s], > 0.
    r_eq : array_like
        Equivalent radius [m], > 0.
    w_per_length : array_like
        Load per length [N/m], > 0.
    e_prime : array_like
        E' = 2 E* [Pa], default 2.3e11 (steel/steel).
    pressure_viscosity : array_like
        Barus alpha [1/Pa], default 2.0e-8 (mineral oil).

    Returns
    -------
    float or numpy.ndarray
        h_c [m], the broadcast shape (a float for scalar input).

    Raises
    ------
    ToothfemError
        Naming the first argument that is not positive and finite.
    """
    u = _array("ve", ve, 0.0, lo_open=True, why="mean entraining velocity [m/s]")
    eta = _array("eta0", eta0, 0.0, lo_open=True, why="dynamic viscosity [Pa s]")
    r = _array("r_eq", r_eq, 0.0, lo_open=True, why="equivalent radius [m]")
    w = _array("w_per_length", w_per_length, 0.0, lo_open=True, why="load per length [N/m]")
    ep = _array("e_prime", e_prime, 0.0, lo_open=True, why="E' = 2E* [Pa]")
    al = _array("pressure_viscosity", pressure_viscosity, 0.0, lo_open=True, why="alpha [1/Pa]")
    return _out(film_core(u, eta, r, w, ep, al))


def film_core(ve, eta0, r_eq, w_per_length, e_prime, pressure_viscosity):
    """:func:`central_film_thickness_line` of arguments already checked (positive and
    finite; broadcast together): the formula alone, for a caller that checked its inputs
    once (:func:`toothfem.efficiency.contact_friction.contact_mu`).

    Parameters
    ----------
    ve, eta0, r_eq, w_per_length, e_prime, pressure_viscosity : numpy.ndarray or float
        As :func:`central_film_thickness_line`'s.

    Returns
    -------
    numpy.ndarray or float
        h_c [m], the broadcast shape.
    """
    U = eta0 * ve / (e_prime * r_eq)
    G = pressure_viscosity * e_prime
    W = w_per_length / (e_prime * r_eq)
    return 3.06 * r_eq * U**0.69 * G**0.56 * W**-0.10


def minimum_film_thickness_line(ve, eta0, r_eq, w_per_length, *, e_prime=E_PRIME_STEEL,
                                pressure_viscosity=ALPHA_MINERAL_OIL):
    """Minimum film thickness h_min [m] of an EHL line contact (cross-check only).

    Dowson & Higginson, *Elastohydrodynamic Lubrication* (1977 SI ed.):
    ``h_min / R = 2.65 U^0.70 G^0.54 W^-0.13``; symbols, units and validity as in
    :func:`central_film_thickness_line`.

    Parameters
    ----------
    ve : array_like
        Mean entraining velocity [m/s], > 0.
    eta0 : array_like
        Inlet dynamic viscosity [Pa s], > 0.
    r_eq : array_like
        Equivalent radius [m], > 0.
    w_per_length : array_like
        Load per length [N/m], > 0.
    e_prime : array_like
        E' = 2 E* [Pa].
    pressure_viscosity : array_like
        Barus alpha [1/Pa].

    Returns
    -------
    float or numpy.ndarray
        h_min [m], the broadcast shape.

    Raises
    ------
    ToothfemError
        Naming the first argument that is not positive and finite.
    """
    u = _array("ve", ve, 0.0, lo_open=True, why="mean entraining velocity [m/s]")
    eta = _array("eta0", eta0, 0.0, lo_open=True, why="dynamic viscosity [Pa s]")
    r = _array("r_eq", r_eq, 0.0, lo_open=True, why="equivalent radius [m]")
    w = _array("w_per_length", w_per_length, 0.0, lo_open=True, why="load per length [N/m]")
    ep = _array("e_prime", e_prime, 0.0, lo_open=True, why="E' = 2E* [Pa]")
    al = _array("pressure_viscosity", pressure_viscosity, 0.0, lo_open=True, why="alpha [1/Pa]")
    U = eta * u / (ep * r)
    G = al * ep
    W = w / (ep * r)
    return _out(2.65 * r * U**0.70 * G**0.54 * W**-0.13)


# --------------------------------------------------------------------------- Xu 2007

def ehl_xu2007(ph, sr, ve, eta0, r, roughness, *, e_prime=E_PRIME_STEEL,
               pressure_viscosity=ALPHA_MINERAL_OIL, lambda_min=LAMBDA_FULL_FILM):
    """EHL friction coefficient of Xu, Kahraman, Anderson & Maddock (2007).

    Source: H. Xu, A. Kahraman, N.E. Anderson, D.G. Maddock, "Prediction of mechanical
    efficiency of parallel-axis gear pairs", J. Mech. Des. 129(1) (2007) 58-68 (from
    H. Xu, PhD thesis, Ohio State University, 2005), a multiple linear regression of
    full-film non-Newtonian thermal EHL predictions::

        mu = exp(f) * Ph^b2 * |SR|^b3 * Ve^b6 * nu0^b7 * R^b8
        f  = b1 + b4 |SR| Ph log10(nu0) + b5 exp(-|SR| Ph log10(nu0)) + b9 exp(S)

    in the regression's units Ph [GPa], Ve [m/s], nu0 [cP = mPa s], R [m], S [um];
    coefficients :data:`XU2007_COEFFICIENTS`.  Conversion from the SI arguments is done
    here.

    Trends built into the formula: mu rises with S (b9 > 0) and falls with Ve (b6 < 0).
    Validity: gear-like EHL conditions of the original simulations (pressures of order
    GPa, speeds of order m/s, one automotive gear oil); the exact regression ranges were
    not verified here.  Low speeds, low pressures or thin films are extrapolation.

    Parameters
    ----------
    ph : array_like
        Maximum Hertz pressure [Pa], > 0.
    sr : array_like
        Slide-to-roll ratio vs/ve = 2(u1-u2)/(u1+u2) [-], any finite value; its sign is
        ignored.  mu -> 0 as SR -> 0 (mu ~ |SR|^1.036), i.e. zero friction at the pitch
        point.
    ve : array_like
        Mean entraining velocity (u1 + u2)/2 [m/s], > 0.  (Primary text not read here;
        see docs.  Using the sum instead changes mu by 2^-0.1006, i.e. -6.7 %.)
    eta0 : array_like
        Dynamic viscosity at the inlet temperature, ambient pressure [Pa s], > 0.
    r : array_like
        Equivalent radius of curvature [m], > 0.
    roughness : array_like
        Composite RMS roughness S [m], >= 0.
    e_prime, pressure_viscosity : array_like
        E' = 2E* [Pa] and alpha [1/Pa] for the film ratio; the load per length follows
        from Hertz, ``w = pi ph^2 R / E* = 2 pi ph^2 R / E'``.
    lambda_min : array_like
        Full-film threshold on lambda = h_c/S [-] (default 3, Tallian 1972); a
        :class:`MixedLubricationWarning` is issued where lambda < lambda_min, since the
        regression describes full-film EHL only.

    Returns
    -------
    FrictionResult
        mu [-], film_ratio [-] and film_thickness [m], the broadcast shape.

    Raises
    ------
    ToothfemError
        Naming the first argument outside its range.
    """
    ph_a = _array("ph", ph, 0.0, lo_open=True, why="maximum Hertz pressure [Pa]")
    sr_a = _array("sr", sr, why="slide-to-roll ratio [-]")
    ve_a = _array("ve", ve, 0.0, lo_open=True, why="mean entraining velocity [m/s]")
    eta_a = _array("eta0", eta0, 0.0, lo_open=True, why="dynamic viscosity [Pa s]")
    r_a = _array("r", r, 0.0, lo_open=True, why="equivalent radius [m]")
    s_a = _array("roughness", roughness, 0.0, why="composite RMS roughness [m]")
    ep = _array("e_prime", e_prime, 0.0, lo_open=True, why="E' = 2E* [Pa]")
    lam_min = _array("lambda_min", lambda_min, 0.0, why="full-film threshold [-]")

    al = _array("pressure_viscosity", pressure_viscosity, 0.0, lo_open=True, why="alpha [1/Pa]")
    mu = xu2007_core(ph_a, sr_a, ve_a, eta_a, r_a, s_a)
    w = _array("w_per_length", hertz_load(ph_a, r_a, ep), 0.0, lo_open=True,
               why="load per length [N/m]")
    h_c = np.asarray(film_core(ve_a, eta_a, r_a, w, ep, al))
    with np.errstate(divide="ignore"):
        lam = np.where(s_a > 0.0, h_c / np.where(s_a > 0.0, s_a, 1.0), np.inf)
    low = lam < lam_min
    if np.any(low):
        warnings.warn(
            f"ehl_xu2007: film ratio lambda = h_c/S = {float(np.min(lam)):.3g} "
            f"(min over {int(np.count_nonzero(low))} of {low.size} points) is below "
            f"{float(np.max(lam_min)):g}; the Xu (2007) regression describes full-film EHL "
            "and is extrapolated in mixed/boundary lubrication",
            MixedLubricationWarning, stacklevel=2)
    shape = np.broadcast_shapes(mu.shape, lam.shape)
    mu = np.broadcast_to(mu, shape)
    return FrictionResult(mu=_out(mu), film_ratio=_out(np.broadcast_to(lam, shape)),
                          film_thickness=_out(np.broadcast_to(h_c, shape)))


def xu2007_core(ph, sr, ve, eta0, r, roughness):
    """:func:`ehl_xu2007`'s friction coefficient of arguments already checked (in their
    ranges; broadcast together): the regression alone, for a caller that checked its
    inputs once (:func:`toothfem.efficiency.contact_friction.contact_mu`).

    Parameters
    ----------
    ph, sr, ve, eta0, r, roughness : numpy.ndarray or float
        As :func:`ehl_xu2007`'s, SI.

    Returns
    -------
    numpy.ndarray or float
        mu [-], the broadcast shape.
    """
    b1, b2, b3, b4, b5, b6, b7, b8, b9 = XU2007_COEFFICIENTS
    # SI -> regression units
    p_gpa = ph * GPA_PER_PA
    nu_cp = eta0 * CP_PER_PA_S
    s_um = roughness * UM_PER_M
    a_sr = np.abs(sr)

    x = a_sr * p_gpa * np.log10(nu_cp)
    f = b1 + b4 * x + b5 * np.exp(-x) + b9 * np.exp(s_um)
    return np.exp(f) * p_gpa**b2 * a_sr**b3 * ve**b6 * nu_cp**b7 * r**b8


def hertz_load(ph, r, e_prime):
    """Load per length [N/m] of a Hertz line contact of peak pressure ``ph`` [Pa] and
    equivalent radius ``r`` [m]: w = pi ph^2 R / E* = 2 pi ph^2 R / E'.

    Parameters
    ----------
    ph, r, e_prime : numpy.ndarray or float
        Peak pressure [Pa], equivalent radius [m], E' = 2 E* [Pa].

    Returns
    -------
    numpy.ndarray or float
        w [N/m].
    """
    return 2.0 * math.pi * ph**2 * r / e_prime


# --------------------------------------------------------------------------- B & K

def benedict_kelley(w_per_length, vs, v_sum, eta0, roughness=None):
    """Benedict & Kelley (1961) instantaneous gear-tooth friction coefficient.

    Source: G.H. Benedict, B.W. Kelley, "Instantaneous coefficients of gear tooth
    friction", ASLE Trans. 4 (1961) 59-70.  Original (US customary) form::

        mu = 0.0127 * C_R * log10(3.17e8 * W / (nu0 * Vs * Vr^2))

    with W [lbf/in], nu0 [cP], Vs, Vr [in/s], Vr the SUM of the rolling velocities and
    C_R = 50 / (50 - S_avg), S_avg the average roughness [micro-inch].  In SI, with
    W [N/m], eta0 [Pa s], velocities [m/s], the constant is
    3.17e8 * 0.0254^3 / (175.1268 * 1000) = 0.029662 (29.66 if eta0 is in cP).
    Disc-machine correlation for mineral oils; a :class:`FrictionExtrapolationWarning`
    is issued where it gives mu <= 0 (log argument <= 1, i.e. very high speed or low
    load).

    Parameters
    ----------
    w_per_length : array_like
        Normal load per unit face width [N/m], > 0.
    vs : array_like
        Sliding speed |u1 - u2| [m/s], > 0 (mu -> infinity as vs -> 0: the formula is
        singular at the pitch point).
    v_sum : array_like
        Sum velocity u1 + u2 [m/s], > 0 (twice the mean entraining velocity).
    eta0 : array_like
        Dynamic viscosity at oil inlet temperature [Pa s], > 0.
    roughness : array_like, optional
        Average surface roughness S_avg [m], 0 <= S_avg < 50 micro-inch (1.27 um); None
        gives C_R = 1.

    Returns
    -------
    float or numpy.ndarray
        mu [-], the broadcast shape.

    Raises
    ------
    ToothfemError
        Naming the first argument outside its range.
    """
    w = _array("w_per_length", w_per_length, 0.0, lo_open=True, why="load per length [N/m]")
    v_s = _array("vs", vs, 0.0, lo_open=True, why="sliding speed [m/s]")
    v_r = _array("v_sum", v_sum, 0.0, lo_open=True, why="sum velocity u1+u2 [m/s]")
    eta = _array("eta0", eta0, 0.0, lo_open=True, why="dynamic viscosity [Pa s]")
    if roughness is None:
        c_r = 1.0
    else:
        s = _array("roughness", roughness, 0.0, hi=50.0 * 2.54e-8, hi_open=True,
                   why="average roughness [m], C_R = 50/(50 - S[micro-inch])")
        c_r = 50.0 / (50.0 - s / 2.54e-8)
    mu = 0.0127 * c_r * np.log10(BK_CONSTANT_SI * w / (eta * v_s * v_r**2))
    if np.any(mu <= 0.0):
        warnings.warn("benedict_kelley: mu <= 0 (log argument <= 1); the correlation "
                      "is outside its range", FrictionExtrapolationWarning, stacklevel=2)
    return _out(mu)


# --------------------------------------------------------------------------- Coulomb

def coulomb(mu):
    """Constant (Coulomb) friction law with the call shape of :func:`ehl_xu2007`.

    Parameters
    ----------
    mu : float
        The friction coefficient [-], in [0, inf).

    Returns
    -------
    callable
        ``law(ph, sr, ve, eta0, r, roughness, **kwargs)`` (all arguments optional and
        ignored except for their broadcast shape) that gives a :class:`FrictionResult`
        with ``mu`` everywhere and ``film_ratio``/``film_thickness`` NaN (unknown);
        ``coulomb(0.05)(...)``.

    Raises
    ------
    ToothfemError
        If ``mu`` is negative or not finite.
    """
    m = float(check_range("mu", mu, 0.0, None, why="Coulomb friction coefficient"))

    def law(*args, **kwargs):
        vals = [a for a in (*args, *kwargs.values()) if a is not None]
        shape = np.broadcast_shapes(*(np.shape(a) for a in vals)) if vals else ()
        return FrictionResult(mu=_out(np.full(shape, m)), film_ratio=_out(np.full(shape, np.nan)),
                              film_thickness=_out(np.full(shape, np.nan)))

    law.__doc__ = f"Coulomb friction law, mu = {m:g} (see toothfem.efficiency.friction.coulomb)."
    return law

