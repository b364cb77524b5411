"""Scan patterns of spinning LiDARs: channel elevations and column azimuths in the sensor frame (FLU).

Azimuth 0 is +x (forward), counter-clockwise positive (REP 103); elevation is positive up. For a full
360° sweep the N columns are spaced fov/N (no duplicate beam at ±180°); for a partial sweep fov/(N-1),
so the first and last beams sit on the edges. The sweep runs from the lowest azimuth to the highest
(`spin: counter_clockwise`), or from the highest to the lowest (`clockwise`: the increment is negative).
Ring 0 is the lowest channel (Velodyne convention).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.config.sensors import Lidar as LidarConfig


@dataclass(frozen=True)
class Pattern:
    elevations_deg: tuple[float, ...]
    columns: int
    horizontal_fov_deg: float
    range_min_m: float
    range_max_m: float
    output: str = "points"
    range_stddev_m: float = 0.0
    clockwise: bool = False


def _even(lo: float, hi: float, n: int) -> tuple[float, ...]:
    return tuple(np.linspace(lo, hi, n).tolist()) if n > 1 else (0.5 * (lo + hi),)


PRESETS = {
    "vlp16": Pattern(_even(-15.0, 15.0, 16), 1800, 360.0, 0.5, 100.0, range_stddev_m=0.03),
    "os1_64": Pattern(_even(-22.5, 22.5, 64), 2048, 360.0, 0.5, 120.0, range_stddev_m=0.03),
    "os1_128": Pattern(_even(-22.5, 22.5, 128), 2048, 360.0, 0.5, 120.0, range_stddev_m=0.03),
    "vrx": Pattern(_even(-15.0, 15.0, 16), 1875, 360.0, 0.1, 130.0, range_stddev_m=0.01),  # gpu_ray ±π/12, 1875
    "seed_3d": Pattern(tuple(-39.375 + 5.625 * k for k in range(16)), 500, 360.0, 0.3, 100.0),  # 500×16, +45..-39.375
    "seed_2d": Pattern((0.0,), 8000, 360.0, 0.1, 50.0, output="scan"),  # ±180° at 0.045°
    "custom": Pattern(_even(-15.0, 15.0, 16), 1024, 360.0, 0.1, 100.0),
}


def resolve(cfg: LidarConfig) -> Pattern:
    """The preset with the config's explicit values applied."""
    p = PRESETS[cfg.preset]
    elevations = p.elevations_deg
    channels = cfg.channels
    if cfg.elevations_deg is not None:
        elevations = tuple(cfg.elevations_deg)
    elif cfg.vertical_fov_deg is not None or channels is not None:
        lo, hi = cfg.vertical_fov_deg or (min(elevations), max(elevations))
        elevations = _even(lo, hi, channels or len(elevations))
    if channels is not None and len(elevations) != channels:
        raise ValueError(f"channels = {channels} but {len(elevations)} elevations are given")
    output = cfg.output or p.output
    if output == "scan" and len(elevations) != 1:
        raise ValueError("a LaserScan LiDAR (output: scan) needs exactly one channel")
    range_min, range_max = p.range_min_m if cfg.range_min_m is None else cfg.range_min_m, cfg.range_max_m or p.range_max_m
    if range_min >= range_max:
        raise ValueError(f"range_min_m ({range_min} m) must be less than range_max_m ({range_max} m)")
    return Pattern(tuple(sorted(elevations)), cfg.columns or p.columns, cfg.horizontal_fov_deg or p.horizontal_fov_deg,
                   range_min, range_max, output,
                   p.range_stddev_m if cfg.range_stddev_m is None else cfg.range_stddev_m,
                   cfg.spin == "clockwise")  # fmt: skip


def azimuths(p: Pattern) -> tuple[np.ndarray, float]:
    """Column azimuths (rad) in firing order and the increment between them (negative for a clockwise spin)."""
    fov = np.radians(p.horizontal_fov_deg)
    full = p.horizontal_fov_deg >= 360.0
    inc = fov / p.columns if full or p.columns == 1 else fov / (p.columns - 1)
    az = -0.5 * fov + inc * np.arange(p.columns)
    return (az[::-1].copy(), -float(inc)) if p.clockwise else (az, float(inc))


def directions(p: Pattern) -> np.ndarray:
    """Unit beam directions (channels, columns, 3) in the sensor frame (FLU)."""
    az, _ = azimuths(p)
    el = np.radians(np.asarray(p.elevations_deg))[:, None]
    return np.stack(np.broadcast_arrays(np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el) + 0 * az), axis=-1)
