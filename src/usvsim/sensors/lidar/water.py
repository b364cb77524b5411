"""The water surface for ray sensors: it hides what lies below it and, optionally, returns some light.

`sim.ocean` is the one surface (the same `elevation` the hydrostatics use). Hits below it are removed.
With `water_returns`, a downward ray returns from the first point where it meets the surface, with probability
cos²θ (θ = incidence from the surface normal there) and intensity ρ_water·cos θ. Still water is a plane (closed
form). On waves the first crossing of the vertical gap g(t) = z_ray(t) - η(x(t), y(t)) is bracketed by marching
along the ray in 1 m horizontal steps between the heights of the highest crest and the deepest trough around the
sensor, then refined by regula falsi (Illinois) to `SURFACE_TOL_M`; a fixed-point iteration t ← t - g/d_z (what
this was) only converges for |slope · cot(grazing angle)| < 1, and left returns of near-grazing beams up to 1.3 m
off the waves in sea state 4 (QA). Only rays that could return are searched: the return draw must lie below the
largest cos²θ the sea's steepest slope allows for the ray, so the grazing beams' long brackets cost little.
"""

from __future__ import annotations

import numpy as np

WAVE_MARGIN_M = 5.0  # hits higher than mean level + this are never tested against the waves
MARCH_STEP_M = 1.0  # horizontal step of the bracketing march along a ray
SURFACE_TOL_M = 1e-4  # |g| at which a water hit counts as on the surface
REFINE_STEPS = 30  # Illinois iterations at most (each one is one surface query for the unconverged rays)
BOUND_GRID = 64  # samples per side of the grid that bounds the crest height and the slope around the sensor


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


def surface_hits(ocean, origins: np.ndarray, dirs: np.ndarray, t: float, max_range_m: float,
                 draws: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Distance along each ray (world origins, unit dirs) to its first meeting with the water surface within
    `max_range_m` (+inf for none, or for rays not going down) and cos θ of incidence there. With `draws` (uniform
    [0, 1) per ray, the return decision), rays whose draw is at least the largest cos²θ the waves allow are left
    at +inf: they could not return."""
    n = len(dirs)
    dist, cos_inc = np.full(n, np.inf), np.zeros(n)
    o, d = origins.astype(float), dirs.astype(float)
    rows = np.flatnonzero(d[:, 2] < -1e-6)
    if ocean.waves is None:
        tt = (ocean.level_m - o[rows, 2]) / d[rows, 2]
        keep = (tt > 0) & (tt <= max_range_m)
        dist[rows[keep]], cos_inc[rows[keep]] = tt[keep], -d[rows[keep], 2]
        return dist, cos_inc
    if not len(rows):
        return dist, cos_inc
    amplitude, slope = _wave_bounds(ocean, o[rows, :2], t, max_range_m)
    if draws is not None:
        horizontal = np.hypot(d[rows, 0], d[rows, 1])
        rows = rows[draws[rows] < np.minimum(1.0, -d[rows, 2] + slope * horizontal) ** 2]
    tt = _first_crossing(ocean, o[rows], d[rows], t, amplitude, max_range_m)
    hit = np.isfinite(tt)
    rows, tt = rows[hit], tt[hit]
    p = o[rows] + d[rows] * tt[:, None]
    dist[rows] = tt
    cos_inc[rows] = np.abs(np.einsum("ij,ij->i", d[rows], ocean.normal(p[:, 0], p[:, 1], t)))
    return dist, cos_inc


def _wave_bounds(ocean, xy: np.ndarray, t: float, max_range_m: float) -> tuple[float, float]:
    """(bound on |η - level| m, bound on the surface slope) over the square the rays from `xy` can reach, from a
    grid of samples with margins for what lies between them."""
    reach = min(max_range_m, 5000.0)
    lo, hi = xy.min(axis=0) - reach, xy.max(axis=0) + reach
    gx, gy = np.meshgrid(np.linspace(lo[0], hi[0], BOUND_GRID), np.linspace(lo[1], hi[1], BOUND_GRID))
    eta = ocean.elevation(gx.ravel(), gy.ravel(), t) - ocean.level_m
    nz = ocean.normal(gx.ravel(), gy.ravel(), t)
    tilt = np.sqrt(np.maximum(1.0 - nz[:, 2] ** 2, 0.0)) / np.maximum(nz[:, 2], 1e-3)
    return 1.25 * float(np.abs(eta).max()) + 0.1, 1.5 * float(tilt.max()) + 0.05


def _first_crossing(
    ocean, o: np.ndarray, d: np.ndarray, t: float, amplitude: float, max_range_m: float
) -> np.ndarray:
    """Distance (m, +inf for none) along downward rays to their first crossing of the surface, searched between the
    heights level ± amplitude and within max_range_m."""
    level = ocean.level_m
    gap = lambda s, rows: o[rows, 2] + d[rows, 2] * s - ocean.elevation(  # noqa: E731
        o[rows, 0] + d[rows, 0] * s, o[rows, 1] + d[rows, 1] * s, t)  # fmt: skip
    start = np.maximum((o[:, 2] - level - amplitude) / -d[:, 2], 0.0)
    end = np.minimum((o[:, 2] - level + amplitude) / -d[:, 2], max_range_m)
    step = np.minimum(
        MARCH_STEP_M / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9), np.maximum(end - start, 1e-9)
    )
    a, b = start.copy(), np.full(len(d), np.inf)
    ga, gb = np.zeros(len(d)), np.zeros(len(d))
    rows = np.flatnonzero(start <= end)
    if len(rows):
        ga[rows] = gap(a[rows], rows)
    # a ray starting under the water (a sensor below a crest) gets no water return
    rows = rows[ga[rows] > 0.0]
    while len(rows):  # march: the first sample at or under the surface closes the bracket [a, b]
        s = np.minimum(a[rows] + step[rows], end[rows])
        g = gap(s, rows)
        done = g <= 0.0
        b[rows[done]], gb[rows[done]] = s[done], g[done]
        a[rows[~done]], ga[rows[~done]] = s[~done], g[~done]
        rows = rows[~done & (s < end[rows])]
    return _refine(gap, a, b, ga, gb)


def _refine(gap, a, b, ga, gb) -> np.ndarray:
    """Illinois regula falsi on the brackets g(a) > 0 >= g(b) (b = +inf: no bracket): the root's distance."""
    out = np.where(np.isfinite(b), b, np.inf)
    rows = np.flatnonzero(np.isfinite(b) & (np.abs(gb) > SURFACE_TOL_M) & (b > a))
    side = np.zeros(len(a), np.int8)  # which end was kept last: halve its gap (Illinois)
    for _ in range(REFINE_STEPS):
        if not len(rows):
            break
        s = (a[rows] * gb[rows] - b[rows] * ga[rows]) / (gb[rows] - ga[rows])
        g = gap(s, rows)
        out[rows] = s
        above = g > 0.0
        ra, rb = rows[above], rows[~above]
        a[ra], ga[ra] = s[above], g[above]
        gb[ra] *= np.where(side[ra] == 1, 0.5, 1.0)
        side[ra] = 1
        b[rb], gb[rb] = s[~above], g[~above]
        ga[rb] *= np.where(side[rb] == -1, 0.5, 1.0)
        side[rb] = -1
        rows = rows[np.abs(g) > SURFACE_TOL_M]
    return out
