"""Full-physics traffic: line-of-sight (LOS) guidance that steers a scenario vessel along a route by setting
its velocity controller's reference (surge speed of the leg, zero sway, a yaw rate towards the LOS course).

Lookahead-based LOS (Fossen, Handbook of Marine Craft Hydrodynamics and Motion Control, 2nd ed., sec. 12.4):
course = leg direction + atan(-e / Δ) with e the cross-track error (left of the leg positive) and Δ the
lookahead distance; the next leg starts when the along-track distance comes within `accept_m` of the
leg's end. Angles are ENU yaw (rad, CCW from east).
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.core.transforms import wrap_angle


class LosPilot:
    def __init__(self, points, speeds, lookahead_m: float, accept_m: float, yaw_gain_1ps: float = 0.5,
                 max_yaw_rate: float = 0.3):  # fmt: skip
        self.points, self.speeds = np.asarray(points, float), np.asarray(speeds, float)
        self.lookahead_m, self.accept_m = lookahead_m, accept_m
        self.yaw_gain, self.max_yaw_rate = yaw_gain_1ps, max_yaw_rate
        self.leg = 0

    def reset(self) -> None:
        self.leg = 0

    def reference(self, pos_enu, yaw_rad: float) -> tuple[float, float, float]:
        """(surge m/s, sway m/s, yaw rate rad/s) for a vessel at pos_enu (x, y) heading yaw_rad."""
        while self.leg < len(self.points) - 1:
            a, b = self.points[self.leg], self.points[self.leg + 1]
            leg = b - a
            length = float(np.hypot(*leg))
            along = float(np.dot(np.asarray(pos_enu[:2]) - a, leg)) / max(length, 1e-9)
            if along < length - self.accept_m or self.leg == len(self.points) - 2 and along < length:
                break
            self.leg += 1
        if self.leg >= len(self.points) - 1:
            return 0.0, 0.0, 0.0
        a, b = self.points[self.leg], self.points[self.leg + 1]
        d = (b - a) / max(float(np.hypot(*(b - a))), 1e-9)
        rel = np.asarray(pos_enu[:2]) - a
        cross = d[0] * rel[1] - d[1] * rel[0]  # left of the leg: positive
        course = math.atan2(d[1], d[0]) + math.atan2(-cross, self.lookahead_m)
        rate = float(np.clip(self.yaw_gain * wrap_angle(course - yaw_rad), -self.max_yaw_rate, self.max_yaw_rate))
        return float(self.speeds[self.leg]), 0.0, rate
