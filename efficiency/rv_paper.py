"""The RV paper's split/virtual power method applied to a case (C. Wang, "A calculation
method of transmission efficiency for RV reducer", Eqs. 8-15), beside the friction model."""
from __future__ import annotations

import numpy as np

from ..errors import CaseError
from .drive_losses import DriveLosses
from .power_flow import rv_split_power


def split_power_losses(si, input_speed_rad_s, output_torque_Nm) -> DriveLosses:
    """The RV paper's method at each operating point with the declared mesh efficiency
    (``[rv] mesh_efficiency`` for both meshes). The method is linear in the input power:
    the losses per watt of input, scaled."""
    if si.rv is None:
        raise CaseError(f"method = 'rv_split_power' needs drive = 'rv', not {si.drive!r}")
    z = si.rv
    eta1 = z.mesh_efficiency
    r = rv_split_power(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count, 1.0, eta1, eta1)
    p_out = output_torque_Nm * np.abs(input_speed_rad_s / r.ratio)
    p_in = p_out / r.efficiency
    return DriveLosses(
        output_power_W=p_out,
        losses_W={"sun_planet_mesh": p_in * r.loss_L1_W, "cycloid_mesh": p_in * r.loss_L2_W},
        notes=("RV paper Eqs. 8-15 with the declared mesh efficiency",),
        mesh_efficiency={"sun_planet": np.full_like(p_out, eta1),
                         "cycloid": np.full_like(p_out, eta1)})
