"""An independent ROS 2 peer (rclpy + rmw_fastrtps_cpp from the PyPI Kilted wheels) for the DDS bridge test.

    python dds_rclpy_peer.py accept SECONDS   # subscribe to everything, check, then drive the boats; JSON out
    python dds_rclpy_peer.py noisy            # subscribe to the heavy topics, send garbage commands, until killed
    python dds_rclpy_peer.py match N          # subscribe to one topic of each message type; until N of each

Run only inside a loopback-only network namespace (test_dds_ros2.py does). Nothing from usvsim is imported.
"""

from __future__ import annotations

import json
import math
import sys
import time

import rclpy
from dds_rclpy_types import decode_tf, raw_message_type
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, qos_profile_sensor_data
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, Imu, LaserScan, NavSatFix, PointCloud2
from std_msgs.msg import Float64

TF = raw_message_type("tf2_msgs", "TFMessage")
RELIABLE, SENSOR = QoSProfile(depth=50), qos_profile_sensor_data
STATIC = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
TOPICS = {  # topic: (type, QoS, raw)
    "/clock": (Clock, QoSProfile(depth=200), False),
    "/tf": (TF, QoSProfile(depth=200), True),
    "/tf_static": (TF, STATIC, True),
    "/wamv/camera/image_raw": (Image, RELIABLE, False),
    "/wamv/camera/camera_info": (CameraInfo, RELIABLE, False),
    "/wamv/camera/depth/image_raw": (Image, SENSOR, False),
    "/wamv/camera/depth/camera_info": (CameraInfo, SENSOR, False),
    "/wamv/lidar/points": (PointCloud2, SENSOR, False),
    "/wamv/lidar2d/scan": (LaserScan, SENSOR, False),
    "/wamv/imu/data": (Imu, RELIABLE, False),
    "/wamv/odometry": (Odometry, RELIABLE, False),
    "/wamv/gps/fix": (NavSatFix, RELIABLE, False),
    "/wamv/ground_truth/odometry": (Odometry, RELIABLE, False),
    "/otter/ground_truth/odometry": (Odometry, RELIABLE, False),
}
NS = 10**9


def stamp_ns(topic: str, msg) -> int:
    if topic == "/clock":
        return msg.clock.sec * NS + msg.clock.nanosec
    if topic.startswith("/tf"):
        return decode_tf(msg)[0]["stamp_ns"]
    return msg.header.stamp.sec * NS + msg.header.stamp.nanosec


def check(topic: str, msg) -> str | None:
    """A problem with one message, or None."""
    if isinstance(msg, PointCloud2):
        names = {f.name: f.datatype for f in msg.fields}
        if any(names.get(k) != 7 for k in "xyz") or msg.is_bigendian:
            return f"fields {names}"
        if msg.row_step != msg.point_step * msg.width or len(msg.data) != msg.row_step * msg.height:
            return "point cloud sizes"
    if isinstance(msg, Image):
        bpp = {"rgb8": 3, "32FC1": 4}.get(msg.encoding)
        if bpp is None or msg.step != msg.width * bpp or len(msg.data) != msg.step * msg.height:
            return f"image {msg.encoding} {msg.width}x{msg.height} step {msg.step} len {len(msg.data)}"
    if isinstance(msg, Imu) and not math.isfinite(msg.linear_acceleration.z):
        return f"imu z {msg.linear_acceleration.z}"
    if isinstance(msg, LaserScan) and len(msg.ranges) < 2:
        return "empty scan"
    return None


class Peer(Node):
    def __init__(self, topics, qos_override=None):
        super().__init__("usvsim_test_peer")
        self.stamps: dict[str, list[int]] = {t: [] for t in topics}
        self.problems: list[str] = []
        self.imu_z: list[float] = []  # specific force, body z (m/s²): single samples swing as the hull settles
        self.frames: dict[str, set[str]] = {"/tf": set(), "/tf_static": set()}
        self.speed = {"wamv": 0.0, "otter": 0.0}
        self.clock_ns = None
        for topic in topics:
            ty, qos, raw = TOPICS[topic]
            qos = (qos_override or {}).get(ty, qos)
            self.create_subscription(ty, topic, lambda m, t=topic: self.on_msg(t, m), qos, raw=raw)

    def on_msg(self, topic: str, msg) -> None:
        self.stamps[topic].append(stamp_ns(topic, msg))
        if topic == "/clock":
            self.clock_ns = self.stamps[topic][-1]
        if topic in self.frames:
            self.frames[topic] |= {f"{t['frame_id']}>{t['child_frame_id']}" for t in decode_tf(msg)}
        elif topic.endswith("ground_truth/odometry"):
            self.speed[topic.split("/")[1]] = msg.twist.twist.linear.x
        if isinstance(msg, Imu):
            self.imu_z.append(msg.linear_acceleration.z)
        problem = check(topic, msg)
        if problem and len(self.problems) < 20:
            self.problems.append(f"{topic}: {problem}")

    def spin_until(self, sim_ns: int, wall_s: float, each=None) -> None:
        deadline = time.monotonic() + wall_s
        while time.monotonic() < deadline and (self.clock_ns is None or self.clock_ns < sim_ns):
            rclpy.spin_once(self, timeout_sec=0.05)
            if each is not None:
                each()


def accept(seconds: float) -> dict:
    peer = Peer(TOPICS)
    peer.spin_until(0, 30.0)  # first /clock
    t0 = peer.clock_ns
    peer.spin_until(t0 + int(seconds * NS), 60.0)
    t1 = peer.clock_ns
    thrust = [peer.create_publisher(Float64, f"/wamv/thrusters/{n}/thrust", 10)
              for n in ("front_left", "front_right", "rear_left", "rear_right")]  # fmt: skip
    cmd_vel = peer.create_publisher(Twist, "/otter/cmd_vel", 10)
    last = [0.0]

    def command():
        if time.monotonic() - last[0] > 0.1:
            last[0] = time.monotonic()
            for pub in thrust:
                pub.publish(Float64(data=1.0))
            twist = Twist()
            twist.linear.x = 1.0
            cmd_vel.publish(twist)

    peer.spin_until(t1 + 3 * NS, 150.0, command)  # wall bound: generous for a machine at load ~15
    imu_z = sorted(peer.imu_z)
    if not imu_z or not 8.8 < imu_z[len(imu_z) // 2] < 10.8:  # median: gravity reaction, REP 145
        peer.problems.append(f"imu z median {imu_z[len(imu_z) // 2] if imu_z else None}")
    return {"window_ns": [t0, t1], "stamps": peer.stamps, "problems": peer.problems,
            "frames": {k: sorted(v) for k, v in peer.frames.items()}, "speed": peer.speed}  # fmt: skip


def match(n: int, wall_s: float = 120.0) -> dict:
    """Until `n` messages of every topic (or `wall_s`): which types match, and are they valid.

    Images are taken best-effort: a reliable Fast DDS 3.2 reader with the kernel's default socket buffers
    can stall for good inside `take` on MB-size samples from a Cyclone writer (docs/ros2.md, known issues);
    type matching, which this peer checks, does not depend on reliability."""
    peer = Peer(TOPICS, qos_override={Image: SENSOR})
    need = {topic: 1 if topic == "/tf_static" else n for topic in TOPICS}  # /tf_static: one latched message
    deadline = time.monotonic() + wall_s
    while time.monotonic() < deadline and any(len(peer.stamps[t]) < k for t, k in need.items()):
        rclpy.spin_once(peer, timeout_sec=0.05)
    return {"counts": {t: len(v) for t, v in peer.stamps.items()}, "problems": peer.problems}


def noisy() -> None:
    peer = Peer(["/clock", "/wamv/camera/image_raw", "/wamv/lidar/points"])
    thrust = peer.create_publisher(Float64, "/wamv/thrusters/rear_left/thrust", 10)
    cmd_vel = peer.create_publisher(Twist, "/wamv/cmd_vel", 10)
    bad_twist = Twist()
    bad_twist.angular.z = math.inf
    garbage = [b"\x00\x01\x00\x00\x01", b"\xde\xad\xbe\xef" * 3, b""]
    while True:
        for msg in (Float64(data=math.nan), Float64(data=5.0)):
            thrust.publish(msg)
        cmd_vel.publish(bad_twist)
        for data in garbage:
            thrust.publish(data)
        rclpy.spin_once(peer, timeout_sec=0.02)


if __name__ == "__main__":
    rclpy.init()
    if sys.argv[1] == "accept":
        print(json.dumps(accept(float(sys.argv[2]))), flush=True)
    elif sys.argv[1] == "match":
        print(json.dumps(match(int(sys.argv[2]))), flush=True)
    else:
        noisy()
