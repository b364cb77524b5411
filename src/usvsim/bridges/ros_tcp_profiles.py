"""Topic-name profiles of the ROS-TCP bridge: which name each topic has on the wire, which commands come in.

`usvsim`: every topic under the name the simulation emits (``/wamv/lidar/points``...) and the command topics
of `sim.commands.topics` (std_msgs/Float64 thrust/angle, Twist ``cmd_vel``, Empty ``/reset``).

`seed`: the topic names of the Unity seed (``edvart-ros/unity_asv_sim``, relative names as it registers them)
for ONE vessel (the first one unless `vessel=` is given); messages are the same bytes, only renamed:

| seed name | usvsim topic (vessel ``<v>``) | type |
|---|---|---|
| ``scan`` | first LiDAR with ``output: scan``: ``/<v>/<name>/scan`` | sensor_msgs/LaserScan |
| ``points`` | first LiDAR with ``output: points``: ``/<v>/<name>/points`` | sensor_msgs/PointCloud2 |
| ``camera/image_raw`` | first camera: ``/<v>/<cam>/image_raw`` | sensor_msgs/Image rgb8 |
| ``camera/depth`` | first camera: ``/<v>/<cam>/depth/image_raw`` | sensor_msgs/Image 32FC1 |
| ``camera/camera_info`` | first camera: ``/<v>/<cam>/camera_info`` (``depth/camera_info`` without RGB) | sensor_msgs/CameraInfo |
| ``imu/raw`` | first IMU: ``/<v>/<imu>/data`` | sensor_msgs/Imu |
| ``odometry`` | first odometry sensor ``/<v>/<name>``, else ``/<v>/ground_truth/odometry`` | nav_msgs/Odometry |
| ``clock`` | ``/clock`` | rosgraph_msgs/Clock |
| ``<t>_thruster/thrust`` (in) | ``/<v>/thrusters/<t>/thrust`` | std_msgs/Float32, normalized [-1, 1] (clamped, as the seed does) |
| ``<t>_thruster/angle`` (in) | ``/<v>/thrusters/<t>/angle`` | std_msgs/Float32, **degrees, positive = clockwise** seen from above (seed); converted to rad, REP 103 |

``<t>`` is the usvsim thruster name; the seed's WAM-V names are ``rear_left_thruster``... so ``_thruster`` is
appended unless the name already ends with it. Every unmapped topic (``/tf``, ``/tf_static``, other vessels,
GNSS, depth camera_info, segmentation, a second LiDAR...) is still published under its usvsim name, and the
usvsim command topics other than the mapped vessel's thrusters (``cmd_vel``, ``/reset``, other vessels) are
still subscribed under their usvsim names.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from usvsim.messages.ros import msg_class, typestore

if TYPE_CHECKING:
    from usvsim.simulation import Simulation

FLOAT32, FLOAT64 = "std_msgs/msg/Float32", "std_msgs/msg/Float64"
PROFILES = ("usvsim", "seed")


@dataclass
class Profile:
    """`rename` maps usvsim topic → wire name (missing: unchanged); `commands` maps a wire topic to its ROS
    type and a handler(cdr bytes) → bool that queues the command on the simulation."""

    name: str
    rename: dict[str, str] = field(default_factory=dict)
    commands: dict[str, tuple[str, Callable[[bytes], bool]]] = field(default_factory=dict)

    def wire_name(self, topic: str) -> str:
        return self.rename.get(topic, topic)


def make_profile(sim: Simulation, name: str = "usvsim", vessel: str | None = None) -> Profile:
    """The named profile for `sim` (``seed`` maps `vessel`, default the first vessel)."""
    if name not in PROFILES:
        raise ValueError(f"unknown ROS-TCP profile {name!r}; choose one of {', '.join(PROFILES)}")
    if name == "usvsim":
        return Profile(name, commands=_native_commands(sim, skip=()))
    vessel = vessel or next(iter(sim.vessels), None)
    if vessel is None or vessel not in sim.vessels:
        raise ValueError(
            f"no vessel named {vessel!r} for the seed profile (vessels: {', '.join(sim.vessels)})"
        )
    thrust_cmds = _seed_thruster_commands(sim, vessel)
    mapped = {
        f"/{vessel}/thrusters/{t}/{k}" for t in sim.vessels[vessel].thrusters for k in ("thrust", "angle")
    }
    commands = _native_commands(sim, skip=mapped) | thrust_cmds
    return Profile(name, rename=seed_topic_names(sim, vessel), commands=commands)


def _native_commands(sim: Simulation, skip) -> dict[str, tuple[str, Callable[[bytes], bool]]]:
    def handler(topic: str) -> Callable[[bytes], bool]:
        return lambda data: sim.commands.post_cdr(topic, data)

    return {t: (msgtype, handler(t)) for t, msgtype in sim.commands.topics.items() if t not in skip}


def seed_thruster_name(thruster: str) -> str:
    return thruster if thruster.endswith("_thruster") else f"{thruster}_thruster"


def _seed_thruster_commands(sim: Simulation, vessel: str) -> dict[str, tuple[str, Callable[[bytes], bool]]]:
    out = {}
    for t in sim.vessels[vessel].thrusters:
        ours, seed = f"/{vessel}/thrusters/{t}", seed_thruster_name(t)
        out[f"{seed}/thrust"] = (FLOAT32, _float32_handler(sim, f"{ours}/thrust", _seed_thrust))
        out[f"{seed}/angle"] = (FLOAT32, _float32_handler(sim, f"{ours}/angle", _seed_angle))
    return out


def _seed_thrust(x: float) -> float:
    return min(1.0, max(-1.0, x)) if math.isfinite(x) else x  # NaN/inf stay, so the inbox rejects them


def _seed_angle(degrees_clockwise: float) -> float:
    return -math.radians(degrees_clockwise)


def _float32_handler(sim: Simulation, topic: str, convert: Callable[[float], float]) -> Callable:
    float64 = msg_class(FLOAT64)

    def handle(data: bytes) -> bool:
        try:
            value = float(typestore().deserialize_cdr(bytes(data), FLOAT32).data)
        except Exception:  # untrusted bytes: counted by the inbox as malformed
            return sim.commands.post_cdr(topic, b"")  # empty CDR: the inbox counts it as malformed
        return sim.commands.post(topic, float64(data=convert(value)))

    return handle


def seed_topic_names(sim: Simulation, vessel: str) -> dict[str, str]:
    """usvsim topic → seed name for `vessel`'s sensors, its odometry and /clock (see the module table)."""
    names, taken = {"/clock": "clock"}, set()
    for sensor in sim.sensors.sensors.values():
        if sensor.vessel != vessel:
            continue
        for topic, seed in _sensor_names(sensor):
            if seed not in taken:  # the first sensor of each kind
                taken.add(seed)
                names[topic] = seed
    if "odometry" not in taken:
        names[f"/{vessel}/ground_truth/odometry"] = "odometry"
    return names


def _sensor_names(sensor: Any) -> list[tuple[str, str]]:
    kind, topic = sensor.cfg.type, sensor.topic
    if kind == "lidar":
        return [(topic, "scan" if sensor.pattern.output == "scan" else "points")]
    if kind == "imu":
        return [(topic, "imu/raw")]
    if kind == "odometry":
        return [(topic, "odometry")]
    if kind != "camera":
        return []
    out = []
    if "rgb" in sensor.streams:
        out += [(f"{topic}/image_raw", "camera/image_raw"), (f"{topic}/camera_info", "camera/camera_info")]
    if "depth" in sensor.streams:
        out.append((f"{topic}/depth/image_raw", "camera/depth"))
        if "rgb" not in sensor.streams:
            out.append((f"{topic}/depth/camera_info", "camera/camera_info"))
    return out
