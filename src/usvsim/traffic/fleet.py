"""`Fleet`: the scenario's traffic ships at run time.

Kinematic ships are world-body geoms of the MuJoCo model (built by `kinematic_bodies`; no MuJoCo bodies, which
would cost per body in every stage of `mj_step`): before each physics step `before_step` evaluates every track for
the time the step ends at and writes all their geoms' poses into `model.geom_pos`/`geom_quat` (one numba call for
all ships), so after `mj_step` cameras, ray sensors and contacts see them where the clock says. Physics ships are
scenario vessels whose velocity controller gets its reference from a pilot (LOS on a route or course, time-based
track following on a recorded track). `pos_enu`, `vel_enu`, `yaw_rad` hold every ship's horizontal state at the current time, in the
order of `traffic.ships` (world ENU m, m/s; ENU yaw rad), after every `step()`, at the end of every `run` and
whenever the situation or AIS is due; in between, inside a `run` whose placements are skipped, they may hold
an earlier time (the tracks themselves, `table.evaluate`, give any time).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import mujoco
import numpy as np

from usvsim.config.loader import base_dir, source_of
from usvsim.config.traffic import Route
from usvsim.core.errors import ScenarioError
from usvsim.traffic import kernels as K
from usvsim.traffic.colav import AvoidingPilot
from usvsim.traffic.kernels import TrackTable, fleet_placer
from usvsim.traffic.motion import make_track
from usvsim.traffic.pilot import LosPilot, TrackPilot
from usvsim.traffic.ships import ship_parts
from usvsim.world.builder import STRUCK_BY_KINEMATIC, KinematicBody, kinematic_colliders, kinematic_geoms

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
    """The kinematic ships (world-body geoms), at their t = 0 poses (world ENU, waterline at z = 0)."""
    ships = [s for s in scenario.traffic.ships if s.vessel is None]
    if not ships:
        return ()
    table = TrackTable.of(_tracks(scenario))
    pos, vel, yaw = np.zeros((len(ships), 2)), np.zeros((len(ships), 2)), np.zeros(len(ships))
    table.evaluate(0.0, pos, vel, yaw)
    out = []
    for s, p, a in zip(ships, pos, yaw):
        solid, visuals = ship_parts(s)
        quat = (math.cos(0.5 * a), 0.0, 0.0, math.sin(0.5 * a))
        out.append(KinematicBody(s.name, (), visuals, (float(p[0]), float(p[1]), 0.0), quat, solid=solid))
    return tuple(out)


def _pilot(world: World, controllers: dict, ship, key: str) -> LosPilot | TrackPilot:
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
    else:  # a recorded track: followed in time
        track = make_track(m, world.scenario.world.origin, base_dir(world.scenario), source, f"{key}.motion")
        return TrackPilot(TrackTable.of([track]))
    lookahead = max(2.0 * ship.length_m, 10.0)
    return LosPilot(points, speeds, lookahead, accept_m=lookahead)


class _ShipGeoms:
    """The kinematic ships' geoms in the MuJoCo model, with their poses in the ship frame (from the build, where
    ship k stood at pos0[k], yaw0[k]). A ship's colliding geom (its hull) pairs with floating bodies only while one is within
    reach (bounding spheres plus `MARGIN_M`); MuJoCo's midphase, whose world-body tree is built once and so
    knows no moved geom, is off only while some hull is near."""

    MARGIN_M = 5.0  # > the distance a ship and a body close in one step (25 m/s each at 100 Hz: 0.5 m)

    def __init__(self, world: World, names: list[str], pos0: np.ndarray, yaw0: np.ndarray):
        m = world.model
        built, geoms, owner = kinematic_geoms(m)
        order = {n: k for k, n in enumerate(names)}
        owner = np.array([order[built[k]] for k in owner], int)
        by_ship = np.argsort(owner, kind="stable")  # each ship's geoms together, ships in fleet order
        owner, geoms = owner[by_ship], geoms[by_ship]
        self.geoms = np.ascontiguousarray(geoms, np.int64)
        self.geom_first = np.searchsorted(owner, np.arange(len(names) + 1)).astype(np.int64)
        self.geom_pos, self.geom_quat, self.conaffinity = m.geom_pos, m.geom_quat, m.geom_conaffinity  # in place
        c, s = np.cos(yaw0[owner]), np.sin(yaw0[owner])
        d = m.geom_pos[geoms, :2] - pos0[owner]
        w, z = np.cos(0.5 * yaw0[owner]), -np.sin(0.5 * yaw0[owner])  # (w, 0, 0, z): the inverse yaw
        q = m.geom_quat[geoms]
        self.local = np.ascontiguousarray(np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], m.geom_pos[geoms, 2],
                                                w * q[:, 0] - z * q[:, 3], w * q[:, 1] - z * q[:, 2],
                                                w * q[:, 2] + z * q[:, 1], w * q[:, 3] + z * q[:, 0]])  # fmt: skip
        solid = kinematic_colliders(m, geoms)  # compiled with conaffinity 0 (see `_add_kinematic`)
        self.affinity = STRUCK_BY_KINEMATIC
        self.box = np.full(len(names), -1, np.int64)  # each ship's colliding geom (its hull), -1: none
        self.box[owner[solid]] = geoms[solid]
        reach = m.geom_rbound[geoms] + np.hypot(self.local[:, 0], self.local[:, 1])  # from the ship's origin
        self.radius = np.zeros(len(names))
        self.radius[owner[solid]] = reach[solid]
        self.radius += self.MARGIN_M
        self.body_radius = np.array([_reach(m, b + 1) for b in range(len(world.bodies))])
        self.opt, self.midphase_off = m.opt, None

    def bind(self, world: World, table: TrackTable, pos: np.ndarray, vel: np.ndarray, yaw: np.ndarray) -> None:
        """Fix the kernel's arguments once, packed into one numba object (all arrays written in place): a step then
        costs one call of the compiled kernel with two arguments (see `kernels.fleet_placer`)."""
        ship_i, ship_f = table.ship_i.copy(), table.ship_f.copy()
        ship_i[:, K.BOX], ship_i[:, K.GEOM_FIRST], ship_i[:, K.GEOM_END] = self.box, self.geom_first[:-1], self.geom_first[1:]
        ship_f[:, K.RADIUS] = self.radius
        self.clearance = np.zeros(1)  # m, written by each placement (see `evaluate_and_place`)
        self.arrays = (ship_i, ship_f, table.seg, pos, vel, yaw, self.geoms, self.local, self.geom_pos, self.geom_quat,
                       world.state.pos, self.body_radius, self.conaffinity, self.affinity, self.clearance)  # after t_s
        self._args, self._place = fleet_placer(self.arrays)

    def place(self, t_s: float) -> None:
        """Evaluate every track at t_s into the bound pos, vel, yaw and put the ships' geoms there (`Fleet.before_step`
        does the same inline: one Python call less per step)."""
        near = self._place(t_s, self._args) > 0
        if near is not self.midphase_off:
            self.midphase(near)

    def midphase(self, near: bool) -> None:
        """MuJoCo's midphase off while some ship's hull is near a floating body (see the class docstring), on otherwise."""
        self.midphase_off = near
        bit = int(mujoco.mjtDisableBit.mjDSBL_MIDPHASE)
        self.opt.disableflags = (self.opt.disableflags | bit) if near else (self.opt.disableflags & ~bit)


def _max_speed(table: TrackTable) -> float:
    """An upper bound (m/s) of every kinematic ship's speed (a cubic segment's: 1.5 |p1 - p0| / h + |v0| + |v1|);
    inf where a track jumps (segments that do not join, a loop that does not close)."""
    seg, out = table.seg, 0.0
    if not len(seg):
        return 0.0
    v0, v1 = np.hypot(seg[:, K.V0], seg[:, K.V0 + 1]), np.hypot(seg[:, K.V1], seg[:, K.V1 + 1])
    h = np.maximum(seg[:, K.T1] - seg[:, K.T0], 1e-12)
    chord = np.hypot(seg[:, K.P1] - seg[:, K.P0], seg[:, K.P1 + 1] - seg[:, K.P0 + 1])
    out = float(np.max(np.where(seg[:, K.LINEAR] != 0.0, v0, 1.5 * chord / h + v0 + v1)))
    for a, n, period in zip(table.ship_i[:, K.FIRST], table.ship_i[:, K.COUNT], table.ship_f[:, K.PERIOD]):
        rows = seg[a : a + n]
        ends = rows[:, K.P1 : K.P1 + 2]
        starts = np.r_[rows[1:, K.P0 : K.P0 + 2], rows[:1, K.P0 : K.P0 + 2]] if period > 0 else rows[1:, K.P0 : K.P0 + 2]
        if np.any(np.hypot(*(ends[: len(starts)] - starts).T) > 1e-6):
            return math.inf
    return out


def _reach(m: mujoco.MjModel, body: int) -> float:
    """Radius (m) around body's origin that holds its collision geoms (0 without any)."""
    g = np.flatnonzero((m.geom_bodyid == body) & ((m.geom_contype > 0) | (m.geom_conaffinity > 0)))
    return float(np.max(np.linalg.norm(m.geom_pos[g], axis=1) + m.geom_rbound[g])) if len(g) else 0.0


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
        self.pilots: dict[int, tuple[str, LosPilot | TrackPilot | AvoidingPilot]] = {
            k: (s.vessel, _pilot(world, self.controllers, s, f"traffic.ships[{k}]"))
            for k, s in enumerate(ships) if s.vessel is not None}  # fmt: skip
        for k, (name, pilot) in self.pilots.items():
            if ships[k].avoidance is not None:
                if not isinstance(pilot, LosPilot):
                    raise ScenarioError(source_of(world.scenario), f"traffic.ships[{k}].avoidance", "a ship replaying "
                                        "a recorded track cannot avoid (give it a route or a constant course)")  # fmt: skip
                self.pilots[k] = (name, AvoidingPilot(pilot, ships[k].avoidance, self, k))
        if self.pilots:
            self._kpos, self._kvel, self._kyaw = np.zeros((nk, 2)), np.zeros((nk, 2)), np.zeros(nk)
        else:  # all kinematic: the kernel fills the public arrays directly
            self._kpos, self._kvel, self._kyaw = self.pos_enu, self.vel_enu, self.yaw_rad
        pos0, yaw0 = np.zeros((nk, 2)), np.zeros(nk)  # where the build put them
        if nk:
            self.table.evaluate(0.0, pos0, np.zeros((nk, 2)), yaw0)
        self._geoms = _ShipGeoms(world, [ships[k].name for k in self.kinematic], pos0, yaw0)
        self._geoms.bind(world, self.table, self._kpos, self._kvel, self._kyaw)
        self._eval_ns = -1  # the clock time (ns) the kinematic ships' arrays hold
        self._has_kinematic = nk > 0
        self._every: tuple[int, ...] = (1,)  # steps at which sensors look (`watch`); until then: every step
        self._quiet_until_ns, self._teleports = -1, 0  # placements may be skipped for steps ending by then
        # the floating bodies' reach spheres (about world.state.pos, base_link) move no faster than the divergence
        # limits allow: |v_com| + |omega| |base_link - CoM| (both offsets: MuJoCo's body frame and base_link's)
        limits = world.scenario.world.divergence
        offsets = np.r_[np.linalg.norm(world.model.body_ipos[1:], axis=1), np.linalg.norm(world._com_body, axis=1)]
        body_mps = limits.max_speed_mps + limits.max_angular_speed_radps * float(np.max(offsets, initial=0.0))
        self._closing_mps = body_mps + _max_speed(self.table)
        if nk:  # hulls paired (or not) for the start, as after a reset
            self._place(world.clock.now_ns)
        self.update(world)

    def __len__(self) -> int:
        return len(self.ships)

    def hull_geoms(self, world: World) -> np.ndarray:
        """(ngeom,) the ship index owning each MuJoCo geom that collides as a ship's hull, -1 elsewhere: a kinematic
        ship's hull prism, a full-physics ship's vessel geoms."""
        out = np.full(world.model.ngeom, -1, np.int64)
        for k, box in zip(self.kinematic, self._geoms.box):
            if box >= 0:
                out[box] = k
        for k, (vessel, _) in self.pilots.items():
            out[world.model.geom_bodyid == world.vessels[vessel].index + 1] = k
        return out

    def watch(self, sensors) -> None:
        """Which sensors may see the ships (all but the IMU and the navigation sensors), at which steps: the ships
        are placed before every step after which one of them samples (see `before_step`)."""
        from usvsim.sensors.imu import Imu
        from usvsim.sensors.navigation import Gnss, GroundTruthPose, Odometry

        seeing = [s for s in sensors.values() if not isinstance(s, (Imu, Odometry, Gnss, GroundTruthPose))]
        self._every = tuple(sorted({int(s.every) for s in seeing}))
        if any(s.observes_every_step for s in seeing):
            self._every = (1,)

    def before_step(self, world: World) -> None:
        """Kinematic ships to their poses at the end of the coming step; pilots set their vessels' references.
        Inside `Simulation.run` (no step callback, no subscribers: `world.unwatched`) a step after which no sensor
        that sees ships samples, and before which no ship can have come within reach of a floating body since
        the last placement (bounded by the fastest ship and the divergence limits' speeds), skips the placement:
        nothing reads the ships' geoms then, and the floating bodies' motion is the same bit for bit. The first
        step of every `run` places (bodies may have been moved by hand in between)."""
        if self._has_kinematic:
            clock, geoms = world.clock, self._geoms
            t_ns = clock.now_ns + clock.step_ns  # the clock after the step
            if t_ns <= self._quiet_until_ns and world.unwatched and world.teleports == self._teleports:
                return self._pilots(world) if self.pilots else None
            self._eval_ns = t_ns
            near = geoms._place(t_ns / 1e9, geoms._args) > 0  # `_ShipGeoms.place`, inline
            if near is not geoms.midphase_off:
                geoms.midphase(near)
            if world.unwatched:
                self._quiet(world, clock.steps + 1, t_ns)
            else:  # someone looks after this step (and may move bodies before the next): place the next one too
                self._quiet_until_ns = -1
        if self.pilots:
            self._pilots(world)

    def _quiet(self, world: World, step: int, t_ns: int) -> None:
        """After a placement for the end of step `step` (at t_ns): until when the next ones may be skipped."""
        quiet_s = min(max(self._geoms.clearance[0], 0.0) / self._closing_mps, 3600.0)  # far ships stay far that long
        until = t_ns + int(quiet_s * 1e9)
        for every in self._every:  # the next step after which a sensor that sees ships samples
            until = min(until, t_ns + ((step // every + 1) * every - step - 1) * world.clock.step_ns)
        self._quiet_until_ns, self._teleports = until, world.teleports

    def _pilots(self, world: World) -> None:
        for name, pilot in self.pilots.values():
            loop = self.controllers[name]
            if world.clock.steps % loop.every == 0:  # at the controller's rate
                i = world.vessels[name].index
                loop.reference = pilot.reference(world.state.pos[i], _yaw(world.state.rot[i]), world.time)

    def _place(self, t_ns: int) -> None:
        self._geoms.place(t_ns / 1e9)
        self._eval_ns = t_ns
        self._quiet_until_ns = -1  # the next step places again

    def update(self, world: World) -> None:
        """Refresh pos_enu / vel_enu / yaw_rad for the current time (after the step)."""
        if self._has_kinematic:
            now_ns = world.clock.now_ns
            if self._eval_ns != now_ns:  # before_step evaluated the tracks for this time already
                self.table.evaluate(now_ns / 1e9, self._kpos, self._kvel, self._kyaw)
                self._eval_ns = now_ns
            if self.pilots:
                self.pos_enu[self.kinematic], self.vel_enu[self.kinematic] = self._kpos, self._kvel
                self.yaw_rad[self.kinematic] = self._kyaw
        for k, (name, _) in self.pilots.items():
            i = world.vessels[name].index
            self.pos_enu[k], self.yaw_rad[k] = world.state.pos[i, :2], _yaw(world.state.rot[i])
            self.vel_enu[k] = world.origin_velocity(i)[:2]

    def place_now(self, world: World) -> None:
        """Kinematic ships' geoms and every ship's state to the clock's current time, for a clock set by hand
        (datasets/rerender.py puts a recorded frame's time back)."""
        if self._has_kinematic:
            self._place(world.clock.now_ns)
        self.update(world)

    def reset(self, world: World) -> None:
        for _, pilot in self.pilots.values():
            pilot.reset()
        if len(self.kinematic):
            self._geoms.bind(world, self.table, self._kpos, self._kvel, self._kyaw)  # world.state may be new
            self._place(0)
        self.update(world)
