"""numba kernels of the ray caster: ray culling, frame changes and hit merging over one chunk of rays.

They run without the GIL (`nogil`), so the chunks cast on the thread pool (Embree also drops the GIL) use
every core, and they allocate nothing: callers pass the output arrays. `rows` selects input rays; with
`all_rows` the k-th output is ray k and `rows` is ignored.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def world_rays(dirs_sensor, origin, rot, origins_out, dirs_out):
    """Rays of a sensor at `origin` (world, m) with rotation `rot` (sensor → world): one common origin and
    dirs_out[k] = rot @ dirs_sensor[k]. Arrays (n, 3) float32; origin, rot float64."""
    for k in range(dirs_sensor.shape[0]):
        x, y, z = dirs_sensor[k, 0], dirs_sensor[k, 1], dirs_sensor[k, 2]
        for i in range(3):
            origins_out[k, i] = origin[i]
            dirs_out[k, i] = rot[i, 0] * x + rot[i, 1] * y + rot[i, 2] * z


@njit(cache=True, nogil=True)
def column_rays(dirs_sensor, column, origin_col, rot_col, origins_out, dirs_out):
    """Rays fired column by column (motion distortion): ray k from origin_col[c] (world, m) along
    rot_col[c] @ dirs_sensor[k], c = column[k]; rot_col (columns, 3, 3) sensor → world."""
    for k in range(dirs_sensor.shape[0]):
        c = column[k]
        x, y, z = dirs_sensor[k, 0], dirs_sensor[k, 1], dirs_sensor[k, 2]
        for i in range(3):
            origins_out[k, i] = origin_col[c, i]
            dirs_out[k, i] = rot_col[c, i, 0] * x + rot_col[c, i, 1] * y + rot_col[c, i, 2] * z


@njit(cache=True, nogil=True)
def sphere_masks(dirs, dist, to_center, min_proj_m, gap_m, masks_out, counts_out):
    """One pass for up to 32 bounding spheres: bit b of masks_out[k] is set when unit ray k meets sphere b (its
    projection on to_center[b] is >= min_proj_m[b]) and its nearest hit so far lies beyond gap_m[b] (the
    sphere's distance). counts_out[b] counts the rays of sphere b."""
    counts_out[:] = 0
    for k in range(dirs.shape[0]):
        mask = 0
        for b in range(to_center.shape[0]):
            if dist[k] > gap_m[b]:
                proj = dirs[k, 0] * to_center[b, 0] + dirs[k, 1] * to_center[b, 1] + dirs[k, 2] * to_center[b, 2]
                if proj >= min_proj_m[b]:
                    mask |= 1 << b
                    counts_out[b] += 1
        masks_out[k] = mask


@njit(cache=True, nogil=True)
def rows_of_bit(masks, bit, dist, rows_out, tfar_out):
    """Indices of the rays with `bit` set in masks, and their current distances; returns their count."""
    count = 0
    flag = 1 << bit
    for k in range(masks.shape[0]):
        if masks[k] & flag:
            rows_out[count] = k
            tfar_out[count] = dist[k]
            count += 1
    return count


@njit(cache=True, nogil=True)
def reachable_box(origins, dirs, dist, lo, hi, gap_m, rows_out, tfar_out):
    """Rays whose stretch between gap_m (nothing is nearer) and their nearest hit so far passes through the box
    [lo, hi] (world; slab test). Writes their indices and current distances; returns their count."""
    count = 0
    for k in range(dirs.shape[0]):
        if dist[k] <= gap_m:
            continue
        t_in, t_out = max(gap_m, 0.0), float(dist[k])
        for j in range(3):
            o, d = origins[k, j], dirs[k, j]
            if abs(d) < 1e-12:
                if o < lo[j] or o > hi[j]:
                    t_in = t_out + 1.0
                continue
            t0, t1 = (lo[j] - o) / d, (hi[j] - o) / d
            t_in, t_out = max(t_in, min(t0, t1)), min(t_out, max(t0, t1))
        if t_in <= t_out:
            rows_out[count] = k
            tfar_out[count] = dist[k]
            count += 1
    return count


@njit(cache=True, nogil=True)
def rays_to_body(origins, dirs, rows, all_rows, pos, rot, origins_out, dirs_out):
    """World rays into a body frame at (pos, rot body → world): o_b = rotᵀ (o - pos), d_b = rotᵀ d."""
    for k in range(origins_out.shape[0]):
        i = k if all_rows else rows[k]
        ox, oy, oz = origins[i, 0] - pos[0], origins[i, 1] - pos[1], origins[i, 2] - pos[2]
        dx, dy, dz = dirs[i, 0], dirs[i, 1], dirs[i, 2]
        for j in range(3):
            origins_out[k, j] = rot[0, j] * ox + rot[1, j] * oy + rot[2, j] * oz
            dirs_out[k, j] = rot[0, j] * dx + rot[1, j] * dy + rot[2, j] * dz


@njit(cache=True, nogil=True)
def gather_rows(origins, dirs, rows, origins_out, dirs_out):
    """origins_out[k], dirs_out[k] = origins[rows[k]], dirs[rows[k]]."""
    for k in range(rows.shape[0]):
        for j in range(3):
            origins_out[k, j] = origins[rows[k], j]
            dirs_out[k, j] = dirs[rows[k], j]


@njit(cache=True, nogil=True)
def merge_hits(rows, all_rows, geom_id, prim_id, tfar, normal, dirs, prim_geom, dist, geom, cos_inc):
    """Write Embree's hits (geom_id != -1: nearer than the tfar they started with) into the outputs: distance,
    MuJoCo geom of the triangle, |cos| of incidence (normal and dirs in one frame: the scene's)."""
    for k in range(geom_id.shape[0]):
        if geom_id[k] == -1:
            continue
        i = k if all_rows else rows[k]
        nx, ny, nz = normal[k, 0], normal[k, 1], normal[k, 2]
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        dot = nx * dirs[k, 0] + ny * dirs[k, 1] + nz * dirs[k, 2]
        dist[i] = tfar[k]
        geom[i] = prim_geom[prim_id[k]]
        cos_inc[i] = abs(dot) / norm if norm > 0.0 else 0.0


@njit(cache=True, nogil=True)
def max_offset(origins):
    """Largest distance (m) of any origin from the first one (0 when all rays share one origin)."""
    worst = 0.0
    for k in range(origins.shape[0]):
        dx, dy, dz = origins[k, 0] - origins[0, 0], origins[k, 1] - origins[0, 1], origins[k, 2] - origins[0, 2]
        worst = max(worst, dx * dx + dy * dy + dz * dz)
    return math.sqrt(worst)


NO_ROWS = np.zeros(0, np.int64)


@njit(cache=True, nogil=True)
def drop_invalid(dist, range_min_m, dropout_draws, dropout):
    """Set dist (m) to +inf below range_min_m and where dropout_draws[k] < dropout (draws used only when
    dropout > 0); returns how many returns are left."""
    count = 0
    for k in range(dist.shape[0]):
        if not dist[k] >= range_min_m or (dropout > 0.0 and dropout_draws[k] < dropout):
            dist[k] = np.inf
        else:
            count += 1
    return count


@njit(cache=True, nogil=True)
def noisy_returns(dist, geom, cos_inc, noise, stddev_m, reflectivity, intensity_out):
    """Add noise[j]·stddev_m to the j-th finite range (no noise when `noise` is empty) and write intensity
    = reflectivity[geom] · |cos incidence| there, 0 elsewhere."""
    j = 0
    for k in range(dist.shape[0]):
        if np.isfinite(dist[k]):
            if noise.shape[0] > 0:
                dist[k] += noise[j] * stddev_m
            intensity_out[k] = reflectivity[geom[k]] * cos_inc[k]
            j += 1
        else:
            intensity_out[k] = 0.0


@njit(cache=True, nogil=True)
def pack_points(dirs_sensor, dist, intensity, ring, times, organized, words_out, halves_out):
    """PointCloud2 points (x, y, z, intensity, ring, pad, time; 24 bytes) into the float32 (n, 6) and uint16
    (n, 12) views of one buffer: every beam (NaN for no return) when organized, else the returns only."""
    j = 0
    for k in range(dist.shape[0]):
        finite = np.isfinite(dist[k])
        if not (finite or organized):
            continue
        r = dist[k] if finite else np.nan
        for i in range(3):
            words_out[j, i] = dirs_sensor[k, i] * r
        words_out[j, 3] = intensity[k]
        halves_out[j, 8] = ring[k]
        halves_out[j, 9] = 0
        words_out[j, 5] = times[k]
        j += 1
