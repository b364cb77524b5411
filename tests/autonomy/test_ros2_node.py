"""Acceptance: the stack as an rclpy node drives the simulated boat to a goal over DDS (loopback namespace).

Two processes on independent DDS stacks (usvsim's Cyclone bridge, rclpy on Fast DDS) inside `unshare -n -m`
with only loopback; the true track comes from the simulation's MCAP recording, read with an independent
reader. Skipped without the ROS 2 wheels (extra `ros2-test`) or a network namespace.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from loopback_ns import isolated, unusable

pytest.importorskip("cyclonedds")
HERE = Path(__file__).parent
pytestmark = pytest.mark.slow  # a whole ROS 2 exchange in a network namespace: about a minute
SCENARIO = {
    "version": 1, "name": "ros2_drive", "world": {"physics_rate_hz": 100},
    "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [0.0, 0.0, 0.0]}, "command_timeout_s": 1.0,
                 "sensors": [{"type": "lidar", "name": "lidar", "preset": "vlp16", "columns": 900, "rate_hz": 10,
                              "motion_distortion": True, "self_returns": False, "mount": {"position": [0.701, 0.0, 1.6]}},
                             {"type": "odometry", "name": "odometry", "rate_hz": 20}]}],
    "objects": [{"type": "wall", "name": "north", "position": [0, 10, 1], "size": [40, 1, 4]},
                {"type": "wall", "name": "south", "position": [0, -10, 1], "size": [40, 1, 4]},
                {"type": "box", "name": "block", "position": [20, 0, 1], "size": [1, 8, 3]}],
}  # fmt: skip


def test_rclpy_node_drives_the_boat_to_its_goal_over_dds(tmp_path):
    if importlib.util.find_spec("rclpy") is None or importlib.util.find_spec("nav_msgs") is None:
        pytest.skip("ROS 2 wheels not installed (extra ros2-test)")
    if unusable():
        pytest.skip(unusable())
    scenario, record = tmp_path / "drive.yaml", tmp_path / "drive.mcap"
    scenario.write_text(yaml.safe_dump(SCENARIO))
    cmd = isolated(sys.executable, str(HERE / "ros2_drive.py"), str(scenario), "10,1", str(record), "90")
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=240)
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("RESULT ")]
    assert lines, done.stderr[-3000:]
    report = json.loads(lines[-1][7:])
    assert "reached_s" in report, report
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    track = []
    with record.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _, _, _, msg in reader.iter_decoded_messages(topics=["/wamv/ground_truth/odometry"]):
            track.append((msg.pose.pose.position.x, msg.pose.pose.position.y))
    end = np.array(track[-1])
    assert np.hypot(*(end - (10.0, 1.0))) < 2.0  # stopped near the goal (declared within 1 m of its estimate)
