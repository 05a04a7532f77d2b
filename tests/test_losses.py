"""Every loss component once (efficiency/losses.py): each shipped case's losses are in the
table with a law, the loop's effects that scale a loss name one of them, and a new
load-independent loss is one entry with its law (efficiency/no_load.py,
docs/architecture.md "Adding a loss")."""
from __future__ import annotations

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency import evaluate, operating_point
from toothfem.efficiency import losses as ls
from toothfem.efficiency import no_load as nl
from toothfem.efficiency.drive_losses import loss_sources
from toothfem.efficiency.loop import effects as fx
from toothfem.fem.drives import drive_for

CASES = ("cycloid_pinhousing", "cycloid_khv", "rv40e", "rv_paper_example", "sine_prototype")


@pytest.mark.parametrize("name", CASES)
def test_every_loss_of_a_case_is_in_the_table_with_its_law(cases_dir, name):
    case = load_case(cases_dir / f"{name}.toml")
    e = evaluate(case, *operating_point(case))
    assert set(e.losses_W) <= set(ls.LOSSES), set(e.losses_W) - set(ls.LOSSES)
    laws = loss_sources(drive_for(case), e.losses_W)
    assert all(laws.values()), [k for k, v in laws.items() if not v]
    # a part-bound loss belongs to a part the layout has
    parts = case.layout.components | {"teeth", "pins"}
    for n in e.losses_W:
        assert ls.LOSSES[n].part in (None, *parts), (name, n)


def test_the_loops_effects_scale_losses_of_the_table(cases_dir):
    """An effect linear in a loss component names one of the table's, on a case whose
    layout has the effect's part."""
    for name in CASES:
        case = load_case(cases_dir / f"{name}.toml")
        for eff in fx.catalog():
            if eff.linear_in is None or (eff.acts_on is not None
                                         and eff.acts_on not in case.layout.components):
                continue
            component = eff.linear_in(case)
            assert component is None or component in ls.LOSSES, (name, eff.name, component)
    assert {x.name for x in nl.NO_LOAD} <= set(ls.LOSSES)


def viscous(si, drive, points):
    """A probe: a drag torque proportional to the input speed, c w^2 [W]."""
    return 1e-3 * np.asarray(points.input_rad_s, float) ** 2


def test_a_new_load_independent_loss_is_one_entry(cases_dir, monkeypatch):
    """A NoLoadLoss with its power law, listed in NO_LOAD and its law in LOSSES, is in every
    evaluation's losses with its law, and the input power rises by exactly its power."""
    case = load_case(cases_dir / "sine_prototype.toml")
    point = operating_point(case)
    before = evaluate(case, *point)
    monkeypatch.setattr(nl, "NO_LOAD", nl.NO_LOAD + (nl.NoLoadLoss("viscous_drag", viscous),))
    monkeypatch.setitem(ls.LOSSES, "viscous_drag",
                        ls.Loss("viscous_drag", None, "a probe: c w_in^2"))
    after = evaluate(case, *point)
    w = point[0] * 2 * np.pi / 60
    assert after.losses_W["viscous_drag"] == pytest.approx(1e-3 * w ** 2, rel=1e-12)
    assert loss_sources(drive_for(case), ["viscous_drag"]) == {"viscous_drag": "a probe: c w_in^2"}
    p_out = float(before.output_power_W[0])
    assert float(after.input_power_W[0]) == pytest.approx(
        float(before.input_power_W[0]) + 1e-3 * w ** 2, rel=1e-9)
    assert float(after.output_power_W[0]) == pytest.approx(p_out, rel=1e-12)
