"""The `environment` section and building the ocean from it."""

import math

import numpy as np
import pydantic
import pytest

from usvsim.config.environment import Environment
from usvsim.core.rng import RngStreams
from usvsim.ocean import DirectWaveField, FFTWaveField, build_ocean
from usvsim.ocean.presets import SEA_STATES, VRX_PRESETS


def ocean(data, seed=0):
    return build_ocean(Environment.model_validate(data), RngStreams(seed).get("ocean"))


def test_defaults_are_flat_calm_and_still():
    o = ocean({})
    assert o.waves is None
    np.testing.assert_array_equal(o.elevation(np.zeros(2), np.zeros(2), 5.0), 0.0)
    np.testing.assert_array_equal(o.wind_velocity(5.0), 0.0)


@pytest.mark.parametrize(
    "data",
    [
        {"sea": {"type": "jonswap", "hs_m": 1.0, "tp_s": 6.0, "bogus": 1}},
        {"wind": {"speed": 3.0}},
        {"current": {"shear": {"profile": "linear", "depth": 3}}},
        {"sea": {"type": "tsunami"}},
        {"wind": {"direction": 1.0, "direction_deg": 57.0}},
        {"sea": {"type": "pierson_moskowitz", "hs_m": 1.0}},
        {"sea": {"type": "pierson_moskowitz", "hs_m": 1.0, "tp_s": 5.0, "from_wind": True}},
        {"sea": {"type": "jonswap", "hs_m": 1.0, "tp_s": 6.0, "spreading_s": None}},
        {"sea": {"type": "sea_state", "code": 10}},
        {"sea": {"type": "vrx", "preset": "stormy"}},
        {"sea": {"type": "regular", "components": [{"amplitude_m": 0.1}]}},
    ],
)
def test_invalid_sections_are_rejected(data):
    with pytest.raises(pydantic.ValidationError):
        Environment.model_validate(data)


def test_same_seed_same_sea_other_seed_other_sea():
    data = {
        "sea": {
            "type": "jonswap",
            "hs_m": 2.0,
            "tp_s": 8.0,
            "choppiness": 0.5,
            "realization": {"resolution": 64},
        },
        "wind": {"speed_mps": 5.0, "gust_gain": 2.0},
    }
    x = np.linspace(0, 50, 20)
    a, b, c = ocean(data, 1), ocean(data, 1), ocean(data, 2)
    np.testing.assert_array_equal(a.elevation(x, x, 3.0), b.elevation(x, x, 3.0))
    np.testing.assert_array_equal(a.wind_velocity(3.0), b.wind_velocity(3.0))
    assert not np.array_equal(a.elevation(x, x, 3.0), c.elevation(x, x, 3.0))


def test_changing_the_wind_does_not_change_the_sea():
    sea = {"type": "jonswap", "hs_m": 2.0, "tp_s": 8.0, "realization": {"resolution": 64}}
    x = np.linspace(0, 50, 20)
    a = ocean({"sea": sea})
    b = ocean({"sea": sea, "wind": {"speed_mps": 9.0, "gust_gain": 3.0}})
    np.testing.assert_array_equal(a.elevation(x, x, 3.0), b.elevation(x, x, 3.0))


def test_wind_sea_takes_speed_and_direction_from_the_wind():
    o = ocean(
        {
            "sea": {"type": "pierson_moskowitz", "from_wind": True, "realization": {"method": "direct"}},
            "wind": {"speed_mps": 10.0, "direction_deg": 90.0},
            "ramp_time_s": 0.0,
        }
    )
    c = o.waves.components
    assert 4 * math.sqrt(c.variance) == pytest.approx(2.133, rel=0.02)
    mean = math.atan2(
        np.sum(c.amplitude**2 * np.sin(c.direction)), np.sum(c.amplitude**2 * np.cos(c.direction))
    )
    assert mean == pytest.approx(math.pi / 2, abs=0.15)


def test_presets():
    assert ocean({"sea": {"type": "sea_state", "code": 0}}).waves is None
    o = ocean({"sea": {"type": "sea_state", "code": 5, "realization": {"resolution": 64}}})
    assert isinstance(o.waves, FFTWaveField)
    assert SEA_STATES[5].hs_m == 3.25
    o = ocean({"sea": {"type": "vrx", "preset": "rough", "gain": 0.5}, "wind": {"preset": "rough"}})
    assert isinstance(o.waves, DirectWaveField)
    p = VRX_PRESETS["rough"]
    np.testing.assert_allclose(o.waves.components.direction, p.direction + np.array([-0.4, 0.0, 0.4]))
    assert o.wind.speed_mps == p.wind_speed_mps and o.wind.direction == p.wind_direction


def test_gerstner_components_and_ramp():
    o = ocean(
        {
            "sea": {
                "type": "gerstner",
                "components": [
                    {"amplitude_m": 0.5, "wavelength_m": 20.0, "steepness": 0.8},
                    {
                        "amplitude_m": 0.25,
                        "wavelength_m": 9.0,
                        "direction_deg": 30.0,
                        "phase": 1.0,
                        "steepness": 0.8,
                    },
                    {
                        "amplitude_m": 0.1,
                        "wavelength_m": 4.0,
                        "direction_deg": -45.0,
                        "phase": 2.0,
                        "steepness": 0.8,
                    },
                ],
            },
            "ramp_time_s": 0.0,
            "water_level_m": 0.5,
        }
    )
    assert o.elevation(np.array([3.0]), np.array([1.0]), 2.0)[0] == pytest.approx(0.5 - 0.683306, abs=1e-6)


def test_phillips_bands_follow_hdrp():
    o = ocean({"sea": {"type": "phillips", "repetition_size_m": 500.0}})
    np.testing.assert_allclose(o.waves.sizes, [500.0, 500.0 / (5 + 45 * 250 / 4750), 10.0])
    with pytest.raises(ValueError, match="resolution"):
        ocean({"sea": {"type": "phillips", "resolution": 64}})


def test_vrx_preset_names_in_the_schema_text_are_the_presets():
    from usvsim.config.environment import PRESETS
    from usvsim.ocean.presets import VRX_PRESETS

    assert PRESETS == ", ".join(VRX_PRESETS)


def test_an_unknown_wind_preset_is_reported_at_its_key(scenario_of):
    from usvsim.core.errors import ScenarioError

    with pytest.raises(ScenarioError) as err:  # it was reported at environment.sea
        scenario_of({"environment": {"wind": {"preset": "nope"}}, "vessels": [{"name": "w", "model": "wamv"}]})
    assert err.value.key_path.startswith("environment.wind") and "unknown VRX preset 'nope'" in str(err.value)
