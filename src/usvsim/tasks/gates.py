"""Gates as VRX's navigation (follow-the-path) and wildlife scoring plugins define them.

A gate is a segment between a left and a right marker (world ENU, m). Its crossing direction is
ẑ × (left - right): with the red marker on the left of the gate definition, a vessel crossing in that
direction has red on its starboard side ("red right returning", VRX's `short_navigation_course`).
The vessel is BEFORE or AFTER the gate when its position projected on the gate line lies within the
gate's width (|y_gate| ≤ width / 2), else OUTSIDE.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum


class Side(Enum):
    OUTSIDE = 0
    BEFORE = 1
    AFTER = 2
    CROSSED = 3
    INVALID = 4


@dataclass(frozen=True)
class Gate:
    """Markers `left` and `right` as (x, y) world ENU m; `width_m` defaults to their distance."""

    left: tuple[float, float]
    right: tuple[float, float]
    width_m: float | None = None

    @property
    def centre(self) -> tuple[float, float]:
        return ((self.left[0] + self.right[0]) / 2.0, (self.left[1] + self.right[1]) / 2.0)

    @property
    def direction(self) -> tuple[float, float]:
        """Unit crossing direction ẑ × (left - right) / |left - right|."""
        dx, dy = self.left[0] - self.right[0], self.left[1] - self.right[1]
        n = math.hypot(dx, dy)
        return (-dy / n, dx / n)

    @property
    def yaw_rad(self) -> float:
        fx, fy = self.direction
        return math.atan2(fy, fx)

    def side(self, x_m: float, y_m: float) -> Side:
        """Where the point is relative to the gate (VRX `IsPoseInGate`)."""
        cx, cy = self.centre
        fx, fy = self.direction
        px, py = x_m - cx, y_m - cy
        along, across = px * fx + py * fy, -px * fy + py * fx
        width = self.width_m if self.width_m is not None else math.dist(self.left, self.right)
        if abs(across) > width / 2.0:
            return Side.OUTSIDE
        return Side.AFTER if along >= 0.0 else Side.BEFORE


class GateCourseScorer:
    """VRX navigation scoring: gates in order; points per gate, consecutive-gate bonus, completion bonus,
    penalty per collision (score never below 0). Higher is better.

    A gate counts when the vessel goes from BEFORE to AFTER; no gate after the first counts before the
    first is crossed; crossing a gate backwards (AFTER → BEFORE) invalidates it and breaks the streak.
    The course is finished when the last gate is crossed or invalidated.
    """

    def __init__(self, gates: list[Gate], points_per_gate: float = 10.0, bonus: float = 1.0,
                 collision_penalty: float = 3.0):  # fmt: skip
        self.gates, self.points, self.bonus, self.penalty = gates, points_per_gate, bonus, collision_penalty
        self.reset()

    def reset(self) -> None:
        self.states = [Side.OUTSIDE] * len(self.gates)
        self.last_crossed, self.last_success = -1, -(10**9)
        self.score, self.finished, self.collisions = 0.0, False, 0

    @property
    def gates_crossed(self) -> int:
        return sum(s is Side.CROSSED for s in self.states)

    def collide(self, count: int = 1) -> None:
        """Counted collisions (after the collision buffer): penalty each, floor 0."""
        self.collisions += count
        self.score = max(0.0, self.score - count * self.penalty)

    def update(self, x_m: float, y_m: float) -> None:
        if self.finished:
            return
        for i in range(self.last_crossed + 1, len(self.gates)):
            now = self.gates[i].side(x_m, y_m)
            if i != 0 and self.states[0] is not Side.CROSSED:
                break
            old = self.states[i]
            if old in (Side.INVALID, Side.CROSSED):
                continue
            if now is Side.AFTER and old is Side.BEFORE:
                self._crossed(i)
                return
            if i != 0 and now is Side.BEFORE and old is Side.AFTER:
                self.states[i], self.last_success, self.last_crossed = Side.INVALID, -(10**9), i
                self.finished = i == len(self.gates) - 1
                return
            self.states[i] = now

    def _crossed(self, i: int) -> None:
        self.states[i] = Side.CROSSED
        self.score += self.points
        if i != 0 and i == self.last_success + 1:
            self.score += self.bonus
        self.last_crossed = self.last_success = i
        if i == len(self.gates) - 1:
            self.score += self.bonus  # VRX adds one more bonus for completing the course
            self.finished = True
