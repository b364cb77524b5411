"""Which topics a recording keeps (`usvsim run --record-topics`, `sim.record(topics=...)`): names and patterns;
a misspelt name recorded nothing in silence, a name without '/' could never match, and the CLI had no filter and
no compression choice at all."""

from __future__ import annotations

import warnings

import pytest
from mcap.reader import make_reader
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.core.errors import UsvsimError
from usvsim.io.topic_filter import TopicFilter
from usvsim.simulation import Simulation


def test_names_and_patterns():
    keep = TopicFilter(["/clock", "/tf*", "/wamv/camera/*", "/nothing"])
    offered = [
        "/clock",
        "/tf",
        "/tf_static",
        "/wamv/camera/image_raw",
        "/wamv/camera/depth/image_raw",
        "/wamv/imu/data",
    ]
    assert [t for t in offered if keep(t)] == offered[:5]  # '*' crosses '/'
    assert keep.unmatched() == ["topics: no message on /nothing"]
    assert all(TopicFilter(None)(t) for t in offered) and TopicFilter(None).unmatched() == []
    all_but_camera = TopicFilter(["!/wamv/camera/*", "!/nothing"])
    assert [t for t in offered if all_but_camera(t)] == ["/clock", "/tf", "/tf_static", "/wamv/imu/data"]
    assert all_but_camera.unmatched() == ["topics: no message on /nothing"]
    some_but_depth = TopicFilter(["/wamv/*", "!/wamv/camera/depth/*"])
    assert [t for t in offered if some_but_depth(t)] == ["/wamv/camera/image_raw", "/wamv/imu/data"]


@pytest.mark.parametrize(("topics", "words"), [("clock", ["not a topic name", "'/clock'"]), ("!clock", ["not a topic name"]), ([], ["no topic given"]),
                                               (5, ["topic name or names"]), (["/a", 3], ["topic name or names"])])  # fmt: skip
def test_bad_topics_are_usvsim_errors(topics, words):
    with pytest.raises(UsvsimError) as info:
        TopicFilter(topics)
    assert all(w in str(info.value) for w in words)


def test_record_warns_about_a_topic_that_got_nothing(tmp_path):
    sim = Simulation.from_scenario("harbor")
    try:
        with pytest.warns(
            UserWarning, match=r"no message on /wamv/ground_truth \(did you mean /wamv/ground_truth/"
        ):
            with sim.record(tmp_path / "a.mcap", topics=["/wamv/ground_truth", "/clock"]) as recorder:
                sim.run(0.1)
        assert set(recorder.message_counts) == {"/clock"}
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # every name matched: no warning
            with sim.record(tmp_path / "b.mcap", topics="/otter/*"):
                sim.run(0.1)
    finally:
        sim.close()


def _topics_and_compression(path):
    with path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    return {c.topic for c in summary.channels.values()}, {c.compression for c in summary.chunk_indexes}


def test_cli_records_the_topics_asked_for_with_the_compression_asked_for(tmp_path):
    out = tmp_path / "f.mcap"
    result = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.5", "--record", str(out), "--record-topics",
                                      "/clock, /tf*", "--record-topics", "/wamv/ground_truth",
                                      "--record-compression", "lz4"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert _topics_and_compression(out) == ({"/clock", "/tf", "/tf_static"}, {"lz4"})
    assert "warning: --record-topics: no message on /wamv/ground_truth (did you mean" in result.stderr


@pytest.mark.parametrize(("args", "words"), [
    (["--record-topics", "/clock"], ["apply to a recording", "--record"]),
    (["--record-compression", "lz4"], ["apply to a recording"]),
    (["--record", "x.mcap", "--record-compression", "gzip"], ["zstd, lz4 or none"]),
    (["--record", "x.mcap", "--record-topics", "clock"], ["not a topic name"]),
    (["--record", "x.mcap", "--record-topics", ","], ["no topic given"]),
    (["--record-epoch", "0"], ["apply to a recording"]),
    (["--record", "x.mcap", "--record-epoch", "yesterday"], ["--record-epoch", "ISO 8601"]),
    (["--record", "x.mcap", "--record-epoch", "-5"], ["--record-epoch", "1970-01-01"]),
])  # fmt: skip
def test_cli_recording_option_mistakes_are_one_line(tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.1", *args])
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and all(w in lines[0] for w in words), result.stderr
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_log_times_keep_increasing_over_a_reset_without_the_episode_marker(tmp_path):
    """The recorder moved its log-time offset only on an episode marker it wrote: filtered out, the second episode
    was logged from 0 again, interleaved with the first on playback."""
    sim = Simulation.from_scenario("harbor")
    try:
        with sim.record(tmp_path / "a.mcap", topics="/clock"):
            sim.run(0.5)
            sim.reset()
            sim.run(0.5)
    finally:
        sim.close()
    with (tmp_path / "a.mcap").open("rb") as f:
        logs = [m.log_time for _, _, m in make_reader(f).iter_messages(log_time_order=False)]
    assert len(logs) == 102 and all(b > a for a, b in zip(logs, logs[1:], strict=False))
    assert logs[51] == logs[50] + 1  # the second episode's t = 0, 1 ns after the first's last message


def test_a_file_that_cannot_be_opened_is_one_line(tmp_path, monkeypatch):
    """A path that passed the CLI's checks but failed to open (as root, /proc/x.mcap) printed the bare
    "[Errno 2] No such file or directory: '/proc/x.mcap'"."""
    import usvsim.cli.outputs

    monkeypatch.setattr(usvsim.cli.outputs, "check_output", lambda path, force: None)
    target = tmp_path / "missing" / "x.mcap"
    result = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.1", "--record", str(target)])
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.exit_code == 2 and len(lines) == 1, result.output
    assert f"cannot write {target}: No such file or directory" in lines[0]


def test_the_scenario_chooses_topics_and_compression_and_the_options_override_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scenario = tmp_path / "s.yaml"
    scenario.write_text("version: 1\nvessels: [{name: wamv, model: wamv}]\noutputs: {recording: {path: s.mcap, "
                        "topics: ['/clock', '/tf*'], compression: lz4}}\n")  # fmt: skip
    assert CliRunner().invoke(app, ["run", str(scenario), "--duration", "0.2"]).exit_code == 0
    assert _topics_and_compression(tmp_path / "s.mcap") == ({"/clock", "/tf", "/tf_static"}, {"lz4"})
    result = CliRunner().invoke(app, ["run", str(scenario), "--duration", "0.2", "--record", "o.mcap",
                                      "--record-topics", "/wamv/*", "--record-compression", "none"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert _topics_and_compression(tmp_path / "o.mcap") == ({"/wamv/ground_truth/odometry"}, {""})
    sim = Simulation.from_scenario(str(scenario))
    try:
        with sim.record(tmp_path / "p.mcap"):  # the Python API writes what the CLI writes
            sim.run(0.2)
    finally:
        sim.close()
    assert _topics_and_compression(tmp_path / "p.mcap") == ({"/clock", "/tf", "/tf_static"}, {"lz4"})


def test_bad_scenario_topics_name_the_key(tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(
        "version: 1\nvessels: [{name: wamv, model: wamv}]\noutputs: {recording: {topics: [clock]}}\n"
    )
    result = CliRunner().invoke(app, ["validate", str(scenario)])
    assert (
        result.exit_code == 2
        and "outputs.recording.topics[0]: should be a topic name or pattern" in result.stderr
    )
