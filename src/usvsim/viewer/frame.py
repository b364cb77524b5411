"""Drawing one viewer frame into the current GL context: scene, wave surface, points, inset, HUD.

The same `FrameRenderer` serves the window (GLFW) and offscreen rendering (EGL, for screenshots and
tests): the caller makes a GL context current and picks the framebuffer (`window=True` or offscreen).
"""

from __future__ import annotations

import mujoco
import numpy as np

from usvsim.core.overlap import Overlap
from usvsim.viewer.camera import CameraPose
from usvsim.viewer.hud import HELP, overlay_columns
from usvsim.viewer.layers import MAX_POINTS, add_points, draw_inset
from usvsim.world.water_visual import still_water_to_view, update_water_visual

VISIBLE_GROUPS = (0, 1, 1, 0, 0, 0)  # visuals and water; collision pieces (group 3) stay hidden


class FrameRenderer:
    """Scene + MuJoCo render context for one model. Create it with the GL context current."""

    def __init__(self, model: mujoco.MjModel, window: bool = False, shadows: bool = False,
                 reflections: bool = False, max_points: int = MAX_POINTS, multisample: bool = False,
                 font_scale=mujoco.mjtFontScale.mjFONTSCALE_150):  # fmt: skip
        self.model = model
        self.max_points = max_points
        self.scene = mujoco.MjvScene(model, maxgeom=model.ngeom + max_points + 200)
        self.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = int(shadows)
        self._shadows = shadows
        self.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = int(reflections)
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = VISIBLE_GROUPS
        self.option.flags[mujoco.mjtVisFlag.mjVIS_TENDON] = 1  # mooring lines
        self.camera = mujoco.MjvCamera()
        samples = model.vis.quality.offsamples
        if not multisample:  # multisampling doubles the cost on a software renderer (llvmpipe)
            model.vis.quality.offsamples = 0
        self.context = mujoco.MjrContext(model, font_scale.value)
        model.vis.quality.offsamples = samples
        self.buffer = mujoco.mjtFramebuffer.mjFB_WINDOW if window else mujoco.mjtFramebuffer.mjFB_OFFSCREEN
        mujoco.mjr_setBuffer(self.buffer, self.context)
        self.marine, self._center_xy = (
            None,
            (0.0, 0.0),
        )  # the shader passes (usvsim.rendering), made on first use
        self.overlap: Overlap | None = Overlap()  # a worker for the ocean's textures (rendering.frame.start_sea); None: here
        from usvsim.rendering.cull import FrustumCull

        self.cull = FrustumCull(
            self.scene
        )  # geoms outside the view are not drawn (same pixels, less vertex work)

    def update_water(self, sim, center_xy) -> None:
        """Re-sample the drawn wave surface from `sim.ocean` around `center_xy` and upload it."""
        self._center_xy = tuple(center_xy[:2])
        if _shader_look(sim) is None:
            update_water_visual(sim, self.context, center_xy)

    def _prepare_marine(self, sim):
        """The shader passes for this frame (None when `sim.look` asks for MuJoCo's plain look)."""
        look = _shader_look(sim)
        self.option.geomgroup[2] = int(look is None)
        self.scene.flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = int(look is None)  # the shader draws the sky
        self.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = int(
            self._shadows or (look is not None and sim.look.shadows)
        )
        if look is None:
            return None
        from usvsim.rendering.frame import prepare_light
        from usvsim.rendering.marine import MarinePass

        if self.marine is None:
            from usvsim.rendering.grid import view_cell_px

            self.marine = MarinePass(
                cell_px=view_cell_px
            )  # coarser water cells than cameras: no depth to keep
        prepare_light(
            self.marine, sim, self._center_xy
        )  # the sea (prepare_sea) while llvmpipe draws the geoms: see draw
        return self.marine

    def draw(self, sim, viewport: mujoco.MjrRect, pose: CameraPose, hud_rows=None, points=None, inset=None,
             help_text: str | None = HELP) -> None:  # fmt: skip
        """Render the scene from `pose` with the optional layers; the caller swaps or reads the pixels."""
        mujoco.mjr_setBuffer(self.buffer, self.context)
        marine = self._prepare_marine(sim)
        sea = None
        if marine is not None:  # the ocean's textures on the second core while this thread submits the geoms
            from usvsim.rendering.frame import start_sea

            sea = start_sea(marine, sim, self._center_xy, self.overlap)
        pose.apply(self.camera)
        mujoco.mjv_updateScene(sim.model, sim.data, self.option, None, self.camera, mujoco.mjtCatBit.mjCAT_ALL.value,
                               self.scene)  # fmt: skip
        if marine is None:  # the plain look's water beyond the drawn field, out to the far plane
            still_water_to_view(self.scene, sim.model, pose.eye, float(self.scene.camera[0].frustum_far))
        if points is not None and len(points):
            add_points(self.scene, points, max_points=self.max_points)
        if marine is not None and marine.daylight is not None:
            from usvsim.rendering.frame import apply_lights

            apply_lights(
                self.scene,
                marine.daylight,
                marine.materials,
                marine.center_xy,
                float(self.scene.camera[0].frustum_far),
            )
        self.cull(
            viewport.width, viewport.height
        )  # after the lights: with shadows it culls along the sun's rays
        from usvsim.rendering.frame import begin_geoms, end_geoms

        shaded = begin_geoms(marine, self.scene, bool(self.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW]))
        mujoco.mjr_render(viewport, self.scene, self.context)
        if shaded:
            end_geoms(marine)
        from usvsim.rendering.frame import sun_shadow_map

        sun_shadow_map(marine, self.scene, self.context)
        if marine is not None:
            from OpenGL import GL

            from usvsim.rendering.frame import prepare_sea

            GL.glFlush()  # llvmpipe's threads draw the geoms while this one uploads the sea
            prepare_sea(marine, sim, self._center_xy, sea)
            from usvsim.rendering import cull

            marine.geom_boxes = cull.drawn_boxes(
                self.scene, sim.model
            )  # what mjr_render drew: the water over them
            view = mujoco.mjv_averageCamera(
                self.scene.camera[0], self.scene.camera[1]
            )  # what mjr_render drew from
            marine.draw(view, viewport, time_s=sim.time)
            GL.glFlush()  # and the water while this one lays out the HUD
        if inset is not None:
            draw_inset(inset, viewport, self.context)
        if hud_rows:
            left, right = overlay_columns(hud_rows)
            mujoco.mjr_overlay(mujoco.mjtFont.mjFONT_NORMAL, mujoco.mjtGridPos.mjGRID_TOPLEFT, viewport, left, right,
                               self.context)  # fmt: skip
        if help_text:
            mujoco.mjr_overlay(mujoco.mjtFont.mjFONT_NORMAL, mujoco.mjtGridPos.mjGRID_BOTTOMLEFT, viewport, help_text,
                               None, self.context)  # fmt: skip

    def read_rgb(self, viewport: mujoco.MjrRect) -> np.ndarray:
        """The drawn pixels (h, w, 3) uint8, top row first."""
        rgb = np.empty((viewport.height, viewport.width, 3), dtype=np.uint8)
        mujoco.mjr_readPixels(rgb, None, viewport, self.context)
        return rgb[::-1].copy()

    def free(self) -> None:
        if self.marine is not None:
            self.marine.release()
        if self.overlap is not None:
            self.overlap.close()
        self.context.free()


def _shader_look(sim):
    look = getattr(sim, "look", None)
    return look if look is not None and look.renderer == "shader" else None
