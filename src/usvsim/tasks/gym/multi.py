"""PettingZoo `ParallelEnv`: several WAM-Vs in one scene, each keeping station at its own goal (VRX score).

Agents `wamv_0 … wamv_{n-1}` start 20 m apart on a line north–south, heading east; each goal is sampled
5–15 m from its own start (seeded). Actions and observations per agent as `TaskEnv`'s `thrusters` /
`state`; reward: minus the agent's mean VRX pose error over the control period. Vessels can collide.
`step` needs an action for every live agent; all are checked before any is applied. No physics step goes
past `time_limit_s` (the last period is cut short when the limit is not a whole number of periods).
"""

from __future__ import annotations

import functools
import math
from typing import cast

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from usvsim.config.scenario import Scenario
from usvsim.core.clock import steps_per_period
from usvsim.tasks import levels
from usvsim.tasks.gym.env import check_action
from usvsim.tasks.pose_error import StationKeepingScorer
from usvsim.tasks.timing import check_seconds, limit_numba_threads


class MultiStationKeeping(ParallelEnv):
    metadata = {"name": "usvsim_multi_station_keeping_v0", "render_modes": []}

    def __init__(self, vessels: int = 2, difficulty: int = 0, control_rate_hz: float = 10.0,
                 time_limit_s: float = 60.0, numba_threads: int | None = 1):  # fmt: skip
        from usvsim.simulation import Simulation

        if isinstance(vessels, bool) or not isinstance(vessels, int) or vessels < 1:  # True was one vessel
            raise ValueError(f"vessels must be a whole number >= 1, not {vessels!r}")
        check_seconds("time_limit_s", time_limit_s, positive=True)
        limit_numba_threads(numba_threads)
        self.possible_agents = [f"wamv_{k}" for k in range(vessels)]
        self.starts = {a: (0.0, 20.0 * (k - (vessels - 1) / 2)) for k, a in enumerate(self.possible_agents)}
        self._scenario = Scenario.model_validate({
            "version": 1, "name": "multi_station_keeping", "environment": levels.environment(difficulty),
            "vessels": [{"name": a, "model": "wamv", "pose": {"position": [*self.starts[a], 0.0]}}
                        for a in self.possible_agents]})  # fmt: skip
        self.sim = Simulation(self._scenario, seed=0)
        self._every = steps_per_period(control_rate_hz, self.sim.clock.step_ns)
        self._limit_steps = round(time_limit_s * 1e9 / self.sim.clock.step_ns)
        if self._limit_steps < 1:
            self.sim.close()
            raise ValueError(f"time_limit_s {time_limit_s:g} is shorter than one physics step "
                             f"({self.sim.clock.step_ns / 1e9:g} s)")  # fmt: skip
        self.agents: list[str] = []

    @functools.cache  # noqa: B019 - one space object per agent, as PettingZoo expects
    def observation_space(self, agent):
        return spaces.Box(-np.inf, np.inf, (13,), np.float32)

    @functools.cache  # noqa: B019
    def action_space(self, agent):
        return spaces.Box(-1.0, 1.0, (4,), np.float32)

    def reset(self, seed: int | None = None, options: dict | None = None):
        entropy = cast(int, np.random.SeedSequence().entropy)  # drawn from the OS when none is given: an int
        seed = int(seed) if seed is not None else entropy % (2**31)
        self.sim.reset(seed=seed)  # exact: a fresh start with `seed`, the compiled model kept
        rng = np.random.default_rng(seed)
        self.scorers = {}
        for a in self.possible_agents:
            r, b, yaw = rng.uniform(5, 15), rng.uniform(-math.pi, math.pi), rng.uniform(-math.pi, math.pi)
            x0, y0 = self.starts[a]
            self.scorers[a] = StationKeepingScorer((x0 + r * math.cos(b), y0 + r * math.sin(b), yaw))
        self.agents = list(self.possible_agents)
        return {a: self._observe(a) for a in self.agents}, {a: {} for a in self.agents}

    def step(self, actions):
        if not self.agents:
            raise RuntimeError("every agent is done: call reset() before step()")
        unknown = [a for a in actions if a not in self.agents]
        if unknown:
            raise ValueError(f"actions for unknown or finished agents {unknown}; agents are {self.agents}")
        checked = {a: check_action(act, 4) for a, act in actions.items()}  # all checked before any is commanded
        missing = [a for a in self.agents if a not in actions]
        if missing:  # they kept their last command without a word
            raise ValueError(f"no action for agents {missing}: give one for every agent in env.agents")
        for a, act in checked.items():
            for t, u in zip(self.sim.vessels[a].thrusters.values(), act):
                t.command(float(u))
        sums = dict.fromkeys(self.agents, 0.0)
        n = min(self._every, self._limit_steps - self.sim.clock.steps)  # no physics step past the time limit
        for _ in range(n):
            self.sim.step()
            for a in self.agents:
                x, y, yaw = self._pose(a)
                sums[a] += self.scorers[a].update(x, y, yaw)
        truncated = self.sim.clock.steps >= self._limit_steps
        obs = {a: self._observe(a) for a in self.agents}
        rewards = {a: -sums[a] / n for a in self.agents}
        infos = {a: {"score": self.scorers[a].score} for a in self.agents}
        terms, truncs = dict.fromkeys(self.agents, False), dict.fromkeys(self.agents, truncated)
        if truncated:
            self.agents = []
        return obs, rewards, terms, truncs, infos

    def close(self):
        self.sim.close()

    def _pose(self, agent):
        v = self.sim.vessels[agent]
        s = self.sim.state
        p, r = s.pos[v.index], s.rot[v.index]
        return float(p[0]), float(p[1]), math.atan2(r[1, 0], r[0, 0])

    def _observe(self, agent):
        v = self.sim.vessels[agent]
        s, i = self.sim.state, v.index
        rot = s.rot[i]
        vel = rot.T @ self.sim.origin_velocity(i)
        roll, pitch = np.arctan2(rot[2, 1], rot[2, 2]), -np.arcsin(np.clip(rot[2, 0], -1.0, 1.0))
        thrust = [t.thrust_n / c.thrust.max_forward_n for t, c in zip(v.thrusters.values(), v.model.thrusters)]
        x, y, yaw = self._pose(agent)
        gx, gy, gyaw = self.scorers[agent].goal
        c, sn = math.cos(yaw), math.sin(yaw)
        ex, ey = c * (gx - x) + sn * (gy - y), -sn * (gx - x) + c * (gy - y)
        feats = [vel[0], vel[1], s.omega_body[i, 2], roll, pitch, *thrust, ex, ey, math.sin(gyaw - yaw), math.cos(gyaw - yaw)]
        return np.array(feats, dtype=np.float32)
