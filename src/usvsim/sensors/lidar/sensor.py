"""Spinning LiDAR → sensor_msgs/PointCloud2 (3D) or sensor_msgs/LaserScan (2D), frame `<vessel>/<name>` (FLU).

Per scan: beam directions (pattern) → world rays from the mount pose → Embree nearest hits against all
static and moving geometry (`RayWorld`; the hits on the own vessel are cast once, in its frame, and kept)
→ hits below the water removed (optional water returns) →
range limits [range_min, range_max] → Gaussian range noise → dropout. A missing return is +inf in a
LaserScan (REP 117) and NaN in an organized cloud; unorganized clouds hold returns only.

Intensity = reflectivity(geom) · |cos incidence|, in [0, 1]; reflectivity is the luminance of the geom's
colour (clamped to [0.05, 1]) unless `reflectivity[<body name>]` ('world' for static objects) sets it.

Self returns: beams that hit the own vessel return its hull (as a real sensor does); `self_returns: false`
crops them (no return for those beams; exact, by geom, unlike a body box or a minimum range).

Timing: without motion distortion the whole sweep is taken at the sample instant (header stamp, point
`time` 0). With `motion_distortion`, column c fires at stamp + c·T/N (T = 1/rate), the header stamp is the
first column's time (the sweep ends at the sample tick) and each column is cast from the mount pose
extrapolated back from the current velocity and body rates (first order); the world geometry is taken
at the sample tick, except the vessel's own hull, which moves with the sensor (its returns stay put).
The cloud is published when the sweep ends (the sample tick): its envelope's `publish_ns` (the MCAP log
time) is the tick, never before the sweep could exist, while the header keeps the Ouster/Velodyne
convention of stamping the first column with non-negative point times.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from usvsim.config.base import KeyedValueError
from usvsim.messages.envelope import Envelope
from usvsim.sensors.base import Sensor
from usvsim.sensors.lidar import kernels, patterns
from usvsim.sensors.lidar.raycast import RayWorld
from usvsim.sensors.lidar.scene import NO_HIT
from usvsim.sensors.lidar.water import sunk_hits, surface_hits
from usvsim.sensors.messages import POINT_DTYPE, laser_scan_msg, point_cloud2_msg
from usvsim.sensors.navigation import mount_velocity_world
from usvsim.world.builder import geom_owners

if TYPE_CHECKING:
    from usvsim.config.sensors import Lidar as LidarConfig
    from usvsim.world.world import World

GROUPS = {"visual": 1, "collision": 3}
WATER = -2  # geom id of a water return
_NO_DRAWS = np.zeros(0)


def reflectivities(sim: World, overrides: dict[str, float]) -> np.ndarray:
    """Per MuJoCo geom reflectivity in [0.05, 1] (+ water at index WATER)."""
    m = sim.model
    luminance = m.geom_rgba[:, :3] @ np.array([0.2126, 0.7152, 0.0722])
    refl = np.clip(luminance, 0.05, 1.0)
    owners = geom_owners(m)  # "world", floating bodies, traffic ships
    unknown = next((name for name in overrides if name not in owners), None)
    if unknown is not None:  # a misspelt body was ignored without a word
        known = ", ".join(sorted(set(owners), key=lambda n: (n != "world", n)))
        raise KeyedValueError(f"reflectivity.{unknown}", f"no body named {unknown!r}; the bodies: {known}")
    for g, owner in enumerate(owners):
        refl[g] = overrides.get(owner, refl[g])
    return np.append(refl, [0.0, 0.0]).astype(np.float32)


def rotations(rotvecs: np.ndarray) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of rotation vectors (n, 3) (Rodrigues)."""
    angle = np.linalg.norm(rotvecs, axis=1)
    axis = rotvecs / np.maximum(angle, 1e-15)[:, None]
    k = np.zeros((len(rotvecs), 3, 3))
    k[:, 0, 1], k[:, 0, 2], k[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    k -= k.transpose(0, 2, 1)
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


class Lidar(Sensor):
    cfg: LidarConfig

    def __init__(self, cfg: LidarConfig, vessel: str, sim: World, shared: dict):
        super().__init__(cfg, vessel, sim)
        self.pattern = p = patterns.resolve(cfg)
        self.azimuths, self.increment = patterns.azimuths(p)
        self.dirs_local = patterns.directions(p).reshape(-1, 3).astype(np.float32)  # row-major: ring, column
        self._origins, self._dirs_world = np.empty_like(self.dirs_local), np.empty_like(self.dirs_local)
        self._no_times = np.zeros(len(self.dirs_local), np.float32)  # point times without motion distortion
        self.channels, self.columns = len(p.elevations_deg), p.columns
        self.ring = np.repeat(np.arange(self.channels, dtype=np.uint16), self.columns)
        self.column = np.tile(np.arange(self.columns), self.channels)
        self.topic = cfg.topic or f"/{vessel}/{cfg.name}/{'scan' if p.output == 'scan' else 'points'}"
        key = f"rays/{cfg.geometry}"
        if key not in shared:
            shared[key] = RayWorld(sim, GROUPS[cfg.geometry])
        self.world: RayWorld = shared[key]
        self._own_scene = self.world.scene_of(self.body)  # the vessel's own geometry, None if it has none
        self._own_hits = None  # hits of the beams on the own vessel: fixed in its frame, cast once
        self._own_geoms = np.flatnonzero(sim.model.geom_bodyid == self.body + 1)  # MuJoCo body id = index + 1
        self.reflectivity = reflectivities(sim, dict(cfg.reflectivity))
        self.reflectivity[WATER] = cfg.water_reflectivity
        self.sweep_s = self.every * sim.clock.dt

    def _rays(self, sim: World) -> tuple[np.ndarray, np.ndarray, int, np.ndarray]:
        """World origins (n, 3), directions (n, 3), header stamp offset (ns), per-point time (s)."""
        origin, rot = self.pose_world(sim)
        if not self.cfg.motion_distortion:
            kernels.world_rays(self.dirs_local, origin, rot, self._origins, self._dirs_world)
            return self._origins, self._dirs_world, 0, self._no_times
        fire = np.arange(self.columns) * self.sweep_s / self.columns  # s after the first column
        back = fire[-1] - fire  # how long before the sample tick each column fired
        omega_sensor = self.mount_rot.T @ sim.state.omega_body[self.body]
        rot_col = rot @ rotations(-back[:, None] * omega_sensor)  # (columns, 3, 3)
        origin_col = origin - back[:, None] * mount_velocity_world(self, sim)
        kernels.column_rays(self.dirs_local, self.column, origin_col, rot_col, self._origins, self._dirs_world)
        return self._origins, self._dirs_world, -round(back[0] * 1e9), fire.astype(np.float32)[self.column]

    def _cast(self, origins: np.ndarray, dirs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`RayWorld.cast` of the world rays. The beams are fixed in the vessel's frame (also while a distorted
        sweep goes on: the hull moves with the sensor), so their hits on the vessel itself never change: they
        are cast once there, and each scan casts only against the rest of the world."""
        max_range = self.pattern.range_max_m
        if self._own_scene is None:
            return self.world.cast(origins, dirs, max_range)
        if self._own_hits is None:
            dirs_body = self.dirs_local @ self.mount_rot.T.astype(np.float32)
            origins_body = np.broadcast_to(self.mount_pos.astype(np.float32), dirs_body.shape)
            self._own_hits = self.world.cast_in_body(self._own_scene, origins_body, dirs_body, max_range)
        return self.world.cast(origins, dirs, max_range, prior=self._own_hits, skip=self._own_scene)

    def measure(self, sim: World) -> tuple[np.ndarray, np.ndarray, int, np.ndarray]:
        """Ranges (n,) m with +inf for no return, intensities (n,), stamp offset ns, point times (n,) s."""
        p, cfg = self.pattern, self.cfg
        origins, dirs, offset_ns, times = self._rays(sim)
        dist, geom, cos_inc = self._cast(origins, dirs)
        if not cfg.self_returns and len(self._own_geoms):
            own = np.isin(geom, self._own_geoms)
            dist[own], geom[own] = np.inf, NO_HIT
        sunk = sunk_hits(sim.ocean, origins, dirs, dist, sim.time)
        dist[sunk], geom[sunk] = np.inf, NO_HIT
        if cfg.water_returns:
            draws = self.rng.random(len(dist))
            w_dist, w_cos = surface_hits(sim.ocean, origins, dirs, sim.time, p.range_max_m, draws)
            ret = (w_dist < dist) & (draws < w_cos**2)
            dist[ret], geom[ret], cos_inc[ret] = w_dist[ret], WATER, w_cos[ret]
        drops = self.rng.random(len(dist)) if cfg.dropout > 0 else _NO_DRAWS
        count = kernels.drop_invalid(dist, p.range_min_m, drops, cfg.dropout)  # the cast stops at range_max_m
        noise = self.rng.standard_normal(count, np.float32) if p.range_stddev_m > 0 else self._no_times[:0]
        intensity = np.empty(len(dist), np.float32)
        kernels.noisy_returns(dist, geom, cos_inc, noise, np.float32(p.range_stddev_m), self.reflectivity, intensity)
        return dist, intensity, offset_ns, times

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        dist, intensity, offset_ns, times = self.measure(sim)
        stamp = stamp_ns + offset_ns
        if self.pattern.output == "scan":
            msg = laser_scan_msg(stamp, self.frame_id, self.azimuths[0], self.increment, dist, intensity,
                                 self.pattern.range_min_m, self.pattern.range_max_m, self.sweep_s)  # fmt: skip
            if self.cfg.motion_distortion:
                msg.time_increment = float(self.sweep_s / self.columns)
            return [Envelope(self.topic, stamp, msg)]
        return [Envelope(self.topic, stamp, self.cloud(stamp, dist, intensity, times))]

    def cloud(self, stamp_ns: int, dist: np.ndarray, intensity: np.ndarray, times: np.ndarray):
        """PointCloud2 in the sensor frame, packed by one kernel pass into one buffer (no per-point Python)."""
        organized = bool(self.cfg.organized)
        pts = np.empty(len(dist) if organized else int(np.isfinite(dist).sum()), POINT_DTYPE)
        kernels.pack_points(self.dirs_local, dist, intensity, self.ring, times, organized,
                            pts.view(np.float32).reshape(-1, 6), pts.view(np.uint16).reshape(-1, 12))  # fmt: skip
        height, width = (self.channels, self.columns) if organized else (1, len(pts))
        return point_cloud2_msg(stamp_ns, self.frame_id, pts, height, width)
