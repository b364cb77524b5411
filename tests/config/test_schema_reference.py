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
    # a key one level too high says where it goes (QA: this said "did you mean 'max_rate_n_s'?", and a top-level
    # `sensors` listed the top-level keys)
    ({"vessels": [{"name": "a", "model": "wamv", "thrusters": [{"name": "t", "position": [0, 0, 0], "max_forward_n": 9}]}]},
     "vessels[0].thrusters[0].max_forward_n: unknown key (it belongs under 'thrust': thrust.max_forward_n)"),
    ({"sensors": []}, "sensors: unknown key (it belongs under 'vessels': vessels[].sensors)"),
    ({"vessels": [{"name": "a", "model": "wamv", "position": [1, 2, 0]}]}, "(it belongs under 'pose': pose.position)"),
    ({"world": {"latitude_deg": 10}}, "world.latitude_deg: unknown key (it belongs under 'origin': origin.latitude_deg)"),
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


def _reference_rows() -> dict[tuple[str, str], tuple[str, str, str]]:
    """(section, key) → (type, unit, description) of docs/scenario-reference.md's tables."""
    rows, section = {}, ""
    for line in reference_markdown().splitlines():
        if line.startswith("## "):
            section = line[3:]
        elif line.startswith("| `"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            rows[(section, cells[0].strip("`"))] = (cells[1], cells[2], cells[4])
    return rows


def test_reference_states_units_frames_and_optional_descriptions():
    """QA of the reference: positions read "list of number | number | number" with no unit or frame, c_n had the
    unit N (its suffix), the description of an optional key (PM's wind_speed_mps) was dropped, wind/current
    `direction` had no unit nor said toward/from, Sun.azimuth_deg's compass convention was only a code comment."""
    from usvsim.vessels.library import LIBRARY

    rows = _reference_rows()
    assert not [k for k, (kind, _, _) in rows.items() if "list of number \\| number" in kind]
    assert rows[("Pose", "position")][:2] == ("[number, number, number]", "m") and "ENU" in rows[("Pose", "position")][2]
    assert "FLU" in rows[("Mount", "position")][2] and "FLU" in rows[("Thruster", "position")][2]
    for (section, key), (_, unit, text) in rows.items():  # every position says its frame
        if key == "position":
            assert unit == "m" and ("ENU" in text or "FLU" in text), (section, text)
    assert rows[("WindLoad", "c_n")][1] == "" and rows[("ThrustMap", "max_forward_n")][1] == "N"
    assert "19.5 m" in rows[("PiersonMoskowitzSea", "wind_speed_mps")][2]
    unit, text = rows[("WindConfig", "direction")][1:]
    assert unit == "rad" and "toward" in text and "counter-clockwise from east" in text
    assert "clockwise from north" in rows[("Sun", "azimuth_deg")][2]
    assert rows[("KernerHydrodynamics", "kinematic_viscosity_m2ps")][1] == "m²/s"
    assert all(name in rows[("Vessel", "model")][2] for name in LIBRARY)
    assert "relative to the scenario file" in rows[("MeshObstacle", "file")][2]
    assert "estimated linear drag" in rows[("Vessel", "hydrodynamics")][2]  # what a custom hull gets by default


def test_every_reference_section_says_what_it_is():
    """World, Environment, Outputs, Traffic, Ship, Waypoint, JonswapSea, ... had a bare table (QA)."""
    text = reference_markdown()
    bare = [s.split("\n", 1)[0] for s in text.split("\n## ")[2:] if s.split("\n")[2].startswith("|")]
    assert bare == []
