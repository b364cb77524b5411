"""The ROS-TCP bridge survives endpoint restarts, garbage and stalls without holding up the simulation."""

from __future__ import annotations

import threading
import time

import pytest
from ros_tcp_endpoint import TestEndpoint, command, frame, wait_for
from test_ros_tcp import FAST, make_sim

from usvsim.bridges.ros_tcp import RosTcpBridge
from usvsim.messages.envelope import Envelope


class Stepper:
    """Steps the simulation in a thread as fast as it can; records each step's wall time."""

    def __init__(self, sim):
        self.sim, self.times, self._stop = sim, [], threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def _loop(self):
        while not self._stop.is_set():
            t0 = time.perf_counter()
            self.sim.step()
            self.times.append((t0, time.perf_counter() - t0))

    def rate(self, seconds: float) -> float:
        """Steps per second over the next `seconds`."""
        n0 = len(self.times)
        time.sleep(seconds)
        return (len(self.times) - n0) / seconds

    def stop(self, since: float) -> float:
        """Stop; the longest single step (s) that started after `since` (perf_counter)."""
        self._stop.set()
        self._thread.join()
        return max(dt for t0, dt in self.times if t0 >= since)


def test_endpoint_restart_reconnects_reregisters_and_the_sim_keeps_its_speed():
    sim = make_sim()
    first = TestEndpoint()
    bridge = RosTcpBridge(sim, port=first.port, **FAST)
    stepper = Stepper(sim)
    second, warm = None, time.perf_counter()
    try:
        assert wait_for(lambda: "/wamv/lidar/points" in first.topics_received(), 5.0)
        warm = time.perf_counter()  # the first steps build ray scenes and compile kernels
        connected_rate = stepper.rate(0.5)
        first.stop()  # the endpoint process dies
        assert wait_for(lambda: not bridge.connected.is_set())
        outage_rate = stepper.rate(0.5)
        second = TestEndpoint(port=first.port)
        assert wait_for(lambda: set(first.publishers) <= second.topics_received(), 5.0)
        assert "/tf_static" in second.topics_received()  # emitted once by the simulation: the latched re-send
        assert second.subscribers == first.subscribers and len(second.subscribers) == len(sim.commands.topics)
        assert second.registrations[: len(first.publishers)] == list(
            first.publishers
        )  # all re-sent on connect
        assert not second.unregistered and bridge.stats["connects"] == 2
        assert bridge.stats["dropped_disconnected"] > 0
    finally:
        longest = stepper.stop(since=warm)
        bridge.close()
        first.stop()
        if second:
            second.stop()
    assert outage_rate > 0.3 * connected_rate  # noisy shared machine: a loose bound, the point is "no stall"
    assert longest < 0.5  # a step blocked on the network would take the 2 s connect or 5 s write timeout


@pytest.mark.parametrize(
    "garbage",
    [
        b"\xff\xff\xff\xff" + b"x" * 16,  # a huge destination length
        b"\x01\x00\x00\x00a\xf0\xff\xff\x7f",  # a 2 GB payload length
        frame("__log", b"{this is not json"),
        b"\x02\x00\x00\x00\xff\xfe\x02\x00\x00\x00{}",  # a destination that is not UTF-8
        b"\x05\x00\x00\x00ab",  # a frame that never completes (read timeout)
    ],
    ids=["huge-name", "huge-payload", "bad-json", "not-utf8", "stalled"],
)
def test_garbage_is_counted_the_bridge_reconnects_and_the_sim_runs(garbage):
    sim = make_sim(sensors=())
    endpoint = TestEndpoint()
    bridge = RosTcpBridge(sim, port=endpoint.port, read_timeout_s=0.3, **FAST)
    try:
        assert wait_for(lambda: bridge.stats["handshakes"] == 1)
        endpoint.send(garbage)
        t0 = time.perf_counter()
        sim.run(0.5)
        assert time.perf_counter() - t0 < 2.0
        assert wait_for(lambda: bridge.stats["protocol_errors"] == 1 and bridge.stats["handshakes"] == 2, 3.0)
        assert endpoint.connections == 2 and bridge.stats["connects"] == 2
        endpoint.send(command("__log", {"text": "still talking"}))
        assert wait_for(lambda: bridge.stats["endpoint_logs"] == 1)
    finally:
        bridge.close()
        endpoint.stop()


def test_a_stalled_endpoint_never_blocks_the_step_loop():
    sim = make_sim(sensors=())
    endpoint = TestEndpoint()
    bridge = RosTcpBridge(sim, port=endpoint.port, queue_limit=16, write_timeout_s=1.0, **FAST)
    try:
        assert wait_for(lambda: bridge.stats["handshakes"] == 1)
        endpoint.reading.clear()  # the endpoint stops reading: TCP buffers fill up, then sends stall
        blob, worst, deadline = b"\x00\x01\x00\x00" + bytes(4 << 20), 0.0, time.monotonic() + 10.0
        while bridge.stats["disconnects"] == 0 and time.monotonic() < deadline:
            env = Envelope("/big", sim.clock_ns, msgtype="std_msgs/msg/ByteMultiArray", cdr=blob)
            t0 = time.perf_counter()
            bridge._on_envelope(env)  # what the simulation calls for every message, here 4 MB ones
            sim.step()  # and its own messages
            worst = max(worst, time.perf_counter() - t0)
            time.sleep(0.005)
        assert bridge.stats["disconnects"] == 1  # the write timeout gave up on the stalled connection
        assert bridge.stats["dropped"] > 0  # while the I/O thread was stuck, the queue dropped the oldest
        assert worst < 0.3  # scheduling noise on a loaded machine, never the 1 s write timeout
        endpoint.reading.set()
        assert wait_for(lambda: bridge.stats["connects"] >= 2 and bridge.connected.is_set(), 5.0)
    finally:
        endpoint.reading.set()
        bridge.close()
        endpoint.stop()
