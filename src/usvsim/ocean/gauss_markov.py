"""First-order Gauss–Markov (Ornstein–Uhlenbeck) processes, advanced on the simulation clock."""

from __future__ import annotations

import math

import numpy as np


def vrx_gain_to_std(gain: float, time_constant_s: float) -> float:
    """Stationary std of VRX's gust process v ← v + (1/τ)(-v + K/√dt·ξ) dt in the limit dt → 0: K/√(2τ)."""
    return gain / math.sqrt(2.0 * time_constant_s) if time_constant_s > 0 else 0.0


class GaussMarkov:
    """x' = -x/τ + noise, with stationary standard deviation `std` and correlation time `time_constant_s`.

    Advanced with the exact discretisation x ← e^{-dt/τ} x + std √(1 - e^{-2dt/τ}) ξ in fixed steps of `dt_s`,
    so the statistics do not depend on the step and the path depends only on the generator and the time.
    The autocorrelation is exp(-|lag|/τ). Starts at a draw from the stationary distribution. With std 0 the
    process is `constant` (0 for ever, no random numbers drawn), so its owner need not step it.
    """

    def __init__(self, std: float, time_constant_s: float, rng: np.random.Generator, dt_s: float = 0.01):
        if std < 0 or (time_constant_s <= 0 and std > 0) or dt_s <= 0:
            raise ValueError(
                f"need std >= 0, time constant > 0 and dt > 0, got {std}, {time_constant_s}, {dt_s}"
            )
        self.std = float(std)
        self.time_constant_s = float(time_constant_s)
        self.dt_s = float(dt_s)
        self._rng = rng
        self._phi = math.exp(-dt_s / time_constant_s) if self.std > 0 else 0.0
        self._kick = self.std * math.sqrt(1.0 - self._phi**2)
        self.value = self.std * float(rng.standard_normal()) if self.std > 0 else 0.0
        self._steps = 0
        self.constant = self.std == 0.0

    @property
    def time(self) -> float:
        """Time (s) of the last step taken (a constant process is never stepped: 0)."""
        return self._steps * self.dt_s

    def advance(self, t: float) -> float:
        """Step forward to the last whole step at or before time t (s); returns the value. Never steps back."""
        target = int(math.floor(t / self.dt_s + 1e-9))
        n = target - self._steps
        if n > 0 and self.std > 0:
            # imported here: scipy.signal takes ~1 s to import, and calm seas never need it
            from scipy.signal import lfilter

            path, _ = lfilter(
                [self._kick], [1.0, -self._phi], self._rng.standard_normal(n), zi=[self._phi * self.value]
            )
            self.value = float(path[-1])
        self._steps = max(self._steps, target)
        return self.value
