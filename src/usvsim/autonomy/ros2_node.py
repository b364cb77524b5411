"""`usvsim-autonomy --ros2`: the reference stack as a ROS 2 node (rclpy, imported lazily).

Subscribes `/<v>/<lidar>/points` (PointCloud2 with per-point `time`) and `/<v>/odometry` (nav_msgs/Odometry:
its twist is the ICP's motion prior; with `--odometry sensor` its pose is the localisation); publishes
`/map` (nav_msgs/OccupancyGrid, transient local, 1 Hz), `/plan` (nav_msgs/Path on every new plan) and
`/<v>/cmd_vel` (geometry_msgs/Twist) at the cloud rate. Frames: the map frame is `<v>/odom` (the odometry's
frame, so the goals are in it); the LiDAR mount in base_link is `--lidar-xyz` (FLU m, no rotation), as a
parameter like most drivers' extrinsics. Prints one JSON line `RESULT {...}` when every goal is reached (or
given up: no plan reached it for 30 s).
"""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from usvsim.autonomy.demo import parse_goals
from usvsim.autonomy.grid import OccupancyGrid
from usvsim.autonomy.navigator import Navigator, NavigatorConfig
from usvsim.autonomy.odometry import KissIcpOdometry, TrackedOdometry
from usvsim.autonomy.sensing import cloud_arrays, odometry_pose, sweep_end_s, twist_vector
from usvsim.core.errors import UsvsimError


def _args(argv):
    p = argparse.ArgumentParser(prog="usvsim-autonomy", description=(__doc__ or "").split("\n\n")[0])
    p.add_argument("--ros2", action="store_true", required=True, help="run as a ROS 2 node (rclpy)")
    p.add_argument("--vessel", default="wamv")
    p.add_argument("--lidar", default="lidar")
    p.add_argument("--lidar-xyz", default="0.701,0.0,1.6", help="LiDAR position in base_link, m")
    p.add_argument("--goals", required=True, help="'x,y;x,y' in the map frame (<vessel>/odom), m")
    p.add_argument(
        "--bounds", default="-60,-40,60,40", help="map extent xmin,ymin,xmax,ymax in m (--bounds=-60,...)"
    )
    p.add_argument("--odometry", choices=("kiss_icp", "sensor"), default="kiss_icp")
    p.add_argument("--exit-when-done", action="store_true")
    args = p.parse_args(argv)
    try:  # before rclpy starts: a bad value was a traceback from inside the node's constructor
        args.goal_list = parse_goals(args.goals, f"the map frame {args.vessel}/odom")
    except UsvsimError as exc:
        p.error(str(exc))
    args.xyz = _numbers(p, "--lidar-xyz", args.lidar_xyz, 3, "x,y,z")
    args.box = xmin, ymin, xmax, ymax = _numbers(p, "--bounds", args.bounds, 4, "xmin,ymin,xmax,ymax")
    if not (xmin < xmax and ymin < ymax):
        p.error(f"--bounds {args.bounds!r}: xmin must be below xmax and ymin below ymax")
    for x, y in args.goal_list:  # never planned to: the boat stayed put
        if not (xmin <= x <= xmax and ymin <= y <= ymax):
            p.error(f"goal {x:g},{y:g} is outside the map (--bounds {args.bounds})")
    return args


def _numbers(parser, option: str, text: str, count: int, form: str) -> list[float]:
    """`count` finite comma-separated numbers, or the parser's error (one line, exit 2)."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        parser.error(f"{option} {text!r}: give {form} in metres ({count} numbers)")
    return values


def build(args):
    base_from_lidar = np.eye(4)
    base_from_lidar[:3, 3] = args.xyz
    xmin, ymin, xmax, ymax = args.box  # checked in _args
    grid = OccupancyGrid.around(xmin, ymin, xmax, ymax, 0.25)
    latest = {}
    odo = KissIcpOdometry(base_from_lidar) if args.odometry == "kiss_icp" else \
        TrackedOdometry(base_from_lidar, lambda: latest.get("odom"))  # fmt: skip
    return Navigator(grid, odo, args.goal_list, NavigatorConfig()), latest


def main(argv=None) -> int:
    args = _args(sys.argv[1:] if argv is None else argv)
    import rclpy
    from rclpy.node import Node

    rclpy.init()
    node = AutonomyNode(Node, args)
    try:
        while rclpy.ok() and not (args.exit_when_done and node.nav.done):
            rclpy.spin_once(node.node, timeout_sec=0.1)
    except KeyboardInterrupt:
        pass
    finally:
        node.node.destroy_node()
        rclpy.try_shutdown()
    return 0


class AutonomyNode:
    def __init__(self, node_class, args):
        from geometry_msgs.msg import Twist
        from nav_msgs.msg import OccupancyGrid as GridMsg
        from nav_msgs.msg import Odometry, Path
        from rclpy.qos import DurabilityPolicy, QoSProfile
        from sensor_msgs.msg import PointCloud2

        self.args, (self.nav, self.latest) = args, build(args)
        self.node = node_class("usvsim_autonomy")
        v = args.vessel
        self.frame, self.last_stamp, self.started, self.map_at = f"{v}/odom", None, False, -math.inf
        self.Twist, self.GridMsg, self.Path = Twist, GridMsg, Path
        self.cmd = self.node.create_publisher(Twist, f"/{v}/cmd_vel", 10)
        self.plan = self.node.create_publisher(Path, "/plan", 10)
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.map = self.node.create_publisher(GridMsg, "/map", latched)
        self.node.create_subscription(Odometry, f"/{v}/odometry", self.on_odometry, 10)
        self.node.create_subscription(PointCloud2, f"/{v}/{args.lidar}/points", self.on_cloud, 2)
        self._path_sent = None

    def on_odometry(self, msg) -> None:
        self.latest["odom"] = msg

    def on_cloud(self, msg) -> None:
        odom = self.latest.get("odom")
        if odom is None:
            return
        xyz, times = cloud_arrays(msg)
        stamp = sweep_end_s(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9, times)
        if not self.started:  # the sweep's end (`stamp`) is the instant the odometry estimates
            self.nav.odometry.initialise(odometry_pose(odom))
            self.started = True
        dt = 0.1 if self.last_stamp is None else stamp - self.last_stamp
        self.last_stamp = stamp
        u, r = self.nav.update(stamp, xyz, times, twist_vector(odom), dt)
        twist = self.Twist()
        twist.linear.x, twist.angular.z = float(u), float(r)
        self.cmd.publish(twist)
        self._publish_plan(msg.header.stamp)
        if stamp - self.map_at >= 1.0:
            self.map_at = stamp
            self.map.publish(self._grid_msg(msg.header.stamp))
        if self.nav.done and self.args.exit_when_done:
            p = self.nav.pose[:2, 3]
            result = {"reached_s": self.nav.reached, "given_up": self.nav.given_up, "x": p[0], "y": p[1]}
            print("RESULT " + json.dumps(result), flush=True)

    def _publish_plan(self, stamp) -> None:
        from geometry_msgs.msg import PoseStamped

        if self.nav.path is None or self.nav.path is self._path_sent:
            return
        self._path_sent = self.nav.path
        msg = self.Path()
        msg.header.stamp, msg.header.frame_id = stamp, self.frame
        poses = []
        for x, y in self.nav.path:
            pose = PoseStamped()
            pose.header = msg.header
            pose.pose.position.x, pose.pose.position.y, pose.pose.orientation.w = float(x), float(y), 1.0
            poses.append(pose)
        msg.poses = poses
        self.plan.publish(msg)

    def _grid_msg(self, stamp):
        g, msg = self.nav.grid, self.GridMsg()
        msg.header.stamp, msg.header.frame_id = stamp, self.frame
        msg.info.resolution = float(g.resolution_m)
        msg.info.height, msg.info.width = g.shape
        msg.info.origin.position.x, msg.info.origin.position.y = (float(v) for v in g.origin_xy)
        msg.info.origin.orientation.w = 1.0
        cells = np.where(g.known(), np.rint(g.probability() * 100), -1).astype(np.int8)
        msg.data = cells.ravel().tolist()  # row-major from the origin corner, as nav_msgs/OccupancyGrid wants
        return msg


if __name__ == "__main__":
    sys.exit(main())
