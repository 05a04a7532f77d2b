"""Tests of toothfem.efficiency.friction.

Reference values are computed here by hand in each formula's ORIGINAL units (GPa, cP,
um, lbf/in, in/s, ...), independently of the module's own unit conversion.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from toothfem.errors import ToothfemError
from toothfem.efficiency import friction as fr
from toothfem.efficiency.friction import (
    FrictionExtrapolationWarning,
    FrictionResult,
    MixedLubricationWarning,
    benedict_kelley,
    central_film_thickness_line,
    coulomb,
    ehl_xu2007,
    minimum_film_thickness_line,
)
from toothfem.fem.hertz import hertz_line, reduced_modulus

REL = 1e-12

# Xu et al. (2007) coefficients typed in again here, from the public reproductions.
B = dict(b1=-8.916465, b2=1.03303, b3=1.036077, b4=-0.354068, b5=2.812084,
         b6=-0.100601, b7=0.752755, b8=-0.390958, b9=0.620305)


def xu_by_hand(p_gpa, sr, ve_ms, nu_cp, r_m, s_um):
    """Xu (2007) in its own units: Ph GPa, Ve m/s, nu0 cP, R m, S um."""
    x = abs(sr) * p_gpa * math.log10(nu_cp)
    f = B["b1"] + B["b4"] * x + B["b5"] * math.exp(-x) + B["b9"] * math.exp(s_um)
    return (math.exp(f) * p_gpa ** B["b2"] * abs(sr) ** B["b3"] * ve_ms ** B["b6"]
            * nu_cp ** B["b7"] * r_m ** B["b8"])


@pytest.fixture
def quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MixedLubricationWarning)
        yield


# ------------------------------------------------------------------ Xu 2007

def test_coefficients_are_the_published_ones():
    assert tuple(B.values()) == fr.XU2007_COEFFICIENTS
    # The seed's Table 1 (3 decimals) agrees except for the lost sign of b1.
    seed = (8.916, 1.033, 1.036, -0.354, 2.812, -0.101, 0.752, -0.391, 0.620)
    for i, (ours, printed) in enumerate(zip(fr.XU2007_COEFFICIENTS, seed)):
        target = -printed if i == 0 else printed
        assert abs(ours - target) <= 1e-3 + 1e-12


@pytest.mark.parametrize("case", [
    # Ph GPa, SR, Ve m/s, nu0 cP, R m, S um
    (1.2, 0.4, 8.0, 12.0, 0.015, 0.35),
    (0.6, -0.9, 2.5, 40.0, 0.004, 0.8),
    (2.0, 0.05, 20.0, 4.0, 0.03, 0.1),
])
def test_xu_matches_hand_value_in_original_units(quiet, case):
    p, sr, ve, nu, r, s = case
    res = ehl_xu2007(p * 1e9, sr, ve, nu * 1e-3, r, s * 1e-6)
    assert isinstance(res, FrictionResult)
    assert res.mu == pytest.approx(xu_by_hand(p, sr, ve, nu, r, s), rel=REL)


def test_xu_typical_gear_magnitude(quiet):
    # 1 GPa, SR 0.3, 10 m/s, 10 cP, R 10 mm, S 0.3 um: a few hundredths, as in Xu (2007).
    mu = ehl_xu2007(1e9, 0.3, 10.0, 0.01, 0.01, 0.3e-6).mu
    assert 0.01 < mu < 0.03


def test_xu_vectorised_equals_scalar_loop(quiet):
    ph = np.array([0.5e9, 1.0e9, 1.8e9])
    sr = np.array([[0.1], [0.5]])
    res = ehl_xu2007(ph, sr, 5.0, 0.02, 0.012, 0.4e-6)
    assert res.mu.shape == (2, 3) and res.film_ratio.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            one = ehl_xu2007(ph[j], sr[i, 0], 5.0, 0.02, 0.012, 0.4e-6)
            assert res.mu[i, j] == pytest.approx(one.mu, rel=REL)
            assert res.film_ratio[i, j] == pytest.approx(one.film_ratio, rel=REL)
    assert isinstance(ehl_xu2007(1e9, 0.1, 5.0, 0.02, 0.01, 0.4e-6).mu, float)


def test_xu_mu_vanishes_with_slide_to_roll_ratio(quiet):
    args = (1e9, 10.0, 0.01, 0.01, 0.3e-6)
    assert ehl_xu2007(1e9, 0.0, *args[1:]).mu == 0.0
    srs = np.array([1e-2, 1e-4, 1e-6, 1e-8])
    mu = ehl_xu2007(1e9, srs, *args[1:]).mu
    assert np.all(np.diff(mu) < 0) and mu[-1] < 1e-9
    # mu ~ |SR|^b3 near zero, sign of SR ignored
    assert mu[2] / mu[3] == pytest.approx(100.0 ** B["b3"], rel=1e-5)   # exp(f) -> const
    assert ehl_xu2007(1e9, -0.3, *args[1:]).mu == ehl_xu2007(1e9, 0.3, *args[1:]).mu


def test_xu_trends_roughness_up_velocity_down(quiet):
    s = np.linspace(0.05e-6, 1.0e-6, 12)
    mu_s = ehl_xu2007(1e9, 0.3, 10.0, 0.01, 0.01, s).mu
    assert np.all(np.diff(mu_s) > 0)
    ve = np.linspace(0.05, 30.0, 12)
    mu_v = ehl_xu2007(1e9, 0.3, ve, 0.01, 0.01, 0.3e-6).mu
    assert np.all(np.diff(mu_v) < 0)


def test_xu_film_thickness_uses_hertz_load_and_dowson_toyoda():
    ph, r, ep, ve, eta = 1.1e9, 0.012, 2.3e11, 6.0, 0.015
    w = 2 * math.pi * ph**2 * r / ep               # Hertz: ph = sqrt(w E*/(pi R)), E* = E'/2
    assert hertz_line(w, r, ep / 2)[0] == pytest.approx(ph, rel=REL)
    res = ehl_xu2007(ph, 0.2, ve, eta, r, 0.0, e_prime=ep)
    assert res.film_thickness == pytest.approx(
        central_film_thickness_line(ve, eta, r, w, e_prime=ep), rel=REL)
    assert res.film_ratio == math.inf


# ------------------------------------------------------------------ lambda warning

def test_mixed_lubrication_warning_below_threshold_only():
    args = (1e9, 0.3, 5.0, 0.02, 0.01, 0.2e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lam = ehl_xu2007(*args).film_ratio
    assert 0 < lam < math.inf
    with pytest.warns(MixedLubricationWarning, match="lambda"):
        ehl_xu2007(*args, lambda_min=lam * 1.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ehl_xu2007(*args, lambda_min=lam * 0.99)


def test_default_threshold_is_three():
    thick = (1e9, 0.3, 20.0, 0.1, 0.02, 0.05e-6)     # lambda >> 3
    thin = (0.5e9, 0.3, 0.05, 0.02, 0.003, 0.4e-6)    # the sine-reducer case, lambda << 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert ehl_xu2007(*thick).film_ratio > 3.0
        assert ehl_xu2007(*thick[:-1], 0.0).film_ratio == math.inf
    with pytest.warns(MixedLubricationWarning):
        assert ehl_xu2007(*thin).film_ratio < 1.0


# ------------------------------------------------------------------ bad input

@pytest.mark.parametrize("kw, name, value", [
    (dict(eta0=-0.01), "eta0", "-0.01"),
    (dict(eta0=0.0), "eta0", "0.0"),
    (dict(ph=0.0), "ph", "0.0"),
    (dict(ph=-2e8), "ph", "-200000000.0"),
    (dict(r=0.0), "r", "0.0"),
    (dict(r=-0.01), "r", "-0.01"),
    (dict(ve=0.0), "ve", "0.0"),
    (dict(roughness=-1e-7), "roughness", "-1e-07"),
    (dict(sr=float("nan")), "sr", "nan"),
])
def test_xu_bad_input_names_parameter_value_and_range(kw, name, value):
    args = dict(ph=1e9, sr=0.2, ve=5.0, eta0=0.02, r=0.01, roughness=0.3e-6)
    args.update(kw)
    with pytest.raises(ToothfemError) as err:
        ehl_xu2007(**args)
    msg = str(err.value)
    assert msg.startswith(f"{name} = {value}")
    assert "valid range" in msg


def test_bad_array_element_is_located():
    with pytest.raises(ToothfemError, match=r"eta0\[1\] = -0\.5 is outside the valid range \(0, inf\)"):
        ehl_xu2007(1e9, 0.2, 5.0, [0.02, -0.5], 0.01, 0.3e-6)
    with pytest.raises(ToothfemError, match="not a number"):
        ehl_xu2007("abc", 0.2, 5.0, 0.02, 0.01, 0.3e-6)


# ------------------------------------------------------------------ Hertz

def test_reduced_modulus_by_hand():
    es = reduced_modulus(210e9, 0.3, 70e9, 0.3)
    assert es == pytest.approx(1.0 / (0.91 / 210e9 + 0.91 / 70e9), rel=REL)
    # steel/steel: E' = 2 E* is the documented default 2.3e11
    assert 2 * reduced_modulus(210e9, 0.3, 210e9, 0.3) == pytest.approx(fr.E_PRIME_STEEL, rel=5e-3)
    with pytest.raises(ToothfemError, match="nu1"):
        reduced_modulus(210e9, 0.6, 210e9, 0.3)


def test_hertz_line_nafems_like_case():
    # R = 50 mm cylinder on flat, E = 210/70 GPa, nu = 0.3, 35 kN per mm of length
    es = reduced_modulus(210e9, 0.3, 70e9, 0.3)
    p0, b = hertz_line(35e3 / 1e-3, 0.05, es)
    assert p0 == pytest.approx(3585e6, rel=1e-3)
    assert b == pytest.approx(6.21e-3, rel=1e-3)
    assert p0 == pytest.approx(math.sqrt(35e6 * es / (math.pi * 0.05)), rel=REL)


def test_hertz_line_vectorised_and_checked():
    p0, b = hertz_line(np.array([1e5, 4e5]), 0.01, 1e11)
    assert p0[1] / p0[0] == pytest.approx(2.0, rel=REL) and b[1] / b[0] == pytest.approx(2.0, rel=REL)
    with pytest.raises(ToothfemError, match=r"r_eq = 0\.0"):
        hertz_line(1e5, 0.0, 1e11)


# ------------------------------------------------------------------ film thickness

def test_dowson_toyoda_central_film_by_hand():
    ve, eta, r, w, ep, al = 4.0, 0.03, 0.008, 3.0e5, 2.2e11, 1.8e-8
    U, G, W = eta * ve / (ep * r), al * ep, w / (ep * r)
    hc = central_film_thickness_line(ve, eta, r, w, e_prime=ep, pressure_viscosity=al)
    assert hc == pytest.approx(3.06 * U**0.69 * G**0.56 * W**-0.10 * r, rel=REL)
    hmin = minimum_film_thickness_line(ve, eta, r, w, e_prime=ep, pressure_viscosity=al)
    assert hmin == pytest.approx(2.65 * U**0.70 * G**0.54 * W**-0.13 * r, rel=REL)
    assert 1.1 < hc / hmin < 1.6                      # central film ~ 4/3 of minimum


# ------------------------------------------------------------------ Benedict & Kelley

LBF_PER_IN = 4.4482216152605 / 0.0254               # N/m per lbf/in


@pytest.mark.parametrize("W, nu, vs, vr", [
    (1000.0, 10.0, 100.0, 1000.0),      # lbf/in, cP, in/s, in/s
    (3500.0, 4.0, 40.0, 2400.0),
])
def test_benedict_kelley_matches_us_units(W, nu, vs, vr):
    by_hand = 0.0127 * math.log10(3.17e8 * W / (nu * vs * vr**2))
    si = benedict_kelley(W * LBF_PER_IN, vs * 0.0254, vr * 0.0254, nu * 1e-3)
    assert si == pytest.approx(by_hand, rel=REL)


def test_benedict_kelley_si_forms_of_the_constant():
    w, vs, vr, eta = 2.0e5, 1.5, 12.0, 0.02          # N/m, m/s, m/s, Pa s
    mu = benedict_kelley(w, vs, vr, eta)
    # SI with eta in cP: constant 29.66 (rounded from 29.6625: |d mu| < 1e-6)
    assert mu == pytest.approx(0.0127 * math.log10(29.66 * w / (eta * 1e3 * vs * vr**2)), abs=1e-6)
    # seed Eq. 22 reading: 29.66e9 with W [N/mm], eta0 [Pa s], velocities [mm/s]
    seed = 0.0127 * math.log10(29.66e9 * (w / 1e3) / (eta * (vs * 1e3) * (vr * 1e3) ** 2))
    assert mu == pytest.approx(seed, abs=1e-6)


def test_benedict_kelley_roughness_factor():
    s = 0.4e-6                                        # m = 15.748 micro-inch
    c_r = 50.0 / (50.0 - 0.4 / 0.0254)
    assert benedict_kelley(2e5, 1.0, 10.0, 0.02, roughness=s) == pytest.approx(
        c_r * benedict_kelley(2e5, 1.0, 10.0, 0.02), rel=REL)
    with pytest.raises(ToothfemError, match="roughness"):
        benedict_kelley(2e5, 1.0, 10.0, 0.02, roughness=1.3e-6)


def test_benedict_kelley_singular_at_pitch_point_and_range_warning():
    with pytest.raises(ToothfemError, match=r"vs = 0\.0 is outside the valid range \(0, inf\)"):
        benedict_kelley(2e5, 0.0, 10.0, 0.02)
    mu = benedict_kelley(2e5, np.array([1.0, 0.1, 0.01]), 10.0, 0.02)
    assert np.all(np.diff(mu) > 0)                    # grows without bound as vs -> 0
    with pytest.warns(FrictionExtrapolationWarning):
        benedict_kelley(1e3, 50.0, 100.0, 0.5)


# ------------------------------------------------------------------ Coulomb

def test_coulomb_law_has_the_xu_call_shape():
    law = coulomb(0.06)
    res = law(np.array([1e9, 2e9]), 0.3, 5.0, 0.02, 0.01, 0.3e-6)
    assert isinstance(res, FrictionResult)
    assert np.all(res.mu == 0.06) and res.mu.shape == (2,) and np.all(np.isnan(res.film_ratio))
    assert law(ph=1e9, sr=0.1).mu == 0.06
    with pytest.raises(ToothfemError, match="mu = -0.1"):
        coulomb(-0.1)


# ------------------------------------------------------------------ roughness

def test_composite_rms_roughness_of_two_flanks():
    """sigma = sqrt(Rq1^2 + Rq2^2), Rq = 1.25 Ra: two 0.4 um flanks give sqrt(2) x 0.5 um =
    0.7071 um (the S the model fed Xu's law before it had a name: sqrt(2) x 1.25 x Ra); 0.3
    and 0.4 um give 1.25 x 0.5 um (a 3-4-5 triangle). Rounding only: 1e-15 relative."""
    assert fr.composite_rms_roughness(0.4e-6) == pytest.approx(
        math.sqrt(2.0) * 0.4e-6 * 1.25, rel=1e-15)
    assert fr.composite_rms_roughness(0.3e-6, 0.4e-6) == pytest.approx(0.625e-6, rel=1e-15)
    assert fr.composite_rms_roughness(0.0) == 0.0
    with pytest.raises(ToothfemError, match=r"ra2_m = -1e-07 is outside the valid range"):
        fr.composite_rms_roughness(0.4e-6, -1e-7)
