"""Bearing load ratings (efficiency/rating.py) against the standards' tables and makers'
catalogues.

Three kinds of check:

1. The f_c and f_0 tables as carried reproduce the standards' printed values at several
   points, and every entry agrees to its printed digit with an independent derivation:
   ISO/TR 1281-1's closed forms for f_c, the Hertz contact at ISO 76's 4 200 MPa for f_0.
   A transcription error of one digit anywhere in a table fails here.
2. Real bearings whose internal geometry is published: C and C0 against the maker's value.
3. Bad input raises ValueError naming the parameter.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from toothfem.efficiency import rating

IN = 0.0254          # m per inch
MM = 1e-3            # m per mm


# -- 1. the tables ------------------------------------------------------------------------

# Printed values of the standards, as quoted in the public sources named in rating.py
# (ISO 281:2007 Tables 2 and 7, ISO 76:2006 Table 1): (gamma, value).
PRINTED_FC_BALL = [(0.01, 29.1), (0.05, 46.7), (0.10, 55.5), (0.19, 60.0), (0.20, 59.9),
                   (0.30, 56.0), (0.40, 48.4)]
PRINTED_FC_ROLLER = [(0.01, 52.1), (0.05, 74.1), (0.10, 84.2), (0.18, 88.8), (0.20, 88.7),
                     (0.30, 83.8)]
PRINTED_F0_BALL = [(0.00, 14.7), (0.06, 15.9), (0.09, 16.5), (0.10, 16.4), (0.20, 14.0),
                   (0.30, 11.6), (0.40, 9.4)]


@pytest.mark.parametrize("gamma, printed", PRINTED_FC_BALL)
def test_fc_ball_printed_values(gamma, printed):
    for kind in rating.BALL_TYPES:
        assert rating.fc_factor(kind, gamma) == pytest.approx(printed, abs=1e-12)


@pytest.mark.parametrize("gamma, printed", PRINTED_FC_ROLLER)
def test_fc_roller_printed_values(gamma, printed):
    for kind in ("cylindrical", "tapered", "needle"):
        assert rating.fc_factor(kind, gamma) == pytest.approx(printed, abs=1e-12)


@pytest.mark.parametrize("gamma, printed", PRINTED_F0_BALL)
def test_f0_printed_values(gamma, printed):
    assert rating.f0_factor(gamma) == pytest.approx(printed, abs=1e-12)


def test_linear_interpolation_between_rows():
    """ISO 281 and ISO 76: linear interpolation for intermediate gamma."""
    assert rating.fc_factor("ball", 0.195) == pytest.approx(59.95)
    assert rating.fc_factor("cylindrical", 0.155) == pytest.approx(88.35)
    assert rating.f0_factor(0.205) == pytest.approx(13.85)


def _fc_ball_closed_form(g):
    """ISO/TR 1281-1 f_c of radial ball bearings with equal inner/outer conformity, so the
    ratio term is 1; K = 39.9 (lambda eta) (2f/(2f-1))^0.41 = 39.9 * 0.9573 * 26^0.41 for
    f = 0.52. K is fitted to the table (the window that reproduces every digit is
    lambda eta = 0.9573 +- 0.00005), not read from ISO/TR 1281-1."""
    k = 39.9 * 0.9573 * (2 * 0.52 / (2 * 0.52 - 1)) ** 0.41
    return (k * g ** 0.3 * (1 - g) ** 1.39 / (1 + g) ** (1 / 3)
            * (1 + (1.04 * ((1 - g) / (1 + g)) ** 1.72) ** (10 / 3)) ** -0.3)


def _fc_roller_closed_form(g):
    """ISO/TR 1281-1 f_c of radial roller bearings with lambda nu = 0.83."""
    return (207.9 * 0.83 * g ** (2 / 9) * (1 - g) ** (29 / 27) / (1 + g) ** 0.25
            * (1 + (1.04 * ((1 - g) / (1 + g)) ** (143 / 108)) ** 4.5) ** (-2 / 9))


def test_fc_ball_table_is_the_closed_form_to_the_printed_digit():
    g = np.array(rating.FC_BALL_GAMMA)
    np.testing.assert_allclose(np.round(_fc_ball_closed_form(g), 1), rating.FC_BALL,
                               atol=1e-9)


def test_fc_roller_table_is_the_closed_form_to_the_printed_digit():
    g = np.array(rating.FC_ROLLER_GAMMA)
    np.testing.assert_allclose(np.round(_fc_roller_closed_form(g), 1), rating.FC_ROLLER,
                               atol=1e-9)


def _hertz_point_load(sum_rho, f_rho, stress=4200.0, e=207000.0, nu=0.3):
    """Normal load [N] of a steel-on-steel point contact whose peak pressure is
    ``stress`` [MPa]; curvatures in 1/mm (Hertz, as in Harris, Rolling Bearing
    Analysis: ellipticity k from F(rho), a*, b* from the complete elliptic integrals)."""
    def residual(k):
        m = 1 - 1 / k ** 2
        return ((k ** 2 + 1) * ellipe(m) - 2 * ellipk(m)) / ((k ** 2 - 1) * ellipe(m)) - f_rho
    k = brentq(residual, 1.0001, 100.0)
    m = 1 - 1 / k ** 2
    a_star = (2 * k ** 2 * ellipe(m) / math.pi) ** (1 / 3)
    b_star = (2 * ellipe(m) / (math.pi * k)) ** (1 / 3)
    c = 3 / (2 * sum_rho) * 2 * (1 - nu ** 2) / e
    # sigma = 3 Q / (2 pi a b), a b = a* b* (c Q)^(2/3)
    return (stress * 2 * math.pi * a_star * b_star * c ** (2 / 3) / 3) ** 3


def _f0_hertz(g, fi=0.52, fe=0.53):
    """f_0 [N/mm^2] from first principles (ISO/TR 10657's basis of ISO 76): 4 200 MPa at the
    more loaded of the inner and outer contacts, groove radii fi D_w and fe D_w, and
    Q_max = 5 F_r / (i Z cos a), so f_0 = Q_max / (5 D_w^2). D_w = 1 mm."""
    loads = []
    for sign, f in ((+1, fi), (-1, fe)):
        rho_ball = 2.0
        rho_roll = sign * 2.0 * g / (1 - sign * g)      # raceway, rolling direction
        rho_groove = -1.0 / f                           # raceway, across the groove
        s = 2 * rho_ball + rho_roll + rho_groove
        loads.append(_hertz_point_load(s, (rho_roll - rho_groove) / s))
    return min(loads) / 5.0


def test_f0_table_is_the_hertz_contact_to_the_printed_digit():
    """40 of the 41 entries are the Hertz value rounded; the 41st (0.13: 15.653, printed
    15.6) is 0.003 past the rounding bound. Every entry is within 0.055 of the derivation
    (a one-digit typo such as the 15.7-for-15.9 at 0.06 of one source is 0.2 off), and a
    common scale of 0.9998 (0.02 %, inside the uncertainty of the elastic constants the
    standard used) reproduces all 41 printed digits."""
    derived = np.array([_f0_hertz(max(g, 1e-9)) for g in rating.F0_BALL_GAMMA])
    table = np.array(rating.F0_BALL)
    assert np.abs(derived - table).max() < 0.055
    assert np.count_nonzero(np.round(derived, 1) != table) == 1
    np.testing.assert_allclose(np.round(0.9998 * derived, 1), table, atol=1e-9)


def test_static_roller_factor_is_the_hertz_line_contact():
    """ISO 76's 44 (1 - gamma): 4 000 MPa line contact at the inner ring, Stribeck 5.
    q = p^2 pi R / E* per mm, R = D_we (1 - gamma)/2, E* = E / (2 (1 - nu^2))."""
    e_star = 207000.0 / (2 * (1 - 0.3 ** 2))
    per_mm2 = 4000.0 ** 2 * math.pi / 2 / e_star / 5      # times D_we L_we (1 - gamma)
    assert per_mm2 == pytest.approx(rating.STATIC_ROLLER_FACTOR, rel=0.01)


# -- 2. real bearings against the maker's catalogue -------------------------------------

# name, type, geometry (i, Z, D_w [m], D_pw [m]), catalogue C [N], catalogue C0 [N].
# Tolerances: C within 10 %: makers publish their own rating (their steel and process
# factor in place of ISO's b_m, e.g. SKF's Explorer uplift), typically 0-10 % above ISO 281;
# C0 within 5 %: makers rate C0 by ISO 76 itself (4 200 MPa), so only rounding and the
# maker's own groove radii separate them.
CATALOGUE = [
    # SKF 6205 (CWRU drive-end bearing "6205-2RS JEM SKF"). Geometry: Case Western Reserve
    # University Bearing Data Center, "Apparatus & Procedures" page
    # (https://engineering.case.edu/bearingdatacenter/apparatus-and-procedures): ball
    # diameter 0.3126 in, pitch diameter 1.537 in; Z = 9 from the same page's defect
    # frequencies (BPFO 3.5848 x shaft speed = Z/2 (1 - D_w/D_pw)). Catalogue: SKF product
    # page "6205" (https://www.skf.com/group/products/rolling-bearings/ball-bearings/
    # deep-groove-ball-bearings/productid-6205): C = 14.8 kN, C0 = 7.8 kN.
    ("SKF 6205", 1, 9, 0.3126 * IN, 1.537 * IN, 14.8e3, 7.8e3),
    # SKF 6203 (CWRU fan-end bearing "6203-2RS JEM SKF"). Geometry: same CWRU page, ball
    # diameter 0.2656 in, pitch diameter 1.122 in; Z = 8 (BPFO 3.0530). Catalogue: SKF
    # product page "6203": C = 9.95 kN, C0 = 4.75 kN.
    ("SKF 6203", 1, 8, 0.2656 * IN, 1.122 * IN, 9.95e3, 4.75e3),
    # LDK UER204 (XJTU-SY run-to-failure data). Geometry and the maker's ratings: B. Wang,
    # Y. Lei, N. Li, N. Li, "A hybrid prognostics approach for estimating remaining useful
    # life of rolling element bearings", IEEE Trans. Reliability 69(1), 401-412 (2020),
    # table of bearing parameters (also https://biaowang.tech/xjtu-sy-bearing-datasets/):
    # 8 balls of 7.92 mm on a 34.55 mm pitch diameter, C = 12.82 kN, C0 = 6.65 kN.
    ("LDK UER204", 1, 8, 7.92 * MM, 34.55 * MM, 12.82e3, 6.65e3),
    # NSK 6804DD (FEMTO-ST PRONOSTIA platform). P. Nectoux et al., "PRONOSTIA: an
    # experimental platform for bearings accelerated degradation tests", IEEE PHM 2012
    # (https://hal.science/hal-00719503), table of bearing characteristics: outer race
    # 29.1 mm, inner race 22.1 mm (pitch diameter their mean, 25.6 mm), 13 balls of
    # 3.5 mm, maximum dynamic load 4 000 N, maximum static load 2 550 N.
    ("NSK 6804", 1, 13, 3.5 * MM, 25.6 * MM, 4000.0, 2550.0),
]


@pytest.mark.parametrize("name, rows, z, dw, dpw, c_cat, c0_cat", CATALOGUE,
                         ids=[c[0] for c in CATALOGUE])
def test_deep_groove_ball_bearings_match_catalogue(name, rows, z, dw, dpw, c_cat, c0_cat):
    geom = dict(rows=rows, elements=z, element_diameter_m=dw, pitch_diameter_m=dpw)
    c = rating.dynamic_rating_N("ball", **geom)
    c0 = rating.static_rating_N("ball", **geom)
    # makers' C carry their own material/process factor: within 10 % of ISO 281
    assert c / c_cat == pytest.approx(1.0, abs=0.10), name
    # makers' C0 is ISO 76 itself: within 5 % (rounding, the maker's groove radii)
    assert c0 / c0_cat == pytest.approx(1.0, abs=0.05), name


def test_catalogue_ratios_for_the_doc():
    """The numbers of docs/bearing_rating.md's verification table (to 0.1 %)."""
    expected = {"SKF 6205": (14027, 7886), "SKF 6203": (9548, 4757),
                "LDK UER204": (12792, 6635), "NSK 6804": (4016, 2463)}
    for name, rows, z, dw, dpw, _c, _c0 in CATALOGUE:
        geom = dict(rows=rows, elements=z, element_diameter_m=dw, pitch_diameter_m=dpw)
        c_doc, c0_doc = expected[name]
        assert rating.dynamic_rating_N("ball", **geom) == pytest.approx(c_doc, rel=1e-3)
        assert rating.static_rating_N("ball", **geom) == pytest.approx(c0_doc, rel=1e-3)


# -- formula structure (types without a catalogue check) --------------------------------

def test_roller_formula_exponents_and_factors():
    """C_r = b_m f_c (i L_we cos a)^(7/9) Z^(3/4) D_we^(29/27), at a gamma on a table row
    (0.15: f_c = 88.2) so no interpolation enters."""
    geom = dict(rows=1, elements=14, element_diameter_m=7.5 * MM,
                element_length_m=7.5 * MM, pitch_diameter_m=50.0 * MM)
    c = rating.dynamic_rating_N("cylindrical", **geom)
    assert c == pytest.approx(1.1 * 88.2 * 7.5 ** (7 / 9) * 14 ** 0.75 * 7.5 ** (29 / 27))
    longer = rating.dynamic_rating_N("cylindrical", **{**geom, "element_length_m": 15 * MM})
    assert longer / c == pytest.approx(2 ** (7 / 9))
    two_rows = rating.dynamic_rating_N("needle", **{**geom, "rows": 2})
    assert two_rows / c == pytest.approx(2 ** (7 / 9))
    c0 = rating.static_rating_N("cylindrical", **geom)
    assert c0 == pytest.approx(44 * (1 - 0.15) * 14 * 7.5 * 7.5)


def test_tapered_uses_cos_alpha_in_gamma_and_in_the_formula():
    a = 15.0
    ca = math.cos(math.radians(a))
    dpw = 7.5 * ca / 0.15 * MM                  # gamma = 0.15 exactly
    geom = dict(rows=1, elements=16, element_diameter_m=7.5 * MM,
                element_length_m=12.0 * MM, pitch_diameter_m=dpw, contact_angle_deg=a)
    c = rating.dynamic_rating_N("tapered", **geom)
    assert c == pytest.approx(1.1 * 88.2 * (12.0 * ca) ** (7 / 9) * 16 ** 0.75
                              * 7.5 ** (29 / 27))
    c0 = rating.static_rating_N("tapered", **geom)
    assert c0 == pytest.approx(44 * 0.85 * 16 * 12.0 * 7.5 * ca)


def test_angular_contact_ball_rows_and_angle():
    a = 40.0
    ca = math.cos(math.radians(a))
    dpw = 7.938 * ca / 0.20 * MM                # gamma = 0.20: f_c 59.9, f_0 14.0
    geom = dict(rows=1, elements=12, element_diameter_m=7.938 * MM, pitch_diameter_m=dpw,
                contact_angle_deg=a)
    c = rating.dynamic_rating_N("angular_ball", **geom)
    assert c == pytest.approx(1.3 * 59.9 * ca ** 0.7 * 12 ** (2 / 3) * 7.938 ** 1.8)
    c2 = rating.dynamic_rating_N("angular_ball", **{**geom, "rows": 2})
    assert c2 / c == pytest.approx(2 ** 0.7)
    c0 = rating.static_rating_N("angular_ball", **{**geom, "rows": 2})
    assert c0 == pytest.approx(14.0 * 2 * 12 * 7.938 ** 2 * ca)


def test_large_ball_branch_meets_the_small_ball_branch_at_25_4_mm():
    """ISO 281: 3.647 D_w^1.4 above 25.4 mm; 3.647 = 25.4^0.4, so C is continuous."""
    def c(dw_mm):
        return rating.dynamic_rating_N("ball", rows=1, elements=10,
                                       element_diameter_m=dw_mm * MM,
                                       pitch_diameter_m=dw_mm / 0.2 * MM)
    below, above = c(25.4), c(25.4 + 1e-9)
    assert above == pytest.approx(below, rel=1e-4)
    assert c(30.0) == pytest.approx(1.3 * 59.9 * 10 ** (2 / 3) * 3.647 * 30.0 ** 1.4)


# -- 3. bad input ------------------------------------------------------------------------

BALL = dict(rows=1, elements=9, element_diameter_m=7.94 * MM, pitch_diameter_m=39.04 * MM)
ROLLER = dict(rows=1, elements=14, element_diameter_m=7.5 * MM, element_length_m=7.5 * MM,
              pitch_diameter_m=50.0 * MM)


@pytest.mark.parametrize("func", [rating.dynamic_rating_N, rating.static_rating_N])
@pytest.mark.parametrize("kind, changes, names", [
    ("ball", dict(pitch_diameter_m=15.0 * MM), ["pitch_diameter_m", "0.529", "0.4"]),
    ("ball", dict(rows=2), ["rows", "2"]),
    ("ball", dict(rows=1.0), ["rows", "1.0"]),
    ("ball", dict(elements=0), ["elements", "0"]),
    ("ball", dict(element_diameter_m=-1e-3), ["element_diameter_m", "-0.001"]),
    ("ball", dict(pitch_diameter_m=0.0), ["pitch_diameter_m", "0.0"]),
    ("ball", dict(contact_angle_deg=60.0), ["contact_angle_deg", "60.0", "45"]),
    ("ball", dict(contact_angle_deg=float("nan")), ["contact_angle_deg", "nan"]),
    ("ball", dict(element_length_m=5e-3), ["element_length_m", "0.005"]),
    ("cylindrical", dict(element_length_m=None), ["element_length_m", "None"]),
    ("cylindrical", dict(element_length_m=0.0), ["element_length_m", "0.0"]),
    ("needle", dict(rows=0), ["rows", "0"]),
])
def test_bad_input_raises_value_error_naming_the_parameter(func, kind, changes, names):
    base = BALL if kind in rating.BALL_TYPES else ROLLER
    with pytest.raises(ValueError) as info:
        func(kind, **{**base, **changes})
    for text in names:
        assert text in str(info.value)


@pytest.mark.parametrize("func", [rating.dynamic_rating_N, rating.static_rating_N])
def test_unknown_type_is_refused(func):
    with pytest.raises(ValueError, match="bearing_type = 'spherical'"):
        func("spherical", **BALL)


def test_gamma_outside_each_table_is_refused_with_its_range():
    with pytest.raises(ValueError, match=r"= 0\.005 is outside the valid range \[0\.01, 0\.4\]"):
        rating.fc_factor("ball", 0.005)
    with pytest.raises(ValueError, match=r"= 0\.35 is outside the valid range \[0\.01, 0\.3\]"):
        rating.fc_factor("cylindrical", 0.35)
    with pytest.raises(ValueError, match=r"= 0\.41 is outside the valid range \[0, 0\.4\]"):
        rating.f0_factor(0.41)
    # a roller bearing with gamma 0.35: no dynamic rating (Table 7 ends at 0.30) ...
    thick = {**ROLLER, "pitch_diameter_m": 7.5 / 0.35 * MM}
    with pytest.raises(ValueError, match="pitch_diameter_m"):
        rating.dynamic_rating_N("cylindrical", **thick)
    # ... but ISO 76's roller formula has no table: the static rating exists
    assert rating.static_rating_N("cylindrical", **thick) == pytest.approx(
        44 * 0.65 * 14 * 7.5 * 7.5)
