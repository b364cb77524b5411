"""User mistakes with outputs and durations, in-process (no subprocess start-up): one line, exit 2."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from usvsim.cli.app import app


def invoke(*args):
    return CliRunner().invoke(app, list(args))


def one_line_error(result, *words):
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and result.stdout == "", result.stderr
    for word in words:
        assert word in lines[0]


@pytest.mark.parametrize(("target", "words"), [("missing/run.mcap", ["does not exist"]), (".", ["is a directory"]),
                                               ("taken.mcap", ["exists", "--force"])])  # fmt: skip
def test_bad_recording_targets_are_one_line(tmp_path, monkeypatch, target, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken.mcap").write_bytes(b"precious")
    one_line_error(invoke("run", "--duration", "0.1", "--record", target), *words)
    assert (tmp_path / "taken.mcap").read_bytes() == b"precious"


def test_nonfinite_duration_is_one_line():
    one_line_error(invoke("run", "--duration", "inf"), "--duration")


def test_low_physics_rate_runs_exactly_the_duration_and_force_overwrites(tmp_path):
    scenario = tmp_path / "slow.yaml"
    scenario.write_text("version: 1\nworld: {physics_rate_hz: 20}\noutputs: {recording: {clock_rate_hz: 20, "
                        "ground_truth_rate_hz: 20}}\nvessels: [{name: otter, model: otter}]\n")  # fmt: skip
    out = tmp_path / "run.mcap"
    out.write_bytes(b"old")
    result = invoke("run", str(scenario), "--duration", "1.3", "--record", str(out), "--force")
    assert result.exit_code == 0, result.output
    assert "simulated 1.30 s" in result.stdout and out.stat().st_size > 1000
