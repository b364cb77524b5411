"""The ocean as GPU textures: FFT tiles as they are (periodic, infinite), any other wave field as a patch.

Per band two RGBA float layers: geometry (h, Dx, Dy, ∂Dx/∂y) and slopes (∂h/∂x, ∂h/∂y, ∂Dx/∂x, ∂Dy/∂y), with
mipmaps so that distant water is filtered instead of aliased. FFT tiles come straight from the field the
physics queries (`FFTWaveField.tiles`), so the drawn surface is the physical one. Other fields (direct sums,
regular waves) are sampled on a patch around the camera with `Ocean.render_grid` and fade to flat outside it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

PATCH_POINTS, PATCH_SIZE_M = 128, 256.0


@dataclass
class SurfaceData:
    geo: np.ndarray  # (bands, N, N, 4) float32
    slope: np.ndarray  # (bands, N, N, 4) float32
    tiles_m: tuple[float, ...]  # tile side per band (patch: the patch side)
    height_scale: float  # s (start-up ramp)
    displacement_scale: float  # k = s · choppiness
    level_m: float
    patch: tuple[float, float, float]  # centre x, y, half side; half side 0 = periodic tiles
    key: tuple  # what the data depends on (the wave field itself, time, ...): equal keys → no upload
    detail: int = 0  # 1: the last layer is the unresolved short waves (rendering/detail.py), slopes only
    whitecap_slope: float = float("inf")  # resolved slope above which the surface breaks (rendering/detail.py)


def surface_data(ocean, t: float, center_xy, detail=None, whitecap_slope: float = float("inf")) -> SurfaceData:
    """Textures of the ocean's surface at time `t` (s); `center_xy` (world ENU, m) centres a patch. `detail`: a
    `DetailBand` of the same FFT field, appended as the last layer; `whitecap_slope`: see `SurfaceData`."""
    waves = ocean.waves
    if waves is None:
        flat = np.zeros((1, 8, 8, 4), np.float32)
        return SurfaceData(
            flat, flat, (8.0,), 0.0, 0.0, ocean.level_m, (0.0, 0.0, 0.0), ("flat", ocean.level_m)
        )
    if hasattr(waves, "tiles"):
        tiles = waves.tiles(t)  # (bands, 4, N, N): h, Dx, Dy, w
        sizes = tuple(float(s) for s in waves.sizes)
        s = waves.ramp(t)
        geo, slope = _periodic_layers(np.ascontiguousarray(tiles), tiles.shape[-1] / np.array(sizes))
        if detail is not None and detail.n == geo.shape[1]:
            extra = np.zeros((1, *geo.shape[1:]), np.float32)
            geo, sl = np.concatenate([geo, extra]), np.concatenate([slope, extra])
            sl[-1, ..., :2] = detail.slopes(t)
            slope, sizes = sl, sizes + (detail.size_m,)
        else:
            detail = None
        return SurfaceData(geo, slope, sizes, s, s * waves.choppiness, ocean.level_m, (0.0, 0.0, 0.0),
                           ("fft", waves, t, detail is not None), int(detail is not None), whitecap_slope)  # fmt: skip
    return _patch(ocean, t, center_xy)


def _patch(ocean, t: float, center_xy) -> SurfaceData:
    step = PATCH_SIZE_M / (PATCH_POINTS - 1)
    cx, cy = (float(np.round(c / step) * step) for c in center_xy[:2])
    axis = np.linspace(-0.5 * PATCH_SIZE_M, 0.5 * PATCH_SIZE_M, PATCH_POINTS)
    gx, gy = np.meshgrid(cx + axis, cy + axis)
    grid = ocean.render_grid((cx, cy), PATCH_SIZE_M, PATCH_POINTS, t)
    h, dx, dy = grid[..., 2] - ocean.level_m, gx - grid[..., 0], gy - grid[..., 1]  # X = x0 - D
    geo, slope = _layers(h[None], dx[None], dy[None], np.array([step]))
    size = PATCH_SIZE_M + step  # texel centres sit on the grid points
    from usvsim.rendering.detail import principal, whitecap_threshold

    sx, sy = slope[0, ..., 0].astype(np.float64), slope[0, ..., 1].astype(np.float64)
    cov = ((np.mean(sx * sx), np.mean(sx * sy)), (np.mean(sx * sy), np.mean(sy * sy)))
    whitecap = whitecap_threshold(4.0 * float(h.std()), principal(np.array(cov)))
    return SurfaceData(geo, slope, (size,), 1.0, 1.0, ocean.level_m, (cx, cy, 0.5 * size), ("patch", ocean.waves, t, cx, cy),
                       0, whitecap)  # fmt: skip


def _layers(h, dx, dy, cell_m) -> tuple[np.ndarray, np.ndarray]:
    """(bands, N, N) fields [iy, ix] of a patch → geometry and slope layers (bands, N, N, 4) float32."""
    inv = (1.0 / cell_m)[:, None, None]
    d_dx = _diff(dx, 2) * inv, _diff(dx, 1) * inv
    geo = np.stack([h, dx, dy, d_dx[1]], axis=-1).astype(np.float32)
    slope = np.stack([_diff(h, 2) * inv, _diff(h, 1) * inv, d_dx[0], _diff(dy, 1) * inv], axis=-1).astype(np.float32)  # fmt: skip
    return geo, slope


@njit(cache=True, nogil=True)
def _periodic_layers(tiles, inv_cell):
    """`_layers` of periodic tiles (bands, 4, N, N) [h, Dx, Dy, w; iy, ix] with central differences, in one pass."""
    bands, n = tiles.shape[0], tiles.shape[2]
    geo, slope = np.empty((bands, n, n, 4), np.float32), np.empty((bands, n, n, 4), np.float32)
    for b in range(bands):
        k = 0.5 * inv_cell[b]
        for iy in range(n):
            up, down = (iy + 1) % n, (iy - 1) % n
            for ix in range(n):
                right, left = (ix + 1) % n, (ix - 1) % n
                geo[b, iy, ix, 0] = tiles[b, 0, iy, ix]
                geo[b, iy, ix, 1] = tiles[b, 1, iy, ix]
                geo[b, iy, ix, 2] = tiles[b, 2, iy, ix]
                geo[b, iy, ix, 3] = k * (tiles[b, 1, up, ix] - tiles[b, 1, down, ix])
                slope[b, iy, ix, 0] = k * (tiles[b, 0, iy, right] - tiles[b, 0, iy, left])
                slope[b, iy, ix, 1] = k * (tiles[b, 0, up, ix] - tiles[b, 0, down, ix])
                slope[b, iy, ix, 2] = k * (tiles[b, 1, iy, right] - tiles[b, 1, iy, left])
                slope[b, iy, ix, 3] = k * (tiles[b, 2, up, ix] - tiles[b, 2, down, ix])
    return geo, slope


def _diff(f: np.ndarray, axis: int) -> np.ndarray:
    """Central difference in cells along `axis` (one-sided at the edges)."""
    return np.gradient(f, axis=axis)
