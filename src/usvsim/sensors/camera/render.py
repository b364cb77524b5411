"""Offscreen MuJoCo rendering with an exact pinhole projection: RGB + depth in one pass, segmentation in a second.

The GL context is EGL unless MUJOCO_GL names another backend (osmesa, glfw); it is created here, so it
works even when `mujoco` was imported before MUJOCO_GL was set. One `RenderContext` (GL context + MjrContext)
serves all cameras of a suite: the drawn water surface is uploaded to it once per change, not once per camera.

The camera is placed by overwriting the scene's GL cameras after `mjv_updateScene`: position, forward (=
optical z), up (= -optical y) and an off-axis frustum from (fx, fy, cx, cy) at the near plane. Geoms come
from a private MjData whose kinematics are recomputed from the simulation's current qpos (MuJoCo's own
`geom_xpos` lag one step). Visible groups: visual (1) and water (2); collision geoms (3) are hidden.

Speed on llvmpipe (measured, see benchmarks/bench_sensors.py): the sky is never drawn by GL (MuJoCo's skybox
costs a third of the RGB pass and writes depth); the kernels paint it from the same gradient where depth is
empty. Planes are compiled with a coarse render grid (MuJoCo's default grid of up to 200 x 200 quads per
plane cost more than the rest of the scene; the plane is uniformly lit, so the image is unchanged), and the
offscreen buffer is only as large as the largest camera, without MSAA.

With `sim.look.renderer == "shader"` (docs/rendering.md) MuJoCo draws only the geoms, lit by the
look's sun and sky; `usvsim.rendering.MarinePass`, attached to this same GL context, then draws fog, sky and the
ocean into the same framebuffer and depth buffer (and the water, in its id colour, into the label pass), and the
kernels keep the drawn colours instead of painting the sky.
"""

from __future__ import annotations

import os
import weakref

import mujoco
import numpy as np

from usvsim.core.errors import UsvsimError
from usvsim.sensors.camera.intrinsics import Intrinsics
from usvsim.sensors.camera.kernels import (
    finish_rgb_depth,
    finish_segmentation,
    finish_segmentation_water,
    still_water_depth,
)
from usvsim.world.water_visual import STILL_WATER, WaterUpload, refresh_water_visual, still_water_to_view

_R = mujoco.mjtRndFlag
SKY_ZENITH = np.array([0.55, 0.72, 0.92]) * 255  # the builder's skybox gradient (world/builder.py)
SKY_HORIZON = np.array([0.95, 0.97, 1.0]) * 255
PLANE_RENDER_GRID_M = 1e6  # render-grid spacing of planes in sensor contexts: one quad (+ padding strips)
FORKED_AFTER_RENDER = (
    "a camera cannot render in a process forked after its parent rendered (OpenGL is not fork-safe): start the "
    "process with the 'spawn' method (multiprocessing.get_context(\"spawn\"); Gymnasium: gymnasium.make_vec(..., "
    "vectorization_mode=\"async\", vector_kwargs={\"context\": \"spawn\"}))"
)
_gl_pid: int | None = None  # the process that made a GL context (a forked child inherits its parent's pid here)


def check_gl_fork() -> None:
    """Raise in a process forked after its parent made a GL context: EGL/Mesa state copied by fork() is broken, and
    a new context there hangs for good (inside eglInitialize / MjrContext) instead of failing."""
    if _gl_pid is not None and _gl_pid != os.getpid():
        raise UsvsimError(FORKED_AFTER_RENDER)


def note_gl_context() -> None:
    """Record that this process made a GL context (see `check_gl_fork`)."""
    global _gl_pid
    _gl_pid = os.getpid()


def gl_context(width: int, height: int):
    check_gl_fork()
    backend = os.environ.get("MUJOCO_GL", "egl").lower()
    if backend == "osmesa":
        from mujoco.osmesa import GLContext
    elif backend == "glfw":
        from mujoco.glfw import GLContext
    else:
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        from mujoco.egl import GLContext
    note_gl_context()  # before the context: a fork during its making is as broken
    return GLContext(width, height)


def _free_context(gl, ctx: mujoco.MjrContext) -> None:
    """Free MuJoCo's GL objects in their own GL context, then the context: MuJoCo frees them in whatever context is
    current, which (when a dropped simulation is collected) is another simulation's, whose objects have the same
    ids. The current context stays current."""
    as_current = getattr(gl, "as_current", None)  # restores the context current before (EGL)
    if as_current is None:
        gl.make_current()
        ctx.free()
    else:
        with as_current():
            ctx.free()
    gl.free()


class RenderContext:
    """A GL context and its MjrContext for one model; offscreen buffer grown to the largest camera."""

    def __init__(self, model: mujoco.MjModel, width: int, height: int):
        self.model, self.width, self.height = model, width, height
        self.gl = gl_context(width, height)
        self.gl.make_current()
        quality, glob, planes = model.vis.quality, model.vis.global_, model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
        saved = quality.offsamples, glob.offwidth, glob.offheight, model.geom_size[planes, 2].copy()
        quality.offsamples, glob.offwidth, glob.offheight = 0, width, height  # no MSAA: labels stay crisp
        model.geom_size[planes, 2] = PLANE_RENDER_GRID_M
        try:
            self.ctx = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        finally:
            quality.offsamples, glob.offwidth, glob.offheight = saved[:3]
            model.geom_size[planes, 2] = saved[3]
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.ctx)
        self._free = weakref.finalize(self, _free_context, self.gl, self.ctx)  # also when dropped without close()
        self.water = WaterUpload()
        self.marine = None  # the shader passes (usvsim.rendering), made on first use

    def make_current(self) -> None:
        if self.gl is None:
            raise RuntimeError("the render context is closed")
        self.gl.make_current()

    def marine_look(self, sim, center_xy):
        """The shader passes ready for a frame of `sim` at its current look and time (None: MuJoCo's look)."""
        look = getattr(sim, "look", None)
        if look is None or look.renderer != "shader":
            return None
        from usvsim.rendering.frame import prepare

        self.make_current()
        if self.marine is None:
            from usvsim.rendering.marine import MarinePass

            self.marine = MarinePass()
        prepare(self.marine, sim, center_xy)
        return self.marine

    def fit(self, width: int, height: int) -> None:
        """Grow the offscreen buffer to hold a `width` x `height` image."""
        if width > self.width or height > self.height:
            self.width, self.height = max(width, self.width), max(height, self.height)
            self.make_current()
            mujoco.mjr_resizeOffscreen(self.width, self.height, self.ctx)
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.ctx)

    def refresh_water(self, sim, center_xy) -> None:
        """Draw the ocean's surface at `sim.time` around `center_xy` (world ENU, m); uploads only on change."""
        self.make_current()
        refresh_water_visual(sim, self.ctx, center_xy, self.water)

    def close(self) -> None:
        if self.gl is not None:
            self.gl.make_current()
            if self.marine is not None:
                self.marine.release()
            self._free()
            self.gl = None


class PinholeRenderer:
    """Renders `Intrinsics` (no distortion) from a world pose into a (shared) `RenderContext`."""

    def __init__(self, model: mujoco.MjModel, cam: Intrinsics, near: float, far: float, shadows=False, fog=False,
                 context: RenderContext | None = None):  # fmt: skip
        self.model, self.cam, self.near, self.far = model, cam, near, far
        self._own = context is None
        self.context = context or RenderContext(model, cam.width, cam.height)
        self.context.fit(cam.width, cam.height)
        self.rect = mujoco.MjrRect(0, 0, cam.width, cam.height)
        self.scene = mujoco.MjvScene(model, maxgeom=10_000)
        from usvsim.rendering.cull import FrustumCull

        self._cull = FrustumCull(self.scene)  # geoms outside the view are not drawn (same pixels, less vertex work)
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 0
        self.option.geomgroup[1] = self.option.geomgroup[2] = 1
        self.data = mujoco.MjData(model)
        self.free, self.pert = mujoco.MjvCamera(), mujoco.MjvPerturb()
        self.flags = {_R.mjRND_SHADOW: shadows, _R.mjRND_REFLECTION: False, _R.mjRND_FOG: fog, _R.mjRND_SKYBOX: False}
        self._gl_rgb = np.empty((cam.height, cam.width, 3), np.uint8)
        self._gl_depth = np.empty((cam.height, cam.width), np.float32)
        self._gl_ids = np.empty((cam.height, cam.width, 3), np.uint8)
        self._gl_water = np.empty((cam.height, cam.width), np.uint8)  # shader look: where the water is nearest
        self._intrinsics = np.array([cam.fx, cam.fy, cam.cx, cam.cy])
        self._up_optical = np.array([0.0, -1.0, 0.0])
        self.marine = None  # set per frame by `use_marine`: the shader passes, or None for MuJoCo's look
        self._plane = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, STILL_WATER)
        self._camera_z, self._level_m = 0.0, 0.0
        self._time_s = 0.0
        self._look_shadows = False

    def use_marine(self, sim, center_xy) -> None:
        """Choose the look of the next frames from `sim.look` (shader passes or MuJoCo's plain look)."""
        self.marine = self.context.marine_look(sim, center_xy)
        self.option.geomgroup[2] = int(self.marine is None)  # the shader draws its own water
        self._time_s = sim.time
        self._level_m = float(sim.ocean.level_m)  # the still water's mean level (MuJoCo's look: its depth)
        self._look_shadows = self.marine is not None and sim.look.shadows  # the sun's shadows on geoms

    @property
    def gl(self):
        return self.context.gl

    @property
    def ctx(self) -> mujoco.MjrContext:
        return self.context.ctx

    def update(self, qpos: np.ndarray, pos_world: np.ndarray, rot_optical: np.ndarray) -> None:
        """Pose the world (`qpos`) and the camera (optical frame → world rotation, origin in ENU m)."""
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)  # the lights' poses (the sun's direction was 0: no sun, no shadows)
        mujoco.mjv_updateScene(self.model, self.data, self.option, self.pert, self.free,
                               mujoco.mjtCatBit.mjCAT_ALL, self.scene)  # fmt: skip
        if self.marine is None:  # the plain look's water beyond the drawn field, out to the far plane
            still_water_to_view(self.scene, self.model, pos_world, self.far)
            for i in range(self.scene.nlight):  # the headlight looks where this camera looks (it kept the pose of
                if self.scene.lights[i].headlight:  # the unused free camera: north and down, whatever the heading)
                    self.scene.lights[i].pos[:], self.scene.lights[i].dir[:] = pos_world, rot_optical[:, 2]
        if self.marine is not None and self.marine.daylight is not None:
            from usvsim.rendering.frame import apply_lights

            apply_lights(self.scene, self.marine.daylight, self.marine.materials, self.marine.center_xy, self.far)
        c, n = self.cam, self.near
        self._up_optical = np.ascontiguousarray(rot_optical[2], dtype=np.float64)  # world z in the optical frame
        self._camera_z = float(pos_world[2])
        left, right = -(c.cx + 0.5) * n / c.fx, (c.width - c.cx - 0.5) * n / c.fx
        top, bottom = (c.cy + 0.5) * n / c.fy, -(c.height - c.cy - 0.5) * n / c.fy
        for gl in self.scene.camera:
            gl.pos[:], gl.forward[:], gl.up[:] = pos_world, rot_optical[:, 2], -rot_optical[:, 1]
            gl.frustum_near, gl.frustum_far = n, self.far
            gl.frustum_center, gl.frustum_width = 0.5 * (left + right), 0.5 * (right - left)
            gl.frustum_bottom, gl.frustum_top = bottom, top
            gl.orthographic = 0

    def _render(self, segment: bool, water_label_pass: bool = True) -> None:
        self.context.make_current()
        for flag, on in self.flags.items():
            self.scene.flags[flag] = on and not segment
        if self._look_shadows and not segment:
            self.scene.flags[_R.mjRND_SHADOW] = True
        self.scene.flags[_R.mjRND_SEGMENT] = self.scene.flags[_R.mjRND_IDCOLOR] = segment
        self._cull(self.rect.width, self.rect.height)  # with the sun's shadows: only what casts none into view
        from usvsim.rendering.frame import begin_geoms, end_geoms

        shaded = not segment and begin_geoms(self.marine, self.scene, bool(self.scene.flags[_R.mjRND_SHADOW]))
        mujoco.mjr_render(self.rect, self.scene, self.ctx)
        if shaded:
            end_geoms(self.marine)
        if not segment:
            from usvsim.rendering.frame import sun_shadow_map

            sun_shadow_map(self.marine, self.scene, self.ctx)
        if self.marine is not None and (water_label_pass or not segment):
            from usvsim.rendering.frame import id_color

            labels = id_color(self.scene.ngeom + 1) if segment else None
            if not segment:  # what mjr_render drew: the water over geoms needs no more quads (same bytes)
                from usvsim.rendering import cull

                self.marine.geom_boxes = cull.drawn_boxes(self.scene, self.model)
            self.marine.draw(self.scene.camera[0], self.rect, labels, self._time_s)

    def capture(self, rgb_depth: bool = True, segmentation: bool = True, water: bool = True) -> dict[str, np.ndarray]:
        """'rgb' (H, W, 3) uint8 + 'depth' (H, W) float32 along optical z (m; NaN where nothing is nearer than
        `far`) from one GL pass, and 'segmentation' (H, W) uint16 (geom id + 1, 0 = background) from a second;
        top row first. The sky (empty depth) is painted from the skybox's gradient. The segmentation pass is
        drawn by llvmpipe's threads while this thread finishes the RGB and depth images. With the shader look,
        the water's labels come from the colour pass (the stencil its water marked) when it was drawn, else from
        a label pass that draws the water in its id colour. `water=False` (a segmentation-only capture): the
        shader's water is left out of the labels, as MuJoCo's water geom is when its alpha is 0 (amodal masks)."""
        out: dict[str, np.ndarray] = {}
        water_mask = rgb_depth and segmentation and self.marine is not None
        if rgb_depth:
            self._render(segment=False)
            mujoco.mjr_readPixels(self._gl_rgb, self._gl_depth, self.rect, self.ctx)
            if water_mask and self.marine is not None:
                self.marine.read_water_mask(self.rect, self._gl_water)
        if segmentation:
            self._render(segment=True, water_label_pass=not water_mask and water)  # returns before the pixels are drawn
        if rgb_depth:
            out["rgb"], out["depth"] = np.empty_like(self._gl_rgb), np.empty_like(self._gl_depth)
            zero_near = self.ctx.readDepthMap == mujoco.mjtDepthMap.mjDEPTH_ZERONEAR  # else reversed Z
            finish_rgb_depth(self._gl_rgb, self._gl_depth, float(self.near), float(self.far), zero_near,
                             self._up_optical, self._intrinsics, SKY_ZENITH, SKY_HORIZON, self.marine is None,
                             out["rgb"], out["depth"])  # fmt: skip
            if self.marine is None and self._plane >= 0:  # the plane sits under the field's troughs: its depth is
                still_water_depth(out["depth"], self._up_optical, self._intrinsics, self._camera_z,  # the mean level's
                                  float(self.model.geom_pos[self._plane, 2]), self._level_m, float(self.far))  # fmt: skip
        if segmentation:
            mujoco.mjr_readPixels(self._gl_ids, None, self.rect, self.ctx)
            out["segmentation"] = np.empty(self._gl_depth.shape, np.uint16)
            lut = self._segment_lut()
            if water_mask:
                finish_segmentation_water(self._gl_ids, self._gl_water, lut, lut[-1], out["segmentation"])
            else:
                finish_segmentation(self._gl_ids, lut, out["segmentation"])
        return out

    def rgb_depth(self) -> tuple[np.ndarray, np.ndarray]:
        images = self.capture(segmentation=False)
        return images["rgb"], images["depth"]

    def segmentation(self) -> np.ndarray:
        return self.capture(rgb_depth=False)["segmentation"]

    def _segment_lut(self) -> np.ndarray:
        """Scene geom index + 1 → model geom id + 1 (0: not a geom)."""
        lut = np.zeros(self.scene.ngeom + 2, np.uint16)
        for i, g in enumerate(self.scene.geoms[: self.scene.ngeom]):
            if g.objtype == mujoco.mjtObj.mjOBJ_GEOM:
                lut[i + 1] = g.objid + 1
        if self.marine is not None:  # the shader's water is drawn in the colour of index ngeom + 1
            from usvsim.rendering.frame import water_label

            lut[-1] = water_label(self.model)
        return lut

    def close(self) -> None:
        if self._own:
            self.context.close()
