"""`render_mode="rgb_array"`: a chase view of the vessel from MuJoCo's renderer in a GL context of its own (EGL unless
MUJOCO_GL names another backend, as camera sensors: no display needed, whenever `mujoco` was imported), with the
sea's height field at the current time around the vessel (world/water_visual.py). Bodies are posed from the current
qpos in a private MjData (MuJoCo's own poses lag a step, and there are none before the first step)."""

from __future__ import annotations

import mujoco
import numpy as np

from usvsim.sensors.camera.render import RenderContext
from usvsim.world.water_visual import still_water_to_view


class ChaseRenderer:
    def __init__(self, sim, width: int = 320, height: int = 240):
        self.sim = sim
        self.context = RenderContext(sim.model, width, height)
        self.scene = mujoco.MjvScene(sim.model, maxgeom=10_000)
        self.option = mujoco.MjvOption()
        self.camera = mujoco.MjvCamera()
        self.camera.distance, self.camera.elevation = 30.0, -25.0
        self.rect = mujoco.MjrRect(0, 0, width, height)
        self.data = mujoco.MjData(sim.model)

    def frame(self, body_index: int) -> np.ndarray:
        s, model = self.sim.state, self.sim.model
        self.camera.lookat[:] = s.pos[body_index]
        self.camera.azimuth = float(np.degrees(np.arctan2(s.rot[body_index][1, 0], s.rot[body_index][0, 0]))) + 180.0
        self.context.refresh_water(self.sim, s.pos[body_index][:2])  # (current) else the field it was made with
        self.data.qpos[:] = self.sim.data.qpos
        mujoco.mj_kinematics(model, self.data)  # the water's and the traffic's geoms from the model too
        mujoco.mj_camlight(model, self.data)  # the lights
        mujoco.mjv_updateScene(model, self.data, self.option, None, self.camera, mujoco.mjtCatBit.mjCAT_ALL,
                               self.scene)  # fmt: skip
        eye = self.scene.camera[0]  # the sea beyond the drawn field, under the eye out to the far plane
        still_water_to_view(self.scene, model, eye.pos, float(eye.frustum_far))
        mujoco.mjr_render(self.rect, self.scene, self.context.ctx)
        rgb = np.empty((self.rect.height, self.rect.width, 3), np.uint8)
        mujoco.mjr_readPixels(rgb, None, self.rect, self.context.ctx)
        return rgb[::-1].copy()

    def close(self) -> None:
        self.context.close()
