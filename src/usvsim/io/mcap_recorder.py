"""MCAP recorder in the rosbag2 layout: one `.mcap` file that `ros2 bag` (Jazzy) and Foxglove open.

Layout (what rosbag2_storage_mcap writes and reads, ros2-interop.md §5):
- header profile `ros2`; one schema per message type, named `pkg/msg/Type`, encoding `ros2msg`,
  data = the full concatenated `.msg` definition; channels with message_encoding `cdr` and metadata
  `offered_qos_profiles` (metadata-version-8 YAML string) and `topic_type_hash` (RIHS01);
- messages carry the envelope's CDR bytes unchanged, logTime = publishTime = `epoch_ns` + the envelope's
  `publish_ns` (the simulation time it was emitted, never before its header stamp) + an episode offset: each
  episode marker (`/usvsim/episode`, sent at a reset) after the first moves the offset to 1 ns past the
  last log time, so log times keep increasing while stamps and /clock restart at 0;
- `epoch_ns` (ns since 1970-01-01 UTC) is by default the wall clock when the recorder is created, as `ros2 bag
  record` logs receive times, so Foxglove's timeline and `ros2 bag info` show the date of the run (log times from
  0 read as 1970). Header stamps and /clock stay simulation time from 0 (what nodes with use_sim_time expect),
  identical from run to run; give a fixed `epoch_ns` (0: log time = simulation time) for byte-identical files.
  The epoch is written in a metadata record `usvsim` (`log_time_epoch_ns`, before the first message) and in
  the rosbag2 metadata's `custom_data`;
- at close, a metadata record `rosbag2` with `serialized_metadata` (the bag information YAML), then
  the summary and footer.

The file is complete only after `close()`: call it in a `finally` (or use the recorder as a context
manager). `close()` holds back Ctrl-C while it writes the summary and re-raises it afterwards.

Crash safety: chunks are at most `chunk_size` bytes (1 MiB) and the chunk in progress is written out and
flushed to the OS at least every `flush_interval_s` of simulated time (0.5 s), so a process killed hard
(`kill -9`, power aside) loses at most that much; `usvsim recover FILE` (io/mcap_recover.py) rewrites
every complete chunk of such a file into a standard one. A failed write (disk full, I/O error) raises
a UsvsimError once and leaves the file recoverable up to the last flushed chunk.
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Self

import yaml
from mcap.writer import CompressionType, Writer

from usvsim.core.errors import InputError, UsvsimError
from usvsim.io.topic_filter import TopicFilter
from usvsim.messages.envelope import EPISODE_TOPIC, Envelope, QosProfile
from usvsim.messages.ros import message_definition, typestore

METADATA_VERSION = 8
_COMPRESSION = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
COMPRESSIONS = tuple(_COMPRESSION)  # the names `compression` takes
# rmw QoS enum values, as rosbag2 metadata version 8 writes them.
_RELIABILITY = {"reliable": 1, "best_effort": 2}
_DURABILITY = {"transient_local": 1, "volatile": 2}
_KEEP_LAST, _LIVELINESS_AUTOMATIC = 1, 1
_INFINITE = {"sec": 9223372036, "nsec": 854775807}  # RMW_DURATION_INFINITE


def qos_yaml(qos: QosProfile) -> str:
    """`offered_qos_profiles` string (metadata version 8: a YAML list with integer enums)."""
    profile = {
        "history": _KEEP_LAST,
        "depth": qos.depth,
        "reliability": _RELIABILITY[qos.reliability],
        "durability": _DURABILITY[qos.durability],
        "deadline": dict(_INFINITE),
        "lifespan": dict(_INFINITE),
        "liveliness": _LIVELINESS_AUTOMATIC,
        "liveliness_lease_duration": dict(_INFINITE),
        "avoid_ros_namespace_conventions": False,
    }
    return yaml.safe_dump([profile], sort_keys=False).strip()


@dataclass
class _Topic:
    channel_id: int
    msgtype: str
    qos_yaml: str
    type_hash: str
    count: int = 0


class McapRecorder:
    """Writes `Envelope`s to a rosbag2-layout MCAP file; channels are registered on first message.

    compression: chunk compression, "zstd" (default), "lz4" or "none"; all are read by rosbag2 and
    Foxglove. On the 2-core reference machine zstd writes ~250 MB/s of camera images vs ~900 MB/s
    uncompressed (benchmarks/bench_recorder.py); pass "none" when images dominate and disk is cheap.
    chunk_size: uncompressed bytes per chunk.
    topics: record only these (names or patterns, a `TopicFilter`; None: all). The episode marker still moves the
    log-time offset when it is not recorded (after a reset the log times went back to 0).
    """

    def __init__(
        self,
        path: str | Path,
        *,
        compression: Literal["zstd", "lz4", "none"] = "zstd",
        chunk_size: int = 1024 * 1024,
        flush_interval_s: float = 0.5,
        ros_distro: str = "jazzy",
        topics: TopicFilter | None = None,
        epoch_ns: int | None = None,
    ) -> None:
        from usvsim import __version__

        if compression not in _COMPRESSION:
            raise InputError(f"compression must be one of {sorted(_COMPRESSION)}, got {compression!r}")
        self.epoch_ns = time.time_ns() if epoch_ns is None else check_epoch_ns(epoch_ns)
        self.path = Path(path)
        self.topic_filter = topics if topics is not None else TopicFilter(None)
        self.ros_distro = ros_distro
        self._topics: dict[str, _Topic] = {}
        self._schemas: dict[str, int] = {}
        self._start_ns: int | None = None
        self._end_ns = 0
        self._flush_interval_ns, self._flushed_ns = int(flush_interval_s * 1e9), self.epoch_ns
        self._closed = self._failed = False
        # added to publish times: the epoch, and what keeps log times increasing across episodes
        self._offset_ns = self.epoch_ns
        self._epoch_written = False
        try:
            self._file = self.path.open("wb")
        except OSError as exc:  # the CLI printed "[Errno 2] No such file or directory: '/proc/x.mcap'"
            raise UsvsimError(f"cannot write {self.path}: {exc.strerror or exc}") from None
        try:
            self._writer = Writer(self._file, chunk_size=chunk_size, compression=_COMPRESSION[compression])
            self._writer.start(profile="ros2", library=f"usvsim/{__version__}")
        except BaseException:
            self._closed = True
            self._file.close()
            raise

    # -- writing -----------------------------------------------------------------------------------
    def write(self, envelope: Envelope) -> None:
        """Append one message (its cached CDR is written as is)."""
        if self._closed:
            raise ValueError(f"recorder for {self.path} is closed")
        if not self.topic_filter(envelope.topic):
            if envelope.topic == EPISODE_TOPIC and self._start_ns is not None:
                self._offset_ns = self._end_ns + 1 - envelope.publish_ns
            return
        topic = self._topics.get(envelope.topic) or self._register(envelope)
        if topic.msgtype != envelope.msgtype:
            raise ValueError(
                f"topic {envelope.topic} was recorded as {topic.msgtype}, got {envelope.msgtype}"
            )
        data = envelope.cdr  # serialize (once) before touching any state
        if envelope.topic == EPISODE_TOPIC and self._start_ns is not None:
            self._offset_ns = self._end_ns + 1 - envelope.publish_ns
        self._append(topic, envelope.publish_ns + self._offset_ns, data)

    def _append(self, topic: _Topic, stamp: int, data: bytes) -> None:
        topic.count += 1
        try:
            if not self._epoch_written:  # before the first message: kept by `usvsim recover`
                self._epoch_written = True
                self._writer.add_metadata("usvsim", {"log_time_epoch_ns": str(self.epoch_ns)})
            self._writer.add_message(topic.channel_id, stamp, data, stamp, topic.count)
            if stamp - self._flushed_ns >= self._flush_interval_ns:
                self._writer.flush()  # the chunk in progress goes to the OS: a hard kill loses at most this
                self._flushed_ns = stamp
        except OSError as exc:
            self._fail(exc)
        if self._start_ns is None or stamp < self._start_ns:
            self._start_ns = stamp
        self._end_ns = max(self._end_ns, stamp)

    def _fail(self, exc: OSError) -> None:
        self._closed = self._failed = True
        with suppress(OSError):
            self._file.close()
        raise UsvsimError(f"recording to {self.path} stopped: {exc.strerror or exc}; it is readable up to the "
                          f"last flushed chunk after 'usvsim recover {self.path}'") from None  # fmt: skip

    def _register(self, envelope: Envelope) -> _Topic:
        msgtype = envelope.msgtype
        qos, type_hash = qos_yaml(envelope.qos), typestore().hash_rihs01(msgtype)
        return self._register_raw(envelope.topic, msgtype, message_definition(msgtype).encode(), qos, type_hash)

    def _register_raw(self, name: str, msgtype: str, msgdef: bytes, qos: str, type_hash: str) -> _Topic:
        if msgtype not in self._schemas:
            self._schemas[msgtype] = self._writer.register_schema(msgtype, "ros2msg", msgdef)
        topic = _Topic(0, msgtype, qos, type_hash)
        topic.channel_id = self._writer.register_channel(
            name, "cdr", self._schemas[msgtype], {"offered_qos_profiles": qos, "topic_type_hash": type_hash}
        )
        self._topics[name] = topic
        return topic

    # -- state -------------------------------------------------------------------------------------
    @property
    def message_counts(self) -> dict[str, int]:
        """Messages written so far, per topic."""
        return {name: t.count for name, t in self._topics.items()}

    @property
    def message_count(self) -> int:
        return sum(t.count for t in self._topics.values())

    @property
    def closed(self) -> bool:
        return self._closed

    # -- closing -----------------------------------------------------------------------------------
    def close(self) -> None:
        """Write the rosbag2 metadata record, summary and footer, and close the file. Idempotent."""
        if self._closed:
            return
        self._closed = True
        with _sigint_deferred(), _as_usvsim_error(self.path):
            try:
                self._writer.add_metadata(
                    "rosbag2", {"serialized_metadata": self.bag_info_yaml(), "ROS_DISTRO": self.ros_distro}
                )
                self._writer.finish()
            finally:
                self._file.close()

    def bag_info_yaml(self) -> str:
        """rosbag2 `BagMetadata` (version 8) as YAML, as rosbag2 stores it in `serialized_metadata`."""
        start = self._start_ns or 0
        duration = {"nanoseconds": max(0, self._end_ns - start)}
        starting_time = {"nanoseconds_since_epoch": start}  # each used twice: copied below, so no YAML anchors
        info = {
            "version": METADATA_VERSION,
            "storage_identifier": "mcap",
            "duration": duration,
            "starting_time": starting_time,
            "message_count": self.message_count,
            "topics_with_message_count": [
                {
                    "topic_metadata": {
                        "name": name,
                        "type": t.msgtype,
                        "serialization_format": "cdr",
                        "offered_qos_profiles": t.qos_yaml,
                        "type_description_hash": t.type_hash,
                    },
                    "message_count": t.count,
                }
                for name, t in self._topics.items()
            ],
            "compression_format": "",
            "compression_mode": "",
            "relative_file_paths": [self.path.name],
            "files": [
                {
                    "path": self.path.name,
                    "starting_time": dict(starting_time),
                    "duration": dict(duration),
                    "message_count": self.message_count,
                }
            ],
            "custom_data": {"usvsim.log_time_epoch_ns": str(self.epoch_ns)},
            "ros_distro": self.ros_distro,
        }
        return yaml.safe_dump(info, sort_keys=False)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __del__(self) -> None:  # last resort: a forgotten recorder still leaves a valid file
        if not getattr(self, "_closed", True):
            with suppress(Exception):
                self.close()


# 2116-02-20; log times are 64-bit ns (signed in rosbag2): this leaves 146 years of run after it
MAX_EPOCH_NS = 2**62


def check_epoch_ns(epoch_ns: object) -> int:
    """`epoch_ns` as an int, or an InputError: a whole number of ns since 1970-01-01 UTC, 0 to MAX_EPOCH_NS."""
    if isinstance(epoch_ns, bool) or not isinstance(epoch_ns, int) or not 0 <= epoch_ns <= MAX_EPOCH_NS:
        raise InputError(f"epoch_ns must be a whole number of nanoseconds since 1970-01-01 UTC, 0 to 2**62 "
                         f"(the year 2116), got {epoch_ns!r}")  # fmt: skip
    return int(epoch_ns)


def parse_epoch(text: str) -> int | None:
    """`--record-epoch`: "now" (None: the wall clock), seconds since 1970-01-01 UTC ("0": log time = simulation
    time), or an ISO 8601 date and time ("2026-01-01T00:00:00Z"; without a zone, UTC) → ns; else an InputError."""
    from datetime import UTC, datetime
    from decimal import Decimal, InvalidOperation

    text = text.strip()
    if text.lower() == "now":
        return None
    try:
        ns = Decimal(text) * 10**9  # exact: a float lost the nanoseconds of today's dates
    except InvalidOperation:
        try:
            when = datetime.fromisoformat(text)
        except ValueError:
            raise InputError(f"--record-epoch must be now, seconds since 1970-01-01 UTC or an ISO 8601 date and time "
                             f"such as 2026-01-01T00:00:00Z, got {text[:40]!r}") from None  # fmt: skip
        when = when if when.tzinfo is not None else when.replace(tzinfo=UTC)
        delta = when - datetime(1970, 1, 1, tzinfo=UTC)
        ns = Decimal((delta.days * 86400 + delta.seconds) * 10**6 + delta.microseconds) * 1000
    if not ns.is_finite() or not 0 <= ns <= MAX_EPOCH_NS:
        raise InputError(f"--record-epoch must be from 1970-01-01 to 2116-02-20 (UTC), got {text[:40]!r}")
    return int(ns)


@contextmanager
def _as_usvsim_error(path: Path) -> Iterator[None]:
    try:
        yield
    except OSError as exc:
        raise UsvsimError(f"finishing the recording {path} failed: {exc.strerror or exc}; "
                          f"'usvsim recover {path}' reads what was flushed") from None  # fmt: skip


@contextmanager
def _sigint_deferred() -> Iterator[None]:
    """Hold back SIGINT (Ctrl-C) for the block and raise KeyboardInterrupt after it, if one came."""
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous is None:
        yield  # signal handlers can only be changed from the main thread
        return
    received: list[int] = []
    signal.signal(signal.SIGINT, lambda signum, _frame: received.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if received and callable(previous):
            previous(signal.SIGINT, None)  # the default handler raises KeyboardInterrupt here
