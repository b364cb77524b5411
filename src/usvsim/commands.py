"""Commands into a running simulation from any bridge (DDS, ROS-TCP, Foxglove) or thread. The inbox belongs
to the loop (`Simulation.commands`); it works on the `World`, the loop's controllers and its reset.

Command topics (absolute ROS names; `<v>` a vessel, `<t>` one of its thrusters):

| topic | type | meaning |
|---|---|---|
| `/<v>/thrusters/<t>/thrust` | std_msgs/msg/Float64 | normalized thrust u in [-1, 1] (refreshes the watchdog) |
| `/<v>/thrusters/<t>/angle` | std_msgs/msg/Float64 | azimuth angle, rad, REP 103 (positive turns the thrust CCW seen from above) |
| `/<v>/cmd_vel` | geometry_msgs/msg/Twist | base_link velocity, body FLU: linear.x, linear.y (m/s), angular.z (rad/s) |
| `/reset` | std_msgs/msg/Empty | back to the scenario's initial state, with the next seed (`Simulation.reset_seeds`) |

More topics can be added with `register(topic, msgtype, parse, apply)` before the bridges open (e.g. a task's
`/vrx/perception/landmark`, VRX's thruster topics): `parse(msg)` runs in the bridge's thread and returns a
value or None (rejected), `apply(value)` runs in the simulation thread before the next step.

Bridges call `post_cdr` (raw CDR from the wire) or `post` (a decoded message with the ROS fields) from
their own threads. Nothing touches the simulation there: commands are validated, counted and queued
(bounded, drop-oldest), and `apply` (called by `Simulation.step`, in the simulation thread) executes them
before the step's physics. Malformed, unknown, NaN/inf or out-of-range commands are rejected and counted in
`stats`, never raised. `cmd_vel` drives the vessel's velocity controller (the scenario's, or a default one
created on the first `cmd_vel`); when `cmd_vel` stops for the vessel's `command_timeout_s`, a controller
created for it is removed (thrusters then fall back to their own watchdog) and a scenario controller gets
back the reference it had before (zero velocity, or its station-keeping target).
"""

from __future__ import annotations

import math
import threading
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from usvsim.core import queues
from usvsim.messages.ros import typestore

if TYPE_CHECKING:
    from usvsim.world.world import World

FLOAT64, TWIST, EMPTY = "std_msgs/msg/Float64", "geometry_msgs/msg/Twist", "std_msgs/msg/Empty"
QUEUE_LIMIT = 1024  # commands waiting for the next step; the oldest is dropped beyond this
STAT_KEYS = ("received", "applied", "rejected", "malformed", "unknown", "dropped")


class CommandInbox:
    """Thread-safe command queue of one simulation; `topics` maps each command topic to its ROS type."""

    def __init__(self, world: World, controllers: dict[str, Any], reset: Callable[[], None]):
        self._world, self._controllers, self._reset = world, controllers, reset
        self.topics: dict[str, str] = {"/reset": EMPTY}
        self._targets: dict[str, tuple[str, str, str | None]] = {"/reset": ("reset", "", None)}
        for vname, vessel in world.vessels.items():
            self.topics[f"/{vname}/cmd_vel"] = TWIST
            self._targets[f"/{vname}/cmd_vel"] = ("cmd_vel", vname, None)
            for tname in vessel.thrusters:
                for kind in ("thrust", "angle"):
                    topic = f"/{vname}/thrusters/{tname}/{kind}"
                    self.topics[topic], self._targets[topic] = FLOAT64, (kind, vname, tname)
        self._queue: deque[tuple[str, str, str | None, Any]] = queues.bounded(QUEUE_LIMIT)
        self._lock = threading.Lock()
        self.stats: dict[str, int] = dict.fromkeys(STAT_KEYS, 0)
        self._velocity_deadline_ns: dict[str, int] = {}  # vessels driven by cmd_vel → when it goes stale
        self._created_loops: set[str] = set()
        self._held_references: dict[str, Any] = {}  # a scenario controller's reference before cmd_vel
        self._handlers: dict[str, tuple[Callable[[Any], Any], Callable[[Any], Any]]] = {}  # registered topics
        self.reset_allowed = True  # False: `/reset` is refused (counted "rejected"), e.g. during a scored trial

    def register(self, topic: str, msgtype: str, parse: Callable[[Any], Any], apply: Callable[[Any], Any]) -> None:
        """Accept `topic` (ROS type `msgtype`) from every bridge opened afterwards: `parse(msg)` (bridge thread;
        None rejects, AttributeError/TypeError/ValueError count as malformed) → `apply(value)` (simulation
        thread; a False result counts as rejected)."""
        if topic in self.topics and topic not in self._handlers:
            raise ValueError(f"{topic} is a built-in command topic")
        self.topics[topic], self._targets[topic] = msgtype, ("custom", topic, None)
        self._handlers[topic] = (parse, apply)

    def streaming(self, topic: str) -> bool:
        """True for a topic whose commands come as a stream that the watchdog expects to be refreshed (cmd_vel,
        thrust): a bridge may accept it best-effort. One-shot commands (/reset, angles, registered topics) not."""
        target = self._targets.get(topic)
        return target is not None and target[0] in ("cmd_vel", "thrust")

    # -- any thread ---------------------------------------------------------------------------
    def post_cdr(self, topic: str, data: bytes | bytearray | memoryview) -> bool:
        """Queue a command from its CDR bytes (with the 4-byte encapsulation header); False if refused."""
        msgtype = self.topics.get(topic)
        if msgtype is None:
            return self._count("unknown")
        try:
            msg = typestore().deserialize_cdr(bytes(data), msgtype)
        except Exception:  # untrusted bytes: any decoding failure is a malformed message
            return self._count("malformed")
        return self.post(topic, msg)

    def post(self, topic: str, msg: Any) -> bool:
        """Queue a decoded command (any object with the ROS fields); False (counted) if refused."""
        target = self._targets.get(topic)
        if target is None:
            return self._count("unknown")
        kind, vessel, thruster = target
        try:
            value = self._handlers[vessel][0](msg) if kind == "custom" else _value(kind, msg)
        except (AttributeError, TypeError, ValueError):
            return self._count("malformed")
        if value is None:
            return self._count("rejected")
        with self._lock:
            self.stats["received"] += 1
            if queues.push(self._queue, (kind, vessel, thruster, value)):
                self.stats["dropped"] += 1
        return True

    def _count(self, key: str) -> bool:
        with self._lock:
            self.stats[key] += 1
        return False

    # -- simulation thread --------------------------------------------------------------------
    def apply(self) -> None:
        """Execute the queued commands (called at the start of every step)."""
        if self._velocity_deadline_ns:
            self._expire_velocity_commands()
        while self._queue:
            with self._lock:
                kind, vessel, thruster, value = self._queue.popleft()
            ok = self._execute(kind, vessel, thruster, value)
            self._count("applied" if ok else "rejected")

    def reset(self, clear_queue: bool = True) -> None:
        """A new episode: cmd_vel timers stop, controllers created for cmd_vel go, scenario controllers get
        back their reference; queued commands are dropped unless `clear_queue` is False (a `/reset`
        command keeps what was sent after it). `stats` keep counting."""
        self._velocity_deadline_ns.clear()
        for name in self._created_loops:
            self._controllers.pop(name, None)
        self._created_loops.clear()
        for name, reference in self._held_references.items():
            self._controllers[name].reference = reference
        self._held_references.clear()
        if clear_queue:
            with self._lock:
                self._queue.clear()

    def _execute(self, kind: str, vessel: str, thruster: str | None, value: Any) -> bool:
        world, controllers = self._world, self._controllers
        if kind == "reset":
            if self.reset_allowed:
                self._reset()
            return self.reset_allowed
        if kind == "custom":
            return self._handlers[vessel][1](value) is not False
        if kind == "thrust":  # a network source: the vessel's watchdog applies
            assert thruster is not None
            return world.vessels[vessel].thrusters[thruster].command(value, hold=False)
        if kind == "angle":
            assert thruster is not None
            return world.vessels[vessel].thrusters[thruster].command_angle(value)
        loop = controllers.get(vessel)
        if loop is None:
            loop = controllers[vessel] = _default_velocity_loop(world, vessel)
            self._created_loops.add(vessel)
        elif vessel not in self._created_loops:
            self._held_references.setdefault(vessel, loop.reference)
        loop.reference, loop.force = value, None
        timeout_s = world.scenario.vessels[world.vessels[vessel].index].command_timeout_s
        if timeout_s > 0:
            self._velocity_deadline_ns[vessel] = world.clock_ns + round(timeout_s * 1e9)
        return True

    def _expire_velocity_commands(self) -> None:
        now = self._world.clock_ns
        for vessel, deadline in list(self._velocity_deadline_ns.items()):
            if now <= deadline:
                continue
            del self._velocity_deadline_ns[vessel]
            if vessel in self._created_loops:
                self._created_loops.discard(vessel)
                self._controllers.pop(vessel, None)
            elif vessel in self._held_references:
                self._controllers[vessel].reference = self._held_references.pop(vessel)


MAX_SPEED_MPS = 50.0  # cmd_vel linear x, y (m/s, FLU): beyond any surface vessel
MAX_YAW_RATE_RADPS = 10.0  # cmd_vel angular z (rad/s)
MAX_ANGLE_RAD = 2 * math.pi  # azimuth command


def _value(kind: str, msg: Any):
    """The command's value from a decoded message, or None when it is out of range or not finite."""
    if kind == "reset":
        return True
    if kind in ("thrust", "angle"):
        x = _number(msg.data)
        return x if abs(x) <= (1.0 if kind == "thrust" else MAX_ANGLE_RAD) else None
    nu = (_number(msg.linear.x), _number(msg.linear.y), _number(msg.angular.z))
    return nu if max(abs(nu[0]), abs(nu[1])) <= MAX_SPEED_MPS and abs(nu[2]) <= MAX_YAW_RATE_RADPS else None


def _number(value) -> float:
    """A real number, strictly: a JSON string "0.5" or a bool is a TypeError; NaN/inf compare as out of range."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise TypeError(f"expected a number, got {type(value).__name__}")
    x = float(value)
    return x if math.isfinite(x) else math.inf


def _default_velocity_loop(world: World, vessel: str):
    """A velocity controller with gains derived from the vessel, at 20 Hz (or the nearest whole step count)."""
    from usvsim.config.control import VelocityController
    from usvsim.control.factory import control_loop

    rate_hz = 1e9 / (max(1, round(50_000_000 / world.clock.step_ns)) * world.clock.step_ns)
    return control_loop(world, vessel, VelocityController(rate_hz=rate_hz))
