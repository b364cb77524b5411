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
