"""Recover a recording cut short (kill -9, power loss, disk full): every complete record up to the damage
is rewritten into a standard rosbag2-layout MCAP with summary, index and `rosbag2` metadata.

The recorder flushes a chunk at least every 0.5 s of simulated time (io/mcap_recorder.py), so a
recovered file lacks at most that much at its end. Chunks are CRC-checked: a damaged chunk ends the
recovery there, nothing after it is trusted.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mcap.records import Channel, Footer, Message, Metadata, Schema
from mcap.stream_reader import StreamReader

from usvsim.core.errors import UsvsimError
from usvsim.io.mcap_recorder import McapRecorder, _Topic

MCAP_MAGIC = b"\x89MCAP0\r\n"  # the first 8 bytes of every MCAP file (format version 0)


@dataclass(frozen=True)
class Recovered:
    path: Path
    messages: int
    end_ns: int  # stamp of the last recovered message
    complete: bool  # the input ended cleanly (it had its summary and footer)


def recover(source: Path, target: Path) -> Recovered:
    """Copy the readable part of `source` into `target` (a new, complete file)."""
    if source.resolve() == target.resolve() or (target.exists() and source.exists() and source.samefile(target)):
        raise UsvsimError(f"recover writes a new file; choose an output other than {source}")  # (a hard link too)
    with source.open("rb") as f:
        head = f.read(len(MCAP_MAGIC))
    if not head:
        raise UsvsimError(f"{source} is empty: nothing to recover")
    if not MCAP_MAGIC.startswith(head):  # a file cut inside its 8-byte magic is still a recording
        raise UsvsimError(f"{source} is not an MCAP recording (it does not start with the MCAP magic bytes)")
    schemas: dict[int, Schema] = {}
    topics: dict[int, _Topic] = {}
    complete = False
    # epoch 0 for a file without an epoch record (older usvsim: log time = simulation time)
    with source.open("rb") as f, McapRecorder(target, epoch_ns=0) as out:
        try:
            for record in StreamReader(f, skip_magic=False, emit_chunks=False, validate_crcs=True).records:
                if isinstance(record, Metadata) and record.name == "usvsim" and not out.message_count:
                    # written before the first message
                    out.epoch_ns = int(record.metadata["log_time_epoch_ns"])
                elif isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel) and record.id not in topics:
                    topics[record.id] = _register(out, record, schemas[record.schema_id])
                elif isinstance(record, Message) and record.channel_id in topics:
                    out._append(topics[record.channel_id], record.log_time, record.data)
                complete = complete or isinstance(record, Footer)
        except Exception:
            pass
        return Recovered(target, out.message_count, out._end_ns, complete)


def _register(out: McapRecorder, channel: Channel, schema: Schema) -> _Topic:
    meta = channel.metadata
    return out._register_raw(channel.topic, schema.name, schema.data, meta.get("offered_qos_profiles", ""),
                             meta.get("topic_type_hash", ""))  # fmt: skip
