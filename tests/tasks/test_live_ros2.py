"""A task live over real DDS between processes: an external stack (vrx_peer.py, its own Cyclone participant
with hand-written IDL types, loopback only, multicast off) reads /clock and /vrx/task/info, drives the boat
with VRX's thruster topics and reports perception objects as geographic_msgs/GeoPoseStamped; the simulation
runs the perception task in external mode (no built-in solution) and its score reflects the reports."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pymap3d
import pytest

pytest.importorskip("cyclonedds")

from usvsim.messages.ros import msg_class
from usvsim.simulation import Simulation
from usvsim.tasks import TaskTiming
from usvsim.tasks.library import Perception
from usvsim.tasks.live import run_live
from usvsim.tasks.ros_inputs import register_task_inputs

HERE = Path(__file__).parent
THRUST_N = 200.0


class QuickPerception(Perception):
    """VRX's practice objects, shown for 2 s each one after another (VRX: 5 s each, 10 s apart)."""

    schedule = [(1.0, "mb_marker_buoy_red", (7.8, 2.1), "red"), (3.5, "mb_marker_buoy_green", (8.3, 0.1), "green"),
                (6.0, "mb_marker_buoy_white", (4.9, -2.32), "white")]  # fmt: skip
    duration_s = 2.0


def _lat_lon(sim, x, y):
    o = sim.scenario.world.origin
    lat, lon, _ = pymap3d.enu2geodetic(x, y, 0.0, o.latitude_deg, o.longitude_deg, o.altitude_m)
    return float(lat), float(lon)


def test_an_external_stack_over_dds_drives_the_boat_and_is_scored(tmp_path):
    domain = 150 + os.getpid() % 80  # apart from the other DDS tests running on this machine
    task = QuickPerception(0, 0, TaskTiming(ready_s=0.5, running_s=10.5))  # 2 s of thrust after the last report
    seen: dict = {}

    def start_peer(sim):
        seen["sim"], seen["start_x"] = sim, float(sim.vessels["wamv"].position[0])
        objects = [[k, 0.5 + t0, task.duration_s, *_lat_lon(sim, *xy)] for t0, k, xy, _ in task.schedule]
        cmd = [sys.executable, str(HERE / "vrx_peer.py"), str(domain), json.dumps(objects), str(THRUST_N)]
        seen["peer"] = peer = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert peer.stdout.readline().strip() == "READY", peer.stderr.read()[-2000:]

    from usvsim.bridges.dds import DdsBridge

    report = run_live(task, bridges=lambda sim: [DdsBridge(sim, domain_id=domain)], external=True,
                      landmark_type="geopose", on_ready=start_peer, record=tmp_path / "live.mcap")  # fmt: skip
    out, err = seen["peer"].communicate(timeout=60)
    lines = [ln for ln in out.splitlines() if ln.startswith("RESULT ")]
    assert lines, err[-2000:]
    peer = json.loads(lines[-1][len("RESULT ") :])
    # the stack read the task's VRX topics
    assert {"name", "state", "score", "elapsed_time", "remaining_time", "num_collisions"} <= set(peer["infos"][-1])
    assert peer["infos"][-1]["name"] == "perception" and "running" in {i["state"] for i in peer["infos"]}
    # its reports were scored: every object matched (error capped at 2 m, 10 m when never matched)
    assert peer["reported"] == sorted(k for _, k, _, _ in task.schedule)
    errors = report["details"]["errors_m"]
    assert all(e < 1.0 for e in errors.values()), errors
    assert report["score"] == pytest.approx(sum(errors.values()) / 3) and report["score"] < 1.0
    assert report["commands"]["rejected"] >= 1  # the NaN report: counted, not scored
    # its VRX thrust (N, once the objects were reported) moved the boat ahead
    assert seen["sim"].vessels["wamv"].position[0] - seen["start_x"] > 1.0
    # the recording holds the task topics too (read by the mcap library, not usvsim)
    from mcap.reader import make_reader

    with open(tmp_path / "live.mcap", "rb") as f:
        schemas = {c.topic: s.name for s, c, _ in make_reader(f).iter_messages()}
    assert schemas["/vrx/task/info"] == "ros_gz_interfaces/msg/ParamVec" and "/clock" in schemas


def test_landmark_as_pose_stamped_and_vrx_thrust_in_newtons():
    """VRX on Gazebo Sim's landmark type (PoseStamped, lat/lon in position.x/.y), in-process."""
    task = QuickPerception(0, 0, TaskTiming(running_s=7.0))
    sim = Simulation(task.scenario())
    try:
        register_task_inputs(sim, task, "pose")
        task.bind(sim)
        lat, lon = _lat_lon(sim, 7.9, 2.0)
        pose = msg_class("geometry_msgs/msg/Pose")(position=msg_class("geometry_msgs/msg/Point")(x=lat, y=lon, z=0.0),
                                                   orientation=msg_class("geometry_msgs/msg/Quaternion")(0.0, 0.0, 0.0, 1.0))  # fmt: skip
        report = msg_class("geometry_msgs/msg/PoseStamped")(
            header=msg_class("std_msgs/msg/Header")(stamp=msg_class("builtin_interfaces/msg/Time")(0, 0),
                                                    frame_id="mb_marker_buoy_red"), pose=pose)  # fmt: skip
        full = msg_class("std_msgs/msg/Float64")(data=1e6)  # clamped to the thruster's maximum
        while sim.time < 1.5:
            sim.step()
            task.update()
        assert sim.commands.post("/vrx/perception/landmark", report)
        assert sim.commands.post("/wamv/thrusters/left/thrust", full)
        sim.step()
        task.update()
        obj = task.scorer.objects[0]
        assert obj.error_m == pytest.approx(((7.9 - obj.x_m) ** 2 + (2.0 - obj.y_m) ** 2) ** 0.5, abs=1e-6)
        assert sim.thrusters.cmd_u[sim.vessels["wamv"].thrusters["rear_left"]._i] == pytest.approx(1.0)
    finally:
        sim.close()
