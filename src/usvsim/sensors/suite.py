"""`SensorSuite`: every sensor of every vessel, ticked once per physics step by the simulation.

Wiring (in `Simulation`): build it from the `World`, call `on_step(world)` after the world's physics step
(clock tick and kinematics), and emit what it returns; put `static_transforms()` into the one
`/tf_static` message together with GroundTruth's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from usvsim.config.base import KeyedValueError
from usvsim.core.errors import Names, ScenarioError
from usvsim.messages import ros
from usvsim.messages.envelope import EPISODE_TOPIC, Envelope
from usvsim.sensors.base import Sensor
from usvsim.sensors.imu import Imu
from usvsim.sensors.navigation import Gnss, GroundTruthPose, Odometry
from usvsim.sensors.readings import Reading

if TYPE_CHECKING:
    from usvsim.world.world import World


def _lidar(cfg, vessel, sim, shared):
    from usvsim.sensors.lidar.sensor import Lidar  # embreex is imported only when a LiDAR exists

    return Lidar(cfg, vessel, sim, shared)


def _camera(cfg, vessel, sim, shared):
    from usvsim.sensors.camera.sensor import Camera  # MuJoCo GL is set up only when a camera exists

    return Camera(cfg, vessel, sim, shared)


def _detections(cfg, vessel, sim, shared):
    from usvsim.sensors.detections import Detections3D

    return Detections3D(cfg, vessel, sim, shared)


def _radar(cfg, vessel, sim, shared):
    from usvsim.sensors.radar.sensor import Radar

    return Radar(cfg, vessel, sim, shared)


def _plain(cls):
    return lambda cfg, vessel, sim, shared: cls(cfg, vessel, sim)


# YAML `type` → factory(cfg, vessel, sim, shared); `shared` holds per-suite resources (ray scenes, renderers)
REGISTRY = {"imu": _plain(Imu), "odometry": _plain(Odometry), "gnss": _plain(Gnss),
            "ground_truth": _plain(GroundTruthPose), "lidar": _lidar, "camera": _camera,
            "detections": _detections, "radar": _radar}  # fmt: skip


def _simulation_topics(sim: World) -> dict[str, str]:
    """Topics the simulation publishes or takes commands on besides its sensors' (ground_truth.py, commands.py,
    traffic/): a sensor there would put a second message type on one topic. Each maps to the scenario key that
    sets it ('' for the fixed ones)."""
    topics = {"/clock", "/tf", "/tf_static", EPISODE_TOPIC, "/reset"}
    for vessel in sim.scenario.vessels:
        topics |= {f"/{vessel.name}/ground_truth/odometry", f"/{vessel.name}/cmd_vel"}
    out = dict.fromkeys(topics, "")
    for key in ("ais", "awareness"):  # a traffic topic left at its default: the sensor's topic is the mistake
        section = getattr(sim.scenario.traffic, key)
        out[section.topic] = f"traffic.{key}.topic" + ("" if "topic" in section.model_fields_set else " (default)")
    return out


class SensorSuite:
    """All sensors, keyed `<vessel>/<name>`. `configs` maps vessel name → sensor configs; by default it is
    read from each scenario vessel's `sensors` key."""

    def __init__(self, sim: World, configs: Mapping[str, Sequence[Any]] | None = None):
        if configs is None:
            configs = {v.name: getattr(v, "sensors", None) or () for v in sim.scenario.vessels}
        self.sensors: dict[str, Sensor] = Names("sensor")
        self.shared: dict[str, Any] = {}
        names = list(sim.vessels)
        self._reserved = _simulation_topics(sim)
        for vessel, cfgs in configs.items():
            for k, cfg in enumerate(cfgs):
                key = f"vessels[{names.index(vessel) if vessel in names else '?'}].sensors[{k}]"
                self._add(sim, vessel, cfg, key)

    def _add(self, sim: World, vessel: str, cfg: Any, key: str) -> None:
        source = getattr(sim.scenario, "_source", sim.scenario.name)
        if vessel not in sim.vessels:
            raise ScenarioError(source, key, f"no vessel named {vessel!r}")
        name = f"{vessel}/{cfg.name}"
        if name in self.sensors:
            raise ScenarioError(source, f"{key}.name", f"sensor name {cfg.name!r} is used twice on {vessel!r}")
        try:
            sensor = REGISTRY[cfg.type](cfg, vessel, sim, self.shared)
        except KeyedValueError as exc:  # a key inside the sensor's section
            raise ScenarioError(source, f"{key}.{exc.key}", str(exc)) from None
        except ValueError as exc:  # rates that are not whole multiples of the physics step, bad patterns
            field = "rate_hz" if "Hz" in str(exc) else ""
            raise ScenarioError(source, f"{key}.{field}".rstrip("."), str(exc)) from None
        other = next((s.name for s in self.sensors.values() if s.topic == sensor.topic), None)
        if other is not None:  # one topic carries one message type (the recorder and the bridges refuse a second)
            raise ScenarioError(source, f"{key}.topic", f"topic {sensor.topic} is already the topic of sensor {other!r}")
        owner = self._reserved.get(sensor.topic)
        if owner and not owner.endswith("(default)"):  # the traffic topic set to a sensor's was blamed on the sensor
            raise ScenarioError(source, owner, f"{sensor.topic} is also the topic of sensor {name} ({key}); one "
                                "topic carries one message type")  # fmt: skip
        if owner:
            raise ScenarioError(source, f"{key}.topic", f"topic {sensor.topic} is {owner}; one topic carries one "
                                "message type")  # fmt: skip
        if owner is not None:
            raise ScenarioError(source, f"{key}.topic", f"topic {sensor.topic} is one of the simulation's own topics")
        # /tf_static gives each sensor frame one parent: a second sensor on the frame, or a frame of the TF tree
        # itself (a base_link would be its own child or get a second parent, `world` a parent), breaks the tree
        tree = {"world"} | {f"{v}/{f}" for v in sim.vessels for f in ("odom", "base_link")}
        for frame in (t.child_frame_id for t in sensor.static_transforms()):  # odometry publishes none
            other = next((s.name for s in self.sensors.values()
                          if frame in {t.child_frame_id for t in s.static_transforms()}), None)  # fmt: skip
            if other is not None or frame in tree:
                why = f"already the frame of sensor {other!r}" if other else "a frame of the TF tree (world, odom, base_link)"
                fix = "set a frame_id of its own" if cfg.frame_id is None else f"give it a frame of its own (default {name})"
                raise ScenarioError(source, f"{key}.frame_id", f"frame {frame} is {why}; {fix}")
        self.sensors[name] = sensor

    def __getitem__(self, name: str) -> Sensor:
        return self.sensors[name]

    def __len__(self) -> int:
        return len(self.sensors)

    def __iter__(self):
        return iter(self.sensors)

    def __contains__(self, name: object) -> bool:
        return name in self.sensors

    def of_vessel(self, vessel: str) -> dict[str, Sensor]:
        """The sensors of one vessel, keyed by their short name (`lidar` for `wamv/lidar`)."""
        return Names("sensor", {s.cfg.name: s for s in self.sensors.values() if s.vessel == vessel})

    def observe(self) -> dict[str, Reading | None]:
        """Every sensor's latest reading (None before its first sample), keyed `<vessel>/<name>`."""
        return {name: sensor.latest for name, sensor in self.sensors.items()}

    def on_step(self, sim: World) -> list[Envelope]:
        """Call after every physics step (after the clock tick): the messages due now, in sensor order."""
        out: list[Envelope] = []
        for sensor in self.sensors.values():
            out += sensor.tick(sim)
        return out

    def static_transforms(self) -> list[Any]:
        """Mount transforms (geometry_msgs/TransformStamped, stamp 0) for the one `/tf_static` message."""
        return [t for s in self.sensors.values() for t in s.static_transforms()]

    def static_envelope(self) -> Envelope | None:
        """`/tf_static` with only the sensor mounts (prefer merging `static_transforms()` into one message)."""
        transforms = self.static_transforms()
        return Envelope("/tf_static", 0, ros.tf_message(transforms)) if transforms else None

    def reset(self, world: World) -> None:
        """A new episode: every sensor back to its state at construction (noise streams included)."""
        for sensor in self.sensors.values():
            sensor.reset(world)

    def close(self) -> None:
        """Release thread pools and GL contexts."""
        for resource in self.shared.values():
            getattr(resource, "close", lambda: None)()
        self.shared.clear()
