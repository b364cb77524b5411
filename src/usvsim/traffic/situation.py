"""The ground-truth situation of the own ship on `traffic.awareness.topic` (usvsim_msgs/TrafficSituation, frame
`world`), and the run report: per target the least distance to the own ship over the sampled relative track
(from t = 0, then every `sample_every` steps: at least REPORT_RATE_HZ and at every message, whatever the message
rate; between two samples, on the straight line joining the two relative positions: the distances at the
samples are exact, a closest pass of straight relative motion between two samples is found exactly, a turn
between samples puts the chord at most its sagitta off (L²/8R for an arc of length L and radius R), and nothing
is extrapolated), when it happened, the least CPA
predicted with 0 <= TCPA <= `tcpa_limit_s` (ARPA's CPA/TCPA alarm window) and the TCPA it came with, and the
range, CPA, TCPA and relative speed at the last sample, and the first and last samples at which the target's
hull touched the own ship (MuJoCo's contacts). The message's `cpa` (m) and `tcpa` (s) are every
target's straight-line prediction as an ARPA shows it, whatever its TCPA: negative TCPA: opening, the closest
point is past; 0 with CPA = range: no relative motion."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from usvsim.config.loader import source_of
from usvsim.core.clock import NS_PER_S, steps_per_period
from usvsim.core.errors import ScenarioError
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.traffic import awareness as aw

if TYPE_CHECKING:
    from usvsim.config.traffic import Awareness
    from usvsim.traffic.fleet import Fleet
    from usvsim.world.world import World

REPORT_RATE_HZ = 10.0  # the run report samples the relative tracks at least this often (Hz)


class SituationPublisher:
    def __init__(self, world: World, fleet: Fleet, cfg: Awareness):
        source = source_of(world.scenario)
        own = cfg.own_ship or (world.scenario.vessels[0].name if world.scenario.vessels else None)
        if own is None or own not in world.vessels:
            raise ScenarioError(source, "traffic.awareness.own_ship", f"{own!r} is not a scenario vessel")
        try:
            self.every = steps_per_period(cfg.rate_hz, world.clock.step_ns)
        except ValueError as exc:
            raise ScenarioError(source, "traffic.awareness.rate_hz", str(exc)) from None
        self.cfg, self.fleet, self.own = cfg, fleet, world.vessels[own]
        self.period_s = self.every * world.clock.dt
        # report samples: every message step and at least REPORT_RATE_HZ (steps of at most 1 / REPORT_RATE_HZ)
        self.sample_every = math.gcd(self.every, max(1, int(NS_PER_S / REPORT_RATE_HZ // world.clock.step_ns)))
        self.targets = np.array([k for k, s in enumerate(fleet.ships) if s.vessel != own], np.int64)
        owner = fleet.hull_geoms(world)  # hull contacts: the target j of each geom (-1: none), the own ship's geoms
        self._target_of_geom = np.full(len(owner), -1, np.int64)
        for j, k in enumerate(self.targets):
            self._target_of_geom[owner == k] = j
        self._own_geom = world.model.geom_bodyid == self.own.index + 1
        self._own, self._out = np.zeros(5), np.zeros((len(self.targets), 10))
        self.reset(world)

    def reset(self, world: World) -> None:
        n = len(self.targets)
        self.min_dist, self.t_min, self.min_cpa = np.full(n, np.inf), np.zeros(n), np.full(n, np.inf)
        self.tcpa_at_min_cpa, self._last, self.sampled = np.full(n, np.nan), np.zeros((n, 4)), False
        self.first_contact, self.last_contact = np.full(n, np.nan), np.full(n, np.nan)
        # the relative positions at the start (the fleet was placed for t = 0 before): where the first chord starts
        self._prev = self.fleet.pos_enu[self.targets] - world.state.pos[self.own.index, :2]
        self._prev_s = world.time
        self.min_dist[:], self.t_min[:] = np.hypot(self._prev[:, 0], self._prev[:, 1]), world.time

    def _run(self, world: World, since_s: float) -> np.ndarray:
        """One call of the situation kernel (awareness.situation); since_s >= 0 (the time since the previous
        sample) also updates the run report."""
        s, own = world.state, self._own
        _own_state(self.own.index, s.pos, s.rot, s.omega_body, s.vcom_world, s.com_world, own)
        f = self.fleet
        aw.situation(own, f.pos_enu, f.vel_enu, f.yaw_rad, self.targets, self._out, since_s, world.time, self._prev,
                     self.min_dist, self.t_min, self.min_cpa, self.tcpa_at_min_cpa, self.cfg.tcpa_limit_s)  # fmt: skip
        return self._out

    def compute(self, world: World) -> dict[str, Any]:
        """Every target's situation now (arrays over targets; see awareness.py for the conventions)."""
        out = self._run(world, -1.0).copy()
        own = self._own.copy()
        return {"own_pos": own[:2], "own_vel": own[2:4], "own_yaw": float(own[4]), "rel_pos": out[:, aw.X : aw.Y + 1],
                "rel_vel": out[:, aw.VX : aw.VY + 1], "range": out[:, aw.RANGE], "bearing": out[:, aw.BEARING],
                "relative_bearing": out[:, aw.REL_BEARING], "cpa": out[:, aw.CPA], "tcpa": out[:, aw.TCPA],
                "encounter": out[:, aw.ENCOUNTER].astype(np.int64)}  # fmt: skip

    def due(self, world: World, publish: bool = True) -> list[Envelope]:
        if world.clock.steps % self.sample_every != 0 or not len(self.targets):
            return []
        # the run report: the chord from the previous sample (or the start) to now, never past the present (a look
        # ahead reported passes after the run's end) nor an extrapolation (a look back along the current relative
        # velocity reported distances that never happened once the own ship had turned)
        self._run(world, max(world.time - self._prev_s, 0.0))
        self._prev_s = world.time
        if world.data.ncon:
            self._contacts(world)
        self.sampled = True
        self._last[:, :3] = self._out[:, [aw.RANGE, aw.CPA, aw.TCPA]]
        self._last[:, 3] = np.hypot(self._out[:, aw.VX], self._out[:, aw.VY])
        if not publish or world.clock.steps % self.every != 0:  # building the message costs more than the rest of the traffic for 50 ships
            return []
        return [Envelope(self.cfg.topic, world.clock.now_ns, self._message(world.clock.now_ns, self.compute(world)))]

    def _contacts(self, world: World) -> None:
        """Targets whose hull touches the own ship now (MuJoCo's contacts of the last step) set their first and last
        contact times."""
        n = world.data.ncon
        g1, g2 = world.data.contact.geom1[:n], world.data.contact.geom2[:n]
        hit = np.r_[self._target_of_geom[g2[self._own_geom[g1]]], self._target_of_geom[g1[self._own_geom[g2]]]]
        hit = np.unique(hit[hit >= 0])
        self.first_contact[hit] = np.where(np.isnan(self.first_contact[hit]), world.time, self.first_contact[hit])
        self.last_contact[hit] = world.time

    def _message(self, stamp_ns: int, s: dict) -> object:
        target_cls = ros.msg_class("usvsim_msgs/msg/TrafficTarget")
        f = self.fleet
        targets = []
        for j, k in enumerate(self.targets):
            vel = f.vel_enu[k]
            targets.append(target_cls(
                name=f.names[k], mmsi=f.ships[k].mmsi, position=ros.point([*f.pos_enu[k], 0.0]),
                velocity=ros.vector3([*vel, 0.0]), course=math.atan2(vel[0], vel[1]) % (2 * math.pi),
                speed=float(np.hypot(*vel)), heading=(0.5 * math.pi - f.yaw_rad[k]) % (2 * math.pi),
                range=float(s["range"][j]), bearing=float(s["bearing"][j]),
                relative_bearing=float(s["relative_bearing"][j]), cpa=float(s["cpa"][j]), tcpa=float(s["tcpa"][j]),
                encounter=int(s["encounter"][j])))  # fmt: skip
        return ros.msg_class("usvsim_msgs/msg/TrafficSituation")(
            header=ros.header(stamp_ns, "world"), own_ship=self.own.name, own_position=ros.point([*s["own_pos"], 0.0]),
            own_velocity=ros.vector3([*s["own_vel"], 0.0]), own_heading=(0.5 * math.pi - s["own_yaw"]) % (2 * math.pi),
            targets=targets)  # fmt: skip

    def report(self) -> dict[str, dict[str, float | None]]:
        """Per target: min_distance_m and t_min_distance_s (when, s of simulated time); min_cpa_m and
        tcpa_at_min_cpa_s, the least CPA predicted with 0 <= TCPA <= tcpa_limit_s and its TCPA (None: none was);
        range_m, cpa_m, tcpa_s and relative_speed_mps at the last sample (None before the first); first_contact_s
        and last_contact_s, the first and last samples at which its hull touched the own ship (None: never; the
        reference points' least distance says nothing of the hulls: a 25 m ship's passes 8 m off through the own
        ship). Metres, seconds, m/s."""

        def opt(x):
            return float(x) if self.sampled and np.isfinite(x) else None

        return {self.fleet.names[k]: {
                    "min_distance_m": opt(self.min_dist[j]), "t_min_distance_s": opt(self.t_min[j]),
                    "min_cpa_m": opt(self.min_cpa[j]), "tcpa_at_min_cpa_s": opt(self.tcpa_at_min_cpa[j]),
                    "range_m": opt(self._last[j, 0]), "cpa_m": opt(self._last[j, 1]), "tcpa_s": opt(self._last[j, 2]),
                    "relative_speed_mps": opt(self._last[j, 3]), "first_contact_s": opt(self.first_contact[j]),
                    "last_contact_s": opt(self.last_contact[j])}
                for j, k in enumerate(self.targets)}  # fmt: skip


@njit(cache=True)
def _own_state(i, pos, rot, omega_body, vcom_world, com_world, own):
    """own = (x, y, vx, vy, yaw) of body i's frame origin: world ENU m, m/s (the CoM's velocity less ω × (CoM −
    origin), ω in the world frame), ENU yaw of its x axis (rad); what `World.origin_velocity` and `Vessel.rpy`
    give, without their Python overhead (~0.2 ms a call in a running simulation)."""
    w = np.zeros(3)
    for r in range(3):
        w[r] = rot[i, r, 0] * omega_body[i, 0] + rot[i, r, 1] * omega_body[i, 1] + rot[i, r, 2] * omega_body[i, 2]
    dx, dy, dz = com_world[i, 0] - pos[i, 0], com_world[i, 1] - pos[i, 1], com_world[i, 2] - pos[i, 2]
    own[0], own[1] = pos[i, 0], pos[i, 1]
    own[2] = vcom_world[i, 0] - (w[1] * dz - w[2] * dy)
    own[3] = vcom_world[i, 1] - (w[2] * dx - w[0] * dz)
    own[4] = math.atan2(rot[i, 1, 0], rot[i, 0, 0])
