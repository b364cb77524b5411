"""Hybrid A* (Dolgov, Thrun, Montemerlo, Diebel 2008) on the occupancy grid: paths the boat can sail, made of
straight runs and arcs of its turning radius, starting along its current heading, with the clearance of the
grid planner.

The search expands continuous poses (x, y, ψ; map ENU m, rad CCW from east) by three motion primitives of
length `step_m`: an arc to port, a straight run and an arc to starboard, of curvature 1/R with R the turning
radius (u / r_max: 1.5 m/s at 0.5 rad/s = 3 m), and keeps the cheapest pose per (0.5 m, 0.5 m, 5°) bin. A
primitive is valid where every sample (every quarter metre) lies on a grid cell that the grid planner allows
(clearance) or, near the start, no closer to obstacles than the start is. Cost = length · (1 + the comfort-band
cost) + a small penalty per turn; heuristic = the 8-connected cost-to-go to the goal over the same cost map
(Dijkstra from the goal, which steers around walls and dead ends). The search ends within `goal_tolerance_m`
of the goal, whose point closes the path. When it fails (no path, or `max_expansions`), and for the final
approach within two turning radii of the goal (where the boat slows down and may turn tighter), the grid
planner's path (A*, shortcuts, fillets) is returned.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from usvsim.autonomy.grid import OccupancyGrid
from usvsim.autonomy.planner import GridPlanner

_SAMPLE_M = 0.25


class HybridAStarPlanner:
    """`plan(grid, start_xy, goal_xy, start_yaw)` like `GridPlanner`, but curvature-bounded."""

    def __init__(self, clearance_m: float = 2.0, comfort_m: float = 2.0, turn_radius_m: float = 3.0,
                 step_m: float = 1.5, goal_tolerance_m: float = 0.5, max_expansions: int = 20000):  # fmt: skip
        self.grid_planner = GridPlanner(clearance_m, comfort_m, turn_radius_m)
        self.turn_radius_m, self.step_m = turn_radius_m, step_m
        self.goal_tolerance_m, self.max_expansions = goal_tolerance_m, max_expansions
        self.expansions = 0  # of the last search

    def plan(
        self, grid: OccupancyGrid, start_xy, goal_xy, start_yaw: float | None = None
    ) -> np.ndarray | None:
        fallback = lambda: self.grid_planner.plan(grid, start_xy, goal_xy)  # noqa: E731
        if start_yaw is None or math.dist(start_xy[:2], goal_xy[:2]) < 2.0 * self.turn_radius_m:
            return fallback()  # the final approach turns at low speed, tighter than at cruise
        gp = self.grid_planner
        cost = gp.cost_map(grid)
        (s, g) = grid.cells(np.array([start_xy[:2], goal_xy[:2]], float))
        if not (_inside(grid, s) and _inside(grid, g)) or not np.isfinite(cost[g[0], g[1]]):
            return None
        dist = gp.distance_m
        assert dist is not None  # cost_map sets it
        allowed = np.isfinite(cost) | (dist >= min(gp.clearance_m, dist[s[0], s[1]]))
        cost = np.where(
            allowed, np.where(np.isfinite(cost), cost, 4.0), np.inf
        )  # the start may lie in the band
        h = gp.cost_to_go(grid, cost, g)
        path = self._search(grid, cost, allowed, h, start_xy, start_yaw, goal_xy)
        return path if path is not None else fallback()

    def _primitives(self) -> np.ndarray:
        """Samples (3, n, 3) of the three primitives from the origin heading east: x, y, heading."""
        s = np.arange(1, int(round(self.step_m / _SAMPLE_M)) + 1) * _SAMPLE_M
        out = np.zeros((3, len(s), 3))
        for k, kappa in enumerate((1.0 / self.turn_radius_m, 0.0, -1.0 / self.turn_radius_m)):
            out[k, :, 2] = kappa * s
            out[k, :, 0] = np.sin(kappa * s) / kappa if kappa else s
            out[k, :, 1] = (1.0 - np.cos(kappa * s)) / kappa if kappa else 0.0
        return out

    def _search(self, grid, cost, allowed, h, start_xy, start_yaw, goal_xy) -> np.ndarray | None:
        prims, goal = self._primitives(), np.asarray(goal_xy[:2], float)
        nodes = [(float(start_xy[0]), float(start_xy[1]), float(start_yaw), -1)]  # x, y, ψ, parent
        best: dict[tuple[int, int, int], float] = {}
        heap = [(0.0, 0.0, 0)]
        shape = np.array(grid.shape) - 1
        self.expansions = 0
        while heap and self.expansions < self.max_expansions:
            _, g_cost, n = heapq.heappop(heap)
            x, y, yaw, _ = nodes[n]
            if math.hypot(goal[0] - x, goal[1] - y) <= self.goal_tolerance_m:
                return self._path(nodes, n, prims, goal)
            self.expansions += 1
            c, s = math.cos(yaw), math.sin(yaw)
            px, py = x + c * prims[..., 0] - s * prims[..., 1], y + s * prims[..., 0] + c * prims[..., 1]
            ij = grid.cells(np.stack([px.ravel(), py.ravel()], axis=1))
            ok_cell = ((ij >= 0) & (ij <= shape)).all(axis=1)
            ij = np.clip(ij, 0, shape)
            ok = (ok_cell & allowed[ij[:, 0], ij[:, 1]]).reshape(px.shape).all(axis=1)
            extra = cost[ij[:, 0], ij[:, 1]].reshape(px.shape).mean(axis=1)
            for k in np.flatnonzero(ok):
                i, j = ij[(k + 1) * px.shape[1] - 1]
                if not np.isfinite(h[i, j]):
                    continue
                end_yaw = yaw + prims[k, -1, 2]
                key = (
                    int(px[k, -1] // 0.5),
                    int(py[k, -1] // 0.5),
                    int(round(end_yaw / math.radians(5.0))) % 72,
                )
                ng = g_cost + self.step_m * (1.0 + extra[k]) + (0.1 * self.step_m if k != 1 else 0.0)
                if ng < best.get(key, math.inf):
                    best[key] = ng
                    nodes.append((float(px[k, -1]), float(py[k, -1]), end_yaw, n))
                    heapq.heappush(heap, (ng + h[i, j], ng, len(nodes) - 1))
        return None

    def _path(self, nodes, n: int, prims: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """The poses back to the start, each primitive's samples in between, and the goal."""
        chain = []
        while n >= 0:
            chain.append(nodes[n])
            n = nodes[n][3]
        chain.reverse()
        pts = [chain[0][:2]]
        for (x, y, yaw, _), (x1, y1, yaw1, _) in zip(chain[:-1], chain[1:]):
            turn = (yaw1 - yaw) * self.turn_radius_m / self.step_m  # +1 port, 0 straight, -1 starboard
            k = 1 - int(round(turn))
            c, s = math.cos(yaw), math.sin(yaw)
            for u, v in prims[k, 1::2, :2]:  # every half metre
                pts.append((x + c * u - s * v, y + s * u + c * v))
            pts[-1] = (x1, y1)
        pts.append(tuple(goal))
        return np.array(pts, float)


def _inside(grid: OccupancyGrid, cell) -> bool:
    return bool(0 <= cell[0] < grid.shape[0] and 0 <= cell[1] < grid.shape[1])
