"""Divergence detection beyond NaN: physically absurd speeds, turn rates or accelerations of a floating
body stop the run with an error that names the body (limits: `world.divergence` in the scenario).

Quantities: CoM velocity in the world (ENU, m/s), angular velocity in the body frame (FLU, rad/s),
CoM acceleration as the velocity change over one physics step (m/s^2).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.core.errors import DivergenceError
from usvsim.hydro.wrenches import body_kinematics

KEYS = ("max_speed_mps", "max_angular_speed_radps", "max_acceleration_mps2")
WHAT = (("speed", "m/s"), ("angular speed", "rad/s"), ("acceleration", "m/s^2"))


@njit(cache=True, nogil=True)
def _worst(vcom, omega, previous, limits, dt):  # pragma: no cover - compiled
    """(ratio to its limit, kind, body, value) of the worst quantity; NaN/inf give an infinite ratio."""
    worst, kind, body, value = 0.0, 0, 0, 0.0
    for i in range(vcom.shape[0]):
        speed = np.sqrt(vcom[i, 0] ** 2 + vcom[i, 1] ** 2 + vcom[i, 2] ** 2)
        turn = np.sqrt(omega[i, 0] ** 2 + omega[i, 1] ** 2 + omega[i, 2] ** 2)
        dv = vcom[i] - previous[i]
        accel = np.sqrt(dv[0] ** 2 + dv[1] ** 2 + dv[2] ** 2) / dt
        for k, x in enumerate((speed, turn, accel)):
            ratio = x / limits[k] if np.isfinite(x) else np.inf
            if ratio > worst:
                worst, kind, body, value = ratio, k, i, x
        previous[i] = vcom[i]
    return worst, kind, body, value


@njit(cache=True)
def kinematics_and_worst(qpos, qvel, qpos_adr, qvel_adr, com_body, pos, rot, com_world, vcom_world, omega_body,
                         previous, limits, dt):  # fmt: skip
    """`body_kinematics` (hydro/wrenches.py) then `_worst` of the new velocities, in one call."""
    body_kinematics(qpos, qvel, qpos_adr, qvel_adr, com_body, pos, rot, com_world, vcom_world, omega_body)
    return _worst(vcom_world, omega_body, previous, limits, dt)


class DivergenceGuard:
    """Checks every step's kinematics against the scenario's limits; raises DivergenceError."""

    def __init__(self, limits, names: list[str], dt_s: float):
        self._names, self._dt = list(names), dt_s
        self._limits = np.array([getattr(limits, key) for key in KEYS])
        self._previous: np.ndarray | None = None

    def reset(self) -> None:
        self._previous = None

    def check(self, vcom_world: np.ndarray, omega_body: np.ndarray, time_s: float) -> None:
        if not self._names:
            return
        if self._previous is None:
            self._previous = vcom_world.copy()
        self.judge(_worst(vcom_world, omega_body, self._previous, self._limits, self._dt), time_s)

    def kinematics_and_check(self, qpos, qvel, qpos_adr, qvel_adr, com_body, state, time_s: float) -> None:
        """Refresh `state` (world/state.py) from MuJoCo's qpos/qvel (`body_kinematics`) and `check` it, in one
        compiled call (the same operations)."""
        s = state
        if self._previous is None or not self._names:  # `check` sets the first previous velocities itself
            body_kinematics(qpos, qvel, qpos_adr, qvel_adr, com_body, s.pos, s.rot, s.com_world, s.vcom_world,
                            s.omega_body)  # fmt: skip
            return self.check(s.vcom_world, s.omega_body, time_s)
        self.judge(kinematics_and_worst(qpos, qvel, qpos_adr, qvel_adr, com_body, s.pos, s.rot, s.com_world,
                                        s.vcom_world, s.omega_body, self._previous, self._limits, self._dt), time_s)  # fmt: skip
        return None

    def judge(self, worst_tuple, time_s: float) -> None:
        """Raise DivergenceError if the worst quantity (`_worst`'s tuple) exceeds its limit."""
        worst, kind, body, value = worst_tuple
        if worst <= 1.0:
            return
        what, unit = WHAT[kind]
        raise DivergenceError(self._names[body], time_s,
                              f"({what} {value:.4g} {unit} exceeds world.divergence.{KEYS[kind]} = "
                              f"{self._limits[kind]:g}; a smaller physics step may help)")  # fmt: skip
