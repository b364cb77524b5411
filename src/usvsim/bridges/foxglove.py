"""Foxglove live view: a foxglove-sdk WebSocket server (subprotocol `foxglove.sdk.v1`) with every ROS 2 topic of
the simulation plus a 3D scene, so Foxglove shows the world without any ROS installation.

Channels:
- one per ROS topic, created on its first message: schema encoding `ros2msg` (the full `.msg` definition, as
  the MCAP recorder writes it), message encoding `cdr`, payload = `Envelope.cdr` unchanged (serialized once,
  shared with the recorder and the other bridges), log time = the simulation stamp. A topic nobody subscribes
  to costs one check and no serialization. Transient-local topics (`/tf_static`) are latched: the last
  message is logged again whenever a client subscribes.
- `/usvsim/scene` (`foxglove.SceneUpdate`): vessels in their `<v>/base_link` frames (moved by `/tf`), static
  obstacles in `world` (both sent when a client subscribes), buoys in `world` every scene tick;
  `/usvsim/water` (`foxglove.SceneUpdate`): the ocean surface around the vessels every scene tick
  (foxglove_scene.py). Both are built in the simulation thread, only while someone subscribes, at
  `scene_rate_hz` in simulation time and at most that often in wall time (a fast simulation does not
  multiply the scene's cost and bandwidth).
- server time (`time` capability) = simulation time, so Foxglove's clock follows the simulation.
- `clientPublish`: clients may publish to the command topics of `sim.commands.topics` (e.g. the Teleop panel
  on `/<vessel>/cmd_vel`), as `cdr` or `json`; everything is validated and counted by the command inbox. A
  message on a channel the client never advertised, a text frame that is no valid JSON operation and a binary
  frame with an unknown opcode are refused by the SDK and counted here too (`client_refused`, foxglove_logs.py).

Non-blocking: `channel.log` only queues; the SDK's server threads send. Each client has a bounded queue
(`backlog` messages): the oldest data message is dropped when it is full. The SDK server listens on an
internal loopback port; users connect to `host:port`, served by a front proxy (foxglove_proxy.py, in a child
process: its byte copying never takes the simulation's GIL) that admits at most `max_clients` connections (one
more gets HTTP 503), closes connections that send no WebSocket upgrade within `client_handshake_s`, and drops a client whose
unsent bytes exceed `max_client_buffer_bytes` or that reads nothing for `client_stall_s` while behind (counted
in `stats`, asynchronously: the child reports them). Errors inside the bridge are
counted in `stats["errors"]` and never reach the simulation loop.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

import foxglove
from foxglove.channels import SceneUpdateChannel
from foxglove.websocket import Capability, ServerListener
from rosbags.interfaces import Nodetype

from usvsim.bridges import foxglove_logs
from usvsim.bridges.foxglove_proxy_process import ProxyProcess
from usvsim.bridges.foxglove_scene import SceneBuilder, scene_period_ns
from usvsim.messages.ros import message_definition, typestore

if TYPE_CHECKING:
    from usvsim.messages.envelope import Envelope
    from usvsim.simulation import Simulation

log = logging.getLogger(__name__)
SCENE_TOPIC, WATER_TOPIC = "/usvsim/scene", "/usvsim/water"
SDK_SEND_LOGGER = "foxglove.websocket.connected_client.poller"
TIME_PERIOD_NS = 50_000_000  # server time broadcast every 50 ms of simulation time
STAT_KEYS = ("messages", "bytes", "skipped", "latched_resent", "scene_updates", "water_updates", "errors",
             "client_messages", "client_accepted", "client_refused",
             "connections_accepted", "connections_refused", "connections_dropped")  # fmt: skip


class _OncePerClient(logging.Filter):
    """Lets one "Error sending message to client <addr>" through per client and minute: the SDK logs one per
    queued message when a client vanishes (hundreds of lines for one killed Foxglove tab)."""

    PREFIX, QUIET_S = "Error sending message to client ", 60.0

    def __init__(self):
        super().__init__()
        self._last: dict[str, float] = {}

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        if not text.startswith(self.PREFIX):
            return True
        client, now = text[len(self.PREFIX) :].split(":", 2)[:2], time.monotonic()
        key = ":".join(client)
        if now - self._last.get(key, -self.QUIET_S) < self.QUIET_S:
            return False
        self._last = {k: t for k, t in self._last.items() if now - t < self.QUIET_S} | {key: now}
        return True


def _quiet_send_errors(bridge: FoxgloveBridge) -> Callable[[], None]:
    sdk = logging.getLogger(SDK_SEND_LOGGER)
    if not any(isinstance(f, _OncePerClient) for f in sdk.filters):
        sdk.addFilter(_OncePerClient())
    # invalid client frames: short excerpts, a few lines per client and minute; messages on unknown channels counted
    return foxglove_logs.install(bridge)


class _RosChannel:
    __slots__ = ("channel", "latched", "msgtype")

    def __init__(self, channel: foxglove.Channel, msgtype: str):
        self.channel, self.msgtype = channel, msgtype
        self.latched: tuple[bytes, int] | None = None


class FoxgloveBridge:
    """Serves `sim` to Foxglove on ws://host:port (port 0: a free one, see `port`); `close()` stops it."""

    def __init__(
        self,
        sim: Simulation,
        host: str = "127.0.0.1",
        port: int = 8765,
        scene_rate_hz: float = 5.0,
        *,
        water_size_m: float = 60.0,
        water_points: int = 31,
        backlog: int = 256,
        client_publish: bool = True,
        max_clients: int = 16,
        max_client_buffer_bytes: int = 16 << 20,
        client_stall_s: float = 10.0,
        client_handshake_s: float = 5.0,
    ) -> None:
        self.sim = sim
        self.stats: dict[str, int] = dict.fromkeys(STAT_KEYS, 0)
        self._host = host
        self._lock = threading.Lock()  # stats written from the server's threads
        self._scene_period_ns = scene_period_ns(scene_rate_hz)
        self._scene = SceneBuilder(sim, water_size_m, water_points)
        self._context = foxglove.Context()
        self._topics: dict[str, _RosChannel] = {}
        self._resend: set[int] = set()  # channel ids a client subscribed to since the last message
        self._next_scene_ns = self._next_time_ns = self._last_stamp_ns = 0
        self._next_scene_wall = 0.0  # the scene rate holds in simulation time and in wall time
        self._scene_channel = SceneUpdateChannel(SCENE_TOPIC, context=self._context)
        self._water_channel = SceneUpdateChannel(WATER_TOPIC, context=self._context)
        self._inbox = _ClientCommands(self) if client_publish else None
        capabilities = [Capability.Time] + ([Capability.ClientPublish] if client_publish else [])
        try:
            self._server = foxglove.start_server(
                name="usvsim", host="127.0.0.1", port=0, capabilities=capabilities, server_listener=_Listener(self),
                supported_encodings=["cdr", "json"] if client_publish else None, context=self._context,
                message_backlog_size=backlog,
            )  # fmt: skip
        except RuntimeError as exc:  # the SDK reports bind failures (port taken, bad address) this way
            raise OSError(f"cannot start the Foxglove server on {host}:{port}: {str(exc)[:160]}") from None
        try:
            self._proxy = ProxyProcess(host, port, self._server.port, max_clients=max_clients,
                                        max_buffer_bytes=max_client_buffer_bytes, stall_s=client_stall_s,
                                        handshake_s=client_handshake_s, count=self._count)  # fmt: skip
        except OSError as exc:  # port taken, bad address
            self._server.stop()
            raise OSError(f"cannot start the Foxglove server on {host}:{port}: {str(exc)[:160]}") from None
        self._unwatch_logs = _quiet_send_errors(self)
        self._latch_static_transforms()
        self._unsubscribe = sim.subscribe(self._on_envelope)
        self._closed = False

    @property
    def port(self) -> int:
        return self._proxy.port

    @property
    def url(self) -> str:
        """The server's address for Foxglove: ws://HOST:PORT (a wildcard host as the loopback address)."""
        host = "127.0.0.1" if self._host in ("", "0.0.0.0", "::") else self._host
        return f"ws://{'[' + host + ']' if ':' in host else host}:{self.port}"

    def close(self) -> None:
        """Stop serving: unsubscribe from the simulation, stop the server, close the channels."""
        if getattr(self, "_closed", True):
            return
        self._closed = True
        try:
            self._unsubscribe()
        except ValueError:
            pass
        self._server.stop()
        self._proxy.close()
        self._unwatch_logs()
        for ch in [*(t.channel for t in self._topics.values()), self._scene_channel, self._water_channel]:
            ch.close()

    def __enter__(self) -> FoxgloveBridge:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- simulation thread ------------------------------------------------------------------------
    def _on_envelope(self, env: Envelope) -> None:
        try:
            self._publish(env)
        except Exception:  # the bridge must never stop the simulation
            self._count("errors")
            log.exception("foxglove bridge: failed to publish %s", env.topic)

    def _publish(self, env: Envelope) -> None:
        stamp = env.publish_ns  # emission time (a LiDAR sweep is stamped at its start)
        if stamp < self._last_stamp_ns:  # the simulation was reset: restart the schedules
            self._next_scene_ns = self._next_time_ns = 0
            self._next_scene_wall = 0.0
            self._subscribed(self._scene_channel.id())
        self._last_stamp_ns = stamp
        if self._resend:
            self._resend_latched()
        topic = self._topics.get(env.topic) or self._register(env.topic, env.msgtype)
        if topic.msgtype != env.msgtype:
            raise TypeError(f"{env.topic} was advertised as {topic.msgtype}, got {env.msgtype}")
        if env.qos.durability == "transient_local":
            topic.latched = (env.cdr, stamp)
        if topic.channel.has_sinks():
            data = env.cdr
            topic.channel.log(data, log_time=stamp)
            self.stats["messages"] += 1
            self.stats["bytes"] += len(data)
        else:
            self.stats["skipped"] += 1
        self._tick(stamp)

    def _tick(self, stamp: int) -> None:
        """Server time every TIME_PERIOD_NS; the scene at its rate (simulation and wall time)."""
        if stamp >= self._next_time_ns:
            self._next_time_ns = stamp + TIME_PERIOD_NS
            self._server.broadcast_time(stamp)
        now = time.monotonic()
        if stamp >= self._next_scene_ns and now >= self._next_scene_wall:
            self._next_scene_ns = stamp + self._scene_period_ns
            self._next_scene_wall = now + self._scene_period_ns / 1e9
            self._scene_tick(stamp)

    def _register(self, name: str, msgtype: str) -> _RosChannel:
        schema = foxglove.Schema(name=msgtype, encoding="ros2msg", data=message_definition(msgtype).encode())
        channel = foxglove.Channel(name, schema=schema, message_encoding="cdr", context=self._context)
        topic = self._topics[name] = _RosChannel(channel, msgtype)
        return topic

    def _latch_static_transforms(self) -> None:
        """Latch `/tf_static` now, so a client sees it even if the bridge joins a running simulation."""
        sim = self.sim
        for env in sim.ground_truth.static_transforms(sim.sensors.static_transforms()):
            self._register(env.topic, env.msgtype).latched = (env.cdr, env.stamp_ns)

    def _resend_latched(self) -> None:
        with self._lock:
            ids, self._resend = self._resend, set()
        scene_id = self._scene_channel.id()
        for topic in self._topics.values():
            if topic.latched is not None and topic.channel.id() in ids:
                topic.channel.log(topic.latched[0], log_time=topic.latched[1])
                self.stats["latched_resent"] += 1
        if scene_id in ids:
            self._scene_channel.log(
                self._scene.static_update(self._last_stamp_ns), log_time=self._last_stamp_ns
            )
            self.stats["scene_updates"] += 1

    def _scene_tick(self, stamp: int) -> None:
        if self._scene_channel.has_sinks() and self._scene.buoys:
            self._scene_channel.log(self._scene.bodies_update(stamp), log_time=stamp)
            self.stats["scene_updates"] += 1
        if self._water_channel.has_sinks():
            self._water_channel.log(self._scene.water_update(stamp), log_time=stamp)
            self.stats["water_updates"] += 1

    # -- server threads ---------------------------------------------------------------------------
    def _count(self, key: str, n: int = 1) -> None:
        with self._lock:
            self.stats[key] += n

    def _subscribed(self, channel_id: int) -> None:
        with self._lock:
            self._resend.add(channel_id)


class _Listener(ServerListener):
    """foxglove.websocket.ServerListener: subscriptions (latched re-sends) and client publishing."""

    def __init__(self, bridge: FoxgloveBridge):
        self._bridge = bridge

    def on_subscribe(self, client, channel) -> None:
        self._bridge._subscribed(channel.id)

    def on_unsubscribe(self, client, channel) -> None:
        return None

    def on_client_advertise(self, client, channel) -> None:
        if self._bridge._inbox is not None:
            self._bridge._inbox.advertise(client.id, channel)

    def on_client_unadvertise(self, client, client_channel_id: int) -> None:
        if self._bridge._inbox is not None:
            self._bridge._inbox.unadvertise(client.id, client_channel_id)

    def on_message_data(self, client, client_channel_id: int, data: bytes) -> None:
        if self._bridge._inbox is not None:
            self._bridge._inbox.message(client.id, client_channel_id, data)


class _ClientCommands:
    """Client-published messages → `sim.commands` (CDR with its 4-byte header, or JSON with the ROS fields)."""

    def __init__(self, bridge: FoxgloveBridge):
        self._bridge = bridge
        self._commands = bridge.sim.commands
        self._channels: dict[tuple[int, int], tuple[str, str]] = {}  # (client, channel) → (topic, encoding)

    def advertise(self, client_id: int, channel) -> None:
        self._channels[(client_id, channel.id)] = (str(channel.topic), str(channel.encoding))

    def unadvertise(self, client_id: int, channel_id: int) -> None:
        self._channels.pop((client_id, channel_id), None)

    def message(self, client_id: int, channel_id: int, data: bytes) -> None:
        self._bridge._count("client_messages")
        topic, encoding = self._channels.get((client_id, channel_id), ("", ""))
        try:
            ok = self._post(topic, encoding, data)
        except Exception:  # untrusted input: never let it escape into the server
            ok = False
        self._bridge._count("client_accepted" if ok else "client_refused")

    def _post(self, topic: str, encoding: str, data: bytes) -> bool:
        if topic not in self._commands.topics:
            return False
        if encoding == "cdr":
            return self._commands.post_cdr(topic, data)
        if encoding == "json":
            try:
                value = json.loads(data)
            except ValueError:
                return False
            return self._commands.post(topic, _namespace(_with_defaults(self._commands.topics[topic], value)))
        return False


def _with_defaults(msgtype: str, value: Any) -> Any:
    """A JSON message with the fields it leaves out set to their ROS defaults (0, "", False), as rosbridge and
    foxglove_bridge fill them: `{"linear": {"x": 0.5}}` is a whole Twist. Anything but an object is left as it is
    (and refused as malformed)."""
    if not isinstance(value, dict):
        return value
    out = dict(value)
    for name, (nodetype, detail) in typestore().fielddefs[msgtype][1]:
        if nodetype == Nodetype.NAME:
            out[name] = _with_defaults(detail, out.get(name, {}))
        elif nodetype == Nodetype.BASE and name not in out:
            out[name] = {"string": "", "bool": False}.get(detail[0], 0)
    return out


def _namespace(value: Any) -> Any:
    """JSON objects as attribute namespaces (the command parsers read `msg.linear.x`)."""
    if isinstance(value, dict):
        return SimpleNamespace(**{k: _namespace(v) for k, v in value.items()})
    return value
