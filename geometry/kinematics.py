"""The record that geometry hands to the contact and efficiency models.

`MeshingState` holds the kinematics of every candidate contact of a drive over a set of
meshing positions. Shapes: P positions, C candidate contacts per position (pins of a
cycloid drive, tooth pairs of a sine pair); points and normals are (P, C, 2).

Conventions (SI: m, rad, m/s):
- Frame: fixed to the stationary member (pin housing or ring gear), origin at its centre.
- ``position_rad``: the crank (eccentric, input) angle, counter-clockwise.
- ``normal``: unit normal at the contact, pointing from the stationary member into the
  moving member (disc or planet): the direction of a compressive contact force acting on
  the moving member.
- ``moment_arm``: signed moment arm of that normal about the moving member's centre,
  (point - centre) x normal; a force F along ``normal`` puts torque F*moment_arm on it.
- ``gap``: initial normal clearance before load (0 for exact conjugate contact).
- ``sliding_velocity``: tangential velocity of the moving member's surface minus the
  stationary member's surface at the contact (for rolling pins, the pin's surface).
- ``entrainment_velocity``: mean of the two surfaces' rolling speeds relative to the
  contact point, U = (u1 + u2)/2; ``slide_to_roll`` = sliding_velocity / U.
- Curvature radii are signed, positive where the surface is convex toward the other body;
  ``equivalent_radius`` R = 1/(1/r_moving + 1/r_fixed) (positive for a valid contact).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class MeshingState:
    drive: str                       # "cycloid" or "sine"
    position_rad: np.ndarray         # (P,)
    contact_id: np.ndarray           # (P, C) int: pin index or planet tooth index
    point: np.ndarray                # (P, C, 2) contact point, m
    normal: np.ndarray               # (P, C, 2) unit normal, fixed -> moving member
    centre: np.ndarray               # (P, 2) centre of the moving member, m
    moment_arm: np.ndarray           # (P, C) m
    pressure_angle: np.ndarray       # (P, C) rad
    gap: np.ndarray                  # (P, C) m
    sliding_velocity: np.ndarray     # (P, C) m/s
    entrainment_velocity: np.ndarray  # (P, C) m/s
    slide_to_roll: np.ndarray        # (P, C) -
    radius_moving: np.ndarray        # (P, C) m, signed
    radius_fixed: np.ndarray         # (P, C) m, signed
    equivalent_radius: np.ndarray    # (P, C) m
    crank_speed_rad_s: float

    @property
    def shape(self) -> tuple[int, int]:
        return self.moment_arm.shape


def equivalent_radius(r1, r2):
    """1/R = 1/r1 + 1/r2 for signed curvature radii (positive convex). Hertz line contact.

    Written with the curvatures, so that a flat body (r = inf, an inflection point of a
    profile) gives R = the other radius, not inf/inf = NaN (issue 14).

    Parameters
    ----------
    r1, r2 : array_like
        Signed curvature radii of the two bodies [m] (inf: flat).

    Returns
    -------
    numpy.ndarray
        Equivalent radius R [m], the broadcast shape.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        return 1.0 / (1.0 / np.asarray(r1, float) + 1.0 / np.asarray(r2, float))


def slide_to_roll(sliding, entrainment):
    """SR = v_s / U; where U = 0 (pure spin about the contact) SR is reported as inf.

    Parameters
    ----------
    sliding : array_like
        Sliding velocity v_s [m/s].
    entrainment : array_like
        Entrainment velocity U [m/s].

    Returns
    -------
    numpy.ndarray
        Slide-to-roll ratio [-] (0 where both are 0), the broadcast shape.
    """
    sliding = np.asarray(sliding, float)
    entrainment = np.asarray(entrainment, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        sr = np.where(entrainment != 0.0, sliding / np.where(entrainment != 0, entrainment, 1.0),
                      np.where(sliding == 0.0, 0.0, np.inf))
    return sr
