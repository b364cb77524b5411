"""`with sim.record(path):` writes the file `usvsim run --record` writes: the same channels (topic, type, QoS
metadata), schemas and messages (log time and bytes) for the same scenario, seed and duration."""

from __future__ import annotations

from pathlib import Path

from mcap.reader import make_reader
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.simulation import Simulation


def contents(path: Path):
    with path.open("rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        channels = sorted((c.topic, c.message_encoding, sorted(c.metadata.items()), summary.schemas[c.schema_id].name,
                           summary.schemas[c.schema_id].data) for c in summary.channels.values())  # fmt: skip
        messages = [(channel.topic, message.log_time, message.publish_time, message.data)
                    for _, channel, message in reader.iter_messages(log_time_order=False)]  # fmt: skip
    return channels, messages


def test_python_recording_equals_the_cli_recording(tmp_path):
    cli_path, api_path = tmp_path / "cli.mcap", tmp_path / "api.mcap"
    result = CliRunner().invoke(app, ["run", "harbor", "--seed", "4", "--duration", "2", "--record", str(cli_path),
                                      "--record-epoch", "2026-01-01T00:00:00Z"])  # fmt: skip
    assert result.exit_code == 0, result.output
    sim = Simulation.from_scenario("harbor", seed=4)
    try:
        with sim.record(api_path, epoch_ns=1_767_225_600 * 10**9):  # the same epoch: byte-identical messages
            sim.run(2.0)
    finally:
        sim.close()
    cli, api = contents(cli_path), contents(api_path)
    assert len(cli[1]) > 200  # /clock, /tf, odometry... over 2 s
    assert api[0] == cli[0]
    assert api[1] == cli[1]


def _decoded(path: Path) -> list[tuple[str, int, object]]:
    from mcap_ros2.decoder import DecoderFactory

    with path.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        return [(c.topic, m.log_time, d) for _, c, m, d in reader.iter_decoded_messages(log_time_order=False)]


def _stamp_ns(topic: str, msg) -> int:
    if topic == "/clock":
        return msg.clock.sec * 10**9 + msg.clock.nanosec
    header = msg.transforms[0].header if topic.startswith("/tf") else \
        msg.markers[0].header if topic.startswith("/usvsim/markers") else msg.header  # fmt: skip
    return header.stamp.sec * 10**9 + header.stamp.nanosec


def test_a_recording_started_mid_episode_starts_then(tmp_path):
    """Started at t = 1 s (after steps with no subscriber, or after an earlier recording), the file began at log
    time 0 with /clock 0 and ground truth stamped 0 that held the pose at 1 s, then jumped to 1.01 s."""
    sim = Simulation.from_scenario("harbor", seed=0)
    try:
        sim.vessels["wamv"].command(1.0)
        sim.run(1.0)  # nobody subscribed: nothing announced yet
        with sim.record(tmp_path / "late.mcap", epoch_ns=0):  # log time = simulation time
            sim.run(0.1)
        sim.run(0.4)
        with sim.record(tmp_path / "later.mcap", epoch_ns=0):  # announced by the first recording
            sim.run(0.1)
    finally:
        sim.close()
    for name, start_ns in (("late.mcap", 1_000_000_000), ("later.mcap", 1_500_000_000)):
        messages = _decoded(tmp_path / name)
        assert min(log for _, log, _ in messages) == start_ns
        assert [t for t, _, _ in messages[:3]] == ["/usvsim/episode", "/tf_static", "/usvsim/markers"]  # latched,
        for topic, log, msg in messages[3:]:  # stamped 0
            assert start_ns < _stamp_ns(topic, msg) <= log, (name, topic)
        x0 = [m.pose.pose.position.x for t, _, m in messages if t == "/wamv/ground_truth/odometry"][0]
        assert x0 > 1.0  # under way: the first odometry is the boat at ~start_ns, stamped so


def test_relative_topic_names_are_recorded_absolute(tmp_path):
    """`topic: my_imu` was recorded (and served to Foxglove) as `my_imu`, where ROS 2 and the DDS bridge name it
    `/my_imu`; rosbag2 stores fully qualified names only."""
    scenario = {"version": 1, "vessels": [{"name": "a", "model": "otter",
                                           "sensors": [{"type": "imu", "name": "imu", "rate_hz": 50, "topic": "my_imu"},
                                                       {"type": "gnss", "name": "gps", "rate_hz": 10, "topic": "a/fix"}]}]}  # fmt: skip
    sim = Simulation(scenario)
    try:
        with sim.record(tmp_path / "rel.mcap") as recorder:
            sim.run(0.2)
    finally:
        sim.close()
    topics = set(recorder.message_counts)
    assert {"/my_imu", "/a/fix"} <= topics and all(t.startswith("/") for t in topics)


def test_record_epoch_sets_the_log_times_and_leaves_the_stamps(tmp_path):
    """`usvsim run --record` logged at simulation time from 0 (Foxglove: 1970-01-01); now at the wall clock by
    default, at `--record-epoch` when given (0: log time = simulation time). /clock holds simulation time in all."""
    import time

    runs = {"now": tmp_path / "now.mcap", "0": tmp_path / "zero.mcap", "2026-01-01T00:00:00Z": tmp_path / "d.mcap"}
    before = time.time_ns()
    for epoch, path in runs.items():
        result = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.2", "--record", str(path),
                                          "--record-epoch", epoch])  # fmt: skip
        assert result.exit_code == 0, result.output
    after = time.time_ns()
    for epoch, path in runs.items():
        clocks = [(log, _stamp_ns(t, m)) for t, log, m in _decoded(path) if t == "/clock"]
        assert [stamp for _, stamp in clocks] == [k * 10_000_000 for k in range(21)]  # simulation time, from 0
        offsets = {log - stamp for log, stamp in clocks}
        assert len(offsets) == 1  # one epoch per recording
        if epoch == "now":
            assert before <= offsets.pop() <= after
        else:
            assert offsets == {0 if epoch == "0" else 1_767_225_600 * 10**9}
