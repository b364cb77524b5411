"""A small scenario for the Foxglove bridge tests: a WAM-V with a small 3D LiDAR and a small camera on a
sea-state-3 sea, one buoy and a dock; and a bridge on a free loopback port."""

from __future__ import annotations

from usvsim.config.loader import parse_scenario
from usvsim.simulation import Simulation

MOUNT = {"position": [0.7, 0.0, 1.2]}
LIDAR = {"type": "lidar", "name": "lidar", "preset": "custom", "channels": 8, "columns": 90,
         "vertical_fov_deg": [-15.0, 15.0], "range_max_m": 60.0, "rate_hz": 10, "mount": MOUNT}  # fmt: skip
CAMERA = {"type": "camera", "name": "camera", "width": 64, "height": 48, "rate_hz": 10, "mount": MOUNT}
SCENARIO = {
    "version": 1,
    "world": {"physics_rate_hz": 100},
    "environment": {"sea": {"type": "sea_state", "code": 3}, "ramp_time_s": 0.0},
    "vessels": [{"name": "wamv", "model": "wamv", "sensors": [LIDAR, CAMERA]}],
    "objects": [
        {"type": "buoy", "name": "buoy_1", "position": [8.0, 3.0, 0.0], "color": "red"},
        {"type": "dock", "name": "dock", "position": [12.0, 0.0, -1.0], "size": [2.0, 8.0, 3.0]},
    ],
}
POINTS, IMAGE = "/wamv/lidar/points", "/wamv/camera/image_raw"


def make_sim(sensors: bool = True) -> Simulation:
    data = dict(SCENARIO)
    if not sensors:
        data["vessels"] = [{"name": "wamv", "model": "wamv"}]
    return Simulation(parse_scenario(data, "test"), seed=0)


def make_bridge(sim, **kwargs):
    from usvsim.bridges.foxglove import FoxgloveBridge

    kwargs.setdefault("scene_rate_hz", 20.0)  # the tests run short simulations, faster than real time
    return FoxgloveBridge(sim, host="127.0.0.1", port=0, **kwargs)
