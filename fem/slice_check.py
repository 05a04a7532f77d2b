"""Checks of the face-width slicing (fem/cycloid_fe/slices.py) on a crowned roller on a flat
under a tilt, where closed forms and a 3-D solution exist (docs/face_width.md,
"Verification"):

- Hertz's elliptic contact (Johnson 1985, Sec. 4.2): a circular crown of drop c over the
  length L is a second curvature radius R_y = L^2/(8c); under a tilt theta the crown's
  parabola only moves, by theta L^2/(8c) along the length, so while the ellipse stays on
  the roller its peak pressure is Hertz's and its centre sits there;
- the 3-D elastic half-space (Boussinesq; the uniform pressure on a rectangle, Love 1929),
  solved with the same complementarity solver (:func:`halfspace_roller`);
- the slices: :func:`toothfem.fem.cycloid_fe.slices.slice_solve`, the solver of the disc's
  slices, with each slice's law the half-space approach of a Hertz line pressure of its
  own line load over the whole length (:func:`roller_slice_law`: the per-length compliance
  the planar FE gives the disc's slices, here of the half-space), independent slices.
"""
from __future__ import annotations

import math

import numpy as np

from . import contact
from .cycloid_fe.slices import slice_solve

#: Points of the quadrature over the Hertz strip's width (x = b sin t, midpoint rule in t).
STRIP_POINTS = 400


def _corner(x, y):
    """The double antiderivative of 1/r: x asinh(y/|x|) + y asinh(x/|y|) (0 on the axes)."""
    ax, ay = np.abs(x), np.abs(y)
    a = np.where(ax > 0, x * np.arcsinh(y / np.where(ax > 0, ax, 1.0)), 0.0)
    b = np.where(ay > 0, y * np.arcsinh(x / np.where(ay > 0, ay, 1.0)), 0.0)
    return a + b


def halfspace_roller(radius, length, e_star, load, tilt, crown, nx=24, ny=60, x_max=None):
    """A crowned roller (circular crown) on a flat, both elastic half-spaces, under a normal
    load and a tilt: the 3-D contact pressure on a grid of uniform rectangles.

    Parameters
    ----------
    radius : float
        The roller's radius [m] (the equivalent radius across the contact).
    length : float
        Its length L [m].
    e_star : float
        The contact modulus E* [Pa].
    load : float
        The normal force [N].
    tilt : float
        The tilt [rad]: the gap grows by tilt * y along the length.
    crown : float
        The crown's drop at the ends [m].
    nx, ny : int
        Rectangles across and along.
    x_max : float, optional
        The grid's half-width across [m]; default 3.5 times the line contact's half-width.

    Returns
    -------
    x : numpy.ndarray, shape (nx,)
    y : numpy.ndarray, shape (ny,)
        The rectangles' centres [m].
    p : numpy.ndarray, shape (nx, ny)
        The pressure [Pa].
    """
    if x_max is None:
        x_max = 3.5 * math.sqrt(4 * load / length * radius / (math.pi * e_star))
    dx, dy = 2 * x_max / nx, length / ny
    x = -x_max + dx * (np.arange(nx) + 0.5)
    y = -length / 2 + dy * (np.arange(ny) + 0.5)
    gx, gy = (g.ravel() for g in np.meshgrid(x, y, indexing="ij"))
    rx, ry = gx[:, None] - gx[None, :], gy[:, None] - gy[None, :]
    a, b = dx / 2, dy / 2
    love = (_corner(rx + a, ry + b) - _corner(rx + a, ry - b) - _corner(rx - a, ry + b)
            + _corner(rx - a, ry - b))
    h = love / (math.pi * e_star * dx * dy)
    g0 = gx ** 2 / (2 * radius) + crown * (2 * gy / length) ** 2 + tilt * gy
    sol = contact.solve_contact(h, g0 - g0.min(), -np.ones(gx.size), load)
    return x, y, sol.force.reshape(nx, ny) / (dx * dy)


def roller_slice_law(radius, length, e_star, y):
    """Each slice's local law: the half-space approach at (0, y_s) under a Hertz line
    pressure of the slice's line load over the whole length, per line load.

    Parameters
    ----------
    radius, length, e_star : float
        As :func:`halfspace_roller`.
    y : numpy.ndarray, shape (S,)
        The slices' centres [m].

    Returns
    -------
    callable
        lam (S, 1) [N/m] -> (S, 1) [m per N/m] (an unloaded slice: at the mean line load).
    """
    t = -math.pi / 2 + math.pi * (np.arange(STRIP_POINTS) + 0.5) / STRIP_POINTS
    ys = np.asarray(y, float)[:, None]

    def law(lam):
        lam = np.asarray(lam, float)
        w = np.where(lam > 0, lam, max(float(np.mean(lam[lam > 0])) if np.any(lam > 0)
                                       else 1.0, 1e-9))[:, 0]
        b = np.sqrt(4 * w * radius / (math.pi * e_star))[:, None]
        x = np.abs(b * np.sin(t))[None] if b.ndim == 1 else np.abs(b * np.sin(t))
        k = np.arcsinh((length / 2 - ys) / x) + np.arcsinh((length / 2 + ys) / x)
        # p dx = p0 cos^2 t b dt, p0 b = 2 w / pi: per unit w the weights 2/pi cos^2 t dt
        per_w = np.sum(np.cos(t) ** 2 * k, axis=1) * (2 / math.pi) * (math.pi / STRIP_POINTS)
        return (per_w / (math.pi * e_star))[:, None]
    return law


def sliced_roller(radius, length, e_star, load, tilt, crown, slices):
    """The roller of :func:`halfspace_roller` in independent slices, solved by the disc's
    slice solver.

    Parameters
    ----------
    radius, length, e_star, load, tilt, crown : float
        As :func:`halfspace_roller`.
    slices : int

    Returns
    -------
    y : numpy.ndarray, shape (S,)
        The slices' centres [m].
    w : numpy.ndarray, shape (S,)
        Their line loads [N/m].
    ph : numpy.ndarray, shape (S,)
        Hertz's peak pressure of each slice's line load [Pa].
    """
    y = -length / 2 + length / slices * (np.arange(slices) + 0.5)
    g0 = crown * (2 * y / length) ** 2 + tilt * y
    lam, _, _ = slice_solve(np.zeros((1, 1)), roller_slice_law(radius, length, e_star, y),
                            (g0 - g0.min())[:, None], np.array([-1.0]), load / length)
    w = lam[:, 0]
    return y, w, np.sqrt(w * e_star / (math.pi * radius))
