"""Step-response tools for tuning and checking controllers in the real simulation (one vessel, flat sea)."""

from __future__ import annotations

import numpy as np

from usvsim.config.loader import parse_scenario
from usvsim.control.vessel_controller import ControlLoop, VesselController
from usvsim.simulation import Simulation


def one_vessel(model: str) -> Simulation:
    return Simulation(
        parse_scenario({"version": 1, "name": f"{model}_only", "vessels": [{"name": "boat", "model": model}]})
    )


class ClosedLoop:
    """sim + VesselController at 20 Hz; `run` logs (t, u, v, r) of base_link at every physics step."""

    def __init__(self, model: str, allocator: str = "constrained"):
        self.sim = one_vessel(model)
        self.vessel = self.sim.vessels["boat"]
        self.controller = VesselController.for_model(self.vessel.model, allocator=allocator)
        self.loop = ControlLoop(self.sim, "boat", self.controller, 20.0)

    def run(self, reference, seconds: float) -> np.ndarray:
        self.loop.reference = reference
        rows = []

        def on_step(sim):
            self.loop(sim)
            u, v, _ = self.vessel.velocity_body
            rows.append((sim.time, u, v, self.vessel.angular_velocity_body[2]))

        self.sim.run(seconds, on_step=on_step)
        return np.array(rows)

    def kick(self, sway_mps: float, yaw_rate_rad_s: float) -> None:
        """Add a sway velocity and a yaw rate to the vessel (an external disturbance)."""
        a = self.sim.world.qvel_adr[0]
        self.sim.data.qvel[a : a + 3] += self.sim.state.rot[0] @ np.array([0.0, sway_mps, 0.0])
        self.sim.data.qvel[a + 5] += yaw_rate_rad_s


def step_metrics(t: np.ndarray, y: np.ndarray, y0: float, y1: float) -> tuple[float, float]:
    """(overshoot % of the step, 2 % settling time s from t[0]) of a step y0 → y1."""
    e = (y - y0) / (y1 - y0)
    overshoot = max(0.0, float(e.max()) - 1.0) * 100.0
    outside = np.flatnonzero(np.abs(e - 1.0) > 0.02)
    settle = float(t[outside[-1]] - t[0] + (t[1] - t[0])) if len(outside) else 0.0
    return overshoot, settle
