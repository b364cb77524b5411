"""docs/geo.md: its scenario validates against the shipped sample files; its Python and shell lines run."""

from __future__ import annotations

import re
import shutil
from importlib import resources
from pathlib import Path

from typer.testing import CliRunner

from usvsim.cli.app import app

DOC = Path(__file__).resolve().parents[2] / "docs" / "geo.md"


def blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", DOC.read_text(), flags=re.DOTALL)


def test_geo_doc_scenario_validates_with_the_sample_place(tmp_path):
    shutil.copytree(Path(str(resources.files("usvsim.scenarios"))) / "geo", tmp_path / "geo")
    (text,) = blocks("yaml")
    (tmp_path / "my_place.yaml").write_text(text)
    result = CliRunner().invoke(app, ["validate", str(tmp_path / "my_place.yaml")])
    assert result.exit_code == 0, result.output


def test_geo_doc_python_and_commands_run(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (code,) = blocks("python")
    exec(compile(code, "docs/geo.md", "exec"), {})
    assert "[" in capsys.readouterr().out
    (shell,) = blocks("bash")
    for line in shell.strip().splitlines():
        args = line.split("#")[0].split()
        assert args[0] == "usvsim"
        if args[1] == "run":
            args[args.index("--duration") + 1] = "1"
        assert CliRunner().invoke(app, args[1:]).exit_code == 0, line
