"""Wind: mean speed plus Gauss–Markov gusts (the VRX `USVWind` form) and a direction.

Direction = where the wind blows toward, rad CCW from east (ENU); this is VRX's convention (its worlds give it
in degrees). The speed is at the reference height of the air-drag coefficients (10 m unless stated).
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.ocean.gauss_markov import GaussMarkov, vrx_gain_to_std


class Wind:
    """V(t) = V_mean + v_gust(t); v_gust is Gauss–Markov with time constant τ and VRX gain K (std K/√(2τ))."""

    def __init__(
        self,
        speed_mps: float = 0.0,
        direction: float = 0.0,
        rng: np.random.Generator | None = None,
        gust_gain: float = 0.0,
        gust_time_constant_s: float = 2.0,
        dt_s: float = 0.01,
    ):
        self.speed_mps = float(speed_mps)
        self.direction = float(direction)
        std = vrx_gain_to_std(gust_gain, gust_time_constant_s)
        rng = rng if rng is not None else np.random.default_rng(0)
        self.gust = GaussMarkov(std, gust_time_constant_s, rng, dt_s)

    @property
    def constant(self) -> bool:
        """No gusts: the velocity never changes."""
        return self.gust.constant

    def advance(self, t: float) -> None:
        self.gust.advance(t)

    @property
    def speed(self) -> float:
        """Current wind speed (m/s): mean plus gust."""
        return self.speed_mps + self.gust.value

    def velocity(self) -> np.ndarray:
        """Wind velocity (3,), ENU m/s, at the current time of the process."""
        v = self.speed
        return np.array([v * math.cos(self.direction), v * math.sin(self.direction), 0.0])
