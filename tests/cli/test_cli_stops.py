"""Ctrl-C and SIGTERM (`kill`, `timeout`, `docker stop`, a job scheduler) in `usvsim task` and `usvsim dataset`
stop between two steps, as in `usvsim run`: what was written is complete and readable, one line says what was
kept, and the exit status is the shell's (130, 143). SIGTERM used to end both with their files cut short."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest
from PIL import Image
from readers import read_with_mcap_ros2
from typer.testing import CliRunner

from usvsim.cli.app import app

USVSIM = [sys.executable, "-m", "usvsim"]
STOPS = [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGINT, 130, "Ctrl-C")]


def _stop_when(proc: subprocess.Popen, ready, stop: int) -> tuple[str, str]:
    """Send `stop` once `ready()` (a file the command writes has grown: its handlers are in place), then wait."""
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None and not ready():
        time.sleep(0.2)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(stop)
    return proc.communicate(timeout=120)


@pytest.mark.parametrize(("stop", "status", "said"), STOPS)
def test_a_stopped_live_task_closes_its_recording_and_writes_its_report(tmp_path, stop, status, said):
    """`usvsim task --ros2 --record` (DDS on loopback): the MCAP was left without its summary, no report."""
    record, report = tmp_path / "live.mcap", tmp_path / "report.json"
    domain = str(150 + os.getpid() % 80)  # apart from the other DDS tests on this machine
    proc = subprocess.Popen([*USVSIM, "task", "station_keeping", "--ros2", "--domain-id", domain, "--record",
                             str(record), "--report", str(report), "--time-limit", "100000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    out, err = _stop_when(proc, lambda: record.exists() and record.stat().st_size > 50_000, stop)
    assert proc.returncode == status, err
    assert "Traceback" not in err
    assert f"station_keeping: stopped ({said}) in trial 1/1 (seed 0), which is not scored" in out
    assert str(report) in out and f"recording {record} closed complete" in out
    messages = read_with_mcap_ros2(record)  # the summary and footer are there: read without `usvsim recover`
    assert {"/clock", "/vrx/task/info"} <= {t for t, _, _ in messages}
    data = json.loads(report.read_text())
    assert data["trials"] == [] and data["mean_score"] is None
    assert data["stopped"] == {"signal": said, "trial": 0, "seed": 0, "trials_asked": 1}


def test_a_task_stopped_in_its_second_trial_reports_the_first(tmp_path, monkeypatch):
    """In-process, the reference solution without bridges: SIGTERM arrives 20 steps into trial 2 of 3."""
    import usvsim.tasks.solutions as solutions

    real_drive, calls = solutions.drive, []

    def drive(task, sim, controller, trace=None, after_step=None, realtime=False):
        calls.append(task.seed)
        steps = [0]

        def each_step():
            steps[0] += 1
            if len(calls) == 2 and steps[0] == 20:
                signal.raise_signal(signal.SIGTERM)  # as `kill PID` does
            after_step()

        return real_drive(task, sim, controller, trace, each_step, realtime)

    monkeypatch.setattr(solutions, "drive", drive)
    report, before = tmp_path / "r.json", signal.getsignal(signal.SIGTERM)
    result = CliRunner().invoke(app, ["task", "station_keeping", "--trials", "3", "--seed", "4", "--time-limit",
                                      "1", "--report", str(report)])  # fmt: skip
    assert result.exit_code == 143, result.output
    assert "stopped (SIGTERM) in trial 2/3 (seed 5)" in result.stdout and "1 finished trial(s)" in result.stdout
    assert calls == [4, 5]  # the third trial never started
    data = json.loads(report.read_text())
    assert [t["seed"] for t in data["trials"]] == [4] and data["mean_score"] == data["trials"][0]["score"]
    assert data["stopped"]["trial"] == 1 and signal.getsignal(signal.SIGTERM) == before  # the handler given back


@pytest.mark.parametrize(("stop", "status", "said"), STOPS)
def test_a_stopped_dataset_is_a_readable_dataset_of_the_frames_written(tmp_path, stop, status, said):
    out = tmp_path / "ds"
    proc = subprocess.Popen([*USVSIM, "dataset", "buoy_field", "--frames", "100000", "--resolution", "64x48",
                             "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    stdout, err = _stop_when(proc, lambda: len(list((out / "meta").glob("*.json"))) >= 3, stop)
    assert proc.returncode == status, err
    assert "Traceback" not in err
    assert stdout.startswith(f"stopped ({said}): wrote ") and "of 100000 frames" in stdout
    written = int(stdout.split("wrote ")[1].split()[0])
    images = sorted((out / "images").rglob("*.png"))
    assert written >= 3 and len(images) == written
    for png in images:  # every image complete
        with Image.open(png) as im:
            im.load()
        assert (out / "labels" / png.parent.name / f"{png.stem}.txt").is_file()
        for kind in ("instance", "semantic"):
            with Image.open(out / "masks" / kind / png.parent.name / png.name) as im:
                im.load()
    coco = {s: json.loads((out / "annotations" / f"{s}.json").read_text()) for s in ("train", "val", "test")}
    listed = sorted(f"{s}/{img['file_name'].split('/')[1]}" for s, c in coco.items() for img in c["images"])
    assert listed == sorted(f"{p.parent.name}/{p.name}" for p in images)  # the annotations name exactly those
    ids = {img["id"] for c in coco.values() for img in c["images"]}
    assert all(a["image_id"] in ids for c in coco.values() for a in c["annotations"])
    settings = json.loads((out / "dataset.json").read_text())
    assert settings["frames"] == written and settings["frames_requested"] == 100000 and settings["stopped"] == said
    assert (out / "data.yaml").is_file() and len(list((out / "meta").glob("*.json"))) == written


@pytest.mark.skipif(shutil.which("Xvfb") is None, reason="Xvfb is not installed")
@pytest.mark.parametrize(("stop", "status", "said"), STOPS)
def test_the_viewer_stopped_between_frames_counts_its_steps_and_closes_its_recording(tmp_path, stop, status, said):
    """`usvsim run --view --record`: Ctrl-C raised anywhere (a physics step, a recorder's write) and left the steps
    uncounted ('simulated 0.00 s'); SIGTERM killed the process with the recording unfinished."""
    display = f":{os.getpid() % 700 + 200}"
    xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    try:
        time.sleep(1.0)
        record = tmp_path / "view.mcap"
        env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
        proc = subprocess.Popen([*USVSIM, "run", "harbor", "--view", "--duration", "100000", "--record", str(record)],
                                env={**env, "DISPLAY": display}, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True)  # fmt: skip
        out, err = _stop_when(proc, lambda: record.exists() and record.stat().st_size > 50_000, stop)
    finally:
        xvfb.terminate()
        xvfb.wait()
    assert proc.returncode == status, err
    assert "Traceback" not in err
    simulated = float(out.split(f"stopped ({said}): simulated ")[1].split(" s")[0])
    assert simulated > 0.0
    clock = [t for t, _, _ in read_with_mcap_ros2(record) if t == "/clock"]  # complete: no `usvsim recover`
    assert len(clock) >= 1
