"""Scenario validation: strict keys, types, rates and references, with errors that name the key path."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from usvsim.config.loader import builtin_scenarios, load_scenario
from usvsim.core.errors import MeshError, ScenarioError
from usvsim.simulation import Simulation


def test_builtin_harbor_loads_with_description():
    assert "harbor" in builtin_scenarios()
    sc = load_scenario("harbor")
    assert [v.model for v in sc.vessels] == ["wamv", "otter"]
    assert sum(o.type == "buoy" for o in sc.objects) == 9
    assert {o.type for o in sc.objects} >= {"dock", "berth", "buoy"}


@pytest.mark.parametrize(
    "data, path, words",
    [
        ({"vessels": [{"name": "a", "model": "wamv", "posee": {}}]}, "vessels[0].posee", "unknown key"),
        ({"world": {"physics_rate_hz": "fast"}}, "world.physics_rate_hz", "valid number"),
        ({"vessels": [{"name": "a", "model": "wamv", "pose": {"position": [0, 0]}}]}, "vessels[0].pose.position",
         "should have 3 items, got 2"),  # was "position[2]: missing, and required here"
        ({"vessels": [{"name": "a", "model": "wamv", "pose": {"position": [0, 0, 0, 1]}}]}, "vessels[0].pose.position",
         "should have 3 items, got 4"),
        ({"objects": [{"type": "volcano", "name": "v"}]}, "objects[0]", "volcano"),
        ({"objects": [{"type": "buoy", "name": "b", "position": [0, 0, 0], "colour": "red"}]},
         "objects[0].colour", "unknown key"),
        ({"outputs": {"recording": {"ground_truth_rate_hz": 30}}}, "outputs.recording.ground_truth_rate_hz",
         "multiple of the physics step"),
        ({"world": {"physics_rate_hz": 300}}, "world.physics_rate_hz", "nanosecond"),
        ({"environment": {"sea": {"type": "jonswap", "hs_m": 1e9, "tp_s": 8.0}}}, "environment.sea.hs_m",
         "less than or equal to 30"),
        ({"environment": {"sea": {"type": "pierson_moskowitz", "wind_speed_mps": 80.0}}},
         "environment.sea.wind_speed_mps", "less than or equal to 35"),
    ],
)
def test_errors_name_the_key_path(scenario_of, data, path, words):
    with pytest.raises(ScenarioError) as err:
        scenario_of(data)
    assert err.value.key_path == path
    assert words in err.value.message


@pytest.mark.parametrize("physics_hz, clock_hz, truth_hz", [
    (20, 20.0, 20.0), (50, 50.0, 50.0), (100, 100.0, 50.0), (125, 62.5, 41.666666666666664), (250, 250 / 3, 50.0),
    (1000, 100.0, 50.0),
])  # fmt: skip
def test_output_rates_left_out_fit_the_physics_step(physics_hz, clock_hz, truth_hz):
    """/clock and ground truth left at their defaults run at 100 and 50 Hz or the nearest rate below that the step
    allows: fixed defaults of 100 and 50 Hz refused every physics rate below 100 Hz (and 125, 250 Hz) with an
    error about keys the file did not have."""
    scenario = {"version": 1, "world": {"physics_rate_hz": physics_hz}, "vessels": [{"name": "a", "model": "otter"}]}
    sim = Simulation(scenario)
    try:
        step_ns = sim.world.clock.step_ns
        assert sim.scenario.outputs.recording.rates_hz(step_ns) == pytest.approx((clock_hz, truth_hz), rel=1e-12)
        assert (sim.ground_truth.clock_every, sim.ground_truth.odom_every) == (
            round(1e9 / clock_hz / step_ns), round(1e9 / truth_hz / step_ns))
    finally:
        sim.close()


def test_version_is_required(scenario_of):
    from usvsim.config.loader import parse_scenario

    with pytest.raises(ScenarioError, match="version"):
        parse_scenario({"vessels": []}, "x.yaml")
    with pytest.raises(ScenarioError, match="version"):
        scenario_of({"version": 2})


def test_duplicate_names_rejected(scenario_of):
    with pytest.raises(ScenarioError, match="repeated: a"):
        scenario_of({"vessels": [{"name": "a", "model": "wamv"}, {"name": "a", "model": "otter"}]})


def test_unknown_vessel_model_names_the_key(scenario_of):
    sc = scenario_of({"vessels": [{"name": "a", "model": "titanic"}]})
    with pytest.raises(ScenarioError) as err:
        Simulation(sc)
    assert err.value.key_path == "vessels[0].model" and "wamv" in err.value.message


def test_custom_vessel_needs_mesh_and_mass(scenario_of, box_stl, tmp_path):
    with pytest.raises(ScenarioError, match="hull_mesh"):
        scenario_of({"vessels": [{"name": "a", "model": "custom"}]})
    sc = scenario_of({"vessels": [{"name": "a", "model": "custom", "hull_mesh": str(box_stl)}]}, tmp_path)
    with pytest.raises(ScenarioError, match="mass_kg"):
        Simulation(sc)


def test_missing_and_open_meshes_are_clear_errors(scenario_of, open_stl, tmp_path):
    missing = {"name": "a", "model": "custom", "hull_mesh": "nope.stl", "mass": {"mass_kg": 100.0}}
    with pytest.raises(MeshError, match="not found"):
        Simulation(scenario_of({"vessels": [missing]}, tmp_path))
    leaky = dict(missing, hull_mesh=open_stl.name)
    with pytest.raises(MeshError, match="not watertight"):
        Simulation(scenario_of({"vessels": [leaky]}, tmp_path))


def test_sections_are_frozen():
    sc = load_scenario("harbor")
    with pytest.raises(ValidationError, match="frozen"):
        sc.world.physics_rate_hz = 50.0


@pytest.mark.parametrize("rate_hz", [30.0, 33.33, 14.29, 7.0, 3.0])
def test_the_suggested_rate_is_accepted_when_copied(rate_hz):
    """The suggestion was printed with 6 digits (`33.3333`, `14.2857`): 1e-6 off the step, and refused in turn."""
    import re

    from usvsim.core.clock import steps_per_period

    with pytest.raises(ValueError, match="e.g.") as info:
        steps_per_period(rate_hz, 10_000_000)
    suggested = float(re.search(r"e\.g\. ([0-9.]+) Hz", str(info.value)).group(1))
    assert steps_per_period(suggested, 10_000_000) == round(1e9 / rate_hz / 10_000_000)


def test_a_misspelt_realization_method_is_named():
    """`realization: {method: ff}` said "unknown type None" (the tag is under `method`, not `type`)."""
    from usvsim.config.loader import parse_scenario
    from usvsim.core.errors import ScenarioError

    sea = {"type": "jonswap", "hs_m": 1.0, "tp_s": 4.0, "realization": {"method": "ff"}}
    with pytest.raises(ScenarioError, match=r"environment\.sea\.realization: unknown method 'ff'; expected one of 'fft'"):
        parse_scenario({"version": 1, "environment": {"sea": sea}}, "s.yaml")
    with pytest.raises(ScenarioError, match=r"objects\[0\]: unknown type 'bouy'"):
        parse_scenario({"version": 1, "objects": [{"type": "bouy", "name": "b", "position": [1, 2, 0]}]}, "s.yaml")
