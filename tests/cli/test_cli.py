"""The `usvsim` command as a user runs it: one-line errors with exit 2, recordings, Ctrl-C."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from readers import read_with_mcap_ros2, read_with_rosbags

USVSIM = [sys.executable, "-m", "usvsim.cli"]


def usvsim(*args, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([*USVSIM, *args], capture_output=True, text=True, timeout=300, **kw)


def assert_one_line_error(result: subprocess.CompletedProcess, *words: str) -> None:
    assert result.returncode == 2, result.stderr
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    for w in words:
        assert w in lines[0], lines[0]


def test_scenarios_lists_harbor():
    result = usvsim("scenarios")
    assert result.returncode == 0 and "harbor" in result.stdout


@pytest.mark.parametrize(
    "text, words",
    [
        ("version: 1\nvessels:\n  - {name: a, model: wamv, posee: {}}\n", ["vessels[0].posee", "unknown key"]),
        ("version: 1\nworld: {physics_rate_hz: fast}\n", ["world.physics_rate_hz"]),
        ("version: 1\nvessels:\n  - {name: a, model: custom, hull_mesh: gone.stl, mass: {mass_kg: 9.0}}\n",
         ["gone.stl", "not found"]),
        ("version: 1\noutputs: {recording: {clock_rate_hz: 30}}\n", ["outputs.recording.clock_rate_hz"]),
        ("version: 1\nvessels: [\n", ["not valid YAML"]),
    ],
)
def test_bad_scenarios_fail_with_one_line(tmp_path, text, words):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    assert_one_line_error(usvsim("validate", str(path)), str(path), *words)
    assert_one_line_error(usvsim("run", str(path), "--duration", "1"), str(path), *words)


def test_open_hull_mesh_is_rejected(tmp_path, open_stl):
    path = tmp_path / "leaky.yaml"
    path.write_text(f"version: 1\nvessels:\n  - {{name: a, model: custom, hull_mesh: {open_stl.name}, "
                    "mass: {mass_kg: 100.0}}\n")  # fmt: skip
    assert_one_line_error(usvsim("validate", str(path)), "vessels[0].hull_mesh", "not watertight")


def test_unknown_scenario_name():
    assert_one_line_error(usvsim("run", "atlantis"), "atlantis", "harbor")


def count(messages, topic: str) -> int:
    return sum(t == topic for t, _, _ in messages)


def test_run_records_a_readable_mcap(tmp_path):
    out = tmp_path / "run.mcap"
    result = usvsim("run", "--duration", "3", "--record", str(out))
    assert result.returncode == 0, result.stderr
    for read in (read_with_mcap_ros2, read_with_rosbags):
        messages = read(out)
        topics = {t for t, _, _ in messages}
        assert topics == {"/clock", "/tf", "/tf_static", "/wamv/ground_truth/odometry", "/otter/ground_truth/odometry",
                          "/usvsim/episode", "/usvsim/markers", "/usvsim/markers/bodies"}  # fmt: skip
        assert count(messages, "/clock") == 301  # 100 Hz from t = 0 to 3 s inclusive
        assert count(messages, "/wamv/ground_truth/odometry") == 151  # 50 Hz
        assert count(messages, "/usvsim/markers") == 1 and count(messages, "/usvsim/markers/bodies") == 31  # 10 Hz
        scene = next(m for t, _, m in messages if t == "/usvsim/markers")
        assert {k.ns for k in scene.markers} == {"vessel/wamv", "vessel/otter", "obstacles"}
        last = [m for t, _, m in messages if t == "/clock"][-1]
        assert (last.clock.sec, last.clock.nanosec) == (3, 0)


@pytest.mark.parametrize("stop, status, said", [(signal.SIGINT, 130, "stopped"), (signal.SIGTERM, 143, "stopped (SIGTERM)")])
def test_a_stopped_run_leaves_a_valid_recording(tmp_path, stop, status, said):
    """Ctrl-C, and `kill`, `timeout` or `docker stop` (SIGTERM: it ended the process with the MCAP unfinished, no
    summary, unreadable until `usvsim recover`), stop between steps with the shell's status and a readable file."""
    out = tmp_path / "long.mcap"
    proc = subprocess.Popen([*USVSIM, "run", "--duration", "100000", "--record", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.time() + 120
    while time.time() < deadline and not (out.exists() and out.stat().st_size > 20_000):
        time.sleep(0.2)
    proc.send_signal(stop)
    out_text, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err
    assert "Traceback" not in err and said in out_text  # results on stdout, progress on stderr
    messages = read_with_mcap_ros2(out)
    assert len(messages) > 100 and {t for t, _, _ in messages} >= {"/clock", "/tf_static"}


def test_experiment_unknown_name():
    assert_one_line_error(usvsim("experiment", "nonesuch"), "nonesuch", "sphere")


def test_long_experiments_report_progress_on_stderr(tmp_path, monkeypatch):
    """endurance (~15 min) and detection-robustness (~30 min) ran without a word until their verdict."""
    from typer.testing import CliRunner

    from usvsim.cli.app import app
    from usvsim.experiments import endurance

    def fake_run(out, duration_s=3600.0, progress=None):
        progress("model 1 of 4, state_space: 3600 s of sea state 6 ...")
        return {"passed": True, "summary": {}}

    monkeypatch.setattr(endurance, "run", fake_run)
    result = CliRunner().invoke(app, ["experiment", "endurance", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "usvsim: endurance: model 1 of 4, state_space" in result.stderr
    assert "endurance: PASS" in result.stdout


def test_experiment_help_says_what_each_experiment_checks_and_how_long_it_takes():
    """The names alone were listed (the descriptions were never shown; endurance runs ~15 minutes unannounced)."""
    from usvsim.cli.app import EXPERIMENTS

    result = usvsim("experiment", "--help", env={**os.environ, "COLUMNS": "400", "NO_COLOR": "1"})
    assert result.returncode == 0
    lines = result.stdout.splitlines()
    for name, (_, text, took) in EXPERIMENTS.items():
        assert any(f"{name}: {text} (about {took})" in line for line in lines), name


@pytest.fixture(autouse=True)
def _no_color(monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")
    monkeypatch.setenv("COLUMNS", "400")
    os.environ.setdefault("PYTHONUNBUFFERED", "1")




def test_sensor_messages_are_recorded(tmp_path):
    """harbor_sensors: the seed's demo sensor set on the WAM-V reaches the recording, readable by both readers."""
    out = tmp_path / "sensors.mcap"
    result = usvsim("run", "harbor_sensors", "--duration", "1", "--record", str(out))
    assert result.returncode == 0, result.stderr
    expected = {"/wamv/imu/data", "/wamv/odometry", "/wamv/gps/fix", "/wamv/lidar/points", "/wamv/lidar2d/scan",
                "/wamv/camera/image_raw", "/wamv/camera/camera_info", "/wamv/camera/depth/image_raw"}  # fmt: skip
    for read in (read_with_mcap_ros2, read_with_rosbags):
        messages = read(out)
        assert expected <= {t for t, _, _ in messages}
        assert count(messages, "/wamv/imu/data") == 50  # 50 Hz for 1 s
        static = [m for t, _, m in messages if t == "/tf_static"][0]
        assert "wamv/lidar" in {tf.child_frame_id for tf in static.transforms}


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--ros-tcp", "nohostport"], ["--ros-tcp", "HOST:PORT"]),
        (["--ros-tcp", "127.0.0.1:1", "--ros-tcp-profile", "bogus"], ["profile", "bogus", "seed"]),
        (["--ros-tcp", "127.0.0.1:1", "--ros-tcp-profile", "seed", "--ros-tcp-vessel", "nope"], ["nope"]),
    ],
)
def test_bad_bridge_options_fail_with_one_line(args, words):
    assert_one_line_error(usvsim("run", "--duration", "0.1", *args), *words)


@pytest.mark.skipif(shutil.which("ss") is None, reason="needs iproute2's ss")
def test_live_bridges_listen_only_on_loopback():
    """`ss -lntup` during `usvsim run --ros2 --foxglove`: every socket of the run (and of its Foxglove proxy
    process) is bound to 127.0.0.1 or to the loopback device (Cyclone's wildcard sockets: `0.0.0.0%lo`)."""
    run = subprocess.Popen([*USVSIM, "run", "--duration", "60", "--realtime", "--ros2", "--foxglove",
                            "--foxglove-port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        deadline, ours = time.monotonic() + 120, []
        while time.monotonic() < deadline and len({ln.split()[0] for ln in ours}) < 2:  # udp (DDS) and tcp
            time.sleep(0.5)
            pids = {str(run.pid), *_children(run.pid)}
            table = subprocess.run(["ss", "-lntupH"], capture_output=True, text=True).stdout.splitlines()
            ours = [ln for ln in table if any(f"pid={pid}," in ln for pid in pids)]
        assert {ln.split()[0] for ln in ours} == {"udp", "tcp"}, ours
        for line in ours:
            local = line.split()[4]
            assert local.startswith("127.0.0.1:") or "%lo:" in local, line
    finally:
        run.send_signal(signal.SIGINT)
        run.communicate(timeout=60)


def _children(pid: int) -> set[str]:
    found = set()
    for task in Path(f"/proc/{pid}/task").glob("*/children"):
        for child in task.read_text().split():
            found |= {child, *_children(int(child))}
    return found


def test_run_with_live_bridges_reports_their_counts():
    """DDS pinned to loopback (the default) and a Foxglove server on a free port of 127.0.0.1."""
    result = usvsim("run", "--duration", "1", "--ros2", "--foxglove", "--foxglove-port", "0")
    assert result.returncode == 0, result.stderr
    assert "DdsBridge: published" in result.stdout and "FoxgloveBridge:" in result.stdout
    url = result.stderr.split("usvsim: Foxglove: open ")[1].split()[0]  # the port it was given
    assert url.startswith("ws://127.0.0.1:") and int(url.rsplit(":", 1)[1]) > 0
    published = int(result.stdout.split("DdsBridge: published ")[1].split(",")[0])
    assert published >= 100 + 50 * 2  # /clock at 100 Hz, /tf and two odometry topics at 50 Hz (+ t = 0)


def test_realtime_falling_behind_warning_is_one_line(monkeypatch, capsys):
    """The warning was wrapped by rich at 80 columns when stderr is not a terminal (a log file, a pipe): its figure
    '(0.58x real time)' landed on a line of its own (QA: usvsim run --ros2 --realtime on a loaded machine)."""
    from types import SimpleNamespace

    from rich.console import Console

    from usvsim.cli import app as app_module

    monkeypatch.setattr(app_module, "console", Console(stderr=True, width=80))  # a pipe or a file
    clock = iter(range(0, 10_000, 3))  # every perf_counter() call: 3 s of wall time later
    monkeypatch.setattr(app_module, "time", SimpleNamespace(perf_counter=lambda: float(next(clock))))
    steps = app_module._StepCount()

    def run(seconds, realtime, on_step):
        for _ in range(round(seconds / 0.01)):
            steps.n += 1

    sim = SimpleNamespace(clock=SimpleNamespace(dt=0.01), scenario=SimpleNamespace(name="harbor"), run=run)
    app_module._progress_loop(sim, 2.0, True, None, steps)
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    warning = [line for line in lines if "falling behind" in line]
    assert len(warning) == 1 and warning[0].endswith("real time)"), lines
