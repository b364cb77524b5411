"""DDS bridge against a Cyclone DDS reader/writer in this process (loopback-only configuration).

Checks ROS 2 naming, QoS, the type hash, byte-identical CDR, the transient-local late joiner, commands
in (raw CDR through DDS moves the boat), bounded queue accounting and the network-safe configuration.
The independent-stack (rclpy / Fast DDS) acceptance test is test_dds_ros2.py.
"""

from __future__ import annotations

import socket
import time

import numpy as np
import pytest

pytest.importorskip("cyclonedds")

from usvsim.bridges import dds_types
from usvsim.bridges.dds import DdsBridge, _qos
from usvsim.bridges.dds_config import cyclone_config
from usvsim.bridges.dds_domain import socket_fds
from usvsim.messages.envelope import Envelope, QosProfile
from usvsim.messages.ros import clock_msg, msg_class, typestore
from usvsim.simulation import Simulation


@pytest.fixture
def sim(scenario_of):
    scenario = scenario_of({"vessels": [{"name": "wamv", "model": "wamv", "command_timeout_s": 1.0,
                                         "sensors": [{"type": "imu", "name": "imu", "rate_hz": 50}]}]})  # fmt: skip
    return Simulation(scenario)


def _raw_reader(bridge: DdsBridge, topic: str, msgtype: str, profile: QosProfile):
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    dds_topic = Topic(bridge.participant, dds_types.dds_topic_name(topic), dds_types.idl_type(msgtype))
    return DataReader(bridge.participant, dds_topic, qos=_qos(profile, msgtype))


def _take_until(reader, count: int, timeout_s: float = 3.0) -> list[bytes]:
    got, deadline = [], time.monotonic() + timeout_s
    while len(got) < count and time.monotonic() < deadline:
        got += dds_types.take_cdr(reader)
        time.sleep(0.01)
    return got


def test_names_and_types_follow_ros2_conventions():
    assert dds_types.dds_topic_name("/wamv/lidar/points") == "rt/wamv/lidar/points"
    assert dds_types.dds_type_name("sensor_msgs/msg/PointCloud2") == "sensor_msgs::msg::dds_::PointCloud2_"
    image = dds_types.idl_type("sensor_msgs/msg/Image")
    assert image.__idl_typename__ == "sensor_msgs::msg::dds_::Image_"
    assert image.__idl_annotations__["extensibility"] == "final"  # XCDR1, as ROS 2 RMWs expect


def test_idl_types_serialize_like_rosbags():
    """Golden check of the type mapping: cyclonedds' own serializer equals rosbags' CDR for a CameraInfo."""
    store, t = typestore(), dds_types.idl_type
    msg = msg_class("sensor_msgs/msg/CameraInfo")(
        header=msg_class("std_msgs/msg/Header")(stamp=msg_class("builtin_interfaces/msg/Time")(sec=3, nanosec=4),
                                                frame_id="cam_optical"),
        height=480, width=640, distortion_model="plumb_bob", d=np.zeros(5), k=np.ones(9), r=np.full(9, 2.0),
        p=np.full(12, 3.0), binning_x=0, binning_y=0, roi=msg_class("sensor_msgs/msg/RegionOfInterest")(0, 0, 0, 0, False))  # fmt: skip
    sample = t("sensor_msgs/msg/CameraInfo")(
        header=t("std_msgs/msg/Header")(stamp=t("builtin_interfaces/msg/Time")(sec=3, nanosec=4), frame_id="cam_optical"),
        height=480, width=640, distortion_model="plumb_bob", d=[0.0] * 5, k=[1.0] * 9, r=[2.0] * 9, p=[3.0] * 12,
        binning_x=0, binning_y=0, roi=t("sensor_msgs/msg/RegionOfInterest")(0, 0, 0, 0, False))  # fmt: skip
    assert sample.serialize() == bytes(store.serialize_cdr(msg, "sensor_msgs/msg/CameraInfo"))


def test_every_topic_is_published_with_its_cdr_and_qos(sim):
    with DdsBridge(sim) as bridge:
        clock = _raw_reader(bridge, "/clock", "rosgraph_msgs/msg/Clock", QosProfile(depth=100))
        seen: list[Envelope] = []
        sim.subscribe(seen.append)
        time.sleep(0.3)  # reader and writer match within the process
        sim.run(0.2)
        got = _take_until(clock, 20)
        late = _raw_reader(bridge, "/tf_static", "tf2_msgs/msg/TFMessage",
                           QosProfile(durability="transient_local", depth=1))  # fmt: skip
        static = _take_until(late, 1)
        sent = {e.topic: e for e in seen}
        assert set(bridge.topics) == set(sent)  # one writer per emitted topic
        assert bridge.topics["/wamv/imu/data"] == "sensor_msgs/msg/Imu"
        assert len(got) >= 20 and got == [e.cdr for e in seen if e.topic == "/clock"][: len(got)]  # the envelopes' bytes, as they are
        assert static and static[0][: len(sent["/tf_static"].cdr)] == sent["/tf_static"].cdr
        assert bridge.stats["published"] == len(seen) and bridge.stats["write_errors"] == 0


def test_writer_qos_carries_reliability_durability_depth_and_type_hash():
    from cyclonedds.qos import Policy

    qos = _qos(QosProfile(durability="transient_local", depth=1), "tf2_msgs/msg/TFMessage")
    assert qos[Policy.Durability] == Policy.Durability.TransientLocal
    assert qos[Policy.History] == Policy.History.KeepLast(1)
    assert qos[Policy.DataRepresentation].use_cdrv0_representation
    rihs = typestore().hash_rihs01("tf2_msgs/msg/TFMessage")
    assert rihs.startswith("RIHS01_") and qos[Policy.Userdata].data == f"typehash={rihs};".encode()


def test_commands_over_dds_move_the_boat_and_bad_ones_are_counted(sim):
    from cyclonedds.pub import DataWriter
    from cyclonedds.topic import Topic

    with DdsBridge(sim) as bridge:
        writers = {}
        for name in sim.vessels["wamv"].thrusters:
            topic = Topic(bridge.participant, f"rt/wamv/thrusters/{name}/thrust", dds_types.idl_type("std_msgs/msg/Float64"))
            writers[name] = DataWriter(bridge.participant, topic, qos=_qos(QosProfile(), "std_msgs/msg/Float64"))
        time.sleep(0.3)
        one, nan = (bytes(typestore().serialize_cdr(msg_class("std_msgs/msg/Float64")(data=x), "std_msgs/msg/Float64"))
                    for x in (1.0, float("nan")))  # fmt: skip
        for writer in writers.values():
            dds_types.write_cdr(writer, one)
        dds_types.write_cdr(writers["rear_left"], nan)
        deadline = time.monotonic() + 3.0
        while bridge.stats["commands_received"] + bridge.stats["commands_refused"] < 5 and time.monotonic() < deadline:
            time.sleep(0.01)
        sim.run(1.0)
    assert bridge.stats["commands_received"] == 4 and bridge.stats["commands_refused"] == 1
    assert sim.commands.stats["rejected"] == 1
    assert sim.vessels["wamv"].velocity_body[0] > 0.1


def test_a_slow_sender_drops_the_oldest_and_counts_it(sim):
    bridge = DdsBridge(sim, queue_limit=4)
    try:
        bridge._wake.wait = lambda timeout=None: time.sleep(0.5)  # the sender thread stalls
        time.sleep(0.2)
        for i in range(50):
            bridge._on_envelope(Envelope("/clock", i, clock_msg(i)))
        assert len(bridge._queue) == 4 and bridge.stats["dropped"] == 46
        assert bridge._queue[0].stamp_ns == 46  # the newest kept
    finally:
        bridge.close()
    assert sim._subscribers == []


def test_default_configuration_keeps_traffic_on_loopback():
    xml = cyclone_config()
    assert '<NetworkInterface name="lo"/>' in xml and "<AllowMulticast>false</AllowMulticast>" in xml
    assert '<Peer address="127.0.0.1"/>' in xml
    wide = cyclone_config("eth0")
    assert '<NetworkInterface name="eth0"/>' in wide and "AllowMulticast" not in wide and "Peer" not in wide


def test_udp_sockets_of_a_loopback_domain_accept_only_loopback_traffic(sim):
    """Cyclone binds 0.0.0.0 whatever its interface; the bridge binds those sockets to the `lo` device."""
    before = socket_fds()
    with DdsBridge(sim, domain_id=37):  # a domain of its own: its sockets are opened now
        new = [socket.socket(fileno=fd) for fd in sorted(socket_fds() - before)]
        try:
            udp = [s for s in new if s.type == socket.SOCK_DGRAM]
            assert udp and all(s.getsockname()[0] == "127.0.0.1" or _device(s) == "lo" for s in udp)
            assert any(s.getsockname()[0] == "0.0.0.0" for s in udp)  # the wildcard ones were there to pin
        finally:
            for s in new:
                s.detach()


def test_an_interface_given_as_an_address_starts(sim):
    """`--ros2-interface 127.0.0.1` (an address, as the docs allow) was a bare DDS_RETCODE_ERROR traceback: the
    address went into `name=`. Loopback addresses are `lo` (pinned as `lo` is); other addresses go in `address=`."""
    assert '<NetworkInterface name="lo"/>' in cyclone_config("127.0.0.1")
    assert '<NetworkInterface address="192.0.2.7"/>' in cyclone_config("192.0.2.7")  # built, not started: off-host
    before = socket_fds()
    with DdsBridge(sim, domain_id=38, interface="127.0.0.1"):
        new = [socket.socket(fileno=fd) for fd in sorted(socket_fds() - before)]
        try:
            udp = [s for s in new if s.type == socket.SOCK_DGRAM]
            assert udp and all(s.getsockname()[0] == "127.0.0.1" or _device(s) == "lo" for s in udp)
        finally:
            for s in new:
                s.detach()


def test_cli_names_an_unknown_interface_in_one_line():
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    result = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.1", "--ros2", "--ros2-interface", "nosuch0"])
    assert result.exit_code == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "no network interface 'nosuch0'" in lines[0], result.stderr


def _device(sock: socket.socket) -> str:
    return sock.getsockopt(socket.SOL_SOCKET, socket.SO_BINDTODEVICE, 16).rstrip(b"\0").decode()


def test_fast_dds_endpoints_are_matched_by_type_name():
    """Kilted's Fast DDS type information is ignored (Cyclone would reject it for types with fixed arrays);
    test_dds_ros2.py shows a default-settings Kilted peer receiving every type."""
    assert "<IgnoreTypeInformation>1.15</IgnoreTypeInformation>" in cyclone_config()


def test_unknown_cyclonedds_version_fails_clearly(monkeypatch):
    import importlib.metadata

    dds_types.check_raw_api.cache_clear()
    monkeypatch.setattr(importlib.metadata, "version", lambda name: "99.0.0")
    try:
        with pytest.raises(RuntimeError, match="cyclonedds 11.0.x; found 99.0.0"):
            dds_types.check_raw_api()
    finally:
        dds_types.check_raw_api.cache_clear()


def test_writes_go_through_dds_write_with_the_gil_released():
    """The bundled libddsc's dds_write is found (ctypes frees the GIL during the call); a sample written that
    way arrives byte for byte (the round-trip tests above use the same path)."""
    from usvsim.bridges import dds_types

    assert dds_types._dds_write() is not None


def test_best_effort_publishers_drive_the_streaming_command_topics(sim):
    """A best-effort publisher (rclpy's qos_profile_sensor_data, `ros2 topic pub --qos-reliability best_effort`)
    of cmd_vel or thrust matched no command reader (they were all reliable, a request a best-effort writer cannot
    meet): its commands were lost without a word on either side (QA, rclpy peer: 0 matched subscriptions)."""
    from cyclonedds.pub import DataWriter
    from cyclonedds.topic import Topic

    best_effort = QosProfile(reliability="best_effort")
    float64, twist = "std_msgs/msg/Float64", "geometry_msgs/msg/Twist"
    with DdsBridge(sim) as bridge:
        thrust_name = "rt/wamv/thrusters/rear_left/thrust"
        thrust_topic = Topic(bridge.participant, thrust_name, dds_types.idl_type(float64))
        thrust = DataWriter(bridge.participant, thrust_topic, qos=_qos(best_effort, float64))
        cmd_topic = Topic(bridge.participant, "rt/wamv/cmd_vel", dds_types.idl_type(twist))
        cmd_vel = DataWriter(bridge.participant, cmd_topic, qos=_qos(best_effort, twist))
        time.sleep(0.3)
        half = bytes(typestore().serialize_cdr(msg_class(float64)(data=0.5), float64))
        forward = msg_class(twist)(linear=msg_class("geometry_msgs/msg/Vector3")(x=1.0, y=0.0, z=0.0),
                                   angular=msg_class("geometry_msgs/msg/Vector3")(x=0.0, y=0.0, z=0.0))  # fmt: skip
        dds_types.write_cdr(thrust, half)
        dds_types.write_cdr(cmd_vel, bytes(typestore().serialize_cdr(forward, twist)))
        deadline = time.monotonic() + 3.0
        while bridge.stats["commands_received"] < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
    assert bridge.stats["commands_received"] == 2 and bridge.stats["commands_refused"] == 0
