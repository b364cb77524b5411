"""The reference stack in one loop: LiDAR odometry → occupancy mapping → planning → LOS guidance →
reactive avoidance → goal logic. It sees only sensor data (clouds in the LiDAR frame with per-point
times) and answers with a base_link velocity command (surge m/s, yaw rate rad/s, like `cmd_vel`).

Per cloud: the odometry gives map ← base_link; the deskewed cloud goes to the map frame; of the points whose
height lies in the `slice_m` band above the water (map z), the nearest per bearing are beams for the 2D grid. The path is replanned
when the goal changes, every `replan_s`, or when the map closes the current path. Avoidance: LiDAR points of
the band inside a corridor ahead of the bow (the boat's half width + margin) cap the surge to stop in time,
and make a replan (from the map, which also holds moving obstacles as they are seen).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from usvsim.autonomy.grid import OccupancyGrid
from usvsim.autonomy.guidance import LosGuidance
from usvsim.autonomy.hybrid import HybridAStarPlanner
from usvsim.autonomy.planner import GridPlanner


@dataclass
class NavigatorConfig:
    slice_m: tuple[float, float] = (0.1, 2.5)  # map z band of the 2D map, m above the mean water
    goal_tolerance_m: float = 0.6  # on the estimate: the true distance stays within 1 m at the odometry error
    replan_s: float = 2.0
    half_width_m: float = 1.3  # WAM-V beam / 2
    corridor_margin_m: float = 0.7
    stop_distance_m: float = 3.0
    give_up_s: float = 30.0  # a goal no plan reaches for this long is given up (the next one is taken)
    guidance: LosGuidance = field(default_factory=LosGuidance)
    planner: GridPlanner | HybridAStarPlanner = field(default_factory=GridPlanner)


def nearest_per_bearing(xy: np.ndarray, origin: np.ndarray, bins: int = 512) -> np.ndarray:
    """The nearest point in each of `bins` bearings around `origin` (like pointcloud_to_laserscan): a beam that
    passes above a low deck and returns from a shed behind it must not clear the deck's cells. 512 bins: one per
    column of the demo's OS1-64 (finer bins hold a neighbouring column's farther point)."""
    d = xy - origin
    rng = np.hypot(d[:, 0], d[:, 1])
    b = ((np.arctan2(d[:, 1], d[:, 0]) + math.pi) * (bins / (2 * math.pi))).astype(np.int64) % bins
    order = np.lexsort((rng, b))
    first = np.ones(len(order), bool)
    first[1:] = b[order][1:] != b[order][:-1]
    return xy[order[first]]


class Navigator:
    """Drives through `goals` (k, 2) map ENU m; `update` per cloud returns (surge, yaw rate)."""

    def __init__(self, grid: OccupancyGrid, odometry, goals, config: NavigatorConfig | None = None):
        self.grid, self.odometry, self.config = grid, odometry, config or NavigatorConfig()
        self.goals = [np.asarray(g, float) for g in goals]
        self.reached: list[float] = []  # time (s) each reached goal was reached
        self.reached_goals: list[int] = []  # their indices in `goals`
        self.given_up: list[dict] = []  # {"goal": index, "t_s": time, "why": reason} of goals no plan reached
        self.path: np.ndarray | None = None
        self.pose = np.eye(4)
        self._index = 0  # the goal driven to
        self._planned_at = -math.inf
        self._blocked_since: float | None = None  # since when no plan reaches the goal
        self._prev: tuple[float, np.ndarray] | None = None
        self._band = np.zeros((0, 3))

    @property
    def done(self) -> bool:
        """Every goal reached or given up."""
        return self._index == len(self.goals)

    @property
    def goal(self) -> np.ndarray | None:
        return None if self.done else self.goals[self._index]

    def _next_goal(self) -> None:
        self._index += 1
        self.path, self._blocked_since = None, None

    def update(self, t: float, xyz: np.ndarray, times_s: np.ndarray, twist=None, dt_s: float = 0.1):
        """One cloud (LiDAR frame, m; per-point times s after its stamp) whose sweep ended at t: the new velocity
        command (surge m/s, yaw rate rad/s). `twist`: base_link's (vx, vy, vz, wx, wy, wz) from a velocity sensor,
        or None; `dt_s`: the time since the previous cloud's sweep end."""
        self.pose, deskewed = self.odometry.update(xyz, times_s, twist, dt_s)
        self.map_cloud(deskewed)
        return self.decide(t)

    def map_cloud(self, deskewed: np.ndarray) -> None:
        """The cloud's band points into the grid, as beams from the LiDAR (pose: `self.pose`)."""
        lidar = self.pose @ self.odometry.base_from_lidar
        self._band = self._map_band(lidar, deskewed)
        self.grid.integrate(lidar[:2, 3], nearest_per_bearing(self._band[:, :2], lidar[:2, 3]))

    def decide(self, t: float) -> tuple[float, float]:
        """Goal logic, planning, guidance and avoidance at the current pose: (surge m/s, yaw rate rad/s)."""
        dt = t - self._prev[0] if self._prev is not None and t > self._prev[0] else 0.1  # the update period
        nu = self._velocity(t)
        p, yaw = self.pose[:2, 3], math.atan2(self.pose[1, 0], self.pose[0, 0])
        goal = self.goal
        if goal is not None and np.hypot(*(goal - p)) < self.config.goal_tolerance_m:
            self.reached.append(t)
            self.reached_goals.append(self._index)
            self._next_goal()
        if self.done:
            return 0.0, 0.0
        ahead = self._obstacle_ahead(self._band, p, yaw)
        if (
            self.path is None
            or t - self._planned_at >= self.config.replan_s
            or ahead < self.config.stop_distance_m
        ):
            self._replan(t, p, yaw)
        if self.done:  # the last goal was given up
            return 0.0, 0.0
        if self.path is None:
            return 0.0, 0.3  # no way yet: turn on the spot to see more
        u, r = self.config.guidance.command(p, yaw, nu, dt)  # it was 0.1 s, whatever the period
        u = min(u, max(0.0, 0.5 * (ahead - self.config.stop_distance_m)))  # stop before what is in the way
        return u, r

    def _map_band(self, map_from_lidar: np.ndarray, xyz: np.ndarray) -> np.ndarray:
        pts = xyz @ map_from_lidar[:3, :3].T + map_from_lidar[:3, 3]
        lo, hi = self.config.slice_m
        return pts[(pts[:, 2] > lo) & (pts[:, 2] < hi)]

    def _velocity(self, t: float) -> np.ndarray:
        """Body velocity (u, v) m/s from the last two poses."""
        p = self.pose[:2, 3].copy()
        nu = np.zeros(2)
        if self._prev is not None and t > self._prev[0]:
            v_map = (p - self._prev[1]) / (t - self._prev[0])
            nu = self.pose[:2, :2].T @ v_map
        self._prev = (t, p)
        return nu

    def _obstacle_ahead(self, band: np.ndarray, p: np.ndarray, yaw: float) -> float:
        """Distance (m) along the bow to the nearest band point inside the corridor, inf if none."""
        c, s = math.cos(yaw), math.sin(yaw)
        d = band[:, :2] - p
        x, y = d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c
        inside = (x > 0.0) & (np.abs(y) < self.config.half_width_m + self.config.corridor_margin_m)
        return float(x[inside].min()) if inside.any() else math.inf

    def _replan(self, t: float, p: np.ndarray, yaw: float) -> None:
        self._planned_at = t
        path = self.config.planner.plan(self.grid, p, self.goal, yaw)
        if path is not None and len(path) >= 2:
            self.path, self._blocked_since = path, None
            self.config.guidance.follow(path)
            return
        # no plan: an unreachable goal held the boat (turning or on a stale path) until the time limit, and the
        # goals after it were never tried
        if self._blocked_since is None:
            self._blocked_since = t
        elif t - self._blocked_since >= self.config.give_up_s:
            self.given_up.append({"goal": self._index, "t_s": round(t, 2), "why": self._why_unreachable()})
            self._next_goal()

    def _why_unreachable(self) -> str:
        """Why no plan reaches the current goal, from the map."""
        goal = self.goal
        assert goal is not None
        i, j = self.grid.cells(goal[None, :])[0]
        if not (0 <= i < self.grid.shape[0] and 0 <= j < self.grid.shape[1]):
            return "outside the map"
        occupied = self.grid.occupied()
        clearance = getattr(self.config.planner, "clearance_m", None)
        if occupied[i, j]:
            return "on an obstacle in the map"
        if occupied.any() and clearance is not None:
            ii, jj = np.nonzero(occupied)
            near = float(np.hypot(ii - i, jj - j).min()) * self.grid.resolution_m
            if near < clearance:
                return f"{near:.2f} m from an obstacle in the map, within the {clearance:g} m clearance"
        return f"no path to it in the map for {self.config.give_up_s:g} s (closed off, or the way too narrow)"
