"""Recording faults: a writer killed with SIGKILL, and a write that fails (file-size limit, i.e. the
disk is full for this process): `usvsim recover` gives a file the standard readers open, losing at most
the last flush interval (0.5 s of simulated time)."""

from __future__ import annotations

import resource
import signal
import subprocess
import sys
import time

import pytest
from readers import read_with_mcap_ros2, read_with_rosbags, rosbag2_metadata
from typer.testing import CliRunner

from usvsim.cli.app import app

CHILD = """
import sys
from usvsim.io.mcap_recorder import McapRecorder
from usvsim.simulation import Simulation
sim = Simulation.from_scenario("harbor")
recorder = McapRecorder(sys.argv[1])
sim.subscribe(recorder.write)
while True:
    sim.run(0.1)
    print(f"{sim.time:.3f}", flush=True)
"""


def _recover(path, tmp_path):
    out = tmp_path / "recovered.mcap"
    result = CliRunner().invoke(app, ["recover", str(path), "--out", str(out)])
    assert result.exit_code == 0, result.stderr
    assert "cut short" in result.stdout
    return out


def _clock_stamps_s(messages) -> list[float]:
    """/clock in simulation seconds (its value: the log times are the recording's epoch + simulation time)."""
    return sorted(m.clock.sec + m.clock.nanosec / 1e9 for topic, _, m in messages if topic == "/clock")


def test_kill_9_loses_at_most_one_flush_interval(tmp_path):
    path, started_ns = tmp_path / "killed.mcap", time.time_ns()
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE, text=True)
    try:
        reported = 0.0
        for line in child.stdout:  # the child's simulated time, at least this far when killed
            reported = float(line)
            if reported >= 2.5:
                break
        child.send_signal(signal.SIGKILL)
    finally:
        child.kill()
        child.wait(timeout=60)
    assert reported >= 2.5
    out = _recover(path, tmp_path)
    by_mcap, by_rosbags = read_with_mcap_ros2(out), read_with_rosbags(out)
    assert len(by_mcap) == len(by_rosbags) > 0
    clock = _clock_stamps_s(by_mcap)
    assert clock[-1] >= reported - 1.0  # at most the flush interval (0.5 s) plus one chunk is lost
    assert all(abs(b - a - 0.01) < 1e-6 for a, b in zip(clock, clock[1:]))  # nothing missing before that
    epoch = int(rosbag2_metadata(out)["custom_data"]["usvsim.log_time_epoch_ns"])  # the killed recorder's, kept
    assert started_ns <= epoch <= time.time_ns()
    assert [t - epoch for topic, t, _ in by_mcap if topic == "/clock"][:3] == [0, 10_000_000, 20_000_000]


def _limit_file_size():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() then fails with EFBIG instead of killing us
    resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, 100_000))


@pytest.mark.slow
def test_full_disk_is_one_line_and_the_file_recovers(tmp_path):
    path = tmp_path / "full.mcap"
    cmd = [sys.executable, "-m", "usvsim.cli", "run", "harbor", "--duration", "60", "--record", str(path)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600, preexec_fn=_limit_file_size)
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert proc.returncode == 2 and len(lines) == 1, proc.stderr
    assert "recording to" in lines[0] and "File too large" in lines[0]
    out = _recover(path, tmp_path)
    clock = _clock_stamps_s(read_with_mcap_ros2(out))
    assert len(clock) > 50 and len(read_with_rosbags(out)) > 0
