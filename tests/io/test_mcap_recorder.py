"""McapRecorder: a rosbag2-layout MCAP read back by two independent readers (rosbags and mcap-ros2)."""

from __future__ import annotations

import signal
from pathlib import Path

import numpy as np
import pytest
import yaml
from mcap.reader import make_reader
from readers import read_with_mcap_ros2, read_with_rosbags, rosbag2_metadata

from usvsim.core.errors import InputError
from usvsim.io.mcap_recorder import McapRecorder
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope

VESSELS = {"wamv": np.array([10.0, -5.0, 0.0]), "otter": np.array([-3.0, 4.0, 0.0])}
STEPS = 40
DT_NS = 10_000_000
YAW_RATE = 0.1  # rad/s, so the quaternion is not trivial


def vessel_state(name: str, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Pose in <vessel>/odom at step k: position and (w, x, y, z) quaternion (yaw only)."""
    yaw = YAW_RATE * k * DT_NS / 1e9 + (0.5 if name == "otter" else 0.0)
    pos = np.array([0.01 * k, 0.02 * k, -0.1])
    return pos, np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


def scenario_envelopes(steps: int = STEPS):
    """Envelopes a simulation of two vessels would emit: /tf_static once, then per step."""
    static = [
        ros.transform_stamped(DT_NS, "world", f"{v}/odom", p, np.array([1.0, 0, 0, 0]))
        for v, p in VESSELS.items()
    ]
    yield Envelope("/tf_static", DT_NS, ros.tf_message(static))
    for k in range(1, steps + 1):
        stamp = k * DT_NS
        yield Envelope("/clock", stamp, ros.clock_msg(stamp))
        transforms = []
        for v in VESSELS:
            pos, q = vessel_state(v, k)
            transforms.append(ros.transform_stamped(stamp, f"{v}/odom", f"{v}/base_link", pos, q))
            odom = ros.odometry_msg(
                stamp,
                f"{v}/odom",
                f"{v}/base_link",
                pos,
                q,
                np.array([1.0, 0.0, 0.0]),
                np.array([0.0, 0.0, YAW_RATE]),
            )
            yield Envelope(f"/{v}/ground_truth/odometry", stamp, odom)
        yield Envelope("/tf", stamp, ros.tf_message(transforms))


EXPECTED_COUNTS = {
    "/tf_static": 1,
    "/clock": STEPS,
    "/tf": STEPS,
    "/wamv/ground_truth/odometry": STEPS,
    "/otter/ground_truth/odometry": STEPS,
}


EPOCH = 1_767_225_600 * 10**9  # 2026-01-01T00:00:00Z: log time = EPOCH + simulation time


@pytest.fixture
def recording(tmp_path: Path) -> Path:
    path = tmp_path / "run.mcap"
    with McapRecorder(path, epoch_ns=EPOCH) as rec:
        for env in scenario_envelopes():
            rec.write(env)
        assert rec.message_counts == EXPECTED_COUNTS
    return path


def check_messages(messages: list[tuple[str, int, object]], steps: int = STEPS) -> None:
    """Values, stamps, frames and quaternion order (x, y, z, w) of every message; log time - EPOCH = the stamps."""
    counts: dict[str, int] = {}
    for topic, epoch_log_time, msg in messages:
        log_time = epoch_log_time - EPOCH
        counts[topic] = counts.get(topic, 0) + 1
        if topic == "/clock":
            assert ros.time_to_ns(msg.clock) == log_time
        elif topic == "/tf_static":
            assert [(t.header.frame_id, t.child_frame_id) for t in msg.transforms] == [
                ("world", "wamv/odom"),
                ("world", "otter/odom"),
            ]
            assert msg.transforms[0].transform.translation.x == 10.0
            assert msg.transforms[1].transform.rotation.w == 1.0
        elif topic == "/tf":
            k = log_time // DT_NS
            for t, v in zip(msg.transforms, VESSELS):
                assert (t.header.frame_id, t.child_frame_id) == (f"{v}/odom", f"{v}/base_link")
                assert ros.time_to_ns(t.header.stamp) == log_time
                r = t.transform.rotation
                assert np.allclose([r.w, r.x, r.y, r.z], vessel_state(v, k)[1])
        else:
            v = topic.split("/")[1]
            k = log_time // DT_NS
            pos, q = vessel_state(v, k)
            assert ros.time_to_ns(msg.header.stamp) == log_time == k * DT_NS
            assert (msg.header.frame_id, msg.child_frame_id) == (f"{v}/odom", f"{v}/base_link")
            o, p = msg.pose.pose.orientation, msg.pose.pose.position
            assert np.allclose([o.x, o.y, o.z, o.w], [q[1], q[2], q[3], q[0]])
            assert np.allclose([p.x, p.y, p.z], pos)
            assert msg.twist.twist.angular.z == YAW_RATE
            assert len(msg.pose.covariance) == 36 and not any(msg.pose.covariance)
    expected = {t: (1 if t == "/tf_static" else steps) for t in EXPECTED_COUNTS}
    assert counts == expected


def test_rosbags_reads_every_message(recording: Path):
    check_messages(read_with_rosbags(recording))


def test_mcap_ros2_decodes_every_message(recording: Path):
    check_messages(read_with_mcap_ros2(recording))


def test_rosbag2_layout(recording: Path):
    with recording.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None and summary.statistics.message_count == sum(EXPECTED_COUNTS.values())
    schemas = {s.name: s for s in summary.schemas.values()}
    assert set(schemas) == {"tf2_msgs/msg/TFMessage", "rosgraph_msgs/msg/Clock", "nav_msgs/msg/Odometry"}
    assert all(s.encoding == "ros2msg" for s in schemas.values())
    assert b"\nMSG: geometry_msgs/TransformStamped\n" in schemas["tf2_msgs/msg/TFMessage"].data
    channels = {c.topic: c for c in summary.channels.values()}
    assert set(channels) == set(EXPECTED_COUNTS)  # one channel per topic, shared schema for odometry
    assert all(c.message_encoding == "cdr" for c in channels.values())
    counts = summary.statistics.channel_message_counts
    assert {topic: counts[c.id] for topic, c in channels.items()} == EXPECTED_COUNTS
    static_qos = yaml.safe_load(channels["/tf_static"].metadata["offered_qos_profiles"])
    assert (static_qos[0]["durability"], static_qos[0]["depth"], static_qos[0]["reliability"]) == (1, 1, 1)
    assert yaml.safe_load(channels["/tf"].metadata["offered_qos_profiles"])[0]["durability"] == 2
    assert channels["/clock"].metadata["topic_type_hash"].startswith("RIHS01_")

    meta = rosbag2_metadata(recording)
    assert meta["version"] == 8 and meta["storage_identifier"] == "mcap"
    assert meta["files"][0]["duration"] == meta["duration"]
    with recording.open("rb") as f:  # written out as rosbag2 writes it: no YAML anchors (&id001) and aliases
        text = next(m for m in make_reader(f).iter_metadata() if m.name == "rosbag2").metadata["serialized_metadata"]
    assert "&id" not in text and "*id" not in text
    assert meta["relative_file_paths"] == ["run.mcap"]
    assert meta["message_count"] == sum(EXPECTED_COUNTS.values())
    assert meta["starting_time"]["nanoseconds_since_epoch"] == EPOCH + DT_NS  # since 1970: it read 1970-01-01
    assert meta["custom_data"] == {"usvsim.log_time_epoch_ns": str(EPOCH)}
    assert meta["duration"]["nanoseconds"] == (STEPS - 1) * DT_NS
    topics = {t["topic_metadata"]["name"]: t for t in meta["topics_with_message_count"]}
    assert {name: t["message_count"] for name, t in topics.items()} == EXPECTED_COUNTS
    assert topics["/tf"]["topic_metadata"]["type"] == "tf2_msgs/msg/TFMessage"


def test_interrupted_run_leaves_complete_file(tmp_path: Path):
    path = tmp_path / "interrupted.mcap"
    rec = McapRecorder(path, compression="lz4", chunk_size=4096, epoch_ns=EPOCH)  # several chunks before the interrupt
    written = 0
    with pytest.raises(KeyboardInterrupt):
        try:
            for env in scenario_envelopes():
                if env.stamp_ns == 21 * DT_NS and env.topic == "/clock":
                    raise KeyboardInterrupt  # Ctrl-C in the middle of step 21
                rec.write(env)
                written += 1
        finally:
            rec.close()
    assert rec.closed and rec.message_count == written
    rec.close()  # idempotent
    with pytest.raises(ValueError, match="closed"):
        rec.write(Envelope("/clock", 0, ros.clock_msg(0)))
    check_messages(read_with_mcap_ros2(path), steps=20)
    check_messages(read_with_rosbags(path), steps=20)
    assert rosbag2_metadata(path)["message_count"] == written


def test_ctrl_c_during_close_is_deferred(tmp_path: Path, monkeypatch):
    path = tmp_path / "sigint.mcap"
    rec = McapRecorder(path, compression="none", epoch_ns=EPOCH)
    for env in scenario_envelopes(steps=3):
        rec.write(env)
    real_finish = rec._writer.finish

    def finish_with_ctrl_c():
        signal.raise_signal(signal.SIGINT)  # arrives while the summary is being written
        real_finish()

    monkeypatch.setattr(rec._writer, "finish", finish_with_ctrl_c)
    # Python's own Ctrl-C handler, as in a terminal: a process started in the background by a shell without job
    # control (CI scripts, `cmd &` in a script) starts with SIGINT ignored, and then there is rightly nothing to raise
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            rec.close()
    finally:
        signal.signal(signal.SIGINT, previous)
    check_messages(read_with_mcap_ros2(path), steps=3)


def test_recorder_writes_cached_cdr_and_rejects_type_change(tmp_path: Path, monkeypatch):
    store = ros.typestore()
    calls = []
    real = store.serialize_cdr
    monkeypatch.setattr(store, "serialize_cdr", lambda *a, **k: calls.append(1) or real(*a, **k))
    env = Envelope("/clock", 5, ros.clock_msg(5))
    other_consumer = env.cdr  # e.g. a DDS bridge serialized it first
    with McapRecorder(tmp_path / "once.mcap") as rec:
        rec.write(env)
        with pytest.raises(ValueError, match="recorded as"):
            rec.write(Envelope("/clock", 6, ros.header(6, "x")))
    assert len(calls) == 1
    with (tmp_path / "once.mcap").open("rb") as f:
        assert [m.data for _, _, m in make_reader(f).iter_messages()] == [other_consumer]


def test_log_times_are_the_wall_clock_by_default_and_the_stamps_simulation_time(tmp_path: Path):
    """Log times started at 0: Foxglove's timeline and `ros2 bag info` showed 1970-01-01. By default the epoch is the
    wall clock when the recorder is created (as `ros2 bag record` logs receive times); header stamps and /clock stay
    simulation time from 0. The epoch is in the file (metadata `usvsim`, rosbag2 custom_data)."""
    import time

    path, before = tmp_path / "wall.mcap", time.time_ns()
    with McapRecorder(path) as rec:
        for env in scenario_envelopes(steps=3):
            rec.write(env)
    assert before <= rec.epoch_ns <= time.time_ns()
    with path.open("rb") as f:
        reader = make_reader(f)
        epoch = int(next(m for m in reader.iter_metadata() if m.name == "usvsim").metadata["log_time_epoch_ns"])
    assert epoch == rec.epoch_ns
    messages = read_with_mcap_ros2(path)
    clocks = [(log, ros.time_to_ns(m.clock)) for topic, log, m in messages if topic == "/clock"]
    assert clocks == [(epoch + k * DT_NS, k * DT_NS) for k in range(1, 4)]
    assert rosbag2_metadata(path)["starting_time"]["nanoseconds_since_epoch"] == epoch + DT_NS


@pytest.mark.parametrize("epoch", [-1, 2**62 + 1, 1.5, True, "0"])
def test_a_bad_epoch_is_refused(tmp_path: Path, epoch):
    with pytest.raises(InputError, match="epoch_ns"):
        McapRecorder(tmp_path / "x.mcap", epoch_ns=epoch)
    assert not (tmp_path / "x.mcap").exists()
