"""Contact mechanics shared by the FE model and the efficiency model: the contact modulus
and Hertz's line contact (Johnson, *Contact Mechanics*, 1985). SI arguments, vectorised
over numpy arrays (all-scalar input gives float output).

Conventions: ``E*`` with ``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2`` is what
:func:`reduced_modulus` returns and :func:`hertz_line` takes; the EHL film formulas of
``toothfem.efficiency.friction`` take ``E' = 2 E*``.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import checked_array as _array


def float_or_array(x):
    """A writable float copy of ``x``: a float for scalar input, else an array.

    Parameters
    ----------
    x : array_like
        Any numbers.

    Returns
    -------
    float or numpy.ndarray
        The copy.
    """
    x = np.array(x, dtype=float)          # a writable copy (inputs may be broadcast views)
    return float(x) if x.ndim == 0 else x


def reduced_modulus(e1, nu1, e2, nu2):
    """Contact modulus E* [Pa] of two elastic bodies (Johnson 1985, Eq. 4.22/4.45).

    ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``.  Note: EHL film formulas use ``E' = 2 E*``.

    Parameters
    ----------
    e1, e2 : array_like
        Young's moduli [Pa], > 0.
    nu1, nu2 : array_like
        Poisson ratios [-] in (-1, 0.5].

    Returns
    -------
    float or numpy.ndarray
        E* [Pa], the broadcast shape (a float for scalar input).

    Raises
    ------
    ToothfemError
        Naming the first modulus or ratio outside its range.
    """
    e1 = _array("E1", e1, 0.0, lo_open=True, why="Young's modulus [Pa]")
    e2 = _array("E2", e2, 0.0, lo_open=True, why="Young's modulus [Pa]")
    nu1 = _array("nu1", nu1, -1.0, lo_open=True, hi=0.5, why="Poisson ratio")
    nu2 = _array("nu2", nu2, -1.0, lo_open=True, hi=0.5, why="Poisson ratio")
    return float_or_array(1.0 / ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2))


def hertz_line(w_per_length, r_eq, e_reduced):
    """Hertz line (2-D cylinder) contact: returns ``(p0, b)``.

    Johnson, *Contact Mechanics* (1985), Eq. 4.45:
    ``b = sqrt(4 w R / (pi E*))`` (semi-width, m) and ``p0 = 2 w / (pi b)
    = sqrt(w E* / (pi R))`` (peak pressure, Pa).
    Valid for elastic, frictionless, non-conforming contact with b << R.

    Parameters
    ----------
    w_per_length : array_like
        Load per unit contact length [N/m], > 0.
    r_eq : array_like
        Equivalent radius 1/R = 1/R1 + 1/R2 [m], > 0 (concave body: negative R2).
    e_reduced : array_like
        E* [Pa] from :func:`reduced_modulus` (not E' = 2E*).

    Returns
    -------
    p0 : float or numpy.ndarray
        Peak pressure [Pa], the broadcast shape.
    b : float or numpy.ndarray
        Semi-width [m], the broadcast shape.

    Raises
    ------
    ToothfemError
        Naming the first argument that is not positive and finite.
    """
    w = _array("w_per_length", w_per_length, 0.0, lo_open=True, why="load per length [N/m]")
    r = _array("r_eq", r_eq, 0.0, lo_open=True, why="equivalent radius [m]")
    e = _array("e_reduced", e_reduced, 0.0, lo_open=True, why="contact modulus E* [Pa]")
    b = line_half_width(w, r, e)
    p0 = 2.0 * w / (math.pi * b)
    return float_or_array(p0), float_or_array(b)


def line_half_width(w, r, e):
    """Hertz's semi-width ``b = sqrt(4 w R / (pi E*))`` [m] of :func:`hertz_line` on arrays
    already checked (the inner loop of the cycle solver's Hertz iteration).

    Parameters
    ----------
    w : numpy.ndarray
        Load per unit length [N/m].
    r : numpy.ndarray
        Equivalent radius [m].
    e : float or numpy.ndarray
        Contact modulus E* [Pa].

    Returns
    -------
    numpy.ndarray
        b [m], the broadcast shape.
    """
    return np.sqrt(4.0 * w * r / (math.pi * e))
