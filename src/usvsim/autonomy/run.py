"""Runs the reference stack on a simulation and measures it (the engine of `usvsim demo navigate`).

Per physics step: `sim.step()`; when a new cloud has arrived, the Navigator updates and its command becomes
the vessel's velocity reference (`sim.controllers[vessel].reference`, base_link u, v = 0, r). Measured
against the ground truth at each cloud: odometry error (the estimate is compared with the true base_link
pose at the sweep's end, the instant both odometries estimate), cross-track error of the true position on the
path being followed, hull clearance to the true occupancy, collisions (MuJoCo contacts of the vessel).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from usvsim.autonomy.grid import OccupancyGrid
from usvsim.autonomy.guidance import LosGuidance
from usvsim.autonomy.hybrid import HybridAStarPlanner
from usvsim.autonomy.navigator import Navigator, NavigatorConfig
from usvsim.autonomy.odometry import KissIcpOdometry, TrackedOdometry, kiss_icp_available
from usvsim.autonomy.planner import GridPlanner
from usvsim.autonomy.sensing import Tap, cloud_arrays, sweep_end_s
from usvsim.core.transforms import matrix_from_quat


@dataclass
class Trace:
    """What happened, one row per cloud: time s, true x y yaw, estimated x y yaw, cross-track m, speed m/s."""

    rows: list = field(default_factory=list)
    truth: list = field(default_factory=list)  # every physics step: t, x, y, yaw of the true base_link
    paths: list = field(default_factory=list)
    contacts: set = field(default_factory=set)
    wall_s: dict = field(default_factory=lambda: {"physics_and_sensors": 0.0, "odometry": 0.0, "mapping": 0.0,
                                                  "planning_guidance": 0.0})  # fmt: skip

    def array(self) -> np.ndarray:
        return np.array(self.rows).reshape(-1, 9)


def pose_matrix(vessel) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = matrix_from_quat(vessel.quat), vessel.position
    return out


MAP_MARGIN_M = 10.0


def half_extent_xy(obj) -> np.ndarray:
    """Half sides (x, y, m) of the world-aligned box around an object's footprint, about its `position`: boxes,
    walls and docks by `size`, piers by length and width, berths with their walls, buoys by radius (yawed); a mesh
    obstacle counts as its position (its extent is known only once the file is read)."""
    t = obj.type
    if t in ("box", "wall", "dock"):
        hx, hy = obj.size[0] / 2, obj.size[1] / 2
    elif t == "pier":
        hx, hy = obj.length_m / 2, obj.width_m / 2
    elif t == "berth":  # the slot with its side walls and its back wall, about the slot's centre
        hx, hy = obj.inner_length_m / 2 + obj.wall_thickness_m, obj.inner_width_m / 2 + obj.wall_thickness_m
    elif t == "buoy":
        return np.full(2, obj.radius_m)
    else:
        return np.zeros(2)
    c, s = abs(math.cos(math.radians(obj.yaw_deg))), abs(math.sin(math.radians(obj.yaw_deg)))
    return np.array([c * hx + s * hy, s * hx + c * hy])


def map_bounds(scenario) -> tuple[np.ndarray, np.ndarray]:
    """The mapped area (x, y world ENU m, low and high corners): the scenario's objects (their whole footprints:
    with centres only, a quay 80 m long ended 10 m past its middle) and its vessels' starts, + MAP_MARGIN_M."""
    lo, hi = np.full(2, math.inf), np.full(2, -math.inf)
    for obj in scenario.objects:
        centre, half = np.asarray(obj.position[:2]), half_extent_xy(obj)
        lo, hi = np.minimum(lo, centre - half), np.maximum(hi, centre + half)
    for vessel in scenario.vessels:
        lo, hi = np.minimum(lo, vessel.pose.position[:2]), np.maximum(hi, vessel.pose.position[:2])
    return lo - MAP_MARGIN_M, hi + MAP_MARGIN_M


def build_navigator(sim, vessel: str, lidar: str, goals, resolution_m: float = 0.25, odometry: str = "auto",
                    planner: str = "astar"):  # fmt: skip
    """A Navigator on a grid covering the scenario's objects (+10 m), with KISS-ICP when available; `planner`
    astar (A* with fillets) or hybrid (hybrid A*, arcs of the turning radius)."""
    lo, hi = map_bounds(sim.scenario)
    grid = OccupancyGrid.around(lo[0], lo[1], hi[0], hi[1], resolution_m)
    tap = Tap(sim, [f"/{vessel}/{lidar}/points", f"/{vessel}/odometry"])
    sim.step()  # /tf_static goes out before the first step
    base_from_lidar = tap.static[f"{vessel}/{lidar}"]
    use_icp = odometry == "kiss_icp" or (odometry == "auto" and kiss_icp_available())
    odo = (
        KissIcpOdometry(base_from_lidar)
        if use_icp
        else TrackedOdometry(base_from_lidar, lambda: tap.latest_odometry)
    )
    guidance = guidance_for(sim.controllers[vessel])
    radius = guidance.speed_mps / guidance.max_yaw_rate_radps  # the turning radius at cruise
    config = (
        NavigatorConfig(guidance=guidance, planner=HybridAStarPlanner(turn_radius_m=radius), replan_s=5.0)
        if planner == "hybrid"
        else NavigatorConfig(guidance=guidance, planner=GridPlanner(turn_radius_m=radius))
    )
    return Navigator(grid, odo, goals, config), tap


def guidance_for(loop, share: float = 0.7) -> LosGuidance:
    """LOS guidance within `share` of what the vessel's velocity controller can reach (its top surge speed and yaw
    rate), at most the WAM-V's 1.5 m/s and 0.5 rad/s. An Otter tops out at 0.42 rad/s (at speed): asked for 0.5, its two
    thrusters saturated, the surge it was told to drop stayed at 0.64 m/s, and it circled a goal for good."""
    top = loop.controller.velocity.max_velocity
    default = LosGuidance()
    return LosGuidance(speed_mps=min(default.speed_mps, share * float(top[0])),
                       max_yaw_rate_radps=min(default.max_yaw_rate_radps, share * float(top[2])))  # fmt: skip


def navigate(sim, nav: Navigator, tap: Tap, vessel: str, lidar: str, max_time_s: float, cloud_every: int = 3):
    """Drive until every goal is reached or `max_time_s`; returns the Trace. The stack takes every
    `cloud_every`-th cloud (3: 3.3 Hz of a 10 Hz LiDAR; in harbor_navigate the same ATE and goals as at 5 Hz,
    IoU 0.90 vs 0.86, KISS-ICP 10 % of the wall time instead of 15 %)."""
    trace, topic, boat = Trace(), f"/{vessel}/{lidar}/points", sim.vessels[vessel]
    loop = sim.controllers[vessel]
    history: list[tuple[float, np.ndarray]] = []  # true (t, pose) to look up a sweep's end
    clock, clouds = time.perf_counter, 0
    while sim.time < max_time_s and not nav.done:
        t0 = clock()
        sim.step()
        trace.wall_s["physics_and_sensors"] += clock() - t0
        pose = pose_matrix(boat)
        history.append((sim.time, pose))
        trace.truth.append((sim.time, pose[0, 3], pose[1, 3], math.atan2(pose[1, 0], pose[0, 0])))
        if sim.data.ncon:  # a contact list only when MuJoCo has one
            trace.contacts.update(b if a == vessel else a for a, b, _ in sim.contacts() if vessel in (a, b))
        env = tap.take(topic)
        if env is None or (clouds := clouds + 1) % cloud_every:
            continue
        xyz, times = cloud_arrays(env.msg)
        end = sweep_end_s(env.stamp_ns / 1e9, times)  # the instant the pose refers to
        if not trace.rows:  # the true pose then initialises the map frame (like /initialpose)
            nav.odometry.initialise(min(history, key=lambda h: abs(h[0] - end))[1])
        dt = end - trace.rows[-1][0] if trace.rows else 0.1
        u, r = _timed_update(nav, trace, end, xyz, times, tap.mean_twist(), dt)
        loop.reference = (u, 0.0, r)
        _record(trace, nav, history, end, u)
        del history[:-50]
    loop.reference = (0.0, 0.0, 0.0)
    return trace


def _timed_update(nav: Navigator, trace: Trace, stamp: float, xyz, times, twist, dt: float):
    clock = time.perf_counter
    t0 = clock()
    nav.pose, deskewed = nav.odometry.update(xyz, times, twist, dt)
    t1 = clock()
    trace.wall_s["odometry"] += t1 - t0
    nav.map_cloud(deskewed)
    t2 = clock()
    trace.wall_s["mapping"] += t2 - t1
    out = nav.decide(stamp)
    trace.wall_s["planning_guidance"] += clock() - t2
    return out


def _record(trace: Trace, nav: Navigator, history, t_ref: float, u_cmd: float) -> None:
    true = min(history, key=lambda h: abs(h[0] - t_ref))[1]
    est = nav.pose
    yaw = lambda m: math.atan2(m[1, 0], m[0, 0])  # noqa: E731
    e = nav.config.guidance.cross_track(true[:2, 3]) if nav.path is not None else math.nan
    trace.rows.append([t_ref, true[0, 3], true[1, 3], yaw(true), est[0, 3], est[1, 3], yaw(est), e, u_cmd])
    if nav.path is not None and (not trace.paths or trace.paths[-1] is not nav.path):
        trace.paths.append(nav.path)
