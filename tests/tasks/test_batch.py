"""usvsim.batch: the same metrics whatever the backend and worker count; the sweep CLI."""

import json

import pytest
from typer.testing import CliRunner

from usvsim.batch import expand, run
from usvsim.cli.app import app

SPEC = {"task": "station_keeping", "difficulty": 1, "seeds": {"start": 0, "count": 4},
        "time_limit_s": 1.0, "grid": {"mass_kg": [180.0, 250.0]}}  # fmt: skip


def _metrics(results):
    return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in results]


def test_expand_is_the_grid_product():
    runs = expand(SPEC)
    assert len(runs) == 8 and [r.seed for r in runs[:4]] == [0, 1, 2, 3] and runs[4].mass_kg == 250.0


@pytest.fixture(scope="module")
def in_process():
    """The 8 runs one after another in this process (workers=1)."""
    return _metrics(run(expand(SPEC), "process", workers=1))


def test_process_backend_two_workers_identical(in_process):
    assert _metrics(run(expand(SPEC), "process", workers=2)) == in_process
    assert len({r["score"] for r in in_process}) == 8  # seeds and masses all differ


def test_ray_backend_identical(in_process):
    pytest.importorskip("ray")
    assert _metrics(run(expand(SPEC), "ray", workers=2)) == in_process


def test_sweep_cli(tmp_path):
    spec = tmp_path / "sweep.yaml"
    spec.write_text("task: follow_path\nseeds: [0, 1]\ntime_limit_s: 2\nworkers: 1\n")
    out = tmp_path / "runs.jsonl"
    result = CliRunner().invoke(app, ["sweep", str(spec), "--out", str(out)])
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in out.read_text().splitlines()]
    assert [r["run"]["seed"] for r in rows] == [0, 1]
    bad = tmp_path / "bad.yaml"
    bad.write_text("task: station_keeping\nseeds: [0]\nbackend: spark\n")
    result = CliRunner().invoke(app, ["sweep", str(bad)])
    assert result.exit_code == 2 and "backend" in result.output
