"""Test oracle: mesh power loss over the meshing cycle from a load-sharing record, as the
sine paper writes it (Y. Lu, L. Xu, "Transmission efficiency of one tooth difference sine
tooth profile planetary reducer", Heliyon 10 (2024) e26300, Eqs. 21 and 25).

loss(phi) = sum_i mu_i F_i |v_s,i| (Eq. 21 in SI; the paper's 1e-3 is its unit
conversion), with mu_i from a friction law evaluated at each contact's own load, pressure,
sliding and rolling speeds; mesh efficiency eta(phi) = 1 - loss / P, P the power through
the stage (Eq. 25). Works on either load-sharing source (FE or analytic split). The
production model sums the same loss over its flattened contact table
(``toothfem.efficiency`` (evaluation, drive_losses, contact_friction)); the tests hold the two paths together.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from toothfem.efficiency.friction import ehl_xu2007
from toothfem.errors import ToothfemError, check_range


@dataclass(frozen=True)
class MeshLoss:
    position_rad: np.ndarray    # (P,)
    mu: np.ndarray              # (P, C) friction coefficient at each loaded contact (0 idle)
    film_ratio: np.ndarray      # (P, C) lambda (inf where not computed)
    loss_W: np.ndarray          # (P,) mesh power loss
    power_W: float              # power through the stage
    efficiency: np.ndarray      # (P,) 1 - loss/P

    @property
    def mean_efficiency(self) -> float:
        return float(np.mean(self.efficiency))


def stage_power(torque_Nm: float, crank_speed_rad_s: float, ratio: float) -> float:
    """Power through a K-H-V stage: torque on the moving member times its speed, which is
    the crank speed over the ratio (lossless)."""
    return abs(torque_Nm * crank_speed_rad_s / ratio)


def mesh_loss(state, load_sharing, power_W: float, mu=None, *, eta0_Pa_s=None,
              roughness_m=None, e_prime_Pa=None, pressure_viscosity=None) -> MeshLoss:
    """Mesh loss of every position.

    ``state``: MeshingState at the load sharing's positions with its crank speed (the
    velocities); ``mu``: a constant Coulomb coefficient, or None for the EHL regression of
    Xu et al. (2007) with ``eta0_Pa_s``, ``roughness_m`` (the composite RMS roughness S,
    :func:`toothfem.efficiency.friction.composite_rms_roughness`), ``e_prime_Pa`` and
    ``pressure_viscosity`` (1/Pa).
    """
    check_range("power_W", power_W, 0, None, lo_open=True)
    force = load_sharing.force
    if force.shape != state.moment_arm.shape:
        raise ToothfemError(f"load sharing shape {force.shape} does not match the meshing "
                            f"state {state.moment_arm.shape}")
    loaded = force > 0
    vs = np.abs(state.sliding_velocity)
    mu_arr = np.zeros_like(force)
    lam = np.full(force.shape, np.inf)
    if mu is not None:
        check_range("mu", mu, 0, 1)
        mu_arr[loaded] = mu
    else:
        sel = loaded & (vs > 0)
        kw = {}
        if e_prime_Pa is not None:
            kw["e_prime"] = e_prime_Pa
        if pressure_viscosity is not None:
            kw["pressure_viscosity"] = pressure_viscosity
        if np.any(sel):
            res = ehl_xu2007(load_sharing.ph[sel], state.slide_to_roll[sel],
                             np.abs(state.entrainment_velocity[sel]), eta0_Pa_s,
                             load_sharing.equivalent_radius[sel], roughness_m, **kw)
            mu_arr[sel] = res.mu
            lam[sel] = res.film_ratio
    loss = np.sum(mu_arr * force * vs, axis=1)
    return MeshLoss(load_sharing.position_rad, mu_arr, lam, loss, float(power_W),
                    1.0 - loss / power_W)
