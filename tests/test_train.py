"""Train ratios from tooth numbers (Willis equations solved as a linear system)."""
import math

import pytest
from hypothesis import given, strategies as st

from toothfem.errors import GeometryError
from toothfem.geometry import train

REL = 1e-12  # a 5x5 linear solve in double precision


def test_rv40e_and_pin_housing_ratio_121():
    """RV paper Table 1 (12/36/39/40) and pin-housing paper Table 1 (9/27/39/40): 121."""
    assert math.isclose(train.rv_ratio(12, 36, 39, 40), 121, rel_tol=REL)
    assert math.isclose(train.rv_ratio(9, 27, 39, 40), 121, rel_tol=REL)


def test_sine_ratio_minus_79():
    """K-H-V, planet 79 in ring 80: the planet turns back 1/79 per crank revolution."""
    assert math.isclose(train.khv_ratio(79, 80), -79, rel_tol=REL)
    assert math.isclose(train.khv_ratio(39, 40), -39, rel_tol=REL)


def test_rv_members_follow_paper_eqs_1_to_3():
    """Speeds satisfy each of RV paper Eqs. 1-3 (w4 = w6 = w7; Willis on both stages)."""
    w = train.rv_speeds(12, 36, 39, 40)
    assert math.isclose((w["sun"] - w["carrier"]) / (w["planet"] - w["carrier"]), -36 / 12,
                        rel_tol=REL)
    assert math.isclose((w["disc"] - w["planet"]) / (w["pins"] - w["planet"]), 40 / 39,
                        rel_tol=REL)
    # Eq. 4: w3/w4 = z4/(z4 - z5)
    assert math.isclose(w["planet"] / w["disc"], 39 / (39 - 40), rel_tol=REL)


@given(zs=st.integers(6, 60), zp=st.integers(6, 90), zd=st.integers(5, 120),
       diff=st.integers(1, 3))
def test_closed_forms_match_linear_solve(zs, zp, zd, diff):
    zpins = zd + diff
    closed = 1 + (zp / zs) * zpins / (zpins - zd)
    assert math.isclose(train.rv_ratio(zs, zp, zd, zpins), closed, rel_tol=1e-9)
    assert math.isclose(train.khv_ratio(zd, zpins), zd / (zd - zpins), rel_tol=1e-9)


@pytest.mark.parametrize("args", [(39, 39), (0, 40), (39.5, 40)])
def test_bad_teeth_refused(args):
    with pytest.raises(GeometryError, match=r"z_"):
        train.khv_ratio(*args)
