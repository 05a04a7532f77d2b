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

import hashlib
import warnings

import numpy as np

from . import friction as fr
from ..limits import film_ratio
from .mixed_film import asperity_load_share, mixed_friction

#: Full-film bound of the EHL regression (friction.LAMBDA_FULL_FILM).
LAMBDA_FULL = fr.LAMBDA_FULL_FILM


#: Contacts (points x contacts) whose friction is worked out at a time: a block of the
#: (M, N) arrays small enough (32768 elements: 256 kB an array) to stay in the processor's
#: cache through the many array operations of the EHL law and the mixed film's Newton
#: steps, which on the whole arrays went to memory at each operation (each element is
#: computed alone: the result does not depend on the block).
BLOCK_ELEMENTS = 32768


def _ehl_block(ph, ve, vs, eta, r_eq, ok, sigma, e_prime, alpha, hardness):
    """The Xu (2007) friction, the film ratio and the asperities' share of a block of rows
    of :func:`contact_mu`'s arrays (0, inf and 0 where a contact is not loaded): ``eta``
    (B, 1), ``r_eq`` (1, N), the others (B, N). The law's arguments are checked here once
    (finite, positive); one out of its range goes through :func:`friction.ehl_xu2007`,
    which refuses it naming it."""
    mu = np.zeros(ph.shape)
    lam = np.full(ph.shape, np.inf)
    sr = np.where(ve > 0, vs / np.where(ve > 0, ve, 1.0), 0.0)
    every = bool(ok.all())    # every contact loaded: the arrays as they are, broadcast
    p, s, v, e, r = ((ph, sr, ve, eta, r_eq) if every else
                     (np.broadcast_to(a, ph.shape)[ok] for a in (ph, sr, ve, eta, r_eq)))
    w = fr.hertz_load(p, r, e_prime)
    if not all(np.all(np.isfinite(a)) for a in (p, s, v, e, r, w)) or np.any(e <= 0) \
            or np.any(r <= 0) or np.any(w <= 0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", fr.MixedLubricationWarning)
            p, s, v, e, r = (np.broadcast_to(a, ph.shape)[ok] for a in (ph, sr, ve, eta, r_eq))
            res = fr.ehl_xu2007(p, s, v, e, r, sigma, e_prime=e_prime,
                                pressure_viscosity=alpha)
        mu[ok], lam[ok] = res.mu, res.film_ratio
        return mu, lam, asperity_load_share(lam, ph, hardness)

    def put(a):               # the block's loaded contacts of a result
        return np.broadcast_to(a, ph.shape)[ok] if every else a

    mu[ok] = put(fr.xu2007_core(p, s, v, e, r, np.asarray(sigma)))
    if sigma > 0:
        lam[ok] = put(fr.film_core(v, e, r, w, e_prime, alpha) / sigma)
    return mu, lam, asperity_load_share(lam, ph, hardness)


def contact_mu(si, e_star_Pa, table, force, ph, crank_speed, eta0, notes, limits=None, *,
               memo=None):
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
    memo : toothfem.efficiency.mesh_table.LoadsMemo, optional
        Keeps the EHL law's friction, the film ratio and the asperities' share of these
        inputs for the calling computation's next evaluation (the same numbers).

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
    eta_col = (np.asarray(eta0, float)[:, None] if np.ndim(eta0) else
               np.full((force.shape[0], 1), float(eta0)))        # (M, 1)
    eta = np.broadcast_to(eta_col, force.shape)
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
    r_eq = np.asarray(table.r_eq, float)[None, :]
    sigma = fr.composite_rms_roughness(lub.roughness_Ra_m)
    law = (sigma, 2 * e_star_Pa, lub.pressure_viscosity_1_per_Pa, si.material.hardness_Pa)

    def film():
        mu, lam, share = np.zeros(force.shape), np.full(force.shape, np.inf), \
            np.zeros(force.shape)
        rows = max(1, BLOCK_ELEMENTS // max(1, force.shape[1]))
        for start in range(0, force.shape[0], rows):
            b = slice(start, start + rows)
            mu[b], lam[b], share[b] = _ehl_block(ph[b], ve[b], vs[b], eta_col[b], r_eq, ok[b],
                                                 *law)
        return mu, lam, share

    if memo is None:
        mu, lam, share = film()
    else:
        mu, lam, share = memo.film(_fingerprint(force, ph, crank_speed, eta_col, table, law),
                                   film)
        lam = lam.copy()       # the caller's, not the memo's
    if limits is not None and np.any(ok):
        limits.extend(film_ratio("the mesh contacts", float(np.min(lam[ok]))))
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
        return mu.copy(), lam
    return mixed_friction(mu, share, f.boundary_coefficient), lam


def _fingerprint(force, ph, crank_speed, eta, table, law):
    """A key of the contacts' inputs: SHA-256 digests of their bytes (3 ms for two
    (4913, 142) arrays) and the law's constants."""
    digest = hashlib.sha256()
    for a in (force, ph, crank_speed, eta, table.ve, table.vs, table.r_eq):
        a = np.ascontiguousarray(a, float)
        digest.update(repr(a.shape).encode())
        digest.update(a.data)
    return digest.hexdigest(), tuple(float(v) for v in law)


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
