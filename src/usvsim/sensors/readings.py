"""Sensor samples as numpy arrays, read from the ROS messages a sensor emitted (no per-element Python).

One `Reading` per sample: `reading["points"]`, `reading["rgb"]`, ...; `reading.messages` keeps the ROS
messages (topic → message). Every array is read-only (copy to modify): a view of the message buffer where the
message has one (point clouds, scans, images), else a small new array; every sample has buffers of its own, so a
reading stays valid after later steps, and the Reading (cached per sample) cannot be changed through its arrays. Fields (frames and units as in the messages):

| message | fields |
|---|---|
| PointCloud2 | `points`: structured (N,) or (rings, columns) `x, y, z, intensity` float32 (m, sensor FLU), `ring` uint16, `time` float32 (s after the stamp) |
| LaserScan | `ranges`, `intensities` float32 (m), `angles` float32 (rad) |
| RadarSector | `echoes` (spokes, range bins) float32 (0..1 over the dynamic range), `angles` float32 (rad, sensor frame) |
| Image | `rgb` (H, W, 3) uint8, `depth` (H, W) float32 m, `segmentation` (H, W) uint16 (model geom id + 1, 0 = none; the camera's `segmentation_ids` maps id → (object name, class; the water's two labels: class `water`)); other encodings (a radar's mono8 PPI) as `image` |
| CameraInfo | `K` (3, 3) float64 |
| Imu | `orientation` (w, x, y, z), `angular_velocity` rad/s, `linear_acceleration` m/s² (sensor frame) |
| Odometry | `position` m, `orientation` (w, x, y, z), `linear_velocity` m/s, `angular_velocity` rad/s |
| NavSatFix | `lla` (latitude deg, longitude deg, altitude m), `position_covariance` (3, 3) m² ENU |
| TwistWithCovarianceStamped | `velocity` m/s (ENU), `angular_velocity` rad/s |
| Detection2DArray / 3DArray | `detections` (or `detections_2d` from a camera): structured `id`, `class_id` (U32), `center` (3,) or (2,), `orientation` (w, x, y, z) (3D), `size` (3,) or (2,) |
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import _IMAGE_ENCODINGS as _ENCODINGS  # encoding → (dtype, channels)

POINTS_DTYPE = np.dtype({"names": ["x", "y", "z", "intensity", "ring", "time"],
                         "formats": ["<f4", "<f4", "<f4", "<f4", "<u2", "<f4"],
                         "offsets": [0, 4, 8, 12, 16, 20], "itemsize": 24})  # fmt: skip  the cloud's layout
_IMAGES = {"rgb8": ("rgb", np.uint8, 3), "32FC1": ("depth", np.float32, 1), "16UC1": ("segmentation", np.uint16, 1)}
DETECTION_2D = np.dtype([("id", "U32"), ("class_id", "U32"), ("center", "<f8", (2,)), ("size", "<f8", (2,))])
DETECTION_3D = np.dtype([("id", "U32"), ("class_id", "U32"), ("center", "<f8", (3,)), ("orientation", "<f8", (4,)),
                         ("size", "<f8", (3,))])  # fmt: skip


@dataclass(frozen=True)
class Reading(Mapping[str, np.ndarray]):
    """One sample of one sensor: `stamp_ns` (its sample time), `frame_id`, named arrays, the ROS messages."""

    stamp_ns: int
    frame_id: str
    arrays: dict[str, np.ndarray]
    messages: dict[str, Any] = field(repr=False)

    def __getitem__(self, key: str) -> np.ndarray:
        return self.arrays[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.arrays)

    def __len__(self) -> int:
        return len(self.arrays)


def reading(envelopes: list[Envelope]) -> Reading | None:
    """The Reading of one sample's messages (None for an empty sample)."""
    if not envelopes:
        return None
    arrays: dict[str, np.ndarray] = {}
    for env in envelopes:
        convert = _CONVERTERS.get(env.msgtype)
        if convert is not None:
            arrays.update({key: _read_only(a) for key, a in convert(env.msg).items()})
    first = envelopes[0]
    return Reading(first.stamp_ns, _frame_of(first.msg), arrays, {e.topic: e.msg for e in envelopes})


def _frame_of(msg: Any) -> str:
    head = getattr(msg, "header", None)
    return head.frame_id if head is not None else ""


def _read_only(a: np.ndarray) -> np.ndarray:
    """A read-only view of `a` (no copy; the message's own array, if `a` is one, stays as it was)."""
    view = a.view()
    view.flags.writeable = False
    return view


def _cloud(msg) -> dict[str, np.ndarray]:
    points = np.frombuffer(msg.data, POINTS_DTYPE).reshape(-1)
    if msg.height > 1:
        points = points.reshape(msg.height, msg.width)
    return {"points": points}


def _scan(msg) -> dict[str, np.ndarray]:
    ranges = np.asarray(msg.ranges, dtype=np.float32)
    angles = (msg.angle_min + msg.angle_increment * np.arange(len(ranges))).astype(np.float32)
    return {"ranges": ranges, "intensities": np.asarray(msg.intensities, np.float32),
            "angles": angles}  # fmt: skip


def _image(msg) -> dict[str, np.ndarray]:
    """Camera streams by name; any other image (a radar's PPI, mono8) as `image`."""
    name, dtype, channels = _IMAGES.get(msg.encoding) or ("image", *_ENCODINGS.get(msg.encoding, (None, 0)))
    if dtype is None:
        return {}
    shape = (msg.height, msg.width, channels) if channels > 1 else (msg.height, msg.width)
    return {name: np.frombuffer(msg.data, dtype).reshape(shape)}


def _radar_sector(msg) -> dict[str, np.ndarray]:
    """One radar sample's spokes: `echoes` (spokes, bins) float32 (a new array: one row per spoke, tens per
    sample, not per bin) and each spoke's `angles` float32 (rad, CCW from the bow)."""
    rows = [np.asarray(e.echoes, np.float32) for e in msg.intensities]
    echoes = np.stack(rows) if rows else np.zeros((0, 0), np.float32)
    angles = (msg.angle_start + msg.angle_increment * np.arange(len(rows))).astype(np.float32)
    return {"echoes": echoes, "angles": angles}


def _camera_info(msg) -> dict[str, np.ndarray]:
    return {"K": np.asarray(msg.k, dtype=float).reshape(3, 3)}


def _vec(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


def _quat(q) -> np.ndarray:
    return np.array([q.w, q.x, q.y, q.z])


def _imu(msg) -> dict[str, np.ndarray]:
    return {"orientation": _quat(msg.orientation), "angular_velocity": _vec(msg.angular_velocity),
            "linear_acceleration": _vec(msg.linear_acceleration)}  # fmt: skip


def _odometry(msg) -> dict[str, np.ndarray]:
    pose, twist = msg.pose.pose, msg.twist.twist
    return {"position": _vec(pose.position), "orientation": _quat(pose.orientation),
            "linear_velocity": _vec(twist.linear), "angular_velocity": _vec(twist.angular)}  # fmt: skip


def _navsat(msg) -> dict[str, np.ndarray]:
    return {"lla": np.array([msg.latitude, msg.longitude, msg.altitude]),
            "position_covariance": np.asarray(msg.position_covariance, dtype=float).reshape(3, 3)}  # fmt: skip


def _twist(msg) -> dict[str, np.ndarray]:
    t = msg.twist.twist
    return {"velocity": _vec(t.linear), "angular_velocity": _vec(t.angular)}


def _detections(dims: int) -> Callable[[Any], dict[str, np.ndarray]]:
    def convert(msg) -> dict[str, np.ndarray]:
        out = np.zeros(len(msg.detections), DETECTION_3D if dims == 3 else DETECTION_2D)
        for k, d in enumerate(msg.detections):  # one row per object (tens), not per pixel or point
            label = d.results[0].hypothesis.class_id if d.results else ""
            b = d.bbox
            if dims == 3:
                out[k] = (d.id, label, _vec(b.center.position), _quat(b.center.orientation), _vec(b.size))
            else:
                c = b.center.position
                out[k] = (d.id, label, (c.x, c.y), (b.size_x, b.size_y))
        return {"detections" if dims == 3 else "detections_2d": out}

    return convert


_CONVERTERS: dict[str, Callable[[Any], dict[str, np.ndarray]]] = {
    "sensor_msgs/msg/PointCloud2": _cloud,
    "sensor_msgs/msg/LaserScan": _scan,
    "marine_sensor_msgs/msg/RadarSector": _radar_sector,
    "sensor_msgs/msg/Image": _image,
    "sensor_msgs/msg/CameraInfo": _camera_info,
    "sensor_msgs/msg/Imu": _imu,
    "nav_msgs/msg/Odometry": _odometry,
    "sensor_msgs/msg/NavSatFix": _navsat,
    "geometry_msgs/msg/TwistWithCovarianceStamped": _twist,
    "vision_msgs/msg/Detection2DArray": _detections(2),
    "vision_msgs/msg/Detection3DArray": _detections(3),
}
