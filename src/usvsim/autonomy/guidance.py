"""Path following: Fossen's lookahead-based line-of-sight (LOS) guidance into a velocity command.

For the path leg from p_k to p_k+1 with direction angle π_k (rad, CCW from east, map ENU), the along-track
and cross-track errors of the position p are (Fossen 2021, Handbook of Marine Craft Hydrodynamics §12.4)
    s = (p - p_k)·(cos π_k, sin π_k),  e = -(p_x - x_k) sin π_k + (p_y - y_k) cos π_k  (e > 0: left of the path),
and the desired course is χ_d = π_k - atan(e / Δ) with look-ahead distance Δ. Optionally (integral LOS,
Børhaug et al. 2008) χ_d = π_k - atan((e + σ_i·y_int) / Δ), ẏ_int = Δ e / (Δ² + (e + σ_i y_int)²), which removes
the steady cross-track offset that a current or wave drift causes.
The yaw-rate command turns the course error into r = k_χ·wrap(χ_d - χ), saturated at ±r_max, where the
course χ = ψ + β adds the sideslip β = atan2(v, u) once the boat moves. Surge slows in sharp turns
(u·cos²(course error)) and near the final point (√(2·a·d)), never above `speed_mps`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.core.errors import require_finite


def wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@dataclass
class LosGuidance:
    speed_mps: float = 1.5
    lookahead_m: float = 6.0
    course_gain_1ps: float = 0.4
    max_yaw_rate_radps: float = 0.5
    decel_mps2: float = 0.15
    integral_gain: float = 0.0  # σ_i of integral LOS; 0 = plain LOS

    def __post_init__(self):
        # a NaN speed or gain reached the velocity controller as a NaN reference, refused there, far from the cause
        for name, value in vars(self).items():
            require_finite("LosGuidance", name, value, zero_ok=name == "integral_gain")
        self.path = np.zeros((0, 2))
        self.leg, self.y_int = 0, 0.0

    def follow(self, path: np.ndarray) -> None:
        """A new path (k >= 2 points, map ENU m), followed from its first leg."""
        self.path, self.leg, self.y_int = np.asarray(path, float), 0, 0.0

    def errors(self, p: np.ndarray) -> tuple[float, float, float]:
        """(along-track m, cross-track m, leg angle rad) on the current leg; advances past finished legs."""
        while True:
            a, b = self.path[self.leg], self.path[self.leg + 1]
            d = b - a
            length = float(np.hypot(*d))
            angle = math.atan2(d[1], d[0])
            c, s = math.cos(angle), math.sin(angle)
            along = (p[0] - a[0]) * c + (p[1] - a[1]) * s
            if along < length or self.leg + 2 >= len(self.path):
                return along, -(p[0] - a[0]) * s + (p[1] - a[1]) * c, angle
            self.leg += 1

    def command(self, p: np.ndarray, yaw: float, nu: np.ndarray, dt: float) -> tuple[float, float]:
        """(surge m/s, yaw rate rad/s) for base_link at map position p, heading yaw, body velocity nu (u, v)."""
        _, e, angle = self.errors(p)
        delta = self.lookahead_m
        chi_d = angle - math.atan((e + self.integral_gain * self.y_int) / delta)
        if self.integral_gain > 0:
            self.y_int += dt * delta * e / (delta**2 + (e + self.integral_gain * self.y_int) ** 2)
        beta = math.atan2(nu[1], nu[0]) if nu[0] > 0.3 else 0.0
        error = wrap(chi_d - (yaw + beta))
        r = float(np.clip(self.course_gain_1ps * error, -self.max_yaw_rate_radps, self.max_yaw_rate_radps))
        remaining = float(np.hypot(*(self.path[-1] - p)))
        u = min(
            self.speed_mps * max(math.cos(error), 0.0) ** 2,
            math.sqrt(2.0 * self.decel_mps2 * remaining) + 0.2,
        )
        return u, r

    def cross_track(self, p: np.ndarray) -> float:
        """Cross-track error (m) of p on the current leg, without advancing."""
        leg = self.leg
        _, e, _ = self.errors(p)
        self.leg = leg
        return e
