"""Ground truth for evaluating the stack (not used by it): the true occupancy of the scene in a height band.

A cell is occupied when any of four vertical rays down through it (at ±¼ cell from its centre) first hits
the scene (MuJoCo `mj_ray`, all geoms but the own vessel's) at a height of at least lo: structures are
vertical prisms (quays, piers, boxes, hulls), so their top view is their footprint in the band, and a cell
that a face crosses counts as occupied, as it does for a LiDAR. Objects are where they are now.
"""

from __future__ import annotations

import mujoco
import numpy as np

from usvsim.autonomy.grid import OccupancyGrid


def true_occupancy(
    sim, grid: OccupancyGrid, own_vessel: str, band_m: tuple[float, float], top_m: float = 30.0
):
    """Boolean (rows, cols) of the grid: scene geometry reaches into the band above the cell."""
    xs, ys = grid.centres()
    exclude = sim.vessels[own_vessel].index + 1  # MuJoCo body id
    down = np.array([0.0, 0.0, -1.0])
    geom = np.zeros(1, np.int32)
    out = np.zeros(grid.shape, bool)
    q = grid.resolution_m / 4.0
    for i, y in enumerate(ys):
        for j, x in enumerate(xs):
            for dx, dy in ((-q, -q), (q, -q), (-q, q), (q, q)):
                d = mujoco.mj_ray(
                    sim.model, sim.data, np.array([x + dx, y + dy, top_m]), down, None, 1, exclude, geom
                )
                if d >= 0 and top_m - d >= band_m[0]:
                    out[i, j] = True
                    break
    return out
