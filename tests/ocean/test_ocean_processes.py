"""Gauss–Markov statistics, wind gusts, current profiles and the Ocean bundle."""

import math

import numpy as np
import pytest

from usvsim.ocean.current import Current, shear_factor
from usvsim.ocean.gauss_markov import GaussMarkov, vrx_gain_to_std
from usvsim.ocean.ocean import Ocean
from usvsim.ocean.wind import Wind


def test_gauss_markov_stationary_std_and_correlation_time():
    tau, dt = 5.0, 0.1
    gm = GaussMarkov(2.0, tau, np.random.default_rng(0), dt)
    path = np.array([gm.advance(dt * i) for i in range(1, 200001)])
    assert path.std() == pytest.approx(2.0, rel=0.03)
    lag = round(tau / dt)
    assert np.corrcoef(path[:-lag], path[lag:])[0, 1] == pytest.approx(math.exp(-1), abs=0.03)
    acf = [np.corrcoef(path[:-m], path[m:])[0, 1] for m in range(1, 400, 5)]
    assert np.sum(acf) * 5 * dt == pytest.approx(tau, rel=0.15)  # integral time scale


def test_gauss_markov_path_does_not_depend_on_how_it_is_advanced():
    a = GaussMarkov(1.0, 2.0, np.random.default_rng(4), 0.01)
    b = GaussMarkov(1.0, 2.0, np.random.default_rng(4), 0.01)
    for t in np.arange(0.01, 10.0001, 0.01):
        a.advance(t)
    b.advance(3.0)
    b.advance(10.0)
    assert a.value == pytest.approx(b.value, abs=1e-12)
    b.advance(5.0)  # never steps back
    assert b.time == pytest.approx(10.0)


def test_wind_gusts_have_the_vrx_gain_std_and_blow_toward_the_direction():
    wind = Wind(
        6.0, math.radians(240), np.random.default_rng(1), gust_gain=4.0, gust_time_constant_s=2.0, dt_s=0.05
    )
    speeds = []
    for i in range(1, 100001):
        wind.advance(0.05 * i)
        speeds.append(wind.speed)
    assert np.mean(speeds) == pytest.approx(6.0, abs=0.1)
    assert np.std(speeds) == pytest.approx(vrx_gain_to_std(4.0, 2.0), rel=0.05)
    assert vrx_gain_to_std(4.0, 2.0) == pytest.approx(2.0)
    v = wind.velocity()
    assert math.atan2(v[1], v[0]) == pytest.approx(math.radians(240) - 2 * math.pi)


def test_shear_profiles():
    z = np.array([1.0, 0.0, -2.0, -10.0, -20.0])
    np.testing.assert_allclose(shear_factor(z, "uniform", 10.0), 1.0)
    np.testing.assert_allclose(shear_factor(z, "linear", 10.0), [1, 1, 0.8, 0, 0])
    np.testing.assert_allclose(
        shear_factor(z, "exponential", 10.0), [1, 1, math.exp(-0.2), math.exp(-1), math.exp(-2)]
    )
    np.testing.assert_allclose(shear_factor(z, "power", 10.0), [1, 1, 0.8 ** (1 / 7), 0, 0])


def test_ocean_velocity_is_orbital_plus_current():
    current = Current(0.5, math.pi / 2, np.random.default_rng(0), profile="linear", shear_depth_m=4.0)
    ocean = Ocean(None, None, current, level_m=1.0)
    vel = ocean.velocity(np.zeros(2), np.zeros(2), np.array([1.0, -1.0]), 3.0)
    np.testing.assert_allclose(vel, [[0, 0.5, 0], [0, 0.25, 0]], atol=1e-12)
    np.testing.assert_allclose(ocean.elevation(np.zeros(3), np.zeros(3), 0.0), 1.0)
    np.testing.assert_allclose(ocean.normal(np.zeros(2), np.zeros(2), 0.0), [[0, 0, 1], [0, 0, 1]])


def test_time_varying_current_statistics():
    current = Current(
        1.0,
        0.0,
        np.random.default_rng(2),
        speed_std_mps=0.2,
        direction_std=0.1,
        time_constant_s=10.0,
        dt_s=0.5,
    )
    samples = []
    for i in range(1, 40001):
        current.advance(0.5 * i)
        samples.append(current.surface_velocity())
    samples = np.array(samples)
    speed = np.hypot(samples[:, 0], samples[:, 1])
    assert speed.std() == pytest.approx(0.2, rel=0.1)
    assert np.std(np.arctan2(samples[:, 1], samples[:, 0])) == pytest.approx(0.1, rel=0.1)
