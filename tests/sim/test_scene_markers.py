"""The scene as visualization_msgs/MarkerArray (scene_markers.py): what RViz and Foxglove draw from ROS 2 topics and
recordings. Checked against the scenario's own numbers and the bodies' poses, and read back from an MCAP file by
mcap_ros2 (an independent reader)."""

from __future__ import annotations

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from usvsim.config.loader import ScenarioError
from usvsim.messages.ros import time_to_ns
from usvsim.simulation import Simulation

DOCK = {"type": "dock", "name": "dock", "position": [30.0, 2.0, -1.0], "size": [2.0, 16.0, 3.0]}
BUOYS = [{"type": "buoy", "name": "red_1", "position": [10.0, -5.0, 0.0], "color": "red"},
         {"type": "buoy", "name": "green_1", "position": [10.0, 5.0, 0.0], "color": "green"}]  # fmt: skip


def _scenario(scenario_of, markers=None, rate=100):
    data = {"world": {"physics_rate_hz": rate}, "vessels": [{"name": "wamv", "model": "wamv"}],
            "objects": [DOCK, *BUOYS]}  # fmt: skip
    if markers is not None:
        data["outputs"] = {"markers": markers}
    return scenario_of(data)


def _collect(sim, seconds):
    got = []
    sim.subscribe(got.append)
    sim.run(seconds)
    return got


def test_vessels_obstacles_and_buoys_are_drawn_where_they_are(scenario_of):
    sim = Simulation(_scenario(scenario_of))
    got = _collect(sim, 0.35)
    static = [e for e in got if e.topic == "/usvsim/markers"]
    assert len(static) == 1 and static[0].qos.durability == "transient_local" and static[0].stamp_ns == 0
    markers = static[0].msg.markers
    m = markers[0].__class__
    vessel = [k for k in markers if k.ns == "vessel/wamv"]
    visuals = sim.vessels["wamv"].model.visuals
    assert len(vessel) == len(visuals) and all(k.header.frame_id == "wamv/base_link" and k.frame_locked for k in vessel)
    for marker, part in zip(vessel, visuals):
        if part.kind == "mesh":  # three points per face, in the part's frame (placed by the marker's pose)
            assert marker.type == m.TRIANGLE_LIST and len(marker.points) == 3 * len(part.mesh.faces)
            first = part.mesh.vertices[part.mesh.faces[0]]
            np.testing.assert_array_equal([[p.x, p.y, p.z] for p in marker.points[:3]], first)
        else:
            assert marker.type == m.CUBE and [marker.scale.x, marker.scale.y, marker.scale.z] == pytest.approx(
                2 * np.array(part.size))
        assert [marker.pose.position.x, marker.pose.position.y, marker.pose.position.z] == pytest.approx(part.pos)
    dock = [k for k in markers if k.ns == "obstacles" and k.type == m.CUBE
            and [k.scale.x, k.scale.y, k.scale.z] == pytest.approx(DOCK["size"])]  # fmt: skip
    assert len(dock) == 1 and dock[0].header.frame_id == "world"
    centre = [dock[0].pose.position.x, dock[0].pose.position.y, dock[0].pose.position.z]
    assert centre == pytest.approx(DOCK["position"])  # the box's centre
    bodies = [e for e in got if e.topic == "/usvsim/markers/bodies"]
    assert [e.stamp_ns for e in bodies] == [0, 100_000_000, 200_000_000, 300_000_000]  # 10 Hz by default
    last = bodies[-1].msg.markers
    assert sorted(k.ns for k in last) == ["body/green_1", "body/red_1"]
    for k in last:  # the 0.3 s sample: spheres in world
        assert k.type == m.SPHERE and k.header.frame_id == "world" and time_to_ns(k.header.stamp) == 300_000_000


def test_buoy_markers_follow_the_buoys(scenario_of):
    from scipy.spatial.transform import Rotation

    sim = Simulation(_scenario(scenario_of, {"bodies_rate_hz": 20}))
    got, checked, start = [], 0, sim.bodies["red_1"].position.copy()
    sim.subscribe(got.append)
    sim.vessels["wamv"].teleport({"position": [10.0, -5.0, 0.0]})  # onto red_1: the contact pushes it away
    for _ in range(100):
        sim.step()
        for env in got:
            if env.topic == "/usvsim/markers/bodies" and env.stamp_ns == sim.clock_ns:
                red = next(k for k in env.msg.markers if k.ns == "body/red_1")
                body = sim.bodies["red_1"]
                w, x, y, z = body.quat
                want = body.position + Rotation.from_quat([x, y, z, w]).apply(body.model.visuals[0].pos)
                assert [red.pose.position.x, red.pose.position.y, red.pose.position.z] == pytest.approx(want, abs=1e-12)
                checked += 1
        got.clear()
    assert checked == 20 and np.linalg.norm(sim.bodies["red_1"].position - start) > 0.05  # it moved


def test_late_subscribers_and_new_episodes_get_the_latched_scene(scenario_of):
    sim = Simulation(_scenario(scenario_of))
    sim.run(0.5)
    got = _collect(sim, 0.1)
    assert [e.topic for e in got].count("/usvsim/markers") == 1
    got.clear()
    sim.reset()
    sim.run(0.1)
    assert [e.topic for e in got].count("/usvsim/markers") == 1


def test_markers_can_be_turned_off_and_bad_rates_are_named(scenario_of):
    got = _collect(Simulation(_scenario(scenario_of, {"scene": False, "bodies_rate_hz": 0})), 0.3)
    assert not [e for e in got if e.topic.startswith("/usvsim/markers")]
    got = _collect(Simulation(_scenario(scenario_of, rate=40)), 0.3)  # default: 10 Hz, 4 steps of 25 ms
    assert len([e for e in got if e.topic == "/usvsim/markers/bodies"]) == 4
    with pytest.raises(ScenarioError, match=r"outputs\.markers\.bodies_rate_hz.*not a whole multiple"):
        _scenario(scenario_of, {"bodies_rate_hz": 30}, rate=100)


def test_a_recording_holds_the_scene_for_foxglove_and_ros2_bag(scenario_of, tmp_path):
    sim = Simulation(_scenario(scenario_of))
    path = tmp_path / "run.mcap"
    with sim.record(path):
        sim.run(0.5)
    with open(path, "rb") as f:
        seen = {}
        for _, channel, _, decoded in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages(
                topics=["/usvsim/markers", "/usvsim/markers/bodies"]):  # fmt: skip
            seen.setdefault(channel.topic, []).append(decoded)
    assert len(seen["/usvsim/markers"]) == 1 and len(seen["/usvsim/markers/bodies"]) == 6
    namespaces = {k.ns for k in seen["/usvsim/markers"][0].markers}
    assert namespaces == {"vessel/wamv", "obstacles"}


def test_kinematic_traffic_ships_are_drawn_where_they_sail(scenario_of):
    """A traffic ship without `vessel` is world geoms moved by the traffic kernel: no body, no TF frame. It was in
    neither array (an Imazu recording drew only the own ship); now its hull and superstructure are in
    /usvsim/markers/bodies at its pose: the hull's world bounds are the ship's 25 m x 6.25 m about its track
    point, which sails the closed form position + speed t (sin course, cos course)."""
    from scipy.spatial.transform import Rotation

    ship = {"name": "cargo", "mmsi": 257000001, "length_m": 25.0, "beam_m": 6.25,
            "motion": {"type": "constant", "position": [100.0, 20.0], "course_deg": 270.0, "speed_mps": 2.0}}  # fmt: skip
    sim = Simulation(scenario_of({"vessels": [{"name": "wamv", "model": "wamv"}], "traffic": {"ships": [ship]}}))
    got = [e for e in _collect(sim, 3.0) if e.topic == "/usvsim/markers/bodies"]
    assert got and got[-1].stamp_ns == 3_000_000_000
    markers = [m for m in got[-1].msg.markers if m.ns == "ship/cargo"]
    hull = next(m for m in markers if m.type == m.TRIANGLE_LIST)
    assert len(markers) >= 2 and hull.header.frame_id == "world" and not hull.frame_locked
    q, p = hull.pose.orientation, hull.pose.position
    local = np.array([[v.x, v.y, v.z] for v in hull.points])
    world = Rotation.from_quat([q.x, q.y, q.z, q.w]).apply(local) + [p.x, p.y, p.z]
    low, high = world.min(axis=0), world.max(axis=0)
    assert (low[:2] + high[:2]) / 2 == pytest.approx([100.0 - 2.0 * 3.0, 20.0], abs=0.05)
    assert high[:2] - low[:2] == pytest.approx([25.0, 6.25], abs=0.1)
