"""Thrusters of all vessels as one bank: command handling, first-order dynamics, body-frame wrenches.

Each thruster has a force point and a mounting heading in its vessel's `base_link` (FLU, m). The
thrust vector points along heading `mount_yaw + angle` in the body x-y plane (REP 103: positive angle
turns it counter-clockwise seen from above). Commands are a normalized thrust u in [-1, 1] and an
azimuth angle in radians. Thrust magnitude and angle follow first-order lags with rate limits
(thesis §4.4.7), integrated exactly over each physics step.

A propeller acts only where it is in the water: its disc (diameter `propeller_diameter_m`, vertical, centred
at the force point) delivers the thrust times the fraction of its area under the local surface, found each
step from the wave field at the disc's centre (`wet`: 1 when the disc's top is under water, 0 when its bottom
is above it). The motor's thrust state (`thrust`) keeps following the command; only the force on the hull
fades. Ventilation losses beyond the lost disc area (air drawn down a propeller close to the surface) are not
modelled.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numba import njit

from usvsim.config.vessel import Thruster
from usvsim.ocean.fft_kernels import heights_cached

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
def disc_wet_fraction(depth, radius):
    """Fraction of the area of a vertical disc of `radius` (m) under a level surface `depth` (m) above its
    centre (negative: the centre is in the air): 1 - (θ - sin θ) / 2π, θ = 2 acos(depth / radius) the central
    angle of the dry segment. radius <= 0: a point force, wet (1) at or under the surface."""
    if radius <= 0.0:
        return 1.0 if depth >= 0.0 else 0.0
    if depth >= radius:
        return 1.0
    if depth <= -radius:
        return 0.0
    theta = 2.0 * math.acos(depth / radius)
    return 1.0 - (theta - math.sin(theta)) / (2.0 * math.pi)


@njit(cache=True)
def propeller_points(p, body, pos, rot, out):
    """World (ENU, m) position of every thruster's force point (`p` columns 10-12, base_link FLU) into out (n, 3),
    from the body origins `pos` (nb, 3) and rotations `rot` (nb, 3, 3)."""
    for i in range(p.shape[0]):
        b = body[i]
        for k in range(3):
            out[i, k] = pos[b, k] + rot[b, k, 0] * p[i, 10] + rot[b, k, 1] * p[i, 11] + rot[b, k, 2] * p[i, 12]


@njit(cache=True)
def wet_fractions(p, points, eta, wet):
    """`wet[i]`: the wet fraction of thruster i's disc (radius `p[i, 13]`, m; < 0: no immersion model, always 1)
    under the surface height eta[i] (m, ENU) at its centre points[i]."""
    for i in range(p.shape[0]):
        wet[i] = 1.0 if p[i, 13] < 0.0 else disc_wet_fraction(eta[i] - points[i, 2], p[i, 13])


@njit(cache=True)
def wet_in_still_water(p, body, pos, rot, level, points, wet):
    """`propeller_points` and `wet_fractions` under a level surface at z = level (m) in one call."""
    propeller_points(p, body, pos, rot, points)
    for i in range(p.shape[0]):
        wet[i] = 1.0 if p[i, 13] < 0.0 else disc_wet_fraction(level - points[i, 2], p[i, 13])


@njit(cache=True)
def wet_in_fft_sea(p, body, pos, rot, level, tiles, wts, inv_cells, eta, band_h, cache, stamp, now, points, wet):
    """`propeller_points`, the heights there (`fft_kernels.heights_cached`, + level: what `Ocean.elevation` gives)
    into eta and `wet_fractions`, in one call."""
    propeller_points(p, body, pos, rot, points)
    heights_cached(points[:, 0], points[:, 1], tiles, wts, inv_cells, eta, band_h, cache, stamp, now)
    for i in range(eta.shape[0]):
        eta[i] += level
    wet_fractions(p, points, eta, wet)


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
def thruster_step(p, cmd_u, cmd_angle, last_cmd_ns, timeout_ns, now_ns, dt, thrust, angle, wet, body, com, out):
    """Advance every thruster one step and accumulate body-frame wrenches (force, torque about the
    body's CoM; N, N m) into out (nb, 6): thrust times the wet fraction `wet` of each propeller. `p` columns:
    kind, max_fwd, max_rev, tau, rate, az_tau, az_rate, az_min, az_max, mount_yaw, px, py, pz, propeller
    radius (m; -1: none). Commands older than timeout_ns (> 0) are zeroed."""
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
        force = thrust[i] * wet[i]
        fx, fy = force * math.cos(heading), force * math.sin(heading)
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
        -1.0 if t.propeller_diameter_m is None else t.propeller_diameter_m / 2,
    ]  # fmt: skip


class ThrusterBank:
    """All thrusters of all bodies. Thruster i belongs to body `body[i]`; names are `<vessel>/<thruster>`."""

    def __init__(self, entries: list[tuple[int, str, Thruster]], n_bodies: int, timeouts_s: np.ndarray):
        self.names = [name for _, name, _ in entries]
        self.index = {name: i for i, name in enumerate(self.names)}
        self.specs = [t for _, _, t in entries]
        n = len(entries)
        self.params = np.array([_row(t) for _, _, t in entries], dtype=float).reshape(n, 14)
        self.body = np.array([b for b, _, _ in entries], dtype=np.int64)
        self.timeout_ns = np.round(np.asarray(timeouts_s, dtype=float) * 1e9).astype(np.int64)
        self.cmd_u, self.cmd_angle = np.zeros(n), np.zeros(n)
        self.thrust, self.angle = np.zeros(n), np.zeros(n)
        self.last_cmd_ns = np.zeros(n, dtype=np.int64)
        self.wet = np.ones(n)  # wet fraction of each propeller disc (`immerse`)
        self._points, self._eta = np.zeros((n, 3)), np.zeros(n)
        self.wrench_body = np.zeros((n_bodies, 6))
        self.rejected = 0

    def reset(self) -> None:
        """Zero every command and state (thrust, angle) and the rejected-command count."""
        for array in (self.cmd_u, self.cmd_angle, self.thrust, self.angle, self.last_cmd_ns):
            array[:] = 0
        self.wet[:] = 1.0
        self.rejected = 0

    def immerse(self, pos: np.ndarray, rot: np.ndarray, ocean, t: float) -> None:
        """Find every propeller's wet fraction (`wet`) from the body poses (origins `pos` (nb, 3) ENU m,
        rotations `rot` (nb, 3, 3) FLU → ENU) and the water surface at its centre at time t (s)."""
        if not len(self.names):
            return
        if ocean.waves is None:
            wet_in_still_water(self.params, self.body, pos, rot, ocean.level_m, self._points, self.wet)
            return
        kernel = getattr(ocean.waves, "height_kernel_args", None)
        args = kernel(t, len(self.names)) if kernel is not None else None
        if args is not None:  # an FFT sea without displacement: one compiled call
            (tiles, weights, inv_cells), (bands, cache, stamp, now) = args
            wet_in_fft_sea(self.params, self.body, pos, rot, ocean.level_m, tiles, weights, inv_cells, self._eta, bands,
                           cache, stamp, now, self._points, self.wet)  # fmt: skip
            return
        propeller_points(self.params, self.body, pos, rot, self._points)
        self._eta[:] = ocean.elevation(self._points[:, 0], self._points[:, 1], t)
        wet_fractions(self.params, self._points, self._eta, self.wet)

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
                self.thrust, self.angle, self.wet, self.body, com_body, self.wrench_body,
            )  # fmt: skip
        return self.wrench_body


def _real(x) -> bool:
    """A command value must be a real number (a Python or numpy int or float, or a 0-d numpy array of one); a
    string, None or a bool is rejected like NaN."""
    if isinstance(x, np.ndarray):
        return x.ndim == 0 and x.dtype.kind in "iuf"
    return isinstance(x, numbers.Real) and not isinstance(x, bool | np.bool_)
