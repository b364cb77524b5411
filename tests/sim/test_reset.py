"""Episodes: `reset(seed)` gives, bit for bit, the run of a fresh simulation with that seed, whatever ran
before (other commands, another seed); poses and teleports place vessels without recompiling."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from usvsim.config.loader import parse_scenario, resolve
from usvsim.core.errors import UsvsimError
from usvsim.messages.envelope import EPISODE_TOPIC
from usvsim.simulation import Simulation

ROUGH = {"sea": {"type": "sea_state", "code": 4, "realization": {"method": "direct", "components": 24}},
         "wind": {"speed_mps": 8.0, "gust_gain": 3.0},
         "current": {"speed_mps": 0.3, "speed_std_mps": 0.1, "direction_std": 0.2, "time_constant_s": 5.0}}  # fmt: skip


def builtin(name: str, **changes) -> dict:
    return {**yaml.safe_load(resolve(name)[0]), **changes}


def messages(sim: Simulation, seconds: float, drive=None) -> list[tuple[str, int, bytes]]:
    """(topic, stamp, CDR bytes) of every message emitted while running `seconds`."""
    out: list[tuple[str, int, bytes]] = []
    unsubscribe = sim.subscribe(lambda env: out.append((env.topic, env.stamp_ns, bytes(env.cdr))))
    if drive is not None:
        drive(sim)
    sim.run(seconds)
    unsubscribe()
    return out


def other_episode(sim: Simulation) -> None:
    """An earlier episode that leaves every kind of state behind: commands, motion, queued inbox."""
    sim.vessels["wamv"].command(0.8, 0.3)
    sim.run(0.7)
    sim.vessels["wamv"].teleport((3.0, 1.0, 0.2, 0.1, 0.0, 1.0), twist=(1.0, 0.0, 0.0, 0.0, 0.0, 0.2))
    sim.run(0.3)
    sim.commands.post("/wamv/cmd_vel", _Twist(0.5, 0.0, 0.1))


class _Twist:
    def __init__(self, u, v, r):
        self.linear = type("V", (), {"x": u, "y": v, "z": 0.0})()
        self.angular = type("V", (), {"x": 0.0, "y": 0.0, "z": r})()


def forward(sim: Simulation) -> None:
    sim.vessels["wamv"].command(0.5)


# the FFT realization (sea_state's default) and the direct one; the last case has a station-keeping controller
FFT_ROUGH = {**ROUGH, "sea": {"type": "sea_state", "code": 4}}
HOLD = {"version": 1, "name": "hold", "environment": ROUGH,
        "vessels": [{"name": "wamv", "model": "wamv", "controller": {"type": "station_keeping"}}]}  # fmt: skip


@pytest.mark.parametrize("name, changes, seconds", [
    ("harbor", {"environment": ROUGH}, 5.0),
    ("harbor", {"environment": FFT_ROUGH}, 5.0),
    ("harbor_sensors", {"environment": ROUGH}, 5.0),
    ("harbor_sensors", {"environment": FFT_ROUGH}, 5.0),
    ("hold", HOLD, 5.0),
])  # fmt: skip
def test_reset_equals_a_fresh_simulation(name, changes, seconds):
    """All message bytes over 5 s after `reset(seed=11)` (after an episode with other commands and seed 3)
    equal those of a fresh simulation with seed 11."""
    scenario = parse_scenario(builtin(name, **changes) if name != "hold" else changes, name)
    sim = Simulation(scenario, seed=3)
    try:
        other_episode(sim)
        sim.reset(seed=11)
        after_reset = messages(sim, seconds, forward)
    finally:
        sim.close()
    fresh_sim = Simulation(scenario, seed=11)
    try:
        fresh = messages(fresh_sim, seconds, forward)
    finally:
        fresh_sim.close()
    marker = [m for m in after_reset if m[0] == EPISODE_TOPIC]
    assert len(marker) == 1 and b'"episode": 1, "seed": 11' in marker[0][2]
    after_reset = [m for m in after_reset if m[0] != EPISODE_TOPIC]
    fresh = [m for m in fresh if m[0] != EPISODE_TOPIC]
    assert [m[:2] for m in after_reset] == [m[:2] for m in fresh]
    assert all(a[2] == b[2] for a, b in zip(after_reset, fresh)), "message bytes differ"


def test_reset_restores_a_station_keeping_controller(scenario_of):
    data = {"name": "hold", "environment": ROUGH,
            "vessels": [{"name": "wamv", "model": "wamv", "controller": {"type": "station_keeping"}}]}  # fmt: skip
    sim = Simulation(scenario_of(data), seed=1)
    other_episode(sim)
    sim.reset(seed=2)
    sim.run(2.0)
    fresh = Simulation(scenario_of(data), seed=2)
    fresh.run(2.0)
    assert np.array_equal(sim.data.qpos, fresh.data.qpos) and np.array_equal(sim.data.qvel, fresh.data.qvel)
    assert sim.commands.stats["received"] == 1  # the inbox counted the earlier cmd_vel, and dropped it


def test_reset_with_poses_and_teleport(scenario_of):
    sim = Simulation(scenario_of({"name": "two", "vessels": [{"name": "wamv", "model": "wamv"}]}))
    model = sim.model
    sim.run(0.5)
    sim.reset(poses={"wamv": {"position": [5.0, -2.0, 0.0], "yaw_deg": 90.0}})
    assert sim.model is model and sim.time == 0.0
    np.testing.assert_allclose(sim.vessels["wamv"].position, [5.0, -2.0, 0.0])
    np.testing.assert_allclose(sim.vessels["wamv"].rpy, [0.0, 0.0, np.pi / 2], atol=1e-12)
    sim.vessels["wamv"].teleport((0.0, 0.0, 0.0, 0.0, 0.0, 0.0), twist=(2.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    np.testing.assert_allclose(sim.vessels["wamv"].velocity_body, [2.0, 0.0, 0.0], atol=1e-12)
    sim.run(1.0)
    assert 1.0 < sim.vessels["wamv"].position[0] < 2.0  # coasting forward, slowed by drag
    with pytest.raises(KeyError, match="nope"):
        sim.reset(poses={"nope": (0, 0, 0, 0, 0, 0)})
    with pytest.raises(ValueError, match="6 .* or 7"):
        sim.vessels["wamv"].teleport((1.0, 2.0))


def test_bad_poses_are_one_line_errors_and_change_nothing(scenario_of):
    """A pose dict's mistakes were pydantic's several lines with links; a teleport 200 km away was taken (every
    scenario position is within 100 km of the origin)."""
    sim = Simulation(scenario_of({"name": "one", "vessels": [{"name": "wamv", "model": "wamv"}]}))
    sim.run(0.2)
    before = sim.data.qpos.copy()
    for pose, words in (({"position": [0, 0, 0], "yawdeg": 3}, "yawdeg: unknown key (did you mean 'yaw_deg'?)"),
                        ({"position": [0, 0], "yaw_deg": 1}, "position: should have 3 items, got 2"),
                        ({"position": [0, 0, 0], "yaw_deg": "east"}, "yaw_deg"),
                        ((2e5, 0, 0, 0, 0, 0), "more than 100 km")):  # fmt: skip
        with pytest.raises(ValueError) as reset_error:
            sim.reset(poses={"wamv": pose})
        with pytest.raises(ValueError) as teleport_error:
            sim.vessels["wamv"].teleport(pose)
        for error in (reset_error, teleport_error):
            assert words in str(error.value) and "\n" not in str(error.value)
    assert np.array_equal(sim.data.qpos, before) and sim.time > 0  # neither call changed the state


def test_a_simulation_from_a_name_or_a_path(tmp_path):
    """`Simulation("harbor")` failed deep inside with "'str' object has no attribute 'traffic'"."""
    assert Simulation("harbor", seed=2).scenario.name == "harbor"
    path = tmp_path / "one.yaml"
    path.write_text("version: 1\nname: one\nvessels: [{name: a, model: otter}]\n")
    assert list(Simulation(path).vessels) == ["a"]
    with pytest.raises(UsvsimError, match="a built-in scenario's name or a YAML file's path, not int"):
        Simulation(3)  # type: ignore[arg-type]


def test_two_simulations_interleaved_equal_separate_runs(scenario_of):
    data = {"name": "gm", "environment": ROUGH, "vessels": [{"name": "wamv", "model": "wamv"}]}

    def run_alone(seed):
        sim = Simulation(scenario_of(data), seed=seed)
        sim.vessels["wamv"].command(0.6)
        sim.run(1.0)
        return sim.data.qpos.copy()

    a, b = Simulation(scenario_of(data), seed=5), Simulation(scenario_of(data), seed=6)
    for sim in (a, b):
        sim.vessels["wamv"].command(0.6)
    for _ in range(100):
        a.step()
        b.step()
    assert np.array_equal(a.data.qpos, run_alone(5)) and np.array_equal(b.data.qpos, run_alone(6))


def test_python_commands_hold_network_commands_time_out(scenario_of):
    """The README's `boat.command(0.5)` keeps driving; a bridge's thrust command stops at the watchdog."""
    sim = Simulation(scenario_of({"name": "w", "vessels": [{"name": "wamv", "model": "wamv",
                                                              "command_timeout_s": 1.0}]}))  # fmt: skip
    sim.vessels["wamv"].command(0.5)
    sim.run(3.0)
    assert min(t.thrust_n for t in sim.vessels["wamv"].thrusters.values()) > 50.0
    sim.reset()
    for name in sim.vessels["wamv"].thrusters:
        sim.commands.post(f"/wamv/thrusters/{name}/thrust", type("F", (), {"data": 0.5})())
    sim.run(3.0)
    assert max(abs(t.thrust_n) for t in sim.vessels["wamv"].thrusters.values()) < 1.0


def test_reset_with_kerner_hydrodynamics_equals_a_fresh_simulation(scenario_of):
    """Kerner's Reynolds length (the last step's waterline) restarts with the episode (it kept the earlier
    episode's: the first step after `reset` had other viscous forces, and every pose after it differed)."""
    data = {"name": "kerner", "environment": ROUGH,
            "vessels": [{"name": "wamv", "model": "wamv", "hydrodynamics": {"type": "kerner"}}]}  # fmt: skip
    sim = Simulation(scenario_of(data), seed=3)
    other_episode(sim)
    sim.reset(seed=4)
    forward(sim)
    sim.run(2.0)
    fresh = Simulation(scenario_of(data), seed=4)
    forward(fresh)
    fresh.run(2.0)
    assert np.array_equal(sim.data.qpos, fresh.data.qpos) and np.array_equal(sim.data.qvel, fresh.data.qvel)


def test_every_reset_not_only_the_first_equals_a_fresh_simulation():
    """Sensor noise after the second and later `reset(seed)` (QA: from episode 2 on the IMU read up to 0.145 m/s²
    and the GNSS fix 0.26-1.15 m off a fresh run's: `RngStreams.reseed` restarted its table's generator, not the
    sensors' own, from the second reseed on)."""
    from usvsim.core.rng import RngStreams

    streams = RngStreams(1)
    held = streams.get("sensor/x")
    first = held.random()
    for _ in range(3):
        streams.reseed(1)
        assert held.random() == first
    data = {"version": 1, "name": "noisy", "vessels": [{"name": "wamv", "model": "wamv", "sensors": [
        {"type": "imu", "name": "imu", "rate_hz": 100, "preset": "vrx"},
        {"type": "gnss", "name": "gps", "rate_hz": 10, "horizontal_stddev_m": 0.5}]}]}  # fmt: skip

    def episode(sim):
        sim.run(0.5)
        seen = sim.observe()
        return np.concatenate([seen["wamv/imu"]["linear_acceleration"], seen["wamv/gps"]["lla"]])

    fresh = episode(Simulation(parse_scenario(data, "noisy"), seed=3))
    sim = Simulation(parse_scenario(data, "noisy"), seed=3)
    for _ in range(4):
        assert np.array_equal(episode(sim), fresh)
        sim.reset(seed=3)
