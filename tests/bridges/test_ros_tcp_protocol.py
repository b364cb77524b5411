"""ROS-TCP framing against the byte examples of ros2-interop.md §1.2, and the test endpoint's quirks."""

from __future__ import annotations

import json
import socket

import pytest
from ros_tcp_endpoint import TestEndpoint, wait_for

from usvsim.bridges.ros_tcp_protocol import (
    KEEPALIVE,
    FrameReader,
    ProtocolError,
    client_command_frame,
    client_topic_frame,
    endpoint_message_name,
    handshake_frame,
    parse_handshake,
    parse_json,
    publish_command,
    subscribe_command,
)
from usvsim.messages.ros import msg_class, typestore

IMU_JSON = b'{"topic":"/usv/imu","message_name":"sensor_msgs/Imu","queue_size":10,"latch":false}'


def test_publish_command_golden_bytes():
    frame = publish_command("/usv/imu", "sensor_msgs/msg/Imu", 10, False)
    head = bytes.fromhex("0a000000 5f5f7075626c69736800 54000000")  # len 10 incl. NUL, "__publish\0", len 84
    assert frame == head + IMU_JSON + b"\x00"
    assert frame[len(head) :].hex().startswith("7b22746f706963223a222f7573762f696d75222c")
    assert frame.hex().endswith("7d00")  # "}" then the NUL the endpoint chops off


def test_topic_frame_golden_bytes():
    cdr = bytes(
        typestore().serialize_cdr(msg_class("std_msgs/msg/String")(data="hello"), "std_msgs/msg/String")
    )
    expected = bytes.fromhex("09000000 2f6368617474657200 0e000000 00010000 06000000 68656c6c6f00")
    assert client_topic_frame("/chatter", cdr) == expected


def test_handshake_and_keepalive_golden_bytes():
    body = b'{"version": "v0.7.0", "metadata": "{\\"protocol\\": \\"ROS2\\"}"}'
    assert handshake_frame() == bytes.fromhex("0b000000") + b"__handshake" + bytes.fromhex("3d000000") + body
    assert KEEPALIVE == bytes.fromhex("00000000 00000000")
    assert parse_handshake(json.loads(body)) == ("v0.7.0", "ROS2")


def test_names_commands_and_json():
    assert endpoint_message_name("sensor_msgs/msg/PointCloud2") == "sensor_msgs/PointCloud2"
    sub = subscribe_command("/wamv/cmd_vel", "geometry_msgs/msg/Twist")
    assert sub.startswith(bytes.fromhex("0c000000") + b"__subscribe\x00")
    assert sub.endswith(b'{"topic":"/wamv/cmd_vel","message_name":"geometry_msgs/Twist"}\x00')
    assert client_command_frame("__topic_list", {}) == bytes.fromhex("0d000000") + b"__topic_list\x00" + \
        bytes.fromhex("03000000") + b"{}\x00"  # fmt: skip
    assert parse_json(b'{"a":1}\x00', drop_last=True) == {"a": 1}
    with pytest.raises(ProtocolError):
        parse_json(b'{"a":1}', drop_last=True)  # a client without the NUL loses its "}"
    with pytest.raises(ProtocolError):
        parse_json(b"[1, 2]")


def test_reader_reassembles_frames_fed_byte_by_byte():
    parts = [handshake_frame(), KEEPALIVE, client_topic_frame("/x", b"\x00\x01\x00\x00abcd")]
    data, ends = b"".join(parts), {len(parts[0]), len(parts[0]) + 8, sum(map(len, parts))}
    reader, frames = FrameReader(), []
    for i in range(len(data)):
        frames += reader.feed(data[i : i + 1])
        assert reader.partial == (i + 1 not in ends)
    assert [f[0] for f in frames] == ["__handshake", "", "/x"]  # the NUL of "/x\0" is stripped
    assert frames[2][1] == b"\x00\x01\x00\x00abcd"


@pytest.mark.parametrize(
    "garbage",
    [
        b"\xff\xff\xff\xff",
        b"\x03\x00\x00\x00abc\xff\xff\xff\xff",
        b"\x02\x00\x00\x00\xff\xfe\x00\x00\x00\x00",
    ],
    ids=["huge-name", "huge-payload", "not-utf8"],
)
def test_reader_rejects_broken_streams(garbage):
    with pytest.raises(ProtocolError):
        FrameReader().feed(garbage)


def _connect(endpoint):
    sock = socket.create_connection(("127.0.0.1", endpoint.port), timeout=2.0)
    reader, frames = FrameReader(), []
    while not frames:
        frames = reader.feed(sock.recv(4096))
    assert frames[0] == ("__handshake", handshake_frame()[4 + 11 + 4 :])  # the first frame, byte for byte
    return sock


def test_test_endpoint_drops_the_last_json_character_like_the_real_one():
    endpoint = TestEndpoint()
    try:
        good = _connect(endpoint)
        good.sendall(
            KEEPALIVE
            + publish_command("/a", "std_msgs/msg/String")
            + client_topic_frame("/a", b"\x00\x01\x00\x00")
        )
        assert wait_for(lambda: endpoint.received)
        assert endpoint.publishers["/a"]["message_name"] == "std_msgs/String" and endpoint.keepalives == 1
        bad = _connect(endpoint)
        body = json.dumps({"topic": "/b", "message_name": "std_msgs/String"}).encode()  # no trailing NUL
        bad.sendall(bytes.fromhex("0a000000") + b"__publish\x00" + len(body).to_bytes(4, "little") + body)
        assert wait_for(lambda: endpoint.errors)
        assert "JSONDecodeError" in endpoint.errors[0] and "/b" not in endpoint.publishers
        assert bad.recv(100) == b""  # the endpoint closed that connection
        good.close()
        bad.close()
    finally:
        endpoint.stop()
