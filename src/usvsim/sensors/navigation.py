"""Odometry, GNSS and ground-truth pose sensors.

- `Odometry`: nav_msgs/Odometry of `<vessel>/base_link` in `<vessel>/odom` (the vessel's initial pose,
  the same frame `GroundTruth` publishes as `world → <vessel>/odom`), twist in base_link, Gaussian noise
  with its covariance filled in (6x6 over x, y, z, rotX, rotY, rotZ); or a dead-reckoned pose that drifts.
- `Gnss`: sensor_msgs/NavSatFix of the antenna (mount point) from ENU through the scenario's geodetic
  origin (pymap3d, WGS-84; altitude = the origin's + world z, the sea being level), with a Gauss–Markov position error (white when the correlation time is 0); optional ENU velocity (TwistWithCovarianceStamped, frame `world`) on the sibling topic `.../vel`.
- `GroundTruthPose`: exact nav_msgs/Odometry of the sensor frame in `world`, twist in the sensor frame.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pymap3d

from usvsim.core.transforms import cross3, matrix_from_quat, quat_conjugate, quat_from_rpy, quat_multiply
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.sensors.base import Sensor, gaussian
from usvsim.sensors.messages import navsat_fix_msg, twist_cov_stamped_msg

if TYPE_CHECKING:
    from usvsim.config.sensors import Gnss as GnssConfig
    from usvsim.config.sensors import GroundTruth as GroundTruthConfig
    from usvsim.config.sensors import Odometry as OdometryConfig
    from usvsim.world.world import World

_FIX_STATUS = {"no_fix": -1, "fix": 0, "sbas_fix": 1, "gbas_fix": 2}


def mount_velocity_world(sensor: Sensor, sim: World) -> np.ndarray:
    """World (ENU) velocity of the sensor's mount point, m/s."""
    rot = sim.state.rot[sensor.body]
    return sim.origin_velocity(sensor.body) + cross3(rot @ sim.state.omega_body[sensor.body], rot @ sensor.mount_pos)


def _cov6(linear_var: float, angular_var: float) -> np.ndarray:
    return np.diag([linear_var] * 3 + [angular_var] * 3)


class Odometry(Sensor):
    cfg: OdometryConfig

    def __init__(self, cfg: OdometryConfig, vessel: str, sim: World):
        super().__init__(cfg, vessel, sim)
        self.odom_frame, self.child_frame = f"{vessel}/odom", f"{vessel}/base_link"
        self.reset(sim)

    def reset(self, sim: World) -> None:
        super().reset(sim)
        self.origin_pos, self.origin_quat = sim.odom_origin[self.vessel]
        self.period_s = self.every * sim.clock.dt
        # dead reckoning: the true position in odom at the last sample, the estimate, its heading error (rad), the
        # white noise's covariance so far (x, y, yaw in odom: m², m rad, rad²; z m²) and the teleport count
        pos, _ = self._true_pose(sim)
        self.dead_reckoning = [pos, pos.copy(), 0.0, np.zeros((3, 3)), 0.0, int(sim.body_teleports[self.body])]

    def static_transforms(self) -> list:
        return []  # odometry refers to base_link itself; GroundTruth owns world → odom and odom → base_link

    def _true_pose(self, sim: World) -> tuple[np.ndarray, np.ndarray]:
        v, inv = sim.vessels[self.vessel], quat_conjugate(self.origin_quat)
        return matrix_from_quat(inv) @ (v.position - self.origin_pos), quat_multiply(inv, v.quat)

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        c, v = self.cfg, sim.vessels[self.vessel]
        if c.mode == "dead_reckoning":
            return self._dead_reckoning(sim, stamp_ns)
        pos, quat = self._true_pose(sim)
        pos = pos + gaussian(self.rng, c.position_stddev_m)
        if c.orientation_stddev_rad > 0:
            quat = quat_multiply(quat, quat_from_rpy(*self.rng.normal(0.0, c.orientation_stddev_rad, 3)))
        lin = v.velocity_body + gaussian(self.rng, c.linear_velocity_stddev_mps)
        ang = v.angular_velocity_body + gaussian(self.rng, c.angular_velocity_stddev_radps)
        pose_cov = _cov6(c.position_stddev_m**2, c.orientation_stddev_rad**2)
        twist_cov = _cov6(c.linear_velocity_stddev_mps**2, c.angular_velocity_stddev_radps**2)
        msg = ros.odometry_msg(stamp_ns, self.odom_frame, self.child_frame, pos, quat, lin, ang, pose_cov, twist_cov)
        return [Envelope(self.topic, stamp_ns, msg)]

    def _dead_reckoning(self, sim: World, stamp_ns: int) -> list[Envelope]:
        """The pose integrated from the measured motion (config/sensors.py `Odometry`): the true displacement since
        the last sample in the odometry's heading, scaled, plus the velocity noise over the period; the heading
        error grows by the yaw-rate error. A teleport moves the estimate with the boat (its error kept)."""
        c, v, dt = self.cfg, sim.vessels[self.vessel], self.period_s
        pos, quat = self._true_pose(sim)
        lin_noise = gaussian(self.rng, c.linear_velocity_stddev_mps)
        ang_noise = gaussian(self.rng, c.angular_velocity_stddev_radps)
        last, est, dpsi, cov, var_z, teleports = self.dead_reckoning
        step = pos - last
        if sim.body_teleports[self.body] != teleports:  # not sailed: no measurement error
            est = est + step
        else:
            cos_e, sin_e = math.cos(dpsi), math.sin(dpsi)
            step = step * (1.0 + c.velocity_scale_error)
            turned = np.array([cos_e * step[0] - sin_e * step[1], sin_e * step[0] + cos_e * step[1], step[2]])
            est_quat = quat_multiply(quat_from_rpy(0.0, 0.0, dpsi), quat)
            est = est + turned + matrix_from_quat(est_quat) @ lin_noise * dt
            dpsi += (c.yaw_rate_bias_radps + ang_noise[2]) * dt
            # the heading's error turns this step: x, y gain -Δy δψ, Δx δψ (first order), so a run at speed V
            # adds V² σ_r² Δt t³/3 across its track to the velocity noise's σ_v² Δt t
            jac = np.array([[1.0, 0.0, -turned[1]], [0.0, 1.0, turned[0]], [0.0, 0.0, 1.0]])
            white = np.array([c.linear_velocity_stddev_mps, c.linear_velocity_stddev_mps,
                              c.angular_velocity_stddev_radps]) * dt  # fmt: skip
            cov = jac @ cov @ jac.T + np.diag(white**2)
            var_z += (c.linear_velocity_stddev_mps * dt) ** 2
        self.dead_reckoning = [pos, est, dpsi, cov, var_z, int(sim.body_teleports[self.body])]
        est_quat = quat_multiply(quat_from_rpy(0.0, 0.0, dpsi), quat)
        lin = v.velocity_body * (1.0 + c.velocity_scale_error) + lin_noise
        ang = v.angular_velocity_body + ang_noise + np.array([0.0, 0.0, c.yaw_rate_bias_radps])
        pose_cov = np.zeros((6, 6))  # the white noise's share (biases are unknown); roll and pitch are true
        pose_cov[np.ix_((0, 1, 5), (0, 1, 5))], pose_cov[2, 2] = cov, var_z
        twist_cov = _cov6(c.linear_velocity_stddev_mps**2, c.angular_velocity_stddev_radps**2)
        msg = ros.odometry_msg(stamp_ns, self.odom_frame, self.child_frame, est, est_quat, lin, ang, pose_cov,
                               twist_cov)  # fmt: skip
        return [Envelope(self.topic, stamp_ns, msg)]


class Gnss(Sensor):
    cfg: GnssConfig

    def __init__(self, cfg: GnssConfig, vessel: str, sim: World):
        super().__init__(cfg, vessel, sim)
        o = sim.scenario.world.origin
        self.origin = (o.latitude_deg, o.longitude_deg, o.altitude_m)
        self.topic = cfg.topic or f"/{vessel}/{cfg.name}/fix"
        self.vel_topic = f"{self.topic.rsplit('/', 1)[0]}/vel"  # sibling of the fix topic
        horizontal, vertical, tau = cfg.error_model()
        self.sigma = np.array([horizontal, horizontal, vertical])
        self.phi = math.exp(-self.every * sim.clock.dt / tau) if tau > 0 else 0.0
        self.error = None if self.sigma.any() else np.zeros(3)

    def lla(self, pos_enu: np.ndarray) -> tuple[float, float, float]:
        """WGS-84 latitude, longitude (deg) of an ENU point (exact, through the tangent plane at the origin) and
        its ellipsoidal altitude (m): the origin's plus the world z. The world's still water is level, as the sea
        is; the tangent plane itself rises d²/2R above the ellipsoid (31 m at 20 km), which made a boat afloat
        far from the origin read that high (QA)."""
        (e, n, u), (lat0, lon0, alt0) = pos_enu, self.origin
        lat, lon, _ = pymap3d.enu2geodetic(e, n, u, lat0, lon0, alt0)
        return float(lat), float(lon), float(alt0 + u)

    def position_error(self) -> np.ndarray:
        """Advance the ENU error (m) one fix: x ← φx + σ√(1-φ²)·n, φ = exp(-T/τ) (exact discretisation of a
        first-order Gauss–Markov process; φ = 0 is white noise). Starts at a draw from the stationary law."""
        if self.error is not None and not self.sigma.any():
            return self.error  # exact zeros
        kick = self.rng.normal(0.0, 1.0, 3) * self.sigma
        self.error = kick if self.error is None else self.phi * self.error + math.sqrt(1.0 - self.phi**2) * kick
        return self.error

    def reset(self, sim: World) -> None:
        super().reset(sim)
        self.error = None if self.sigma.any() else np.zeros(3)

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        c, sigma = self.cfg, self.sigma
        pos, _ = self.pose_world(sim)
        noisy = pos + self.position_error()
        msg = navsat_fix_msg(stamp_ns, self.frame_id, self.lla(noisy), _FIX_STATUS[c.fix], sigma**2)
        out = [Envelope(self.topic, stamp_ns, msg)]
        if c.velocity:
            vel = mount_velocity_world(self, sim) + gaussian(self.rng, c.velocity_stddev_mps)
            cov = _cov6(c.velocity_stddev_mps**2, -1.0)  # angular part: not measured
            out.append(Envelope(self.vel_topic, stamp_ns, twist_cov_stamped_msg(stamp_ns, "world", vel, np.zeros(3), cov)))
        return out


class GroundTruthPose(Sensor):
    cfg: GroundTruthConfig

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        pos, rot = self.pose_world(sim)
        lin = rot.T @ mount_velocity_world(self, sim)
        ang = self.mount_rot.T @ sim.state.omega_body[self.body]
        msg = ros.odometry_msg(stamp_ns, "world", self.frame_id, pos, self.quat_world(sim), lin, ang)
        return [Envelope(self.topic, stamp_ns, msg)]
