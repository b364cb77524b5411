"""The Simulation: the step loop around one `World` (usvsim.world.world, the owner of all state).

Step: queued commands (usvsim.commands) → vessel controllers (at their rates) → the world's physics step
(ocean, hydrostatics, marine models, thrusters, `mj_step`, clock tick, kinematics; see `World`) → sensors
→ messages due at this tick go to subscribers. Sensors, controllers and ground truth take the World.
"""

from __future__ import annotations

import math
import numbers
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from usvsim.commands import CommandInbox
from usvsim.config.loader import load_scenario, parse_scenario
from usvsim.config.scenario import Scenario
from usvsim.control.factory import control_loop, initial_reference
from usvsim.core.errors import Names, UsvsimError
from usvsim.ground_truth import GroundTruth
from usvsim.messages.envelope import Envelope
from usvsim.rendering.wakes import WakeTracks
from usvsim.scene_markers import SceneMarkers
from usvsim.sensors import SensorSuite
from usvsim.sensors.readings import Reading
from usvsim.traffic import Traffic, kinematic_bodies
from usvsim.world.state import BodyState
from usvsim.world.world import World

__all__ = ["BodyState", "Simulation", "World"]


class Simulation:
    """A scenario running in MuJoCo with marine physics. `seed` drives every random stream."""

    def __init__(self, scenario: Scenario | Mapping[str, Any] | str | Path, seed: int = 0):
        """`scenario`: a `Scenario`, a built-in scenario's name (see `usvsim scenarios`), a YAML file's path, or a
        dict of what the YAML file would hold (checked as a file is)."""
        if isinstance(scenario, str | Path):  # Simulation("harbor") failed deep inside with an AttributeError
            scenario = load_scenario(scenario)
        elif isinstance(scenario, Mapping):
            scenario = parse_scenario(dict(scenario), "<dict>")
        elif not isinstance(scenario, Scenario):
            raise UsvsimError(f"Simulation: give a Scenario, a dict, a built-in scenario's name or a YAML file's path, "
                              f"not {type(scenario).__name__}")  # fmt: skip
        self.world = world = World(scenario, seed, kinematic_bodies(scenario))  # traffic ships: moving world geoms
        scenario = world.scenario  # with a real place's parts resolved (geo/)
        self._controller_configs = {v.name: v.controller for v in scenario.vessels if v.controller is not None}
        self.controllers = Names("controller", {name: control_loop(world, name, c)
                                                for name, c in self._controller_configs.items()})  # fmt: skip
        rec = scenario.outputs.recording
        self.ground_truth = GroundTruth(world, *rec.rates_hz(world.clock.step_ns))
        markers = scenario.outputs.markers
        self.markers = SceneMarkers(world, markers.scene, markers.bodies_rate(world.clock.step_ns))  # RViz / Foxglove scene
        self.traffic = Traffic(world, self.controllers)  # other ships: tracks, pilots, awareness, AIS
        # the vessels' recent tracks for the drawn wakes (rendering/wakes.py); the world carries them to the cameras
        world.traffic = self.traffic  # the renderer evaluates the traffic ships' tracks (lamps, wakes)
        self.wakes = world.wakes = WakeTracks(world)
        self.sensors = SensorSuite(world)
        self.traffic.fleet.watch(self.sensors.sensors)  # kinematic ships are placed before steps they are seen after
        for name, vessel in world.vessels.items():
            vessel.sensors = self.sensors.of_vessel(name)
        self.commands = CommandInbox(world, self.controllers, self._reset_command)
        self._reset_seeds = "next"
        self.episode = 0  # index of the current episode: 0 at construction, +1 at every reset
        self._subscribers: list[Callable[[Envelope], None]] = []
        self._announced = False  # the latched messages and the t = 0 ones go before the first step (_announce)
        self._closed = False

    @classmethod
    def from_scenario(cls, name_or_path: str | Path, seed: int = 0) -> Simulation:
        """A built-in scenario by name (see `usvsim scenarios`) or a YAML file path."""
        return cls(load_scenario(name_or_path), seed=seed)

    # -- the world's state (delegated) ----------------------------------------------------------
    scenario = property(lambda self: self.world.scenario)
    seed = property(lambda self: self.world.seed)
    rng = property(lambda self: self.world.rng)
    clock = property(lambda self: self.world.clock)
    ocean = property(lambda self: self.world.ocean)
    model = property(lambda self: self.world.model)
    data = property(lambda self: self.world.data)
    state = property(lambda self: self.world.state)
    hulls = property(lambda self: self.world.hulls)
    marine = property(lambda self: self.world.marine)
    thrusters = property(lambda self: self.world.thrusters)
    hydrostatics = property(lambda self: self.world.hydrostatics)
    vessels = property(lambda self: self.world.vessels)
    bodies = property(lambda self: self.world.bodies)
    rho = property(lambda self: self.world.rho)
    g = property(lambda self: self.world.g)
    rho_air = property(lambda self: self.world.rho_air)
    odom_origin = property(lambda self: self.world.odom_origin)
    body_teleports = property(lambda self: self.world.body_teleports)
    place = property(lambda self: self.world.place)

    @property
    def look(self):
        """The current rendering look (config/rendering.py); assign a new one between frames."""
        return self.world.look

    @look.setter
    def look(self, value) -> None:
        self.world.look = value

    @property
    def time(self) -> float:
        """Simulation time in seconds (float); `clock_ns` is exact."""
        return self.world.clock.seconds

    @property
    def clock_ns(self) -> int:
        return self.world.clock.now_ns

    def body_quat(self, i: int) -> np.ndarray:
        return self.world.body_quat(i)

    def origin_velocity(self, i: int) -> np.ndarray:
        """World-frame velocity of body i's frame origin (m/s)."""
        return self.world.origin_velocity(i)

    def point_velocity(self, i, point: np.ndarray) -> np.ndarray:
        """World-frame velocity (m/s) of `point` (ENU m) moving with body i (see `World.point_velocity`)."""
        return self.world.point_velocity(i, point)

    def contacts(self) -> list[tuple[str, str, float]]:
        """Active contacts as (body name, other body name or 'world', penetration depth m >= 0)."""
        return self.world.contacts()

    # -- the loop -------------------------------------------------------------------------------
    def step(self) -> None:
        """Advance one physics step."""
        if self._closed:  # it stepped the physics, then failed in a closed camera's render context
            raise UsvsimError("this simulation is closed: make a new one")
        world = self.world
        self.commands.apply()  # a /reset starts the new episode here: its announcement goes out next, before this step's
        self._announce()  # messages (announced first, the step's /clock at 0.01 s went out before the marker and t = 0)
        self.traffic.before_step(world)
        for loop in self.controllers.values():
            loop(world)
        world.step_physics()
        self.wakes.record(world)  # vessels' tracks for the drawn wakes (a clock check; a sample per 0.25 s)
        measurements = self.traffic.on_step(world, bool(self._subscribers)) + self.sensors.on_step(world)  # IMU: every step
        if self._subscribers:
            steps, now_ns = world.clock.steps, world.clock.now_ns
            self._emit(self.ground_truth.due(steps, now_ns) + self.markers.due(steps, now_ns) + measurements)

    def reset(self, seed: int | None = None, poses: Mapping[str, Any] | None = None) -> None:
        """A new episode from t = 0 that is bit for bit a fresh `Simulation(scenario, seed)` (seed None: the
        current seed), with `poses` (body name → pose, see `Vessel.teleport`) placing bodies at rest. Every
        stateful part restarts: the world (random streams, ocean, wind and current processes, MuJoCo data,
        thrusters, marine models), sensors, scenario controllers (station keeping re-targets the start
        pose), the command inbox (queued commands dropped). Subscribers stay; the episode marker goes out
        first (see ground_truth.py)."""
        self._new_episode(seed, poses, True)

    @property
    def reset_seeds(self) -> str:
        """The seed of a reset asked for at run time (`/reset` over ROS 2, ROS-TCP or Foxglove; R in the viewer):
        "next" (the default) runs the current seed + 1, so a run with seed s gives episodes s, s + 1, s + 2...
        (reproducible, each a fresh start with its seed); "same" repeats the current seed (the same waves, gusts and
        noise every episode). `reset(seed)` from Python takes the seed it is given (None: the current one)."""
        return self._reset_seeds

    @reset_seeds.setter
    def reset_seeds(self, value: str) -> None:
        if value not in ("next", "same"):
            raise UsvsimError(f"reset_seeds must be 'next' or 'same', not {value!r}")
        self._reset_seeds = value

    def next_reset_seed(self) -> int:
        """The seed the next reset asked for at run time uses (`/reset`, R in the viewer): see `reset_seeds`."""
        return self.world.seed + 1 if self._reset_seeds == "next" else self.world.seed

    def _reset_command(self) -> None:
        """A `/reset` (from the command inbox; its queue is kept: commands after the reset still apply)."""
        self._new_episode(self.next_reset_seed(), None, False)

    def _new_episode(self, seed: int | None, poses: Mapping[str, Any] | None, clear_queue: bool) -> None:
        world = self.world
        world.reset(seed, poses)
        self.wakes.reset()
        self.traffic.reset(world)
        self.commands.reset(clear_queue)
        self.sensors.reset(world)
        for name, loop in self.controllers.items():  # the scenario's, and traffic pilots' (their pilots reset)
            loop.reset()
            if name in self._controller_configs:
                loop.reference, loop.force = initial_reference(world, name, self._controller_configs[name]), None
        self.episode += 1
        self._announced = False

    def run(
        self, seconds: float, realtime: bool = False, on_step: Callable[[Simulation], None] | None = None
    ):
        """Run for `seconds` of simulation time (a whole number of physics steps, halves rounded up), as fast as
        possible or paced to the wall clock."""
        if isinstance(seconds, bool) or not isinstance(seconds, numbers.Real) or not math.isfinite(seconds) \
                or seconds < 0:  # fmt: skip
            raise UsvsimError(f"run: seconds must be a finite number >= 0, not {seconds!r}")  # -1 ran no step
        clock = self.world.clock
        steps = math.floor(seconds * 1e9 / clock.step_ns + 0.5)  # halves up: round() ran 0.005 s as 0 steps, 0.025 as 2
        start_wall = time.perf_counter()
        unwatched = on_step is None and not realtime  # nobody looks between steps (subscribers: see below)
        try:
            for k in range(steps):
                self.world.unwatched = unwatched and k < steps - 1 and not self._subscribers
                self.step()
                if on_step is not None:
                    on_step(self)
                if realtime:
                    ahead = (k + 1) * clock.step_ns / 1e9 - (time.perf_counter() - start_wall)  # steps, not the
                    # clock: a /reset mid-run restarts the clock, and pacing from it would race ahead
                    if ahead > 0:
                        time.sleep(ahead)
        finally:
            self.world.unwatched = False

    # -- outputs ------------------------------------------------------------------------------
    def observe(self) -> dict[str, Reading | None]:
        """The latest reading of every sensor as arrays, keyed `<vessel>/<name>` (see sensors/readings.py)."""
        return self.sensors.observe()

    def publish(self, envelopes: Iterable[Envelope]) -> None:
        """Send extra messages (a task's topics, an app's own) to every subscriber now: the recorder, the DDS,
        ROS-TCP and Foxglove bridges and callbacks get them like the simulation's own. Stamp them with
        simulation time (`clock_ns`); each `Envelope`'s QoS is what the bridges offer."""
        if self._subscribers:
            self._announce()
            self._emit(list(envelopes))

    def _announce(self) -> None:
        """The latched messages (episode marker, /tf_static, scene markers) and the t = 0 ones, once per episode
        before anything else. A first subscriber after steps without one gets the latched messages only (the t = 0
        ones were then the current state stamped 0, and /clock went back to 0 before jumping ahead)."""
        if not self._announced and self._subscribers:
            self._announced = True
            clock = self.world.clock
            first = [*self.ground_truth.due(0, 0), *self.markers.due(0, 0)] if clock.steps == 0 else []
            self._emit([*self._latched(), *first])

    def subscribe(self, callback: Callable[[Envelope], None]) -> Callable[[], None]:
        """Receive every message the simulation emits; returns a function that unsubscribes."""
        if not callable(callback):  # it failed at the next step, far from the mistake
            raise UsvsimError(f"subscribe: the callback must be callable (a function of one Envelope), not {callback!r}")
        self._subscribers.append(callback)

        def unsubscribe() -> None:  # a second call does nothing (it was a ValueError from list.remove)
            if callback in self._subscribers:
                self._subscribers.remove(callback)

        return unsubscribe

    @contextmanager
    def record(self, path: str | Path, topics: Iterable[str] | None = None, compression: str | None = None,
               epoch_ns: int | None = None) -> Iterator[Any]:  # fmt: skip
        """Record to an MCAP file while the block runs: the file `usvsim run --record` writes (rosbag2
        layout), limited to `topics` if given (names or patterns such as "/tf*", io/topic_filter.py; one that
        matched no message is a warning at exit); `topics` and `compression` default to the scenario's
        `outputs.recording` (all topics, zstd). Log times are `epoch_ns` + simulation time (default: the wall
        clock at the start; 0 or a fixed epoch for byte-identical files; see io/mcap_recorder.py). Started after
        the first step, it first writes the latched messages (episode marker, /tf_static, scene markers). Yields
        the `McapRecorder`; the file is complete at exit."""
        import warnings

        from usvsim.io.mcap_recorder import McapRecorder
        from usvsim.io.topic_filter import TopicFilter

        configured = self.scenario.outputs.recording
        wanted = TopicFilter(topics, "record: topics") if topics is not None \
            else TopicFilter(configured.topics, "outputs.recording.topics")  # fmt: skip
        compression = configured.compression if compression is None else compression
        recorder = McapRecorder(path, compression=compression, topics=wanted, epoch_ns=epoch_ns)  # type: ignore[arg-type]
        if self._announced:
            for envelope in self._latched():
                recorder.write(envelope)
        unsubscribe = self.subscribe(recorder.write)
        try:
            yield recorder
        finally:
            unsubscribe()
            recorder.close()
        for line in wanted.unmatched():  # not on an exception: the block did not run its course
            warnings.warn(f"{line}; {path} has none", UserWarning, stacklevel=3)

    def _latched(self) -> list[Envelope]:
        """The episode marker, /tf_static and the scene markers: what a subscriber joining mid-episode has missed.
        Stamped 0 (the episode's start), published now: a recording started at t = 5 s began with 5 s of nothing."""
        gt = self.ground_truth
        static = gt.static_transforms(self.sensors.static_transforms())
        latched = [gt.episode(self.episode, self.world.seed), *static, *self.markers.static()]
        for envelope in latched:
            envelope.publish_ns = self.world.clock.now_ns
        return latched

    def close(self) -> None:
        """Release sensor resources (render contexts, thread pools); the simulation cannot step after this."""
        self._closed = True
        self.sensors.close()
        self.traffic.close()
        self.world.close()

    def _emit(self, envelopes: list[Envelope]) -> None:
        for env in envelopes:
            for cb in list(self._subscribers):
                cb(env)
