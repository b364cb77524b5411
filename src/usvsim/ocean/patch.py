"""Water patch (thesis §4.2.2, done right): the water surface around one vessel, sampled once per step.

Grid mode: an (n+1)×(n+1) vertex grid, axis-aligned in world ENU, covering the xy bounding box of the hull
footprint plus `margin_m`, sampled from the ocean at the current time (no one-step lag). Each cell is split along
its (i, j)–(i+1, j+1) diagonal and a point is interpolated on the triangle that contains it; points outside the
grid raise ValueError instead of reading out of range. Direct mode queries the ocean at every point instead, so
the two can be compared for accuracy and cost.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from usvsim.ocean.field import as_points


@njit(cache=True)
def interpolate_patch(px, py, x_min, y_min, cell_x, cell_y, heights, out):
    """Piecewise-linear height on the patch triangles; heights[j, i] at (x_min + i·cell_x, y_min + j·cell_y).

    Cell (i, j) has the triangles (00, 10, 11) where fx ≥ fy and (00, 11, 01) where fx < fy. Returns the number
    of points outside the grid (their output is NaN).
    """
    nj, ni = heights.shape[0] - 1, heights.shape[1] - 1
    outside = 0
    for p in range(px.shape[0]):
        u = (px[p] - x_min) / cell_x
        v = (py[p] - y_min) / cell_y
        if not (0.0 <= u <= ni and 0.0 <= v <= nj):
            out[p] = math.nan
            outside += 1
            continue
        i = min(int(u), ni - 1)
        j = min(int(v), nj - 1)
        fx = u - i
        fy = v - j
        z00, z10, z01, z11 = heights[j, i], heights[j, i + 1], heights[j + 1, i], heights[j + 1, i + 1]
        if fx >= fy:
            out[p] = z00 + (z10 - z00) * fx + (z11 - z10) * fy
        else:
            out[p] = z00 + (z01 - z00) * fy + (z11 - z01) * fx
    return outside


class WaterPatch:
    """Water heights around one vessel for the hydrostatics; `mode` is "grid" or "direct"."""

    def __init__(self, surface, resolution: int = 10, margin_m: float = 1.0, mode: str = "grid"):
        if mode not in ("grid", "direct"):
            raise ValueError(f"patch mode must be 'grid' or 'direct', got {mode!r}")
        if resolution < 1 or margin_m < 0:
            raise ValueError(f"need resolution >= 1 and margin >= 0, got {resolution}, {margin_m}")
        self.surface = surface
        self.resolution = int(resolution)
        self.margin_m = float(margin_m)
        self.mode = mode
        self.t = 0.0
        self.heights = np.zeros((resolution + 1, resolution + 1))
        self.origin = np.zeros(2)
        self.cell = np.ones(2)

    def update(self, footprint_xy: np.ndarray, t: float) -> None:
        """Re-centre on the footprint (m, 2) world xy points (e.g. hull vertices) and sample the ocean at time t."""
        self.t = float(t)
        if self.mode == "direct":
            return
        lo = np.min(footprint_xy, axis=0) - self.margin_m
        hi = np.max(footprint_xy, axis=0) + self.margin_m
        self.origin = lo
        self.cell = np.maximum((hi - lo) / self.resolution, 1e-9)
        axis_x = lo[0] + self.cell[0] * np.arange(self.resolution + 1)
        axis_y = lo[1] + self.cell[1] * np.arange(self.resolution + 1)
        gx, gy = np.meshgrid(axis_x, axis_y)
        self.heights = self.surface.elevation(gx, gy, self.t)

    def water_height(self, x, y) -> np.ndarray:
        """Water surface z (m) at world points (x, y) at the time of the last update."""
        px, py = as_points(x, y)
        if self.mode == "direct":
            return self.surface.elevation(px, py, self.t)
        out = np.empty_like(px)
        (ox, oy), (cx, cy) = self.origin, self.cell
        outside = interpolate_patch(px, py, ox, oy, cx, cy, self.heights, out)
        if outside:
            raise ValueError(
                f"{outside} point(s) lie outside the water patch [{self.origin[0]:.2f}, {self.origin[1]:.2f}] + "
                f"{self.resolution}×({self.cell[0]:.3f}, {self.cell[1]:.3f}) m; update the patch with a footprint "
                "that contains every queried point"
            )
        return out

    def height_above_water(self, points: np.ndarray) -> np.ndarray:
        """Signed height (m) of world points (m, 3) above the water; negative means submerged."""
        points = np.asarray(points, dtype=float)
        return points[:, 2] - self.water_height(points[:, 0], points[:, 1])
