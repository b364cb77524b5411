"""Offscreen MuJoCo rendering with an exact pinhole projection: RGB + depth in one pass, segmentation in a second.

The GL context is EGL unless MUJOCO_GL names another backend (osmesa, glfw); it is created here, so it
works even when `mujoco` was imported before MUJOCO_GL was set. The camera is placed by overwriting
the scene's GL cameras after `mjv_updateScene`: position, forward (= optical z), up (= -optical y) and
an off-axis frustum from (fx, fy, cx, cy) at the near plane. Geoms come from a private MjData whose
kinematics are recomputed from the simulation's current qpos (MuJoCo's own `geom_xpos` lag one step).
Visible groups: visual (1) and water (2); collision geoms (3) are hidden.
"""

from __future__ import annotations

import os

import mujoco
import numpy as np

from usvsim.sensors.camera.intrinsics import Intrinsics

_R = mujoco.mjtRndFlag
SKY_ZENITH = np.array([0.55, 0.72, 0.92]) * 255  # the builder's skybox gradient (world/builder.py)
SKY_HORIZON = np.array([0.95, 0.97, 1.0]) * 255


def gl_context(width: int, height: int):
    backend = os.environ.get("MUJOCO_GL", "egl").lower()
    if backend == "osmesa":
        from mujoco.osmesa import GLContext
    elif backend == "glfw":
        from mujoco.glfw import GLContext
    else:
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        from mujoco.egl import GLContext
    return GLContext(width, height)


class PinholeRenderer:
    """Renders `Intrinsics` (no distortion) from a world pose. Not thread-safe; one GL context each."""

    def __init__(self, model: mujoco.MjModel, cam: Intrinsics, near: float, far: float, shadows=False, fog=False):
        self.model, self.cam, self.near, self.far = model, cam, near, far
        self.gl = gl_context(cam.width, cam.height)
        self.gl.make_current()
        samples = model.vis.quality.offsamples
        model.vis.quality.offsamples = 0  # no MSAA: 3-4x faster on llvmpipe, and labels stay crisp
        try:
            self.ctx = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        finally:
            model.vis.quality.offsamples = samples
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.ctx)
        self.rect = mujoco.MjrRect(0, 0, cam.width, cam.height)
        self.scene = mujoco.MjvScene(model, maxgeom=10_000)
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 0
        self.option.geomgroup[1] = self.option.geomgroup[2] = 1
        self.data = mujoco.MjData(model)
        self.free = mujoco.MjvCamera()
        self.pert = mujoco.MjvPerturb()
        self.flags = {_R.mjRND_SHADOW: shadows, _R.mjRND_REFLECTION: False, _R.mjRND_FOG: fog, _R.mjRND_SKYBOX: True}
        self._rgb = np.empty((cam.height, cam.width, 3), np.uint8)
        v, u = np.mgrid[0 : cam.height, 0 : cam.width]
        self._rays = np.stack([(u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, np.ones(u.shape)], axis=-1)
        self._rot = np.eye(3)
        self._depth = np.empty((cam.height, cam.width), np.float32)

    def update(self, qpos: np.ndarray, pos_world: np.ndarray, rot_optical: np.ndarray) -> None:
        """Pose the world (`qpos`) and the camera (optical frame → world rotation, origin in ENU m)."""
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mjv_updateScene(self.model, self.data, self.option, self.pert, self.free,
                               mujoco.mjtCatBit.mjCAT_ALL, self.scene)  # fmt: skip
        c, n, self._rot = self.cam, self.near, rot_optical
        left, right = -(c.cx + 0.5) * n / c.fx, (c.width - c.cx - 0.5) * n / c.fx
        top, bottom = (c.cy + 0.5) * n / c.fy, -(c.height - c.cy - 0.5) * n / c.fy
        for gl in self.scene.camera:
            gl.pos[:], gl.forward[:], gl.up[:] = pos_world, rot_optical[:, 2], -rot_optical[:, 1]
            gl.frustum_near, gl.frustum_far = n, self.far
            gl.frustum_center, gl.frustum_width = 0.5 * (left + right), 0.5 * (right - left)
            gl.frustum_bottom, gl.frustum_top = bottom, top
            gl.orthographic = 0

    def _render(self, segment: bool, skybox: bool = True) -> None:
        self.gl.make_current()
        for flag, on in self.flags.items():
            self.scene.flags[flag] = on and not segment
        self.scene.flags[_R.mjRND_SKYBOX] = skybox and not segment
        self.scene.flags[_R.mjRND_SEGMENT] = self.scene.flags[_R.mjRND_IDCOLOR] = segment
        mujoco.mjr_render(self.rect, self.scene, self.ctx)

    def rgb_depth(self, want_depth: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """(H, W, 3) uint8 and depth along optical z (m; NaN where nothing is nearer than `far`), top row first.

        MuJoCo's skybox writes depth, so with depth the sky is painted here instead, from the same gradient."""
        self._render(segment=False, skybox=not want_depth)
        mujoco.mjr_readPixels(self._rgb, self._depth if want_depth else None, self.rect, self.ctx)
        rgb = self._rgb[::-1].copy()
        if not want_depth:
            return rgb, None
        raw = self._depth[::-1].astype(np.float64)
        n, f = self.near, self.far
        if self.ctx.readDepthMap == mujoco.mjtDepthMap.mjDEPTH_ZERONEAR:  # window z: 0 at near, 1 at far
            depth = n / (1.0 - raw * (1.0 - n / f))
            empty = raw >= 1.0
        else:  # reversed Z: 1 at near, 0 at far
            depth = n / (raw + (1.0 - raw) * n / f)
            empty = raw <= 0.0
        depth = depth.astype(np.float32)
        empty |= depth >= 0.999 * f
        depth[empty] = np.nan
        up = self._rays[empty] @ self._rot[2]  # world z of each empty pixel's ray (unnormalized)
        t = np.clip(up / np.linalg.norm(self._rays[empty], axis=1), 0.0, 1.0)[:, None]
        rgb[empty] = (SKY_HORIZON + t * (SKY_ZENITH - SKY_HORIZON)).astype(np.uint8)
        return rgb, depth

    def segmentation(self) -> np.ndarray:
        """(H, W) uint16: MuJoCo geom id + 1 of the visible geom, 0 for sky/background."""
        self._render(segment=True)
        mujoco.mjr_readPixels(self._rgb, None, self.rect, self.ctx)
        img = self._rgb[::-1].astype(np.int32)
        seg = img[..., 0] + (img[..., 1] << 8) + (img[..., 2] << 16)  # scene geom index + 1
        lut = np.zeros(self.scene.ngeom + 1, np.uint16)
        for i in range(self.scene.ngeom):
            g = self.scene.geoms[i]
            if g.objtype == mujoco.mjtObj.mjOBJ_GEOM:
                lut[i + 1] = g.objid + 1
        return lut[np.clip(seg, 0, self.scene.ngeom)]

    def close(self) -> None:
        if self.gl is not None:
            self.gl.make_current()
            self.ctx.free()
            self.gl.free()
            self.gl = None
