"""Friction at the tooth/pin contacts of a meshing table, and the loss it causes.

Each loaded contact gets its own coefficient from ``friction.mesh_law``: the EHL regression
of Xu, Kahraman, Anderson & Maddock (J. Mech. Des. 129 (2007) 58-68) at its own load, Hertz
pressure, sliding and entraining speed and radius (default); Coulomb; Benedict & Kelley
(1961). With the EHL law, the asperities carry the share f of each contact's load that
the film cannot (:mod:`.mixed_film`: the load sharing of Johnson, Greenwood & Poon 1972
with plastically flattened Gaussian asperities), at the boundary friction
``friction.boundary_coefficient`` (0.1 for lubricated steel, Bowden & Tabor 1950):
mu = (1 - f) mu_EHL + f mu_b.
"""
from __future__ import annotations

import warnings

import numpy as np

from . import friction as fr
from ..limits import film_ratio
from .mixed_film import asperity_load_share, mixed_friction

#: Full-film bound of the EHL regression (friction.LAMBDA_FULL_FILM).
LAMBDA_FULL = fr.LAMBDA_FULL_FILM


def contact_mu(si, e_star_Pa, table, force, ph, crank_speed, eta0, notes, limits=None):
    """Friction coefficient at each loaded contact, and the film ratio.

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Friction laws and lubricant.
    e_star_Pa : float
        Contact modulus E* of the pair (E' = 2 E* in the film formula).
    table : toothfem.efficiency.mesh_table.MeshTable
    force, ph : numpy.ndarray
        (M, N) contact forces [N] and Hertz pressures [Pa] at the M operating points.
    crank_speed : numpy.ndarray
        (M,) crank speed relative to the fixed member [rad/s].
    eta0 : float or numpy.ndarray
        Inlet dynamic viscosity [Pa s], scalar or (M,).
    notes : list of str
        Notes about the validity of the laws are appended here.
    limits : list, optional
        The film ratio's limits passed (:func:`toothfem.limits.film_ratio`) are appended
        here.

    Returns
    -------
    mu, lam : numpy.ndarray
        (M, N) friction coefficient and film ratio (inf where not computed).
    """
    f = si.friction
    lub = si.lubricant
    ve = table.ve[None, :] * crank_speed[:, None]
    vs = table.vs[None, :] * crank_speed[:, None]
    lam = np.full(force.shape, np.inf)
    if f.mesh_law == "coulomb":
        return np.where(force > 0, f.coefficient, 0.0), lam
    mu = np.zeros(force.shape)
    ok = (force > 0) & (ve > 0) & (ph > 0)
    eta = np.broadcast_to(np.asarray(eta0, float)[:, None] if np.ndim(eta0) else eta0,
                          force.shape)
    if f.mesh_law == "benedict_kelley":
        w = force / table.face_width
        with np.errstate(divide="ignore", invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mu[ok] = fr.benedict_kelley(w[ok], vs[ok], 2 * ve[ok], eta[ok],
                                        lub.roughness_Ra_m)
        neg = ok & ~(mu > 0)
        if np.any(neg):      # the log term of B-K turns negative at low load and speed
            notes.append(f"Benedict-Kelley gives mu <= 0 at {int(neg.sum())} contact(s) "
                         "(outside its range): taken as 0")
            mu[neg] = 0.0
        return mu, lam
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fr.MixedLubricationWarning)
        sr = np.where(ve > 0, vs / np.where(ve > 0, ve, 1.0), 0.0)
        res = fr.ehl_xu2007(ph[ok], sr[ok], ve[ok], eta[ok],
                            np.broadcast_to(table.r_eq, force.shape)[ok],
                            fr.composite_rms_roughness(lub.roughness_Ra_m),
                            e_prime=2 * e_star_Pa,
                            pressure_viscosity=lub.pressure_viscosity_1_per_Pa)
    mu[ok] = res.mu
    lam[ok] = res.film_ratio
    if limits is not None and np.any(ok):
        limits.extend(film_ratio("the mesh contacts", float(np.min(lam[ok]))))
    share = asperity_load_share(lam, ph, si.material.hardness_Pa)
    low = np.isfinite(lam) & (lam < LAMBDA_FULL)
    if np.any(low):
        carried = float(np.sum(share * force) / np.sum(force))
        notes.append(f"film ratio lambda < {LAMBDA_FULL:g} at {100 * low.mean():.0f} % of the "
                     f"loaded contacts (min {lam[ok].min():.2g}): mixed lubrication; the "
                     f"asperities carry {100 * carried:.0f} % of the contact load"
                     + (f" at the boundary friction {f.boundary_coefficient:g}, the film the "
                        "rest at the Xu (2007) friction" if f.boundary_coefficient > 0 else
                        "; friction.boundary_coefficient = 0: the Xu (2007) law alone, "
                        "extrapolated"))
    # friction.boundary_coefficient = 0 switches the blend off: the EHL law alone (a test
    # oracle's reading, and the model before issue 13), not frictionless asperities
    if f.boundary_coefficient <= 0:
        return mu, lam
    return mixed_friction(mu, share, f.boundary_coefficient), lam


def sliding_loss(table, force, mu, crank_speed):
    """Cycle-mean friction loss sum mu F |v_s| over the period [W].

    Parameters
    ----------
    table : toothfem.efficiency.mesh_table.MeshTable
        The N loaded contacts (sliding speed at unit crank speed).
    force : numpy.ndarray, shape (M, N)
        Contact forces [N].
    mu : numpy.ndarray, shape (M, N)
        Friction coefficients [-].
    crank_speed : numpy.ndarray, shape (M,)
        Crank speed relative to the fixed member [rad/s].

    Returns
    -------
    numpy.ndarray, shape (M,)
        Loss [W].
    """
    vs = table.vs[None, :] * crank_speed[:, None]
    return np.sum(mu * force * vs, axis=1) / table.n_positions
