"""VRX pose error and the two scorers built on it: station keeping and wayfinding.

VRX (`StationkeepingScoringPlugin`, `WayfindingScoringPlugin`) samples the vessel's base_link pose at
every physics step while the task runs:

    d = hypot(x_goal - x, y_goal - y)                     planar distance, m (world ENU)
    e_ψ = π - | |ψ_goal - ψ| - π |                          heading error in [0, π], rad
    e = d + 0.75^d · e_ψ                                  (heading term optional: e = d)

Station keeping scores the running mean of e over all samples; wayfinding keeps, per waypoint, the
minimum e seen so far and scores the mean of those minima. Lower is better for both.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

HEADING_WEIGHT_BASE = 0.75  # VRX's k in d + k^d·e_ψ


def wrap_pi(angle_rad: float) -> float:
    """Angle wrapped to [-π, π)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def heading_error(goal_yaw_rad: float, yaw_rad: float) -> float:
    """VRX's absolute heading error in [0, π] for yaws in [-π, π) (rad)."""
    return math.pi - abs(abs(wrap_pi(goal_yaw_rad) - wrap_pi(yaw_rad)) - math.pi)


def pose_error(goal: Sequence[float], x_m: float, y_m: float, yaw_rad: float, heading: bool = True) -> float:
    """VRX pose error of a pose (x, y world ENU m, yaw rad) to `goal` = (x, y, yaw)."""
    d = math.hypot(goal[0] - x_m, goal[1] - y_m)
    if not heading:
        return d
    return d + HEADING_WEIGHT_BASE**d * heading_error(goal[2], yaw_rad)


class StationKeepingScorer:
    """Running mean of the pose error to one goal (x, y world ENU m, yaw rad). Lower is better."""

    def __init__(self, goal: Sequence[float], heading: bool = True):
        self.goal, self.heading = tuple(float(g) for g in goal), heading
        self.reset()

    def reset(self) -> None:
        self.samples, self.total, self.last_error = 0, 0.0, math.nan

    def update(self, x_m: float, y_m: float, yaw_rad: float) -> float:
        """Add one sample; returns its pose error."""
        self.last_error = pose_error(self.goal, x_m, y_m, yaw_rad, self.heading)
        self.total += self.last_error
        self.samples += 1
        return self.last_error

    @property
    def score(self) -> float:
        """Mean pose error so far (nan before the first sample)."""
        return self.total / self.samples if self.samples else math.nan


class WayfindingScorer:
    """Per-waypoint minimum pose error, scored as the mean of the minima. Lower is better."""

    def __init__(self, waypoints: Sequence[Sequence[float]]):
        self.waypoints = [tuple(float(c) for c in w) for w in waypoints]
        self.reset()

    def reset(self) -> None:
        self.min_errors = [math.inf] * len(self.waypoints)

    def update(self, x_m: float, y_m: float, yaw_rad: float) -> None:
        for i, w in enumerate(self.waypoints):
            self.min_errors[i] = min(self.min_errors[i], pose_error(w, x_m, y_m, yaw_rad))

    @property
    def score(self) -> float:
        """Mean over waypoints of the minimum error (inf before the first sample)."""
        return sum(self.min_errors) / len(self.min_errors)
