"""Fixtures for sensor tests."""

from __future__ import annotations

import pytest
from sensor_rig import Collector, make_sim, sensor_configs

from usvsim.sensors import SensorSuite


@pytest.fixture
def rig():
    """rig(*sensor_dicts, **make_sim_kwargs) -> (sim, suite, collector) for one WAM-V named 'wamv'."""

    def make(*sensor_dicts, **sim_kwargs):
        sim = make_sim(**sim_kwargs)
        suite = SensorSuite(sim.world, {"wamv": sensor_configs(*sensor_dicts)})
        return sim, suite, Collector(sim, suite)

    return make
