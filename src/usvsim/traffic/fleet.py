"""`Fleet`: the scenario's traffic ships at run time.

Kinematic ships are MuJoCo mocap bodies (built by `kinematic_bodies` into the model after the floating
bodies): before each physics step `before_step` puts every one at its track's pose for the time the step
ends at (one numba call for all ships), so after `mj_step` cameras, ray sensors and contacts see them where
the clock says. Physics ships are scenario vessels whose velocity controller gets its reference from a LOS
pilot. `pos_enu`, `vel_enu`, `yaw_rad` hold every ship's horizontal state at the current time, in the
order of `traffic.ships` (world ENU m, m/s; ENU yaw rad).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from usvsim.config.loader import base_dir, source_of
from usvsim.config.traffic import Route
from usvsim.core.errors import ScenarioError
from usvsim.traffic.kernels import TrackTable
from usvsim.traffic.motion import make_track
from usvsim.traffic.pilot import LosPilot
from usvsim.traffic.ships import ship_parts
from usvsim.world.builder import KinematicBody

if TYPE_CHECKING:
    from usvsim.config.scenario import Scenario
    from usvsim.world.world import World


def _yaw(rot: np.ndarray) -> float:
    """ENU yaw (rad) of the body x axis of a body → world rotation matrix."""
    return math.atan2(rot[1, 0], rot[0, 0])


def _tracks(scenario: Scenario) -> list:
    source, base, origin = source_of(scenario), base_dir(scenario), scenario.world.origin
    return [make_track(s.motion, origin, base, source, f"traffic.ships[{k}].motion")
            for k, s in enumerate(scenario.traffic.ships) if s.vessel is None]  # fmt: skip


def kinematic_bodies(scenario: Scenario) -> tuple[KinematicBody, ...]:
    """The mocap bodies of the kinematic ships, at their t = 0 poses (world ENU, waterline at z = 0)."""
    ships = [s for s in scenario.traffic.ships if s.vessel is None]
    if not ships:
        return ()
    table = TrackTable.of(_tracks(scenario))
    pos, vel, yaw = np.zeros((len(ships), 2)), np.zeros((len(ships), 2)), np.zeros(len(ships))
    table.evaluate(0.0, pos, vel, yaw)
    out = []
    for s, p, a in zip(ships, pos, yaw):
        collision, visuals = ship_parts(s)
        quat = (math.cos(0.5 * a), 0.0, 0.0, math.sin(0.5 * a))
        out.append(KinematicBody(s.name, collision, visuals, (float(p[0]), float(p[1]), 0.0), quat))
    return tuple(out)


def _pilot(world: World, controllers: dict, ship, key: str) -> LosPilot:
    source = source_of(world.scenario)
    if ship.vessel not in world.vessels or ship.vessel not in controllers:
        raise ScenarioError(source, f"{key}.vessel", f"{ship.vessel!r} must be a scenario vessel with a velocity "
                            "controller (vessels[].controller: {type: velocity})")  # fmt: skip
    m = ship.motion
    if isinstance(m, Route):
        points, speeds = [w.position for w in m.waypoints], [w.speed_mps for w in m.waypoints]
    elif m.type == "constant":
        c = math.radians(m.course_deg)
        far = (m.position[0] + 1e6 * math.sin(c), m.position[1] + 1e6 * math.cos(c))
        points, speeds = [m.position, far], [m.speed_mps, m.speed_mps]
    else:
        raise ScenarioError(source, f"{key}.motion.type", "a physics ship follows a route or a constant course; "
                            "replay AIS tracks kinematically (leave out 'vessel')")  # fmt: skip
    lookahead = max(2.0 * ship.length_m, 10.0)
    return LosPilot(points, speeds, lookahead, accept_m=lookahead)


class Fleet:
    def __init__(self, world: World, controllers: dict | None = None):
        ships = world.scenario.traffic.ships
        self.controllers = controllers or {}  # the loop's ControlLoops: pilots set their references
        self.ships = ships
        self.names = [s.name for s in ships]
        self.kinematic = np.array([k for k, s in enumerate(ships) if s.vessel is None], int)
        self.table = TrackTable.of(_tracks(world.scenario))
        n, nk = len(ships), len(self.kinematic)
        self.pos_enu, self.vel_enu, self.yaw_rad = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n)
        self.pilots = {k: (s.vessel, _pilot(world, self.controllers, s, f"traffic.ships[{k}]"))
                       for k, s in enumerate(ships) if s.vessel is not None}  # fmt: skip
        if self.pilots:
            self._kpos, self._kvel, self._kyaw = np.zeros((nk, 2)), np.zeros((nk, 2)), np.zeros(nk)
        else:  # all kinematic: the kernel fills the public arrays directly
            self._kpos, self._kvel, self._kyaw = self.pos_enu, self.vel_enu, self.yaw_rad
        self.mocap = slice(0, nk)  # the traffic ships are the only mocap bodies, in this order
        self._t_eval = math.nan
        self.update(world)

    def __len__(self) -> int:
        return len(self.ships)

    def before_step(self, world: World) -> None:
        """Kinematic ships to their poses at the end of the coming step; pilots set their vessels' references."""
        if len(self.kinematic):
            t_next = (world.clock.now_ns + world.clock.step_ns) / 1e9  # == world.time after the step
            self._place(world, t_next)
        for name, pilot in self.pilots.values():
            loop = self.controllers[name]
            if world.clock.steps % loop.every == 0:  # at the controller's rate
                i = world.vessels[name].index
                loop.reference = pilot.reference(world.state.pos[i], _yaw(world.state.rot[i]))

    def _place(self, world: World, t_s: float) -> None:
        self.table.evaluate(t_s, self._kpos, self._kvel, self._kyaw)
        self._t_eval = t_s
        data = world.data
        data.mocap_pos[self.mocap, :2] = self._kpos
        half = 0.5 * self._kyaw
        data.mocap_quat[self.mocap, 0] = np.cos(half)
        data.mocap_quat[self.mocap, 3] = np.sin(half)

    def update(self, world: World) -> None:
        """Refresh pos_enu / vel_enu / yaw_rad for the current time (after the step)."""
        if len(self.kinematic):
            if self._t_eval != world.time:  # before_step evaluated the tracks for this time already
                self.table.evaluate(world.time, self._kpos, self._kvel, self._kyaw)
                self._t_eval = world.time
            if self.pilots:
                self.pos_enu[self.kinematic], self.vel_enu[self.kinematic] = self._kpos, self._kvel
                self.yaw_rad[self.kinematic] = self._kyaw
        for k, (name, _) in self.pilots.items():
            i = world.vessels[name].index
            self.pos_enu[k], self.yaw_rad[k] = world.state.pos[i, :2], _yaw(world.state.rot[i])
            self.vel_enu[k] = world.origin_velocity(i)[:2]

    def reset(self, world: World) -> None:
        for _, pilot in self.pilots.values():
            pilot.reset()
        if len(self.kinematic):
            self._place(world, 0.0)
        self.update(world)
