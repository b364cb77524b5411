"""The scenario file: top-level schema (`version: 1`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import KeyedValueError, NonNegativeFloat, PositiveFloat, Section, TupleOf
from usvsim.config.environment import Environment
from usvsim.config.geo import Geo
from usvsim.config.objects import WorldObject
from usvsim.config.rendering import Rendering
from usvsim.config.sensors import TOPIC_FILTER_PATTERN
from usvsim.config.traffic import Traffic
from usvsim.config.vessel import Vessel
from usvsim.core.clock import rate_at_most

RESERVED_NAMES = {"world"}  # TF's world frame, MuJoCo's body 0, the static objects in LiDAR `reflectivity`


class GeodeticOrigin(Section):
    """WGS-84 position of the world frame's origin (ENU)."""

    latitude_deg: float = Field(default=59.42083, ge=-90, le=90)
    longitude_deg: float = Field(default=10.43278, ge=-180, le=180)
    altitude_m: float = Field(default=0.0, ge=-11_000, le=10_000)


class DivergenceLimits(Section):
    """A floating body beyond any of these has diverged numerically: the run stops with an error naming it."""

    max_speed_mps: float = Field(default=100.0, gt=0, le=10_000)
    max_angular_speed_radps: float = Field(default=100.0, gt=0, le=100_000)
    max_acceleration_mps2: float = Field(default=10_000.0, gt=0, le=1e7)


class World(Section):
    """The physics step and the constants of the world; its frame is ENU with its origin at `origin`."""

    physics_rate_hz: float = Field(default=100.0, ge=20, le=10_000, description="MuJoCo step rate; must divide 1e9 ns")
    gravity_mps2: float = Field(default=9.81, ge=0.1, le=100)
    water_density_kgpm3: float = Field(default=1025.0, ge=500, le=2000)
    air_density_kgpm3: float = Field(default=1.225, gt=0, le=10)
    origin: GeodeticOrigin = GeodeticOrigin()
    divergence: DivergenceLimits = DivergenceLimits()


class Recording(Section):
    """What `--record` (or `outputs.recording.path`) writes: an MCAP file in the rosbag2 layout."""

    path: str | None = Field(
        default=None,
        description="MCAP file written by `usvsim run` without --record (which overrides it); a relative path is "
        "taken from the working directory, like --record's (not from the scenario file, unlike meshes)",
    )
    clock_rate_hz: PositiveFloat | None = Field(
        default=None, description="/clock rate, Hz; null: 100 Hz, or the nearest rate below whose period is a whole "
        "number of physics steps (every step when the physics runs below 100 Hz)")
    ground_truth_rate_hz: PositiveFloat | None = Field(
        default=None, description="ground-truth odometry and TF rate, Hz; null: 50 Hz, or the nearest rate below "
        "whose period is a whole number of physics steps (every step when the physics runs below 50 Hz)")
    topics: list[Annotated[str, Field(pattern=TOPIC_FILTER_PATTERN, max_length=256)]] | None = Field(
        default=None, min_length=1, description="record only these topics: names or patterns such as /tf* ('*' "
        "matches across '/'), '!' before one leaves it out (['!/wamv/camera/*']: all but the camera); null: all. "
        "--record-topics overrides it")  # fmt: skip
    compression: Literal["zstd", "lz4", "none"] = Field(
        default="zstd", description="chunk compression (all three open in ros2 bag and Foxglove); --record-compression "
        "overrides it")  # fmt: skip

    def rates_hz(self, step_ns: int) -> tuple[float, float]:
        """(clock, ground truth) rates at a physics step of `step_ns`: the given ones, or the defaults fitted to the
        step (fixed 100 and 50 Hz refused every physics rate below 100 Hz and rates such as 250 Hz)."""
        clock = self.clock_rate_hz if self.clock_rate_hz is not None else rate_at_most(100.0, step_ns)
        truth = self.ground_truth_rate_hz if self.ground_truth_rate_hz is not None else rate_at_most(50.0, step_ns)
        return clock, truth


class Tf(Section):
    """Which ground-truth transforms the simulation publishes (REP 105). Turn one off when another node owns
    it: SLAM or AMCL publishing `map → odom` needs `world_to_odom: false` (a frame has one parent), and
    robot_localization's EKF publishing `odom → base_link` needs `odom_to_base_link: false`."""

    world_to_odom: bool = Field(default=True, description="static world → <vessel>/odom at the start pose")
    odom_to_base_link: bool = Field(default=True, description="dynamic <vessel>/odom → <vessel>/base_link (true pose)")


class Markers(Section):
    """The scene as visualization_msgs/MarkerArray for RViz and Foxglove, live over ROS 2 and in recordings
    (scene_markers.py)."""

    scene: bool = Field(default=True, description="/usvsim/markers: the vessels (in their base_link frames, moved by "
                        "/tf) and the static obstacles (in world); latched, once per episode")  # fmt: skip
    bodies_rate_hz: NonNegativeFloat | None = Field(
        default=None, description="/usvsim/markers/bodies: buoys and other floating bodies that are not vessels, at "
        "their poses in world, Hz of simulation time (its period a whole number of physics steps); null: 10 Hz, or "
        "the nearest rate below whose period is a whole number of steps; 0: off")  # fmt: skip

    def bodies_rate(self, step_ns: int) -> float:
        """The bodies' marker rate (Hz; 0 off) at a physics step of `step_ns`."""
        return rate_at_most(10.0, step_ns) if self.bodies_rate_hz is None else self.bodies_rate_hz


class Outputs(Section):
    """What the simulation writes besides its sensors' messages."""

    recording: Recording = Recording()
    tf: Tf = Tf()
    markers: Markers = Field(default=Markers(), description="the scene drawn in RViz and Foxglove from ROS 2 topics")


class Scenario(Section):
    version: Literal[1] = Field(description="the file format; 1")
    name: str = Field(default="scenario", max_length=200, description="shown in reports and recordings")
    description: str = Field(default="", max_length=20_000, description="its first line is `usvsim scenarios`' text")
    world: World = Field(default=World(), description="physics step, gravity, densities, geodetic origin")
    environment: Environment = Field(default=Environment(), description="sea, wind, current, water level")
    vessels: TupleOf[Vessel] = Field(default=(), max_length=256, description="simulated vessels (topics and frames "
                                     "under their names)")
    objects: TupleOf[WorldObject] = Field(default=(), description="buoys, docks, walls, piers, berths, mesh obstacles")
    geo: Geo | None = Field(default=None, description="a real place from geospatial files (docs/geo.md)")
    outputs: Outputs = Field(default=Outputs(), description="recording, TF and scene markers")
    rendering: Rendering = Field(default=Rendering(), description="sky, sun, water look, fog, camera effects")
    traffic: Traffic = Field(default=Traffic(), description="scripted ships, AIS, situational awareness")

    @model_validator(mode="after")
    def _unique_names(self):
        seen: dict[str, str] = {}
        keys = [(f"vessels[{i}].name", v.name) for i, v in enumerate(self.vessels)]
        keys += [(f"objects[{i}].name", o.name) for i, o in enumerate(self.objects)]
        keys += [(f"traffic.ships[{i}].name", s.name) for i, s in enumerate(self.traffic.ships)]
        for key, name in keys:
            if name in RESERVED_NAMES:  # a vessel 'world' crashed the MuJoCo build ("repeated name 'world' in body")
                raise KeyedValueError(key, f"{name!r} is reserved (the world frame and MuJoCo's world body); choose "
                                      "another name")  # fmt: skip
            if name in seen:
                raise KeyedValueError(key, f"{name!r} is already the name of {seen[name]}; names of vessels, objects "
                                      "and traffic ships must be unique (repeated: " + ", ".join(_repeated(keys)) + ")")
            seen[name] = key.removesuffix(".name")
        own = {"/clock", "/tf", "/tf_static", "/usvsim/episode", "/reset", "/usvsim/markers",
               "/usvsim/markers/bodies"}  # ground_truth.py, commands.py, scene_markers.py
        own |= {f"/{v.name}/{t}" for v in self.vessels for t in ("ground_truth/odometry", "cmd_vel")}
        for key, topic in (("ais", self.traffic.ais.topic), ("awareness", self.traffic.awareness.topic)):
            if topic in own:
                raise ValueError(f"traffic.{key}.topic {topic} is one of the simulation's own topics")
        return self


def _repeated(keys: list[tuple[str, str]]) -> list[str]:
    names = [name for _, name in keys]
    return sorted({n for n in names if names.count(n) > 1})
