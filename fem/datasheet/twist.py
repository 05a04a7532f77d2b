"""The output's twist at one torque as the datasheet reads it (docs/stiffness.md): the
record every twist curve returns (:class:`toothfem.fem.system.datasheet.SystemTwist`, the
system model of the whole reducer) and the torque that stands for zero."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...units import ARCMIN, ARCSEC  # noqa: F401  (the datasheet's angles, re-exported)

if TYPE_CHECKING:
    from ..load_sharing import LoadSharing

#: The limit of zero torque is the solution at this output torque [N m] of the flank's
#: sign: its elastic part is below 1e-6 of the twist at 100 N m (linear-ish in the torque),
#: while the rigid closing rotation of the clearances is all there (the sine pair's flanks
#: close where their gap has no minimum of its own, so no gap table gives that rotation).
ZERO_TORQUE_NM = 1e-4


@dataclass(frozen=True, kw_only=True)
class TwistPoint:
    """The twist at one output torque, per position: ``paths`` {name: (P,) rad} whose sum
    is ``total``; ``contacts`` (P,) loaded contacts of the member."""
    output_torque_Nm: float
    total: np.ndarray
    paths: dict
    contacts: np.ndarray
    load_sharing: LoadSharing | None = None     # the mesh's (None at zero torque)
    member_torques_Nm: tuple = ()   # (M,) the members' torques [N m], signed
