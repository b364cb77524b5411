"""The array side of every sensor type (sensors/readings.py): one contract over a scenario with one of each.

Finite values where a value is promised, the sensor's frame id, stamps on the sensor's clock grid, arrays
that later steps never overwrite (no aliasing of internal buffers), and the documented dtypes."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.simulation import Simulation

SENSORS = [
    {"type": "lidar", "name": "lidar", "channels": 4, "columns": 90, "vertical_fov_deg": [-10, 10], "range_max_m": 60,
     "rate_hz": 10, "mount": {"position": [0.7, 0.0, 1.03]}},
    {"type": "lidar", "name": "scan", "output": "scan", "channels": 1, "columns": 180, "range_max_m": 60,
     "rate_hz": 10, "mount": {"position": [0.7, 0.0, 1.03]}},
    {"type": "camera", "name": "camera", "width": 64, "height": 48, "rate_hz": 10,
     "streams": ["rgb", "depth", "segmentation"], "detections": {}, "mount": {"position": [0.3, 0.0, 1.3]}},
    {"type": "imu", "name": "imu", "rate_hz": 50, "preset": "vrx"},
    {"type": "odometry", "name": "odometry", "rate_hz": 20, "position_stddev_m": 0.1},
    {"type": "gnss", "name": "gps", "rate_hz": 5, "velocity": True, "horizontal_stddev_m": 0.5},
    {"type": "ground_truth", "name": "truth", "rate_hz": 20},
    {"type": "detections", "name": "objects", "rate_hz": 10},
    {"type": "radar", "name": "radar", "rpm": 60, "rate_hz": 10, "range_max_m": 200.0, "spokes": 128, "range_bins": 64,
     "image": "none", "mount": {"position": [0.0, 0.0, 2.5]}},
]  # fmt: skip
DTYPES = {"points": None, "ranges": np.float32, "rgb": np.uint8, "depth": np.float32, "segmentation": np.uint16,
          "echoes": np.float32}  # fmt: skip


def _bytes(a: np.ndarray) -> bytes:
    """The values' bytes (field by field for structured arrays: their padding is not data)."""
    return b"".join(a[n].tobytes() for n in a.dtype.names) if a.dtype.names else a.tobytes()


@pytest.fixture(scope="module")
def sim(tmp_path_factory):
    from usvsim.config.loader import parse_scenario

    data = {"version": 1, "name": "contract",
            "vessels": [{"name": "wamv", "model": "wamv", "sensors": SENSORS},
                        {"name": "otter", "model": "otter", "pose": {"position": [12.0, 1.0, 0.0]}}],
            "objects": [{"type": "buoy", "name": "red_1", "position": [8.0, -2.0, 0.0], "color": "red"}]}  # fmt: skip
    sim = Simulation(parse_scenario(data, "contract"))
    sim.vessels["wamv"].command(0.4)
    yield sim
    sim.close()


def test_every_sensor_type_meets_the_reading_contract(sim):
    sim.run(0.5)
    first = sim.observe()
    assert all(r is not None for r in first.values()), [n for n, r in first.items() if r is None]
    copies = {name: {k: np.array(a, copy=True) for k, a in r.items()} for name, r in first.items()}
    sim.run(0.5)
    later = sim.observe()
    for name, r in first.items():
        sensor = sim.sensors[name]
        assert r.frame_id in (sensor.frame_id, sensor.optical_frame_id, f"{sensor.vessel}/odom", "world"), name
        period_ns = sensor.every * sim.clock.step_ns
        assert r.stamp_ns % period_ns == 0 and 0 < r.stamp_ns <= 500_000_000, (name, r.stamp_ns)
        assert later[name] is not r and later[name].stamp_ns > r.stamp_ns, name
        for key, array in r.items():
            assert _bytes(array) == _bytes(copies[name][key]), f"{name}/{key} overwritten by later steps"
            assert not np.shares_memory(array, later[name][key]) if key in later[name] else True
            if array.dtype.names is None and array.dtype.kind == "f" and key not in ("ranges", "depth"):
                assert np.isfinite(array).all(), f"{name}/{key}"
            if DTYPES.get(key) is not None:
                assert array.dtype == DTYPES[key], key
    assert {k for r in first.values() for k in r} >= {"points", "ranges", "angles", "rgb", "K", "detections_2d",
                                                      "orientation", "lla", "position_covariance", "detections"}
    for name, r in later.items():  # every array read-only (docs/python-api.md): the cached Reading cannot be changed
        for key, array in r.items():
            assert not array.flags.writeable, f"{name}/{key} is writeable"
            with pytest.raises(ValueError, match="read-only"):
                array[...] = array
        assert sim.sensors[name].latest is r  # the Reading every later observe() hands out


def test_reading_fields_and_handles(sim):
    sim.run(0.2)
    boat = sim.vessels["wamv"]
    assert set(boat.sensors) == {c["name"] for c in SENSORS} and boat.sensors["imu"] is sim.sensors["wamv/imu"]
    points = boat.sensors["lidar"].latest["points"]
    assert points.dtype.names == ("x", "y", "z", "intensity", "ring", "time") and points["ring"].max() == 3
    camera = boat.sensors["camera"].latest
    assert camera["rgb"].shape == (48, 64, 3) and camera["depth"].shape == (48, 64)
    ids = set(np.unique(camera["segmentation"])) - {0}
    labels = sim.sensors["wamv/camera"].segmentation_ids
    assert ids <= set(labels)  # every label is named: objects and the water (its drawn surface and the plane beyond)
    names = {labels[i][0] for i in ids}
    assert "otter" in names and "water" in {labels[i][1] for i in ids}
    assert "otter" in set(sim.sensors["wamv/objects"].latest["detections"]["id"])
    imu = boat.sensors["imu"].latest
    assert 0.0 < imu["linear_acceleration"][2] < 20.0 and imu["orientation"].shape == (4,)  # specific force: +g, heaving
    assert sim.sensors["wamv/imu"].read() is not None and sim.sensors["wamv/imu"].read() is None  # read() consumes
    msg = imu.messages["/wamv/imu/data"]
    assert msg.linear_acceleration.z == imu["linear_acceleration"][2]  # the ROS message rides along
