"""ROS-TCP-Endpoint client: the simulation takes the Unity side of ``ros_tcp_endpoint`` (v0.7.0, ROS 2).

The endpoint (``ros2 run ros_tcp_endpoint default_server_endpoint``) is the TCP server; this bridge connects to
it (``usvsim run --ros-tcp HOST:PORT``), so a user of the Unity seed keeps the endpoint node they run today.
Topic names: `usvsim.bridges.ros_tcp_profiles` (``usvsim``, or ``seed`` for the seed's names); wire format:
`usvsim.bridges.ros_tcp_protocol`.

Per connection: a keepalive, ``__subscribe`` for every command topic, ``__publish`` for every topic seen so far
(``pkg/Type``, ``queue_size`` = the topic's QoS depth, ``latch`` for transient-local topics), then the latched
messages (``/tf_static``) again; a topic seen later is registered just before its first message. The endpoint's
``__handshake`` is checked (``v0.7.x``/``ROS2``, else a warning), ``__log``/``__warn``/``__error`` go to this
module's logger, topic frames on command topics go to `sim.commands` (others count as ``unknown_topics``).
A keepalive goes out after ``keepalive_s`` (1 s) without sending; a started frame must complete within
``read_timeout_s`` (2 s).

Threading: the `sim.subscribe` callback only appends to a bounded drop-oldest queue (``dropped``) and wakes
the one I/O thread, which serializes (``Envelope.cdr``, cached), frames and sends. While disconnected,
messages are dropped (``dropped_disconnected``); topics are still noted for registration and latched messages
kept. A socket error, a broken frame from the endpoint (bad or huge lengths, undecodable names, garbage JSON:
``protocol_errors``) or a send stalled beyond ``write_timeout_s`` closes the connection; the bridge reconnects
after ``reconnect_delay_s`` (1 s) and re-registers everything.

Caveats of the endpoint (ros2-interop.md §1.4): its publishers are RELIABLE + VOLATILE, so ``/tf_static``
misses tf2's transient-local listeners that start later; its subscribers are RELIABLE, so command publishers
must not be BEST_EFFORT.
"""

from __future__ import annotations

import contextlib
import logging
import re
import select
import socket
import threading
import time
from collections import deque
from typing import TYPE_CHECKING, Any

from usvsim.bridges.ros_tcp_profiles import make_profile
from usvsim.bridges.ros_tcp_protocol import (
    KEEPALIVE,
    FrameReader,
    ProtocolError,
    Timing,
    client_command_frame,
    client_topic_frame,
    parse_handshake,
    parse_json,
    publish_command,
    subscribe_command,
)
from usvsim.core import queues

if TYPE_CHECKING:
    from usvsim.messages.envelope import Envelope
    from usvsim.simulation import Simulation

log = logging.getLogger(__name__)
STAT_KEYS = ("connects", "connect_failures", "disconnects", "protocol_errors", "messages_out", "bytes_out",
             "keepalives_out", "registrations", "dropped", "dropped_disconnected", "frames_in", "keepalives_in",
             "commands_in", "commands_refused", "unknown_topics", "endpoint_logs", "handshakes",
             "dropped_refused")  # fmt: skip
# The endpoint's reply to a frame on a topic it could not register (its message package is missing there).
REFUSED = re.compile(r"Not registered to publish topic '([^']{1,256})'")
BATCH_BYTES = 1 << 18  # small frames are joined into sends of about this size
LOG_LEVELS = {"__log": logging.INFO, "__warn": logging.WARNING, "__error": logging.ERROR}


class RosTcpBridge:
    """Connects `sim` to a ROS-TCP-Endpoint at `host`:`port` with topic-name `profile` ``usvsim`` or ``seed``."""

    def __init__(self, sim: Simulation, host: str = "127.0.0.1", port: int = 10000, profile: str = "usvsim",
                 vessel: str | None = None, *, queue_limit: int = 256, **timing: float) -> None:  # fmt: skip
        """`timing`: fields of `Timing` (keepalive_s, read_timeout_s, reconnect_delay_s, ...)."""
        self.address, self.queue_limit, self.timing = (host, int(port)), queue_limit, Timing(**timing)
        self.profile = make_profile(sim, profile, vessel)
        self.stats: dict[str, int] = dict.fromkeys(STAT_KEYS, 0)
        self.endpoint_version: tuple[str, str] | None = None  # (version, protocol) of the last handshake
        self.topic_list: dict[str, Any] | None = None
        self.connected = threading.Event()
        self._queue: deque[Envelope] = queues.bounded(queue_limit)
        self._control: deque[bytes] = deque()  # frames from user threads (topic list requests)
        self._lock = threading.Lock()
        self._wake_r, self._wake_w = socket.socketpair()
        for end in (self._wake_r, self._wake_w):
            end.setblocking(False)
        self._wake_pending = False
        self._closed = threading.Event()
        self._unreachable_warned = False
        self._refused: set[str] = set()  # wire names the endpoint refused: no longer sent (I/O thread)
        self._topic_list_event = threading.Event()
        self._topics: dict[str, tuple[str, int, bool]] = {}  # wire name → (msgtype, depth, latch); I/O thread
        self._latched: dict[str, bytes] = {}  # wire name → last topic frame of a transient-local topic
        self._unsubscribe = sim.subscribe(self._on_envelope)
        self._thread = threading.Thread(target=self._run, name="usvsim-ros-tcp", daemon=True)
        self._thread.start()

    # -- any thread -----------------------------------------------------------------------------
    def _on_envelope(self, env: Envelope) -> None:
        """The simulation's callback: O(1), never blocks on the network."""
        with self._lock:
            if queues.push(self._queue, env):
                self.stats["dropped"] += 1
            wake, self._wake_pending = not self._wake_pending, True
        if wake:
            self._wake()

    def _wake(self) -> None:
        with contextlib.suppress(OSError):  # buffer full (a wake is pending anyway) or closed
            self._wake_w.send(b"\x00")

    def wait_connected(self, timeout: float | None = None) -> bool:
        return self.connected.wait(timeout)

    def request_topic_list(self, timeout: float = 2.0) -> dict[str, Any] | None:
        """Ask the endpoint for ``__topic_list``; its reply ``{"topics": [...], "types": [...]}`` or None."""
        self._topic_list_event.clear()
        self._control.append(client_command_frame("__topic_list", {}))
        self._wake()
        return self.topic_list if self._topic_list_event.wait(timeout) else None

    def close(self) -> None:
        """Unsubscribe, disconnect and stop the I/O thread (idempotent)."""
        if self._closed.is_set():
            return
        self._unsubscribe()
        self._closed.set()
        self._wake()
        self._thread.join(timeout=self.timing.write_timeout_s + self.timing.drain_s + 1.0)
        self._wake_r.close()
        self._wake_w.close()

    def __enter__(self) -> RosTcpBridge:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- I/O thread: connection life cycle ------------------------------------------------------
    def _run(self) -> None:
        while not self._closed.is_set():
            sock = self._connect()
            if sock is not None:
                self._serve(sock)
            if not self._closed.is_set():
                self._idle(self.timing.reconnect_delay_s)

    def _connect(self) -> socket.socket | None:
        try:
            sock = socket.create_connection(self.address, timeout=self.timing.connect_timeout_s)
        except OSError as exc:
            self.stats["connect_failures"] += 1
            if not self._unreachable_warned:  # once, until a connection succeeds
                self._unreachable_warned = True
                log.warning("ROS-TCP: cannot reach the endpoint at %s:%d (%s); retrying every %g s",
                            *self.address, exc.strerror or exc, self.timing.reconnect_delay_s)  # fmt: skip
            return None
        self._unreachable_warned = False
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.settimeout(self.timing.write_timeout_s)  # bounds sendall; reads happen only after select
        self.stats["connects"] += 1
        return sock

    def _serve(self, sock: socket.socket) -> None:
        self._sock, self._reader, self._registered = sock, FrameReader(), set()
        self._partial_since: float | None = None
        self._handshake_seen = False
        try:
            self._begin()
            self.connected.set()
            log.info("ROS-TCP: connected to %s:%d", *self.address)
            while not self._closed.is_set():
                self._cycle()
            self._finish()
        except ProtocolError as exc:
            self.stats["protocol_errors"] += 1
            log.warning("ROS-TCP: broken frame from the endpoint (%s); reconnecting", exc)
        except OSError as exc:
            log.info("ROS-TCP: connection to %s:%d lost (%s)", *self.address, exc)
        finally:
            self.connected.clear()
            self.stats["disconnects"] += 1
            sock.close()

    def _finish(self) -> None:
        """Closing: send what is queued, half-close, and read until the endpoint's EOF (or `drain_s`), so
        that the endpoint reads the last step's frames before the connection goes away."""
        self._flush()
        self._sock.shutdown(socket.SHUT_WR)
        deadline = time.monotonic() + self.timing.drain_s
        while (left := deadline - time.monotonic()) > 0:
            ready, _, _ = select.select([self._sock], [], [], left)
            if ready and not self._sock.recv(1 << 16):
                return

    def _begin(self) -> None:
        """Keepalive, command subscriptions, publisher registrations and latched messages, in that order."""
        out = bytearray(KEEPALIVE)
        for topic, (msgtype, _) in self.profile.commands.items():
            out += subscribe_command(topic, msgtype)
        for wire in self._topics:
            out += self._registration(wire)
        for frame in self._latched.values():
            out += frame
        self._send(out)
        self.stats["keepalives_out"] += 1

    def _idle(self, seconds: float) -> None:
        """Wait while disconnected; note topics and latched messages, drop the rest (counted)."""
        deadline = time.monotonic() + seconds
        while not self._closed.is_set() and (left := deadline - time.monotonic()) > 0:
            select.select([self._wake_r], [], [], left)
            self._drain_wake()
            for env in self._take():
                self._note(env)
                self.stats["dropped_disconnected"] += 1

    # -- I/O thread: one connected cycle --------------------------------------------------------
    def _cycle(self) -> None:
        ready, _, _ = select.select([self._sock, self._wake_r], [], [], self._select_timeout())
        if self._sock in ready:
            self._receive()
        if self._wake_r in ready:
            self._drain_wake()
        self._flush()
        now = time.monotonic()
        if now - self._last_send >= self.timing.keepalive_s:
            self._send(KEEPALIVE)
            self.stats["keepalives_out"] += 1
        if self._partial_since is not None and now - self._partial_since > self.timing.read_timeout_s:
            raise ProtocolError(f"a frame stayed incomplete for more than {self.timing.read_timeout_s} s")

    def _select_timeout(self) -> float:
        deadline = self._last_send + self.timing.keepalive_s
        if self._partial_since is not None:
            deadline = min(deadline, self._partial_since + self.timing.read_timeout_s)
        return max(0.0, deadline - time.monotonic())

    def _drain_wake(self) -> None:
        with contextlib.suppress(OSError):  # BlockingIOError once empty
            while self._wake_r.recv(4096):
                pass

    def _take(self) -> deque[Envelope]:
        with self._lock:
            envs, self._queue, self._wake_pending = self._queue, queues.bounded(self.queue_limit), False
        return envs

    def _note(self, env: Envelope) -> str:
        """Remember the topic for registration (and its frame when latched); its wire name."""
        wire = self.profile.wire_name(env.topic)
        if wire not in self._topics:
            self._topics[wire] = (env.msgtype, env.qos.depth, env.qos.durability == "transient_local")
        if self._topics[wire][2]:
            self._latched[wire] = client_topic_frame(wire, env.cdr)
        return wire

    def _registration(self, wire: str) -> bytes:
        msgtype, depth, latch = self._topics[wire]
        self._registered.add(wire)
        self.stats["registrations"] += 1
        return publish_command(wire, msgtype, depth, latch)

    def _flush(self) -> None:
        out = bytearray()
        while self._control:
            out += self._control.popleft()
        for env in self._take():
            wire = self._note(env)
            if wire in self._refused:
                self.stats["dropped_refused"] += 1
                continue
            if wire not in self._registered:
                out += self._registration(wire)
            out += self._latched.get(wire) or client_topic_frame(wire, env.cdr)
            self.stats["messages_out"] += 1
            if len(out) >= BATCH_BYTES:
                self._send(out)
                out = bytearray()
        if out:
            self._send(out)

    def _send(self, data: bytes | bytearray) -> None:
        self._sock.sendall(data)
        self._last_send = time.monotonic()
        self.stats["bytes_out"] += len(data)

    # -- I/O thread: from the endpoint ----------------------------------------------------------
    def _receive(self) -> None:
        data = self._sock.recv(1 << 16)
        if not data:
            raise ConnectionError("the endpoint closed the connection")
        frames = self._reader.feed(data)
        if frames or self._partial_since is None:
            self._partial_since = time.monotonic() if self._reader.partial else None
        for destination, payload in frames:
            self._handle(destination, payload)

    def _handle(self, destination: str, payload: bytes) -> None:
        self.stats["frames_in"] += 1
        if not self._handshake_seen and destination != "__handshake":
            self._handshake_seen = True
            log.warning("ROS-TCP: the endpoint's first frame is %r, not __handshake", destination)
        if destination == "":
            self.stats["keepalives_in"] += 1
        elif destination.startswith("__"):
            self._system(destination, parse_json(payload))
        else:
            self._command(destination, payload)

    def _system(self, command: str, params: dict[str, Any]) -> None:
        if command == "__handshake":
            self._handshake_seen = True
            self.stats["handshakes"] += 1
            self.endpoint_version = version, protocol = parse_handshake(params)
            if not version.startswith("v0.7.") or protocol != "ROS2":
                log.warning("ROS-TCP: endpoint %s %r; this client speaks v0.7.x ROS2", version, protocol)
        elif command in LOG_LEVELS:
            self.stats["endpoint_logs"] += 1
            text = str(params.get("text", ""))
            refused = REFUSED.search(text) if command == "__error" else None
            if refused is None:
                log.log(LOG_LEVELS[command], "ROS-TCP endpoint: %s", text[:300])
            elif refused.group(1) not in self._refused:
                self._refused.add(refused.group(1))
                log.warning("ROS-TCP: the endpoint refused %s (is its message package installed there?); "
                            "no longer sending it", refused.group(1))  # fmt: skip
        elif command == "__topic_list":
            self.topic_list = params
            self._topic_list_event.set()
        else:  # __request/__response: this client registers no services
            log.warning("ROS-TCP: ignoring unsupported system command %s", command)

    def _command(self, topic: str, payload: bytes) -> None:
        entry = self.profile.commands.get(topic)  # (ROS type, handler that queues it on sim.commands)
        if entry is None:
            self.stats["unknown_topics"] += 1
        else:
            self.stats["commands_in" if entry[1](payload) else "commands_refused"] += 1
