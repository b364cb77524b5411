"""Full-physics traffic: pilots that steer a scenario vessel by setting its velocity controller's reference
(surge speed, zero sway, a yaw rate): `LosPilot` along a route or constant course, `TrackPilot` along a recorded
(AIS) track in time.

Lookahead-based LOS (Fossen, Handbook of Marine Craft Hydrodynamics and Motion Control, 2nd ed., sec. 12.4):
course = leg direction + atan(-e / Δ) with e the cross-track error (left of the leg positive) and Δ the
lookahead distance; the next leg starts when the along-track distance comes within `accept_m` of the
leg's end. A route ends at its first waypoint of speed 0 (the ship stops there for good, as a kinematic ship
does: motion.route_track) or its last; past the end the pilot holds (no surge, no turning). Angles are ENU yaw
(rad, CCW from east).
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.core.transforms import wrap_angle


class LosPilot:
    def __init__(self, points, speeds, lookahead_m: float, accept_m: float, yaw_gain_1ps: float = 0.5,
                 max_yaw_rate: float = 0.3):  # fmt: skip
        points, speeds = np.asarray(points, float), np.asarray(speeds, float)
        stops = np.flatnonzero(speeds[: len(points) - 1] <= 0.0)
        end = int(stops[0]) + 1 if len(stops) else len(points)  # a speed-0 waypoint is the route's end
        self.points, self.speeds = points[:end], speeds[:end]
        self.lookahead_m, self.accept_m = lookahead_m, accept_m
        self.yaw_gain, self.max_yaw_rate = yaw_gain_1ps, max_yaw_rate
        self.leg = 0

    def reset(self) -> None:
        self.leg = 0

    def course(self, pos_enu) -> tuple[float, float] | None:
        """(course as ENU yaw rad, speed m/s) the LOS law asks of a vessel at pos_enu (x, y); None past the end."""
        while self.leg < len(self.points) - 1:
            a, b = self.points[self.leg], self.points[self.leg + 1]
            leg = b - a
            length = float(np.hypot(*leg))
            along = float(np.dot(np.asarray(pos_enu[:2]) - a, leg)) / max(length, 1e-9)
            if along < length - self.accept_m or self.leg == len(self.points) - 2 and along < length:
                break
            self.leg += 1
        if self.leg >= len(self.points) - 1:
            return None
        a, b = self.points[self.leg], self.points[self.leg + 1]
        d = (b - a) / max(float(np.hypot(*(b - a))), 1e-9)
        rel = np.asarray(pos_enu[:2]) - a
        cross = d[0] * rel[1] - d[1] * rel[0]  # left of the leg: positive
        return math.atan2(d[1], d[0]) + math.atan2(-cross, self.lookahead_m), float(self.speeds[self.leg])

    def leg_course(self) -> float:
        """Direction of the current leg (ENU yaw, rad): the course along the track, without the return to it."""
        leg = self.points[min(self.leg + 1, len(self.points) - 1)] - self.points[min(self.leg, len(self.points) - 2)]
        return math.atan2(leg[1], leg[0])

    def steer(self, course: float, speed: float, yaw_rad: float) -> tuple[float, float, float]:
        """(surge m/s, sway m/s, yaw rate rad/s) that turn a vessel heading yaw_rad towards `course` at `speed`."""
        rate = float(np.clip(self.yaw_gain * wrap_angle(course - yaw_rad), -self.max_yaw_rate, self.max_yaw_rate))
        return speed, 0.0, rate

    def reference(self, pos_enu, yaw_rad: float, t_s: float = 0.0) -> tuple[float, float, float]:
        """(surge m/s, sway m/s, yaw rate rad/s) for a vessel at pos_enu (x, y) heading yaw_rad (any time t_s)."""
        wanted = self.course(pos_enu)
        return (0.0, 0.0, 0.0) if wanted is None else self.steer(*wanted, yaw_rad)


class TrackPilot:
    """Time-based track following for a full-physics ship replaying a recorded (AIS) track: at time t the track
    gives where the ship should be, p_ref(t), and its velocity v_ref(t) (ENU); the wanted velocity is
    v_ref + k (p_ref - p) with the correction capped at `max_correction_mps` (feed-forward plus a proportional
    position loop, so along-track lag and cross-track error both decay at rate k); the ship steers towards the
    wanted velocity's course and holds its speed (surge = |v| cos(heading error), never astern)."""

    def __init__(self, table, gain_1ps: float = 0.25, max_correction_mps: float = 2.0, yaw_gain_1ps: float = 0.8,
                 max_yaw_rate: float = 0.3):  # fmt: skip
        self.table, self.gain, self.max_correction = table, gain_1ps, max_correction_mps
        self.yaw_gain, self.max_yaw_rate = yaw_gain_1ps, max_yaw_rate
        self._pos, self._vel, self._yaw = np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(1)

    def reset(self) -> None:
        pass  # a pure function of time and the ship's state

    def target(self, t_s: float) -> tuple[np.ndarray, np.ndarray, float]:
        """The track's position (m), velocity (m/s) and ENU yaw (rad) at t_s."""
        self.table.evaluate(t_s, self._pos, self._vel, self._yaw)
        return self._pos[0].copy(), self._vel[0].copy(), float(self._yaw[0])

    def reference(self, pos_enu, yaw_rad: float, t_s: float = 0.0) -> tuple[float, float, float]:
        """(surge m/s, sway m/s, yaw rate rad/s) for a vessel at pos_enu (x, y) heading yaw_rad at time t_s."""
        p_ref, v_ref, yaw_ref = self.target(t_s)
        correction = self.gain * (p_ref - np.asarray(pos_enu[:2], float))
        size = float(np.hypot(*correction))
        if size > self.max_correction:
            correction *= self.max_correction / size
        want = v_ref + correction
        speed = float(np.hypot(*want))
        if speed < 0.05:  # on the spot (before the track starts or after it ends): hold the track's heading
            course, speed = yaw_ref, 0.0
        else:
            course = math.atan2(want[1], want[0])
        error = wrap_angle(course - yaw_rad)
        rate = float(np.clip(self.yaw_gain * error, -self.max_yaw_rate, self.max_yaw_rate))
        return max(0.0, speed * math.cos(error)), 0.0, rate
