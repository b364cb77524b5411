"""Spectra, spreading and dispersion against the reference numbers of physics.md §4.1–§4.3 and §4.7."""

import math

import numpy as np
import pytest

from usvsim.ocean import spectra

OMEGA = np.linspace(0.01, 10.0, 400001)


@pytest.mark.parametrize(
    "hs, tp, gamma, s_peak, m0",
    [
        (1.0, 6.0, 1.0, 0.08550, 0.06249),
        (1.0, 6.0, 3.3, 0.18546, 0.06264),
        (2.0, 8.0, 1.0, 0.45599, 0.24999),
        (2.0, 8.0, 2.0, 0.73055, 0.24945),
        (2.0, 8.0, 3.3, 0.98914, 0.25060),
        (2.0, 8.0, 5.0, 1.22681, 0.24999),
        (4.0, 10.0, 3.3, 4.94571, 1.00240),
    ],
)
def test_jonswap_table_4_7(hs, tp, gamma, s_peak, m0):
    wp = 2 * math.pi / tp
    assert spectra.jonswap(np.array([wp]), hs, tp, gamma)[0] == pytest.approx(s_peak, rel=1e-4)
    assert np.trapezoid(spectra.jonswap(OMEGA, hs, tp, gamma), OMEGA) == pytest.approx(m0, rel=2e-4)


def test_pierson_moskowitz_is_jonswap_with_gamma_one_and_m0_is_hs2_over_16():
    s = spectra.pierson_moskowitz(OMEGA, 3.0, 9.0)
    np.testing.assert_allclose(s, spectra.jonswap(OMEGA, 3.0, 9.0, 1.0))
    assert np.trapezoid(s, OMEGA) == pytest.approx(9.0 / 16.0, rel=1e-3)


def test_pm_from_wind_reference_values():
    hs, tp = spectra.pm_from_wind(10.0)
    # the reference rounds (4β/5)^{1/4} = 0.87716 to 0.877 and 2√(α/β) = 0.2092 to 0.21
    assert (4 * spectra.PM_BETA / 5) ** 0.25 == pytest.approx(0.877, abs=5e-4)
    assert 2 * math.pi / tp == pytest.approx(0.8603, rel=5e-4)
    assert tp == pytest.approx(7.303, rel=5e-4)
    assert hs == pytest.approx(2.141, rel=0.005)
    wind_form = (
        spectra.PM_ALPHA
        * spectra.G**2
        * OMEGA**-5
        * np.exp(-spectra.PM_BETA * (spectra.G / (10 * OMEGA)) ** 4)
    )
    np.testing.assert_allclose(spectra.pierson_moskowitz(OMEGA, hs, tp), wind_form, rtol=1e-10, atol=1e-300)


def test_dnv_gamma():
    assert spectra.dnv_gamma(2.5, 7.0) == pytest.approx(1.932, abs=1e-3)
    assert spectra.dnv_gamma(4.0, 6.0) == 5.0
    assert spectra.dnv_gamma(1.0, 8.0) == 1.0


@pytest.mark.parametrize(
    "s, c", [(1, 0.318310), (2, 0.424413), (5, 0.646725), (10, 0.903278), (15, 1.101689)]
)
def test_cos2s_normalisation(s, c):
    assert spectra.cos2s_norm(s) == pytest.approx(c, abs=1e-6)
    theta = np.linspace(-math.pi, math.pi, 200001)
    d = spectra.cos2s(theta, 0.7, s)
    assert np.trapezoid(d, theta) == pytest.approx(1.0, abs=1e-6)
    r1 = np.trapezoid(d * np.cos(theta - 0.7), theta)
    assert r1 == pytest.approx(spectra.cos2s_mean_resultant(s), abs=1e-6)


def test_cos2s_sampling_matches_the_distribution():
    rng = np.random.default_rng(0)
    theta = spectra.sample_cos2s(rng, 200000, 1.0, 5.0)
    assert np.mean(np.cos(theta - 1.0)) == pytest.approx(5.0 / 6.0, abs=3e-3)
    assert math.atan2(np.mean(np.sin(theta)), np.mean(np.cos(theta))) == pytest.approx(1.0, abs=5e-3)


@pytest.mark.parametrize(
    "period, depth, k",
    [
        (4.0, math.inf, 0.251519),
        (4.0, 10.0, 0.254628),
        (4.0, 5.0, 0.283050),
        (8.0, math.inf, 0.062880),
        (8.0, 10.0, 0.088622),
        (8.0, 5.0, 0.118369),
    ],
)
def test_dispersion_table_4_3(period, depth, k):
    omega = 2 * math.pi / period
    assert float(spectra.wavenumber(omega, depth)) == pytest.approx(k, abs=1e-6)
    assert float(spectra.angular_frequency(k, depth)) == pytest.approx(omega, rel=1e-5)


def test_phillips_follows_the_wind_and_chaos_lets_waves_run_against_it():
    kx, ky = np.array([0.5, -0.5, 0.0]), np.array([0.0, 0.0, 0.5])
    s = spectra.phillips(kx, ky, 10.0, 0.0, chaos=0.0)
    assert s[0] > 0 and s[1] == 0 and s[2] == 0
    s = spectra.phillips(kx, ky, 10.0, 0.0, chaos=1.0)
    assert s[1] > 0 and s[2] == pytest.approx(s[0] / 1.0)  # chaos 1: isotropic (w = 0.5)
    length = 100.0 / spectra.G
    expected = 0.2 / (2 * math.pi) ** 2 * math.exp(-1 / (0.5 * length) ** 2) / 0.5**4
    assert spectra.phillips(kx[:1], ky[:1], 10.0, 0.0)[0] == pytest.approx(expected)
