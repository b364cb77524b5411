"""Commands posted as CDR bytes from another thread move the boat; bad ones are counted, never raised."""

from __future__ import annotations

import struct
import threading

import pytest

from usvsim.core.errors import UsvsimError
from usvsim.messages.ros import msg_class, typestore
from usvsim.simulation import Simulation


def cdr(msgtype: str, **fields) -> bytes:
    return bytes(typestore().serialize_cdr(msg_class(msgtype)(**fields), msgtype))


def float64(x: float) -> bytes:
    return cdr("std_msgs/msg/Float64", data=x)


def twist(u: float, v: float, r: float) -> bytes:
    vec = msg_class("geometry_msgs/msg/Vector3")
    return cdr("geometry_msgs/msg/Twist", linear=vec(x=u, y=v, z=0.0), angular=vec(x=0.0, y=0.0, z=r))


@pytest.fixture
def sim(scenario_of):
    return Simulation(scenario_of({"vessels": [{"name": "wamv", "model": "wamv", "command_timeout_s": 1.0}]}))


def test_command_topics_name_every_thruster(sim):
    topics = sim.commands.topics
    for name in sim.vessels["wamv"].thrusters:
        assert topics[f"/wamv/thrusters/{name}/thrust"] == "std_msgs/msg/Float64"
        assert topics[f"/wamv/thrusters/{name}/angle"] == "std_msgs/msg/Float64"
    assert topics["/wamv/cmd_vel"] == "geometry_msgs/msg/Twist" and topics["/reset"] == "std_msgs/msg/Empty"


def test_thrust_from_another_thread_moves_the_boat_and_the_watchdog_stops_it(sim):
    names = list(sim.vessels["wamv"].thrusters)

    def publish():
        for name in names:
            assert sim.commands.post_cdr(f"/wamv/thrusters/{name}/thrust", float64(1.0))

    worker = threading.Thread(target=publish)
    worker.start()
    worker.join()
    sim.run(0.5)
    assert sim.vessels["wamv"].velocity_body[0] > 0.1  # surging forward, FLU
    assert all(t.thrust_n > 100.0 for t in sim.vessels["wamv"].thrusters.values())
    sim.run(2.0)  # no more commands: the 1 s watchdog has zeroed them
    assert all(abs(t.thrust_n) < 1.0 for t in sim.vessels["wamv"].thrusters.values())
    assert sim.commands.stats["applied"] == len(names)


def test_angle_command_steers_without_refreshing_the_watchdog(sim):
    assert sim.commands.post_cdr("/wamv/thrusters/rear_left/angle", float64(0.3))  # an azimuth outboard
    sim.run(2.0)
    assert sim.vessels["wamv"].thrusters["rear_left"].angle_rad == pytest.approx(0.3, abs=0.01)
    assert sim.thrusters.last_cmd_ns.max() == 0


def test_bad_commands_are_counted_and_the_simulation_runs_on(sim):
    topic = f"/wamv/thrusters/{next(iter(sim.vessels['wamv'].thrusters))}/thrust"
    assert not sim.commands.post_cdr(topic, float64(float("nan")))
    assert not sim.commands.post_cdr(topic, float64(1.5))
    assert not sim.commands.post_cdr(topic, b"\x00\x01\x00\x00\x01")  # truncated CDR
    assert not sim.commands.post_cdr(topic, b"garbage")
    assert not sim.commands.post_cdr("/wamv/thrusters/nope/thrust", float64(0.5))
    assert not sim.commands.post_cdr("/wamv/cmd_vel", twist(float("inf"), 0.0, 0.0))
    sim.run(0.1)
    s = sim.commands.stats
    assert (s["rejected"], s["malformed"], s["unknown"], s["applied"]) == (3, 2, 1, 0)
    assert sim.thrusters.cmd_u.max() == 0.0


def test_queue_is_bounded_and_drops_the_oldest(sim):
    topic = f"/wamv/thrusters/{next(iter(sim.vessels['wamv'].thrusters))}/thrust"
    for i in range(1100):
        sim.commands.post_cdr(topic, float64((i % 10) / 10.0))
    assert sim.commands.stats["dropped"] == 1100 - 1024
    sim.step()
    assert sim.thrusters.cmd_u.max() == pytest.approx(0.9)  # the newest command is the one that holds
    assert sim.commands.stats["applied"] == 1024


def test_cmd_vel_creates_a_controller_that_goes_away_when_commands_stop(sim):
    assert "wamv" not in sim.controllers
    for _ in range(40):  # 20 s of cmd_vel at 2 Hz
        assert sim.commands.post_cdr("/wamv/cmd_vel", twist(1.2, 0.0, 0.0))
        sim.run(0.5)
    assert sim.vessels["wamv"].velocity_body[0] == pytest.approx(1.2, abs=0.05)
    assert "wamv" in sim.controllers
    sim.run(1.5)  # cmd_vel silent longer than command_timeout_s
    assert "wamv" not in sim.controllers
    sim.run(2.0)
    assert all(abs(t.thrust_n) < 1.0 for t in sim.vessels["wamv"].thrusters.values())


def test_cmd_vel_timeout_restores_a_scenario_station_keeping_target(scenario_of):
    sc = scenario_of(
        {"vessels": [{"name": "wamv", "model": "wamv", "controller": {"type": "station_keeping"}}]}
    )
    sim = Simulation(sc)
    target = sim.controllers["wamv"].reference
    sim.commands.post_cdr("/wamv/cmd_vel", twist(1.0, 0.0, 0.0))
    sim.run(0.5)
    assert sim.controllers["wamv"].reference == (1.0, 0.0, 0.0)
    sim.run(1.0)
    assert sim.controllers["wamv"].reference == target


def test_reset_topic_restores_the_start(sim):
    start = sim.vessels["wamv"].position
    for name in sim.vessels["wamv"].thrusters:
        sim.commands.post_cdr(f"/wamv/thrusters/{name}/thrust", float64(1.0))
    sim.run(3.0)
    assert sim.commands.post_cdr("/reset", struct.pack("<4sB", b"\x00\x01\x00\x00", 0))
    sim.step()
    assert sim.clock_ns == sim.clock.step_ns
    assert abs(sim.vessels["wamv"].position[0] - start[0]) < 0.01
    assert sim.thrusters.cmd_u.max() == 0.0


def test_a_reset_topic_announces_the_new_episode_before_its_first_step(sim):
    """After /reset, the subscribers see the episode marker and the t = 0 messages first, then the new episode's clock
    rising from there (QA: /clock went 3.05, 0.01, 0.0, 0.02 over DDS, and the recording got the 0.01 s clock before
    the marker, out of log-time order)."""
    seen = []
    sim.subscribe(lambda env: seen.append((env.topic, env.stamp_ns)))
    sim.run(0.5)
    assert sim.commands.post_cdr("/reset", struct.pack("<4sB", b"\x00\x01\x00\x00", 0))
    mark = len(seen)
    sim.run(0.05)
    after = seen[mark:]
    assert after[0][0] == "/usvsim/episode"
    clocks = [stamp for topic, stamp in after if topic == "/clock"]
    assert clocks[0] == 0 and clocks == sorted(clocks) and len(set(clocks)) == len(clocks)


EMPTY = struct.pack("<4sB", b"\x00\x01\x00\x00", 0)  # std_msgs/msg/Empty


def test_each_reset_topic_starts_the_next_seed_unless_asked_for_the_same(scenario_of):
    """Every /reset replayed the run's seed: the same waves, wind gusts and sensor noise each episode, so a
    controller trained or tested through /reset saw one sea. Now the k-th reset runs seed + k (reproducible), each
    episode equal to a fresh start with that seed; `reset_seeds = "same"` keeps the old behaviour."""
    import json

    config = {"environment": {"sea": {"type": "jonswap", "hs_m": 1.0, "tp_s": 5.0}},
              "vessels": [{"name": "wamv", "model": "wamv"}]}  # fmt: skip
    sim, markers = Simulation(scenario_of(config), seed=5), []
    sim.subscribe(lambda env: markers.append(json.loads(env.msg.data)) if env.topic == "/usvsim/episode" else None)
    for _ in range(2):
        sim.run(0.1)
        assert sim.commands.post_cdr("/reset", EMPTY)
    sim.run(0.1)
    assert [(m["episode"], m["seed"]) for m in markers] == [(0, 5), (1, 6), (2, 7)]
    fresh = Simulation(scenario_of(config), seed=7)
    fresh.run(0.1)
    assert sim.vessels["wamv"].position.tolist() == fresh.vessels["wamv"].position.tolist()  # bit for bit
    sim.reset_seeds = "same"
    assert sim.commands.post_cdr("/reset", EMPTY)
    sim.run(0.1)
    assert (markers[-1]["episode"], markers[-1]["seed"]) == (3, 7)
    with pytest.raises(UsvsimError, match="reset_seeds"):
        sim.reset_seeds = "random"
