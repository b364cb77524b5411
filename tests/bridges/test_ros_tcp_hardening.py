"""ROS-TCP bridge against hostile or incomplete endpoints: deep JSON, refused topics, shutdown drain."""

from __future__ import annotations

from ros_tcp_endpoint import TestEndpoint, frame, wait_for
from test_ros_tcp import FAST, delivered, make_sim

from usvsim.bridges.ros_tcp import RosTcpBridge


def test_deep_json_frame_is_a_protocol_error_and_the_bridge_reconnects():
    sim, endpoint = make_sim(sensors=()), TestEndpoint()
    bridge = RosTcpBridge(sim, port=endpoint.port, **FAST)
    try:
        assert wait_for(lambda: bridge.connected.is_set(), 10.0)
        endpoint.send(frame("__log", b'{"text": ' + b"[" * 200_000 + b"]" * 200_000 + b"}"))
        assert wait_for(lambda: bridge.stats["protocol_errors"] == 1, 30.0), bridge.stats
        assert wait_for(lambda: endpoint.connections == 2 and bridge.connected.is_set(), 30.0)  # ~0.1 s unloaded
        sim.run(0.05)
        assert wait_for(lambda: "/clock" in endpoint.topics_received(), 30.0)
    finally:
        bridge.close()
        endpoint.stop()


def test_refused_topic_is_no_longer_sent_and_the_last_step_is_drained_at_close():
    sim, endpoint = make_sim(sensors=()), TestEndpoint(refuse={"/tf"})
    emitted = []
    sim.subscribe(lambda env: emitted.append(env.topic))
    bridge = RosTcpBridge(sim, port=endpoint.port, **FAST, drain_s=30.0)  # the drain ends at the endpoint's EOF
    try:
        assert wait_for(lambda: bridge.connected.is_set(), 10.0)
        sim.run(0.5)
        assert wait_for(lambda: "/tf" in bridge._refused, 10.0)
        assert wait_for(lambda: delivered(bridge, endpoint, emitted), 30.0)  # frames sent before the refusal
        refused_frames = endpoint.unregistered.count("/tf")
        sim.run(1.0)
        assert wait_for(lambda: delivered(bridge, endpoint, emitted), 30.0)
        assert bridge.stats["dropped_refused"] >= 40  # /tf at 50 Hz, no longer sent
        assert endpoint.unregistered.count("/tf") == refused_frames
    finally:
        bridge.close()  # sends what is queued, half-closes and waits for the endpoint's EOF
        endpoint.stop()
    assert [t for t, _, _ in endpoint.received].count("/clock") == emitted.count("/clock")
