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

solved for f in [0, 1] (the right side falls as f grows: one root, by bisection). Friction
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
from scipy.special import erfc

#: Exponent of the load in the central film thickness (Dowson & Toyoda 1979:
#: h_c ~ W^-0.10), by which a film carrying (1 - f) W is thicker.
FILM_LOAD_EXPONENT = -0.10
#: Bisection steps on f in [0, 1] (2^-20: the share to 1e-6, far below any visible loss).
SHARE_BISECTION_STEPS = 20
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
    # and films so thick that the asperities' share is below SATURATED (f = its first order)
    first = rhs(0.0, lam_a, ratio)
    share = np.where(full, 1.0, first)
    part = ~full & (first >= SATURATED)
    lam_p, k_p = lam_a[part], ratio[part]
    lo, hi = np.zeros(lam_p.shape), np.ones(lam_p.shape)
    for _ in range(SHARE_BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        high = mid > rhs(mid, lam_p, k_p)
        hi = np.where(high, mid, hi)
        lo = np.where(high, lo, mid)
    share[part] = 0.5 * (lo + hi)
    out[active] = share
    return out


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
