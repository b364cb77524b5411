"""`render_mode="rgb_array"`: a chase view of the vessel from MuJoCo's renderer (EGL unless MUJOCO_GL says)."""

from __future__ import annotations

import os

import mujoco
import numpy as np


class ChaseRenderer:
    def __init__(self, sim, width: int = 320, height: int = 240):
        os.environ.setdefault("MUJOCO_GL", "egl")
        self.sim = sim
        self.renderer = mujoco.Renderer(sim.model, height, width)
        self.camera = mujoco.MjvCamera()
        self.camera.distance, self.camera.elevation = 30.0, -25.0

    def frame(self, body_index: int) -> np.ndarray:
        s = self.sim.state
        self.camera.lookat[:] = s.pos[body_index]
        self.camera.azimuth = float(np.degrees(np.arctan2(s.rot[body_index][1, 0], s.rot[body_index][0, 0]))) + 180.0
        self.renderer.update_scene(self.sim.data, self.camera)
        return self.renderer.render().copy()

    def close(self) -> None:
        self.renderer.close()
