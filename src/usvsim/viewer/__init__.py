"""Interactive viewer (the `viewer` extra): a GLFW window with MuJoCo's renderer, a follow camera, a HUD,
wave surface, point-cloud and image layers, and manual driving by keyboard or gamepad.

    from usvsim.viewer import run_viewer
    run_viewer(sim)                      # interactive
    run_viewer(sim, script=[(0.0, "w", "press")], max_seconds=10, screenshot="shot.png")

Pure parts (camera, HUD, driver) import no window system; `offscreen.OffscreenViewer` draws the same
frames without a window (`MUJOCO_GL=egl`).
"""

from __future__ import annotations

from usvsim.viewer.camera import CameraPose, FollowCamera, mujoco_ray
from usvsim.viewer.display import NO_DISPLAY
from usvsim.viewer.driver import ManualDriver
from usvsim.viewer.hud import hud_lines


def run_viewer(sim, **kwargs) -> dict:
    """Open the interactive viewer window on `sim`; see `usvsim.viewer.app.run_viewer` for the options."""
    from usvsim.viewer.app import run_viewer as _run

    return _run(sim, **kwargs)


__all__ = ["NO_DISPLAY", "CameraPose", "FollowCamera", "ManualDriver", "hud_lines", "mujoco_ray", "run_viewer"]
