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
    scenario, radar = blocks("yaml")
    parse_scenario(yaml.safe_load(scenario), "docs/traffic.md")
    TypeAdapter(Sensor).validate_python(yaml.safe_load(radar)["sensors"][0])


def test_python_block_runs(capsys):
    (code,) = blocks("python")
    exec(compile(code, "docs/traffic.md", "exec"), {})
    assert capsys.readouterr().out.startswith("[2]")


def test_shell_lines_run(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    for line in blocks("bash")[0].strip().splitlines():
        args = line.split()
        assert args[0] == "usvsim"
        subprocess.run([sys.executable, "-m", "usvsim.cli", *args[1:]], cwd=tmp_path, env=env, check=True,
                       capture_output=True)  # fmt: skip
    assert (tmp_path / "imazu14_otter.yaml").is_file()


@pytest.mark.slow  # renders a camera and runs an encounter: about a minute on a loaded machine
def test_figure_script_runs(tmp_path):
    env = dict(os.environ, MUJOCO_GL="egl", PYTHONPATH=str(ROOT / "src"))
    subprocess.run([sys.executable, str(ROOT / "examples/traffic_figures.py"), str(tmp_path), "--quick"], env=env,
                   check=True, capture_output=True)  # fmt: skip
    assert (tmp_path / "traffic_radar.png").stat().st_size > 10_000
    assert (tmp_path / "traffic_encounter.png").stat().st_size > 10_000
