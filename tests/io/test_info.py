"""`usvsim info FILE`: what a recording holds, without ROS (there was no way to inspect one from the CLI)."""

from __future__ import annotations

import re
from datetime import UTC, datetime, timedelta

from mcap.reader import make_reader
from typer.testing import CliRunner

from usvsim.cli.app import app


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_info_lists_every_topic_with_its_count_and_rate(tmp_path):
    out = tmp_path / "run.mcap"
    assert invoke("run", "harbor", "--duration", "2", "--record", out).exit_code == 0
    with out.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None and summary.statistics is not None
    expected = {c.topic: summary.statistics.channel_message_counts[c.id] for c in summary.channels.values()}
    result = invoke("info", out)
    assert result.exit_code == 0, result.output
    when = re.search(r"log time 0\.000 to 2\.000 s after (\S+)Z \(2\.000 s\)", result.stdout)  # simulation time
    assert when is not None and "1 episode marker(s)" in result.stdout, result.stdout  # and the epoch: the run's date
    assert abs(datetime.fromisoformat(when.group(1)).replace(tzinfo=UTC) - datetime.now(UTC)) < timedelta(hours=1)
    assert "zstd chunks" in result.stdout and "profile ros2" in result.stdout
    rows = {
        m[0]: (m[1], int(m[2]), m[3])
        for m in re.findall(r"^(/\S+)\s+(\S+)\s+(\d+)\s+(\S+)$", result.stdout, re.M)
    }
    assert {t: n for t, (_, n, _) in rows.items()} == expected
    assert rows["/clock"] == (
        "rosgraph_msgs/msg/Clock",
        201,
        "100.50",
    )  # t = 0 to 2 s at 100 Hz, per second of 2 s
    assert rows["/tf_static"][2] == "-"


def test_info_on_a_file_cut_short_or_not_a_recording_is_one_line(tmp_path):
    out = tmp_path / "run.mcap"
    assert invoke("run", "harbor", "--duration", "1", "--record", out).exit_code == 0
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(out.read_bytes()[: out.stat().st_size // 2])
    (tmp_path / "notes.mcap").write_text("hello")
    (tmp_path / "empty.mcap").write_bytes(b"")
    for name, words in [("cut.mcap", ["cut short", "usvsim recover"]), ("notes.mcap", ["not an MCAP"]),
                        ("empty.mcap", ["is empty"]), ("missing.mcap", ["no such recording"])]:  # fmt: skip
        result = invoke("info", tmp_path / name)
        lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
        assert result.exit_code == 2 and len(lines) == 1 and all(w in lines[0] for w in words), result.output
