"""Builders for ROS 2 messages (rosbags dataclasses of the Jazzy typestore) from numpy state.

Conventions (see docs in `design.md`):
- stamps are simulation time in integer nanoseconds, converted to `builtin_interfaces/Time`;
- quaternions inside usvsim are (w, x, y, z) (MuJoCo order); ROS messages get x, y, z, w fields;
- `nav_msgs/Odometry` twist is expressed in the child frame (REP 105), the pose in the parent frame.

All builders are pure functions; the only shared object is the typestore, built once per process on
first use and never mutated afterwards. The Jazzy store lacks vision_msgs, so its twelve message types
(vision_msgs 4.1, ROS 2 Jazzy) are registered when the store is built: CDR, MCAP schemas and DDS types
then work for them like for any other type, in every part of the process.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

import numpy as np
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from usvsim.messages.marine import MARINE_MSGS

NS_PER_S = 1_000_000_000
_INT32_MAX = 2**31 - 1
_ZERO_COV = np.zeros(36, dtype=np.float64)
_IMAGE_ENCODINGS = {  # encoding -> (numpy dtype, channels) for the encodings the sensors produce
    "rgb8": (np.uint8, 3),
    "bgr8": (np.uint8, 3),
    "rgba8": (np.uint8, 4),
    "mono8": (np.uint8, 1),
    "mono16": (np.uint16, 1),
    "16UC1": (np.uint16, 1),
    "32FC1": (np.float32, 1),
}


# vision_msgs 4.1 (ros-perception/vision_msgs, branch ros2): the message definitions, comments left out
VISION_MSGS = {
    "Point2D": "float64 x\nfloat64 y\n",
    "Pose2D": "vision_msgs/Point2D position\nfloat64 theta\n",
    "BoundingBox2D": "vision_msgs/Pose2D center\nfloat64 size_x\nfloat64 size_y\n",
    "BoundingBox3D": "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size\n",
    "ObjectHypothesis": "string class_id\nfloat64 score\n",
    "ObjectHypothesisWithPose": "vision_msgs/ObjectHypothesis hypothesis\ngeometry_msgs/PoseWithCovariance pose\n",
    "Detection2D": "std_msgs/Header header\nvision_msgs/ObjectHypothesisWithPose[] results\n"
                   "vision_msgs/BoundingBox2D bbox\nstring id\n",
    "Detection2DArray": "std_msgs/Header header\nvision_msgs/Detection2D[] detections\n",
    "Detection3D": "std_msgs/Header header\nvision_msgs/ObjectHypothesisWithPose[] results\n"
                   "vision_msgs/BoundingBox3D bbox\nstring id\n",
    "Detection3DArray": "std_msgs/Header header\nvision_msgs/Detection3D[] detections\n",
    "VisionClass": "uint16 class_id\nstring class_name\n",
    "LabelInfo": "std_msgs/Header header\nvision_msgs/VisionClass[] class_map\nfloat32 threshold\n",
}  # fmt: skip

# ros_gz_interfaces (gazebosim/ros_gz, Jazzy): the two types VRX's task topics use
ROS_GZ_MSGS = {
    "ParamVec": "std_msgs/Header header\nrcl_interfaces/Parameter[] params\n",
    "Float32Array": "float32[] data\n",
}

# geographic_msgs (ros-geographic-info/geographic_info, ros2): a VRX perception report may be a GeoPoseStamped
GEOGRAPHIC_MSGS = {
    "GeoPoint": "float64 latitude\nfloat64 longitude\nfloat64 altitude\n",
    "GeoPose": "geographic_msgs/GeoPoint position\ngeometry_msgs/Quaternion orientation\n",
    "GeoPoseStamped": "std_msgs/Header header\ngeographic_msgs/GeoPose pose\n",
}


@functools.cache
def typestore() -> Any:
    """The ROS 2 Jazzy typestore (message classes, CDR (de)serializer, message definitions) + vision_msgs
    + the ros_gz_interfaces types of VRX's task topics + geographic_msgs' GeoPoseStamped."""
    store = get_typestore(Stores.ROS2_JAZZY)
    types: dict = {}
    for package, msgs in (("vision_msgs", VISION_MSGS), ("ros_gz_interfaces", ROS_GZ_MSGS),
                          ("geographic_msgs", GEOGRAPHIC_MSGS)):
        for name, text in msgs.items():
            types |= get_types_from_msg(text, f"{package}/msg/{name}")
    for name, text in MARINE_MSGS.items():  # radar, NMEA sentences, traffic awareness (messages/marine.py)
        types |= get_types_from_msg(text, name)
    store.register(types)
    return store


@functools.cache
def message_definition(msgtype: str) -> str:
    """Full ROS 2 `.msg` text of `msgtype` with its dependencies (MCAP schema encoding `ros2msg`)."""
    return typestore().generate_msgdef(msgtype, ros_version=2)[0]


def msg_class(msgtype: str) -> Any:
    """The dataclass for `msgtype`, e.g. ``msg_class("nav_msgs/msg/Odometry")``."""
    return typestore().types[msgtype]


def time_msg(stamp_ns: int) -> Any:
    """`builtin_interfaces/Time` for `stamp_ns` (floor split: sec = ns // 1e9, 0 <= nanosec < 1e9)."""
    sec, nanosec = divmod(int(stamp_ns), NS_PER_S)
    if not -_INT32_MAX - 1 <= sec <= _INT32_MAX:
        raise ValueError(f"stamp {stamp_ns} ns does not fit builtin_interfaces/Time (int32 seconds)")
    return msg_class("builtin_interfaces/msg/Time")(sec=sec, nanosec=nanosec)


def time_to_ns(stamp: Any) -> int:
    """Inverse of `time_msg`: integer nanoseconds of a `builtin_interfaces/Time`."""
    return int(stamp.sec) * NS_PER_S + int(stamp.nanosec)


def header(stamp_ns: int, frame_id: str) -> Any:
    """`std_msgs/Header` (ROS 2: stamp + frame_id, no seq)."""
    return msg_class("std_msgs/msg/Header")(stamp=time_msg(stamp_ns), frame_id=frame_id)


def clock_msg(stamp_ns: int) -> Any:
    """`rosgraph_msgs/Clock` for `/clock`."""
    return msg_class("rosgraph_msgs/msg/Clock")(clock=time_msg(stamp_ns))


def vector3(v: Sequence[float] | np.ndarray) -> Any:
    return msg_class("geometry_msgs/msg/Vector3")(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def point(v: Sequence[float] | np.ndarray) -> Any:
    return msg_class("geometry_msgs/msg/Point")(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def quaternion(quat_wxyz: Sequence[float] | np.ndarray) -> Any:
    """`geometry_msgs/Quaternion` from a usvsim (w, x, y, z) quaternion."""
    w, x, y, z = (float(c) for c in quat_wxyz)
    return msg_class("geometry_msgs/msg/Quaternion")(x=x, y=y, z=z, w=w)


def _covariance(cov: np.ndarray | None) -> np.ndarray:
    if cov is None:
        return _ZERO_COV.copy()
    flat = np.ascontiguousarray(cov, dtype=np.float64).reshape(-1)
    if flat.size != 36:
        raise ValueError(f"covariance must have 36 elements (6x6 row-major), got {flat.size}")
    return flat


def odometry_msg(
    stamp_ns: int,
    frame_id: str,
    child_frame_id: str,
    pos: np.ndarray,
    quat_wxyz: np.ndarray,
    lin_vel_child: np.ndarray,
    ang_vel_child: np.ndarray,
    pose_cov: np.ndarray | None = None,
    twist_cov: np.ndarray | None = None,
) -> Any:
    """`nav_msgs/Odometry`: pose of `child_frame_id` in `frame_id`, twist in `child_frame_id` (REP 105).

    Covariances are 6x6 row-major over (x, y, z, rotX, rotY, rotZ). The default is all zeros, which
    is the right value for exact ground truth; noisy odometry sources must pass their covariance.
    """
    types = typestore().types
    pose = types["geometry_msgs/msg/Pose"](position=point(pos), orientation=quaternion(quat_wxyz))
    twist = types["geometry_msgs/msg/Twist"](linear=vector3(lin_vel_child), angular=vector3(ang_vel_child))
    return types["nav_msgs/msg/Odometry"](
        header=header(stamp_ns, frame_id),
        child_frame_id=child_frame_id,
        pose=types["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=_covariance(pose_cov)),
        twist=types["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=_covariance(twist_cov)),
    )


def transform_stamped(stamp_ns: int, parent: str, child: str, pos: np.ndarray, quat_wxyz: np.ndarray) -> Any:
    """`geometry_msgs/TransformStamped`: pose of frame `child` expressed in frame `parent`."""
    types = typestore().types
    transform = types["geometry_msgs/msg/Transform"](translation=vector3(pos), rotation=quaternion(quat_wxyz))
    return types["geometry_msgs/msg/TransformStamped"](
        header=header(stamp_ns, parent), child_frame_id=child, transform=transform
    )


def tf_message(transforms: Sequence[Any]) -> Any:
    """`tf2_msgs/TFMessage` for `/tf` or `/tf_static` (put ALL static transforms in one message)."""
    return msg_class("tf2_msgs/msg/TFMessage")(transforms=list(transforms))


def image_msg(stamp_ns: int, frame_id: str, array: np.ndarray, encoding: str = "rgb8") -> Any:
    """`sensor_msgs/Image` from an (H, W[, C]) array, without per-pixel Python work.

    The pixel buffer is viewed as bytes (little endian, `is_bigendian=0`); a copy is made only when
    the array is not C-contiguous.
    """
    if encoding not in _IMAGE_ENCODINGS:
        raise ValueError(f"unsupported image encoding {encoding!r}; use one of {sorted(_IMAGE_ENCODINGS)}")
    dtype, channels = _IMAGE_ENCODINGS[encoding]
    arr = np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<"))
    shape_ok = (arr.ndim == 3 and arr.shape[2] == channels) or (arr.ndim == 2 and channels == 1)
    if not shape_ok:
        raise ValueError(f"{encoding} needs shape (H, W, {channels}), got {array.shape}")
    height, width = arr.shape[:2]
    return msg_class("sensor_msgs/msg/Image")(
        header=header(stamp_ns, frame_id),
        height=height,
        width=width,
        encoding=encoding,
        is_bigendian=0,
        step=width * channels * arr.itemsize,
        data=arr.reshape(-1).view(np.uint8),
    )
