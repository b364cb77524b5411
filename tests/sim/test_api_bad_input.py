"""Mistakes with the Simulation API raise at once, naming the value. Before: run(seconds=-1) ran no step and
said nothing; run(seconds=nan) said 'cannot convert float NaN to integer'; subscribe(5) was taken and the next
step failed with "'int' object is not callable"; record(path, topics="/clock") recorded nothing (the topics
were the string's characters)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mcap.reader import make_reader

from usvsim.core.errors import UsvsimError
from usvsim.simulation import Simulation


@pytest.fixture(scope="module")
def sim():
    sim = Simulation.from_scenario("harbor", seed=0)
    yield sim
    sim.close()


@pytest.mark.parametrize("seconds", [-1.0, math.nan, math.inf, "1", None, True])
def test_run_refuses_a_duration_that_is_not_a_finite_number_at_least_0(sim, seconds):
    steps = sim.world.clock.steps
    with pytest.raises(UsvsimError, match=f"seconds must be a finite number >= 0, not {seconds!r}"):
        sim.run(seconds)
    assert sim.world.clock.steps == steps


def test_run_takes_numpy_floats_and_zero(sim):
    steps = sim.world.clock.steps
    sim.run(0.0)
    sim.run(np.float32(0.05))
    assert sim.world.clock.steps == steps + 5


def test_subscribe_refuses_what_is_not_callable(sim):
    with pytest.raises(UsvsimError, match="callback must be callable .* not 5"):
        sim.subscribe(5)  # type: ignore[arg-type]
    sim.step()  # nothing was subscribed


def test_record_takes_one_topic_name_as_a_string(tmp_path):
    sim = Simulation.from_scenario("harbor", seed=0)
    with sim.record(tmp_path / "one.mcap", topics="/clock"):
        sim.run(0.1)
    sim.close()
    with (tmp_path / "one.mcap").open("rb") as f:
        topics = {channel.topic for _, channel, _ in make_reader(f).iter_messages()}
    assert topics == {"/clock"}


@pytest.mark.parametrize("point", [([math.nan], [0.0]), (0.0, math.inf), ([1.0, math.nan], [0.0, 0.0])])
def test_depth_at_refuses_a_position_that_is_not_finite(sim, point):
    """depth_at([nan], [0]) gave the default depth (20 m in a geo place, inf without one) as if it were a place."""
    with pytest.raises(UsvsimError, match="depth_at: ._m must be finite numbers"):
        sim.world.depth_at(*point)
    assert sim.world.depth_at([0.0, 5.0], [0.0, 1.0]).shape == (2,)


def test_a_bad_velocity_reference_is_refused_and_does_not_stall_the_controller():
    """A NaN reference was taken: the controller's state became NaN for good and the boat never moved again,
    whatever came next; (1.0,) failed at the next step with 'not enough values to unpack'."""
    from usvsim.config.scenario import Scenario

    scenario = Scenario.model_validate({"version": 1, "vessels": [
        {"name": "wamv", "model": "wamv", "controller": {"type": "velocity", "rate_hz": 20}}]})  # fmt: skip
    sim = Simulation(scenario, seed=0)
    loop = sim.controllers["wamv"]
    for bad in ((math.nan, 0.0, 0.0), (1.0,), "fast", None):
        with pytest.raises(UsvsimError, match="reference must be 3 finite numbers"):
            loop.reference = bad
    loop.reference = np.array([1.5, 0.0, 0.0])
    sim.run(8.0)
    assert sim.vessels["wamv"].velocity_body[0] > 1.0  # still under way at the good reference
    sim.close()
