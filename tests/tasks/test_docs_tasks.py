"""docs/tasks.md: every Python and shell block runs as written; the sweep example file matches the docs."""

import re
import shlex
from pathlib import Path

import pytest
from typer.testing import CliRunner

from usvsim.cli.app import app

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs/tasks.md").read_text()


def blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", DOC, flags=re.DOTALL)


@pytest.mark.parametrize("index", range(len(blocks("python"))))
def test_python_blocks_run(index, monkeypatch, tmp_path):
    code = blocks("python")[index]
    for module in ("gymnasium", "pettingzoo", "stable_baselines3"):
        if f"import {module}" in code or f"from {module}" in code or (module != "stable_baselines3" and ".gym" in code):
            pytest.importorskip(module)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"docs/tasks.md block {index}", "exec"), {})


def test_shell_blocks_run(monkeypatch, tmp_path):
    monkeypatch.chdir(ROOT)
    for command in blocks("bash"):
        args = shlex.split(command.strip())
        assert args[0] == "usvsim"
        args = [a.replace("out/", f"{tmp_path}/") for a in args[1:]]
        result = CliRunner().invoke(app, args)
        assert result.exit_code == 0, result.output


def test_sweep_example_is_the_documented_one():
    (yaml_block,) = blocks("yaml")
    assert yaml_block.split("\n", 1)[1] == (ROOT / "examples/sweep_station_keeping.yaml").read_text().split("\n", 1)[1]
