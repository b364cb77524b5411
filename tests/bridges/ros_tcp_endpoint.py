"""A stand-in for ROS-TCP-Endpoint v0.7.0 (ROS 2 branch) written from the protocol facts (ros2-interop.md §1).

It is the TCP server, bound to 127.0.0.1. Per accepted connection it first sends ``__handshake`` (JSON with the
metadata as a JSON string inside), then reads frames with exact reads: uint32 LE length, destination with
trailing NULs stripped, uint32 LE length, payload. Like the real endpoint it drops the last character of
every system-command JSON before parsing (so a client that forgets the ``\\0`` breaks it), and any error in a
system command (bad JSON, unknown command, wrong arguments) ends that connection's reader and closes it.
Outgoing frames (topic list replies, ``__error``, subscribed messages, whatever a test sends) go to the most
recently connected client, with no NULs. Instead of ROS it records what it is told: publishers and
subscribers registered, the topic frames received on registered topics (with the receive time), keepalives.
"""

from __future__ import annotations

import json
import socket
import struct
import threading
import time

U32 = struct.Struct("<I")


def frame(destination: str, payload: bytes) -> bytes:
    """Endpoint → client framing: no NUL on the destination."""
    name = destination.encode()
    return U32.pack(len(name)) + name + U32.pack(len(payload)) + payload


def command(name: str, params: dict) -> bytes:
    return frame(name, json.dumps(params).encode())


class TestEndpoint:
    """ROS-TCP-Endpoint look-alike; `port=0` picks a free port (then reuse `.port` to "restart" it)."""

    __test__ = False  # not a pytest class

    def __init__(self, port: int = 0, version: str = "v0.7.0", protocol: str = "ROS2", refuse=()):
        self.version, self.protocol = version, protocol
        self.refuse = set(refuse)  # topics whose __publish fails (their message package is missing here)
        self.publishers: dict[str, dict] = {}  # topic → __publish arguments
        self.subscribers: dict[str, str] = {}  # topic → message_name
        self.registrations: list[str] = []  # every __publish topic in order (re-registrations included)
        self.received: list[tuple[str, bytes, float]] = []  # (topic, CDR payload, time.perf_counter())
        self.keepalives = 0
        self.errors: list[str] = []  # what broke a connection (bad JSON, unknown command...)
        self.unregistered: list[str] = []  # topic frames for topics without a publisher
        self.connections = 0
        self.reading = threading.Event()  # cleared: stop reading (a stalled endpoint)
        self.reading.set()
        self._client: socket.socket | None = None
        self._send_lock = threading.Lock()
        self._conns: list[socket.socket] = []
        self._server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self._server.bind(("127.0.0.1", port))
        self._server.listen(10)
        self.port = self._server.getsockname()[1]
        self._running = True
        threading.Thread(target=self._accept_loop, daemon=True).start()

    # -- test API ---------------------------------------------------------------------------------
    def send(self, data: bytes, wait_s: float = 30.0) -> None:
        """Raw bytes to the most recent client. Waits (up to `wait_s`) for the first one to be accepted: a
        client's connect() completes from the listen backlog, possibly before the accept thread has run."""
        deadline = time.monotonic() + wait_s
        while self._client is None and time.monotonic() < deadline:
            time.sleep(0.005)
        with self._send_lock:
            if self._client is not None:
                self._client.sendall(data)

    def send_topic(self, topic: str, cdr: bytes) -> None:
        """A message on a subscribed topic, as the endpoint forwards it."""
        assert topic in self.subscribers, f"{topic} was not subscribed"
        self.send(frame(topic, cdr))

    def topics_received(self) -> set[str]:
        return {t for t, _, _ in list(self.received)}

    def stop(self) -> None:
        """The endpoint process dies: listening socket and connections closed."""
        self._running = False
        try:
            self._server.shutdown(socket.SHUT_RDWR)  # wakes the blocked accept() (close alone does not)
        except OSError:
            pass
        self._server.close()
        for conn in list(self._conns):
            try:
                conn.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            conn.close()

    # -- server -----------------------------------------------------------------------------------
    def _accept_loop(self) -> None:
        while self._running:
            try:
                conn, _ = self._server.accept()
            except OSError:
                return
            self.connections += 1
            self._conns.append(conn)
            with self._send_lock:
                self._client = conn
            meta = json.dumps({"protocol": self.protocol})
            self.send(command("__handshake", {"version": self.version, "metadata": meta}))
            threading.Thread(target=self._read_loop, args=(conn,), daemon=True).start()

    def _read_loop(self, conn: socket.socket) -> None:
        try:
            while self._running:
                destination = self._read(conn, self._read_u32(conn)).decode("utf-8").rstrip("\x00")
                payload = self._read(conn, self._read_u32(conn))
                self._dispatch(destination, payload)
        except (OSError, EOFError):
            pass
        except Exception as exc:  # a failing system command kills the reader, as in the real endpoint
            self.errors.append(f"{type(exc).__name__}: {exc}")
        finally:
            conn.close()

    def _read_u32(self, conn: socket.socket) -> int:
        return U32.unpack(self._read(conn, 4))[0]

    def _read(self, conn: socket.socket, n: int) -> bytes:
        buf = bytearray()
        while len(buf) < n:
            self.reading.wait()
            chunk = conn.recv(min(n - len(buf), 1 << 20))
            if not chunk:
                raise EOFError
            buf += chunk
        return bytes(buf)

    def _dispatch(self, destination: str, payload: bytes) -> None:
        if destination == "":
            self.keepalives += 1
        elif destination.startswith("__"):
            handler = getattr(self, f"_sys_{destination[2:]}")  # AttributeError for unknown commands
            handler(**json.loads(payload.decode("utf-8")[:-1]))  # the real endpoint's [:-1]
        elif destination in self.publishers:
            self.received.append((destination, payload, time.perf_counter()))
        else:
            self.unregistered.append(destination)
            valid = ", ".join(self.publishers)
            self.send(command("__error", {"text": f"Not registered to publish topic '{destination}'! "
                                                  f"Valid publish topics are: {valid}"}))  # fmt: skip

    # -- system commands (keyword arguments exactly as the JSON gives them) ------------------------
    def _sys_publish(self, topic: str, message_name: str, queue_size: int = 10, latch: bool = False) -> None:
        if topic in self.refuse:
            self.send(command("__error", {"text": f"Failed to resolve message name {message_name}"}))
            return
        self.publishers[topic] = {"message_name": message_name, "queue_size": queue_size, "latch": latch}
        self.registrations.append(topic)

    def _sys_subscribe(self, topic: str, message_name: str) -> None:
        self.subscribers[topic] = message_name

    def _sys_topic_list(self) -> None:
        names = {**{t: p["message_name"] for t, p in self.publishers.items()}, **self.subscribers}
        self.send(command("__topic_list", {"topics": list(names), "types": list(names.values())}))


def wait_for(predicate, timeout: float = 5.0, interval: float = 0.01) -> bool:
    """Poll `predicate` until it is true or `timeout` passes; its last value."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(interval)
    return bool(predicate())
