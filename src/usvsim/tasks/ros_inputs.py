"""What a VRX team's ROS 2 stack sends to a task, registered on the simulation's command inbox
(`sim.commands.register`), so every bridge (DDS, ROS-TCP, Foxglove) accepts it:

- `/vrx/perception/landmark`: one perception report, the object's class in `header.frame_id`, its position
  geodetic. VRX on Gazebo Sim bridges it as geometry_msgs/PoseStamped with latitude and longitude in
  `pose.position.x` / `.y` (vrx_gz/src/vrx_gz/bridges.py, `perception_reports`; the default here);
  VRX Classic (ROS 1) used geographic_msgs/GeoPoseStamped (`pose.position.latitude` / `.longitude`):
  `landmark_type="geopose"`. Reports go to the perception scorer; other tasks ignore them.
- `/wamv/thrusters/{left,right}/thrust` (std_msgs/Float64, N; VRX's H layout) drive the WAM-V's aft
  thrusters through the inverse of their thrust map (clamped to its range), and
  `/wamv/thrusters/{left,right}/pos` (Float64, rad) their azimuth. usvsim's own
  `/wamv/thrusters/<name>/thrust` (normalized) topics keep working beside them.
Bad reports (empty class, latitude/longitude out of range or not finite) are rejected and counted
(`sim.commands.stats`), never raised.
"""

from __future__ import annotations

import math

import numpy as np
import pymap3d

from usvsim.hydro.thrusters import MAP_CODES, thrust_map

LANDMARK_TOPIC = "/vrx/perception/landmark"
LANDMARK_TYPES = {"pose": "geometry_msgs/msg/PoseStamped", "geopose": "geographic_msgs/msg/GeoPoseStamped"}
VRX_THRUSTERS = {"left": "rear_left", "right": "rear_right"}  # VRX H layout → the WAM-V's aft thrusters
FLOAT64 = "std_msgs/msg/Float64"


def register_task_inputs(sim, task, landmark_type: str = "pose", vessel: str = "wamv") -> None:
    """Register the landmark topic (perception task only) and VRX's thruster topics on `sim.commands`."""
    if landmark_type not in LANDMARK_TYPES:
        raise ValueError(f"landmark_type must be one of {sorted(LANDMARK_TYPES)}, not {landmark_type!r}")
    if task.name == "perception":
        origin = sim.scenario.world.origin
        geo = landmark_type == "geopose"

        def parse(msg):
            p = msg.pose.position
            lat, lon = (p.latitude, p.longitude) if geo else (p.x, p.y)
            kind = msg.header.frame_id
            if not kind or not (math.isfinite(lat) and math.isfinite(lon) and abs(lat) <= 90 and abs(lon) <= 180):
                return None
            alt = origin.altitude_m  # the report's point at the origin's height, as every 2D position (geo/frame.py)
            e, n, _ = pymap3d.geodetic2enu(lat, lon, alt, origin.latitude_deg, origin.longitude_deg, alt)
            return kind, float(e), float(n)

        sim.commands.register(LANDMARK_TOPIC, LANDMARK_TYPES[landmark_type], parse, lambda r: task.scorer.report(*r))
    boat = sim.vessels[vessel]
    for side, name in VRX_THRUSTERS.items():
        thruster = boat.thrusters.get(name)
        if thruster is None:
            continue
        config = next(t for t in boat.model.thrusters if t.name == name)
        newtons_to_u = inverse_thrust_map(config.thrust)
        sim.commands.register(f"/{vessel}/thrusters/{side}/thrust", FLOAT64, lambda m, f=newtons_to_u: f(_finite(m.data)),
                              lambda u, t=thruster: t.command(u, hold=False))  # fmt: skip
        sim.commands.register(f"/{vessel}/thrusters/{side}/pos", FLOAT64, lambda m: _finite(m.data),
                              lambda a, t=thruster: t.command_angle(a))  # fmt: skip


def inverse_thrust_map(thrust):
    """Thrust (N) → normalized command u in [-1, 1] for a `config.vessel.ThrustMap` (monotonic), clamped."""
    u = np.linspace(-1.0, 1.0, 4001)
    newtons = np.array([thrust_map(x, MAP_CODES[thrust.type], thrust.max_forward_n, thrust.max_reverse_n) for x in u])
    return lambda n: None if n is None else float(np.interp(n, newtons, u))


def _finite(x) -> float | None:
    if isinstance(x, bool) or not isinstance(x, int | float | np.floating | np.integer):
        raise TypeError(f"expected a number, got {type(x).__name__}")
    return float(x) if math.isfinite(x) else None
