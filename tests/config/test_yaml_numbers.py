"""Numbers with an exponent and no decimal point (`1e9`, `5e-2`) are numbers in a scenario, as in YAML 1.2 and
JSON; PyYAML's YAML 1.1 reads them as text, and the schema then said "Input should be a valid number (got '5e-2')"."""

from __future__ import annotations

import pytest
import yaml

from usvsim.config.loader import parse_scenario
from usvsim.config.safe_yaml import parse


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1e9", 1e9),
        ("5e-2", 0.05),
        ("-1.5E+3", -1500.0),
        ("+2e0", 2.0),
        ("1_0e1", 100.0),
        ("12", 12),
        ("0.5", 0.5),
    ],
)
def test_exponent_numbers_are_numbers(text, value):
    out = parse(f"v: {text}\n", "t.yaml")["v"]
    assert out == value and type(out) is type(value)


@pytest.mark.parametrize("text", ["1e", "e5", "3e0x", "'1e9'", "1e9 m"])
def test_other_text_stays_text(text):
    assert isinstance(parse(f"v: {text}\n", "t.yaml")["v"], str)


def test_the_global_pyyaml_loader_is_left_alone():
    assert yaml.safe_load("v: 1e9") == {"v": "1e9"}


def test_a_scenario_value_written_with_an_exponent_is_accepted():
    text = "version: 1\nvessels: [{name: w, model: otter, buoyancy: {type: voxels, voxel_size_m: 5e-2}}]\n"
    scenario = parse_scenario(parse(text, "t.yaml"), "t.yaml", None)
    assert scenario.vessels[0].buoyancy.voxel_size_m == 0.05


def test_a_validator_message_has_no_pydantic_prefix():
    """Errors of usvsim's own validators read "names of ... must be unique", not "Value error, names ..."."""
    from usvsim.core.errors import ScenarioError

    text = "version: 1\nvessels: [{name: w, model: wamv}, {name: w, model: otter}]\n"
    with pytest.raises(ScenarioError) as info:
        parse_scenario(parse(text, "t.yaml"), "t.yaml", None)
    assert "unique" in str(info.value) and "Value error" not in str(info.value)


def test_yes_no_on_off_are_text_as_in_yaml_1_2():
    """`navigation: off` (a documented value) arrived as False and was refused as "should be 'auto', 'on' or 'off'
    (got False)"; `name: no` became False (QA). Booleans are true/false only, as YAML 1.2 and the YAML language
    server read them; a yes for a boolean says what to write."""
    from usvsim.core.errors import ScenarioError

    text = "version: 1\nname: no\nrendering: {lights: {navigation: off}, shadows: true, materials: False}\n"
    scenario = parse_scenario(parse(text, "t.yaml"), "t.yaml", None)
    assert scenario.name == "no" and scenario.rendering.lights.navigation == "off"
    assert scenario.rendering.shadows is True and scenario.rendering.materials is False
    with pytest.raises(ScenarioError) as info:
        parse_scenario(parse("version: 1\nrendering: {shadows: yes}\n", "t.yaml"), "t.yaml", None)
    assert info.value.key_path == "rendering.shadows" and "should be true or false (got the text 'yes')" in str(info.value)
