"""LiDAR odometry: KISS-ICP (optional extra `autonomy`, imported lazily) on our clouds, deskewed with their
per-point `time` field and a velocity sensor's twist (DVL/GNSS-like, body frame) as the motion prior in place
of KISS-ICP's constant-velocity prediction; or, without it, the pose of a nav_msgs/Odometry source with the
cloud deskewed by the same twist (`--odometry sensor`).

Frames and times: a cloud's header stamp is its first column, point times are seconds after it, so the sweep
ends at stamp + max(time). Both odometries give the base_link pose at the sweep END and the cloud deskewed to
the LiDAR frame at that instant (KISS-ICP's convention: it normalises the point times to [0, 1] and moves every
point to the last one's frame). The map frame is the world ENU frame, initialised (like AMCL's `initialpose`)
with the base_link pose at the first sweep's end: T_map_base(t) = T_map_lidar(0) · T_icp(t) · T_lidar_base.

KISS-ICP settings for these harbour clouds (benchmarks/bench_autonomy.py, docs/autonomy.md): voxel 1.0 m
(KISS-ICP's own rule max_range / 100 gives 0.4-0.6 m here, 7x slower for a worse ATE), points beyond 40 m
dropped (sparse, grazing quay faces), 3 points per map voxel.
"""

from __future__ import annotations

import numpy as np

from usvsim.core.errors import UsvsimError
from usvsim.core.transforms import cross3


def kiss_icp_available() -> bool:
    try:
        import kiss_icp  # noqa: F401
    except ImportError:
        return False
    return True


def _rotation(rotvec: np.ndarray) -> np.ndarray:
    """Rodrigues: the rotation matrix of a rotation vector (rad)."""
    angle = float(np.linalg.norm(rotvec))
    if angle < 1e-12:
        return np.eye(3)
    k = rotvec / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * kx + (1.0 - np.cos(angle)) * kx @ kx


def twist_motion(twist: np.ndarray, dt_s: float) -> np.ndarray:
    """Motion (4x4, frame at t ← frame at t + dt) at a constant body twist (vx, vy, vz, wx, wy, wz; m/s, rad/s)
    over dt s: rotation exp(ω·dt), translation v·dt (first order)."""
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = _rotation(np.asarray(twist[3:]) * dt_s), np.asarray(twist[:3]) * dt_s
    return out


def lidar_twist(twist_base: np.ndarray, base_from_lidar: np.ndarray) -> np.ndarray:
    """The twist of the LiDAR frame (in it) from base_link's: ω_L = R ω, v_L = R (v + ω × r) with R = R_lb."""
    r_lb, mount = base_from_lidar[:3, :3].T, base_from_lidar[:3, 3]
    v, w = np.asarray(twist_base[:3], float), np.asarray(twist_base[3:], float)
    return np.concatenate([r_lb @ (v + cross3(w, mount)), r_lb @ w])


def deskew(xyz: np.ndarray, times_s: np.ndarray, twist_lidar: np.ndarray) -> np.ndarray:
    """Points (n, 3) each taken at its time (s) by a LiDAR moving at `twist_lidar`, moved to the LiDAR frame at
    the sweep end (max time): p* = Exp(-Δ_i ξ)·p, Δ_i = t_end - t_i (Rodrigues per point, translation first order)."""
    dt = (times_s.max() - times_s)[:, None] if len(times_s) else np.zeros((0, 1))
    v, w = twist_lidar[:3], twist_lidar[3:]
    rate = float(np.linalg.norm(w))
    out = xyz - dt * v
    if rate < 1e-9:
        return out
    k = w / rate
    theta = -dt * rate
    c, s = np.cos(theta), np.sin(theta)
    return out + (c - 1.0) * xyz + s * cross3(k, xyz) + (1.0 - c) * (xyz @ k)[:, None] * k


class KissIcpOdometry:
    """Pose (4x4, map ← base_link, at the sweep end) from successive clouds (sensor frame xyz (n, 3), times (n,) s)."""

    def __init__(self, base_from_lidar: np.ndarray, max_range_m: float = 40.0, voxel_size_m: float = 1.0):
        try:
            from kiss_icp.config import KISSConfig
            from kiss_icp.kiss_icp import KissICP
        except ImportError:
            raise UsvsimError(
                "LiDAR odometry needs KISS-ICP: pip install 'usvsim[autonomy]' (or kiss-icp)"
            ) from None
        config = KISSConfig()
        config.data.max_range, config.data.min_range, config.data.deskew = max_range_m, 1.0, True
        config.mapping.voxel_size = voxel_size_m
        config.mapping.max_points_per_voxel = 3  # 20 by default; 3: cheaper and a lower ATE here
        config.registration.max_num_threads = 1  # the simulation uses the other core
        self.icp = KissICP(config)
        self.base_from_lidar = base_from_lidar
        self.lidar_from_base = np.linalg.inv(base_from_lidar)
        self.map_from_lidar0: np.ndarray | None = None

    def initialise(self, map_from_base: np.ndarray) -> None:
        self.map_from_lidar0 = map_from_base @ self.base_from_lidar
        self.z0_m = float(map_from_base[2, 3])

    def update(self, xyz: np.ndarray, times_s: np.ndarray, twist=None, dt_s: float = 0.1):
        """Register one cloud; returns (map ← base_link pose at the sweep end, the deskewed cloud in the LiDAR frame).
        `twist`: base_link's (vx, vy, vz, wx, wy, wz) from a velocity sensor, `dt_s` the time since the previous
        registered sweep's end (clouds may be skipped). The twist predicts the pose at this sweep's start (the
        initial guess, with the sweep's own motion) and deskews the sweep, in place of KISS-ICP's constant velocity."""
        times_s = np.asarray(times_s, np.float64)
        if twist is not None:
            sweep = float(times_s.max()) if len(times_s) else 0.0
            to_lidar = lambda m: self.lidar_from_base @ m @ self.base_from_lidar  # noqa: E731
            self.icp.last_pose = self.icp.last_pose @ to_lidar(twist_motion(twist, max(dt_s - sweep, 0.0)))
            self.icp.last_delta = to_lidar(twist_motion(twist, sweep))
        # a cloud whose points share one time (a LiDAR without motion_distortion) has nothing to deskew, and
        # KISS-ICP's time normalisation (t - min) / (max - min) made NaN of it: Sophus aborted the process
        stamps = times_s if len(times_s) and times_s.max() > times_s.min() else np.zeros(0)
        frame, _ = self.icp.register_frame(np.asarray(xyz, np.float64), stamps)
        if self.map_from_lidar0 is None:
            raise RuntimeError("LidarOdometry.update() before initialise()")
        pose = self.map_from_lidar0 @ self.icp.last_pose @ self.lidar_from_base
        # a floating boat's height: the start's. Walls and sheds seen from near their tops do not fix it, and
        # KISS-ICP's drifted 0.8 m down in a minute (an Otter's VLP-16 at 1 m by 1 m quays): buoys left the band
        pose[2, 3] = self.z0_m
        return pose, frame


class TrackedOdometry:
    """Without KISS-ICP: the newest nav_msgs/Odometry from `source()` (odom ← base_link), in the map frame; the
    cloud is deskewed to its sweep end with the velocity sensor's twist (at 1.5 m/s a 10 Hz sweep would
    otherwise smear walls by up to 0.15 m)."""

    def __init__(self, base_from_lidar: np.ndarray, source):
        self.base_from_lidar, self.source = base_from_lidar, source
        self.map_from_odom = np.eye(4)

    def _odom_from_base(self) -> np.ndarray:
        from usvsim.autonomy.sensing import odometry_pose

        msg = self.source()
        if msg is None:
            raise UsvsimError("--odometry sensor needs an `odometry` sensor on the vessel")
        return odometry_pose(msg)

    def initialise(self, map_from_base: np.ndarray) -> None:
        self.map_from_odom = map_from_base @ np.linalg.inv(self._odom_from_base())

    def update(self, xyz: np.ndarray, times_s: np.ndarray, twist=None, dt_s: float = 0.1):
        pose = self.map_from_odom @ self._odom_from_base()
        if twist is None or not len(xyz):
            return pose, xyz
        return pose, deskew(xyz, np.asarray(times_s, np.float64), lidar_twist(twist, self.base_from_lidar))
