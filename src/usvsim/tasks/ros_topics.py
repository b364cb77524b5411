"""VRX's task topics as ROS 2 messages (`Envelope`s), with VRX's names and types (vrx_gz/src/vrx_gz/bridges.py):

- `/vrx/task/info`: ros_gz_interfaces/ParamVec, parameters name, state (strings), ready_time, running_time,
  elapsed_time, remaining_time, score (doubles), timed_out (bool), num_collisions (integer);
- `/vrx/stationkeeping/goal` (geometry_msgs/PoseStamped: latitude, longitude in position.x/.y, yaw as a
  quaternion), `/vrx/stationkeeping/pose_error`, `/vrx/stationkeeping/mean_pose_error` (std_msgs/Float32);
- `/vrx/wayfinding/waypoints` (geometry_msgs/PoseArray, lat/lon/yaw like the goal),
  `/vrx/wayfinding/min_errors` (ros_gz_interfaces/Float32Array), `/vrx/wayfinding/mean_error` (Float32);
- `/vrx/wildlife/animal<i>/pose` (PoseStamped, class in header.frame_id), `/vrx/gymkhana_blackbox/goal`,
  `.../pose_error`, `.../mean_pose_error`.
Positions go out geodetic (WGS-84 degrees) from the scenario's origin, as VRX publishes them. QoS: reliable,
volatile, keep last 10, what VRX's `ros_gz_bridge` parameter bridges offer (the envelope default).
"""

from __future__ import annotations

import math

import numpy as np
import pymap3d

from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import header, msg_class

PARAMETER_TYPE = {bool: 1, int: 2, float: 3, str: 4}  # rcl_interfaces/ParameterType


def _parameter(name: str, value):
    kind = PARAMETER_TYPE[type(value)]
    fields = {"type": kind, "bool_value": False, "integer_value": 0, "double_value": 0.0, "string_value": "",
              "byte_array_value": np.zeros(0, np.uint8), "bool_array_value": np.zeros(0, bool),
              "integer_array_value": np.zeros(0, np.int64), "double_array_value": np.zeros(0), "string_array_value": []}  # fmt: skip
    fields[{1: "bool_value", 2: "integer_value", 3: "double_value", 4: "string_value"}[kind]] = value
    value_msg = msg_class("rcl_interfaces/msg/ParameterValue")(**fields)
    return msg_class("rcl_interfaces/msg/Parameter")(name=name, value=value_msg)


def _geo_pose(task, x: float, y: float, yaw: float):
    o = task.sim.scenario.world.origin
    lat, lon, _ = pymap3d.enu2geodetic(x, y, 0.0, o.latitude_deg, o.longitude_deg, o.altitude_m)
    point = msg_class("geometry_msgs/msg/Point")(x=float(lat), y=float(lon), z=0.0)
    quat = msg_class("geometry_msgs/msg/Quaternion")(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    return msg_class("geometry_msgs/msg/Pose")(position=point, orientation=quat)


def task_envelopes(task, stamp_ns: int) -> list[Envelope]:
    """The task's VRX topics at `stamp_ns` (VRX publishes them at 1 Hz)."""
    info = task.info()
    params = [_parameter(k, float(v) if isinstance(v, float) else v) for k, v in info.items()]
    out = [Envelope("/vrx/task/info", stamp_ns, msg_class("ros_gz_interfaces/msg/ParamVec")(
        header=header(stamp_ns, ""), params=params))]  # fmt: skip
    float32 = msg_class("std_msgs/msg/Float32")
    if task.name == "station_keeping":
        pose = msg_class("geometry_msgs/msg/PoseStamped")(header=header(stamp_ns, ""), pose=_geo_pose(task, *task.goal))
        err = task.scorer.last_error if math.isfinite(task.scorer.last_error) else 0.0
        out += [Envelope("/vrx/stationkeeping/goal", stamp_ns, pose),
                Envelope("/vrx/stationkeeping/pose_error", stamp_ns, float32(data=float(err))),
                Envelope("/vrx/stationkeeping/mean_pose_error", stamp_ns, float32(data=float(info["score"])))]  # fmt: skip
    elif task.name == "wayfinding":
        poses = [_geo_pose(task, *w) for w in task.waypoints]
        minima = [float(m) if math.isfinite(m) else 0.0 for m in task.scorer.min_errors]
        out += [Envelope("/vrx/wayfinding/waypoints", stamp_ns,
                         msg_class("geometry_msgs/msg/PoseArray")(header=header(stamp_ns, ""), poses=poses)),
                Envelope("/vrx/wayfinding/min_errors", stamp_ns, msg_class("ros_gz_interfaces/msg/Float32Array")(
                    data=np.array(minima, dtype=np.float32))),
                Envelope("/vrx/wayfinding/mean_error", stamp_ns, float32(data=sum(minima) / len(minima)))]  # fmt: skip
    elif task.name == "wildlife":
        out += animal_envelopes(task, stamp_ns)
    elif task.name == "gymkhana":
        out += blackbox_envelopes(task, stamp_ns)
    return out


ANIMAL_CLASS = {"avoid": "crocodile", "circumnavigate_clockwise": "platypus", "circumnavigate_counterclockwise": "turtle"}


def animal_envelopes(task, stamp_ns: int) -> list[Envelope]:
    """VRX wildlife: `/vrx/wildlife/animal<i>/pose` (geometry_msgs/PoseStamped, lat/lon in position.x/.y, the
    animal's world orientation, its class by goal in header.frame_id), at 1 Hz like VRX's scoring plugin."""
    out, s = [], task.sim.state
    for i, a in enumerate(task.scorer.animals):
        k = task.object_index[a.name]
        x, y = float(s.pos[k, 0]), float(s.pos[k, 1])
        pose = _geo_pose(task, x, y, 0.0)
        w, qx, qy, qz = task.sim.body_quat(k).tolist()
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = qx, qy, qz, w
        msg = msg_class("geometry_msgs/msg/PoseStamped")(header=header(stamp_ns, ANIMAL_CLASS[a.goal]), pose=pose)
        out.append(Envelope(f"/vrx/wildlife/animal{i}/pose", stamp_ns, msg))
    return out


def blackbox_envelopes(task, stamp_ns: int) -> list[Envelope]:
    """VRX gymkhana: `/vrx/gymkhana_blackbox/goal` (PoseStamped), `pose_error` and `mean_pose_error` (Float32)."""
    float32, box = msg_class("std_msgs/msg/Float32"), task.blackbox
    goal = msg_class("geometry_msgs/msg/PoseStamped")(header=header(stamp_ns, ""), pose=_geo_pose(task, *task.pinger))
    last = box.last_error if math.isfinite(box.last_error) else 0.0
    mean = box.score if box.samples and math.isfinite(box.score) else 0.0
    return [Envelope("/vrx/gymkhana_blackbox/goal", stamp_ns, goal),
            Envelope("/vrx/gymkhana_blackbox/pose_error", stamp_ns, float32(data=float(last))),
            Envelope("/vrx/gymkhana_blackbox/mean_pose_error", stamp_ns, float32(data=float(mean)))]  # fmt: skip
