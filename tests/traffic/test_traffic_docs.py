"""docs/traffic.md: its scenario and radar YAML validate, its Python runs, its shell lines run; the figure
script runs (quick mode)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from pydantic import TypeAdapter

from usvsim.config.loader import parse_scenario
from usvsim.config.sensors import Sensor

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "traffic.md"


def blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", DOC.read_text(), flags=re.S)


def test_yaml_blocks_validate():
    scenario, avoidance, radar = blocks("yaml")
    parse_scenario(yaml.safe_load(scenario), "docs/traffic.md")
    vessels = [{"name": "own", "model": "wamv", "controller": {"type": "velocity"}}]
    parse_scenario({"version": 1, "vessels": vessels, **yaml.safe_load(avoidance)}, "docs/traffic.md")
    TypeAdapter(Sensor).validate_python(yaml.safe_load(radar)["sensors"][0])


def test_python_blocks_run(capsys):
    report, avoidance = blocks("python")
    exec(compile(report, "docs/traffic.md", "exec"), {})
    assert capsys.readouterr().out.startswith("[2]")
    exec(compile(avoidance, "docs/traffic.md", "exec"), {})
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "target_1 127 None crossing_give_way 30 True"  # the line the page shows


def test_shell_lines_run(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    for line in "".join(blocks("bash")).strip().splitlines():
        args = line.split()
        assert args[0] == "usvsim"
        subprocess.run([sys.executable, "-m", "usvsim.cli", *args[1:]], cwd=tmp_path, env=env, check=True,
                       capture_output=True)  # fmt: skip
    assert (tmp_path / "imazu14_otter.yaml").is_file()
    assert "avoidance: {type: velocity_obstacle}" in (tmp_path / "imazu01_avoid.yaml").read_text()


@pytest.mark.slow  # renders a camera and runs an encounter: about a minute on a loaded machine
def test_figure_script_runs(tmp_path):
    env = dict(os.environ, MUJOCO_GL="egl", PYTHONPATH=str(ROOT / "src"))
    subprocess.run([sys.executable, str(ROOT / "examples/traffic_figures.py"), str(tmp_path), "--quick"], env=env,
                   check=True, capture_output=True)  # fmt: skip
    assert (tmp_path / "traffic_radar.png").stat().st_size > 10_000
    assert (tmp_path / "traffic_encounter.png").stat().st_size > 10_000


def test_the_example_run_report_is_what_the_run_prints(tmp_path):
    """The report table in docs/traffic.md is the one `usvsim run` prints for the scenario the text describes (a
    ship stopped 200 m east, one crossing 30 m north westward at 5 m/s from 100 m east, 30 s). It said TCPA 19.0
    where the run gives 18.0 (QA)."""
    doc = DOC.read_text()
    table = re.search(r"```\n(target +min dist.*?)```", doc, flags=re.S)
    assert table is not None
    expected = [line.split() for line in table.group(1).strip().splitlines()]
    scenario = tmp_path / "report.yaml"
    scenario.write_text(
        "version: 1\nvessels:\n  - {name: wamv, model: wamv}\ntraffic:\n  ships:\n"
        "    - {name: still, mmsi: 257000061, motion: {type: route, waypoints: [{position: [200, 0], speed_mps: 0},"
        " {position: [200, 10], speed_mps: 0}]}}\n"
        "    - {name: crosser, mmsi: 257000062, motion: {type: constant, position: [100, 30], course_deg: 270, speed_mps: 5}}\n"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), COLUMNS="200")
    out = subprocess.run([sys.executable, "-m", "usvsim.cli", "run", str(scenario), "--duration", "30"], env=env,
                         check=True, capture_output=True, text=True).stdout  # fmt: skip
    rows = [line.split() for line in out.splitlines() if line.split() and line.split()[0] in ("target", "still", "crosser")]
    assert rows == expected


def test_the_reference_says_the_radar_turns_clockwise():
    """Marine radars turn clockwise seen from above; usvsim's spoke k points at -k·360°/n (REP 103, CCW from the
    bow), i.e. clockwise. The schema (and so docs/scenario-reference.md) said 'CCW seen from above' (QA)."""
    from usvsim.config.sensors import Radar
    from usvsim.sensors.radar.revolution import spoke_angle

    assert spoke_angle(1, 360) < 0.0  # spoke 1 is 1° to starboard: clockwise
    text = (ROOT / "docs" / "scenario-reference.md").read_text()
    section = text[text.index("X-band marine radar") :].split("\n")[0]
    assert Radar.__doc__ is not None and "clockwise seen from above" in " ".join(Radar.__doc__.split())
    assert "clockwise seen from above" in section and "CCW seen from above" not in section
