"""Foxglove connection limit (the front proxy): one client too many is refused with HTTP 503, a client that
stops reading is dropped once its unsent bytes pass the bound while a normal client keeps receiving."""

from __future__ import annotations

import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from foxglove_client import FoxgloveClient, raw_connect
from foxglove_rig import POINTS, make_bridge, make_sim
from test_foxglove_robustness import channel_ids, subscribe_raw
from websockets.exceptions import InvalidStatus

from usvsim.bridges.foxglove import FoxgloveBridge
from usvsim.bridges.foxglove_proxy import FoxgloveProxy


def wait(predicate, seconds: float = 30.0) -> bool:
    deadline = time.monotonic() + seconds
    while not predicate() and time.monotonic() < deadline:
        time.sleep(0.02)
    return predicate()


def test_one_client_more_than_the_limit_is_refused_and_a_freed_slot_admits_again():
    sim = make_sim(sensors=False)
    bridge = make_bridge(sim, max_clients=2)
    try:
        sim.run(0.05)
        first, second = FoxgloveClient(bridge.url), FoxgloveClient(bridge.url)
        with pytest.raises(InvalidStatus) as refused:
            FoxgloveClient(bridge.url)
        assert refused.value.response.status_code == 503
        # the proxy process reports its counters asynchronously
        assert wait(lambda: bridge.stats["connections_refused"] == 1 and bridge.stats["connections_accepted"] == 2)
        assert second.wait_for(lambda: second.server_info is not None)  # the admitted ones are served
        first.close()
        assert wait(lambda: bridge._proxy.clients == 1)
        third = FoxgloveClient(bridge.url)
        assert third.wait_for(lambda: third.server_info is not None)
        second.close()
        third.close()
    finally:
        bridge.close()
        sim.close()


@pytest.mark.parametrize("bound", [{"max_client_buffer_bytes": 256 << 10}, {"client_stall_s": 0.5}])
def test_a_client_that_never_reads_is_dropped_and_a_reading_client_keeps_receiving(bound):
    sim = make_sim()
    bridge = make_bridge(sim, **bound)
    try:
        sim.run(0.1)
        ids = channel_ids(bridge)
        stalled = raw_connect(bridge.port)  # subscribes to everything (camera images too), never reads a byte
        subscribe_raw(stalled, ids)
        reader = FoxgloveClient(bridge.url)
        assert reader.wait_for(lambda: reader.channel(POINTS) is not None)
        sub = reader.subscribe(POINTS)
        reader.pump(0.05)
        for _ in range(200):  # the kernel's socket buffers take a few MB first; bounded in simulated time
            if bridge.stats["connections_dropped"]:
                break
            sim.run(0.1)
            reader.pump(0.0)
        assert wait(lambda: bridge.stats["connections_dropped"] == 1)
        before = len(reader.messages.get(sub, []))
        sim.run(0.3)
        assert reader.wait_for(lambda: len(reader.messages.get(sub, [])) >= before + 2, seconds=10)
        assert wait(lambda: bridge._proxy.clients == 1)
        reader.close()
        stalled.close()
        assert bridge.stats["errors"] == 0
    finally:
        bridge.close()
        sim.close()


def test_idle_connections_never_take_a_slot_and_are_closed_after_the_handshake_time():
    sim = make_sim(sensors=False)
    bridge = make_bridge(sim, max_clients=1, client_handshake_s=0.5)
    idle = [socket.create_connection(("127.0.0.1", bridge.port), timeout=10) for _ in range(3)]  # say nothing
    try:
        sim.run(0.05)
        client = FoxgloveClient(bridge.url)  # admitted although three connections came first
        assert client.wait_for(lambda: client.server_info is not None)
        for sock in idle:
            assert sock.recv(1) == b""  # closed by the proxy, without a byte
        assert wait(lambda: bridge.stats["connections_dropped"] == 3 and bridge.stats["connections_refused"] == 0)
        client.close()
    finally:
        for sock in idle:
            sock.close()
        bridge.close()
        sim.close()


def test_the_proxy_process_ends_with_the_simulation_process():
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); from foxglove_rig import make_bridge, make_sim;"
        "b = make_bridge(make_sim(sensors=False)); print(b._proxy._child.pid, flush=True); sys.stdin.read()"
    )
    parent = subprocess.Popen([sys.executable, "-c", code, str(Path(__file__).parent)], stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        child = int(parent.stdout.readline())
        parent.kill()  # SIGKILL: no close(), no atexit
        parent.wait()
        assert wait(lambda: not Path(f"/proc/{child}").exists() or "zombie" in _state(child))
    finally:
        parent.kill()


def _state(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/status").read_text().split("State:")[1].split("\n")[0].lower()
    except (OSError, IndexError):
        return "zombie"


def test_a_taken_port_and_bad_limits_are_errors():
    sim = make_sim(sensors=False)
    bridge = make_bridge(sim)
    try:
        with pytest.raises(OSError, match="cannot start the Foxglove server"):
            FoxgloveBridge(sim, port=bridge.port)
        with pytest.raises(ValueError, match="max_clients"):
            FoxgloveProxy("127.0.0.1", 0, bridge.port, max_clients=0)
    finally:
        bridge.close()
        sim.close()
