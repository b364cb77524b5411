"""ROS 2 message builders for sensors (rosbags dataclasses), vectorized: no per-point Python loops.

Quaternions in usvsim are (w, x, y, z); messages get x, y, z, w. Covariances are row-major.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from usvsim.messages.ros import header, msg_class, point, quaternion, vector3

FLOAT32, UINT16 = 7, 4  # sensor_msgs/PointField datatypes
NO_ESTIMATE = np.array([-1.0] + [0.0] * 8)  # Imu.msg: element 0 = -1 means "no estimate"
POINT_DTYPE = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("intensity", "<f4"), ("ring", "<u2"),
                        ("_pad", "<u2"), ("time", "<f4")])  # fmt: skip  22 bytes used, 24 per point
_POINT_FIELDS = (("x", 0, FLOAT32), ("y", 4, FLOAT32), ("z", 8, FLOAT32), ("intensity", 12, FLOAT32),
                 ("ring", 16, UINT16), ("time", 20, FLOAT32))  # fmt: skip


def imu_msg(stamp_ns: int, frame_id: str, quat_wxyz, gyro, accel, cov_orientation, cov_gyro, cov_accel) -> Any:
    """sensor_msgs/Imu (REP 145): orientation w.r.t. ENU, angular velocity rad/s, specific force m/s^2."""
    f64 = lambda c: np.asarray(c, dtype=np.float64).reshape(9)  # noqa: E731
    return msg_class("sensor_msgs/msg/Imu")(
        header=header(stamp_ns, frame_id),
        orientation=quaternion(quat_wxyz),
        orientation_covariance=f64(cov_orientation),
        angular_velocity=vector3(gyro),
        angular_velocity_covariance=f64(cov_gyro),
        linear_acceleration=vector3(accel),
        linear_acceleration_covariance=f64(cov_accel),
    )


def navsat_fix_msg(stamp_ns: int, frame_id: str, lla, status: int, cov_enu_diag) -> Any:
    """sensor_msgs/NavSatFix: latitude/longitude in degrees, altitude (m, WGS-84 ellipsoid), ENU covariance."""
    types = msg_class
    nav_status = types("sensor_msgs/msg/NavSatStatus")(status=np.int8(status), service=np.uint16(1))
    cov = np.diag(np.asarray(cov_enu_diag, dtype=np.float64)).reshape(9)
    known = bool(np.any(cov > 0))
    return types("sensor_msgs/msg/NavSatFix")(
        header=header(stamp_ns, frame_id), status=nav_status, latitude=float(lla[0]), longitude=float(lla[1]),
        altitude=float(lla[2]), position_covariance=cov, position_covariance_type=np.uint8(2 if known else 0),
    )  # fmt: skip


def twist_cov_stamped_msg(stamp_ns: int, frame_id: str, linear, angular, cov6) -> Any:
    """geometry_msgs/TwistWithCovarianceStamped (6x6 row-major covariance)."""
    twist = msg_class("geometry_msgs/msg/Twist")(linear=vector3(linear), angular=vector3(angular))
    twc = msg_class("geometry_msgs/msg/TwistWithCovariance")(twist=twist, covariance=np.asarray(cov6, np.float64).reshape(36))
    return msg_class("geometry_msgs/msg/TwistWithCovarianceStamped")(header=header(stamp_ns, frame_id), twist=twc)


def laser_scan_msg(stamp_ns: int, frame_id: str, angle_min: float, increment: float, ranges: np.ndarray,
                   intensities: np.ndarray, range_min: float, range_max: float, scan_time: float) -> Any:  # fmt: skip
    """sensor_msgs/LaserScan with exactly N = len(ranges) beams: angle_max = angle_min + (N-1)·increment."""
    n = len(ranges)
    return msg_class("sensor_msgs/msg/LaserScan")(
        header=header(stamp_ns, frame_id), angle_min=float(angle_min), angle_max=float(angle_min + (n - 1) * increment),
        angle_increment=float(increment), time_increment=0.0, scan_time=float(scan_time), range_min=float(range_min),
        range_max=float(range_max), ranges=np.ascontiguousarray(ranges, np.float32),
        intensities=np.ascontiguousarray(intensities, np.float32),
    )  # fmt: skip


def point_cloud2_msg(stamp_ns: int, frame_id: str, points: np.ndarray, height: int, width: int) -> Any:
    """sensor_msgs/PointCloud2 from a POINT_DTYPE array: x, y, z, intensity FLOAT32, ring UINT16, time FLOAT32.

    `height` 1 = unorganized; `height` = channels for an organized cloud (misses are NaN). is_dense is
    true only when no coordinate is NaN.
    """
    field = msg_class("sensor_msgs/msg/PointField")
    fields = [field(name=n, offset=o, datatype=t, count=1) for n, o, t in _POINT_FIELDS]
    dense = not bool(np.isnan(points["x"]).any())
    step = POINT_DTYPE.itemsize
    return msg_class("sensor_msgs/msg/PointCloud2")(
        header=header(stamp_ns, frame_id), height=int(height), width=int(width), fields=fields, is_bigendian=False,
        point_step=step, row_step=step * int(width), data=np.ascontiguousarray(points).reshape(-1).view(np.uint8),
        is_dense=dense,
    )  # fmt: skip


def camera_info_msg(stamp_ns: int, frame_id: str, width: int, height: int, K: np.ndarray, D) -> Any:
    """sensor_msgs/CameraInfo, plumb_bob: d = [k1, k2, p1, p2, k3], r = I, p = [K | 0] (monocular)."""
    P = np.zeros((3, 4))
    P[:, :3] = K
    roi = msg_class("sensor_msgs/msg/RegionOfInterest")(x_offset=0, y_offset=0, height=0, width=0, do_rectify=False)
    return msg_class("sensor_msgs/msg/CameraInfo")(
        header=header(stamp_ns, frame_id), height=int(height), width=int(width), distortion_model="plumb_bob",
        d=np.asarray(D, np.float64), k=np.asarray(K, np.float64).reshape(9), r=np.eye(3).reshape(9),
        p=P.reshape(12), binning_x=0, binning_y=0, roi=roi,
    )  # fmt: skip


def points_from_cloud(msg: Any) -> np.ndarray:
    """Inverse of `point_cloud2_msg` (for tests and tools): a POINT_DTYPE view of the data."""
    return np.frombuffer(bytes(msg.data), dtype=POINT_DTYPE).reshape(msg.height, msg.width)


def _hypothesis(label: str, pos, quat_wxyz) -> Any:
    """vision_msgs/ObjectHypothesisWithPose: ground truth, score 1, the object's pose, zero covariance."""
    pose = msg_class("geometry_msgs/msg/Pose")(position=point(pos), orientation=quaternion(quat_wxyz))
    return msg_class("vision_msgs/msg/ObjectHypothesisWithPose")(
        hypothesis=msg_class("vision_msgs/msg/ObjectHypothesis")(class_id=label, score=1.0),
        pose=msg_class("geometry_msgs/msg/PoseWithCovariance")(pose=pose, covariance=np.zeros(36)),
    )


def detection3d_msg(stamp_ns: int, frame_id: str, object_id: str, label: str, center, quat_wxyz, size_m) -> Any:
    """vision_msgs/Detection3D: an oriented box (centre pose + full size, m) in `frame_id`."""
    pose = msg_class("geometry_msgs/msg/Pose")(position=point(center), orientation=quaternion(quat_wxyz))
    bbox = msg_class("vision_msgs/msg/BoundingBox3D")(center=pose, size=vector3(size_m))
    return msg_class("vision_msgs/msg/Detection3D")(header=header(stamp_ns, frame_id),
                                                    results=[_hypothesis(label, center, quat_wxyz)], bbox=bbox,
                                                    id=object_id)  # fmt: skip


def detection2d_msg(stamp_ns: int, frame_id: str, object_id: str, label: str, box_px, pos_optical, quat_optical) -> Any:
    """vision_msgs/Detection2D: axis-aligned pixel box (u_min, v_min, u_max, v_max; pixel centres at integers)
    and, as the hypothesis pose, the object's box pose in the camera's optical frame."""
    u0, v0, u1, v1 = (float(b) for b in box_px)
    centre = msg_class("vision_msgs/msg/Pose2D")(position=msg_class("vision_msgs/msg/Point2D")(x=0.5 * (u0 + u1),
                                                 y=0.5 * (v0 + v1)), theta=0.0)  # fmt: skip
    bbox = msg_class("vision_msgs/msg/BoundingBox2D")(center=centre, size_x=u1 - u0, size_y=v1 - v0)
    return msg_class("vision_msgs/msg/Detection2D")(header=header(stamp_ns, frame_id),
                                                    results=[_hypothesis(label, pos_optical, quat_optical)], bbox=bbox,
                                                    id=object_id)  # fmt: skip


def detection_array_msg(stamp_ns: int, frame_id: str, detections: list, dims: int) -> Any:
    """vision_msgs/Detection2DArray (dims 2) or Detection3DArray (dims 3)."""
    return msg_class(f"vision_msgs/msg/Detection{dims}DArray")(header=header(stamp_ns, frame_id), detections=detections)


def label_classes(labels: dict[int, tuple[str, str]]) -> list:
    """vision_msgs/VisionClass per segmentation id: class_id = the pixel value, class_name = "<class>:<object>"
    (e.g. "buoy:red_1"; 0, the background, is not listed). Made once per camera (the ids never change)."""
    vision_class = msg_class("vision_msgs/msg/VisionClass")
    return [vision_class(class_id=int(k), class_name=f"{cls}:{name}") for k, (name, cls) in sorted(labels.items())]


def label_info_msg(stamp_ns: int, frame_id: str, classes: list) -> Any:
    """vision_msgs/LabelInfo of a segmentation image from `label_classes`; threshold 0 (ground truth)."""
    return msg_class("vision_msgs/msg/LabelInfo")(header=header(stamp_ns, frame_id), class_map=classes, threshold=0.0)
