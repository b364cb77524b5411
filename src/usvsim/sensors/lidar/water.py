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


def sunk_hits(ocean, origins: np.ndarray, dirs: np.ndarray, dist: np.ndarray, t: float) -> np.ndarray:
    """Indices of the rays (world origins, unit dirs) whose hit at `dist` (m, +inf = none) lies below the water
    surface at time t. Only hits lower than mean level + margin are looked up in the wave field."""
    margin = 0.0 if ocean.waves is None else WAVE_MARGIN_M
    with np.errstate(invalid="ignore"):  # 0 * inf for horizontal misses: NaN compares False
        z = origins[:, 2] + dirs[:, 2] * dist
    near = np.flatnonzero((z < ocean.level_m + margin) & np.isfinite(dist))
    if ocean.waves is None or len(near) == 0:
        return near[z[near] < ocean.level_m]
    x = origins[near, 0] + dirs[near, 0] * dist[near]
    y = origins[near, 1] + dirs[near, 1] * dist[near]
    return near[z[near] < ocean.elevation(x, y, t)]


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
