"""Two independent readers of usvsim's MCAP recordings, shared by the tests: rosbags and mcap-ros2."""

from __future__ import annotations

from pathlib import Path

import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

from usvsim.messages import ros


def rosbag2_metadata(path: Path) -> dict:
    with path.open("rb") as f:
        records = [m for m in make_reader(f).iter_metadata() if m.name == "rosbag2"]
    assert len(records) == 1
    return yaml.safe_load(records[0].metadata["serialized_metadata"])


def read_with_rosbags(path: Path) -> list[tuple[str, int, object]]:
    """rosbags reads rosbag2 directories: give it the bare file plus the metadata.yaml that rosbag2
    reconstructs from the file's `rosbag2` record (this also checks that record is valid metadata)."""
    bag = path.parent / "bag"
    bag.mkdir()
    (bag / path.name).symlink_to(path)
    info = {"rosbag2_bagfile_information": rosbag2_metadata(path)}
    (bag / "metadata.yaml").write_text(yaml.safe_dump(info))
    with AnyReader([bag], default_typestore=ros.typestore()) as reader:
        qos = {c.topic: c.ext.offered_qos_profiles for c in reader.connections}
        assert qos["/tf_static"][0].durability.name == "TRANSIENT_LOCAL"
        assert qos["/tf_static"][0].depth == 1 and qos["/tf"][0].durability.name == "VOLATILE"
        return [(c.topic, t, reader.deserialize(raw, c.msgtype)) for c, t, raw in reader.messages()]


def read_with_mcap_ros2(path: Path) -> list[tuple[str, int, object]]:
    with path.open("rb") as f:
        reader = make_reader(f, validate_crcs=True, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        return [(ch.topic, m.log_time, dec) for _, ch, m, dec in reader.iter_decoded_messages()]
