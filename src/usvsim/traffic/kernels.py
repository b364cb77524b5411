"""Numba kernels for traffic: every ship's track evaluated at one time, in one call (no Python per ship)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np
from numba import njit, types
from numba.experimental import structref

from usvsim.traffic.motion import Track

# columns of `TrackTable.seg`, one row per segment
T0, T1, P0, P1, V0, V1, YAW0, YAW1, LINEAR, HALF_COS0, HALF_SIN0 = 0, 1, 2, 4, 6, 8, 10, 11, 12, 13, 14
SEG_COLUMNS = 15
# columns of the per-ship tables: integers (segments, colliding geom or -1, geoms), floats
FIRST, COUNT, BOX, GEOM_FIRST, GEOM_END = range(5)
PERIOD, RADIUS = range(2)


@dataclass(frozen=True)
class TrackTable:
    """The segments of many tracks, concatenated into one table: ship k owns rows ship_i[k, FIRST] ..
    ship_i[k, FIRST] + ship_i[k, COUNT] - 1 of `seg` (columns above: times s, ENU positions m and velocities m/s
    as x, y pairs, yaws rad, linear 1/0, and cos, sin of half the start yaw, so straight segments need no
    trigonometry per step); ship_f[k, PERIOD] > 0 repeats a track. The geom columns are for `evaluate_and_place`
    (fleet.py fills them in a copy; here: no geoms)."""

    ship_i: np.ndarray
    ship_f: np.ndarray
    seg: np.ndarray

    @classmethod
    def of(cls, tracks: list[Track]) -> TrackTable:
        count = np.array([len(tr.t0) for tr in tracks], np.int64)
        ship_i = np.zeros((len(tracks), 5), np.int64)
        ship_i[:, FIRST], ship_i[:, COUNT], ship_i[:, BOX] = np.cumsum(count) - count, count, -1
        ship_f = np.zeros((len(tracks), 2))
        ship_f[:, PERIOD] = [tr.period_s for tr in tracks]
        seg = np.zeros((int(count.sum()), SEG_COLUMNS))
        for tr, a, n in zip(tracks, ship_i[:, FIRST], count):
            rows = seg[a : a + n]
            rows[:, T0], rows[:, T1], rows[:, YAW0], rows[:, YAW1] = tr.t0, tr.t1, tr.yaw0, tr.yaw1
            rows[:, P0 : P0 + 2], rows[:, P1 : P1 + 2] = tr.p0, tr.p1
            rows[:, V0 : V0 + 2], rows[:, V1 : V1 + 2] = tr.v0, tr.v1
            rows[:, LINEAR] = np.asarray(tr.linear, bool)
            rows[:, HALF_COS0], rows[:, HALF_SIN0] = np.cos(0.5 * rows[:, YAW0]), np.sin(0.5 * rows[:, YAW0])
        return cls(ship_i, ship_f, seg)

    def __len__(self) -> int:
        return len(self.ship_i)

    @functools.cached_property
    def _no_geoms(self) -> tuple:
        """`evaluate_and_place`'s geom and body arguments for no geoms and no bodies (same types: one compilation)."""
        return (np.zeros(0, np.int64), np.zeros((0, 7)), np.zeros((0, 3)), np.zeros((0, 4)), np.zeros((0, 3)),
                np.zeros(0), np.zeros(0, np.int32), 0, np.zeros(1))  # fmt: skip

    def evaluate(self, t_s: float, pos: np.ndarray, vel: np.ndarray, yaw: np.ndarray) -> None:
        """Fill pos (N, 2), vel (N, 2), yaw (N,) of every ship at time t_s."""
        evaluate_and_place(t_s, self.ship_i, self.ship_f, self.seg, pos, vel, yaw, *self._no_geoms)


@njit(cache=True)
def _segment(t, seg, count, first):
    lo, hi = first, first + count - 1  # last segment with t0 <= t (binary search)
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if seg[mid, T0] <= t:
            lo = mid
        else:
            hi = mid - 1
    return lo


@njit(cache=True)
def evaluate_and_place(t_s, ship_i, ship_f, seg, pos, vel, yaw, geoms, local, geom_pos, geom_quat, body_pos,
                       body_radius, conaffinity, affinity, clearance):  # fmt: skip
    """Every track at t_s (into pos, vel, yaw), then the kinematic ships' geoms put where the ships are, a
    ship's colliding geom (its hull) pairing with floating bodies only while it is near one; one call per physics step
    (few arguments: numba's dispatch costs ~50 ns per array). Ship k (tables above): pos (N, 2) ENU m, yaw (N,)
    rad, colliding geom ship_i[k, BOX] (-1: none) with bounding radius ship_f[k, RADIUS] m, geoms
    geoms[ship_i[k, GEOM_FIRST] : ship_i[k, GEOM_END]] with their poses in the ship's frame local[j] = (x, y, z m,
    w, x, y, z quaternion). Floating bodies: body_pos (B, 3) m, body_radius (B,) m, margin included. Writes
    MuJoCo's geom_pos, geom_quat and conaffinity (`affinity` near, 0 far); returns the number of ships near, and
    writes into clearance[0] a lower bound (m) of the least distance between a ship's colliding reach and a
    floating body's (< 0 where some ship is near; inf without either)."""
    near = 0
    least = math.inf
    lo_x = lo_y = math.inf  # the box around every floating body's reach: most ships are far from all of them
    hi_x = hi_y = -math.inf
    for b in range(len(body_radius)):
        lo_x, hi_x = min(lo_x, body_pos[b, 0] - body_radius[b]), max(hi_x, body_pos[b, 0] + body_radius[b])
        lo_y, hi_y = min(lo_y, body_pos[b, 1] - body_radius[b]), max(hi_y, body_pos[b, 1] + body_radius[b])
    for k in range(len(ship_i)):  # the track at t_s (written out here: a helper taking the arrays costs 50 ns a call)
        a, n, period = ship_i[k, FIRST], ship_i[k, COUNT], ship_f[k, PERIOD]
        t = t_s
        if period > 0.0:
            t = seg[a, T0] + (t - seg[a, T0]) % period
        if t < seg[a, T0]:  # not yet started: at rest at the start
            pos[k, 0], pos[k, 1], vel[k, 0], vel[k, 1], yaw[k] = seg[a, P0], seg[a, P0 + 1], 0.0, 0.0, seg[a, YAW0]
            w, z = seg[a, HALF_COS0], seg[a, HALF_SIN0]
        else:
            i = _segment(t, seg, n, a)
            if t >= seg[i, T1]:  # past the end: at rest at the end
                pos[k, 0], pos[k, 1], vel[k, 0], vel[k, 1], yaw[k] = seg[i, P1], seg[i, P1 + 1], 0.0, 0.0, seg[i, YAW1]
                w, z = math.cos(0.5 * yaw[k]), math.sin(0.5 * yaw[k])
            elif seg[i, LINEAR] != 0.0:
                dt = t - seg[i, T0]
                pos[k, 0], pos[k, 1] = seg[i, P0] + seg[i, V0] * dt, seg[i, P0 + 1] + seg[i, V0 + 1] * dt
                vel[k, 0], vel[k, 1], yaw[k] = seg[i, V0], seg[i, V0 + 1], seg[i, YAW0]
                w, z = seg[i, HALF_COS0], seg[i, HALF_SIN0]
            else:  # cubic Hermite from (p0, v0) to (p1, v1) over h seconds
                h = seg[i, T1] - seg[i, T0]
                u = (t - seg[i, T0]) / h
                h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
                d00, d10, d01, d11 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1, -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
                for j in range(2):
                    p0, p1, v0, v1 = seg[i, P0 + j], seg[i, P1 + j], seg[i, V0 + j], seg[i, V1 + j]
                    pos[k, j] = h00 * p0 + h10 * h * v0 + h01 * p1 + h11 * h * v1
                    vel[k, j] = (d00 * p0 + d10 * h * v0 + d01 * p1 + d11 * h * v1) / h
                yaw[k] = (seg[i, YAW0] + u * (seg[i, YAW1] - seg[i, YAW0]) + math.pi) % (2.0 * math.pi) - math.pi
                w, z = math.cos(0.5 * yaw[k]), math.sin(0.5 * yaw[k])
        c, s = w * w - z * z, 2.0 * w * z  # cos, sin of the yaw
        x, y = pos[k, 0], pos[k, 1]
        box = ship_i[k, BOX]
        if box >= 0:
            hit = False
            r = ship_f[k, RADIUS]
            inside = lo_x - r < x < hi_x + r and lo_y - r < y < hi_y + r
            if not inside:  # outside the box of every body's reach: its distance to the box bounds the clearance
                least = min(least, max(lo_x - r - x, x - hi_x - r, lo_y - r - y, y - hi_y - r))
            for b in range(len(body_radius) if inside else 0):
                dx, dy = body_pos[b, 0] - x, body_pos[b, 1] - y
                reach = r + body_radius[b]
                if dx * dx + dy * dy < reach * reach:
                    hit = True
                    least = -1.0
                    break
                least = min(least, math.sqrt(dx * dx + dy * dy) - reach)
            conaffinity[box] = affinity if hit else 0
            near += hit
        for j in range(ship_i[k, GEOM_FIRST], ship_i[k, GEOM_END]):
            g = geoms[j]
            geom_pos[g, 0] = x + c * local[j, 0] - s * local[j, 1]
            geom_pos[g, 1] = y + s * local[j, 0] + c * local[j, 1]
            geom_pos[g, 2] = local[j, 2]
            qw, qx, qy, qz = local[j, 3], local[j, 4], local[j, 5], local[j, 6]  # (w, 0, 0, z) * local quaternion
            geom_quat[g, 0], geom_quat[g, 1] = w * qw - z * qz, w * qx - z * qy
            geom_quat[g, 2], geom_quat[g, 3] = w * qy + z * qx, w * qz + z * qw
    clearance[0] = least
    return near


@structref.register
class _FleetArgsType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class FleetArgs(structref.StructRefProxy):
    """`evaluate_and_place`'s arguments after t_s, bound once into one numba object (fields named as its
    parameters; the arrays are the caller's, written in place): `place_fleet` then costs one cheap argument to
    unbox per step instead of 13 arrays (~0.5 µs of numba's dispatch at 50 ships)."""


_FIELDS = ("ship_i", "ship_f", "seg", "pos", "vel", "yaw", "geoms", "local", "geom_pos", "geom_quat", "body_pos",
           "body_radius", "conaffinity", "affinity", "clearance")  # fmt: skip
structref.define_proxy(FleetArgs, _FleetArgsType, list(_FIELDS))


@njit(cache=True)
def _pack(ship_i, ship_f, seg, pos, vel, yaw, geoms, local, geom_pos, geom_quat, body_pos, body_radius, conaffinity,
          affinity, clearance):  # fmt: skip
    return FleetArgs(ship_i, ship_f, seg, pos, vel, yaw, geoms, local, geom_pos, geom_quat, body_pos, body_radius,
                     conaffinity, affinity, clearance)  # fmt: skip


@njit(cache=True)
def place_fleet(t_s, a):
    """`evaluate_and_place(t_s, ...)` with the arguments bound in `a` (a `FleetArgs`); returns the ships near."""
    return evaluate_and_place(t_s, a.ship_i, a.ship_f, a.seg, a.pos, a.vel, a.yaw, a.geoms, a.local, a.geom_pos,
                              a.geom_quat, a.body_pos, a.body_radius, a.conaffinity, a.affinity, a.clearance)  # fmt: skip


def fleet_placer(args: tuple) -> tuple[FleetArgs, Callable[[float, FleetArgs], int]]:
    """(`FleetArgs` of `args`, a function f(t_s, packed) -> ships near): `place_fleet`'s compiled entry point
    for exactly the packed argument's type where numba exposes it (skipping the dispatcher's type lookup saves
    ~0.4 µs a call), else `place_fleet` itself."""
    packed = _pack(*[*args[:-2], int(args[-2]), args[-1]])
    key = (types.float64, numba.typeof(packed))
    try:
        place_fleet.compile(key)  # compiled or loaded from the cache once per type; nothing is called
        entry = place_fleet.overloads[key].entry_point
    except (AttributeError, KeyError, TypeError):  # numba's internals changed: the dispatcher (type checked)
        entry = None
    call: Callable[[float, FleetArgs], int] = entry if callable(entry) else place_fleet  # type: ignore[assignment]
    return packed, call
