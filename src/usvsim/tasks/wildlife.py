"""VRX wildlife scoring: animals (buoys) to avoid, or to circle clockwise / counter-clockwise.

Per animal (VRX `WildlifeScoringPlugin`): the vessel is ENGAGED within `engagement_distance` (10 m) of
it. Circling is detected with 8 virtual gates, each a segment from the animal to a point at the
engagement distance at angle α = k·45° (world ENU), crossed counter-clockwise in the gate's forward
direction. While engaged, each gate crossed in the goal's direction counts one, a crossing the other
way resets the count, and leaving the engagement circle resets it too (so does a collision). Eight
counted crossings mark the animal CIRCUMNAVIGATED.

Score (lower is better): elapsed running time (capped at the time limit); when every circling goal is
done the task finishes and 30 s is subtracted per animal circled and per `avoid` animal never engaged. At the
time limit the same bonus is subtracted (`time_out()`: VRX's `OnFinished` sets the timeout score to the score
minus the bonus, used when it is positive).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from usvsim.tasks.gates import Gate, Side

GOALS = ("avoid", "circumnavigate_clockwise", "circumnavigate_counterclockwise")
VIRTUAL_GATES = 8


@dataclass
class Animal:
    """One animal with its goal (one of GOALS); state NEVER_ENGAGED / NOT_ENGAGED / ENGAGED / CIRCUMNAVIGATED."""

    name: str
    goal: str
    state: str = "NEVER_ENGAGED"
    gates_crossed: int = 0
    gate_states: list[Side] = field(default_factory=lambda: [Side.OUTSIDE] * VIRTUAL_GATES)

    def __post_init__(self):
        if self.goal not in GOALS:
            raise ValueError(f"animal {self.name!r}: goal must be one of {GOALS}, not {self.goal!r}")

    @property
    def circles(self) -> bool:
        return self.goal != "avoid"


def virtual_gates(x_m: float, y_m: float, radius_m: float) -> list[Gate]:
    """The 8 virtual gates around an animal at (x, y); forward direction counter-clockwise."""
    out = []
    for k in range(VIRTUAL_GATES):
        a = 2.0 * math.pi * k / VIRTUAL_GATES
        outer = (x_m + radius_m * math.cos(a), y_m + radius_m * math.sin(a))
        out.append(Gate(left=outer, right=(x_m, y_m), width_m=radius_m))
    return out


class WildlifeScorer:
    def __init__(self, animals: list[tuple[str, str]], engagement_distance_m: float = 10.0,
                 time_bonus_s: float = 30.0, time_limit_s: float = 300.0):  # fmt: skip
        self.names_goals, self.radius = animals, engagement_distance_m
        self.bonus, self.limit = time_bonus_s, time_limit_s
        self.reset()

    def reset(self) -> None:
        self.animals = [Animal(n, g) for n, g in self.names_goals]
        self.score, self.finished, self.collisions = 0.0, False, 0

    def collide(self, count: int = 1) -> None:
        """A counted collision resets every circling progress."""
        self.collisions += count
        for a in self.animals:
            a.gates_crossed = 0

    def update(self, elapsed_s: float, x_m: float, y_m: float, animal_xy: list[tuple[float, float]]) -> None:
        if self.finished:
            return
        self.score = min(self.limit, elapsed_s)
        for animal, (ax, ay) in zip(self.animals, animal_xy):
            if animal.state != "CIRCUMNAVIGATED":
                self._update_animal(animal, ax, ay, x_m, y_m)
        if all(a.state == "CIRCUMNAVIGATED" for a in self.animals if a.circles):
            self.score -= self.time_bonus()
            self.finished = True

    def time_out(self) -> None:
        """The time limit is reached before every circle is done: the bonus of the goals met so far is
        subtracted as VRX does (its timeout score, applied only when positive), and scoring stops."""
        if self.finished:
            return
        if self.score - self.time_bonus() > 0.0:
            self.score -= self.time_bonus()
        self.finished = True

    def time_bonus(self) -> float:
        done = [(a.goal == "avoid" and a.state == "NEVER_ENGAGED") or a.state == "CIRCUMNAVIGATED"
                for a in self.animals]  # fmt: skip
        return self.bonus * sum(done)

    def _update_animal(self, a: Animal, ax: float, ay: float, x_m: float, y_m: float) -> None:
        inside = math.hypot(x_m - ax, y_m - ay) <= self.radius
        if a.state in ("NEVER_ENGAGED", "NOT_ENGAGED"):
            if inside:
                a.state = "ENGAGED"
            return
        if not inside:
            a.state, a.gates_crossed = "NOT_ENGAGED", 0
            return
        if not a.circles:
            return
        for k, gate in enumerate(virtual_gates(ax, ay, self.radius)):
            now, old = gate.side(x_m, y_m), a.gate_states[k]
            if (now, old) in ((Side.AFTER, Side.BEFORE), (Side.BEFORE, Side.AFTER)):
                ccw = now is Side.AFTER
                right_way = ccw == (a.goal == "circumnavigate_counterclockwise")
                a.gates_crossed = a.gates_crossed + 1 if right_way else 0
                now = Side.CROSSED
            if a.gates_crossed == VIRTUAL_GATES:
                a.state = "CIRCUMNAVIGATED"
            a.gate_states[k] = now
