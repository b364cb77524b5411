"""Adapter from the simulation's public message stream to arrays the stack uses (one place to change
when `sim.sensors[...].latest` arrays land): PointCloud2 → xyz (n, 3) and per-point time (n,) by field
name, like any ROS consumer; the LiDAR mount from `/tf_static`."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from usvsim.core.transforms import matrix_from_quat

if TYPE_CHECKING:
    from usvsim.messages.envelope import Envelope

_NUMPY = {7: "<f4", 8: "<f8", 4: "<u2", 6: "<u4", 2: "<u1"}  # sensor_msgs/PointField datatypes


def cloud_arrays(msg) -> tuple[np.ndarray, np.ndarray]:
    """(xyz float64 (n, 3) in the cloud's frame, time float64 (n,) s after its stamp) of the finite points."""
    fields = {f.name: (f.offset, _NUMPY[f.datatype]) for f in msg.fields}
    dtype = np.dtype({"names": list(fields), "formats": [v[1] for v in fields.values()],
                      "offsets": [v[0] for v in fields.values()], "itemsize": msg.point_step})  # fmt: skip
    pts = np.frombuffer(bytes(msg.data), dtype=dtype, count=msg.width * msg.height)
    xyz = np.stack([pts["x"], pts["y"], pts["z"]], axis=1).astype(np.float64)
    keep = np.isfinite(xyz).all(axis=1)
    times = pts["time"].astype(np.float64) if "time" in fields else np.zeros(len(pts))
    return xyz[keep], times[keep]


def transform_matrix(tf) -> np.ndarray:
    """4x4 parent ← child of a geometry_msgs/TransformStamped."""
    t, q = tf.transform.translation, tf.transform.rotation
    out = np.eye(4)
    out[:3, :3] = matrix_from_quat(np.array([q.w, q.x, q.y, q.z]))
    out[:3, 3] = (t.x, t.y, t.z)
    return out


def sweep_end_s(stamp_s: float, times_s: np.ndarray) -> float:
    """The end of a sweep stamped at its first column (s): stamp + the largest point time."""
    return stamp_s + (float(times_s.max()) if len(times_s) else 0.0)


def twist_vector(msg) -> np.ndarray:
    """(vx, vy, vz, wx, wy, wz) of a nav_msgs/Odometry's twist (child frame, e.g. base_link; m/s, rad/s)."""
    v, w = msg.twist.twist.linear, msg.twist.twist.angular
    return np.array([v.x, v.y, v.z, w.x, w.y, w.z])


def odometry_pose(msg) -> np.ndarray:
    """4x4 parent ← child (e.g. odom ← base_link) of a nav_msgs/Odometry."""
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    out = np.eye(4)
    out[:3, :3] = matrix_from_quat(np.array([q.w, q.x, q.y, q.z]))
    out[:3, 3] = (p.x, p.y, p.z)
    return out


class Tap:
    """Subscribes to a simulation; keeps the newest message of each topic it is asked for, and the static TFs."""

    def __init__(self, sim, topics):
        self.topics = set(topics)
        self.fresh: dict[str, Envelope] = {}
        self.static: dict[str, np.ndarray] = {}
        self.latest_odometry = None  # the newest nav_msgs/Odometry of the topics
        self._twists: list[np.ndarray] = []  # its twists since the last `mean_twist`
        self.unsubscribe = sim.subscribe(self._on)

    def _on(self, env) -> None:
        if env.msgtype == "nav_msgs/msg/Odometry" and env.topic in self.topics:
            self.latest_odometry = env.msg
            self._twists.append(twist_vector(env.msg))
        elif env.topic in self.topics:
            self.fresh[env.topic] = env
        elif env.topic == "/tf_static":
            for tf in env.msg.transforms:
                self.static[tf.child_frame_id] = transform_matrix(tf)

    def take(self, topic: str) -> Envelope | None:
        """The newest envelope on `topic` since the last take, or None."""
        return self.fresh.pop(topic, None)

    def mean_twist(self) -> np.ndarray | None:
        """The mean odometry twist since the last call (a noisy velocity sensor averaged over the interval), else
        the newest one's, else None."""
        if self._twists:
            out = np.mean(self._twists, axis=0)
            self._twists.clear()
            return out
        return None if self.latest_odometry is None else twist_vector(self.latest_odometry)
