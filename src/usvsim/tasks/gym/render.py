"""`render_mode="rgb_array"`: a chase view of the vessel from MuJoCo's renderer (EGL unless MUJOCO_GL says), with
the sea's height field at the current time around the vessel (world/water_visual.py). Bodies are posed from the
current qpos in a private MjData (MuJoCo's own poses lag a step, and there are none before the first step)."""

from __future__ import annotations

import os

import mujoco
import numpy as np

from usvsim.world.water_visual import WaterUpload, refresh_water_visual


class ChaseRenderer:
    def __init__(self, sim, width: int = 320, height: int = 240):
        os.environ.setdefault("MUJOCO_GL", "egl")
        self.sim = sim
        self.renderer = mujoco.Renderer(sim.model, height, width)
        self.camera = mujoco.MjvCamera()
        self.camera.distance, self.camera.elevation = 30.0, -25.0
        self._water = WaterUpload()  # what this renderer's GL context holds of the water surface
        self.data = mujoco.MjData(sim.model)

    def frame(self, body_index: int) -> np.ndarray:
        s = self.sim.state
        self.camera.lookat[:] = s.pos[body_index]
        self.camera.azimuth = float(np.degrees(np.arctan2(s.rot[body_index][1, 0], s.rot[body_index][0, 0]))) + 180.0
        refresh_water_visual(self.sim, self.renderer, s.pos[body_index][:2], self._water)  # else the field it was made with
        self.data.qpos[:] = self.sim.data.qpos
        mujoco.mj_kinematics(self.sim.model, self.data)  # the water's and the traffic's geoms from the model too
        mujoco.mj_camlight(self.sim.model, self.data)  # the lights
        self.renderer.update_scene(self.data, self.camera)
        return self.renderer.render().copy()

    def close(self) -> None:
        self.renderer.close()
