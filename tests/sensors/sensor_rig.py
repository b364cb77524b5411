"""Helpers for sensor tests: a one-WAM-V simulation and a collector that runs a SensorSuite on it."""

from __future__ import annotations

import numpy as np
from pydantic import TypeAdapter

from usvsim.config.loader import parse_scenario
from usvsim.config.sensors import Sensor
from usvsim.simulation import Simulation

SENSOR = TypeAdapter(Sensor)


def sensor_configs(*dicts):
    return [SENSOR.validate_python(d) for d in dicts]


def make_sim(vessel_pose=None, objects=(), seed=0, rate_hz=100):
    vessel = {"name": "wamv", "model": "wamv"}
    if vessel_pose:
        vessel["pose"] = vessel_pose
    data = {"version": 1, "world": {"physics_rate_hz": rate_hz}, "vessels": [vessel], "objects": list(objects)}
    return Simulation(parse_scenario(data, "test"), seed=seed)


class Collector:
    """Runs `suite.on_step` after each step and keeps every envelope by topic."""

    def __init__(self, sim, suite):
        self.sim, self.suite, self.by_topic = sim, suite, {}

    def __call__(self, sim):
        for env in self.suite.on_step(sim):
            self.by_topic.setdefault(env.topic, []).append((sim.clock.now_ns, env))

    def run(self, seconds):
        self.sim.run(seconds, on_step=self)
        return self


def quat_angle(a, b) -> float:
    """Angle (rad) of the rotation between two unit quaternions (w, x, y, z)."""
    return 2.0 * np.arccos(min(1.0, abs(float(np.dot(a, b)))))
