"""VRX perception scoring: objects appear one after another; the team reports each object's class and
position (`/vrx/perception/landmark`: geometry_msgs/PoseStamped, class in header.frame_id, latitude and
longitude in pose.position.x / .y).

Per object (VRX `PerceptionScoringPlugin`): the object is active during (t, t + duration) of running
time (`show`/`hide` callbacks of `update` let the task move it into view and back, as VRX's StartTrial and
EndTrial do); each active object adds one attempt to the balance and removing it takes one away. Every report
burns one attempt (ignored at balance 0); a report of the right class sets the object's error to
min(2.0, its error, planar distance in m) while the object is active. An object never matched keeps
10.0. The score is the mean error per object (lower is better), final when all objects are gone; before
that, objects not yet shown count 10.0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

ERROR_CAP_M, ERROR_UNMATCHED_M = 2.0, 10.0


@dataclass
class PerceptionObject:
    """`kind` (class name as VRX spells it, e.g. mb_marker_buoy_red), appearance time (s of running time) and
    position (world ENU, m: where it is, for scoring)."""

    kind: str
    time_s: float
    x_m: float
    y_m: float
    duration_s: float = 5.0
    active: bool = False
    done: bool = False
    error_m: float = ERROR_UNMATCHED_M


class PerceptionScorer:
    def __init__(self, objects: list[PerceptionObject]):
        self.template = [(o.kind, o.time_s, o.x_m, o.y_m, o.duration_s) for o in objects]
        self.reset()

    def reset(self) -> None:
        self.objects = [PerceptionObject(*t) for t in self.template]
        self.balance, self.pending, self.total, self.finished = 0, [], 0.0, False

    @property
    def score(self) -> float:
        """The mean error per object: its final error once shown, its error so far while shown, 10 m before.
        It was NaN until the last object had gone (a time limit under 30 s: 'mean score nan', NaN in the JSON
        report, which strict JSON readers refuse)."""
        if self.finished:
            return self.total / len(self.objects)
        return sum(o.error_m for o in self.objects) / len(self.objects)

    def report(self, kind: str, x_m: float, y_m: float) -> None:
        """A team's report (class, world ENU position), processed at the next update like VRX's queue."""
        self.pending.append((kind, x_m, y_m))

    def active_objects(self) -> list[PerceptionObject]:
        return [o for o in self.objects if o.active]

    def update(self, elapsed_s: float, show=None, hide=None) -> None:
        """Objects appear and go at `elapsed_s` (s of running time), then the reports since the last update are
        scored. `show(i)` / `hide(i)` (optional) run when object i appears / goes, before any report is scored."""
        if self.finished:
            return
        for i, o in enumerate(self.objects):
            if o.time_s < elapsed_s < o.time_s + o.duration_s and not o.active and not o.done:
                o.active, self.balance = True, self.balance + 1
                if show is not None:
                    show(i)
            if elapsed_s > o.time_s + o.duration_s and o.active:
                self.balance = max(0, self.balance - 1)
                o.active, o.done = False, True
                self.total += o.error_m
                if hide is not None:
                    hide(i)
        if all(o.done for o in self.objects):
            self.finished = True
        self._process()

    def _process(self) -> None:
        for kind, x, y in self.pending:
            if self.balance == 0:
                break
            self.balance -= 1
            for o in self.objects:
                if o.kind == kind and o.active:
                    o.error_m = min(ERROR_CAP_M, o.error_m, math.hypot(x - o.x_m, y - o.y_m))
        self.pending.clear()
