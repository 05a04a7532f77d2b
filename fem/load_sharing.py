"""The load-sharing record, and the seeds' analytic load split that returns it too.

`LoadSharing` is what the efficiency model consumes: per meshing position and candidate
contact, the normal force, contact point, moment arm, Hertz half-width and pressure, and the
remaining gap; per position, the transmission error. The FE contact model (cycle and
detailed modes) and the analytic split of the seeds return the same type, so the two can be
compared side by side.

Shapes: P positions, C candidates; forces in N over the face width, lengths in m, Pa.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .hertz import hertz_line
from ..errors import ToothfemError, check_range
from ..units import ARCSEC, MM_PER_M, PA_PER_MPA

#: Hertz's half-space assumption is flagged when the half-width exceeds this fraction of the
#: smaller curvature radius (Johnson 1985, Sec. 4.1: b << R).
HERTZ_VALID_B_OVER_R = 0.1


@dataclass(frozen=True)
class LoadSharing:
    """Load sharing over P meshing positions and C candidate contacts, SI throughout:
    forces N (over the face width), lengths m, pressures Pa, angles rad (the transmission
    error too: x 206265 for arcsec); shapes beside each field."""
    method: str                     # "analytic", "cycle" or "detailed"
    position_rad: np.ndarray        # (P,) crank angle
    contact_id: np.ndarray          # (P, C)
    force: np.ndarray               # (P, C) N, normal force over the face width
    point: np.ndarray               # (P, C, 2) m, housing frame
    moment_arm: np.ndarray          # (P, C) m, signed as in MeshingState
    half_width: np.ndarray          # (P, C) m (0 where not in contact)
    ph: np.ndarray                  # (P, C) Pa, peak contact pressure (0 where not in contact)
    gap: np.ndarray                 # (P, C) m, remaining gap under load (0 in contact)
    transmission_error: np.ndarray  # (P,) rad, lag of the output member (rigid rotation)
    torque: float                   # N m carried by the moving member
    face_width: float               # m
    pressure_from_fe: np.ndarray    # (P, C) bool: P_h is the FE peak (Hertz fails there)
    equivalent_radius: np.ndarray   # (P, C) m
    hertz_invalid: np.ndarray       # (P, C) bool: b not small against the radii

    @property
    def in_contact(self) -> np.ndarray:
        return self.force > 0

    @property
    def contacts_per_position(self) -> np.ndarray:
        return np.sum(self.in_contact, axis=1)

    def torque_residual(self) -> np.ndarray:
        """Relative error of sum F_i l_i against the torque (equilibrium check).

        Returns
        -------
        numpy.ndarray, shape (P,)
            |sum F_i l_i| / |T| - 1 [-] per position.
        """
        return np.abs(np.sum(self.force * self.moment_arm, axis=1)) / abs(self.torque) - 1

    def figures(self, contacts_name: str) -> dict:
        """The headline figures of a result (a contact summary, a sweep row).

        Parameters
        ----------
        contacts_name : str
            What the contacts are called in the key ("pins", "teeth").

        Returns
        -------
        dict
            ``<contacts>_in_contact_max`` [-], ``max_force_N`` [N], ``max_ph_MPa`` [MPa] and
            ``transmission_error_arcsec`` (the mean over the positions) [arcsec].
        """
        return {f"{contacts_name}_in_contact_max": int(self.contacts_per_position.max()),
                "max_force_N": float(self.force.max()),
                "max_ph_MPa": float(self.ph.max() / PA_PER_MPA),
                "transmission_error_arcsec": float(self.transmission_error.mean() / ARCSEC)}

    def rows(self):
        """The rows of load_sharing.csv: every candidate in contact, position by position.

        Yields
        ------
        tuple
            (position [deg], contact_id, force [N], moment arm [mm], half-width [mm],
            peak pressure [MPa], gap [mm]).
        """
        for p in range(self.force.shape[0]):
            for c in np.flatnonzero(self.in_contact[p]):
                yield (math.degrees(self.position_rad[p]), int(self.contact_id[p, c]),
                       float(self.force[p, c]), float(self.moment_arm[p, c]) * MM_PER_M,
                       float(self.half_width[p, c]) * MM_PER_M, float(self.ph[p, c]) / PA_PER_MPA,
                       float(self.gap[p, c]) * MM_PER_M)


def hertz_fields(force, face_width, equivalent_radius, e_star, radii=None):
    """Half-width and peak pressure of each contact from its force (line contact).

    Parameters
    ----------
    force : array_like, shape (P, C)
        Normal force over the face width [N].
    face_width : float
        Face width [m].
    equivalent_radius : array_like, shape (P, C)
        Equivalent radius [m].
    e_star : float
        Contact modulus E* [Pa].
    radii : sequence of array_like, optional
        The curvature radii of the two bodies [m], each (P, C).

    Returns
    -------
    b : numpy.ndarray, shape (P, C)
        Half-width [m] (0 where not in contact).
    ph : numpy.ndarray, shape (P, C)
        Peak pressure [Pa] (0 where not in contact).
    invalid : numpy.ndarray of bool, shape (P, C)
        Where b exceeds HERTZ_VALID_B_OVER_R of the smaller |radius| in ``radii`` or where
        R_eq <= 0.
    """
    force = np.asarray(force, float)
    r = np.asarray(equivalent_radius, float)
    b = np.zeros_like(force)
    ph = np.zeros_like(force)
    ok = (force > 0) & (r > 0) & np.isfinite(r)
    if np.any(ok):
        p0, bb = hertz_line(force[ok] / face_width, r[ok], e_star)
        ph[ok], b[ok] = p0, bb
    invalid = (force > 0) & ~ok
    if radii is not None:
        rmin = np.min(np.abs(np.stack([np.asarray(x, float) for x in radii])), axis=0)
        invalid |= (force > 0) & (b > HERTZ_VALID_B_OVER_R * rmin)
    return b, ph, invalid


def check_member_torque(torque, member: str) -> None:
    """A member torque of either sign; zero leaves the member's rotation undetermined.

    Parameters
    ----------
    torque : float
        [N m].
    member : str
        What the member is called in the message ("disc", "planet").

    Raises
    ------
    ToothfemError
        For a torque that is zero or not finite.
    """
    check_range("torque", torque)
    if torque == 0:
        raise ToothfemError("torque = 0 is outside the valid range: nonzero (the rotation "
                            f"of an unloaded {member} is not determined)")


def position_pitches(pitches, n_positions: int) -> np.ndarray:
    """The meshing period each position of a cycle solve stands in (a built reducer's
    positions over its pairing period).

    Parameters
    ----------
    pitches : array_like of int, shape (n_positions,), or None
        None: every position in period 0.
    n_positions : int
        The solver's positions.

    Returns
    -------
    numpy.ndarray of int, shape (n_positions,)

    Raises
    ------
    ToothfemError
        For another shape.
    """
    out = np.zeros(n_positions, int) if pitches is None else np.asarray(pitches, int)
    if out.shape != (n_positions,):
        raise ToothfemError(f"pitches has shape {out.shape}, expected ({n_positions},)")
    return out


#: The seeds' two rules for the force on each load-carrying contact (see analytic_split).
SPLIT_WEIGHTS = ("moment_arm", "cos_pressure_angle")


def analytic_split(state, torque_Nm: float, face_width_m: float, e_star_Pa: float,
                   in_mesh_gap_m: float = 0.0, *, weight: str) -> LoadSharing:
    """The seeds' load split on a :class:`~toothfem.geometry.kinematics.MeshingState`.

    Cycloid (pin-housing paper Eqs. 8-13): rigid pins, load proportional to the moment arm,
    F_i = F_max l_i / r_a on the pins whose normal can carry the torque; F_max follows from
    sum F_i l_i = T exactly (the paper's Zb r_a^2/4 is its approximation, docs C4).
    Sine (sine paper Eqs. 16-19): F_i = F_0 cos(alpha_i) on the z_s tooth pairs in mesh
    (here: within ``in_mesh_gap_m`` once the rigid rotation of the moving member has closed
    its first load-carrying pair), F_0 = T / sum cos^2(alpha_i) r_i, which is the same
    rule since r_i cos(alpha_i) is the moment arm.

    Parameters
    ----------
    state : MeshingState
        The candidate contacts, P positions by C.
    torque_Nm : float
        Output torque carried by the moving member [N m], > 0; the load-carrying contacts
        are those with negative moment arm (MeshingState convention).
    face_width_m : float
        Face width [m], > 0.
    e_star_Pa : float
        Contact modulus E* [Pa].
    in_mesh_gap_m : float
        Contacts within this gap [m] after the rigid rotation carry load.
    weight : {"moment_arm", "cos_pressure_angle"}
        The rule: "moment_arm" (the cycloid seed) or "cos_pressure_angle" (the sine seed);
        a drive passes its own (:attr:`toothfem.fem.drives.Drive.analytic_weight`).

    Returns
    -------
    LoadSharing
        ``method`` "analytic"; no transmission error (zeros).

    Raises
    ------
    ToothfemError
        If ``weight`` is unknown, the torque or face width is not positive, or no contact
        can carry the torque at some position.
    """
    if weight not in SPLIT_WEIGHTS:
        raise ToothfemError(f"weight = {weight!r} is not one of {list(SPLIT_WEIGHTS)}")
    check_range("torque_Nm", torque_Nm, 0, None, lo_open=True)
    check_range("face_width_m", face_width_m, 0, None, lo_open=True)
    arm = state.moment_arm
    finite = (arm < 0) & np.isfinite(state.gap)
    # rigid rotation of the moving member that closes its first load-carrying pair (a pair
    # with gap g and arm l closes by |l| theta): the gaps the in-mesh rule is applied to
    theta = np.min(np.where(finite, state.gap / np.where(finite, -arm, 1.0), np.inf), axis=1)
    theta = np.where(np.isfinite(theta), theta, 0.0)
    gap = np.where(finite, state.gap + arm * theta[:, None], state.gap)
    carry = finite & (gap <= in_mesh_gap_m)
    if weight == "cos_pressure_angle":
        # cos(alpha) r = |l|: weight by |l| as well, F = F0 cos(alpha)
        share = np.where(carry, np.cos(state.pressure_angle), 0.0)
    else:
        share = np.where(carry, -arm, 0.0)
    denom = np.sum(share * -arm, axis=1)
    if np.any(denom <= 0):
        bad = int(np.flatnonzero(denom <= 0)[0])
        raise ToothfemError(f"no contact can carry the torque at position "
                            f"{math.degrees(state.position_rad[bad]):.3f} deg")
    force = share * (torque_Nm / denom)[:, None]
    b, ph, invalid = hertz_fields(force, face_width_m, state.equivalent_radius, e_star_Pa,
                                  (state.radius_moving, state.radius_fixed))
    return LoadSharing(
        method="analytic", position_rad=state.position_rad, contact_id=state.contact_id,
        force=force, point=state.point, moment_arm=arm, half_width=b, ph=ph,
        gap=np.where(force > 0, 0.0, gap),
        transmission_error=np.zeros(state.position_rad.shape), torque=float(torque_Nm),
        face_width=float(face_width_m), pressure_from_fe=np.zeros_like(invalid),
        equivalent_radius=state.equivalent_radius, hertz_invalid=invalid)
