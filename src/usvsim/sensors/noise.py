"""Noise processes of inertial sensors (the gz-sensors / rotors_simulator IMU model, per axis).

reading = truth + bias_on + b + w, where
- w ~ N(0, stddev^2) white noise per sample;
- bias_on = ±N(bias_mean, bias_stddev^2), drawn once at start-up with a random sign;
- b is a first-order Gauss–Markov process with correlation time τ and driving stddev σ_d:
  b_k+1 = φ b_k + σ_b,d n,  φ = exp(-dt/τ),  σ_b,d = sqrt(-σ_d^2 τ/2 · expm1(-2 dt/τ)).
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.config.sensors import AxisNoise


class TriadNoise:
    """Noise of a 3-axis sensor sampled every `dt` seconds, drawing from `rng`."""

    def __init__(self, cfg: AxisNoise, dt: float, rng: np.random.Generator):
        self.cfg, self.rng = cfg, rng
        tau = cfg.dynamic_bias_correlation_time_s
        self.phi = math.exp(-dt / tau)
        self.sigma_bd = math.sqrt(-(cfg.dynamic_bias_stddev**2) * tau / 2.0 * math.expm1(-2.0 * dt / tau))
        self.turn_on = np.zeros(3)
        if cfg.bias_mean != 0.0 or cfg.bias_stddev > 0.0:
            self.turn_on = rng.normal(cfg.bias_mean, cfg.bias_stddev, 3) * np.where(rng.random(3) < 0.5, -1.0, 1.0)
        self.walk = np.zeros(3)

    @property
    def bias(self) -> np.ndarray:
        """Current total bias (turn-on + random walk)."""
        return self.turn_on + self.walk

    def apply(self, truth: np.ndarray) -> np.ndarray:
        """Advance the bias one sample and return the noisy reading."""
        if self.sigma_bd > 0.0:
            self.walk = self.phi * self.walk + self.rng.normal(0.0, self.sigma_bd, 3)
        white = self.rng.normal(0.0, self.cfg.stddev, 3) if self.cfg.stddev > 0 else 0.0
        return truth + self.bias + white

    @property
    def variance(self) -> float:
        """White-noise variance for the message covariance (bias excluded: it is unknown to the user)."""
        return self.cfg.stddev**2
