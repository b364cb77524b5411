"""X-band marine radar → marine_sensor_msgs/RadarSector per sample, an image and ARPA tracks per revolution.

The antenna turns clockwise seen from above (as marine radars do) at `rpm`; spoke k points at
-k·2π/spokes in the sensor frame (REP 103 angle, CCW from the bow), so sectors carry a negative
`angle_increment`. Spokes are emitted by time (spoke k at k / (spokes · rpm/60) s), so a reset replays them.

Per sample: the spokes swept since the last sample are cast as rays (beam.py) from the antenna against the
same Embree scenes as the LiDAR (visual geometry: everything cameras see, traffic ships included) → hits
below the water surface (z < 0) or on the own vessel give no echo (the own superstructure thus casts the
blind sectors it really casts) → each hit returns K · cos(incidence) · dΩ / (r / 1 km)² (K from
`reference_snr_db`: a 1 m² facing surface at 1 km), so bigger and broadside targets return more → fine rays
summed into range bins and weighted by the horizontal beam pattern → plus noise, sea clutter where the sea
is not shadowed, and rain (clutter.py) → echoes 0..1 over `dynamic_range_db`. Spokes in configured
`blind_sectors_deg` hold noise only. All powers are in units of the receiver noise.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.sensors.base import Sensor
from usvsim.sensors.lidar.raycast import RayWorld
from usvsim.sensors.radar import clutter, kernels
from usvsim.sensors.radar.beam import SpokeRays, elevations, two_way_gain
from usvsim.sensors.radar.revolution import Revolution

if TYPE_CHECKING:
    from usvsim.config.sensors import Radar as RadarConfig
    from usvsim.world.world import World

VISUAL_GROUP = 1
REFERENCE_SOLID_ANGLE = 1e-6  # sr: 1 m² at 1 km


class Radar(Sensor):
    cfg: RadarConfig

    def __init__(self, cfg: RadarConfig, vessel: str, world: World, shared: dict):
        super().__init__(cfg, vessel, world)
        self.n, self.bins = cfg.spokes, cfg.range_bins
        self.spokes_per_ns = cfg.rpm / 60.0 * cfg.spokes / 1e9
        per_sample = self.spokes_per_ns * self.every * world.clock.step_ns
        if per_sample > cfg.spokes:
            raise ValueError(f"rate_hz {cfg.rate_hz} Hz is too low for {cfg.rpm} rpm: one sample would sweep more "
                             f"than a turn; use at least {cfg.rpm / 60.0:g} Hz")  # fmt: skip
        self.bin_m = cfg.range_max_m / cfg.range_bins
        self.bin_centres = (np.arange(cfg.range_bins) + 0.5) * self.bin_m
        self.rays = SpokeRays(cfg.spokes, math.radians(cfg.horizontal_beamwidth_deg), cfg.azimuth_oversampling)
        self.gain = 10.0 ** (cfg.reference_snr_db / 10.0) / REFERENCE_SOLID_ANGLE
        sea = cfg.sea_clutter
        state = sea.sea_state if sea.sea_state is not None else clutter.sea_state_of(world.scenario.environment.sea)
        snr100 = sea.snr_at_100m_db if sea.snr_at_100m_db is not None else clutter.SEA_STATE_SNR_DB[state]
        near = self.bin_centres >= cfg.range_min_m
        self.sea_mean = clutter.sea_clutter_mean(self.bin_centres, snr100, sea.range_exponent) * near
        self.rain_mean = clutter.rain_mean(self.bin_centres, cfg.rain_rate_mm_h) * near
        self.blind = self._blind_spokes(cfg.blind_sectors_deg)
        key = "rays/visual"
        if key not in shared:
            shared[key] = RayWorld(world, VISUAL_GROUP)
        self.caster: RayWorld = shared[key]
        m = world.model
        self.own_geoms = np.flatnonzero(m.geom_bodyid == world.vessels[vessel].index + 1)
        self.revolution = Revolution(cfg, self.topic, self.frame_id, self.body)
        self.sector_cls, self.echo_cls = (ros.msg_class(f"marine_sensor_msgs/msg/{t}") for t in ("RadarSector", "RadarEcho"))
        self._weights: dict[int, np.ndarray] = {}
        self.emitted = 0

    def _blind_spokes(self, sectors) -> np.ndarray:
        angle = np.degrees(-np.arange(self.n) * 2 * np.pi / self.n) % 360.0
        blind = np.zeros(self.n, bool)
        for a, b in sectors:
            if b - a >= 360.0:  # all round: [0, 360] was reduced to [0, 0], one spoke
                blind[:] = True
                continue
            a, b = a % 360.0, b % 360.0
            blind |= (angle >= a) & (angle <= b) if a <= b else (angle >= a) | (angle <= b)
        return blind

    def reset(self, world: World) -> None:
        super().reset(world)
        self.emitted = 0
        self.revolution.reset()

    def sample(self, world: World, stamp_ns: int) -> list[Envelope]:
        k1 = int(math.floor(stamp_ns * self.spokes_per_ns + 1e-9))
        k0, count = self.emitted, k1 - self.emitted
        if count <= 0:
            return []
        self.emitted = k1
        power = self.sweep(world, k0, count)
        echoes = np.clip(10.0 * np.log10(power) / self.cfg.dynamic_range_db, 0.0, 1.0).astype(np.float32)
        pos, rot = self.pose_world(world)
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        out = [Envelope(self.topic, stamp_ns, self._sector(stamp_ns, k0, echoes))]
        return out + self.revolution.add(world, stamp_ns, k0, power, echoes, pos, yaw)

    def sweep(self, world: World, k0: int, count: int) -> np.ndarray:
        """Received power (count, bins), noise units, of spokes k0 .. k0 + count - 1 at the current pose."""
        cfg = self.cfg
        pos, rot = self.pose_world(world)
        el, water_r, width = elevations(pos[2], cfg.range_min_m, cfg.range_max_m, cfg.elevation_rays)
        # rays are levelled (the sparse elevations near the horizon must not tilt with the hull); the vertical beam
        # pattern is applied about the antenna's own, tilted, plane
        az = math.atan2(rot[1, 0], rot[0, 0]) - self.rays.azimuths(k0, count)  # world azimuths, clockwise spokes
        ce = np.cos(el)
        dirs = np.stack([np.cos(az)[:, None] * ce, np.sin(az)[:, None] * ce, np.broadcast_to(np.sin(el), (len(az), len(el)))], -1)
        dirs_world = dirs.reshape(-1, 3)
        off_plane = np.arcsin(np.clip(dirs_world @ rot[:, 2], -1.0, 1.0))
        w_ray = np.tile(width * ce, len(az)) * two_way_gain(off_plane, math.radians(cfg.vertical_beamwidth_deg))
        dist, geom, cos_inc = self.caster.cast(np.broadcast_to(pos, dirs_world.shape), dirs_world, cfg.range_max_m)
        dist = dist.astype(float)
        z_hit = pos[2] + dist * dirs_world[:, 2]
        own = np.isin(geom, self.own_geoms)
        valid = np.isfinite(dist) & ~own & (z_hit > 0.0) & (dist >= cfg.range_min_m)
        fine = np.flatnonzero(valid) // len(el)
        d = dist[valid]
        p = self.gain * cos_inc[valid] * w_ray[valid] * (self.rays.step / self.rays.oversampling) / (d / 1000.0) ** 2
        bins = np.minimum((d / self.bin_m).astype(np.int64), self.bins - 1)
        power = np.zeros((count, self.bins))
        kernels.spread_returns(fine, bins, p, self._horizontal(count), self.rays.oversampling, self.rays.margin, power)
        visible = self._sea_visible(dist.reshape(len(az), len(el)), water_r, count)
        power += clutter.background(self.rng, power.shape, self.sea_mean * visible, cfg.sea_clutter.shape, self.rain_mean)
        blind = self.blind[(k0 + np.arange(count)) % self.n]
        power[blind] = self.rng.standard_exponential((int(blind.sum()), self.bins))
        return power

    def _horizontal(self, count: int) -> np.ndarray:
        if count not in self._weights:
            self._weights[count] = self.rays.weights(count)
        return self._weights[count]

    def _sea_visible(self, dist: np.ndarray, water_r: np.ndarray, count: int) -> np.ndarray:
        """(count, bins) 1 where the sea surface at that range is in view (the ray to it is not blocked)."""
        m, margin = self.rays.oversampling, self.rays.margin
        centre = dist[(margin + np.arange(count)) * m + m // 2]  # the ray nearest each spoke's centre
        down = np.isfinite(water_r)
        blocked = centre[:, down] < water_r[down] * 0.999
        ray_of_bin = np.minimum(np.searchsorted(water_r[down], self.bin_centres), int(down.sum()) - 1)
        return ~blocked[:, ray_of_bin]

    def _sector(self, stamp_ns: int, k0: int, echoes: np.ndarray):
        """RadarSector of spokes k0.. (marine_sensor_msgs: range_min and range_max are the ranges of each ray's first
        and last samples, here the centres of the first and last range bins, where the ARPA puts an echo too; they
        were 0 and range_max_m, half a bin off at each end)."""
        step = 2.0 * math.pi / self.n
        spoke_ns = int(round(1.0 / self.spokes_per_ns))
        duration = ros.msg_class("builtin_interfaces/msg/Duration")
        turn_ns = int(round(self.n / self.spokes_per_ns))
        return self.sector_cls(
            header=ros.header(stamp_ns, self.frame_id), angle_start=float(-(k0 % self.n) * step),
            angle_increment=float(-step), time_increment=duration(sec=spoke_ns // 10**9, nanosec=spoke_ns % 10**9),
            scan_time=duration(sec=turn_ns // 10**9, nanosec=turn_ns % 10**9), range_min=float(self.bin_centres[0]),
            range_max=float(self.bin_centres[-1]), intensities=[self.echo_cls(echoes=row) for row in echoes])  # fmt: skip
