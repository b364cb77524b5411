"""The VRX tasks: station keeping, wayfinding, perception, follow the path (navigation channel),
wildlife, gymkhana. Geometry is relative to the WAM-V's start pose (origin, heading east)."""

from __future__ import annotations

import math

import numpy as np

from usvsim.control.station_keeping import Pose2D
from usvsim.tasks.animals import ANIMALS, AnimalMotion
from usvsim.tasks.base import Task, body_offset
from usvsim.tasks.gates import Gate, GateCourseScorer
from usvsim.tasks.perception import PerceptionObject, PerceptionScorer
from usvsim.tasks.pose_error import StationKeepingScorer, WayfindingScorer, pose_error
from usvsim.tasks.wildlife import WildlifeScorer


def _goal_features(x, y, yaw, goal) -> list[float]:
    ex, ey = body_offset(x, y, yaw, goal[0], goal[1])
    d = goal[2] - yaw
    return [ex, ey, math.sin(d), math.cos(d)]


class StationKeeping(Task):
    """Hold a goal pose (sampled 5–15 m away, any heading); score: mean VRX pose error (m + rad)."""

    scorer: StationKeepingScorer
    name, vrx_name, n_features = "station_keeping", "station_keeping", 4

    def sample(self, rng):
        r, bearing, yaw = rng.uniform(5.0, 15.0), rng.uniform(-math.pi, math.pi), rng.uniform(-math.pi, math.pi)
        self.goal = (r * math.cos(bearing), r * math.sin(bearing), yaw)
        self.scorer = StationKeepingScorer(self.goal)

    def plan_marks(self):
        return [(*self.goal, "goal (hold)")]

    def clear(self):
        super().clear()
        self._period_sum, self._period_n = 0.0, 0

    def score_step(self, x, y, yaw):
        self._period_sum += self.scorer.update(x, y, yaw)
        self._period_n += 1

    def features(self):
        return np.array(_goal_features(*self.pose(), self.goal))

    def reward(self):
        """Minus the mean pose error over the control period: the return is −score × control steps."""
        r = -self._period_sum / self._period_n if self._period_n else 0.0
        self._period_sum, self._period_n = 0.0, 0
        return r

    def reference_target(self):
        return Pose2D(*self.goal)


class Wayfinding(Task):
    """Visit 3 waypoints (each 10–20 m on from the last, any heading); score: mean of per-waypoint minimum errors."""

    scorer: WayfindingScorer
    name, vrx_name, n_features = "wayfinding", "wayfinding", 15
    waypoint_count = 3

    def sample(self, rng):
        x = y = 0.0
        self.waypoints = []
        for _ in range(self.waypoint_count):
            r, b = rng.uniform(10.0, 20.0), rng.uniform(-math.pi / 2, math.pi / 2)
            x, y = x + r * math.cos(b), y + r * math.sin(b)
            self.waypoints.append((x, y, rng.uniform(-math.pi, math.pi)))
        self.scorer = WayfindingScorer(self.waypoints)

    def plan_marks(self):
        return [(x, y, yaw, f"waypoint {k + 1}") for k, (x, y, yaw) in enumerate(self.waypoints)]

    def clear(self):
        super().clear()
        self._last, self._target = None, 0

    def score_step(self, x, y, yaw):
        self.scorer.update(x, y, yaw)

    def features(self):
        x, y, yaw = self.pose()
        out = []
        for w, m in zip(self.waypoints, self.scorer.min_errors):
            out += _goal_features(x, y, yaw, w) + [min(m, 100.0)]
        return np.array(out)

    def reward(self):
        """Decrease of the score (mean of minima) over the control period."""
        now = self.scorer.score
        r = 0.0 if self._last is None or not math.isfinite(now) else self._last - now
        self._last = now if math.isfinite(now) else None
        return r

    def reference_target(self):
        x, y, yaw = self.pose()
        while self._target < len(self.waypoints) - 1 and pose_error(self.waypoints[self._target], x, y, yaw) < 0.5:
            self._target += 1
        return Pose2D(*self.waypoints[self._target])


def channel(difficulty: int, start_m: float = 15.0, spacing_m: float = 30.0, width_m: float = 20.0):
    """VRX `short_navigation_course_0` laid out eastward: 3 gates (red to starboard) 20 m wide, 30 m apart,
    first gate 15 m ahead; one black obstacle buoy 20 m past the first gate, 2 m inside the green side."""
    gates = [Gate(left=(start_m + k * spacing_m, -width_m / 2), right=(start_m + k * spacing_m, width_m / 2))
             for k in range(3)]  # fmt: skip
    objects = []
    for k, g in enumerate(gates):
        objects += [{"type": "buoy", "name": f"red_bound_{k}", "position": [*g.left, 0.0], "color": "red"},
                    {"type": "buoy", "name": f"green_bound_{k}", "position": [*g.right, 0.0], "color": "green"}]  # fmt: skip
    objects.append({"type": "buoy", "name": "obstacle_0", "position": [start_m + 20.0, width_m / 2 - 2.0, 0.0],
                    "color": "black", "radius_m": 0.5})  # fmt: skip
    return gates, objects


class FollowPath(Task):
    """Pass the gates of a buoy channel in order with red to starboard; +10 per gate, +1 consecutive bonus,
    +1 on completion, −3 per collision (10 s collision buffer). Higher is better."""

    scorer: GateCourseScorer
    name, vrx_name, n_features, higher_is_better = "follow_path", "follow_path", 6, True
    collision_buffer_s = 10.0

    def sample(self, rng):
        self.gates, self._objects = channel(self.difficulty)
        self.scorer = GateCourseScorer(self.gates)

    def plan_marks(self):
        return [(*g.centre, g.yaw_rad, f"gate {k + 1}") for k, g in enumerate(self.gates)]

    def objects(self):
        return self._objects

    def clear(self):
        super().clear()
        self._last = 0.0

    def score_step(self, x, y, yaw):
        self.scorer.update(x, y)
        self._finished = self.scorer.finished

    def next_gate(self) -> Gate:
        return self.gates[min(self.scorer.last_crossed + 1, len(self.gates) - 1)]

    def features(self):
        x, y, yaw = self.pose()
        g = self.next_gate()
        ex, ey = body_offset(x, y, yaw, *g.centre)
        ox, oy = body_offset(x, y, yaw, *self._objects[-1]["position"][:2])
        d = g.yaw_rad - yaw
        return np.array([ex, ey, math.sin(d), math.cos(d), ox, oy])

    def reward(self):
        r, self._last = self.scorer.score - self._last, self.scorer.score
        return r

    def reference_target(self):
        g = self.next_gate()
        fx, fy = g.direction
        cx, cy = g.centre
        return Pose2D(cx + 5.0 * fx, cy + 5.0 * fy, g.yaw_rad)  # aim 5 m beyond the gate's centre


class Wildlife(Task):
    """Circle the platypus clockwise and the turtle counter-clockwise, keep 10 m from the crocodile;
    score: elapsed s minus 30 s per goal met (when all circles are done, or at the time limit). Lower is better.
    The animals move as in VRX's wildlife world (tasks/animals.py): each shuttles between two waypoints."""

    scorer: WildlifeScorer
    name, vrx_name, n_features = "wildlife", "wildlife", 15
    collision_buffer_s = 10.0
    circle_radius_m = 6.0
    avoid_radius_m = 13.0  # the reference solution's berth around an animal to avoid (engagement: 10 m)

    def sample(self, rng):
        self.scorer = WildlifeScorer([(n, g) for n, (_, g) in ANIMALS.items()], time_limit_s=self.timing.running_s)
        self.motion = AnimalMotion(list(ANIMALS))

    def plan_marks(self):
        what = {"avoid": "keep 10 m off", "circumnavigate_clockwise": "circle clockwise",
                "circumnavigate_counterclockwise": "circle counter-clockwise"}  # fmt: skip
        return [(*xy, None, f"{name}: {what[goal]}") for name, (xy, goal) in ANIMALS.items()]

    def objects(self):
        colour = {"avoid": "green", "circumnavigate_clockwise": "orange", "circumnavigate_counterclockwise": "yellow"}
        return [{"type": "buoy", "name": n, "position": [*xy, 0.0], "color": colour[g], "radius_m": 0.6, "mooring": None}
                for n, (xy, g) in ANIMALS.items()]  # fmt: skip

    def bind(self, sim):
        super().bind(sim)
        self.motion.apply(sim)

    def clear(self):
        super().clear()
        self.motion.reset()
        self._last = 0.0

    def update(self):
        self.motion.apply(self.sim)  # the animals' forces for the next step
        super().update()

    def score_step(self, x, y, yaw):
        self.scorer.update(self.elapsed_s, x, y, [self.object_xy(n) for n in ANIMALS])
        self._finished = self.scorer.finished

    def features(self):
        x, y, yaw = self.pose()
        out = []
        for a in self.scorer.animals:
            ex, ey = body_offset(x, y, yaw, *self.object_xy(a.name))
            out += [ex, ey, a.gates_crossed / 8.0, float(a.state == "CIRCUMNAVIGATED"), float(a.state != "NEVER_ENGAGED")]
        return np.array(out)

    def reward(self):
        r, self._last = self._last - self.scorer.score, self.scorer.score
        return r

    def reference_target(self):
        """Circle each circling animal in turn on 12 points at 6 m (plus one extra quarter), around animals to
        avoid."""
        x, y, _ = self.pose()
        for a in self.scorer.animals:
            if a.circles and a.state != "CIRCUMNAVIGATED":
                ax, ay = self.object_xy(a.name)
                sense = 1.0 if a.goal == "circumnavigate_counterclockwise" else -1.0
                phase = math.atan2(y - ay, x - ax) + sense * math.radians(40.0)
                r = self.circle_radius_m if math.hypot(x - ax, y - ay) < 15.0 else 8.0
                tx, ty = self._around_avoided(x, y, ax + r * math.cos(phase), ay + r * math.sin(phase))
                return Pose2D(tx, ty, math.atan2(ty - y, tx - x))
        return None

    def _around_avoided(self, x, y, tx, ty):
        """(tx, ty), or a point `avoid_radius_m` beside an animal to avoid that lies near the straight way there."""
        for a in self.scorer.animals:
            if a.goal != "avoid":
                continue
            cx, cy = self.object_xy(a.name)
            dx, dy = tx - x, ty - y
            length = math.hypot(dx, dy) or 1.0
            along = ((cx - x) * dx + (cy - y) * dy) / length
            left = ((cx - x) * -dy + (cy - y) * dx) / length  # > 0: the animal lies left of the way
            if 0.0 < along < length and abs(left) < self.avoid_radius_m:
                nx, ny = -dy / length, dx / length  # unit normal to the left of the way
                sign = -1.0 if left > 0 else 1.0  # pass on the side away from the animal
                return cx + sign * self.avoid_radius_m * nx, cy + sign * self.avoid_radius_m * ny
        return tx, ty


PERCEPTION_OBJECTS = [  # VRX practice_2023_perception0: appearance time s, class, offset (x forward, y left) m in
    (5.0, "mb_marker_buoy_red", (7.8, 2.1), "red"),  # the WAM-V's body frame (FLU) when the object appears, colour
    (15.0, "mb_marker_buoy_green", (8.3, 0.1), "green"),
    (25.0, "mb_marker_buoy_white", (4.9, -2.32), "white"),
]
PERCEPTION_STASH_M = 1000.0  # where the objects wait out of sight (world ENU: this far south of the start, 10 m apart)


class Perception(Task):
    """Report each object's class and position while it is shown (5 s each); score: mean error per object
    (capped at 2 m when the class is right, 10 m if never matched). As VRX's StartTrial, an object appears at its
    offset from the WAM-V where it is then: (x forward, y left) m in the boat's body frame (FLU), turned by the
    boat's heading only (its roll and pitch are left out), at the still water level; after its window it goes
    back out of sight (VRX's EndTrial), `PERCEPTION_STASH_M` south of the start."""

    scorer: PerceptionScorer
    name, vrx_name = "perception", "perception"
    schedule = PERCEPTION_OBJECTS  # (appearance s, class, (x forward, y left) m, colour); `duration_s` each
    duration_s = 5.0

    def sample(self, rng):
        self.scorer = PerceptionScorer([PerceptionObject(k, t, *self._stash(i)[:2], self.duration_s)
                                        for i, (t, k, _, _) in enumerate(self.schedule)])  # fmt: skip

    def plan_marks(self):
        """Where the objects appear if the WAM-V is still at its start pose (origin, heading east)."""
        return [(*xy, None, f"{kind} at {t:g} s (offset from the WAM-V)") for t, kind, xy, _ in self.schedule]

    def objects(self):
        return [{"type": "buoy", "name": f"object_{i}", "position": list(self._stash(i)), "color": c, "mooring": None}
                for i, (_, _, _, c) in enumerate(self.schedule)]  # fmt: skip

    def _stash(self, i: int) -> tuple[float, float, float]:
        return 0.0, -PERCEPTION_STASH_M - 10.0 * i, 0.0

    def clear(self):
        for i in sorted(getattr(self, "_shown", ())):  # shown when the task was reset: out of sight again
            self._hide(i)
        self._shown: set[int] = set()
        super().clear()

    def score_step(self, x, y, yaw):
        self._sync()
        self.scorer.update(self.elapsed_s, show=self._show, hide=self._hide)
        self._finished = self.scorer.finished

    def _sync(self) -> None:
        for i, o in enumerate(self.scorer.objects):  # the buoys drift a little: score against where they are
            o.x_m, o.y_m = self.object_xy(f"object_{i}")

    def _show(self, i: int) -> None:
        """Object i to its offset from the WAM-V as it is now (VRX's StartTrial: the boat's position and yaw)."""
        x, y, yaw = self.pose()
        fwd, left = self.schedule[i][2]
        c, s = math.cos(yaw), math.sin(yaw)
        self.sim.bodies[f"object_{i}"].teleport((x + c * fwd - s * left, y + s * fwd + c * left, 0.0, 0.0, 0.0, yaw))
        self._shown.add(i)
        self._sync()

    def _hide(self, i: int) -> None:
        self.sim.bodies[f"object_{i}"].teleport((*self._stash(i), 0.0, 0.0, 0.0))
        self._shown.discard(i)

    def reference_target(self):
        return Pose2D(0.0, 0.0, 0.0)


class Gymkhana(FollowPath):
    """The channel, then hold position (no heading term) at a "black box" pinger 15 m past the last gate.
    Score, as VRX's gymkhana world runs it (practice_2022_gymkhana*_task.sdf): the black box's mean distance to
    the pinger, 200 while the channel is not completed, + 1 per collision (the world's `obstacle_penalty`).
    The black box is a station-keeping plugin with the task's own timing, so it samples from the start of the
    running state, the channel transit included. Lower is better."""

    name, vrx_name, n_features, higher_is_better = "gymkhana", "gymkhana", 8, False
    collision_penalty = 1.0
    collision_buffer_s = 3.0  # the world's gymkhana plugin sets none: VRX's default (it inherited follow_path's 10)

    def sample(self, rng):
        super().sample(rng)
        last = self.gates[-1]
        self.pinger = (last.centre[0] + 15.0 * last.direction[0], last.centre[1] + 15.0 * last.direction[1], 0.0)
        self.blackbox = StationKeepingScorer(self.pinger, heading=False)

    def plan_marks(self):
        return [*super().plan_marks(), (self.pinger[0], self.pinger[1], None, "pinger (hold)")]

    def clear(self):
        super().clear()
        self.blackbox.reset()

    def score_step(self, x, y, yaw):
        if not self.scorer.finished:
            self.scorer.update(x, y)
        self.blackbox.update(x, y, yaw)  # every running step (it sampled only after the channel)

    @property
    def score(self):
        base = self.blackbox.score if self.scorer.finished else 200.0
        return base + self.collision_penalty * self.collisions.count

    def features(self):
        x, y, yaw = self.pose()
        return np.array([*super().features(), *body_offset(x, y, yaw, *self.pinger[:2])])

    def reward(self):
        """Channel phase: gate points / 10; hold phase: minus the distance to the pinger."""
        if not self.scorer.finished:
            return super().reward() / 10.0
        return -self.blackbox.last_error

    def reference_target(self):
        if not self.scorer.finished:
            return super().reference_target()
        return Pose2D(self.pinger[0], self.pinger[1], self.gates[-1].yaw_rad)


TASKS: dict[str, type[Task]] = {t.name: t for t in (StationKeeping, Wayfinding, Perception, FollowPath, Wildlife, Gymkhana)}
