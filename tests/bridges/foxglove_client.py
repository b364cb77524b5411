"""A minimal Foxglove WebSocket client (subprotocol `foxglove.sdk.v1`) written from the protocol spec, for tests.

Text frames are JSON (`serverInfo`, `advertise`, `unadvertise`, `status`, ...). Binary server frames start with
an opcode byte: 0x01 message data `u32 subscription id | u64 log time | payload`, 0x02 time `u64 ns`
(little endian). Client binary frames: 0x01 message data `u32 client channel id | payload`.
"""

from __future__ import annotations

import base64
import json
import os
import socket
import struct
import time
from itertools import count

from websockets.sync.client import connect

SUBPROTOCOL = "foxglove.sdk.v1"


class FoxgloveClient:
    def __init__(self, url: str, subprotocol: str = SUBPROTOCOL):
        self.ws = connect(url, subprotocols=[subprotocol], max_size=None, open_timeout=5, legacy=True)
        self.server_info: dict | None = None
        self.channels: dict[int, dict] = {}  # channel id → advertised channel
        self.status: list[dict] = []
        self.messages: dict[int, list[tuple[int, bytes]]] = {}  # subscription id → [(log time, payload)]
        self.times: list[int] = []
        self._subs: dict[int, int] = {}  # subscription id → channel id
        self._ids = count(1)

    def close(self) -> None:
        self.ws.close()

    # -- receiving --------------------------------------------------------------------------------
    def pump(self, seconds: float = 0.0) -> int:
        """Read every frame that arrives within `seconds` (at least the ones already queued); returns the count."""
        deadline, n = time.monotonic() + seconds, 0
        while True:
            try:
                frame = self.ws.recv(timeout=max(0.0, deadline - time.monotonic()))
            except TimeoutError:
                return n
            self._handle(frame)
            n += 1

    def _handle(self, frame: str | bytes) -> None:
        if isinstance(frame, str):
            msg = json.loads(frame)
            op = msg.get("op")
            if op == "serverInfo":
                self.server_info = msg
            elif op == "advertise":
                self.channels.update({c["id"]: c for c in msg["channels"]})
            elif op == "unadvertise":
                for cid in msg["channelIds"]:
                    self.channels.pop(cid, None)
            elif op == "status":
                self.status.append(msg)
            return
        if frame[0] == 0x01:
            sub_id, log_time = struct.unpack_from("<IQ", frame, 1)
            self.messages.setdefault(sub_id, []).append((log_time, bytes(frame[13:])))
        elif frame[0] == 0x02:
            self.times.append(struct.unpack_from("<Q", frame, 1)[0])

    def wait_for(self, predicate, seconds: float = 5.0) -> bool:
        deadline = time.monotonic() + seconds
        while not predicate():
            if time.monotonic() > deadline:
                return False
            self.pump(0.05)
        return True

    # -- requests ---------------------------------------------------------------------------------
    def channel(self, topic: str) -> dict | None:
        return next((c for c in self.channels.values() if c["topic"] == topic), None)

    def subscribe(self, topic: str) -> int:
        channel = self.channel(topic)
        if channel is None:
            raise KeyError(f"{topic} is not advertised")
        sub_id = next(self._ids)
        self._subs[sub_id] = channel["id"]
        self.ws.send(
            json.dumps({"op": "subscribe", "subscriptions": [{"id": sub_id, "channelId": channel["id"]}]})
        )
        return sub_id

    def advertise(self, channel_id: int, topic: str, encoding: str, schema_name: str) -> None:
        channel = {"id": channel_id, "topic": topic, "encoding": encoding, "schemaName": schema_name}
        self.ws.send(json.dumps({"op": "advertise", "channels": [channel]}))

    def publish(self, channel_id: int, payload: bytes) -> None:
        self.ws.send(b"\x01" + struct.pack("<I", channel_id) + payload)


# -- a raw client for misbehaving on purpose (stalling, resetting, garbage) -----------------------------------
def raw_connect(port: int, rcvbuf: int = 4096) -> socket.socket:
    """A TCP socket after a completed WebSocket handshake; the caller reads nothing unless it wants to."""
    sock = socket.create_connection(("127.0.0.1", port), timeout=5)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    key = base64.b64encode(os.urandom(16)).decode()
    sock.sendall(
        f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: {SUBPROTOCOL}\r\n\r\n".encode()
    )
    response = b""
    while b"\r\n\r\n" not in response:
        response += sock.recv(1)
    if b" 101 " not in response.split(b"\r\n", 1)[0]:
        raise ConnectionError(response.decode(errors="replace"))
    return sock


def send_frame(sock: socket.socket, payload: bytes, opcode: int = 0x1) -> None:
    """One masked client frame (text 0x1, binary 0x2)."""
    mask = os.urandom(4)
    n = len(payload)
    header = bytes([0x80 | opcode])
    if n < 126:
        header += bytes([0x80 | n])
    elif n < 65536:
        header += bytes([0x80 | 126]) + struct.pack(">H", n)
    else:
        header += bytes([0x80 | 127]) + struct.pack(">Q", n)
    sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))


def reset(sock: socket.socket) -> None:
    """Close abruptly: a TCP RST, no close frame (like a killed process)."""
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    sock.close()
