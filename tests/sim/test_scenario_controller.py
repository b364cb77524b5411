"""A vessel that declares a controller in its scenario entry follows velocity commands and holds station."""

from __future__ import annotations

import math

import pytest

from usvsim.core.errors import ScenarioError
from usvsim.simulation import Simulation


def test_declared_velocity_controller_follows_cmd_vel(scenario_of):
    sim = Simulation(scenario_of({"vessels": [{"name": "wamv", "model": "wamv", "controller": {"type": "velocity"}}]}))
    sim.controllers["wamv"].reference = (1.5, 0.0, 0.1)  # surge m/s, sway m/s, yaw rate rad/s (base_link, FLU)
    sim.run(25.0)
    boat = sim.vessels["wamv"]
    assert boat.velocity_body[0] == pytest.approx(1.5, abs=0.05)
    assert boat.angular_velocity_body[2] == pytest.approx(0.1, abs=0.005)


def test_station_keeping_holds_the_start_pose_against_current(scenario_of):
    sc = scenario_of({
        "environment": {"current": {"speed_mps": 0.2, "direction_deg": 45.0}},
        "vessels": [{"name": "wamv", "model": "wamv", "controller": {"type": "station_keeping"}}],
    })  # fmt: skip
    sim = Simulation(sc)
    sim.run(60.0)
    boat = sim.vessels["wamv"]
    assert math.hypot(*boat.position[:2]) < 0.3
    assert abs(boat.rpy[2]) < math.radians(3)


def test_controller_rate_must_divide_into_physics_steps(scenario_of):
    with pytest.raises(ScenarioError) as err:
        scenario_of({"vessels": [{"name": "w", "model": "wamv", "controller": {"type": "velocity", "rate_hz": 30}}]})
    assert err.value.key_path == "vessels[0].controller.rate_hz"


@pytest.mark.parametrize(
    ("model", "hydrodynamics", "reference"),
    [
        ("otter_pvs", None, (1.2, 0.0, 0.1)),  # Fossen's model by default
        ("otter", {"type": "fossen", "parameters": "otter"}, (1.2, 0.0, 0.1)),
        ("wamv", {"type": "kerner"}, (1.5, 0.0, 0.1)),
        ("wamv", {"type": "fossen", "parameters": "wamv_vrx"}, (1.5, 0.0, 0.1)),
    ],
)
def test_controller_on_fossen_and_kerner_hydrodynamics(scenario_of, model, hydrodynamics, reference):
    """The controller's plant model comes from Fossen's damping and added mass, or for Kerner's per-face forces
    from an unidentified hull's estimate (it raised AttributeError: no 'X_u'); the loop then follows cmd_vel."""
    vessel = {"name": "b", "model": model, "controller": {"type": "velocity"}}
    if hydrodynamics:
        vessel["hydrodynamics"] = hydrodynamics
    sim = Simulation(scenario_of({"vessels": [vessel]}))
    sim.controllers["b"].reference = reference
    sim.run(40.0)
    boat = sim.vessels["b"]
    assert boat.velocity_body[0] == pytest.approx(reference[0], abs=0.05)
    assert boat.angular_velocity_body[2] == pytest.approx(reference[2], abs=0.005)
