"""usvsim.batch: the same metrics whatever the backend and worker count; the sweep CLI."""

import importlib.util
import json
from pathlib import Path

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


def test_a_stopped_sweep_keeps_its_finished_runs_and_ends_its_workers():
    """`stop()` raising once a run has come in (as the CLI's Ctrl-C / SIGTERM check does): the finished runs are
    kept, the running ones end with their workers (none is left running)."""
    import multiprocessing

    from usvsim.cli.stopping import Stopped

    runs = expand({**SPEC, "seeds": {"start": 0, "count": 6}, "time_limit_s": 2.0, "grid": {}})
    finished: list = [None] * len(runs)

    def stop():
        if any(r is not None for r in finished):
            raise Stopped(15)

    with pytest.raises(Stopped):
        run(runs, "process", workers=2, stop=stop, finished=finished)
    done = [r for r in finished if r is not None]
    assert 1 <= len(done) < len(runs)
    assert all(r["run"]["task"] == "station_keeping" and "score" in r for r in done)
    assert multiprocessing.active_children() == []


def test_sweep_stopped_by_sigterm_writes_the_finished_runs_and_leaves_no_worker(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    spec = tmp_path / "sweep.yaml"
    spec.write_text("task: station_keeping\nseeds: {start: 0, count: 4}\ntime_limit_s: 600\nworkers: 2\n")
    out = tmp_path / "runs.jsonl"
    proc = subprocess.Popen([sys.executable, "-m", "usvsim", "sweep", str(spec), "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    children = Path(f"/proc/{proc.pid}/task/{proc.pid}/children")
    deadline, workers = time.monotonic() + 240, []
    while time.monotonic() < deadline and proc.poll() is None and len(workers) < 2:  # the pool's workers started
        workers = children.read_text().split() if children.exists() else []
        time.sleep(0.2)
    assert proc.poll() is None and len(workers) >= 2, proc.communicate()
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 143, stderr
    assert "Traceback" not in stderr
    assert "stopped (SIGTERM): 0 of 4 runs finished, no score" in stdout and str(out) in stdout
    assert out.read_text() == ""  # 600 s trials: none finished
    for pid in workers:  # the workers went with it (they ran on after the sweep's process before)
        assert not Path(f"/proc/{pid}").exists() or "zombie" in Path(f"/proc/{pid}/status").read_text()


def test_sweep_prints_a_mean_score_per_configuration(tmp_path, monkeypatch):
    """One mean over every run mixed tasks and levels (station keeping metres with follow-the-path points:
    '4 runs, mean score 5.039'); now a row per configuration, its seeds averaged, with its direction."""
    from dataclasses import asdict

    import usvsim.batch

    fake = {("station_keeping", 0): 2.0, ("station_keeping", 1): 4.0, ("follow_path", 0): 30.0, ("follow_path", 1): 33.0}

    def scored(runs, *args, finished, **kwargs):
        for i, r in enumerate(runs):  # a score per (task, seed); collisions: 0 for seed 0, 1 for seed 1
            finished[i] = {"run": asdict(r), "score": fake[(r.task, r.seed)], "num_collisions": r.seed,
                           "higher_is_better": r.task == "follow_path"}  # fmt: skip
        return finished

    monkeypatch.setattr(usvsim.batch, "run", scored)
    spec = tmp_path / "sweep.yaml"
    spec.write_text("task: [station_keeping, follow_path]\nseeds: [0, 1]\ntime_limit_s: 2\n")
    result = CliRunner().invoke(app, ["sweep", str(spec), "--out", str(tmp_path / "runs.jsonl")])
    assert result.exit_code == 0, result.output
    rows = {line.split()[0]: line.split()[1:] for line in result.output.splitlines() if line.split()[:1] in
            (["station_keeping"], ["follow_path"])}  # fmt: skip
    assert rows == {"station_keeping": ["0", "2", "3", "lower", "1"], "follow_path": ["0", "2", "31.5", "higher", "1"]}
    assert "4 runs, mean scores of 2 configurations above" in result.output


FAILING = {"task": "station_keeping", "seeds": [0, 1], "time_limit_s": 1.0, "grid": {"mass_kg": [180, 0.01]}}


def test_a_failed_run_keeps_the_others_and_says_why():
    """A WAM-V of 10 g diverges in 0.04 s: its runs hold the error, the 180 kg runs their scores (one divergence
    ended the sweep before, 2 workers: BrokenProcessPool and a traceback; 1 worker: nothing written)."""
    from usvsim.batch import failed

    both = []
    for backend, workers in (("process", 1), ("process", 2), ("ray", 2)):
        if backend == "ray" and importlib.util.find_spec("ray") is None:
            continue
        results = run(expand(FAILING), backend, workers=workers)
        assert [("score" in r) for r in results] == [True, True, False, False]
        assert failed(results) == results[2:]
        assert all(r["error"].startswith("DivergenceError: simulation diverged") for r in results[2:])
        both.append(_metrics(results))
    assert all(b == both[0] for b in both)


def test_sweep_cli_with_a_failed_run_writes_every_run_and_exits_1(tmp_path):
    spec = tmp_path / "sweep.yaml"
    spec.write_text(json.dumps({**FAILING, "workers": 2}))
    out = tmp_path / "runs.jsonl"
    result = CliRunner().invoke(app, ["sweep", str(spec), "--out", str(out)])
    assert result.exit_code == 1, result.output
    assert "Traceback" not in result.output and "2 of 4 runs failed" in result.output
    assert "failed: station_keeping level 0 mass_kg=0.01 seed 0: DivergenceError" in result.output
    rows = [json.loads(line) for line in out.read_text().splitlines()]
    assert ["score" in r for r in rows] == [True, True, False, False]


@pytest.mark.parametrize("workers", [0, -1, 1.5, True])
def test_workers_below_one_is_refused(workers):
    from usvsim.core.errors import UsvsimError

    with pytest.raises(UsvsimError, match="workers must be a whole number >= 1"):  # 0 meant every CPU
        run(expand({"task": "station_keeping", "seeds": [0]}), "process", workers=workers)


def test_a_broken_sweep_writes_the_runs_it_finished(tmp_path, monkeypatch):
    """A worker killed (BrokenProcessPool) ended the sweep with a traceback and nothing written."""
    from concurrent.futures.process import BrokenProcessPool
    from dataclasses import asdict

    import usvsim.batch

    def broken(runs, *args, finished, **kwargs):
        finished[0] = {"run": asdict(runs[0]), "score": 2.0, "num_collisions": 0, "higher_is_better": False}
        raise BrokenProcessPool("A process in the process pool was terminated abruptly")

    monkeypatch.setattr(usvsim.batch, "run", broken)
    spec = tmp_path / "sweep.yaml"
    spec.write_text("task: station_keeping\nseeds: [0, 1, 2]\ntime_limit_s: 2\n")
    out = tmp_path / "runs.jsonl"
    result = CliRunner().invoke(app, ["sweep", str(spec), "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "the sweep stopped: BrokenProcessPool" in result.output
    assert "wrote the 1 of 3 runs finished" in result.output
    assert [json.loads(line)["score"] for line in out.read_text().splitlines()] == [2.0]


def test_an_unreachable_ray_cluster_is_one_error():
    """`address: 127.0.0.1:1` (nothing listens): Ray retried for over 2 minutes, printing its own warnings."""
    pytest.importorskip("ray")
    from usvsim.core.errors import UsvsimError

    with pytest.raises(UsvsimError, match="cannot reach the Ray cluster at 127.0.0.1:1"):
        run(expand({"task": "station_keeping", "seeds": [0]}), "ray", workers=1, address="127.0.0.1:1")
