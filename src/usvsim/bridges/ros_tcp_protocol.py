"""ROS-TCP-Endpoint v0.7.0 (ROS 2) wire format: frames, system commands, an incremental frame reader.

Every frame, both directions, is two length-prefixed blobs (uint32 little endian lengths):
``[len(destination)][destination][len(payload)][payload]``. The destination is a topic, a system command
(``__publish``, ``__subscribe``, ``__topic_list``, ``__handshake``, ``__log``/``__warn``/``__error``...) or ``""``
(keepalive, eight zero bytes). Topic payloads are ROS 2 serialized messages: XCDR1 little endian with the
4-byte encapsulation header ``00 01 00 00``.

The asymmetry a client must reproduce (ROS-TCP-Connector in ROS 2 mode, ros2-interop.md §1.2): strings the
client writes carry a trailing NUL counted in their length (``0a000000 "__publish\\0"``), and the JSON of a
system command is followed by a ``\\0`` because the endpoint drops the last character of every command JSON
before parsing it. Strings the endpoint writes have no NUL. Topic payloads are sent as they are.
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass
from typing import Any

U32 = struct.Struct("<I")
KEEPALIVE = b"\x00" * 8  # empty destination, empty payload
MAX_DESTINATION = 1024  # bytes; ROS names are far shorter, a larger length means a broken stream
MAX_PAYLOAD = 64 << 20  # bytes; endpoint → client frames are commands (tiny) or subscribed messages


@dataclass(frozen=True)
class Timing:
    """Client timing, seconds; the first three are ROS-TCP-Connector's defaults (keepalive after 1 s without
    sending, 2 s to finish a started frame, 1 s between connection attempts)."""

    keepalive_s: float = 1.0
    read_timeout_s: float = 2.0
    reconnect_delay_s: float = 1.0
    connect_timeout_s: float = 2.0
    write_timeout_s: float = 5.0  # a send stalled this long (endpoint not reading) drops the connection
    drain_s: float = 1.0  # at close: after the last frames and a half-close, wait this long for the endpoint's EOF


class ProtocolError(Exception):
    """The byte stream from the peer is not ROS-TCP framing (bad length, bad name, bad JSON)."""


def endpoint_message_name(msgtype: str) -> str:
    """The endpoint's type name: ``sensor_msgs/msg/Image`` → ``sensor_msgs/Image`` (``/msg/`` removed)."""
    return msgtype.replace("/msg/", "/", 1)


def client_string(text: str) -> bytes:
    """A client → endpoint string: length (including the NUL), UTF-8 bytes, NUL."""
    data = text.encode("utf-8") + b"\x00"
    return U32.pack(len(data)) + data


def client_topic_frame(topic: str, payload: bytes | bytearray | memoryview) -> bytes:
    """A client → endpoint message frame: NUL-terminated topic, then the CDR payload as it is."""
    return b"".join((client_string(topic), U32.pack(len(payload)), payload))


def client_command_frame(command: str, params: dict[str, Any]) -> bytes:
    """A client → endpoint system command: NUL-terminated ``__name``, then compact JSON plus ``\\0``."""
    body = json.dumps(params, separators=(",", ":")).encode("utf-8") + b"\x00"
    return client_string(command) + U32.pack(len(body)) + body


def publish_command(topic: str, msgtype: str, queue_size: int = 10, latch: bool = False) -> bytes:
    """``__publish``: the endpoint creates a ROS 2 publisher (RELIABLE, VOLATILE, KEEP_LAST(queue_size))."""
    params = {"topic": topic, "message_name": endpoint_message_name(msgtype),
              "queue_size": int(queue_size), "latch": bool(latch)}  # fmt: skip
    return client_command_frame("__publish", params)


def subscribe_command(topic: str, msgtype: str) -> bytes:
    """``__subscribe``: the endpoint forwards every message on `topic` to the client as a topic frame."""
    params = {"topic": topic, "message_name": endpoint_message_name(msgtype)}
    return client_command_frame("__subscribe", params)


def endpoint_frame(destination: str, payload: bytes | bytearray | memoryview) -> bytes:
    """An endpoint → client frame (no NUL anywhere)."""
    name = destination.encode("utf-8")
    return b"".join((U32.pack(len(name)), name, U32.pack(len(payload)), payload))


def endpoint_command_frame(command: str, params: dict[str, Any]) -> bytes:
    """An endpoint → client system command (Python ``json.dumps`` default separators, no NUL)."""
    return endpoint_frame(command, json.dumps(params).encode("utf-8"))


def handshake_frame(version: str = "v0.7.0", protocol: str = "ROS2") -> bytes:
    """The endpoint's first frame: ``metadata`` is a JSON string inside the JSON."""
    metadata = json.dumps({"protocol": protocol})
    return endpoint_command_frame("__handshake", {"version": version, "metadata": metadata})


def parse_json(payload: bytes, drop_last: bool = False) -> dict[str, Any]:
    """A command's JSON object; `drop_last` chops the final character first, as the endpoint does."""
    try:
        text = payload.decode("utf-8")
        value = json.loads(text[:-1] if drop_last else text)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ProtocolError(f"bad command JSON: {str(exc)[:80]}") from None
    if not isinstance(value, dict):
        raise ProtocolError("command JSON is not an object")
    return value


def parse_handshake(params: dict[str, Any]) -> tuple[str, str]:
    """(version, protocol) from a ``__handshake`` JSON object (metadata may be a string or an object)."""
    meta = params.get("metadata", "{}")
    if isinstance(meta, str):
        try:
            meta = json.loads(meta)
        except (ValueError, RecursionError):
            meta = {}
    protocol = meta.get("protocol", "") if isinstance(meta, dict) else ""
    return str(params.get("version", "")), str(protocol)


class FrameReader:
    """Incremental parser: `feed` bytes as they arrive, get whole ``(destination, payload)`` frames back.

    Destinations are decoded as UTF-8 with trailing NULs stripped (so it reads both sides' framing).
    Raises `ProtocolError` for lengths beyond the limits or undecodable names; `partial` tells whether a
    frame has started but not finished (the caller's read timeout applies then).
    """

    def __init__(self, max_destination: int = MAX_DESTINATION, max_payload: int = MAX_PAYLOAD):
        self._buf = bytearray()
        self.max_destination, self.max_payload = max_destination, max_payload

    @property
    def partial(self) -> bool:
        return bool(self._buf)

    def feed(self, data: bytes) -> list[tuple[str, bytes]]:
        self._buf += data
        frames, pos = [], 0
        while True:
            frame, end = self._next(pos)
            if frame is None:
                break
            frames.append(frame)
            pos = end
        del self._buf[:pos]
        return frames

    def _next(self, pos: int) -> tuple[tuple[str, bytes] | None, int]:
        buf = self._buf
        if len(buf) - pos < 4:
            return None, pos
        (name_len,) = U32.unpack_from(buf, pos)
        if name_len > self.max_destination:
            raise ProtocolError(f"destination length {name_len} exceeds {self.max_destination}")
        head = pos + 4 + name_len
        if len(buf) < head + 4:
            return None, pos
        (size,) = U32.unpack_from(buf, head)
        if size > self.max_payload:
            raise ProtocolError(f"payload length {size} exceeds {self.max_payload}")
        if len(buf) < head + 4 + size:
            return None, pos
        try:
            name = bytes(buf[pos + 4 : head]).decode("utf-8").rstrip("\x00")
        except UnicodeDecodeError:
            raise ProtocolError("destination is not UTF-8") from None
        return (name, bytes(buf[head + 4 : head + 4 + size])), head + 4 + size
