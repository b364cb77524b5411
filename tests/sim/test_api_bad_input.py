"""Mistakes with the Simulation API raise at once, naming the value. Before: run(seconds=-1) ran no step and
said nothing; run(seconds=nan) said 'cannot convert float NaN to integer'; subscribe(5) was taken and the next
step failed with "'int' object is not callable"; record(path, topics="/clock") recorded nothing (the topics
were the string's characters)."""

from __future__ import annotations

import math
import re

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


def test_a_bad_force_is_refused():
    """`loop.force` (τ about the CoM) took a NaN (thrusters silently at 0), (1.0,) (broadcast to (1, 1, 1)) and a
    string (ValueError inside the next run); now refused like a bad reference."""
    from usvsim.config.scenario import Scenario

    scenario = Scenario.model_validate({"version": 1, "vessels": [
        {"name": "wamv", "model": "wamv", "controller": {"type": "velocity", "rate_hz": 20}}]})  # fmt: skip
    sim = Simulation(scenario, seed=0)
    loop = sim.controllers["wamv"]
    for bad in ((math.nan, 0.0, 0.0), (1.0,), "x", (0.0, 0.0, math.inf)):
        with pytest.raises(UsvsimError, match="force must be 3 finite numbers"):
            loop.force = bad
    loop.force = (200.0, 0.0, 0.0)
    sim.run(3.0)
    assert sim.vessels["wamv"].velocity_body[0] > 0.5  # 200 N ahead moves it
    loop.force = None  # back to the reference
    assert loop.force is None
    sim.close()


@pytest.mark.parametrize(
    ("call", "value", "message"),
    [
        ("set_hydrodynamics", "kerner", "give a dict like {'type': ...}"),
        ("set_hydrodynamics", None, "give a dict like {'type': ...}"),
        ("set_hydrodynamics", {"type": "kerner", "slaming_scale": 1.0}, "did you mean 'slamming_scale'"),
        ("set_hydrodynamics", {"type": "kerner", "slamming_scale": math.nan}, "slamming_scale: Input should be a fin"),
        ("set_buoyancy", "voxels", "give a dict like {'type': ...} (type one of 'triangles', 'voxels')"),
        ("set_buoyancy", {"type": "voxel"}, "unknown type 'voxel'"),
        ("set_buoyancy", {"type": "voxels", "voxel_size_m": 1e-4}, "cells over the 2 x 1.04 x 0.63 m hull, more than"),
    ],
)
def test_model_switches_refuse_what_is_not_a_section_in_one_line(sim, call, value, message):
    """set_hydrodynamics("kerner") was stored as the string and every hydrodynamic force vanished (an Otter at half
    thrust reached 6.85 m/s instead of 0.77); a dict's mistake was pydantic's lines with a link."""
    boat = sim.vessels["otter"]
    before = (boat.hydrodynamics, boat.buoyancy)
    with pytest.raises(ValueError, match=re.escape(message)) as err:
        getattr(boat, call)(value)
    assert "\n" not in str(err.value) and "http" not in str(err.value)
    assert isinstance(err.value, UsvsimError)  # voxels too fine for the hull: a bare ValueError from the voxelizer
    assert (boat.hydrodynamics, boat.buoyancy) == before  # ... after the buoyancy had been switched (half built)


def test_thruster_commands_that_are_not_numbers_are_rejected_and_counted(sim):
    """command("0.5") was taken (float() of the string) and command(None) raised TypeError."""
    thruster = sim.vessels["otter"].thrusters["left"]
    rejected = sim.world.thrusters.rejected
    assert [thruster.command(v) for v in ("0.5", None, True, np.array([0.5]))] == [False] * 4
    assert thruster.command_angle("0.1") is False
    assert sim.world.thrusters.rejected == rejected + 5
    assert thruster.command(np.float32(0.25)) and thruster.command(np.array(0.25)) and thruster.command(0)


def test_reset_refuses_a_bad_seed_and_an_unknown_body_in_one_plain_line(sim):
    with pytest.raises(UsvsimError, match="a seed is a non-negative integer, got 'a'"):
        sim.reset(seed="a")
    with pytest.raises(KeyError) as err:
        sim.reset(poses={"nope": (0, 0, 0, 0, 0, 0)})
    assert str(err.value).startswith("no body named ['nope']; bodies: [")  # KeyError's own text was its repr
