"""Sensor observations of the task envs: the WAM-V gets a planar LiDAR and/or a camera, sampled at the control
rate, and the env returns their latest readings (`Simulation.observe()`, sensors/readings.py) as arrays:

- `lidar`: Box(0, LIDAR_RANGE_M, (LIDAR_COLUMNS,), float32): per bearing sector, the nearest horizontal range
  (m) of a 4-channel scanner (elevations −8…+4°, so a pitching boat still sees low buoys); sector i covers
  bearings [−180° + i·w, −180° + (i+1)·w), w = 360°/LIDAR_COLUMNS, counter-clockwise, 0 = ahead (sensor FLU).
  The scanner sits low at the bow, 2.6 m ahead of and 0.3 m above base_link, as marker buoys stand only
  ~0.3 m out of the water (the own hull is transparent to it, the water gives no returns); an empty sector
  reads LIDAR_RANGE_M;
- `camera`: Box(0, 255, (CAMERA_HEIGHT, CAMERA_WIDTH, 3), uint8), RGB looking ahead (80° horizontal field).
Before a sensor's first sample (right after `reset`) its observation is the "nothing seen" value (all
ranges at the maximum, a black image).
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

SENSORS = ("lidar", "camera")
LIDAR_COLUMNS, LIDAR_RANGE_M = 180, 60.0
CAMERA_WIDTH, CAMERA_HEIGHT = 96, 72


def sensor_configs(wanted, rate_hz: float) -> list[dict]:
    """Scenario `sensors` entries for the WAM-V (names `lidar`, `camera`)."""
    out = []
    if "lidar" in wanted:
        out.append({"type": "lidar", "name": "lidar", "output": "points", "elevations_deg": [-8.0, -4.0, 0.0, 4.0],
                    "columns": 2 * LIDAR_COLUMNS, "range_max_m": LIDAR_RANGE_M, "rate_hz": rate_hz,
                    "mount": {"position": [2.6, 0.0, 0.3]}, "self_returns": False})  # fmt: skip
    if "camera" in wanted:
        out.append({"type": "camera", "name": "camera", "width": CAMERA_WIDTH, "height": CAMERA_HEIGHT,
                    "rate_hz": rate_hz, "mount": {"position": [1.0, 0.0, 1.5]}})  # fmt: skip
    return out


def sensor_spaces(wanted) -> dict[str, spaces.Space]:
    out: dict[str, spaces.Space] = {}
    if "lidar" in wanted:
        out["lidar"] = spaces.Box(0.0, LIDAR_RANGE_M, (LIDAR_COLUMNS,), np.float32)
    if "camera" in wanted:
        out["camera"] = spaces.Box(0, 255, (CAMERA_HEIGHT, CAMERA_WIDTH, 3), np.uint8)
    return out


def sensor_arrays(sim, wanted, vessel: str = "wamv") -> dict[str, np.ndarray]:
    """The latest readings as observation arrays (copies: the env owns what it returns)."""
    readings, out = sim.observe(), {}
    if "lidar" in wanted:
        r = readings.get(f"{vessel}/lidar")
        out["lidar"] = sectors(None if r is None else r["points"])
    if "camera" in wanted:
        r = readings.get(f"{vessel}/camera")
        out["camera"] = np.zeros((CAMERA_HEIGHT, CAMERA_WIDTH, 3), np.uint8) if r is None else np.array(r["rgb"])
    return out


def sectors(points) -> np.ndarray:
    """Nearest horizontal range per bearing sector (see the module docstring) of a PointCloud2 reading."""
    out = np.full(LIDAR_COLUMNS, LIDAR_RANGE_M, np.float32)
    if points is None or points.size == 0:
        return out
    x, y = points["x"].ravel().astype(float), points["y"].ravel().astype(float)
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    sector = ((np.arctan2(y, x) + np.pi) * (LIDAR_COLUMNS / (2 * np.pi))).astype(int) % LIDAR_COLUMNS
    np.minimum.at(out, sector, np.minimum(np.hypot(x, y), LIDAR_RANGE_M).astype(np.float32))
    return out
