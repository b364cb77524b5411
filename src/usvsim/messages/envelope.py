"""The message envelope shared by every consumer (recorder, DDS bridge, Foxglove bridge, callbacks).

A sensor emits one `Envelope` per message. `stamp_ns` is the message's header stamp (when it was measured);
`publish_ns` is when the simulation emitted it (>= the stamp: a LiDAR sweep is stamped at its first
column and published when the sweep ends, a sensor with latency is published `latency_s` later). The MCAP
recorder logs at `publish_ns`, so a replayed bag never delivers a message before it could have existed.
Its CDR bytes are computed on first access of `cdr` and
cached, so the message is serialized once however many consumers read it. Producers that build CDR
themselves (e.g. a fast image path) pass `cdr=` directly.

`QosProfile` is the offered QoS of a topic, chosen once per topic by `qos_for_topic`, so the MCAP
recorder (`offered_qos_profiles`) and the live bridges offer the same thing (ros2-interop.md §2.3).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from usvsim.messages.cdr_fast import FAST
from usvsim.messages.ros import typestore


@dataclass(frozen=True, slots=True)
class QosProfile:
    """Offered QoS of a writer: KEEP_LAST(depth), reliability, durability; other policies default."""

    reliability: Literal["reliable", "best_effort"] = "reliable"
    durability: Literal["volatile", "transient_local"] = "volatile"
    depth: int = 10


SENSOR_QOS = QosProfile()  # reliable serves best-effort readers too (slam_toolbox, Nav2) and rviz2
TF_QOS = QosProfile(depth=100)  # tf2 DynamicListenerQoS
TF_STATIC_QOS = QosProfile(durability="transient_local", depth=1)  # tf2 StaticBroadcasterQoS
CLOCK_QOS = QosProfile(depth=1)
EPISODE_TOPIC = "/usvsim/episode"  # the episode marker (usvsim.ground_truth), latched like /tf_static
MARKERS_TOPIC = "/usvsim/markers"  # the scene's vessels and obstacles (usvsim.scene_markers), latched
_TOPIC_QOS = {"/tf_static": TF_STATIC_QOS, "/tf": TF_QOS, "/clock": CLOCK_QOS, EPISODE_TOPIC: TF_STATIC_QOS,
              MARKERS_TOPIC: TF_STATIC_QOS}  # fmt: skip


def qos_for_topic(topic: str) -> QosProfile:
    """Default offered QoS of `topic`: `/tf_static`, the episode marker and the scene markers transient_local
    depth 1, everything else volatile."""
    return _TOPIC_QOS.get(topic, SENSOR_QOS)


class Envelope:
    """One message on one topic at one simulation time, with its CDR serialized at most once.

    `msgtype` defaults to the message's ROS type (`msg.__msgtype__`, e.g. "nav_msgs/msg/Odometry");
    `qos` defaults to `qos_for_topic(topic)`. Reading `cdr` from several threads at once is safe
    (the result is the same); it may then serialize more than once, so producers that fan out to
    threaded consumers should touch `cdr` once before handing the envelope over.
    """

    __slots__ = ("_cdr", "_msg", "msgtype", "publish_ns", "qos", "stamp_ns", "topic")
    msgtype: str  # set in __init__: given, or the message's own

    def __init__(
        self,
        topic: str,
        stamp_ns: int,
        msg: Any = None,
        *,
        msgtype: str | None = None,
        qos: QosProfile | None = None,
        cdr: bytes | None = None,
        publish_ns: int | None = None,
    ) -> None:
        if msg is None and cdr is None:
            raise ValueError("an Envelope needs a message or its CDR bytes")
        self.topic = topic
        if msgtype is not None:
            self.msgtype = msgtype
        elif msg is None:
            raise ValueError("msgtype is required when only CDR bytes are given")
        else:
            self.msgtype = msg.__msgtype__
        self.stamp_ns = int(stamp_ns)
        self.publish_ns = self.stamp_ns if publish_ns is None else int(publish_ns)
        self._msg = msg
        self.qos = qos if qos is not None else qos_for_topic(topic)
        self._cdr = cdr

    @property
    def cdr(self) -> bytes:
        """CDR (XCDR1, little endian, with the 4-byte encapsulation header), serialized once."""
        if self._cdr is None:
            fast = FAST.get(self.msgtype)
            self._cdr = fast(self.msg) if fast else bytes(typestore().serialize_cdr(self.msg, self.msgtype))
        return self._cdr

    @property
    def msg(self) -> Any:
        """The message object; an envelope built from CDR bytes only deserializes them on first access."""
        if self._msg is None:
            self._msg = typestore().deserialize_cdr(self._cdr, self.msgtype)
        return self._msg

    def decoded(self) -> Any:
        """The message object (`msg`)."""
        return self.msg

    def __repr__(self) -> str:
        return f"Envelope({self.topic!r}, {self.msgtype!r}, stamp_ns={self.stamp_ns})"
