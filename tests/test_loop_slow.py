"""Slow checks of the measured-data loop: the false-positive study over 20 seeded data sets,
the clearance effect with its FE contact springs and against the FE cycle mode, aliasing
of effects the data cannot tell apart, and two effects that hide each other on a cycloid."""
import dataclasses
import math

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency.loop import effects as fx
from toothfem.efficiency import loop as lp
from toothfem.efficiency import drive_losses as md
from toothfem.efficiency.loop import synthetic as sy
from toothfem.efficiency.mesh_table import table_from_records
from toothfem.fem.drives import drive_for

pytestmark = pytest.mark.slow
R = dataclasses.replace
CATALOG = fx.catalog(clearance_compliance=5e-11)
#: At most this many false effects over the 20 data sets without an effect (the issue).
MAX_FALSE = 1


@pytest.fixture(scope="module")
def cases(cases_dir):
    return {n: load_case(cases_dir / f"{n}.toml")
            for n in ("sine_prototype", "cycloid_pinhousing", "rv40e")}


def test_no_effect_twenty_seeds(cases):
    """20 data sets of the model alone (sine case with every effect field at its default,
    so seven candidates compete, the churning law's factor and the thermal resistance among
    them since issue 13; oil temperatures 20-100 deg C): at most one false effect in all."""
    sine = cases["sine_prototype"]
    case = R(sine, friction=R(sine.friction, bearing_coefficient=0.0015,
                              output_pin_coefficient=0.05),
             lubricant=R(sine.lubricant, vogel_B_C=1000.0))
    false, unexplained = 0, 0
    for seed in range(20):
        data = sy.generate(case, {}, oil_temp_C=(20, 100), seed=100 + seed, catalog=CATALOG)
        rep = lp.run_loop(case, data, CATALOG)
        false += len(rep.effects)
        unexplained += bool(rep.unexplained)
    assert false <= MAX_FALSE
    assert unexplained <= MAX_FALSE


def test_no_effect_cycloid_ten_seeds(cases):
    """The same on the pin-housing cycloid (five candidates, 100 points, 10 seeds)."""
    cyc = cases["cycloid_pinhousing"]
    false = 0
    for seed in range(10):
        data = sy.generate(cyc, {}, n_points=100, torque_Nm=(50.0, 167.0), seed=200 + seed,
                           catalog=CATALOG)
        false += len(lp.run_loop(cyc, data, CATALOG).effects)
    assert false <= MAX_FALSE


def test_clearance_with_fe_springs(cases):
    """The catalog's own clearance effect (contact springs from the FE influence matrix):
    named, recovered within 20 %, error cut 3x."""
    cyc = cases["cycloid_pinhousing"]
    cat = fx.catalog()
    comp = fx.contact_compliance(drive_for(cyc))
    assert 2e-11 < comp < 8e-11          # 3.8e-11 m per N/m: disc plus integral housing
    data = sy.generate(cyc, {"load_sharing_clearance": (0.004,)}, torque_Nm=(50.0, 167.0),
                       seed=7, catalog=cat)
    rep = lp.run_loop(cyc, data, cat)
    assert [e.name for e in rep.effects] == ["load_sharing_clearance"]
    value = rep.effects[0].parameters["equidistant_modification_mm"]["value"]
    assert value == pytest.approx(0.004, rel=0.2)
    assert rep.baseline.rmse >= 3 * rep.final.rmse


def _pin_loss(case, c_mm, springs, torque=120.0, speed=1000.0, positions=12):
    """Cycle-mean sum mu F v_s of the pins at one operating point, load split from the FE
    cycle mode (springs None) or the equal-springs limit."""
    from toothfem.fem import cycloid_fe as cf
    from toothfem.geometry import cycloid_mesh as cym

    cc = R(case.cycloid, equidistant_modification_mm=c_mm)
    g = cc.geometry()
    phis = np.linspace(0, 2 * math.pi / g.pin_count, positions, endpoint=False)
    state = cym.meshing(g, phis, 1.0, pin_motion="fixed")
    model = drive_for(R(case, cycloid=cc)).fe_model()
    rec = cf.CycleSolver(model, phis, equal_springs=springs).solve(torque / cc.disc_count)
    tab = table_from_records(state, [rec], "check")
    t_disc = np.array([torque / cc.disc_count])
    crank = np.array([speed * 2 * math.pi / 60 * fx.crank_speed_factor(case)])
    loss = float(md.disc_contact_losses(case, tab, t_disc, crank,
                                        case.lubricant.dynamic_viscosity_Pa_s)[0][0])
    return loss, float(np.mean(rec.contacts_per_position))


def test_equal_springs_against_fe_cycle_mode(cases):
    """The clearance effect's contact model against the FE cycle mode (disc and housing
    elastic, coupled contacts): the pin loss relative to zero clearance agrees within 5 %
    at 5 um (observed 0.713 against 0.739 at 3 um, 0.640 against 0.659 at 10 um), and the
    pins in contact within one."""
    cyc = cases["cycloid_pinhousing"]
    comp = fx.contact_compliance(drive_for(cyc))
    s0, _ = _pin_loss(cyc, 0.0, comp)
    f0, _ = _pin_loss(cyc, 0.0, None)
    s1, ns = _pin_loss(cyc, 0.005, comp)
    f1, nf = _pin_loss(cyc, 0.005, None)
    assert s1 / s0 == pytest.approx(f1 / f0, rel=0.05)
    assert abs(ns - nf) <= 1.0
    assert s1 / s0 < 0.8                     # the clearance effect is large here


def test_aliased_effects_are_reported(cases):
    """Conventional pins sliding in their grooves and crank-bearing friction are both
    losses proportional to T n: with neither declared, the loop adds one and says the data
    cannot tell it from the other. (The main bearings' preload is declared 0 here: their
    default preload gives bearing friction a load-independent part, which separates the
    two by 28 in BIC.)"""
    cyc = cases["cycloid_pinhousing"]
    conv = R(cyc, friction=R(cyc.friction, pin_groove_coefficient=0.0),
             cycloid=R(cyc.cycloid, pin_structure="conventional"),
             bearings=R(cyc.bearings, main_preload_N=0.0))
    data = sy.generate(conv, {"pin_sliding": (0.05,)}, torque_Nm=(50.0, 167.0), seed=1,
                       catalog=CATALOG)
    rep = lp.run_loop(conv, data, CATALOG)
    first = rep.steps[0]
    assert {first.added, *first.aliased} >= {"pin_sliding", "bearing_friction"}
    assert "cannot tell it from" in first.reason
    assert rep.baseline.rmse >= 3 * rep.final.rmse


def test_two_effects_that_hide_each_other(cases):
    """Drag (a loss) and a lower boundary friction than the default 0.1 (a gain: the pins of
    this disc rub at the boundary value) partly cancel, so neither alone passes first; the
    forward steps take detours and the backward step removes them again. (Before issue 13
    the model had no asperity friction by default and the truth was 0.1, a gain because it
    capped the extrapolated EHL friction.)"""
    cyc = cases["cycloid_pinhousing"]
    data = sy.generate(cyc, {"drag_torque": (200.0,), "mixed_lubrication": (0.07,)},
                       torque_Nm=(50.0, 167.0), seed=2, catalog=CATALOG)
    rep = lp.run_loop(cyc, data, CATALOG)
    found = {e.name: next(iter(e.parameters.values()))["value"] for e in rep.effects}
    assert set(found) == {"drag_torque", "mixed_lubrication"}
    assert found["drag_torque"] == pytest.approx(200.0, rel=0.1)
    assert found["mixed_lubrication"] == pytest.approx(0.07, rel=0.1)
    assert rep.baseline.rmse >= 3 * rep.final.rmse
