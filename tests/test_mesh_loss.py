"""Mesh power loss from a load-sharing record (sine paper Eqs. 21, 25 in SI; the test oracle
tests/oracles/mesh_loss.py)."""
import math

import numpy as np
import pytest

from tests.oracles.mesh_loss import mesh_loss, stage_power
from toothfem import ToothfemError, load_case
from toothfem.fem.load_sharing import analytic_split
from toothfem.geometry import cycloid_mesh as cym

PHIS = np.linspace(0, 2 * math.pi / 40, 6, endpoint=False)


@pytest.fixture(scope="module")
def setup(cases_dir):
    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    g = case.cycloid.geometry()
    torque, crank = 91.85, 60.0
    fixed = cym.meshing(g, PHIS, crank, pin_motion="fixed")
    rolling = cym.meshing(g, PHIS, crank, pin_motion="rolling")
    ls = analytic_split(fixed, torque, 0.01, 1.14e11, weight="moment_arm")
    return fixed, rolling, ls, stage_power(torque, crank, -39)


def test_coulomb_loss_by_hand(setup):
    fixed, _, ls, power = setup
    ml = mesh_loss(fixed, ls, power, mu=0.05)
    by_hand = 0.05 * np.sum(ls.force * np.abs(fixed.sliding_velocity), axis=1)
    assert np.allclose(ml.loss_W, by_hand, rtol=1e-14)
    assert np.all((ml.efficiency > 0) & (ml.efficiency < 1))
    assert power == pytest.approx(91.85 * 60.0 / 39)


def test_rolling_pins_have_no_mesh_sliding_loss(setup):
    _, rolling, ls, power = setup
    assert np.all(mesh_loss(rolling, ls, power, mu=0.05).loss_W == 0)


def test_ehl_friction_per_contact(setup):
    fixed, _, ls, power = setup
    with pytest.warns(Warning):   # these thin films are below the full-film range
        ml = mesh_loss(fixed, ls, power, eta0_Pa_s=0.058, roughness_m=0.5e-6)
    loaded = ls.force > 0
    assert np.all(ml.mu[loaded & (fixed.sliding_velocity != 0)] > 0)
    assert np.all(ml.mu[~loaded] == 0)


def test_shape_mismatch_refused(setup):
    import dataclasses

    fixed, _, ls, power = setup
    short = dataclasses.replace(fixed, moment_arm=fixed.moment_arm[:, :3])
    with pytest.raises(ToothfemError, match="does not match"):
        mesh_loss(short, ls, power, mu=0.05)
    with pytest.raises(ToothfemError, match="mu = 1.5 is outside the valid range"):
        mesh_loss(fixed, ls, power, mu=1.5)
