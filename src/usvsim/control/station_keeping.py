"""Heading hold and position hold (station keeping): outer loops that produce velocity references.

Both are proportional loops closed around the velocity controller (whose integrators remove steady
disturbances such as current or wind, so the position and heading errors go to zero):

    r_ref = clamp(k_ψ · wrap(ψ_target - ψ), ±r_max)                        heading hold
    (u, v)_ref = clamp(k_p · R(ψ)ᵀ (p_target - p), |·| ≤ U_max)            fully actuated position hold

Gains default to a quarter of the inner reference bandwidth (1 rad/s), which keeps ≥ 60° phase margin
over the inner loop's critically damped reference model. An underactuated vessel (no sway authority,
e.g. the Otter) cannot hold position sideways: it turns toward the target and drives to it, then holds
the target heading, correcting only the along-ship error (`arrive_radius_m` switches between the two).
Frames: positions world ENU (m), yaw CCW from east (REP 103), velocities body FLU at base_link.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.core.errors import require_finite


def wrap_angle(angle_rad: float) -> float:
    """Angle wrapped to [-π, π)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def _clamp(x: float, limit: float) -> float:
    return min(max(x, -limit), limit)


def _check_positive(owner, *names: str) -> None:
    """InputError unless each field is a finite number > 0 (a NaN gain froze the vessel without a word)."""
    for name in names:
        require_finite(type(owner).__name__, name, getattr(owner, name))


@dataclass(frozen=True)
class Pose2D:
    """A planar target pose: position (x east, y north, m, world ENU) and yaw (rad, CCW from east)."""

    x_m: float
    y_m: float
    yaw_rad: float = 0.0


@dataclass(frozen=True)
class HeadingHold:
    """Yaw-rate reference that turns the vessel to a heading (shortest way round)."""

    gain_1ps: float = 0.25
    max_yaw_rate_rad_s: float = 0.3

    def __post_init__(self):
        _check_positive(self, "gain_1ps", "max_yaw_rate_rad_s")

    def yaw_rate(self, yaw_rad: float, target_yaw_rad: float) -> float:
        return _clamp(self.gain_1ps * wrap_angle(target_yaw_rad - yaw_rad), self.max_yaw_rate_rad_s)


@dataclass(frozen=True)
class StationKeeping:
    """Position and heading hold → velocity reference (u, v, r) for base_link, body FLU."""

    position_gain_1ps: float = 0.25
    heading: HeadingHold = HeadingHold()
    max_speed_mps: float = 1.0
    fully_actuated: bool = True
    arrive_radius_m: float = 2.0

    def __post_init__(self):
        _check_positive(self, "position_gain_1ps", "max_speed_mps", "arrive_radius_m")

    def velocity_reference(self, position_enu_m, yaw_rad: float, target: Pose2D) -> np.ndarray:
        dx, dy = target.x_m - float(position_enu_m[0]), target.y_m - float(position_enu_m[1])
        c, s = math.cos(yaw_rad), math.sin(yaw_rad)
        ex, ey = c * dx + s * dy, -s * dx + c * dy  # error in the body frame
        if self.fully_actuated:
            return np.array([*self._speed_limited(ex, ey), self.heading.yaw_rate(yaw_rad, target.yaw_rad)])
        return self._underactuated(ex, ey, math.hypot(dx, dy), math.atan2(dy, dx), yaw_rad, target)

    def _speed_limited(self, ex: float, ey: float) -> tuple[float, float]:
        u, v = self.position_gain_1ps * ex, self.position_gain_1ps * ey
        speed = math.hypot(u, v)
        scale = min(1.0, self.max_speed_mps / speed) if speed > 0 else 1.0
        return u * scale, v * scale

    def _underactuated(self, ex, ey, distance, bearing, yaw_rad, target) -> np.ndarray:
        if distance > self.arrive_radius_m:
            heading_error = wrap_angle(bearing - yaw_rad)
            u = _clamp(self.position_gain_1ps * distance, self.max_speed_mps) * max(
                0.0, math.cos(heading_error)
            )
            return np.array([u, 0.0, self.heading.yaw_rate(yaw_rad, bearing)])
        u = _clamp(self.position_gain_1ps * ex, self.max_speed_mps)
        return np.array([u, 0.0, self.heading.yaw_rate(yaw_rad, target.yaw_rad)])
