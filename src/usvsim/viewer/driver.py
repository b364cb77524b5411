"""The viewer's simulation side, without any GL: key events → drive axes → thruster commands → steps.

Keys arrive as (name, action) with lower-case names ("w", "space", "right", "escape") and actions "press",
"release" or "repeat", from the window's key callback or from a script. A script is a list of
(sim_time_s, key, action) replayed through the same path just before the first physics step at or after
that simulation time, so a scripted drive is deterministic whatever the frame rate. Axes are ramped per
physics step by `control.manual.keyboard_axes` (or taken from a gamepad when one is active) and mixed into
thruster commands by `control.manual.manual_commands` (differential, or azimuth with bow counter-steer), or, for a
vessel under a velocity controller (the scenario's, or one a `cmd_vel` created), into its velocity reference by
`control.manual.axes_to_velocity` (the controller would otherwise overwrite the thrusters at its rate). The driver
commands only while the axes are off zero (and at the step they return to it): until a key or the gamepad is
touched, a station-keeping hold, a `cmd_vel` or thruster commands from a bridge drive the vessel.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from usvsim.control.manual import (
    KEYS,
    DriveAxes,
    axes_to_velocity,
    keyboard_axes,
    manual_commands,
    should_reset,
)

DRIVE_KEYS = frozenset(KEYS.values())
PAUSE, STEP_KEYS, QUIT_KEYS, FOLLOW, SCREENSHOT = "space", ("n", "right"), ("escape",), "c", "p"
ScriptEvent = tuple[float, str, str]


class ManualDriver:
    """Drives one vessel of `sim` from key events (and a gamepad); advances the simulation in real time."""

    def __init__(self, sim, vessel_name: str | None = None, script: Iterable[ScriptEvent] = (),
                 time_scale: float = 1.0, max_steps_per_frame: int | None = None, physics_budget_s: float = 0.025,
                 gamepad: Callable[[], DriveAxes | None] | None = None):  # fmt: skip
        self.sim = sim
        self.vessel_name = vessel_name or next(iter(sim.vessels))
        self.vessel = sim.vessels[self.vessel_name]
        self.script = sorted(script, key=lambda e: e[0])
        self._next_event = 0
        self.time_scale = float(time_scale)
        self.max_steps_per_frame = max_steps_per_frame or max(
            1, round(0.25 / sim.clock.dt)
        )  # ≤ 0.25 s a frame
        self.physics_budget_s = (
            physics_budget_s  # wall time per frame for physics; beyond it the sim slows down
        )
        self.gamepad = gamepad
        self.stop_at_step: int | None = None  # the viewer stops after this many steps, resets included (--duration)
        self.steps_taken = 0  # physics steps stepped, across resets (the clock counts the current episode)
        self.pressed: set[str] = set()
        self.axes = DriveAxes()
        self.paused = self.quit = False
        self.follow_toggled = self.was_reset = False  # flags the app reads and clears
        self._screenshot = False
        self._pending_steps = 0
        self._budget_s = 0.0
        self._reset_held = False
        self._driving = False  # the axes were off zero at the last step
        self._start = (self.vessel.position, float(self.vessel.rpy[2]))

    # -- keys ----------------------------------------------------------------------------------
    def key(self, name: str, action: str) -> None:
        name = name.lower()
        if action == "release":
            self.pressed.discard(name)
            return
        if action == "press":
            if name in DRIVE_KEYS:
                self.pressed.add(name)
            elif name == PAUSE:
                self.paused = not self.paused
            elif name in STEP_KEYS and self.paused:
                self._pending_steps += 1
            elif name in QUIT_KEYS:
                self.quit = True
            elif name == FOLLOW:
                self.follow_toggled = True
            elif name == SCREENSHOT:
                self._screenshot = True

    def take_screenshot_request(self) -> bool:
        """True once after the screenshot key was pressed."""
        requested, self._screenshot = self._screenshot, False
        return requested

    def _replay_script(self) -> None:
        t = self.sim.time + 1e-9
        while self._next_event < len(self.script) and self.script[self._next_event][0] <= t:
            _, key, action = self.script[self._next_event]
            self._next_event += 1
            self.key(key, action)

    @property
    def script_done(self) -> bool:
        return self._next_event >= len(self.script)

    # -- stepping ------------------------------------------------------------------------------
    def advance(self, wall_dt: float) -> int:
        """Step the simulation by the wall time elapsed (× time_scale), capped per frame (at most
        `max_steps_per_frame`, and no new step after `physics_budget_s` of wall time); returns steps."""
        self._replay_script()
        if self.paused:
            steps, self._pending_steps, self._budget_s = self._pending_steps, 0, 0.0
        else:
            dt = self.sim.clock.dt
            self._budget_s += max(wall_dt, 0.0) * self.time_scale
            steps = int(self._budget_s / dt + 1e-9)
            if steps > self.max_steps_per_frame:  # too slow to keep up: drop the backlog, do not spiral
                steps, self._budget_s = self.max_steps_per_frame, 0.0
            else:
                self._budget_s -= steps * dt
        if self.stop_at_step is not None:  # never past the requested duration
            steps = max(0, min(steps, self.stop_at_step - self.steps_taken))
        deadline = time.perf_counter() + self.physics_budget_s
        for done in range(steps):
            if done and not self.paused and time.perf_counter() > deadline:  # stay interactive: drop the rest
                self._budget_s = 0.0
                return done
            self.step()
        return steps

    def step(self) -> None:
        """One physics step: replay due script events, update axes, maybe reset, command thrusters, step."""
        self._replay_script()
        axes = keyboard_axes(self.pressed, self.axes, self.sim.clock.dt)
        pad = self.gamepad() if self.gamepad is not None else None
        if pad is not None and (pad.throttle or pad.steering or pad.reset):
            axes = DriveAxes(pad.throttle, pad.steering, pad.reset or axes.reset)
        self.axes = axes
        if axes.reset and not self._reset_held:
            self.reset()
        self._reset_held = axes.reset
        moving = bool(axes.throttle or axes.steering)
        if moving or self._driving:  # until touched, others drive (a hold, cmd_vel, bridges' thrust)
            self._command(axes)
        self._driving = moving
        self.sim.step()
        self.steps_taken += 1

    def _command(self, axes: DriveAxes) -> None:
        """Axes → the vessel's velocity reference when a controller drives it (it overwrote direct thruster
        commands at its rate, so the vessel obeyed a mix of both), else → its thruster commands."""
        loop = self.sim.controllers.get(self.vessel_name)
        if loop is not None:
            # the surge, sway and yaw rate the controller was designed for
            top = loop.controller.velocity.max_velocity
            loop.reference, loop.force = axes_to_velocity(axes, float(top[0]), float(top[2])), None
            return
        for name, (u, angle) in manual_commands(
            axes, self.vessel.model.thrusters, self.vessel.model.com
        ).items():
            self.vessel.thrusters[name].command(u, angle)

    def reset(self, force: bool = False) -> bool:
        """The seed's reset: back to the start if the vessel moved > 2 m or turned > 10° (or `force`)."""
        start_pos, start_yaw = self._start
        if not force and not should_reset(
            self.vessel.position, float(self.vessel.rpy[2]), start_pos, start_yaw
        ):
            return False
        self.sim.reset(seed=self.sim.next_reset_seed())  # as a /reset does (Simulation.reset_seeds)
        self.axes, self.was_reset, self._driving = DriveAxes(reset=self.axes.reset), True, False
        return True
