"""Foxglove bridge under abuse: stalled subscribers, clients killed mid-stream, reconnects and garbage never stop
the simulation or slow it for long, and the server keeps serving well-behaved clients."""

from __future__ import annotations

import json
import socket
import time

import pytest
from foxglove_client import FoxgloveClient, raw_connect, reset, send_frame
from foxglove_rig import IMAGE, POINTS, make_bridge, make_sim

from usvsim.bridges.foxglove import SCENE_TOPIC, WATER_TOPIC

ALL = [POINTS, IMAGE, SCENE_TOPIC, WATER_TOPIC, "/tf", "/tf_static", "/clock", "/wamv/ground_truth/odometry"]


@pytest.fixture(scope="module")
def served():
    sim = make_sim()
    bridge = make_bridge(sim, backlog=16)
    sim.run(0.25)
    yield sim, bridge
    bridge.close()
    sim.close()


def channel_ids(bridge) -> dict[str, int]:
    c = FoxgloveClient(bridge.url)
    assert c.wait_for(lambda: all(c.channel(t) for t in ALL))
    ids = {t: c.channel(t)["id"] for t in ALL}
    c.close()
    return ids


def subscribe_raw(sock, ids) -> None:
    subs = [{"id": k + 1, "channelId": cid} for k, cid in enumerate(ids.values())]
    send_frame(sock, json.dumps({"op": "subscribe", "subscriptions": subs}).encode())


def wall(sim, seconds: float) -> float:
    t = time.perf_counter()
    sim.run(seconds)
    return time.perf_counter() - t


def assert_still_serving(sim, bridge) -> None:
    c = FoxgloveClient(bridge.url)
    try:
        assert c.wait_for(lambda: c.channel(POINTS) is not None)
        sub = c.subscribe(POINTS)
        c.pump(0.05)
        sim.run(0.3)
        assert c.wait_for(lambda: len(c.messages.get(sub, [])) >= 2, seconds=3)
    finally:
        c.close()
    assert bridge.stats["errors"] == 0


def test_stalled_subscribers_do_not_slow_the_simulation(served):
    sim, bridge = served
    ids = channel_ids(bridge)
    wall(sim, 0.1)  # warm
    baseline = min(wall(sim, 0.4) for _ in range(2))  # bridge on, nobody subscribed
    stalled = [raw_connect(bridge.port) for _ in range(3)]  # subscribe to everything, never read a byte
    for sock in stalled:
        subscribe_raw(sock, ids)
    time.sleep(0.1)
    loaded = min(wall(sim, 0.4) for _ in range(3))
    for sock in stalled:
        reset(sock)
    # the stalled clients cost what any subscriber costs (the scene, the time), not a wait: generous on 2 shared cores
    assert loaded < 3.0 * baseline + 0.2, (loaded, baseline)
    assert_still_serving(sim, bridge)


def test_clients_killed_mid_stream_and_reconnecting(served):
    sim, bridge = served
    ids = channel_ids(bridge)
    steps = sim.clock.steps
    for _ in range(4):
        c = FoxgloveClient(bridge.url)
        c.wait_for(lambda c=c: c.channel(POINTS) is not None)
        for topic in (POINTS, IMAGE, WATER_TOPIC):
            c.subscribe(topic)
        sim.run(0.1)
        reset(c.ws.socket)  # killed: no close frame
        sock = raw_connect(bridge.port)
        subscribe_raw(sock, ids)
        sim.run(0.05)
        reset(sock)
    half = socket.create_connection(("127.0.0.1", bridge.port))
    half.sendall(b"GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\n")  # dies mid-handshake
    reset(half)
    sim.run(0.1)
    assert sim.clock.steps == steps + 4 * 15 + 10
    assert_still_serving(sim, bridge)


GARBAGE_TEXT = [b"garbage{", b"{}", b'{"op": "subscribe"}', b'{"op": "subscribe", "subscriptions": [{"id": 1, "channelId": 999999}]}',
                b'{"op": "unsubscribe", "subscriptionIds": [42]}', b'{"op": "advertise", "channels": [{"id": "x"}]}',
                b'{"op": "advertise", "channels": [{"id": 5, "topic": "/wamv/cmd_vel", "encoding": "cdr", "schemaName": "x"}]}']  # fmt: skip
GARBAGE_BINARY = [b"\xff\xff", b"\x01", b"\x01\x05\x00\x00\x00" + b"\x00" * 3, b"\x01\x05\x00\x00\x00" + bytes(range(256)) * 40,
                  b"\x02\x00\x00\x00", b""]  # fmt: skip


def test_garbage_is_refused_and_the_simulation_goes_on(served):
    sim, bridge = served
    refused = bridge.stats["client_refused"]
    raw_tcp = socket.create_connection(("127.0.0.1", bridge.port))
    raw_tcp.sendall(bytes(range(256)) * 16)  # not even HTTP
    sock = raw_connect(bridge.port)
    for payload in GARBAGE_TEXT:
        send_frame(sock, payload, opcode=0x1)
    for payload in GARBAGE_BINARY:
        send_frame(sock, payload, opcode=0x2)
    send_frame(sock, b"\xff\xfe not utf-8", opcode=0x1)  # a protocol error: the server drops this client
    steps = sim.clock.steps
    sim.run(0.2)
    assert sim.clock.steps == steps + 20
    deadline = time.monotonic() + 3
    while bridge.stats["client_refused"] < refused + 9 and time.monotonic() < deadline:
        time.sleep(0.02)
    for s in (raw_tcp, sock):
        reset(s)
    # the two garbage commands on /wamv/cmd_vel, and the 7 frames the SDK refuses as invalid (bad JSON, no "op",
    # no "subscriptions", a string channel id, opcode 255, two binary frames too short), counted; not counted: the
    # subscribe to an unknown channel and unsubscribe of an unknown id (answered with a status), the empty frame
    assert bridge.stats["client_refused"] == refused + 9
    assert sim.commands.stats["malformed"] > 0
    assert_still_serving(sim, bridge)
