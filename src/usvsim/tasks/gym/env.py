"""Gymnasium environments for the VRX tasks (`gymnasium.make("usvsim/StationKeeping-v0", ...)`).

One env step = one control period (10 Hz: 10 physics steps at 100 Hz); the task is scored at every physics
step as VRX does. Actions (normalized to [-1, 1]):
- `thrusters`: one normalized thrust per thruster (the vessel's own thrust map and dynamics apply);
- `velocity`: (u, v, r) references for base_link, body FLU, scaled by `VELOCITY_SCALE`, tracked by
  usvsim's velocity controller and thrust allocator.
Observation `state` (float32): base_link velocity (u, v m/s, r rad/s, body FLU), roll and pitch (rad),
thrusts / their maxima, then the task's features (goal offsets in the body frame, see docs/tasks.md).
`observation=("state", "lidar", "camera")` (any of them): a `Dict` space with those keys, the sensors' latest
readings (a planar LiDAR's ranges, an RGB image; tasks/gym/observations.py); `"state"` alone: the Box.
`terminated`: the task finished (course done, all animals circled); `truncated`: the time limit.
Reward: the task's shaping (station keeping: minus the mean VRX pose error of the period).
`reset(seed=s)` re-samples the task (goals) from s and restarts the simulation with `Simulation.reset(s)`:
exact (bit for bit a fresh start with seed s), no model rebuild.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from usvsim.core.clock import period_ns, steps_per_period
from usvsim.core.errors import UsvsimError
from usvsim.tasks.gym.observations import SENSORS, sensor_arrays, sensor_configs, sensor_spaces
from usvsim.tasks.library import TASKS
from usvsim.tasks.timing import TaskTiming, check_seconds, limit_numba_threads

VELOCITY_SCALE = np.array([2.0, 1.0, 0.5])  # m/s, m/s, rad/s at action ±1
OBSERVATIONS = ("state", *SENSORS)


class TaskEnv(gym.Env):
    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, task: str = "station_keeping", difficulty: int = 0, action_type: str = "thrusters",
                 observation=("state",), control_rate_hz: float = 10.0, time_limit_s: float = 60.0,
                 sea_state: int | None = None, render_mode: str | None = None, numba_threads: int | None = 1):  # fmt: skip
        from usvsim.simulation import Simulation

        observation = (observation,) if isinstance(observation, str) else tuple(observation)
        _check_options(task, action_type, observation, time_limit_s)
        if render_mode not in (None, *self.metadata["render_modes"]):  # 'rgb_aray' was taken: render() gave None
            raise ValueError(f"render_mode must be None or 'rgb_array', not {render_mode!r}")
        self.observation = observation
        limit_numba_threads(numba_threads)
        self.render_mode, self.action_type = render_mode, action_type
        self.metadata = {**self.metadata, "render_fps": control_rate_hz}  # one frame per step (RecordVideo's rate)
        try:  # a bad difficulty or sea state: a ValueError like every other bad argument here
            self.task = TASKS[task](difficulty, 0, TaskTiming(running_s=time_limit_s), sea_state)
        except UsvsimError as exc:
            raise ValueError(str(exc)) from None
        sensors = sensor_configs(observation, control_rate_hz)
        self._scenario = self.task.scenario({"sensors": sensors} if sensors else None)
        self.sim = Simulation(self._scenario, seed=0)
        try:
            self.task.bind(self.sim)  # a time limit under one physics step: ValueError
        except ValueError:
            self.sim.close()
            raise
        self.vessel = self.sim.vessels["wamv"]
        self._thrusters = list(self.vessel.thrusters.values())
        self._thruster_ids = [t._i for t in self._thrusters]
        self._max_thrust = np.array([t.thrust.max_forward_n for t in self.vessel.model.thrusters])
        self._every = steps_per_period(control_rate_hz, self.sim.clock.step_ns)
        self._controller, self._renderer = None, None
        n_act = self._n_act = len(self._thrusters) if action_type == "thrusters" else 3
        self.action_space = spaces.Box(-1.0, 1.0, (n_act,), np.float32)
        n_obs = 5 + len(self._thrusters) + self.task.n_features
        state = spaces.Box(-np.inf, np.inf, (n_obs,), np.float32)
        if observation == ("state",):
            self.observation_space = state
        else:
            parts: dict[str, spaces.Space] = {"state": state} if "state" in observation else {}
            self.observation_space = spaces.Dict(parts | sensor_spaces(observation))

    # -- gymnasium API ----------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        episode_seed = int(seed) if seed is not None else int(self.np_random.integers(2**31 - 1))
        self._restart(episode_seed)
        return self._observe(), self.task.info() | {"seed": episode_seed}

    def step(self, action):
        if self.task.finished:  # it went on stepping and rewarding a scored-out episode (as the multi env refuses)
            raise RuntimeError("the episode is over (terminated or truncated): call reset() before step()")
        self._act(action)
        for _ in range(self._every):
            self.sim.step()
            self.task.update()
            if self.task.finished:
                break
        terminated = self.task.completed
        truncated = not terminated and self.task.finished
        return self._observe(), float(self.task.reward()), terminated, truncated, self.task.info()

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        from usvsim.tasks.gym.render import ChaseRenderer

        if self._renderer is None:
            self._renderer = ChaseRenderer(self.sim)
        return self._renderer.frame(self.task.index)

    def close(self):
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        self.sim.close()

    # -- internals --------------------------------------------------------------------------
    def _restart(self, seed: int) -> None:
        """Task and simulation back to t = 0 with `seed` (`Simulation.reset`: exact, the model is kept)."""
        self.task.reset(seed)
        self.sim.reset(seed=seed)
        self.task.bind(self.sim)
        if self._controller is not None:
            self._controller.reset()

    def _act(self, action: np.ndarray) -> None:
        action = check_action(action, self._n_act)
        if self.action_type == "thrusters":
            for t, u in zip(self._thrusters, action):
                t.command(float(u))
            return
        if self._controller is None:
            from usvsim.tasks.solutions import reference_controller

            self._controller = reference_controller(self.sim)
        self._controller.apply(self.vessel, action * VELOCITY_SCALE, self._every * self.sim.clock.dt)

    def _observe(self):
        if self.observation == ("state",):
            return self._state()
        out = {"state": self._state()} if "state" in self.observation else {}
        return out | sensor_arrays(self.sim, self.observation)

    def _state(self) -> np.ndarray:
        s, i = self.sim.state, self.task.index
        r = s.rot[i].tolist()  # body FLU → world ENU; plain floats are cheaper than tiny numpy ops
        v = self.sim.origin_velocity(i).tolist()
        u = r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2]
        w = r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2]
        roll, pitch = math.atan2(r[2][1], r[2][2]), -math.asin(min(1.0, max(-1.0, r[2][0])))
        head = [u, w, float(s.omega_body[i, 2]), roll, pitch]
        thrust = (self.sim.thrusters.thrust[self._thruster_ids] / self._max_thrust).tolist()
        return np.array(head + thrust + self.task.features().tolist(), dtype=np.float32)


def check_arguments(**kwargs) -> None:
    """ValueError naming what is wrong with `TaskEnv(**kwargs)`, without building its simulation: what an env
    checks when it is made (a bad difficulty, observation, time limit, control rate, an unknown argument)."""
    import inspect

    try:
        bound = inspect.signature(TaskEnv).bind(**kwargs)
    except TypeError as exc:  # "got an unexpected keyword argument 'dificulty'"
        raise ValueError(f"{exc}; TaskEnv takes {', '.join(inspect.signature(TaskEnv).parameters)}") from None
    bound.apply_defaults()
    a = bound.arguments
    observation = (a["observation"],) if isinstance(a["observation"], str) else tuple(a["observation"])
    _check_options(a["task"], a["action_type"], observation, a["time_limit_s"])
    if a["render_mode"] not in (None, *TaskEnv.metadata["render_modes"]):
        raise ValueError(f"render_mode must be None or 'rgb_array', not {a['render_mode']!r}")
    threads = a["numba_threads"]
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int) or threads < 1):
        raise ValueError(f"numba_threads must be a positive integer (or None), not {threads!r}")
    try:
        task = TASKS[a["task"]](a["difficulty"], 0, TaskTiming(running_s=a["time_limit_s"]), a["sea_state"])
    except UsvsimError as exc:
        raise ValueError(str(exc)) from None
    step_ns = period_ns(task.scenario().world.physics_rate_hz)
    steps_per_period(a["control_rate_hz"], step_ns)
    if round(a["time_limit_s"] * 1e9 / step_ns) == 0:
        raise ValueError(f"the running time {a['time_limit_s']:g} s is shorter than one physics step "
                         f"({step_ns / 1e9:g} s): nothing would be scored")  # fmt: skip


def _check_options(task: str, action_type: str, observation: tuple, time_limit_s: float) -> None:
    """ValueError naming the first bad constructor argument."""
    if task == "perception":  # it ran: reward 0 and score 10 whatever the agent did (a report is no action)
        raise ValueError("perception has no env: its reports (class, position) are not thruster actions; score a "
                         "detector with task.scorer.report() in Python or /vrx/perception/landmark (docs/tasks.md)")
    if task not in TASKS:
        raise ValueError(f"task must be one of {[t for t in TASKS if t != 'perception']}, not {task!r}")
    if action_type not in ("thrusters", "velocity"):
        raise ValueError(f"action_type must be 'thrusters' or 'velocity', not {action_type!r}")
    unknown = [o for o in observation if o not in OBSERVATIONS]
    if unknown or not observation:
        raise ValueError(f"observation must be one or more of {OBSERVATIONS}, not {observation!r}")
    check_seconds("time_limit_s", time_limit_s, positive=True)


def check_action(action, n: int) -> np.ndarray:
    """An action as n floats clipped to [-1, 1]; ValueError for another shape or a non-finite value (a
    shorter action used to leave the remaining thrusters at their last command)."""
    try:
        values = np.asarray(action, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"action must be {n} numbers in [-1, 1], got {action!r}") from None
    if values.shape != (n,):
        raise ValueError(f"action must have shape ({n},), got shape {values.shape}")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"action must be finite, got {values}")
    return np.clip(values, -1.0, 1.0)
