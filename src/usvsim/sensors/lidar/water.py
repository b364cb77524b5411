"""The water surface for ray sensors: it hides what lies below it and, optionally, returns some light.

`sim.ocean` is the one surface (the same `elevation` the hydrostatics use). Hits below it are removed.
With `water_returns`, each downward ray is intersected with the surface by a few Newton steps on the
vertical gap z_ray(t) - η(x(t), y(t)) (exact for still water, converging for wave slopes < 1); it returns
with probability cos²θ (θ = incidence from the surface normal) and intensity ρ_water·cos θ.
"""

from __future__ import annotations

import numpy as np

WAVE_MARGIN_M = 5.0  # hits higher than mean level + this are never tested against the waves
NEWTON_STEPS = 4


def underwater(ocean, points: np.ndarray, t: float) -> np.ndarray:
    """Boolean mask: world points (n, 3) below the water surface at time t."""
    below = np.zeros(len(points), bool)
    margin = 0.0 if ocean.waves is None else WAVE_MARGIN_M
    near = points[:, 2] < ocean.level_m + margin
    if near.any():
        below[near] = points[near, 2] < ocean.elevation(points[near, 0], points[near, 1], t)
    return below


def surface_hits(ocean, origins: np.ndarray, dirs: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Distance along each ray to the water surface (+inf for rays not going down) and cos θ of incidence."""
    n = len(dirs)
    dist, cos_inc = np.full(n, np.inf), np.zeros(n)
    down = dirs[:, 2] < -1e-6
    o, d = origins[down].astype(float), dirs[down].astype(float)
    tt = (ocean.level_m - o[:, 2]) / d[:, 2]
    for _ in range(NEWTON_STEPS if ocean.waves is not None else 0):
        p = o + d * tt[:, None]
        tt = tt - (p[:, 2] - ocean.elevation(p[:, 0], p[:, 1], t)) / d[:, 2]
    ok = tt > 0
    p = o + d * tt[:, None]
    normal = ocean.normal(p[:, 0], p[:, 1], t)
    dist_down = np.where(ok, tt, np.inf)
    dist[down], cos_inc[down] = dist_down, np.abs(np.einsum("ij,ij->i", d, normal))
    return dist, cos_inc
