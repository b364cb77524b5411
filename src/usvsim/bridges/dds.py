"""Live ROS 2 over DDS (Cyclone DDS): every simulation topic out, every command topic in.

    bridge = DdsBridge(sim)                  # domain 0 (or $ROS_DOMAIN_ID), loopback only
    sim.run(60.0, realtime=True)
    bridge.close()

Out: each `Envelope` the simulation emits is written to DDS topic `rt/<topic>` with type name
`pkg::msg::dds_::Type_`, on a writer created on the topic's first message with the envelope's QoS
(reliable, KEEP_LAST(depth), volatile or transient_local for /tf_static), XCDR1 data representation and
USER_DATA `typehash=RIHS01_…;` (what Jazzy RMWs announce). The envelope's CDR bytes go out as they are: no
second serialization. Real ROS 2 nodes (rmw_fastrtps, rmw_cyclonedds) receive them as ordinary topics.

In: one reader per topic of `sim.commands.topics` (thrusters, cmd_vel, /reset); raw CDR samples go to
`sim.commands.post_cdr`, which validates and queues them for the next step. The readers of the streaming
commands (cmd_vel, thrust) are best-effort, so that both reliable and best-effort publishers match them
(`qos_profile_sensor_data`); the one-shot ones (/reset, thruster angles) are reliable, so that a command sent
once (`ros2 topic pub --once`) is repaired if its first packet is lost, and need a reliable publisher.

Threads: the step loop only serializes (once, shared with other consumers) and appends to a bounded
queue; a sender thread writes to DDS; when it falls behind, the oldest queued message is dropped and
counted (`stats["dropped"]`); after each large sample it pauses briefly (`PACE_BYTES_PER_S`) so that receivers with
default socket buffers keep up. A receiver thread waits on the command readers. Neither ever blocks the step.
`mode="inline"` writes from the step loop instead (lowest latency, for light topic sets).

Network: see `dds_config.py` (loopback by default; `interface="eth0"` for a real network).
"""

from __future__ import annotations

import os
import threading
from collections import deque
from typing import TYPE_CHECKING, Any, Literal

from usvsim.bridges import dds_types
from usvsim.bridges.dds_config import LOOPBACK_NAMES, cyclone_config
from usvsim.bridges.dds_domain import acquire_domain, release_domain
from usvsim.core import queues
from usvsim.messages.envelope import Envelope, QosProfile
from usvsim.messages.ros import typestore

if TYPE_CHECKING:
    from usvsim.simulation import Simulation

QUEUE_LIMIT = 256  # envelopes waiting for the sender thread; the oldest is dropped beyond this
MAX_BLOCKING_MS = 20  # a reliable writer whose history is full waits at most this long (sender thread)
COMMAND_DEPTH = 10
# After a large sample (an image, a cloud) the sender pauses for len / PACE_BYTES_PER_S, so that back-to-back
# samples do not overflow a receiver's socket buffer: a default Fast DDS reader listens with the kernel's
# default 208 KiB and loses best-effort fragments of an RGB + depth pair sent without a gap.
PACE_ABOVE_BYTES = 128 * 1024
PACE_BYTES_PER_S = 400e6
STAT_KEYS = ("published", "bytes", "dropped", "write_errors", "queue_high_water", "writers",
             "commands_received", "commands_refused")  # fmt: skip


class DdsBridge:
    """Publishes every simulation topic over Cyclone DDS with ROS 2 naming; feeds commands back in."""

    def __init__(
        self,
        sim: Simulation,
        domain_id: int | None = None,
        interface: str | None = "lo",
        *,
        mode: Literal["thread", "inline"] = "thread",
        queue_limit: int = QUEUE_LIMIT,
        config: str | None = None,
    ) -> None:
        from cyclonedds.domain import DomainParticipant

        dds_types.check_raw_api()
        if mode not in ("thread", "inline"):
            raise ValueError(f"mode must be 'thread' or 'inline', got {mode!r}")
        if domain_id is None:
            domain_id = int(os.environ.get("ROS_DOMAIN_ID", "0"))
        self.domain_id, self.mode = domain_id, mode
        self.stats: dict[str, int] = dict.fromkeys(STAT_KEYS, 0)
        self._sim = sim
        self._writers: dict[str, tuple[Any, str]] = {}  # topic → (writer, msgtype)
        self._queue: deque[Envelope] = queues.bounded(queue_limit)
        self._wake = threading.Event()
        self._closed = threading.Event()
        device = "lo" if config is None and interface in LOOPBACK_NAMES else None
        self._domain = acquire_domain(domain_id, config or cyclone_config(interface), device)
        self.participant = DomainParticipant(domain_id)
        self._readers = [self._command_reader(topic, t) for topic, t in sim.commands.topics.items()]
        self._threads = [threading.Thread(target=self._receive_loop, name="usvsim-dds-rx", daemon=True)]
        if mode == "thread":
            self._threads.append(threading.Thread(target=self._send_loop, name="usvsim-dds-tx", daemon=True))
        for thread in self._threads:
            thread.start()
        self._unsubscribe = sim.subscribe(self._on_envelope)

    # -- out: simulation thread -------------------------------------------------------------------
    def _on_envelope(self, envelope: Envelope) -> None:
        _ = envelope.cdr  # serialize once, here (shared with other consumers), not in the sender thread
        if self.mode == "inline":
            self._publish(envelope)
            return
        queue = self._queue
        if queues.push(queue, envelope):
            self.stats["dropped"] += 1
        self.stats["queue_high_water"] = max(self.stats["queue_high_water"], len(queue))
        self._wake.set()

    # -- out: sender thread -----------------------------------------------------------------------
    def _send_loop(self) -> None:
        queue = self._queue
        while not self._closed.is_set():
            self._wake.wait(0.1)
            self._wake.clear()
            while queue:
                try:
                    envelope = queue.popleft()
                except IndexError:  # dropped by the simulation thread meanwhile
                    break
                self._publish(envelope)
                if len(envelope.cdr) > PACE_ABOVE_BYTES:  # let the receivers drain their sockets
                    self._closed.wait(len(envelope.cdr) / PACE_BYTES_PER_S)

    def _publish(self, envelope: Envelope) -> None:
        entry = self._writers.get(envelope.topic)
        if entry is None:
            entry = self._writers[envelope.topic] = (self._writer(envelope), envelope.msgtype)
            self.stats["writers"] = len(self._writers)
        writer, msgtype = entry
        if msgtype != envelope.msgtype or dds_types.write_cdr(writer, envelope.cdr) < 0:
            self.stats["write_errors"] += 1
            return
        self.stats["published"] += 1
        self.stats["bytes"] += len(envelope.cdr)

    def _writer(self, envelope: Envelope) -> Any:
        from cyclonedds.pub import DataWriter
        from cyclonedds.topic import Topic

        topic = Topic(self.participant, dds_types.dds_topic_name(envelope.topic),
                      dds_types.idl_type(envelope.msgtype))  # fmt: skip
        return DataWriter(self.participant, topic, qos=_qos(envelope.qos, envelope.msgtype))

    # -- in: receiver thread ----------------------------------------------------------------------
    def _command_reader(self, topic: str, msgtype: str) -> tuple[str, Any]:
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        dds_topic = Topic(self.participant, dds_types.dds_topic_name(topic), dds_types.idl_type(msgtype))
        reliability = "best_effort" if self._sim.commands.streaming(topic) else "reliable"
        qos = _qos(QosProfile(reliability=reliability, depth=COMMAND_DEPTH), msgtype)
        return topic, DataReader(self.participant, dds_topic, qos=qos)

    def _receive_loop(self) -> None:
        from cyclonedds.core import (
            GuardCondition,
            InstanceState,
            ReadCondition,
            SampleState,
            ViewState,
            WaitSet,
        )
        from cyclonedds.util import duration

        waitset = WaitSet(self.participant)
        self._guard = GuardCondition(self.participant)
        waitset.attach(self._guard)
        mask = SampleState.Any | ViewState.Any | InstanceState.Any
        conditions = [ReadCondition(reader, mask) for _, reader in self._readers]
        for condition in conditions:
            waitset.attach(condition)
        while not self._closed.is_set():
            waitset.wait(duration(milliseconds=200))
            for topic, reader in self._readers:
                for cdr in dds_types.take_cdr(reader):
                    self._post(topic, cdr)

    def _post(self, topic: str, cdr: bytes) -> None:
        ok = self._sim.commands.post_cdr(topic, cdr)
        self.stats["commands_received" if ok else "commands_refused"] += 1

    # -- lifecycle --------------------------------------------------------------------------------
    @property
    def topics(self) -> dict[str, str]:
        """Published topics so far → ROS type."""
        return {topic: msgtype for topic, (_, msgtype) in self._writers.items()}

    def close(self) -> None:
        """Stop the threads, delete the DDS entities; idempotent."""
        if self._closed.is_set():
            return
        self._unsubscribe()
        self._closed.set()
        self._wake.set()
        guard = getattr(self, "_guard", None)
        if guard is not None:
            guard.set(True)
        for thread in self._threads:
            thread.join(timeout=2.0)
        dds_types.delete_entity(self.participant)
        self._writers.clear()
        self._readers.clear()
        release_domain(self._domain)

    def __enter__(self) -> DdsBridge:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _qos(profile: QosProfile, msgtype: str) -> Any:
    """Cyclone QoS for a ROS QoS profile, XCDR1, with the Jazzy type hash in USER_DATA."""
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.util import duration

    if profile.reliability == "reliable":
        reliability = Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=MAX_BLOCKING_MS))
    else:
        reliability = Policy.Reliability.BestEffort
    durability = (Policy.Durability.TransientLocal if profile.durability == "transient_local"
                  else Policy.Durability.Volatile)  # fmt: skip
    return Qos(
        reliability,
        durability,
        Policy.History.KeepLast(profile.depth),
        Policy.DataRepresentation(use_cdrv0_representation=True),
        Policy.Userdata(f"typehash={typestore().hash_rihs01(msgtype)};".encode()),
    )
