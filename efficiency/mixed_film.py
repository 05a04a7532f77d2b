"""Mixed lubrication: the share of the load the asperities carry, and the friction it makes.

Load sharing (Johnson, Greenwood & Poon, "A simple theory of asperity contact in
elastohydrodynamic lubrication", Wear 19 (1972) 91-108): the load W of a contact is carried
partly by the fluid film, W_f = (1 - f) W, partly by the asperities, W_a = f W; the film
sets the separation of the mean planes, and it is the film of the load W_f it carries,
so its thickness is the smooth-surface value at W scaled by the film formula's load
exponent: h = h_c(W) (1 - f)^(-0.10) (Dowson & Toyoda 1979, h_c ~ W^-0.10).

Asperity load: engineering steel surfaces (ground, honed) touch plastically: Greenwood &
Williamson (Proc. R. Soc. A 295 (1966) 300-319) find their plasticity index
psi = (E*/H) sqrt(sigma_s/beta) above 1 for such surfaces, so the real contact area is
A_r = W_a / H (Bowden & Tabor, *The Friction and Lubrication of Solids*, 1950), with H
the hardness (flow pressure). With Gaussian heights of standard deviation sigma (the
composite roughness of the two flanks, Greenwood & Tripp 1970), the share of the nominal
area where the heights pass the separation h is the Abbott-Firestone bearing ratio
A_r/A = 1/2 erfc(lambda/sqrt(2)), lambda = h/sigma. Hence, over the nominal Hertz area
A = 2 b L with the mean pressure p_m = pi P_h / 4,

    f = min(1, (H / p_m) 1/2 erfc(lambda (1 - f)^-0.10 / sqrt(2)))

solved for f in [0, 1] (the right side falls as f grows: one root, by Newton). Friction
(the load-sharing concept of Johnson et al. 1972, as used by Castro & Seabra, Proc. IMechE
J 221 (2007) 399-411): mu = (1 - f) mu_EHL + f mu_b, mu_b the boundary coefficient of
lubricated steel (``friction.boundary_coefficient``, 0.1: Bowden & Tabor 1950).

What it gives: f = 1 (boundary friction) wherever lambda is below about 1-1.5 at gear and
pin pressures (Tallian's boundary regime, lambda < 1), f falling to about 1 % at lambda = 3
(the full-film bound): at P_h = 1 GPa and H = 6.9 GPa, f = 0.48 at lambda = 1.5, 0.18 at 2,
0.012 at 3. At low nominal pressure a few yielding asperities carry the whole load, so f
stays 1 to a larger lambda.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import erfc, erfcinv

#: Exponent of the load in the central film thickness (Dowson & Toyoda 1979:
#: h_c ~ W^-0.10), by which a film carrying (1 - f) W is thicker.
FILM_LOAD_EXPONENT = -0.10
#: Newton steps on the film's separation (safeguarded, quadratic once near the root; the
#: cap is never reached in practice) and the tolerance on G.
NEWTON_STEPS = 50
NEWTON_TOL = 1e-12
#: Bracket of the separation above the smooth film's, in standard deviations (the Gaussian
#: tail beyond 10 sigma is below 1e-23: the asperities carry nothing there).
SEPARATION_SPAN = 10.0
SQRT_2PI = math.sqrt(2.0 * math.pi)
#: A contact whose asperities carry the load with only this share left to the film is
#: taken as all asperity (f = 1; the film's share below it changes no loss visibly).
SATURATED = 1e-9


def bearing_ratio(lam):
    """Abbott-Firestone bearing ratio of a Gaussian surface: the share of the nominal area
    where the heights exceed lam standard deviations, 1/2 erfc(lam / sqrt(2)).

    Parameters
    ----------
    lam : array_like
        Separation of the mean planes in standard deviations of the composite roughness.

    Returns
    -------
    numpy.ndarray
        The share, in [0, 1].
    """
    return 0.5 * erfc(np.asarray(lam, float) / math.sqrt(2.0))


def asperity_load_share(lam, ph, hardness):
    """Share f of a line contact's load carried by plastically flattened asperities
    (module docstring: Johnson, Greenwood & Poon 1972 with Abbott-Firestone asperities).

    Parameters
    ----------
    lam : array_like
        Film ratio h_c/sigma of the smooth-surface film at the whole load (inf: no
        asperity contact).
    ph : array_like
        Maximum Hertz pressure [Pa] (> 0 where a contact is loaded).
    hardness : float
        Flow pressure of the softer surface [Pa] (Vickers hardness in Pa).

    Returns
    -------
    numpy.ndarray
        f in [0, 1], shape of the broadcast inputs (0 where ph <= 0 or lam is inf).
    """
    lam, ph = np.broadcast_arrays(np.asarray(lam, float), np.asarray(ph, float))
    out = np.zeros(lam.shape)
    active = (ph > 0) & np.isfinite(lam)
    ratio = hardness / (math.pi * ph[active] / 4.0)           # H / p_m
    lam_a = np.maximum(lam[active], 0.0)

    def rhs(f, lam_f, k):
        return np.minimum(1.0, k * bearing_ratio(lam_f * (1.0 - f) ** FILM_LOAD_EXPONENT))

    # asperities that carry all but SATURATED of the load even with that little film left
    full = rhs(1.0 - SATURATED, lam_a, ratio) >= 1.0
    share = np.ones(lam_a.shape)
    lam_r, ratio_r = lam_a[~full], ratio[~full]
    # and films so thick that the asperities' share is below SATURATED (f = its first order)
    first = rhs(0.0, lam_r, ratio_r)
    part = first >= SATURATED
    first[part] = _newton_share(lam_r[part], ratio_r[part], below=first[part] < 1.0)
    share[~full] = first
    out[active] = share
    return out


def _newton_share(lam, ratio, below=None):
    """The share f where f = k BR(lam (1 - f)^-0.1), solved for the film's separation
    x = lam (1 - f)^-0.1 instead (f = 1 - (lam/x)^10 is steep near 1 in f, smooth in x):
    G(x) = 1 - (lam/x)^10 - k BR(x) rises through 0 once between x = lam (G <= 0) and
    lam + SEPARATION_SPAN (G near 1). Newton from the left, at the larger of lam and
    BR^-1(1/k) (where G = -(lam/x)^10 <= 0), each step kept inside the bracket (bisecting
    where it leaves), until |G| < NEWTON_TOL (f to 1e-7 or better). ``below``: where
    k BR(lam) < 1 (BR^-1(1/k) is below lam there: the start is lam without the inverse),
    when the caller knows it.

    The contacts still stepping are kept together (those converged leave the arrays after
    their last step), so a step's work goes with the contacts it moves."""
    lo, hi = lam.copy(), lam + SEPARATION_SPAN
    x = lam.copy()
    need = np.ones(lam.size, bool) if below is None else ~below
    with np.errstate(invalid="ignore"):
        start = math.sqrt(2.0) * erfcinv(np.minimum(2.0 / ratio[need], 1.0))
    x[need] = np.clip(np.maximum(lam[need], start), lo[need], hi[need])
    todo = np.arange(lam.size)
    xt, lt, kt = x, lam, ratio
    for _ in range(NEWTON_STEPS):
        q = (lt / xt) ** 10
        g = 1.0 - q - kt * bearing_ratio(xt)
        left = g < 0
        lo = np.where(left, xt, lo)
        hi = np.where(left, hi, xt)
        slope = 10.0 * q / xt + kt * np.exp(-0.5 * xt * xt) / SQRT_2PI
        step = xt - g / slope
        xt = np.where((step >= lo) & (step <= hi), step, 0.5 * (lo + hi))
        going = np.abs(g) >= NEWTON_TOL
        if not going.all():
            x[todo[~going]] = xt[~going]          # converged: its last step taken
            todo, xt, lt, kt, lo, hi = (a[going] for a in (todo, xt, lt, kt, lo, hi))
        if todo.size == 0:
            break
    x[todo] = xt
    return 1.0 - (lam / x) ** 10


def mixed_friction(mu_ehl, share, boundary):
    """Friction of a contact in mixed lubrication, mu = (1 - f) mu_EHL + f mu_b (the
    load-sharing concept, Johnson, Greenwood & Poon 1972).

    Parameters
    ----------
    mu_ehl : array_like
        Friction of the fluid film (the EHL law).
    share : array_like
        f, the asperities' share of the load (:func:`asperity_load_share`).
    boundary : float
        mu_b, the boundary friction of the asperity contacts.

    Returns
    -------
    numpy.ndarray
        The friction coefficient.
    """
    share = np.asarray(share, float)
    return (1.0 - share) * np.asarray(mu_ehl, float) + share * boundary
