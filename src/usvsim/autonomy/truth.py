"""Ground truth for evaluating the stack (not used by it): the true occupancy of the scene in a height band.

A cell is occupied when a vertical ray down through its centre first hits the scene (MuJoCo `mj_ray`, all
geoms but the own vessel's) at a height inside [lo, hi] or above lo: structures are vertical prisms (quays,
piers, boxes, hulls), so their top view is their footprint in the band. Objects are where they are now.
"""

from __future__ import annotations

import mujoco
import numpy as np

from usvsim.autonomy.grid import OccupancyGrid


def true_occupancy(sim, grid: OccupancyGrid, own_vessel: str, band_m: tuple[float, float], top_m: float = 30.0):
    """Boolean (rows, cols) of the grid: scene geometry reaches into the band above the cell."""
    xs, ys = grid.centres()
    exclude = sim.vessels[own_vessel].index + 1  # MuJoCo body id
    down = np.array([0.0, 0.0, -1.0])
    geom = np.zeros(1, np.int32)
    out = np.zeros(grid.shape, bool)
    for i, y in enumerate(ys):
        for j, x in enumerate(xs):
            d = mujoco.mj_ray(sim.model, sim.data, np.array([x, y, top_m]), down, None, 1, exclude, geom)
            out[i, j] = d >= 0 and top_m - d >= band_m[0]
    return out
