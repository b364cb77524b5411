"""Python API inputs QA found mishandled: each is refused before anything changes, or now does what it says."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.core.errors import UsvsimError
from usvsim.simulation import Simulation

BOAT = {"version": 1, "name": "one", "vessels": [{"name": "wamv", "model": "wamv"}]}


def test_a_dict_is_a_scenario():
    sim = Simulation(BOAT, seed=2)
    assert list(sim.vessels) == ["wamv"] and sim.world.seed == 2
    with pytest.raises(UsvsimError, match=r"vessels\[0\]\.model: unknown vessel model"):
        Simulation({**BOAT, "vessels": [{"name": "wamv", "model": "titanic"}]})


@pytest.mark.parametrize("seed", [2.9, True, "3", "a", -1, None])
def test_a_seed_that_is_not_a_non_negative_integer_is_refused(seed):
    """Simulation(seed=2.9) ran with seed 2, True with 1, '3' with 3; 'a' was a bare ValueError (reset refused
    them all)."""
    with pytest.raises(UsvsimError, match="a seed is a non-negative integer"):
        Simulation(BOAT, seed=seed)


def test_a_teleport_with_a_bad_twist_changes_nothing():
    """The teleport was counted (the next IMU sample took it for a jump) before the twist was refused."""
    sim = Simulation(BOAT)
    sim.run(0.1)
    before = (sim.world.teleports, sim.world.body_teleports.copy(), sim.data.qpos.copy(), sim.data.qvel.copy())
    with pytest.raises(ValueError, match="twist"):
        sim.vessels["wamv"].teleport((1.0, 2.0, 0.0, 0.0, 0.0, 0.0), twist=(1.0, float("nan"), 0, 0, 0, 0))
    assert sim.world.teleports == before[0] and np.array_equal(sim.world.body_teleports, before[1])
    assert np.array_equal(sim.data.qpos, before[2]) and np.array_equal(sim.data.qvel, before[3])


@pytest.mark.parametrize(("seconds", "steps"), [(0.004, 0), (0.005, 1), (0.015, 2), (0.025, 3), (0.3, 30)])
def test_run_rounds_halves_up(seconds, steps):
    """round() ran 0.005 s as 0 steps and 0.025 s as 2 at 100 Hz (halves to even)."""
    sim = Simulation(BOAT)
    sim.run(seconds)
    assert sim.clock.steps == steps


def test_an_unknown_name_lists_the_names_there_are():
    """sim.vessels['nope'] and the like were a bare KeyError: 'nope' (still a KeyError, now an UnknownNameError)."""
    from usvsim.core.errors import UnknownNameError

    sim = Simulation({**BOAT, "vessels": [{**BOAT["vessels"][0], "sensors": [{"type": "imu", "name": "imu"}]}]})
    boat = sim.vessels["wamv"]
    for table, name, names in ((sim.vessels, "nope", "['wamv']"), (sim.bodies, "nope", "['wamv']"),
                               (sim.sensors, "wamv/x", "['wamv/imu']"), (boat.sensors, "x", "['imu']"),
                               (boat.thrusters, "x", "'rear_left', 'rear_right'"), (sim.controllers, "x", "[]")):  # fmt: skip
        with pytest.raises(UnknownNameError, match=f"no .* named '{name}'") as err:
            table[name]
        assert isinstance(err.value, KeyError) and names in str(err.value)


def test_api_mistakes_are_usvsim_errors_and_change_nothing(tmp_path):
    """Pose errors were bare ValueErrors (`except UsvsimError` missed them), reset(poses='wamv') said "no body named
    ['a', 'm', 'v', 'w']", record() into a missing folder a FileNotFoundError and with topics=5 a TypeError, a second
    unsubscribe a ValueError, and a step after close() advanced the clock, then failed in a closed render context."""
    from usvsim.core.errors import InputError

    sim = Simulation(BOAT)
    with pytest.raises(InputError, match="a pose has 6"):
        sim.vessels["wamv"].teleport((1.0, 2.0))
    with pytest.raises(InputError, match="poses maps body names"):
        sim.reset(poses="wamv")  # type: ignore[arg-type]
    with pytest.raises(UsvsimError, match="cannot write"), sim.record(tmp_path / "no" / "such" / "x.mcap"):
        pass
    with pytest.raises(UsvsimError, match="topic name or names"), sim.record(tmp_path / "x.mcap", topics=5):  # type: ignore[arg-type]
        pass
    unsubscribe = sim.subscribe(lambda env: None)
    unsubscribe()
    unsubscribe()
    sim.run(0.05)
    sim.close()
    steps = sim.clock.steps
    with pytest.raises(UsvsimError, match="closed"):
        sim.step()
    assert sim.clock.steps == steps


def test_a_moored_buoy_placed_beyond_its_line_is_refused():
    """reset(poses=...) 8-50 m from the anchor of a 6 m line was accepted; the first step diverged (221-2981 rad/s)
    with an error that blamed the time step (QA)."""
    from usvsim.core.errors import InputError

    sim = Simulation("harbor")
    start = sim.bodies["red_1"].position
    near = (start[0] + 2.0, start[1], 0.0, 0.0, 0.0, 0.0)
    sim.reset(poses={"red_1": near})  # within the line's reach: fine
    sim.run(0.5)
    qpos = sim.data.qpos.copy()
    far = (start[0] + 20.0, start[1], 0.0, 0.0, 0.0, 0.0)
    with pytest.raises(InputError, match="beyond its mooring line"):
        sim.reset(poses={"red_1": far})
    with pytest.raises(InputError, match="beyond its mooring line"):
        sim.bodies["red_1"].teleport(far)
    assert np.array_equal(sim.data.qpos, qpos)
