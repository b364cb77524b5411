"""The IMU's Gauss–Markov bias (sensors/noise.py) against its closed form: driven as gz-sensors drives it,
`dynamic_bias_stddev` σ_b is a density (units/√s), the bias settles at σ_b·√(τ/2) and decorrelates as exp(-lag/τ)."""

from __future__ import annotations

import math

import numpy as np

from usvsim.config.sensors import AxisNoise
from usvsim.sensors.noise import TriadNoise


def test_dynamic_bias_settles_at_sigma_sqrt_half_tau_and_decorrelates_with_tau():
    sigma, tau, dt, n = 0.002, 5.0, 0.05, 200_000  # 10,000 s: 2,000 correlation times per axis
    noise = TriadNoise(AxisNoise(dynamic_bias_stddev=sigma, dynamic_bias_correlation_time_s=tau), dt,
                       np.random.default_rng(7))  # fmt: skip
    walk = np.empty((n, 3))
    for i in range(n):
        noise.apply(np.zeros(3))
        walk[i] = noise.bias
    walk = walk[int(10 * tau / dt) :]  # past the start at zero
    expected = sigma * math.sqrt(tau / 2.0)  # 3.16e-3, not 2e-3
    assert abs(walk.std(axis=0) / expected - 1.0).max() < 0.08
    for lag_s in (1.0, 5.0):
        k = int(lag_s / dt)
        rho = np.mean([np.corrcoef(walk[:-k, a], walk[k:, a])[0, 1] for a in range(3)])
        assert abs(rho - math.exp(-lag_s / tau)) < 0.05


def _allan_deviation(rate: np.ndarray, dt: float, m: int) -> np.ndarray:
    """Overlapping Allan deviation (per column) of rate samples at τ = m·dt."""
    angle = np.concatenate([np.zeros((1, rate.shape[1])), np.cumsum(rate, axis=0)]) * dt
    d2 = angle[2 * m :] - 2 * angle[m:-m] + angle[: -2 * m]
    return np.sqrt(np.mean(d2**2, axis=0) / (2 * (m * dt) ** 2))


def test_white_noise_stddev_is_per_sample_so_a_noise_density_converts_with_the_rate():
    """docs/sensor-realism.md: `stddev` = N·√rate_hz gives the Allan deviation N/√τ of a data sheet's noise
    density N at any rate (white noise only: ADEV at τ = 1 s is N)."""
    density = 2e-3  # rad/s/√Hz
    for rate_hz in (50.0, 400.0):
        dt = 1.0 / rate_hz
        noise = TriadNoise(AxisNoise(stddev=density * math.sqrt(rate_hz)), dt, np.random.default_rng(3))
        samples = np.array([noise.apply(np.zeros(3)) for _ in range(int(400 * rate_hz))])  # 400 s
        for tau in (0.1, 1.0):
            adev = _allan_deviation(samples, dt, int(round(tau * rate_hz)))
            assert abs(adev / (density / math.sqrt(tau)) - 1.0).max() < 0.08
