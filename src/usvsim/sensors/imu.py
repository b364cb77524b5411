"""IMU (sensor_msgs/Imu per REP 145), in the sensor frame `<vessel>/<name>` (FLU).

- orientation: sensor frame w.r.t. world ENU (identity when level, facing east);
- angular_velocity: body rate about the sensor axes, rad/s;
- linear_acceleration: specific force f = a - g_vec (m/s^2), +g on z when level at rest.

Acceleration choice: the mount point's world velocity v_p = v_o + ω × r is recorded after every
physics step and differenced over each step, a = (v_p,k - v_p,k-1) / dt. This is the acceleration
MuJoCo's integrator actually applied over that step (its velocity update), so it is exact for the
simulated motion at rest (f = (0, 0, g) to rounding) and includes the lever-arm terms (ω × (ω × r),
α × r). A sample reports the mean over its whole sample period T = 1/rate_hz, as an integrating IMU's
output does: specific force from the velocity change over T (Σ a·dt / T, in the sensor frame at the sample
time) and body rate from the mean of the steps' rates. So R·f·T + g·T is exactly the velocity change between
samples and Σ ω·T the rotation (to coning order) at any rate; sampling the last step alone (what this did)
left errors of 4-9 % of each 50 ms velocity change at 20 Hz in sea state 4 (QA). At rate = physics rate the
two are the same. A `teleport` of the vessel is no motion it made: the step over it reads no acceleration
(gravity only). It costs a few small vector ops per step and needs no extra MuJoCo call
(mj_rnePostConstraint/cacc would give the pre-step acceleration instead).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from usvsim.core.transforms import cross3, quat_from_rpy, quat_multiply
from usvsim.messages.envelope import Envelope
from usvsim.sensors.base import Sensor, diagonal_covariance
from usvsim.sensors.messages import imu_msg
from usvsim.sensors.noise import TriadNoise

if TYPE_CHECKING:
    from usvsim.config.sensors import Imu as ImuConfig
    from usvsim.world.world import World


class Imu(Sensor):
    cfg: ImuConfig

    observes_every_step = True

    def __init__(self, cfg: ImuConfig, vessel: str, sim: World):
        super().__init__(cfg, vessel, sim)
        self.topic = cfg.topic or f"/{vessel}/{cfg.name}/data"
        self.dt = sim.clock.dt
        self.gravity = np.array([0.0, 0.0, -sim.g])
        self.reset(sim)

    def reset(self, sim: World) -> None:
        super().reset(sim)
        dt_sample = self.every * self.dt
        self.gyro = TriadNoise(self.cfg.gyro_noise(), dt_sample, self.rng)  # turn-on biases drawn anew
        self.accel = TriadNoise(self.cfg.accel_noise(), dt_sample, self.rng)
        self._v_prev = self._v_now = self._mount_velocity(sim)
        self._teleports = int(sim.body_teleports[self.body])
        # sums over the current sample period: velocity change, body rates, steps
        self._dv_sum, self._rate_sum, self._steps = np.zeros(3), np.zeros(3), 0
        self._sampled = False  # the next step starts a new period

    def _mount_velocity(self, sim: World) -> np.ndarray:
        rot = sim.state.rot[self.body]
        omega_world = rot @ sim.state.omega_body[self.body]
        return sim.origin_velocity(self.body) + cross3(omega_world, rot @ self.mount_pos)

    def observe(self, sim: World) -> None:
        v = self._mount_velocity(sim)
        if sim.body_teleports[self.body] != self._teleports:  # moved by `teleport` before this step: the
            self._teleports, self._v_now = int(sim.body_teleports[self.body]), v  # jump is not its motion
        self._v_prev, self._v_now = self._v_now, v
        if self._sampled:  # a new sample period (the sums are reused: no allocation on this every-step path)
            self._dv_sum.fill(0.0)
            self._rate_sum.fill(0.0)
            self._steps, self._sampled = 0, False
        self._dv_sum += self._v_now - self._v_prev
        self._rate_sum += sim.state.omega_body[self.body]
        self._steps += 1

    def true_values(self, sim: World) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Exact (quaternion w,x,y,z w.r.t. ENU, gyro rad/s, specific force m/s^2), sensor frame: the orientation
        now, rate and specific force averaged over the sample period so far (the last one, just after a sample)."""
        _, rot_sensor = self.pose_world(sim)
        if self._steps == 0:  # nothing observed since the start: the state now
            accel_world, rate = np.zeros(3), sim.state.omega_body[self.body]
        else:
            accel_world, rate = self._dv_sum / (self._steps * self.dt), self._rate_sum / self._steps
        return self.quat_world(sim), self.mount_rot.T @ rate, rot_sensor.T @ (accel_world - self.gravity)

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        quat, gyro, accel = self.true_values(sim)
        self._sampled = True
        sigma_q = self.cfg.orientation_stddev_rad
        if sigma_q > 0:
            quat = quat_multiply(quat, quat_from_rpy(*self.rng.normal(0.0, sigma_q, 3)))
        msg = imu_msg(stamp_ns, self.frame_id, quat, self.gyro.apply(gyro), self.accel.apply(accel),
                      diagonal_covariance(sigma_q**2), diagonal_covariance(self.gyro.variance),
                      diagonal_covariance(self.accel.variance))  # fmt: skip
        return [Envelope(self.topic, stamp_ns, msg)]
