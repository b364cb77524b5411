"""The inverse thrust maps against the simulator's forward map."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.control.thrust_inverse import command_for_thrust, commands
from usvsim.hydro.thrusters import MAP_CODES, thrust_map


@pytest.mark.parametrize("kind", list(MAP_CODES.values()))
def test_round_trip(kind):
    for u in np.linspace(-1.0, 1.0, 801):
        t = thrust_map(u, kind, 250.0, 100.0)
        assert abs(command_for_thrust(t, kind, 250.0, 100.0) - u) < 1e-9
        assert abs(thrust_map(command_for_thrust(t, kind, 250.0, 100.0), kind, 250.0, 100.0) - t) < 1e-6


@pytest.mark.parametrize("kind", list(MAP_CODES.values()))
def test_saturates_beyond_range(kind):
    assert command_for_thrust(1e4, kind, 250.0, 100.0) == 1.0
    assert command_for_thrust(-1e4, kind, 250.0, 100.0) == -1.0
    np.testing.assert_allclose(commands([0.0, 62.5], [kind, kind], [250.0, 250.0], [100.0, 100.0])[0], 0.0)
