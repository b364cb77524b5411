"""The interactive viewer window (GLFW + MuJoCo's renderer): drive a vessel, watch waves, HUD, layers.

`run_viewer(sim)` opens a window and loops: poll input → advance the simulation by the elapsed wall time
(several physics steps per frame, capped) → refresh the wave surface around the followed vessel → draw.
Keys: W/S throttle, A/D steer, R reset, Space pause, N or Right single step while paused, C follow camera
on/off, Esc quit; mouse drag orbits, scroll zooms; a gamepad (GLFW mapping) drives when one is present.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from pathlib import Path

import glfw
import mujoco

from usvsim.control.manual import DriveAxes, gamepad_axes
from usvsim.core.errors import UsvsimError
from usvsim.viewer.camera import FollowCamera
from usvsim.viewer.capture import Capture, check_outputs
from usvsim.viewer.display import NO_DISPLAY
from usvsim.viewer.driver import ManualDriver, ScriptEvent
from usvsim.viewer.frame import FrameRenderer
from usvsim.viewer.offscreen import save_png
from usvsim.viewer.view import Layer, View

_NAMED = {"SPACE": "space", "RIGHT": "right", "LEFT": "left", "UP": "up", "DOWN": "down", "ESCAPE": "escape"}
_ACTIONS = {glfw.PRESS: "press", glfw.RELEASE: "release", glfw.REPEAT: "repeat"}


def key_name(key: int) -> str | None:
    """Lower-case name of a GLFW key code ("w", "space", "right", "escape"), None if not used."""
    if glfw.KEY_A <= key <= glfw.KEY_Z:
        return chr(ord("a") + key - glfw.KEY_A)
    for name, value in _NAMED.items():
        if key == getattr(glfw, f"KEY_{name}"):
            return value
    return None


def read_gamepad() -> DriveAxes | None:
    """Axes from the first connected gamepad with a GLFW mapping (triggers rest at −1), else None."""
    for jid in range(glfw.JOYSTICK_1, glfw.JOYSTICK_LAST + 1):
        if glfw.joystick_present(jid) and glfw.joystick_is_gamepad(jid):
            state = glfw.get_gamepad_state(jid)
            if state is None:
                continue
            axes, buttons = state.axes, state.buttons
            return gamepad_axes(axes[glfw.GAMEPAD_AXIS_RIGHT_TRIGGER], axes[glfw.GAMEPAD_AXIS_LEFT_TRIGGER],
                                axes[glfw.GAMEPAD_AXIS_LEFT_X], bool(buttons[glfw.GAMEPAD_BUTTON_Y]))  # fmt: skip
    return None


class ViewerWindow:
    """A GLFW window showing a `View` and driving it with a `ManualDriver`."""

    def __init__(
        self, driver: ManualDriver, view: View, width: int = 1280, height: int = 720, title: str = "usvsim"
    ):
        from usvsim.sensors.camera.render import check_gl_fork, note_gl_context

        check_gl_fork()  # a window in a child forked after its parent rendered hangs in GL: one clear error instead
        if not glfw.init():
            raise RuntimeError(NO_DISPLAY)
        note_gl_context()  # and a child forked after this window refuses cameras and windows the same way
        glfw.default_window_hints()  # camera sensors' hidden windows (mujoco.glfw) leave VISIBLE 0 behind: the
        glfw.window_hint(glfw.SAMPLES, 0)  # viewer's window was invisible; multisampling costs 2x on llvmpipe
        self.window = glfw.create_window(width, height, title, None, None)
        if not self.window:  # GLFW stays initialised: camera sensors may hold windows of it
            raise RuntimeError("GLFW could not create a window (OpenGL 2+ with a display is needed)")
        glfw.make_context_current(self.window)
        glfw.swap_interval(0)
        self.driver, self.view = driver, view
        self.renderer = FrameRenderer(view.sim.model, window=True)
        self._drag: tuple[float, float] | None = None
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_mouse_button_callback(self.window, self._on_button)
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)
        glfw.set_scroll_callback(self.window, self._on_scroll)

    # -- callbacks -----------------------------------------------------------------------------
    def _on_key(self, window, key, scancode, action, mods) -> None:
        name = key_name(key)
        if name is not None and action in _ACTIONS:
            self.driver.key(name, _ACTIONS[action])

    def _on_button(self, window, button, action, mods) -> None:
        self._drag = glfw.get_cursor_pos(window) if action == glfw.PRESS else None

    def _on_cursor(self, window, x, y) -> None:
        if self._drag is not None:
            self.view.camera.orbit(x - self._drag[0], y - self._drag[1])
            self._drag = (x, y)

    def _on_scroll(self, window, dx, dy) -> None:
        self.view.camera.zoom(dy)

    # -- loop ----------------------------------------------------------------------------------
    def frame(self, wall_dt: float) -> None:
        """One frame: advance the simulation, handle follow/reset flags, draw, swap."""
        t0 = self.driver.sim.time
        self.driver.advance(wall_dt)
        if self.driver.follow_toggled:
            self.driver.follow_toggled = False
            self.view.camera.toggle_follow(self.view.heading_deg)
        if self.driver.was_reset:
            self.driver.was_reset = False
            self.view.camera.reset_tracking()
        self.view.rates.update(wall_dt, max(self.driver.sim.time - t0, 0.0))
        glfw.make_context_current(self.window)  # camera sensors made their own contexts current while stepping
        width, height = glfw.get_framebuffer_size(self.window)
        self.viewport = mujoco.MjrRect(0, 0, width, height)
        self.view.draw(self.renderer, self.viewport, wall_dt, self.driver.paused, self.driver.axes)

    def screenshot(self, path: str | Path) -> Path:
        return save_png(self.renderer.read_rgb(self.viewport), path)

    def close(self) -> None:
        """Free the window, leaving GLFW initialised: glfw.terminate() also destroyed the camera sensors' hidden
        windows, and their images after the viewer closed were garbage (black sky, a grey band)."""
        self.renderer.free()
        glfw.destroy_window(self.window)


def run_viewer(sim, vessel: str | None = None, script: Iterable[ScriptEvent] = (), max_seconds: float | None = None,
               screenshot: str | Path | None = None, width: int = 1280, height: int = 720, time_scale: float = 1.0,
               max_fps: float = 60.0, points: Layer = None, inset: Layer = None, gamepad: bool = True,
               camera: FollowCamera | None = None, video: str | Path | None = None,
               stop: Callable[[], bool] | None = None) -> dict:  # fmt: skip
    """Open the interactive viewer on `sim` and run until the window closes, Esc, or `max_seconds` of
    simulation time (counted from t = 0 of the clock as it is now; a reset mid-run does not add to it). `script`: (sim_time_s, key, action) events replayed like real key presses.
    `points` / `inset`: an (n, 3) world-point array / (h, w, 3) image, or callables of `sim` returning one.
    Returns {"frames", "wall_s", "sim_s", "steps", "fps"} (sim_s, steps: stepped here, across resets); writes the last frame to `screenshot` if given, every frame
    to `video` (MP4/AVI) if given; the P key saves a screenshot in the working directory. `stop()` is asked
    between frames (never inside a physics step): True ends the run as Esc does (the CLI's Ctrl-C and SIGTERM)."""
    check_outputs(screenshot, video)  # a bad name is an error now, not when the window closes
    if not (math.isfinite(time_scale) and time_scale > 0):  # 0 or less never stepped: the window hung for good
        raise UsvsimError(f"time_scale must be a finite number above 0, got {time_scale}")
    if max_seconds is not None and not (math.isfinite(max_seconds) and max_seconds >= 0):
        raise UsvsimError(f"max_seconds must be a finite number of seconds, 0 or more, got {max_seconds}")
    if not sim.vessels:  # a StopIteration traceback before
        raise UsvsimError(f"the viewer follows and drives a vessel: scenario '{sim.scenario.name}' has none")
    if vessel is not None and vessel not in sim.vessels:
        raise UsvsimError(f"no vessel '{vessel}' to follow (vessels: {', '.join(sim.vessels)})")
    driver = ManualDriver(sim, vessel, script, time_scale, gamepad=read_gamepad if gamepad else None)
    if max_seconds is not None:  # the steps to go from the clock's time now; a reset (R, /reset) adds none
        driver.stop_at_step = max(0, round(max_seconds / sim.clock.dt) - sim.clock.steps)
    view = View(sim, driver.vessel_name, camera, points, inset)
    window = ViewerWindow(driver, view, width, height, f"usvsim - {sim.scenario.name}")
    capture = Capture(sim.scenario.name, video=Path(video) if video else None)
    frames, start, last = 0, time.perf_counter(), time.perf_counter()
    try:
        while True:
            now = time.perf_counter()
            window.frame(now - last if frames else 0.0)
            last, frames = now, frames + 1
            done = (driver.quit or glfw.window_should_close(window.window)
                    or (driver.stop_at_step is not None and driver.steps_taken >= driver.stop_at_step)
                    or (stop is not None and stop()))  # fmt: skip
            capture.frame(window, sim.time, driver.take_screenshot_request())
            if done and screenshot is not None:
                window.screenshot(screenshot)  # the back buffer, before it is swapped away
            glfw.swap_buffers(window.window)
            if done:
                break
            glfw.poll_events()
            spare = 1.0 / max_fps - (time.perf_counter() - now)
            if spare > 0:
                time.sleep(spare)
    finally:
        capture.close()
        window.close()
    wall = time.perf_counter() - start
    return {
        "frames": frames,
        "wall_s": wall,
        "sim_s": driver.steps_taken * sim.clock.dt,
        "steps": driver.steps_taken,
        "fps": frames / wall if wall > 0 else 0.0,
    }
