"""`usvsim demo navigate` mistakes: one line naming the problem and the fix, exit 2."""

from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--goals", "ten,0"], ["--goals", "x,y;x,y"]),
        (["--odometry", "gps"], ["--odometry", "kiss_icp"]),
        (["harbor", "--goals", "5,0"], ["harbor", "controller", "lidar"]),
    ],
)
def test_bad_input_fails_with_one_line(args, words):
    done = subprocess.run([sys.executable, "-m", "usvsim.cli", "demo", "navigate", *args], capture_output=True,
                          text=True, timeout=300)  # fmt: skip
    lines = [ln for ln in done.stderr.splitlines() if ln.strip()]
    assert done.returncode == 2 and len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert all(w in lines[0] for w in words), lines[0]


def test_a_failed_check_exits_1_after_writing_its_outputs(tmp_path):
    """A goal it cannot reach in the time given: FAIL printed, pictures and metrics written, exit 1 (it was 0)."""
    done = subprocess.run([sys.executable, "-m", "usvsim.cli", "demo", "navigate", "--goals", "25,10", "--max-time", "3",
                           "--out", str(tmp_path / "nav")], capture_output=True, text=True, timeout=600)  # fmt: skip
    assert done.returncode == 1, done.stderr
    assert "goals_reached_within_1m: FAIL" in done.stdout and (tmp_path / "nav" / "metrics.json").exists()
