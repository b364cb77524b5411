"""usvsim experiment detection-robustness checks its environment before it makes its data sets (minutes of
rendering). Before: USVSIM_YOLO_PYTHON=/nonexistent was a FileNotFoundError traceback after both sets were
made; a Python without ultralytics failed after them too (/bin/ls: a traceback reading yolo_result.json);
USVSIM_DR_TRAIN=abc was a ValueError traceback and USVSIM_DR_TRAIN=-3 said 'frames must be >= 1 and the
splits ...' without naming the variable."""

import sys

import pytest
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.experiments import detection_robustness


def never(*_args, **_kw):
    raise AssertionError("the data sets were made although the run cannot finish")


@pytest.mark.parametrize(
    ("env", "words"),
    [
        ({"USVSIM_YOLO_PYTHON": "/nonexistent/python"}, "USVSIM_YOLO_PYTHON='/nonexistent/python': no such executable"),
        ({"USVSIM_YOLO_PYTHON": "/bin/ls"}, "USVSIM_YOLO_PYTHON='/bin/ls': cannot import ultralytics"),
        ({"USVSIM_DR_TRAIN": "abc"}, "USVSIM_DR_TRAIN='abc': must be a whole number >= 2"),
        ({"USVSIM_DR_TRAIN": "-3"}, "USVSIM_DR_TRAIN='-3': must be a whole number >= 2"),
        ({"USVSIM_DR_EPOCHS": "0"}, "USVSIM_DR_EPOCHS='0': must be a whole number >= 1"),
    ],
)
def test_bad_environment_is_one_line_before_any_data_set(tmp_path, monkeypatch, env, words):
    monkeypatch.setattr(detection_robustness, "generate", never)
    monkeypatch.setenv("USVSIM_YOLO_PYTHON", sys.executable)  # has no ultralytics here: checked after the sizes
    for key, value in env.items():
        monkeypatch.setenv(key, value)
    result = CliRunner().invoke(app, ["experiment", "detection-robustness", "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and words in lines[0], result.stderr
    assert not (tmp_path / "out" / "detection_robustness_data").exists()
