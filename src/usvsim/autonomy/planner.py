"""Global planning on an occupancy grid: A* with a clearance, line-of-sight shortcuts, corner fillets.

1. Obstacles (occupied cells) are grown by the vessel's clearance: a cell whose distance to the nearest
   obstacle (Euclidean distance transform) is below `clearance_m` is forbidden; within `clearance_m +
   comfort_m` it costs extra, so paths keep to the middle of channels. Unknown cells are free (optimistic).
2. A* over 8-connected cells (numba, binary heap), octile heuristic (admissible: extra costs are >= 0).
3. Shortcuts: from each kept vertex, walk forward to the last vertex of the first run reachable by a straight line
   that stays out of the comfort band (falling back to the forbidden band), which removes the grid staircase.
4. Fillets: each corner of turn angle θ is replaced by a circular arc of radius R (the vessel's turning
   radius u / r_max) tangent to both legs, where both legs are longer than the tangent length
   R·tan(θ/2); shorter legs keep the corner (the guidance law then cuts it inside its look-ahead).
Positions are map-frame (ENU) metres.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from usvsim.autonomy.grid import OccupancyGrid, edt

_MOVES = np.array([(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)], np.int32)
_SQRT2 = math.sqrt(2.0)


@numba.njit(cache=True)
def _search(cost, start, goal, moves, weight):  # pragma: no cover - numba
    """A* (weight 1: octile heuristic) or Dijkstra (weight 0, goal off the grid: every cell) over 8-connected cells
    of `cost` (inf = blocked; step cost = length in cells · (1 + cost of the entered cell)) from `start`.
    Returns the cost g (rows·cols,) and each cell's parent (-1: none)."""
    rows, cols = cost.shape
    n = rows * cols
    g = np.full(n, np.inf)
    parent = np.full(n, -1, np.int64)
    closed = np.zeros(n, np.bool_)
    heap_f, heap_i = np.empty(8 * n + 1), np.empty(8 * n + 1, np.int64)
    size = 0
    s, t = start[0] * cols + start[1], goal[0] * cols + goal[1]
    g[s] = 0.0
    heap_f[0], heap_i[0], size = 0.0, s, 1
    while size > 0:
        cur = heap_i[0]
        size -= 1  # pop: move the last element to the root and sift it down
        lf, li, k = heap_f[size], heap_i[size], 0
        while True:
            c = 2 * k + 1
            if c >= size:
                break
            if c + 1 < size and heap_f[c + 1] < heap_f[c]:
                c += 1
            if heap_f[c] >= lf:
                break
            heap_f[k], heap_i[k], k = heap_f[c], heap_i[c], c
        heap_f[k], heap_i[k] = lf, li
        if closed[cur]:
            continue
        closed[cur] = True
        if cur == t:
            break
        ci, cj = cur // cols, cur % cols
        for m in range(8):
            ni, nj = ci + moves[m, 0], cj + moves[m, 1]
            if ni < 0 or nj < 0 or ni >= rows or nj >= cols or not np.isfinite(cost[ni, nj]):
                continue
            nxt = ni * cols + nj
            step = 1.4142135623730951 if moves[m, 0] != 0 and moves[m, 1] != 0 else 1.0
            ng = g[cur] + step * (1.0 + cost[ni, nj])
            if ng < g[nxt] and not closed[nxt]:
                g[nxt], parent[nxt] = ng, cur
                di, dj = abs(ni - goal[0]), abs(nj - goal[1])
                f = ng + weight * ((di + dj) + (1.4142135623730951 - 2.0) * min(di, dj))
                k = size  # push: sift up
                size += 1
                while k > 0 and heap_f[(k - 1) // 2] > f:
                    heap_f[k], heap_i[k] = heap_f[(k - 1) // 2], heap_i[(k - 1) // 2]
                    k = (k - 1) // 2
                heap_f[k], heap_i[k] = f, nxt
    return g, parent


@numba.njit(cache=True)
def _astar(cost, start, goal, moves):  # pragma: no cover - numba
    """Cheapest 8-connected path on `cost`: the cells (k, 2) from start to goal, or an empty array."""
    rows, cols = cost.shape
    _, parent = _search(cost, start, goal, moves, 1.0)
    s, t = start[0] * cols + start[1], goal[0] * cols + goal[1]
    if parent[t] < 0 and s != t:
        return np.empty((0, 2), np.int64)
    path, cur = [], t
    while cur >= 0:
        path.append(cur)
        cur = parent[cur]
    out = np.empty((len(path), 2), np.int64)
    for k in range(len(path)):
        c = path[len(path) - 1 - k]
        out[k, 0], out[k, 1] = c // cols, c % cols
    return out


class GridPlanner:
    """Plans on an `OccupancyGrid`; `clearance_m` from the path (the vessel's reference point, not its hull: the
    WAM-V's half beam is 1.2 m) to occupied cells, fillets of `turn_radius_m`."""

    def __init__(self, clearance_m: float = 2.0, comfort_m: float = 2.0, turn_radius_m: float = 3.0):
        self.clearance_m, self.comfort_m, self.turn_radius_m = clearance_m, comfort_m, turn_radius_m
        self.distance_m: np.ndarray | None = None

    def cost_map(self, grid: OccupancyGrid) -> np.ndarray:
        """Per-cell extra cost (inf = forbidden) from the distance to the nearest occupied cell."""
        occupied = grid.occupied()
        self.distance_m = edt(~occupied) * grid.resolution_m if occupied.any() else \
            np.full(grid.shape, np.inf)  # fmt: skip
        d = self.distance_m
        band = np.clip((self.clearance_m + self.comfort_m - d) / self.comfort_m, 0.0, 1.0)
        cost = 4.0 * band**2
        cost[d < self.clearance_m] = np.inf
        return cost

    def cost_to_go(self, grid: OccupancyGrid, cost: np.ndarray, goal_ij) -> np.ndarray:
        """Cheapest 8-connected cost (m, weighted like A*'s) from every cell to the goal cell (inf: none)."""
        g, _ = _search(cost, np.asarray(goal_ij, np.int64), np.array([-1, -1], np.int64), _MOVES, 0.0)
        return g.reshape(cost.shape) * grid.resolution_m

    def plan(
        self, grid: OccupancyGrid, start_xy, goal_xy, start_yaw: float | None = None
    ) -> np.ndarray | None:
        """Path (k, 2) map-frame metres from start to goal, or None when the goal cannot be reached
        (`start_yaw`, rad, is not used: the fillets take care of turns)."""
        cost = self.cost_map(grid)
        (s, g) = grid.cells(np.array([start_xy[:2], goal_xy[:2]], float))
        inside = lambda c: 0 <= c[0] < grid.shape[0] and 0 <= c[1] < grid.shape[1]  # noqa: E731
        if not (inside(s) and inside(g)) or not np.isfinite(cost[g[0], g[1]]):
            return None
        cost[s[0], s[1]] = 0.0  # the boat may start inside a band (e.g. next to a quay)
        cells = _astar(cost, s.astype(np.int64), g.astype(np.int64), _MOVES)
        if len(cells) == 0:
            return None
        xs, ys = grid.centres()
        pts = np.column_stack([xs[cells[:, 1]], ys[cells[:, 0]]])
        pts[0], pts[-1] = start_xy[:2], goal_xy[:2]
        return fillet(self.shortcut(grid, pts), self.turn_radius_m)

    def shortcut(self, grid: OccupancyGrid, pts: np.ndarray) -> np.ndarray:
        """Keep only the vertices needed for straight legs clear of the comfort band (or, failing that, clear)."""
        d = self.distance_m
        assert d is not None, "cost_map() sets the distances before a path is shortened"
        out, i = [pts[0]], 0
        while i < len(pts) - 1:
            j = i + 1  # walk forward while the straight leg stays clear (linear in the path length)
            while j + 1 < len(pts) and _clear(
                grid, d, pts[i], pts[j + 1], self.clearance_m + 0.5 * self.comfort_m
            ):
                j += 1
            out.append(pts[j])
            i = j
        return np.array(out)


def _clear(grid: OccupancyGrid, distance_m: np.ndarray, a, b, need_m: float) -> bool:
    """Whether every cell along a → b is at least `need_m` from obstacles (or no worse than at a and b)."""
    n = max(2, int(np.hypot(*(b - a)) / (0.5 * grid.resolution_m)) + 1)
    cells = grid.cells(a + np.linspace(0.0, 1.0, n)[:, None] * (b - a))
    cells = np.clip(cells, 0, np.array(grid.shape) - 1)
    along = distance_m[cells[:, 0], cells[:, 1]]
    return bool(along.min() >= min(need_m, along[0], along[-1]))


def fillet(pts: np.ndarray, radius_m: float, step_m: float = 0.5) -> np.ndarray:
    """Replace each corner by an arc of `radius_m` tangent to both legs where the legs are long enough."""
    if len(pts) < 3 or radius_m <= 0:
        return pts
    out = [pts[0]]
    for k in range(1, len(pts) - 1):
        a, b, c = pts[k - 1], pts[k], pts[k + 1]
        u, v = (b - a) / np.linalg.norm(b - a), (c - b) / np.linalg.norm(c - b)
        turn = math.atan2(u[0] * v[1] - u[1] * v[0], float(u @ v))
        tangent = radius_m * math.tan(abs(turn) / 2.0)
        if abs(turn) < 1e-3 or tangent > 0.5 * min(np.linalg.norm(b - a), np.linalg.norm(c - b)):
            out.append(b)
            continue
        p0 = b - u * tangent
        normal = np.array([-u[1], u[0]]) * math.copysign(1.0, turn)
        centre = p0 + normal * radius_m
        start = math.atan2(*(p0 - centre)[::-1])
        steps = max(2, int(abs(turn) * radius_m / step_m) + 1)
        for s in np.linspace(0.0, turn, steps):
            out.append(centre + radius_m * np.array([math.cos(start + s), math.sin(start + s)]))
    out.append(pts[-1])
    return np.array(out)
