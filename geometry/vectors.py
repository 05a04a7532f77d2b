"""Plane-vector helpers shared by the profiles and the FE models.

Shape convention (as everywhere in ``toothfem.geometry``): a point or vector is stacked on
the FIRST axis, shape ``(2, ...)`` with ``v[0]`` = x and ``v[1]`` = y; the trailing axes
are any batch shape and broadcast between arguments. (The ``MeshingState`` and
``LoadSharing`` records store points the other way round, ``(..., 2)``; move the axis,
``np.moveaxis(p, -1, 0)``, before calling these.) Angles are in radians,
counter-clockwise from the x-axis.
"""
from __future__ import annotations

import numpy as np


def unit(angle_rad):
    """Unit vector u(a) = (cos a, sin a).

    Parameters
    ----------
    angle_rad : array_like, shape (...)
        Angle(s) a from the x-axis (rad).

    Returns
    -------
    numpy.ndarray, shape (2, ...)
    """
    return np.stack([np.cos(angle_rad), np.sin(angle_rad)])


def dot(a, b):
    """Scalar product a . b = a_x b_x + a_y b_y.

    Parameters
    ----------
    a, b : array_like, shape (2, ...)
        The two vectors (symmetric); their trailing axes broadcast.

    Returns
    -------
    numpy.ndarray, shape (...)
    """
    return a[0] * b[0] + a[1] * b[1]


def cross(a, b):
    """z-component of a x b (a_x b_y - a_y b_x): positive when b lies counter-clockwise of a.

    Parameters
    ----------
    a, b : array_like, shape (2, ...)
        First and second factor (the order sets the sign); trailing axes broadcast.

    Returns
    -------
    numpy.ndarray, shape (...)
        |a| |b| sin(angle from a to b).
    """
    return a[0] * b[1] - a[1] * b[0]


def perp(v):
    """k x v: v turned counter-clockwise by 90 degrees, (-v_y, v_x).

    Parameters
    ----------
    v : array_like, shape (2, ...)

    Returns
    -------
    numpy.ndarray, shape (2, ...)
    """
    return np.stack([-v[1], v[0]])


def rotate(v, angle_rad):
    """R(a) v: v turned counter-clockwise by ``angle_rad``.

    Parameters
    ----------
    v : array_like, shape (2, ...)
        Vectors or points (a point turns about the origin).
    angle_rad : array_like, shape broadcasting with (...)
        Rotation angle(s) a (rad).

    Returns
    -------
    numpy.ndarray, shape (2, ...) (the broadcast shape of v[0] and the angle)
    """
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])
