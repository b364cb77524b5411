"""The ROS-TCP bridge against the protocol-exact test endpoint: registration, data, commands, keepalive."""

from __future__ import annotations

import logging
import math
import socket

import pytest
from ros_tcp_endpoint import TestEndpoint, command, frame, wait_for

from usvsim.bridges.ros_tcp import RosTcpBridge
from usvsim.bridges.ros_tcp_profiles import make_profile
from usvsim.config.loader import parse_scenario
from usvsim.messages.ros import msg_class, typestore
from usvsim.simulation import Simulation

SENSORS = [
    {"type": "lidar", "name": "lidar2d", "output": "scan", "channels": 1, "columns": 90, "rate_hz": 10},
    {"type": "lidar", "name": "lidar", "channels": 4, "columns": 90, "rate_hz": 10},
    {"type": "imu", "name": "imu", "rate_hz": 50},
    {"type": "odometry", "name": "odometry", "rate_hz": 50},
    {"type": "gnss", "name": "gps", "rate_hz": 10},
]
FAST = {"reconnect_delay_s": 0.1, "keepalive_s": 0.2}


def make_sim(sensors=SENSORS, vessels=("wamv",)) -> Simulation:
    data = {"version": 1, "vessels": [{"name": n, "model": "wamv", "sensors": list(sensors) if i == 0 else []}
                                      for i, n in enumerate(vessels)]}  # fmt: skip
    return Simulation(parse_scenario(data, "test"))


def cdr(msgtype: str, **fields) -> bytes:
    return bytes(typestore().serialize_cdr(msg_class(msgtype)(**fields), msgtype))


@pytest.fixture
def endpoint():
    ep = TestEndpoint()
    yield ep
    ep.stop()


@pytest.fixture
def connect(endpoint):
    made = []

    def make(sim, **kwargs):
        bridge = RosTcpBridge(sim, "127.0.0.1", endpoint.port, **{**FAST, **kwargs})
        bridge.given = []  # type: ignore[attr-defined]  # subscribed right after the bridge: what it is given
        sim.subscribe(bridge.given.append)  # type: ignore[attr-defined]
        made.append(bridge)
        assert wait_for(lambda: len(endpoint.subscribers) == len(bridge.profile.commands), 3.0)
        return bridge

    yield make
    for bridge in made:
        bridge.close()


def delivered(bridge, endpoint, given) -> bool:
    """Every envelope in `given` (what the simulation gave the bridge) has reached the endpoint as a frame or was
    counted as dropped by the bridge. (`messages_out` alone is no such mark: it counts frames when they join a
    batch, and the next batch may still wait in the queue.)"""
    s = bridge.stats
    dropped = s["dropped"] + s["dropped_refused"] + s["dropped_disconnected"]
    return len(given) > 0 and len(endpoint.received) + len(endpoint.unregistered) + dropped == len(given)


def all_sent(bridge, endpoint):
    return wait_for(lambda: delivered(bridge, endpoint, bridge.given), 30.0)


def test_registers_and_publishes_every_topic_as_decodable_cdr(endpoint, connect):
    sim = make_sim()
    emitted: dict[str, str] = {}
    sim.subscribe(lambda env: emitted.setdefault(env.topic, env.msgtype))
    bridge = connect(sim)
    sim.run(0.5)
    assert all_sent(bridge, endpoint)
    assert endpoint.topics_received() == set(emitted) and not endpoint.unregistered  # registered before data
    for topic, msgtype in emitted.items():
        assert endpoint.publishers[topic]["message_name"] == msgtype.replace("/msg/", "/")
    for topic, payload, _ in endpoint.received:
        assert payload[:4] == b"\x00\x01\x00\x00"
        typestore().deserialize_cdr(payload, emitted[topic])  # raises on a wrong type or broken bytes
    assert endpoint.publishers["/tf_static"] == {
        "message_name": "tf2_msgs/TFMessage",
        "queue_size": 1,
        "latch": True,
    }
    assert {"/wamv/lidar2d/scan", "/wamv/lidar/points", "/wamv/imu/data", "/clock", "/tf"} <= set(emitted)
    assert endpoint.subscribers == {t: m.replace("/msg/", "/") for t, m in sim.commands.topics.items()}
    assert bridge.endpoint_version == ("v0.7.0", "ROS2") and bridge.stats["handshakes"] == 1
    listed = bridge.request_topic_list()
    assert dict(zip(listed["topics"], listed["types"]))["/tf_static"] == "tf2_msgs/TFMessage"


def test_keepalive_every_idle_period(endpoint, connect):
    bridge = connect(make_sim(sensors=()))
    assert wait_for(lambda: endpoint.keepalives >= 4, 3.0)  # one on connect, then one per 0.2 s of silence
    assert bridge.stats["keepalives_out"] >= 4 - 1 and not endpoint.errors  # counted right after sending


def test_commands_from_the_endpoint_move_the_boat(endpoint, connect):
    sim = make_sim(sensors=())
    bridge = connect(sim)
    for name in sim.vessels["wamv"].thrusters:
        endpoint.send_topic(f"/wamv/thrusters/{name}/thrust", cdr("std_msgs/msg/Float64", data=1.0))
    endpoint.send_topic("/wamv/thrusters/rear_left/thrust", b"\x00\x01\x00\x00\x01")  # truncated CDR
    endpoint.send(frame("/not/a/command", cdr("std_msgs/msg/Float64", data=1.0)))
    assert wait_for(lambda: bridge.stats["unknown_topics"] == 1)
    assert bridge.stats["commands_in"] == 4 and bridge.stats["commands_refused"] == 1
    sim.run(0.5)
    assert sim.vessels["wamv"].velocity_body[0] > 0.1
    assert bridge.stats["disconnects"] == 0  # bad messages on a good stream keep the connection


def test_handshake_check_and_endpoint_logs(caplog):
    endpoint = TestEndpoint(version="v0.6.0", protocol="ROS1")
    bridge = RosTcpBridge(make_sim(sensors=()), port=endpoint.port, **FAST)
    try:
        with caplog.at_level(logging.INFO, logger="usvsim.bridges.ros_tcp"):
            assert wait_for(lambda: bridge.stats["handshakes"] == 1)
            endpoint.send(command("__warn", {"text": "QoS mismatch"}) + command("__error", {"text": "boom"}))
            assert wait_for(lambda: bridge.stats["endpoint_logs"] == 2)
        assert bridge.endpoint_version == ("v0.6.0", "ROS1")
        assert "speaks v0.7.x ROS2" in caplog.text and "QoS mismatch" in caplog.text
        assert [r.levelno for r in caplog.records if "boom" in r.getMessage()] == [logging.ERROR]
    finally:
        bridge.close()
        endpoint.stop()


def test_seed_profile_maps_the_seed_names():
    camera = {"type": "camera", "name": "cam", "width": 16, "height": 16, "streams": ["rgb", "depth"]}
    sim = make_sim(sensors=[*SENSORS, camera, {**SENSORS[1], "name": "second"}], vessels=("wamv", "other"))
    profile = make_profile(sim, "seed")
    assert profile.rename == {
        "/clock": "clock", "/wamv/lidar2d/scan": "scan", "/wamv/lidar/points": "points", "/wamv/imu/data": "imu/raw",
        "/wamv/odometry": "odometry", "/wamv/cam/image_raw": "camera/image_raw", "/wamv/cam/camera_info":
        "camera/camera_info", "/wamv/cam/depth/image_raw": "camera/depth"}  # fmt: skip
    assert profile.wire_name("/wamv/second/points") == "/wamv/second/points"  # unmapped: usvsim name
    assert profile.commands["rear_left_thruster/angle"][0] == "std_msgs/msg/Float32"
    assert "/wamv/cmd_vel" in profile.commands and "/other/thrusters/rear_left/thrust" in profile.commands
    assert "/wamv/thrusters/rear_left/thrust" not in profile.commands
    assert make_profile(sim, "seed", vessel="other").rename == {
        "/clock": "clock", "/other/ground_truth/odometry": "odometry"}  # fmt: skip
    with pytest.raises(ValueError, match="no vessel"):
        make_profile(sim, "seed", vessel="nope")
    with pytest.raises(ValueError, match="unknown ROS-TCP profile"):
        make_profile(sim, "unity")


def test_seed_profile_end_to_end(endpoint, connect):
    sim = make_sim()
    bridge = connect(sim, profile="seed")
    endpoint.send_topic(
        "rear_left_thruster/angle", cdr("std_msgs/msg/Float32", data=30.0)
    )  # degrees, clockwise
    endpoint.send_topic("rear_right_thruster/thrust", cdr("std_msgs/msg/Float32", data=2.0))  # clamped to 1
    assert wait_for(lambda: bridge.stats["commands_in"] == 2)
    sim.run(0.5)
    assert sim.vessels["wamv"].thrusters["rear_right"].thrust_n > 100.0  # before the thrust watchdog stops it
    sim.run(1.5)
    assert all_sent(bridge, endpoint)
    assert sim.vessels["wamv"].thrusters["rear_left"].angle_rad == pytest.approx(
        -math.radians(30.0), abs=0.01
    )
    assert {
        "scan",
        "points",
        "imu/raw",
        "odometry",
        "clock",
        "/tf",
        "/wamv/gps/fix",
    } <= endpoint.topics_received()
    assert endpoint.publishers["scan"]["message_name"] == "sensor_msgs/LaserScan"
    assert endpoint.subscribers["front_left_thruster/thrust"] == "std_msgs/Float32"


def test_no_endpoint_drops_counted_and_the_simulation_runs():
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()  # nothing listens there now
    sim = make_sim(sensors=())
    bridge = RosTcpBridge(sim, port=port, queue_limit=8, **FAST)
    try:
        sim.run(1.0)
        assert wait_for(lambda: bridge.stats["connect_failures"] >= 2)
        assert (
            bridge.stats["dropped"] + bridge.stats["dropped_disconnected"] > 50
            and bridge.stats["connects"] == 0
        )
    finally:
        bridge.close()
