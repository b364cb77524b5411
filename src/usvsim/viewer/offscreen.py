"""Offscreen rendering of viewer frames (EGL or any `MUJOCO_GL` platform): screenshots, tests, benchmarks.

Choose the platform before MuJoCo is first imported, e.g. `MUJOCO_GL=egl` on a machine without a display.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from usvsim.viewer.frame import FrameRenderer
from usvsim.viewer.view import View


class OffscreenViewer:
    """A GL context + FrameRenderer of `width` × `height` pixels drawing a `View` of the simulation."""

    def __init__(
        self, sim, width: int = 1280, height: int = 720, view: View | None = None, **renderer_options
    ):
        from mujoco import gl_context

        from usvsim.sensors.camera.render import check_gl_fork, note_gl_context

        check_gl_fork()  # a GL context in a child forked after its parent rendered hangs: one clear error instead
        note_gl_context()
        global_ = sim.model.vis.global_
        size = (max(width, global_.offwidth), max(height, global_.offheight))
        self.sim, self.view = sim, view or View(sim)
        self.gl = gl_context.GLContext(width, height)
        self.gl.make_current()
        # MuJoCo's offscreen buffer exactly the frame's size (the model's may be larger, e.g. 1920 x 1080): MuJoCo clears
        # the viewport with a scissor, and on llvmpipe a clear of part of a buffer is drawn, not filled (~2 ms CPU)
        global_.offwidth, global_.offheight = width, height
        try:
            self.renderer = FrameRenderer(sim.model, window=False, **renderer_options)
        finally:
            global_.offwidth, global_.offheight = size
        self.viewport = mujoco.MjrRect(0, 0, width, height)

    def render(self, dt: float = 0.0, paused: bool = False, axes=None) -> np.ndarray:
        """Draw one frame and return it as (height, width, 3) uint8."""
        self.gl.make_current()
        self.view.draw(self.renderer, self.viewport, dt, paused, axes)
        return self.renderer.read_rgb(self.viewport)

    def save(self, path: str | Path, **kwargs) -> Path:
        return save_png(self.render(**kwargs), path)

    def close(self) -> None:
        self.gl.make_current()
        self.renderer.free()
        self.gl.free()


def save_png(rgb: np.ndarray, path: str | Path) -> Path:
    from PIL import Image

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(rgb).save(path)
    return path
