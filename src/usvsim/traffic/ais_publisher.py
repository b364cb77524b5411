"""`AisPublisher`: every transmitting ship's AIS reports on schedule, as nmea_msgs/Sentence on `traffic.ais.topic`
(frame `world`, as the other traffic topics: a frame of the TF tree; `ais` was none) and, when `udp_port` is set,
as UDP datagrams (one sentence + CRLF each) to 127.0.0.1.

Each transmitter keeps its next position-report and static-report times; the interval after a report
follows its speed and rate of turn at that report (ais.py). First reports are spread at random over the
first interval (stream `traffic/ais`), as real transponders are not synchronized. Reported positions get
Gaussian noise (`position_noise_m` per ENU axis) and whole reports are lost with `dropout_probability`.
Each transmitter alternates its reports between the two AIS channels, A (161.975 MHz) and B (162.025 MHz), as
ITU-R M.1371 transponders do (the `!AIVDM` channel field; a report's sentences share one channel); they all went
out on A.
"""

from __future__ import annotations

import heapq
import math
import socket
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from usvsim.config.traffic import SHIP_TYPES
from usvsim.core.errors import ScenarioError
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.traffic import ais

if TYPE_CHECKING:
    from usvsim.config.traffic import Ais
    from usvsim.traffic.fleet import Fleet
    from usvsim.world.world import World


POSITION, STATIC = 0, 1  # kinds of scheduled report
AIS_FRAME = "world"  # the sentences hold geodetic positions; `world` is ENU at the scenario origin, root of TF


@dataclass
class Transmitter:
    mmsi: int
    name: str
    ais_class: str
    ship_type: int
    callsign: str
    length_m: float
    beam_m: float
    draft_m: float
    ship: int | None  # index into the fleet, or None for the own ship
    last_yaw: float = math.nan
    last_t: float = 0.0
    channel: str = "A"  # of the next report: A and B in turn

    def take_channel(self) -> str:
        """The channel of this report; the next goes out on the other one."""
        channel, self.channel = self.channel, "B" if self.channel == "A" else "A"
        return channel


def _transmitters(world: World, fleet: Fleet, cfg: Ais) -> list[Transmitter]:
    out = [Transmitter(s.mmsi, s.name, s.ais.ais_class, SHIP_TYPES[s.ship_type], s.ais.callsign, s.length_m,
                       s.beam_m, s.draft_m, k) for k, s in enumerate(fleet.ships) if s.ais.enabled]  # fmt: skip
    own = cfg.own_ship
    if own is not None:
        if own.vessel not in world.vessels:
            raise ScenarioError(getattr(world.scenario, "_source", ""), "traffic.ais.own_ship.vessel",
                                f"{own.vessel!r} is not a scenario vessel")  # fmt: skip
        out.append(Transmitter(own.mmsi, own.vessel, own.ais_class, SHIP_TYPES[own.ship_type], "", own.length_m,
                               own.beam_m, 0.0, None))  # fmt: skip
    return out


class AisPublisher:
    def __init__(self, world: World, fleet: Fleet, cfg: Ais):
        self.cfg, self.fleet = cfg, fleet
        self.origin = world.scenario.world.origin
        self.tx = _transmitters(world, fleet, cfg)
        self.own = world.vessels[cfg.own_ship.vessel] if cfg.own_ship is not None else None
        self.rng = world.rng.get("traffic/ais")
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM) if cfg.udp_port is not None else None
        self.sent = self.dropped = 0
        self.reset(world)

    def reset(self, world: World) -> None:
        self._queue: list[tuple[float, int, int]] = []  # (when, POSITION or STATIC, transmitter): a heap
        for k, t in enumerate(self.tx):  # first reports spread over the first interval (at rest: 10 s / 30 s)
            first = float(self.rng.uniform(0.0, 10.0 if t.ais_class == "A" else 30.0))
            self._queue += [(first, POSITION, k), (first + float(self.rng.uniform(0.0, 5.0)), STATIC, k)]
            t.last_yaw, t.last_t, t.channel = math.nan, 0.0, "A"
        heapq.heapify(self._queue)
        self._earliest = self._queue[0][0] if self._queue else math.inf
        self._episode_sent = 0  # sentences sent this episode: the multi-sentence message ids count from 0

    @property
    def next_due_s(self) -> float:
        """Simulation time (s) of the next scheduled report (inf with no transmitters)."""
        return self._earliest

    def _state(self, world: World, t: Transmitter) -> tuple[np.ndarray, np.ndarray, float]:
        if t.ship is not None:
            f = self.fleet
            return f.pos_enu[t.ship], f.vel_enu[t.ship], float(f.yaw_rad[t.ship])
        v = self.own
        assert v is not None, "own-ship transmitters exist only with an own ship"
        return v.position[:2], world.origin_velocity(v.index)[:2], float(v.rpy[2])

    def due(self, world: World, publish: bool = True) -> list[Envelope]:
        """Reports due now: sent over UDP (when configured) and, when `publish` (someone listens), returned as
        messages for the topic."""
        now = world.time
        if now < self._earliest:
            return []
        sentences: list[str] = []
        queue = self._queue
        while queue[0][0] <= now:
            _, kind, k = heapq.heappop(queue)
            if kind == POSITION:
                interval, out = self._position(world, k, now)
            else:
                t = self.tx[k]
                interval, out = ais.STATIC_INTERVAL_S, ais.static_sentences(
                    t.mmsi, t.name, t.ship_type, t.callsign, t.length_m, t.beam_m, t.draft_m, t.ais_class,
                    (self._episode_sent + len(sentences)) % 10, t.take_channel())  # fmt: skip
            sentences += out
            heapq.heappush(queue, (now + interval, kind, k))
        self._earliest = queue[0][0]
        return self._publish(world, sentences, publish)

    def _position(self, world: World, k: int, now: float) -> tuple[float, list[str]]:
        """Transmitter k's position report now (none if dropped) and the interval to its next one."""
        t = self.tx[k]
        pos, vel, yaw = self._state(world, t)
        x, y, vx, vy = float(pos[0]), float(pos[1]), float(vel[0]), float(vel[1])
        sog_kn = math.hypot(vx, vy) / ais.KNOT_MPS
        turn_deg_min = 0.0 if math.isnan(t.last_yaw) or now <= t.last_t else \
            abs(math.degrees(math.remainder(yaw - t.last_yaw, 2 * math.pi))) * 60.0 / (now - t.last_t)  # fmt: skip
        turning = turn_deg_min > ais.TURNING_DEG_PER_MIN
        moored = False if t.ship is None else None  # the own ship is under way, stopped or not
        interval = ais.class_a_interval(sog_kn, turning, moored) if t.ais_class == "A" else ais.class_b_interval(sog_kn)
        t.last_yaw, t.last_t = yaw, now
        channel = t.take_channel()  # a report lost in reception was still sent: the next one uses the other channel
        if self.cfg.dropout_probability > 0 and self.rng.random() < self.cfg.dropout_probability:
            self.dropped += 1
            return interval, []
        if self.cfg.position_noise_m > 0:
            noise = self.rng.normal(0.0, self.cfg.position_noise_m, 2)
            x, y = x + float(noise[0]), y + float(noise[1])
        o = self.origin
        lat, lon = ais.enu_to_latlon(x, y, o.latitude_deg, o.longitude_deg, o.altitude_m)
        grid = (math.degrees(math.atan2(vx, vy)), 90.0 - math.degrees(yaw))  # course and heading, from the y axis
        cog, hdg = ais.true_bearing_deg(lat, lon, np.array(grid), o.latitude_deg, o.longitude_deg).tolist()
        report = ais.Report(t.mmsi, lat, lon, sog_kn, cog, ais.heading_deg(hdg), int(now) % 60, moored)
        return interval, [ais.position_sentence(report, t.ais_class, channel)]

    def _publish(self, world: World, sentences: list[str], publish: bool) -> list[Envelope]:
        self.sent += len(sentences)
        self._episode_sent += len(sentences)
        if self.sock is not None:
            for s in sentences:
                self.sock.sendto((s + "\r\n").encode("ascii"), ("127.0.0.1", self.cfg.udp_port))
        if not publish or not sentences:
            return []
        cls, stamp = ros.msg_class("nmea_msgs/msg/Sentence"), world.clock.now_ns
        messages = [cls(header=ros.header(stamp, AIS_FRAME), sentence=s) for s in sentences]
        return [Envelope(self.cfg.topic, stamp, msg) for msg in messages]

    def close(self) -> None:
        if self.sock is not None:
            self.sock.close()
            self.sock = None
