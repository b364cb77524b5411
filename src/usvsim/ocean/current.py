"""Ocean current: uniform or time-varying (Gauss–Markov speed and direction), optionally sheared with depth.

Direction = where the water flows toward, rad CCW from east (ENU). Depth profiles use z ≤ 0 below the still-water
level (points above it get the surface value). The current acts on vessels through the relative velocity, so it
is part of `Ocean.velocity`.
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.ocean.gauss_markov import GaussMarkov

PROFILES = ("uniform", "linear", "exponential", "power")


def shear_factor(z: np.ndarray, profile: str, depth_m: float) -> np.ndarray:
    """Fraction of the surface current at height z (m, ≤ 0 in the water).

    uniform: 1; linear: 1 + z/d down to 0 at z = -d; exponential: exp(z/d); power: (1 + z/d)^(1/7) (tidal 1/7-law
    over water depth d). Above the still-water level (z > 0) the factor is 1.
    """
    zc = np.minimum(np.asarray(z, dtype=float), 0.0)
    if profile == "uniform":
        return np.ones_like(zc)
    if profile == "linear":
        return np.clip(1.0 + zc / depth_m, 0.0, 1.0)
    if profile == "exponential":
        return np.exp(zc / depth_m)
    if profile == "power":
        return np.clip(1.0 + zc / depth_m, 0.0, 1.0) ** (1.0 / 7.0)
    raise ValueError(f"unknown shear profile {profile!r}; choose one of {PROFILES}")


class Current:
    """Surface current speed(t) = mean + GM, direction(t) = mean + GM, times a depth profile."""

    def __init__(
        self,
        speed_mps: float = 0.0,
        direction: float = 0.0,
        rng: np.random.Generator | None = None,
        speed_std_mps: float = 0.0,
        direction_std: float = 0.0,
        time_constant_s: float = 60.0,
        profile: str = "uniform",
        shear_depth_m: float = 10.0,
        dt_s: float = 0.1,
    ):
        if profile not in PROFILES:
            raise ValueError(f"unknown shear profile {profile!r}; choose one of {PROFILES}")
        self.speed_mps, self.direction = float(speed_mps), float(direction)
        self.profile, self.shear_depth_m = profile, float(shear_depth_m)
        rng = rng if rng is not None else np.random.default_rng(0)
        self.speed_noise = GaussMarkov(speed_std_mps, time_constant_s, rng, dt_s)
        self.direction_noise = GaussMarkov(direction_std, time_constant_s, rng, dt_s)

    @property
    def constant(self) -> bool:
        """No speed or direction variations: the current never changes."""
        return self.speed_noise.constant and self.direction_noise.constant

    def advance(self, t: float) -> None:
        self.speed_noise.advance(t)
        self.direction_noise.advance(t)

    def surface_velocity(self) -> np.ndarray:
        """Current at the surface now (ENU, m/s), shape (3,)."""
        speed = self.speed_mps + self.speed_noise.value
        heading = self.direction + self.direction_noise.value
        return np.array([speed * math.cos(heading), speed * math.sin(heading), 0.0])

    def velocity(self, z: np.ndarray) -> np.ndarray:
        """Current (n, 3), ENU m/s, at heights z (m)."""
        if self.profile == "uniform":
            return np.tile(self.surface_velocity(), (np.size(z), 1))
        return shear_factor(z, self.profile, self.shear_depth_m)[:, None] * self.surface_velocity()[None, :]
