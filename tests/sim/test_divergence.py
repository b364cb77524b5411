"""Divergence detection beyond NaN: a body past the scenario's speed limit stops the run, naming that body."""

from __future__ import annotations

import pytest

from usvsim.core.errors import DivergenceError


def test_speed_limit_names_the_falling_body_not_the_first(scenario_of):
    from usvsim.simulation import Simulation

    scenario = scenario_of({
        "world": {"divergence": {"max_speed_mps": 1.1}},
        "vessels": [{"name": "calm", "model": "otter"},
                    {"name": "dropped", "model": "otter", "pose": {"position": [20.0, 0.0, 3.0]}}],
    })  # fmt: skip
    sim = Simulation(scenario)
    try:
        with pytest.raises(DivergenceError) as err:
            sim.run(2.0)  # deterministic: the settling one peaks at 0.86 m/s, the dropped one passes 1.1 m/s
    finally:
        sim.close()
    assert err.value.body == "dropped" and 0.1 < err.value.time_s < 1.0
    assert "world.divergence.max_speed_mps" in str(err.value)
