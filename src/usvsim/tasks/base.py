"""A task: a scenario (WAM-V + objects + a difficulty's sea and wind), a scorer updated every physics step,
VRX's task info, and the features a learning agent observes.

Lifecycle: `Task(difficulty, seed)` → `scenario()` → `bind(sim)` → `update()` after every physics step
(`score`, `finished`, `info()`); `reset(seed)` re-samples the layout (goals only: objects are fixed per
level, as in VRX's worlds) and clears the scorer. Frames: world ENU (m), yaw rad CCW from east.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Protocol

import mujoco
import numpy as np

from usvsim.config.scenario import Scenario
from usvsim.core.errors import InputError
from usvsim.tasks import levels
from usvsim.tasks.timing import CollisionCounter, TaskTiming

if TYPE_CHECKING:
    from usvsim.world.world import World

VESSEL = "wamv"


class Scorer(Protocol):
    """What every task's scorer offers the task (`collide()` is optional)."""

    @property
    def score(self) -> float: ...

    def reset(self) -> None: ...


class Task:
    sim: World  # set by `bind` (a Simulation also works: it delegates to its world)
    scorer: Scorer  # built by `sample`
    name = ""  # usvsim name (registry key); vrx_name is VRX's task_name
    vrx_name = ""
    higher_is_better = False
    collision_buffer_s = 3.0
    n_features = 0

    def __init__(self, difficulty: int = 0, seed: int = 0, timing: TaskTiming | None = None,
                 sea_state: int | None = None):  # fmt: skip
        self.environment = levels.environment(difficulty, sea_state)  # checks both (1.5 is no level)
        self.difficulty, self.sea_state = int(difficulty), sea_state
        self.timing = timing or TaskTiming()
        self.collisions = CollisionCounter(self.collision_buffer_s)
        self.seed = int(seed)
        self.sample(np.random.default_rng(self.seed))

    # -- scene -------------------------------------------------------------------------------
    def objects(self) -> list[dict]:
        """Scenario `objects` (fixed per difficulty)."""
        return []

    def sample(self, rng: np.random.Generator) -> None:
        """Draw the layout (goals) from a seed and build the scorer."""
        raise NotImplementedError

    def plan_marks(self) -> list[tuple[float, float, float | None, str]]:
        """What a plan view of the task shows (`usvsim map --task`): (x m, y m world ENU, heading rad or None,
        label) per goal, gate or target."""
        return []

    def scenario(self, extra_vessel: dict | None = None) -> Scenario:
        vessel = {"name": VESSEL, "model": "wamv", **(extra_vessel or {})}
        return Scenario.model_validate({
            "version": 1, "name": f"{self.name}_{self.difficulty}",
            "description": f"VRX {self.vrx_name} task, difficulty {self.difficulty} ({levels.LEVELS[self.difficulty]})",
            "environment": self.environment, "vessels": [vessel], "objects": self.objects(),
            "outputs": {"tf": {"world_to_odom": False}}})  # fmt: skip

    # -- running ----------------------------------------------------------------------------
    def bind(self, sim) -> None:
        """Attach to a running `World` (or a `Simulation`, which delegates to its world)."""
        self.sim = sim
        self.index = sim.vessels[VESSEL].index
        self.body_id = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_BODY, VESSEL)
        self.object_index = {name: b.index for name, b in sim.bodies.items()}
        self._clock = sim.clock
        step_s = sim.clock.step_ns / 1e9
        self._start_step = round(self.timing.start_s / step_s)
        self._end_step = self._start_step + round(self.timing.running_s / step_s)
        # no step at all: it ran none and scored NaN (station keeping) or inf (wayfinding)
        if self._end_step == self._start_step:
            raise InputError(f"the running time {self.timing.running_s:g} s is shorter than one physics step "
                             f"({step_s:g} s): nothing would be scored")  # fmt: skip
        self.clear()

    def reset(self, seed: int | None = None) -> None:
        if seed is not None:
            self.seed = int(seed)
            self.sample(np.random.default_rng(self.seed))
        self.clear()

    def clear(self) -> None:
        """Scorer and collisions back to the start (`self.scorer` is built by `sample`)."""
        self.collisions.reset()
        self.scorer.reset()
        self._finished = False

    def pose(self) -> tuple[float, float, float]:
        """Vessel base_link x, y (world ENU, m) and yaw (rad)."""
        s, i = self.sim.state, self.index
        x, y, _ = s.pos[i].tolist()
        (r00, _, _), (r10, _, _), _ = s.rot[i].tolist()
        return x, y, math.atan2(r10, r00)

    def object_xy(self, name: str) -> tuple[float, float]:
        p = self.sim.state.pos[self.object_index[name]]
        return float(p[0]), float(p[1])

    def in_contact(self) -> bool:
        d, m = self.sim.data, self.sim.model
        if d.ncon == 0:
            return False
        geoms = d.contact.geom[: d.ncon]
        return bool(np.any(m.geom_bodyid[geoms] == self.body_id))

    @property
    def state(self) -> str:
        return self.timing.state(self.sim.time, self.finished)

    @property
    def elapsed_s(self) -> float:
        return max(0.0, self.sim.time - self.timing.start_s)

    def update(self) -> None:
        """Call after every physics step: scores the state it reached, from the first step of the running phase
        to its last one (the state at the time limit included: that step's error was left out, so 4 s of
        station keeping had 399 samples and a wildlife run of 5 s scored 4.99 s). Collisions are counted from the
        start, in the initial and ready states too, as VRX's contact callback counts them in every state
        (`ScoringPlugin::OnContacts`); penalties and progress resets (`on_collision`) apply while it runs."""
        steps = self._clock.steps
        if steps > self._end_step or self._finished:
            return
        counted = self.in_contact() and self.collisions.update(self.sim.time, True)
        if steps <= self._start_step:
            return
        if counted:
            self.on_collision()
        self.score_step(*self.pose())
        if steps == self._end_step and not self._finished:
            self.on_time_out()

    def score_step(self, x_m: float, y_m: float, yaw_rad: float) -> None:
        raise NotImplementedError

    def on_collision(self) -> None:
        """A counted collision: scorers with a penalty or a reset (`collide`) get it."""
        collide = getattr(self.scorer, "collide", None)
        if collide is not None:
            collide()

    def on_time_out(self) -> None:
        """The last scored step at the time limit, the task not completed: scorers with a timeout rule
        (`time_out`, VRX's `OnFinished`) get it."""
        time_out = getattr(self.scorer, "time_out", None)
        if time_out is not None:
            time_out()

    @property
    def score(self) -> float:
        return self.scorer.score

    @property
    def completed(self) -> bool:
        """Done before the time limit (course completed, all animals circled, all objects shown)."""
        return self._finished

    @property
    def finished(self) -> bool:
        """Done (course completed) or out of time."""
        return self._finished or self._clock.steps >= self._end_step

    def info(self) -> dict:
        """VRX `/vrx/task/info` fields. The score reads 0 until the scorer has a sample, as VRX publishes it (the
        scorers' own nan or inf before that broke JSON, ROS floats and loggers averaging it after an auto-reset)."""
        t, start = self.sim.time, self.timing.start_s
        score = float(self.score)
        return {"name": self.vrx_name, "state": self.state, "ready_time": self.timing.initial_s,
                "running_time": start, "elapsed_time": self.elapsed_s,
                "remaining_time": max(0.0, start + self.timing.running_s - t),
                "timed_out": t >= start + self.timing.running_s, "num_collisions": self.collisions.count,
                "score": score if math.isfinite(score) else 0.0}  # fmt: skip

    # -- learning ---------------------------------------------------------------------------
    def features(self) -> np.ndarray:
        """Task features for a state observation (body-frame goal offsets etc.), length n_features."""
        return np.zeros(0)

    def reward(self) -> float:
        """Shaped reward for the last control period (see docs/tasks.md)."""
        return 0.0

    def reference_target(self):
        """What the built-in solution steers to now: a `Pose2D` (or None to stop)."""
        return None


def body_offset(x_m, y_m, yaw_rad, gx, gy) -> tuple[float, float]:
    """A world point (gx, gy) in the vessel's planar body frame (x forward, y left), m."""
    dx, dy = gx - x_m, gy - y_m
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    return c * dx + s * dy, -s * dx + c * dy
