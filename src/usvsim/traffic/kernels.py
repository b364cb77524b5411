"""Numba kernels for traffic: every ship's track evaluated at one time, in one call (no Python per ship)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from usvsim.traffic.motion import Track


@dataclass(frozen=True)
class TrackTable:
    """The segments of many tracks, concatenated; ship k owns segments first[k] .. first[k] + count[k] - 1."""

    first: np.ndarray
    count: np.ndarray
    period_s: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    v0: np.ndarray
    v1: np.ndarray
    yaw0: np.ndarray
    yaw1: np.ndarray
    linear: np.ndarray

    @classmethod
    def of(cls, tracks: list[Track]) -> TrackTable:
        count = np.array([len(tr.t0) for tr in tracks], np.int64)
        first = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64)
        cat = {f: np.concatenate([getattr(tr, f) for tr in tracks]) if tracks else np.zeros((0, 2) if f[0] in "pv" else 0)
               for f in ("t0", "t1", "p0", "p1", "v0", "v1", "yaw0", "yaw1", "linear")}  # fmt: skip
        cat = {k: np.ascontiguousarray(v, bool if k == "linear" else float) for k, v in cat.items()}
        return cls(first, count, np.array([tr.period_s for tr in tracks], float), **cat)

    def evaluate(self, t_s: float, pos: np.ndarray, vel: np.ndarray, yaw: np.ndarray) -> None:
        """Fill pos (N, 2), vel (N, 2), yaw (N,) of every ship at time t_s."""
        evaluate(t_s, self.first, self.count, self.period_s, self.t0, self.t1, self.p0, self.p1, self.v0, self.v1,
                 self.yaw0, self.yaw1, self.linear, pos, vel, yaw)  # fmt: skip


@njit(cache=True)
def _segment(t, t0, count, first):
    lo, hi = first, first + count - 1  # last segment with t0 <= t (binary search)
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if t0[mid] <= t:
            lo = mid
        else:
            hi = mid - 1
    return lo


@njit(cache=True)
def evaluate(t_s, first, count, period, t0, t1, p0, p1, v0, v1, yaw0, yaw1, linear, pos, vel, yaw):
    for k in range(len(first)):
        a, n = first[k], count[k]
        t = t_s
        if period[k] > 0.0:
            t = t0[a] + (t - t0[a]) % period[k]
        if t < t0[a]:  # not yet started: at rest at the start
            pos[k, 0], pos[k, 1], vel[k, 0], vel[k, 1], yaw[k] = p0[a, 0], p0[a, 1], 0.0, 0.0, yaw0[a]
            continue
        s = _segment(t, t0, n, a)
        if t >= t1[s]:  # past the end: at rest at the end
            pos[k, 0], pos[k, 1], vel[k, 0], vel[k, 1], yaw[k] = p1[s, 0], p1[s, 1], 0.0, 0.0, yaw1[s]
            continue
        dt = t - t0[s]
        if linear[s]:
            for i in range(2):
                pos[k, i] = p0[s, i] + v0[s, i] * dt
                vel[k, i] = v0[s, i]
            yaw[k] = yaw0[s]
            continue
        h = t1[s] - t0[s]
        u = dt / h
        h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
        d00, d10, d01, d11 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1, -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
        for i in range(2):
            pos[k, i] = h00 * p0[s, i] + h10 * h * v0[s, i] + h01 * p1[s, i] + h11 * h * v1[s, i]
            vel[k, i] = (d00 * p0[s, i] + d10 * h * v0[s, i] + d01 * p1[s, i] + d11 * h * v1[s, i]) / h
        yaw[k] = (yaw0[s] + u * (yaw1[s] - yaw0[s]) + math.pi) % (2.0 * math.pi) - math.pi


@njit(cache=True)
def place_ships(pos, yaw, owner_geom, local, geom_pos, geom_quat, box, radius, body_pos, body_radius, conaffinity,
                affinity):  # fmt: skip
    """Put the kinematic ships' geoms where the ships are and let a ship's collision box pair with floating bodies
    only while it is near one. Ship k: pos (N, 2) ENU m, yaw (N,) rad, collision box geom box[k] with bounding
    radius radius[k] m. Geom j (owner_geom[j] = ship, geom id): pose in its ship's frame local[j] = (x, y, z m,
    w, x, y, z quaternion). Floating bodies: body_pos (B, 3) m, body_radius (B,) m, margin included. Writes
    MuJoCo's geom_pos, geom_quat and conaffinity (`affinity` near, 0 far); returns the number of boxes near."""
    n = len(yaw)
    trig = np.empty((n, 4))
    near = 0
    for k in range(n):
        w, z = math.cos(0.5 * yaw[k]), math.sin(0.5 * yaw[k])
        trig[k, 0], trig[k, 1], trig[k, 2], trig[k, 3] = w * w - z * z, 2.0 * w * z, w, z  # cos, sin of yaw
        hit = False
        for b in range(len(body_radius)):
            dx, dy = body_pos[b, 0] - pos[k, 0], body_pos[b, 1] - pos[k, 1]
            reach = radius[k] + body_radius[b]
            if dx * dx + dy * dy < reach * reach:
                hit = True
                break
        conaffinity[box[k]] = affinity if hit else 0
        near += hit
    for j in range(len(owner_geom)):
        k, g = owner_geom[j, 0], owner_geom[j, 1]
        c, s, w, z = trig[k, 0], trig[k, 1], trig[k, 2], trig[k, 3]
        geom_pos[g, 0] = pos[k, 0] + c * local[j, 0] - s * local[j, 1]
        geom_pos[g, 1] = pos[k, 1] + s * local[j, 0] + c * local[j, 1]
        geom_pos[g, 2] = local[j, 2]
        qw, qx, qy, qz = local[j, 3], local[j, 4], local[j, 5], local[j, 6]  # (w, 0, 0, z) * local quaternion
        geom_quat[g, 0], geom_quat[g, 1] = w * qw - z * qz, w * qx - z * qy
        geom_quat[g, 2], geom_quat[g, 3] = w * qy + z * qx, w * qz + z * qw
    return near


@njit(cache=True)
def evaluate_and_place(t_s, first, count, period, t0, t1, p0, p1, v0, v1, yaw0, yaw1, linear, pos, vel, yaw,
                       owner_geom, local, geom_pos, geom_quat, box, radius, body_pos, body_radius, conaffinity,
                       affinity):  # fmt: skip
    """`evaluate` then `place_ships` in one call (one dispatch per physics step)."""
    evaluate(t_s, first, count, period, t0, t1, p0, p1, v0, v1, yaw0, yaw1, linear, pos, vel, yaw)
    return place_ships(pos, yaw, owner_geom, local, geom_pos, geom_quat, box, radius, body_pos, body_radius,
                       conaffinity, affinity)  # fmt: skip
