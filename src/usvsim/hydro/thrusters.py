"""Thrusters of all vessels as one bank: command handling, first-order dynamics, body-frame wrenches.

Each thruster has a force point and a mounting heading in its vessel's `base_link` (FLU, m). The
thrust vector points along heading `mount_yaw + angle` in the body x-y plane (REP 103: positive angle
turns it counter-clockwise seen from above). Commands are a normalized thrust u in [-1, 1] and an
azimuth angle in radians. Thrust magnitude and angle follow first-order lags with rate limits
(thesis §4.4.7), integrated exactly over each physics step.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numba import njit

from usvsim.config.vessel import Thruster

MAP_CODES = {"linear": 0, "quadratic": 1, "glf": 2}
HOLD_NS = 2**62  # the stamp of a command that holds until changed: the watchdog never expires it
# VRX (classic) generalized logistic fits of measured thruster data: (A, K, B, nu, C, M).
GLF_FORWARD = (0.01, 59.82, 5.0, 0.38, 0.56, 0.28)
GLF_REVERSE = (-199.13, -0.09, 8.84, 5.34, 0.99, -0.57)


@njit(cache=True)
def _glf(u, a, k, b, nu, c, m):
    return a + (k - a) / (c + math.exp(-b * (u - m))) ** (1.0 / nu)


@njit(cache=True)
def thrust_map(u, kind, max_fwd, max_rev):
    """Steady thrust (N) for a normalized command u in [-1, 1]; continuous, 0 at u = 0, ±max at ±1."""
    if kind == 0:
        return u * max_fwd if u >= 0 else u * max_rev
    if kind == 1:
        return u * abs(u) * (max_fwd if u >= 0 else max_rev)
    a, k, b, nu, c, m = GLF_FORWARD if u >= 0 else GLF_REVERSE
    f0 = _glf(0.0, a, k, b, nu, c, m)
    f1 = _glf(1.0 if u >= 0 else -1.0, a, k, b, nu, c, m)
    scale = max_fwd if u >= 0 else max_rev
    return scale * (_glf(u, a, k, b, nu, c, m) - f0) / abs(f1 - f0)


@njit(cache=True)
def _lag(x, target, dt, tau, max_rate):
    step = (target - x) * (1.0 - math.exp(-dt / tau))
    limit = max_rate * dt
    if step > limit:
        step = limit
    elif step < -limit:
        step = -limit
    return x + step


@njit(cache=True)
def thruster_step(p, cmd_u, cmd_angle, last_cmd_ns, timeout_ns, now_ns, dt, thrust, angle, body, com, out):
    """Advance every thruster one step and accumulate body-frame wrenches (force, torque about the
    body's CoM; N, N m) into out (nb, 6). `p` columns: kind, max_fwd, max_rev, tau, rate, az_tau,
    az_rate, az_min, az_max, mount_yaw, px, py, pz. Commands older than timeout_ns (> 0) are zeroed."""
    out[:] = 0.0
    for i in range(thrust.shape[0]):
        b = body[i]
        if timeout_ns[b] > 0 and now_ns - last_cmd_ns[i] > timeout_ns[b]:
            cmd_u[i] = 0.0
        target = thrust_map(cmd_u[i], int(p[i, 0]), p[i, 1], p[i, 2])
        thrust[i] = _lag(thrust[i], target, dt, p[i, 3], p[i, 4])
        if p[i, 5] > 0.0:
            goal = min(max(cmd_angle[i], p[i, 7]), p[i, 8])
            angle[i] = _lag(angle[i], goal, dt, p[i, 5], p[i, 6])
        heading = p[i, 9] + angle[i]
        fx, fy = thrust[i] * math.cos(heading), thrust[i] * math.sin(heading)
        rx, ry, rz = p[i, 10] - com[b, 0], p[i, 11] - com[b, 1], p[i, 12] - com[b, 2]
        out[b, 0] += fx
        out[b, 1] += fy
        out[b, 3] += -rz * fy
        out[b, 4] += rz * fx
        out[b, 5] += rx * fy - ry * fx


def _row(t: Thruster) -> list[float]:
    az = t.azimuth
    return [
        MAP_CODES[t.thrust.type], t.thrust.max_forward_n, t.thrust.max_reverse_n, t.time_constant_s,
        t.max_rate_n_s or np.inf,
        az.time_constant_s if az else 0.0, math.radians(az.max_rate_deg_s) if az else 0.0,
        math.radians(az.min_deg) if az else 0.0, math.radians(az.max_deg) if az else 0.0,
        math.radians(t.mount_yaw_deg), *t.position,
    ]  # fmt: skip


class ThrusterBank:
    """All thrusters of all bodies. Thruster i belongs to body `body[i]`; names are `<vessel>/<thruster>`."""

    def __init__(self, entries: list[tuple[int, str, Thruster]], n_bodies: int, timeouts_s: np.ndarray):
        self.names = [name for _, name, _ in entries]
        self.index = {name: i for i, name in enumerate(self.names)}
        self.specs = [t for _, _, t in entries]
        n = len(entries)
        self.params = np.array([_row(t) for _, _, t in entries], dtype=float).reshape(n, 13)
        self.body = np.array([b for b, _, _ in entries], dtype=np.int64)
        self.timeout_ns = np.round(np.asarray(timeouts_s, dtype=float) * 1e9).astype(np.int64)
        self.cmd_u, self.cmd_angle = np.zeros(n), np.zeros(n)
        self.thrust, self.angle = np.zeros(n), np.zeros(n)
        self.last_cmd_ns = np.zeros(n, dtype=np.int64)
        self.wrench_body = np.zeros((n_bodies, 6))
        self.rejected = 0

    def reset(self) -> None:
        """Zero every command and state (thrust, angle) and the rejected-command count."""
        for array in (self.cmd_u, self.cmd_angle, self.thrust, self.angle, self.last_cmd_ns):
            array[:] = 0
        self.rejected = 0

    def command(self, i: int, u: float, angle_rad: float | None, now_ns: int) -> bool:
        """Set thruster i's command, stamped `now_ns` for the watchdog (HOLD_NS: no watchdog). Rejects
        (returns False, counts) non-finite values and |u| > 1; angles outside the azimuth limits are
        clamped to them; fixed thrusters ignore the angle."""
        ok = _real(u) and math.isfinite(u) and abs(u) <= 1.0 and (angle_rad is None or (_real(angle_rad)
                                                                                    and math.isfinite(angle_rad)))
        if not ok:
            self.rejected += 1
            return False
        self.cmd_u[i] = u
        if angle_rad is not None:
            self.cmd_angle[i] = angle_rad
        self.last_cmd_ns[i] = now_ns
        return True

    def command_angle(self, i: int, angle_rad: float) -> bool:
        """Set thruster i's azimuth command only (rad); rejects non-finite values. The thrust command and
        its watchdog are untouched: only thrust commands keep a thruster running."""
        if not (_real(angle_rad) and math.isfinite(angle_rad)):
            self.rejected += 1
            return False
        self.cmd_angle[i] = angle_rad
        return True

    def step(self, now_ns: int, dt: float, com_body: np.ndarray) -> np.ndarray:
        """Advance the dynamics one step; returns per-body wrenches (nb, 6) in the body frame."""
        if len(self.names):
            thruster_step(
                self.params, self.cmd_u, self.cmd_angle, self.last_cmd_ns, self.timeout_ns, now_ns, dt,
                self.thrust, self.angle, self.body, com_body, self.wrench_body,
            )  # fmt: skip
        return self.wrench_body


def _real(x) -> bool:
    """A command value must be a real number (a Python or numpy int or float, or a 0-d numpy array of one); a
    string, None or a bool is rejected like NaN."""
    if isinstance(x, np.ndarray):
        return x.ndim == 0 and x.dtype.kind in "iuf"
    return isinstance(x, numbers.Real) and not isinstance(x, bool | np.bool_)
