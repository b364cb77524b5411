"""The scenario reference: JSON Schema from the models, docs/scenario-reference.md in sync with them,
"did you mean" for misspelt keys; every scenario the project ships validates against the schema."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.config.loader import parse_scenario
from usvsim.config.schema import reference_markdown, scenario_schema
from usvsim.core.errors import ScenarioError

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "src/usvsim/scenarios").glob("*.yaml")) + [ROOT / "examples/my_harbour.yaml"]


def test_reference_doc_is_generated_from_the_models():
    """Regenerate with `usvsim schema --reference > docs/scenario-reference.md`."""
    assert (ROOT / "docs/scenario-reference.md").read_text() == reference_markdown()


def test_schema_command_prints_a_schema_that_shipped_scenarios_satisfy():
    jsonschema = pytest.importorskip("jsonschema")
    result = CliRunner().invoke(app, ["schema"])
    assert result.exit_code == 0
    schema = json.loads(result.output)
    assert schema == scenario_schema()
    for path in SHIPPED:
        jsonschema.validate(yaml.safe_load(path.read_text()), schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"version": 1, "wrold": {}}, schema)


@pytest.mark.parametrize("data, message", [
    ({"enviroment": {}}, "enviroment: unknown key (did you mean 'environment'?)"),
    ({"vessels": [{"name": "a", "model": "wamv", "pose": {"yaw_dge": 3}}]}, "vessels[0].pose.yaw_dge: unknown key (did you mean 'yaw_deg'?)"),
    ({"environment": {"sea": {"type": "jonswap", "hs_m": 1, "tp_s": 5, "hs": 2}}}, "environment.sea.hs: unknown key (did you mean 'hs_m'?)"),
    ({"vessels": [{"name": "a", "model": "wamv", "sensors": [{"type": "lidar", "name": "l", "chanels": 4}]}]}, "sensors[0].chanels: unknown key (did you mean 'channels'?)"),
    ({"vessels": [{"name": "a", "model": "wamv", "controller": {"type": "station_keeping", "hold": {"position_gain": 1}}}]}, "(did you mean 'position_gain_1ps'?)"),
    ({"world": {"zzz": 1}}, "world.zzz: unknown key (allowed: physics_rate_hz, gravity_mps2,"),
    # a required key misspelt: the unknown key and its suggestion, not "position: missing (+1 more error)" (QA)
    ({"traffic": {"ships": [{"name": "s", "mmsi": 257000001, "motion": {"type": "constant", "positon": [1, 2],
      "course_deg": 0, "speed_mps": 1}}]}}, "traffic.ships[0].motion.positon: unknown key (did you mean 'position'?)"),
    ({"vessels": [{"nmae": "a", "model": "wamv"}]}, "vessels[0].nmae: unknown key (did you mean 'name'?)"),
])  # fmt: skip
def test_unknown_keys_get_a_suggestion(data, message):
    with pytest.raises(ScenarioError) as err:
        parse_scenario({"version": 1, **data}, "my.yaml")
    assert message in str(err.value)


def test_yaml_blocks_in_docs_are_valid_scenarios():
    """Every YAML block of the docs that is a whole scenario (`version:` and only scenario sections; other
    files have versions too) validates as shipped."""
    sections = set(scenario_schema()["properties"])
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for block in re.findall(r"```yaml\n(.*?)```", doc.read_text(), flags=re.DOTALL):
            data = yaml.safe_load(block)
            if not (isinstance(data, dict) and "version" in data and set(data) <= sections):
                continue
            if doc.name == "README.md":
                parse_scenario(data, str(doc), ROOT / "examples")  # its meshes ship in examples/meshes
            elif "geo" not in data:  # docs/geo.md's files are checked by tests/geo/test_geo_docs.py
                parse_scenario(data, str(doc), ROOT)
