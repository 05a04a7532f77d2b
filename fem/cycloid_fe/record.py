"""The load sharing record of a cycloid disc from its pin forces [N] (any mode: cycle,
detailed, system), with the Hertz half-widths [m] and pressures [Pa] of those forces.
"""
from __future__ import annotations

import numpy as np

from ..load_sharing import LoadSharing, hertz_fields


def record(method, model, state, force, gap, beta, torque) -> LoadSharing:
    """The load sharing record of a disc from its pin forces: Hertz half-widths and
    pressures from the forces (:func:`toothfem.fem.load_sharing.hertz_fields`).

    Parameters
    ----------
    method : str
        "cycle", "detailed" or "system".
    model : CycloidFEModel
    state : toothfem.geometry.kinematics.MeshingState
        The meshing at the positions.
    force, gap : numpy.ndarray, shape (P, Zb)
        Pin forces [N] and remaining gaps [m].
    beta : numpy.ndarray, shape (P,)
        The transmission error of the record [rad].
    torque : float
        The disc's torque [N m].

    Returns
    -------
    LoadSharing
    """
    b, ph, invalid = hertz_fields(force, model.face_width, state.equivalent_radius, model.e_star,
                                  (state.radius_moving, state.radius_fixed))
    return LoadSharing(
        method=method, position_rad=state.position_rad, contact_id=state.contact_id,
        force=force, point=state.point, moment_arm=state.moment_arm, half_width=b, ph=ph,
        gap=np.where(force > 0, 0.0, gap), transmission_error=beta, torque=float(torque),
        face_width=model.face_width, pressure_from_fe=np.zeros_like(invalid),
        equivalent_radius=state.equivalent_radius, hertz_invalid=invalid)
