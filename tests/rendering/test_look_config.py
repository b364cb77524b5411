"""The `rendering:` look section: strict validation, merging changes, the sun from a UTC time."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from pydantic import ValidationError

from usvsim.config.rendering import Rendering, solar_angles_deg, sun_angles_deg, sun_direction_enu

ROOT = Path(__file__).resolve().parents[2]


def test_bad_values_name_the_key():
    for bad, key in [({"sun": {"elevation_deg": 95}}, "sun.elevation_deg"), ({"fog": {"colour": [1, 1, 1]}}, "fog.colour"),
                     ({"sun": {"utc": "noon"}}, "sun.utc"), ({"water": {"color": [1, 2, 0]}}, "water.color.1")]:  # fmt: skip
        with pytest.raises(ValidationError, match=re.escape(key)):
            Rendering.model_validate(bad)
    with pytest.raises(ValidationError, match="not both"):
        Rendering.model_validate({"sun": {"utc": "2025-06-21T12:00:00Z", "elevation_deg": 10}})


def test_updated_merges_and_switches_between_time_and_angles():
    look = Rendering().updated({"fog": {"visibility_m": 300.0}, "sun": {"elevation_deg": 5.0}})
    assert look.fog.visibility_m == 300.0 and look.fog.color == Rendering().fog.color and look.sun.elevation_deg == 5.0
    timed = look.updated({"sun": {"utc": "2025-06-21T04:00:00Z"}})
    assert timed.sun.utc is not None and timed.fog.visibility_m == 300.0
    assert timed.updated({"sun": {"azimuth_deg": 10.0}}).sun.utc is None
    with pytest.raises(ValidationError):
        look.updated({"camera": {"exposure_ev": "bright"}})


def test_solar_position_matches_closed_forms():
    # equinox, solar noon on the equator at Greenwich (equation of time ~ -7.5 min): sun ~ overhead
    az, el = solar_angles_deg("2025-03-20T12:07:30Z", 0.0, 0.0)
    assert el == pytest.approx(90.0, abs=1.0)
    # June solstice noon at 59.42° N: elevation 90 - 59.42 + 23.44 = 54.0°, due south
    az, el = solar_angles_deg("2025-06-21T11:18:00Z", 59.42, 10.43)
    assert el == pytest.approx(54.0, abs=0.5) and az == pytest.approx(180.0, abs=3.0)
    # morning: the sun is in the east half; evening: the west half
    assert 0 < solar_angles_deg("2025-06-21T06:00:00Z", 59.42, 10.43)[0] < 180
    assert 180 < solar_angles_deg("2025-06-21T17:00:00Z", 59.42, 10.43)[0] < 360
    look = Rendering().updated({"sun": {"azimuth_deg": 90.0, "elevation_deg": 0.0}})
    assert sun_angles_deg(look, 0, 0) == (90.0, 0.0)
    assert sun_direction_enu(90.0, 0.0) == pytest.approx((1.0, 0.0, 0.0))  # east


def test_docs_examples_run(capsys):
    text = (ROOT / "docs/rendering.md").read_text()
    (yaml_block,) = re.findall(r"```yaml\n(.*?)```", text, flags=re.DOTALL)
    import yaml

    assert Rendering.model_validate(yaml.safe_load(yaml_block)["rendering"]) == Rendering()
    for code in re.findall(r"```python\n(.*?)```", text, flags=re.DOTALL):
        exec(compile(code, "docs/rendering.md", "exec"), {})
    assert "(250.0, 8.0)" in capsys.readouterr().out
