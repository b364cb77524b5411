"""Collision avoidance of a full-physics ship (`traffic.ships[].avoidance`): velocity obstacles (Fiorini & Shiller,
1998) under COLREG rules 13-17, on the ground truth of the traffic (every other ship's position and velocity).

Geometry (world ENU, m, m/s; angles ENU yaw, rad): a target at r = p_target - p_own moving at v_t leaves the own
ship at velocity v a least distance d(v) = min over 0 <= t <= horizon of |r + (v_t - v) t| (straight motion); v is
in the target's (truncated) velocity obstacle when d(v) < safety_m. Without the horizon this is the collision
cone: v - v_t within asin(safety_m / |r|) of the direction of r (`collision_cone`). Distances are between the
ships' reference points (base_link, a kinematic ship's track point), not hull to hull.

Rules, at `rate_hz`, with the nominal course and speed of the ship's LOS pilot:
- a target is engaged when the nominal velocity is in its velocity obstacle and the own ship must give way to it
  (head-on, rule 14; crossing from starboard, rule 15; overtaking, rule 13), or, when the own ship is the stand-on
  ship (crossing from port, being overtaken), only once it has also come within `close_quarters_m` or within
  `close_quarters_s` of its closest approach (rule 17: keep course and speed until the give-way ship's action alone
  cannot avoid a close-quarters situation; a distance alone left 25-32 s against an 8 m/s overtaker: 31.7 m);
- while any target is engaged, the ship takes the cheapest velocity outside every ship's obstacle among course
  alterations of `min_turn_deg`..`max_turn_deg` (5° steps) and speeds 1, 0.5, 0 times the nominal; cost: the
  alteration / max_turn_deg + 2 (1 - speed fraction) + 1 - min(1, |v_t - v| / nominal speed) per engaged ship
  (an encounter must end: no escort of a ship on a parallel course) + a little for a change from the last
  choice; head-on, crossing give-way and stand-on for a ship on the port side (rule 17(c)) allow starboard
  alterations only (a clear, substantial turn: rules 8, 14, 15); none outside: the one with the largest least
  distance;
- a target is released once it is past and clear (opening on the nominal velocity, farther than RELEASE x
  safety_m) or out of reach (farther than that plus horizon_s x both speeds); with none engaged the ship follows
  its nominal course again (the LOS pilot brings it back to its track).
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.core.transforms import wrap_angle
from usvsim.traffic import awareness as aw

GIVE_WAY = (aw.HEAD_ON, aw.CROSSING_GIVE_WAY, aw.OVERTAKING)  # rules 13-15
STAND_ON = (aw.CROSSING_STAND_ON, aw.OVERTAKEN)  # rule 17
STARBOARD = (aw.HEAD_ON, aw.CROSSING_GIVE_WAY, aw.CROSSING_STAND_ON)  # rules 14, 15 and 17(c): never to port
SPEED_FRACTIONS = (1.0, 0.5, 0.0)
STEP_DEG = 5.0
RELEASE = 1.2  # a target is released (past and clear) beyond this factor on the safety distance
PORT_TOLERANCE_DEG = 5.0  # the score: turning this far to port of the heading at engagement is a port turn


def collision_cone(rel_pos, radius: float) -> tuple[float, float]:
    """(axis, half angle) of the collision cone of a target at rel_pos (x, y) m: the own ship's velocity relative to
    the target leads within `radius` of it iff its direction is within the half angle of the axis (ENU, rad);
    half angle π inside the radius."""
    rng = math.hypot(rel_pos[0], rel_pos[1])
    return math.atan2(rel_pos[1], rel_pos[0]), (math.pi if rng <= radius else math.asin(radius / rng))


def min_distance(rel_pos, tgt_vel, own_vel, horizon_s: float) -> np.ndarray:
    """Least distance (m) over the next horizon_s of straight motion: (M, N) for own velocities own_vel (M, 2) and
    targets at rel_pos (N, 2) moving at tgt_vel (N, 2)."""
    r = np.asarray(rel_pos, float).reshape(1, -1, 2)
    w = np.asarray(tgt_vel, float).reshape(1, -1, 2) - np.asarray(own_vel, float).reshape(-1, 1, 2)
    w2 = np.maximum(np.sum(w * w, axis=-1), 1e-12)
    t = np.clip(-np.sum(r * w, axis=-1) / w2, 0.0, horizon_s)
    return np.linalg.norm(r + w * t[..., None], axis=-1)


def candidates(course: float, speed: float, cfg, starboard_only: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(course rad, speed m/s, alteration deg to starboard +) of every velocity the ship may take."""
    turns = np.arange(cfg.min_turn_deg, cfg.max_turn_deg + 1e-9, STEP_DEG)
    turns = turns if starboard_only else np.r_[0.0, turns, -turns]
    alteration = np.repeat(turns, len(SPEED_FRACTIONS))
    fraction = np.tile(SPEED_FRACTIONS, len(turns))
    return course - np.radians(alteration), speed * fraction, alteration


def choose(course: float, speed: float, rel_pos, tgt_vel, engaged, starboard_only: bool, previous_rad: float, cfg):
    """(course rad, speed m/s) for a ship whose nominal velocity is (course, speed), among `candidates`: the cheapest
    outside every target's velocity obstacle, or the one that passes farthest (module docstring). `engaged`: a mask
    over the targets."""
    c, s, alteration = candidates(course, speed, cfg, starboard_only)
    vel = np.c_[s * np.cos(c), s * np.sin(c)]
    least = min_distance(rel_pos, tgt_vel, vel, cfg.horizon_s).min(axis=1) if len(rel_pos) else np.full(len(c), np.inf)
    fraction = s / speed if speed > 0 else np.ones(len(s))
    closing = np.linalg.norm(np.asarray(tgt_vel, float)[None, engaged] - vel[:, None], axis=-1)  # (M, engaged)
    lingering = np.sum(1.0 - np.minimum(1.0, closing / max(speed, 1e-9)), axis=1)
    cost = np.abs(alteration) / cfg.max_turn_deg + 2.0 * (1.0 - fraction) + lingering
    cost += 0.1 * np.abs(wrap_angle(c - previous_rad)) / math.pi
    free = least >= cfg.safety_m
    k = int(np.argmin(np.where(free, cost, np.inf))) if free.any() else int(np.lexsort((cost, -least))[0])
    return float(c[k]), float(s[k])


class AvoidingPilot:
    """A LOS pilot whose course and speed the avoidance overrides while some target is engaged (module docstring).
    Reads the fleet's ground truth (`Fleet.pos_enu`, `vel_enu`, `yaw_rad`); ship `me` is the one it steers."""

    def __init__(self, nominal, cfg, fleet, me: int):
        self.nominal, self.cfg, self.fleet, self.me = nominal, cfg, fleet, me
        self.others = np.array([k for k in range(len(fleet.ships)) if k != me], np.int64)
        self.reset()

    def reset(self) -> None:
        self.nominal.reset()
        n = len(self.others)
        self.engaged, self.role, self.yaw_engaged = np.zeros(n, bool), np.full(n, -1), np.zeros(n)
        self.first_role, self.first_turn_deg, self.max_port_deg = np.full(n, -1), np.full(n, np.nan), np.full(n, -np.inf)
        self.command, self._next_s = None, 0.0

    def reference(self, pos_enu, yaw_rad: float, t_s: float = 0.0) -> tuple[float, float, float]:
        """(surge m/s, sway m/s, yaw rate rad/s), as LosPilot.reference; decisions at `rate_hz`."""
        wanted = self.nominal.course(pos_enu)
        if wanted is None:
            return 0.0, 0.0, 0.0
        if t_s >= self._next_s - 1e-9:
            self._next_s = t_s + 1.0 / self.cfg.rate_hz
            self._decide(yaw_rad, *wanted)
        port = np.degrees(wrap_angle(yaw_rad - self.yaw_engaged[self.engaged]))  # turned to port since engaging
        self.max_port_deg[self.engaged] = np.maximum(self.max_port_deg[self.engaged], port)
        return self.nominal.steer(*(self.command or wanted), yaw_rad)

    def _decide(self, yaw_rad: float, course: float, speed: float) -> None:
        f, cfg = self.fleet, self.cfg
        rel, tgt_vel, own_vel = f.pos_enu[self.others] - f.pos_enu[self.me], f.vel_enu[self.others], f.vel_enu[self.me]
        nominal = min_distance(rel, tgt_vel, [speed * math.cos(course), speed * math.sin(course)], cfg.horizon_s)[0]
        _, tcpa = aw.cpa_tcpa(rel, tgt_vel - own_vel)
        enc = aw.encounters(rel, own_vel, yaw_rad, tgt_vel, f.yaw_rad[self.others], tcpa)
        rng, clear = np.hypot(rel[:, 0], rel[:, 1]), RELEASE * cfg.safety_m
        close = (rng < cfg.close_quarters_m) | ((tcpa >= 0.0) & (tcpa < cfg.close_quarters_s))  # rule 17
        acts = np.isin(enc, GIVE_WAY) | np.isin(enc, STAND_ON) & close  # rules 13-15, 17
        new = ~self.engaged & (nominal < cfg.safety_m) & acts
        self.role[new], self.yaw_engaged[new] = enc[new], yaw_rad
        past = (nominal >= rng - 1e-6) & (rng >= clear)  # opening on the nominal velocity, beyond the release distance
        reach = rng - cfg.horizon_s * (np.hypot(tgt_vel[:, 0], tgt_vel[:, 1]) + speed) >= clear  # cannot come near
        self.engaged = (self.engaged | new) & ~past & ~reach
        if not self.engaged.any():
            self.command = None
            return
        starboard_only = bool(np.isin(self.role[self.engaged], STARBOARD).any())
        track = self.nominal.leg_course()
        previous = self.command[0] if self.command else track
        self.command = choose(track, speed, rel, tgt_vel, self.engaged, starboard_only, previous, cfg)
        first = new & (self.first_role < 0)
        self.first_role[first] = enc[first]
        self.first_turn_deg[first] = math.degrees(wrap_angle(yaw_rad - self.command[0]))

    def report(self) -> dict[str, dict]:
        """Per other ship: `encounter` (the own ship's COLREG role when it first engaged it, None: never),
        `turn_deg` (the course then chosen, deg to starboard of the heading then), `max_port_deg` (how far the own
        ship's measured heading turned to port of its heading at engagement while engaged, deg), `starboard` (for
        head-on, crossing give-way and crossing stand-on: no port turn, i.e. a starboard or no alteration and never
        more than PORT_TOLERANCE_DEG to port; None for other roles and never-engaged ships)."""
        out = {}
        for j, k in enumerate(self.others):
            role = int(self.first_role[j])
            turn, port = float(self.first_turn_deg[j]), float(self.max_port_deg[j])
            out[self.fleet.names[k]] = {
                "encounter": aw.ENCOUNTER_NAMES[role] if role >= 0 else None,
                "turn_deg": turn if math.isfinite(turn) else None, "max_port_deg": port if math.isfinite(port) else None,
                "starboard": (turn >= -1e-6 and port <= PORT_TOLERANCE_DEG) if role in STARBOARD else None}  # fmt: skip
        return out
