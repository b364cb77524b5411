"""Sensor realism: bag replay timing read back from an MCAP, the LiDAR self-return crop, Gauss–Markov GNSS."""

from __future__ import annotations

import numpy as np
import pymap3d
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from sensor_rig import make_sim, sensor_configs

from usvsim.io.mcap_recorder import McapRecorder
from usvsim.messages.ros import time_to_ns
from usvsim.sensors import SensorSuite
from usvsim.sensors.messages import points_from_cloud

MOUNT = {"position": [0.701, 0.0, 1.031]}
BOX = {"type": "box", "name": "wall", "position": [8.0, 0.0, 0.5], "size": [1.0, 12.0, 3.0]}


def test_no_message_is_logged_before_it_could_exist(tmp_path):
    """A distorted sweep is stamped at its first column and logged when it ends; latency delays the log time."""
    sim = make_sim(objects=[BOX])
    sensors = sensor_configs(
        {"type": "lidar", "name": "lidar", "preset": "vlp16", "columns": 360, "rate_hz": 10, "motion_distortion": True,
         "mount": MOUNT},
        {"type": "imu", "name": "imu", "rate_hz": 50, "latency_s": 0.03})  # fmt: skip
    suite = SensorSuite(sim, {"wamv": sensors})
    path = tmp_path / "timing.mcap"
    with McapRecorder(path) as rec:
        sim.run(0.5, on_step=lambda s: [rec.write(e) for e in suite.on_step(s)])
    seen = {}
    with path.open("rb") as f:  # an independent reader: mcap + mcap-ros2
        for _, channel, message, decoded in make_reader(
            f, decoder_factories=[DecoderFactory()]
        ).iter_decoded_messages():
            stamp = time_to_ns(decoded.header.stamp)
            seen.setdefault(channel.topic, []).append((message.log_time - rec.epoch_ns, stamp, decoded))
    clouds, imus = seen["/wamv/lidar/points"], seen["/wamv/imu/data"]
    assert len(clouds) == 5 and len(imus) == 23  # the last two IMU samples are still in flight
    for log_time, stamp, cloud in clouds:
        last_point_ns = stamp + round(float(points_from_cloud(cloud)["time"].max()) * 1e9)
        assert log_time >= last_point_ns and log_time - stamp == pytest.approx(0.1e9, abs=1e7)
    assert all(log_time - stamp == 30_000_000 for log_time, stamp, _ in imus)


def test_self_return_crop_removes_only_the_own_hull():
    sim = make_sim(objects=[BOX])
    suite = SensorSuite(sim, {"wamv": sensor_configs(
        {"type": "lidar", "name": "full", "preset": "os1_64", "columns": 512, "mount": MOUNT},
        {"type": "lidar", "name": "crop", "preset": "os1_64", "columns": 512, "self_returns": False, "mount": MOUNT})})  # fmt: skip
    sim.step()
    full, crop = (points_from_cloud(suite[f"wamv/{n}"].sample(sim, 0)[0].msg) for n in ("full", "crop"))
    rng = lambda p: np.sqrt(p["x"] ** 2 + p["y"] ** 2 + p["z"] ** 2)  # noqa: E731
    assert (rng(full) < 4.0).sum() > 500  # the WAM-V's own hull and frame, 0.5-3 m away
    assert (rng(crop) < 4.0).sum() == 0
    assert (rng(crop) > 6.0).sum() == (rng(full) > 6.0).sum() > 100  # the wall is untouched


@pytest.mark.parametrize(("height_m", "range_min_m", "fraction", "farthest_m"),
                         [(1.2, 0.5, 0.28, 1.9), (1.031, 0.0, 0.57, 0.8), (1.031, 0.5, 0.09, 0.8)])  # fmt: skip
def test_self_returns_are_the_share_of_the_scan_the_docs_state(height_m, range_min_m, fraction, farthest_m):
    """docs/sensor-realism.md: the share of an OS1-64's beams that return from the WAM-V itself, and how far."""
    sim = make_sim()
    cfg = {"type": "lidar", "preset": "os1_64", "range_stddev_m": 0.0, "range_min_m": range_min_m, "organized": True,
           "mount": {"position": [0.701, 0.0, height_m]}}  # fmt: skip
    suite = SensorSuite(sim, {"wamv": sensor_configs({**cfg, "name": "full"}, {**cfg, "name": "crop", "self_returns": False})})
    sim.step()
    full, crop = (points_from_cloud(suite[f"wamv/{n}"].sample(sim, 0)[0].msg) for n in ("full", "crop"))
    own = np.isfinite(full["x"]) & ~np.isfinite(crop["x"])  # nothing else is in range: open water
    dist = np.sqrt(full["x"][own] ** 2 + full["y"][own] ** 2 + full["z"][own] ** 2)
    assert own.mean() == pytest.approx(fraction, abs=0.01)
    assert np.percentile(dist, 99) == pytest.approx(farthest_m, abs=0.1)


def test_gnss_gauss_markov_error_has_its_stddev_and_correlation_time(rig):
    tau, rate = 5.0, 10.0
    sim, suite, col = rig({"type": "gnss", "name": "gps", "rate_hz": rate, "horizontal_stddev_m": 1.5,
                           "vertical_stddev_m": 3.0, "correlation_time_s": tau})  # fmt: skip
    col.run(200.0)
    o = sim.scenario.world.origin
    fixes = [e.msg for _, e in col.by_topic["/wamv/gps/fix"]]
    enu = np.array([pymap3d.geodetic2enu(f.latitude, f.longitude, f.altitude, o.latitude_deg, o.longitude_deg,
                                         o.altitude_m) for f in fixes])  # fmt: skip
    err = enu - suite["wamv/gps"].pose_world(sim)[0]  # the WAM-V drifts < 1 cm here
    assert np.allclose(
        err.std(axis=0), [1.5, 1.5, 3.0], rtol=0.35
    )  # 40 correlation times: ~16 % sampling error
    lag = round(tau * rate)
    e = err[:, :2] - err[:, :2].mean(axis=0)
    rho = (e[lag:] * e[:-lag]).sum() / (e * e).sum()
    assert rho == pytest.approx(np.exp(-1.0), abs=0.15)  # autocorrelation exp(-lag/τ) at lag = τ
    steps = np.linalg.norm(np.diff(err[:, :2], axis=0), axis=1)
    assert np.median(steps) < 0.5  # fix to fix, the error drifts; white noise would jump ~1.8 m
    assert fixes[0].position_covariance[0] == pytest.approx(1.5**2)


def test_gnss_preset_from_the_receiver_data_sheet():
    from usvsim.config.sensors import Gnss

    h, v, tau = Gnss(type="gnss", name="gps", preset="ublox_m8").error_model()
    assert h * 1.1774 == pytest.approx(2.5) and v == pytest.approx(2 * h) and tau == 60.0
    assert Gnss(type="gnss", name="gps", preset="ublox_m8", correlation_time_s=0).error_model()[2] == 0.0
