"""Manual driving: keyboard and gamepad state → drive axes → thruster (or velocity) commands.

Pure functions, no device I/O (the viewer reads the devices and calls these each frame).
Axes: throttle in [-1, 1] (+ ahead), steering in [-1, 1] (+ turn to port, i.e. counter-clockwise seen from
above, positive yaw rate per REP 103), and a reset request.
Keyboard (the seed's map): W ahead, S astern, A port, D starboard, R reset; axes ramp toward the keys'
target at `ramp_per_s` and return to zero at `return_per_s`. Gamepad: right trigger ahead, left trigger
astern, left stick x steers (right = starboard), North button (Y / triangle) resets.
Mixing: twin fixed thrusters steer differentially; azimuth boats turn all engines, stern engines one way
and bow engines the opposite way (the seed's ShipController counter-steer), within ±25°.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np

KEYS = {"ahead": "w", "astern": "s", "port": "a", "starboard": "d", "reset": "r"}
STEER_LIMIT_DEG = 25.0


@dataclass(frozen=True)
class DriveAxes:
    throttle: float = 0.0
    steering: float = 0.0
    reset: bool = False


def _ramp(value: float, target: float, dt: float, rate: float) -> float:
    step = rate * dt
    return value + min(max(target - value, -step), step)


def keyboard_axes(pressed: Collection[str], previous: DriveAxes, dt: float, ramp_per_s: float = 2.0,
                  return_per_s: float = 4.0, keys: dict[str, str] = KEYS) -> DriveAxes:  # fmt: skip
    """Axes from the set of pressed keys (lower-case names), ramped from `previous` over dt seconds."""
    down = {k.lower() for k in pressed}
    throttle = float(keys["ahead"] in down) - float(keys["astern"] in down)
    steering = float(keys["port"] in down) - float(keys["starboard"] in down)
    rate_t = ramp_per_s if throttle != 0 else return_per_s
    rate_s = ramp_per_s if steering != 0 else return_per_s
    return DriveAxes(_ramp(previous.throttle, throttle, dt, rate_t), _ramp(previous.steering, steering, dt, rate_s),
                     keys["reset"] in down)  # fmt: skip


def _deadzone(x: float, width: float) -> float:
    if abs(x) <= width:
        return 0.0
    return math.copysign((abs(x) - width) / (1.0 - width), x)


def gamepad_axes(right_trigger: float, left_trigger: float, stick_x: float, reset_button: bool = False,
                 trigger_rest: float = -1.0, deadzone: float = 0.1) -> DriveAxes:  # fmt: skip
    """Axes from raw gamepad values. Triggers run from `trigger_rest` (released; -1 for SDL/pygame, 0 for
    browsers) to 1 (pressed); stick x from -1 (left) to 1 (right)."""

    def pull(raw: float) -> float:
        return min(max((raw - trigger_rest) / (1.0 - trigger_rest), 0.0), 1.0)

    throttle = _deadzone(pull(right_trigger), deadzone) - _deadzone(pull(left_trigger), deadzone)
    steering = -_deadzone(min(max(stick_x, -1.0), 1.0), deadzone)
    return DriveAxes(throttle, steering, bool(reset_button))


def differential_commands(axes: DriveAxes, names: Sequence[str], y_m: Sequence[float],
                          steering_gain: float = 1.0) -> dict[str, tuple[float, None]]:  # fmt: skip
    """Fixed thrusters at lateral offsets y (FLU, relative to the CoM): u = throttle ∓ steering, scaled so
    that no |u| exceeds 1 (starboard engines push harder to turn to port)."""
    u = np.array([axes.throttle - steering_gain * axes.steering * np.sign(y) for y in y_m])
    peak = np.abs(u).max(initial=0.0)
    u = u / peak if peak > 1.0 else u
    return {n: (float(v), None) for n, v in zip(names, u, strict=True)}


def azimuth_commands(axes: DriveAxes, names: Sequence[str], x_m: Sequence[float], limit_deg: float = STEER_LIMIT_DEG,
                     angle_limits_rad: Sequence[tuple[float, float]] | None = None) -> dict[str, tuple[float, float]]:  # fmt: skip
    """Azimuth thrusters at longitudinal offsets x (FLU, relative to the CoM): all at u = throttle; stern
    engines turn by -steering·limit, bow engines by +steering·limit (counter-steer), clamped to their range."""
    out = {}
    for i, (n, x) in enumerate(zip(names, x_m, strict=True)):
        angle = math.copysign(1.0, x) * axes.steering * math.radians(limit_deg)
        if angle_limits_rad is not None:
            angle = min(max(angle, angle_limits_rad[i][0]), angle_limits_rad[i][1])
        out[n] = (float(min(max(axes.throttle, -1.0), 1.0)), angle)
    return out


def manual_commands(
    axes: DriveAxes, thrusters, com_flu_m=(0.0, 0.0, 0.0)
) -> dict[str, tuple[float, float | None]]:
    """Thruster commands for a vessel's thruster configs: azimuth mixing if any thruster can steer,
    else differential. Feed to `vessel.thrusters[name].command(u, angle)`."""
    names = [t.name for t in thrusters]
    if any(t.azimuth is not None for t in thrusters):
        x = [t.position[0] - com_flu_m[0] for t in thrusters]
        lim = [(math.radians(t.azimuth.min_deg), math.radians(t.azimuth.max_deg)) if t.azimuth else (0.0, 0.0)
               for t in thrusters]  # fmt: skip
        return dict(azimuth_commands(axes, names, x, angle_limits_rad=lim))
    return dict(differential_commands(axes, names, [t.position[1] - com_flu_m[1] for t in thrusters]))


def axes_to_velocity(axes: DriveAxes, max_speed_mps: float, max_yaw_rate_rad_s: float,
                     max_reverse_mps: float | None = None) -> tuple[float, float, float]:  # fmt: skip
    """A velocity command (u, v, r) for a VesselController: throttle scales speed, steering the yaw rate."""
    reverse = max_speed_mps / 2 if max_reverse_mps is None else max_reverse_mps
    u = axes.throttle * (max_speed_mps if axes.throttle >= 0 else reverse)
    return (u, 0.0, axes.steering * max_yaw_rate_rad_s)


def should_reset(position_m, yaw_rad: float, start_position_m, start_yaw_rad: float,
                 min_distance_m: float = 2.0, min_angle_rad: float = math.radians(10.0)) -> bool:  # fmt: skip
    """The seed's rule: a reset request only acts if the vessel moved > 2 m or turned > 10° from its start."""
    moved = float(np.linalg.norm(np.asarray(position_m)[:2] - np.asarray(start_position_m)[:2]))
    turned = abs((yaw_rad - start_yaw_rad + math.pi) % (2 * math.pi) - math.pi)
    return moved > min_distance_m or turned > min_angle_rad
