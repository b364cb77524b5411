"""IMU (REP 145), odometry, GNSS and ground truth against closed-form or independent answers."""

from __future__ import annotations

import numpy as np
import pymap3d
import pytest
from scipy.spatial.transform import Rotation
from sensor_rig import make_sim, quat_angle, sensor_configs

from usvsim.core.errors import ScenarioError
from usvsim.core.transforms import matrix_from_quat, quat_multiply
from usvsim.messages.ros import time_to_ns
from usvsim.sensors import SensorSuite, navigation
from usvsim.sensors.base import OPTICAL_QUAT, OPTICAL_ROT
from usvsim.simulation import Simulation

IMU_MOUNT = {"position": [0.4, -0.3, 1.0], "yaw_deg": 30.0}


def _vec(v):
    return np.array([v.x, v.y, v.z])


def test_imu_at_rest_reads_plus_g_on_z(rig):
    sim, suite, col = rig({"type": "imu", "name": "imu", "mount": {"position": [0.4, -0.3, 1.0]}},
                          {"type": "imu", "name": "vrx", "preset": "vrx"})  # fmt: skip
    col.run(15.0)  # settle at the floating equilibrium
    quat, gyro, accel = suite["wamv/imu"].true_values(sim)
    expected = matrix_from_quat(quat).T @ np.array([0.0, 0.0, sim.g])  # gravity reaction in the sensor frame
    assert np.allclose(accel, expected, atol=2e-3)
    assert accel[2] == pytest.approx(9.81, abs=0.01) and np.abs(gyro).max() < 1e-4
    msgs = [e.msg for _, e in col.by_topic["/wamv/vrx/data"][-500:]]  # last 5 s at 100 Hz
    acc = np.array([_vec(m.linear_acceleration) for m in msgs])
    assert np.allclose(acc.mean(axis=0), [0.0, 0.0, 9.81], atol=0.12)  # within the VRX turn-on bias
    assert np.allclose(acc.std(axis=0), 0.021, rtol=0.15)  # white noise sigma
    assert msgs[-1].linear_acceleration_covariance[0] == pytest.approx(0.021**2)


def test_gyro_integration_reproduces_attitude_change(rig):
    sim, suite, col = rig({"type": "imu", "name": "imu", "rate_hz": 100, "mount": IMU_MOUNT})
    col.run(2.0)
    boat = sim.vessels["wamv"]
    thrusters = list(boat.thrusters.values())
    q0, q = suite["wamv/imu"].true_values(sim)[0], None
    q = q0.copy()
    start = len(col.by_topic["/wamv/imu/data"])
    for _k in range(1000):  # 10 s turning hard: left thrusters back, right forward
        for t in thrusters:
            t.command(0.8 if "right" in t.name else -0.6)
        sim.step()
        col(sim)
    for _, env in col.by_topic["/wamv/imu/data"][start:]:
        w = _vec(env.msg.angular_velocity) * 0.01
        angle = np.linalg.norm(w)
        dq = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * w / max(angle, 1e-15)])
        q = quat_multiply(q, dq)
    q_true = suite["wamv/imu"].true_values(sim)[0]
    assert np.degrees(quat_angle(q0, q_true)) > 20.0  # it really turned
    assert np.degrees(quat_angle(q, q_true)) < 1.0


def test_imu_vrx_bias_walks_and_streams_are_independent():
    def readings(extra):
        sim = make_sim(seed=3)
        cfgs = sensor_configs({"type": "imu", "name": "imu", "preset": "vrx"}, *extra)
        suite = SensorSuite(sim.world, {"wamv": cfgs})
        out = []
        sim.run(1.0, on_step=lambda s: out.extend(e.msg.angular_velocity.x for e in suite.on_step(s) if "imu" in e.topic))
        return np.array(out), suite["wamv/imu"]

    a, imu = readings([])
    b, _ = readings([{"type": "gnss", "name": "gps", "horizontal_stddev_m": 1.0}])
    assert np.array_equal(a, b)  # adding a sensor does not change another sensor's noise
    assert np.any(imu.gyro.walk != 0.0) and np.any(imu.gyro.turn_on != 0.0)


def test_gnss_without_noise_converts_back_to_enu_within_1mm(rig):
    pose = {"position": [812.0, -1534.0, 0.0], "yaw_deg": 70.0}
    sim, suite, col = rig({"type": "gnss", "name": "gps", "rate_hz": 10, "velocity": True,
                           "mount": {"position": [-1.0, 0.5, 1.3]}}, vessel_pose=pose)  # fmt: skip
    col.run(3.0)
    fix = col.by_topic["/wamv/gps/fix"][-1][1].msg
    o = sim.scenario.world.origin
    enu = pymap3d.geodetic2enu(fix.latitude, fix.longitude, fix.altitude, o.latitude_deg, o.longitude_deg, o.altitude_m)
    truth, _ = suite["wamv/gps"].pose_world(sim)
    assert np.linalg.norm(np.array(enu[:2]) - truth[:2]) < 1e-3
    assert fix.altitude == pytest.approx(o.altitude_m + truth[2], abs=1e-9)  # the sea is level (test below)
    assert fix.status.status == 0 and fix.position_covariance_type == 0
    vel = col.by_topic["/wamv/gps/vel"][-1][1].msg
    assert vel.header.frame_id == "world"


def _latlon_of_enu(enu, lat0_deg, lon0_deg, h0_m):
    """WGS-84 latitude, longitude (deg) of an ENU point, by hand (the independent reference): geocentric
    coordinates of the origin plus the ENU offset, then the fixed-point iteration for latitude."""
    a, f = 6378137.0, 1 / 298.257223563
    e2, lat0, lon0 = f * (2 - f), np.radians(lat0_deg), np.radians(lon0_deg)
    n0 = a / np.sqrt(1 - e2 * np.sin(lat0) ** 2)
    origin = np.array([(n0 + h0_m) * np.cos(lat0) * np.cos(lon0), (n0 + h0_m) * np.cos(lat0) * np.sin(lon0),
                       (n0 * (1 - e2) + h0_m) * np.sin(lat0)])  # fmt: skip
    rows = np.array([[-np.sin(lon0), np.cos(lon0), 0.0],
                     [-np.sin(lat0) * np.cos(lon0), -np.sin(lat0) * np.sin(lon0), np.cos(lat0)],
                     [np.cos(lat0) * np.cos(lon0), np.cos(lat0) * np.sin(lon0), np.sin(lat0)]])  # fmt: skip
    x, y, z = origin + rows.T @ np.asarray(enu, float)
    p, lat = np.hypot(x, y), np.arctan2(z, np.hypot(x, y) * (1 - e2))
    for _ in range(10):
        n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
        lat = np.arctan2(z + e2 * n * np.sin(lat), p)
    return np.degrees(lat), np.degrees(np.arctan2(y, x))


def test_gnss_far_from_the_origin_reads_the_level_sea_and_its_point_on_the_tangent_plane(rig):
    """Afloat 20 km east of the origin the fix read 31 m higher than at the origin: the tangent plane's height
    above the ellipsoid, d²/2R, though the world's water is level as the sea is. Lat/lon: the tangent-plane
    point, against a conversion written out by hand."""
    sim, suite, col = rig({"type": "gnss", "name": "gps", "rate_hz": 10}, vessel_pose={"position": [20000.0, 0.0, 0.0]})
    col.run(1.0)
    fix = col.by_topic["/wamv/gps/fix"][-1][1].msg
    o = sim.scenario.world.origin
    truth, _ = suite["wamv/gps"].pose_world(sim)
    assert fix.altitude == pytest.approx(o.altitude_m + truth[2], abs=1e-9) and abs(truth[2]) < 1.0
    lat, lon = _latlon_of_enu(truth, o.latitude_deg, o.longitude_deg, o.altitude_m)
    assert fix.latitude == pytest.approx(lat, abs=1e-9) and fix.longitude == pytest.approx(lon, abs=1e-9)  # 0.1 mm


def test_gnss_noise_statistics(rig):
    sim, suite, col = rig({"type": "gnss", "name": "gps", "rate_hz": 50, "horizontal_stddev_m": 2.0,
                           "vertical_stddev_m": 4.0})  # fmt: skip
    col.run(10.0)
    o = sim.scenario.world.origin
    fixes = [e.msg for _, e in col.by_topic["/wamv/gps/fix"]]
    enu = np.array([pymap3d.geodetic2enu(f.latitude, f.longitude, f.altitude, o.latitude_deg, o.longitude_deg,
                                         o.altitude_m) for f in fixes])  # fmt: skip
    truth, _ = suite["wamv/gps"].pose_world(sim)
    std = (enu - truth).std(axis=0)
    assert np.allclose(std, [2.0, 2.0, 4.0], rtol=0.2)
    assert fixes[0].position_covariance[0] == pytest.approx(4.0) and fixes[0].position_covariance_type == 2


@pytest.mark.parametrize("latency_s", [0.0, 0.05])
def test_rates_in_simulation_time_and_latency(rig, latency_s):
    sensors = [{"type": "imu", "name": "imu", "rate_hz": 100, "latency_s": latency_s},
               {"type": "odometry", "name": "odom", "rate_hz": 50, "latency_s": latency_s},
               {"type": "gnss", "name": "gps", "rate_hz": 5, "latency_s": latency_s},
               {"type": "ground_truth", "name": "truth", "rate_hz": 20, "latency_s": latency_s}]  # fmt: skip
    sim, suite, col = rig(*sensors)
    col.run(60.0)
    for topic, rate in [("/wamv/imu/data", 100), ("/wamv/odom", 50), ("/wamv/gps/fix", 5), ("/wamv/truth", 20)]:
        got = col.by_topic[topic]
        assert abs(len(got) - 60 * rate) <= 1 + round(latency_s * rate), topic  # the last ones are still in flight
        stamps = np.array([env.stamp_ns for _, env in got])
        assert np.all(np.diff(stamps) == 1e9 / rate)
        assert all(now - env.stamp_ns == round(latency_s * 1e9) for now, env in got)
        assert all(time_to_ns(env.msg.header.stamp) == env.stamp_ns for _, env in got[:5])


def test_static_transforms_and_frames(rig):
    sim, suite, _ = rig({"type": "imu", "name": "imu", "mount": IMU_MOUNT})
    (tf,) = suite.static_transforms()
    assert (tf.header.frame_id, tf.child_frame_id) == ("wamv/base_link", "wamv/imu")
    assert tf.transform.translation.x == pytest.approx(0.4)
    assert np.allclose(matrix_from_quat(OPTICAL_QUAT), OPTICAL_ROT)
    assert suite.static_envelope().topic == "/tf_static"


def test_odometry_noise_and_covariance(rig):
    sim, suite, col = rig({"type": "odometry", "name": "odom", "rate_hz": 50, "position_stddev_m": 0.1,
                           "linear_velocity_stddev_mps": 0.05})  # fmt: skip
    col.run(10.0)
    msgs = [e.msg for _, e in col.by_topic["/wamv/odom"]]
    assert msgs[0].header.frame_id == "wamv/odom" and msgs[0].child_frame_id == "wamv/base_link"
    xs = np.array([m.pose.pose.position.x for m in msgs[-250:]])
    assert xs.std() == pytest.approx(0.1, rel=0.2)
    assert msgs[0].pose.covariance[0] == pytest.approx(0.01) and msgs[0].twist.covariance[7] == pytest.approx(0.0025)


def test_bad_rate_is_a_scenario_error():
    sim = make_sim()
    with pytest.raises(ScenarioError, match=r"sensors\[0\]\.rate_hz"):
        SensorSuite(sim.world, {"wamv": sensor_configs({"type": "imu", "name": "imu", "rate_hz": 33})})


def test_a_teleport_is_no_acceleration_for_the_imu(scenario_of):
    """The IMU differences its mount's velocity over each step; a teleport's jump in position and velocity is
    not motion the vessel made: the step over it reads no acceleration (it read ~20 g for a 2 m/s twist), and
    another body's teleport changes nothing."""
    data = {"name": "imu", "vessels": [{"name": "wamv", "model": "wamv",
                                        "sensors": [{"type": "imu", "name": "imu", "rate_hz": 100}]},
                                       {"name": "otter", "model": "otter", "pose": {"position": [30.0, 0.0, 0.0]}}]}  # fmt: skip
    sim, twin = Simulation(scenario_of(data), seed=1), Simulation(scenario_of(data), seed=1)
    for s in (sim, twin):
        s.run(1.0)
    sim.vessels["otter"].teleport((60.0, 0.0, 0.0, 0.0, 0.0, 0.0), twist=(3.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    for s in (sim, twin):
        s.run(0.5)
    imu = sim.sensors["wamv/imu"]
    assert np.array_equal(imu.true_values(sim.world)[2], twin.sensors["wamv/imu"].true_values(twin.world)[2])
    sim.vessels["wamv"].teleport((5.0, 0.0, 0.0, 0.0, 0.0, 0.3), twist=(2.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    sim.step()
    _, rot = imu.pose_world(sim.world)
    np.testing.assert_allclose(imu.true_values(sim.world)[2], rot.T @ [0.0, 0.0, sim.world.g], atol=1e-12)
    sim.run(0.5)
    assert np.linalg.norm(imu.true_values(sim.world)[2]) < 20.0  # the motion after it is measured again


def test_imu_below_the_physics_rate_reports_the_mean_over_its_sample_period(scenario_of):
    """A 20 Hz IMU on 100 Hz physics in sea state 4: R·f·T + g·T is exactly the mount's velocity change between
    samples and ω·T its rotation (to coning order), as an integrating IMU's output; the last step alone (what it
    reported) was 4-9 % off each 50 ms velocity change."""
    data = {"name": "imu", "environment": {"sea": {"type": "sea_state", "code": 4, "direction_deg": 30.0}},
            "vessels": [{"name": "wamv", "model": "wamv",
                         "sensors": [{"type": "imu", "name": "imu", "rate_hz": 20, "mount": IMU_MOUNT}]}]}  # fmt: skip
    sim = Simulation(scenario_of(data), seed=0)
    for thruster in sim.vessels["wamv"].thrusters.values():
        thruster.command(0.7)
    sim.run(5.0)
    imu = sim.sensors["wamv/imu"]
    samples = []
    for _ in range(60):
        sim.run(0.05)
        pos, rot = imu.pose_world(sim.world)
        reading = imu.latest
        assert reading.stamp_ns == sim.clock_ns
        velocity = navigation.mount_velocity_world(imu, sim.world)
        samples.append((rot, velocity, reading["linear_acceleration"], reading["angular_velocity"]))
    dv_error, dv_size, angle_error, angle_size = [], [], [], []
    for (rot0, v0, _, _), (rot1, v1, f1, w1) in zip(samples, samples[1:], strict=False):
        dv = v1 - v0
        dv_error.append(np.abs(rot1 @ f1 * 0.05 - [0.0, 0.0, sim.world.g * 0.05] - dv).max())
        dv_size.append(np.abs(dv).max())
        turn = Rotation.from_matrix(rot0.T @ rot1).as_rotvec()
        angle_error.append(np.abs(w1 * 0.05 - turn).max())
        angle_size.append(np.abs(turn).max())
    assert min(dv_size) > 1e-3 and max(dv_error) < 1e-9
    assert np.median(angle_size) > 1e-3 and max(angle_error) < 1e-5
