"""Divergence detection beyond NaN: physically absurd speeds, turn rates or accelerations of a floating
body stop the run with an error that names the body (limits: `world.divergence` in the scenario).

Quantities: CoM velocity in the world (ENU, m/s), angular velocity in the body frame (FLU, rad/s),
CoM acceleration as the velocity change over one physics step (m/s^2).
"""

from __future__ import annotations

import numpy as np

from usvsim.core.errors import DivergenceError


class DivergenceGuard:
    """Checks every step's kinematics against the scenario's limits; raises DivergenceError."""

    def __init__(self, limits, names: list[str], dt_s: float):
        self._names, self._dt = list(names), dt_s
        self._limits = (limits.max_speed_mps, limits.max_angular_speed_radps, limits.max_acceleration_mps2)
        self._previous: np.ndarray | None = None

    def reset(self) -> None:
        self._previous = None

    def check(self, vcom_world: np.ndarray, omega_body: np.ndarray, time_s: float) -> None:
        if not len(self._names):
            return
        speed = np.linalg.norm(vcom_world, axis=1)
        turn = np.linalg.norm(omega_body, axis=1)
        previous = vcom_world if self._previous is None else self._previous
        accel = np.linalg.norm(vcom_world - previous, axis=1) / self._dt
        self._previous = vcom_world.copy()
        values = np.stack([speed, turn, accel])
        ratios = values / np.asarray(self._limits)[:, None]
        ratios[~np.isfinite(ratios)] = np.inf
        if ratios.max() <= 1.0:
            return
        kind, body = np.unravel_index(int(np.argmax(ratios)), ratios.shape)
        what = ("speed", "angular speed", "acceleration")[kind]
        unit = ("m/s", "rad/s", "m/s^2")[kind]
        key = ("max_speed_mps", "max_angular_speed_radps", "max_acceleration_mps2")[kind]
        raise DivergenceError(self._names[body], time_s,
                              f"({what} {values[kind, body]:.4g} {unit} exceeds world.divergence.{key} = "
                              f"{self._limits[kind]:g}; a smaller physics step may help)")  # fmt: skip
