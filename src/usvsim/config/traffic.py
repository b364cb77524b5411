"""Scenario keys of other ships (`traffic:`): their motion, type and size, AIS and situational awareness.

Positions are world ENU metres (x east, y north). Courses and headings are nautical: degrees clockwise
from north, as on a chart, in AIS and in COLREG practice. Speeds are m/s (AIS messages carry knots).

A ship moves `kinematic`ally (world-body geoms on its track: cameras, LiDAR and radar see it, and physics
vessels collide with it) unless `vessel` names a scenario vessel with a velocity controller: then that vessel
follows the route with full physics (line-of-sight guidance, or for a recorded track time-based track following,
feeding its controller).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import KeyedValueError, NonNegativeFloat, PositiveFloat, Section, TupleOf, Vec2
from usvsim.config.sensors import TopicName

Name = Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")]
Topic = TopicName  # a ROS 2 topic name, as sensors' topics (a relative one made absolute)
# AIS ship type (ITU-R M.1371 table 53, first digit 3x/5x specials and 6x-8x classes) by name
SHIP_TYPES = {"pleasure": 37, "sailing": 36, "fishing": 30, "tug": 52, "pilot": 50, "passenger": 60,
              "cargo": 70, "tanker": 80, "high_speed": 40, "other": 90}  # fmt: skip
ShipType = Literal["pleasure", "sailing", "fishing", "tug", "pilot", "passenger", "cargo", "tanker", "high_speed",
                   "other"]  # fmt: skip
# Upper bounds that no real ship reaches but that refuse nonsense (a 1e6 m/s ferry); docs/limits.md. Speed: 100 m/s
# (194 kn) is above every ship in service (fast ferries ~40-60 kn, naval fast craft ~60 kn, offshore racing boats
# ~140 kn; AIS reports up to 102.2 kn) and is the default `world.divergence.max_speed_mps` of a physics vessel.
# Size: the longest ship built (Seawise Giant) was 458 m with a 24.6 m draught, the widest (Pioneering Spirit) is
# 124 m; AIS carries at most 1022 x 126 m.
MAX_SHIP_SPEED_MPS = 100
MAX_SHIP_LENGTH_M = 500
MAX_SHIP_BEAM_M = 130
MAX_SHIP_HEIGHT_M = 100
MAX_SHIP_DRAFT_M = 30
ShipSpeed = Annotated[float, Field(ge=0, le=MAX_SHIP_SPEED_MPS)]
ShipLength = Annotated[float, Field(gt=0, le=MAX_SHIP_LENGTH_M)]
ShipBeam = Annotated[float, Field(gt=0, le=MAX_SHIP_BEAM_M)]


class Waypoint(Section):
    """A point of a route and the speed of the leg that starts there."""

    position: Vec2 = Field(description="world ENU (x east, y north), m")
    speed_mps: ShipSpeed = Field(description="speed on the leg that starts here, m/s; 0: the ship stops here for good "
                                        "(heading as it arrived, or along this leg at the route's start)")


class Route(Section):
    """Straight legs between waypoints at each leg's speed; stops at the last one (or starts over if `loop`), or
    for good at the first waypoint of speed 0 (later waypoints are never reached). Ships never jump."""

    type: Literal["route"] = "route"
    waypoints: TupleOf[Waypoint] = Field(min_length=2)
    loop: bool = False


class Constant(Section):
    """Constant course and speed from a start position."""

    type: Literal["constant"] = "constant"
    position: Vec2 = Field(description="world ENU position at t = 0, m")
    course_deg: float = Field(ge=0.0, lt=360.0, description="course over ground, degrees clockwise from north")
    speed_mps: ShipSpeed


class AisReplay(Section):
    """A recorded AIS track: CSV with a header `time,lat,lon,sog,cog,heading` (s from the scenario start or
    ISO 8601 UTC; WGS-84 degrees; knots; degrees clockwise from north; cog 360 and heading 511 = not available:
    the course is then the track's own direction at that row, the heading the course)."""

    type: Literal["ais_replay"] = "ais_replay"
    path: str = Field(description="CSV file, relative to the scenario file")


Motion = Annotated[Route | Constant | AisReplay, Field(discriminator="type")]


class ShipAis(Section):
    """What this ship transmits: class A (types 1 + 5) or B (types 18 + 24)."""

    enabled: bool = True
    ais_class: Literal["A", "B"] = "A"
    callsign: str = Field(default="", max_length=7)


class Avoidance(Section):
    """Collision avoidance of a physics ship (`vessel`) against every other ship: velocity obstacles with COLREG
    rules 13-17 (docs/traffic.md, usvsim.traffic.colav). Distances between ship reference points, m."""

    type: Literal["velocity_obstacle"] = "velocity_obstacle"
    safety_m: PositiveFloat = Field(default=50.0, description="least distance to keep to any ship, m")
    close_quarters_m: PositiveFloat = Field(default=150.0, description="a stand-on ship acts (rule 17) once a "
                                            "give-way ship that has not acted comes this close, m")  # fmt: skip
    close_quarters_s: NonNegativeFloat = Field(
        default=60.0, description="... or once it would reach its closest point within this time, s (a fast "
        "overtaker crosses close_quarters_m too late to keep safety_m; 0: distance only)")  # fmt: skip
    horizon_s: PositiveFloat = Field(default=150.0, le=3600.0, description="look-ahead of the velocity obstacles, s")
    min_turn_deg: float = Field(default=30.0, ge=0.0, le=90.0, description="least alteration (rule 8: substantial), deg")
    max_turn_deg: float = Field(default=90.0, gt=0.0, le=180.0, description="largest alteration from the course, deg")
    rate_hz: PositiveFloat = Field(default=1.0, le=100.0, description="decisions per second")

    @model_validator(mode="after")
    def _turns(self):
        if self.min_turn_deg > self.max_turn_deg:
            raise ValueError(f"min_turn_deg ({self.min_turn_deg:g}) must not exceed max_turn_deg ({self.max_turn_deg:g})")
        if self.close_quarters_m < self.safety_m:
            raise ValueError(f"close_quarters_m ({self.close_quarters_m:g}) must be at least safety_m ({self.safety_m:g})")
        return self


class Ship(Section):
    """A traffic ship: a kinematic body on a scripted track (seen by sensors, solid to vessels, not pushed by them),
    or, with `vessel`, the track a scenario vessel's velocity controller follows."""

    name: Name
    motion: Motion
    mmsi: int = Field(ge=100_000_000, le=999_999_999, description="9-digit Maritime Mobile Service Identity")
    ship_type: ShipType = "cargo"
    length_m: ShipLength = 20.0
    beam_m: ShipBeam = 6.0
    height_m: float = Field(default=4.0, gt=0, le=MAX_SHIP_HEIGHT_M,
                            description="hull top above the waterline (superstructure adds half)")
    draft_m: float = Field(default=1.5, ge=0, le=MAX_SHIP_DRAFT_M)
    vessel: Name | None = Field(default=None, description="a scenario vessel (with a velocity controller) to drive")
    ais: ShipAis = ShipAis()
    avoidance: Avoidance | None = Field(default=None, description="collision avoidance (a ship with `vessel` only)")

    @model_validator(mode="after")
    def _avoiding_vessel(self):
        if self.avoidance is not None and self.vessel is None:
            raise KeyedValueError("avoidance", "only a physics ship (one with `vessel`) can avoid; a kinematic ship "
                                  "keeps its track")  # fmt: skip
        return self


class OwnShipAis(Section):
    """AIS from a scenario vessel (the own ship), e.g. to test a receiver."""

    vessel: Name
    mmsi: int = Field(ge=100_000_000, le=999_999_999)
    ais_class: Literal["A", "B"] = "A"
    ship_type: ShipType = "pleasure"
    length_m: ShipLength = 5.0
    beam_m: ShipBeam = 2.0


class Ais(Section):
    """AIS transmissions as NMEA 0183 `!AIVDM` sentences on `topic` (nmea_msgs/Sentence) and, optionally, as
    UDP datagrams to 127.0.0.1:`udp_port` (what chart plotters and OpenCPN listen to)."""

    enabled: bool = True
    topic: Topic = "/ais"
    udp_port: int | None = Field(default=None, ge=1024, le=65535)
    position_noise_m: NonNegativeFloat = Field(default=0.0, description="Gaussian std-dev per axis of reported position")
    dropout_probability: float = Field(default=0.0, ge=0.0, lt=1.0, description="chance a report is lost")
    own_ship: OwnShipAis | None = None


class Awareness(Section):
    """Ground-truth situational awareness of `own_ship`: per target range, bearing, CPA, TCPA and COLREG
    encounter, on `topic` at `rate_hz`; the least CPA per target predicted with 0 <= TCPA <= `tcpa_limit_s`
    (ARPA's CPA/TCPA alarm window) goes into the run report."""

    own_ship: Name | None = Field(default=None, description="default: the first scenario vessel")
    rate_hz: PositiveFloat = 1.0
    topic: Topic = "/traffic/situation"
    tcpa_limit_s: PositiveFloat = Field(
        default=1200.0,
        description="run report: a predicted CPA counts only while 0 <= TCPA <= this, s (ARPA's TCPA limit; 20 min)",
    )


class Traffic(Section):
    """Other ships, their AIS, and the own ship's situational awareness (docs/traffic.md)."""

    ships: TupleOf[Ship] = Field(default=(), max_length=1000)
    ais: Ais = Ais()
    awareness: Awareness = Awareness()

    @model_validator(mode="after")
    def _unique(self):
        for key, values in (("name", [s.name for s in self.ships]), ("mmsi", [str(s.mmsi) for s in self.ships])):
            repeat = next((i for i, v in enumerate(values) if v in values[:i]), None)
            if repeat is not None:
                raise KeyedValueError(f"ships[{repeat}].{key}", f"{values[repeat]} is already the {key} of "
                                      f"ships[{values.index(values[repeat])}]; each ship needs its own {key}")
        own = self.ais.own_ship
        same = next((i for i, s in enumerate(self.ships) if own and s.ais.enabled and s.mmsi == own.mmsi), None)
        if own is not None and same is not None:  # two transmitters under one MMSI: receivers merge them into one ship
            raise KeyedValueError("ais.own_ship.mmsi", f"{own.mmsi} is already the mmsi of ships[{same}], which "
                                  "transmits too; each transmitter needs its own mmsi")  # fmt: skip
        if self.ais.topic == self.awareness.topic:
            raise ValueError(f"ais.topic and awareness.topic must differ (one topic carries one message type), "
                             f"both are {self.ais.topic}")  # fmt: skip
        return self


def ais_type_code(name: str) -> int:
    return SHIP_TYPES[name]

