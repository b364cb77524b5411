"""GeoTIFF rasters (rasterio) sampled at world ENU points: bilinear within a cell of the raster's own grid.

A sample at a pixel centre returns that pixel's value exactly; between centres it is the bilinear blend of
the four surrounding pixels (pixels are areas, their values sit at their centres, as GDAL's bilinear
resampling assumes); in the outer half of an edge pixel it is the edge's value (the pixel covers it: that
band was NaN, the default depth, 225 m wide along a GEBCO raster's edge and over the pole). Outside the
raster or on no-data pixels the value is NaN; callers pick a default.
ENU → raster pixel goes through the exact CRS transform; for dense grids the pixel coordinates are
computed exactly on a lattice every `LATTICE` points and interpolated between (the map is smooth: the
error is far below a millimetre over a 10 km scene).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from usvsim.geo.frame import GeoError, GeoFrame, parse_crs, require, same_crs

LATTICE = 32


@dataclass(frozen=True)
class Raster:
    """One band (float64, NaN for no data) and the map ENU (x, y) → fractional pixel (col, row)."""

    values: np.ndarray
    enu_to_pixel: Callable[[np.ndarray, np.ndarray], tuple[Any, Any]]  # (x, y) → (col, row), pixel centres at integers
    source: str

    def sample(self, x_m, y_m) -> np.ndarray:
        """Bilinear values at ENU points (NaN outside or next to no data)."""
        x = np.atleast_1d(np.asarray(x_m, float))
        col, row = self.enu_to_pixel(x.ravel(), np.broadcast_to(np.asarray(y_m, float), x.shape).ravel())
        return _bilinear(self.values, np.asarray(col, float), np.asarray(row, float)).reshape(x.shape)

    def sample_grid(self, xs_m: np.ndarray, ys_m: np.ndarray) -> np.ndarray:
        """Values (len(ys), len(xs)) on a regular ENU grid, through a lattice of exact transforms."""
        ix = np.unique(np.r_[np.arange(0, len(xs_m), LATTICE), len(xs_m) - 1])
        iy = np.unique(np.r_[np.arange(0, len(ys_m), LATTICE), len(ys_m) - 1])
        gx, gy = np.meshgrid(xs_m[ix], ys_m[iy])
        col, row = (np.asarray(a, float).reshape(gx.shape) for a in self.enu_to_pixel(gx.ravel(), gy.ravel()))
        cols, rows = _refine(col, ix, iy, len(xs_m), len(ys_m)), _refine(row, ix, iy, len(xs_m), len(ys_m))
        return _bilinear(self.values, cols.ravel(), rows.ravel()).reshape(len(ys_m), len(xs_m))


def _refine(coarse: np.ndarray, ix: np.ndarray, iy: np.ndarray, nx: int, ny: int) -> np.ndarray:
    """Bilinear interpolation of a lattice (len(iy), len(ix)) to the full (ny, nx) index grid."""
    along_x = np.stack([np.interp(np.arange(nx), ix, r) for r in coarse])
    return np.stack([np.interp(np.arange(ny), iy, c) for c in along_x.T]).T


@njit(cache=True)
def _bilinear(values, col, row):
    h, w = values.shape
    out = np.empty(len(col))
    for i in range(len(col)):
        c, r = col[i], row[i]
        if not (c >= -0.5 and r >= -0.5 and c <= w - 0.5 and r <= h - 0.5):  # off the raster's outer edge
            out[i] = np.nan
            continue
        c, r = min(max(c, 0.0), w - 1.0), min(max(r, 0.0), h - 1.0)  # the outer half pixel: the edge pixels' value
        c0, r0 = min(int(c), w - 2) if w > 1 else 0, min(int(r), h - 2) if h > 1 else 0
        fc, fr = c - c0, r - r0
        c1, r1 = min(c0 + 1, w - 1), min(r0 + 1, h - 1)
        top = values[r0, c0] * (1.0 - fc) + values[r0, c1] * fc
        bottom = values[r1, c0] * (1.0 - fc) + values[r1, c1] * fc
        out[i] = top * (1.0 - fr) + bottom * fr
    return out


def read_raster(path: Path, band: int, crs: str | None, frame: GeoFrame, extent_m: float) -> Raster:
    """Read one band of a GeoTIFF; checks CRS, band and that the raster overlaps the scene's extent."""
    rasterio = require("rasterio")
    from pyproj import Transformer

    if not path.is_file():
        raise GeoError(f"{path}: no such file")
    try:
        with rasterio.open(path) as ds:
            if band > ds.count:
                raise GeoError(f"{path}: has {ds.count} band(s), band {band} asked for")
            data = ds.read(band, masked=True).astype(float).filled(np.nan)
            file_crs, transform = ds.crs, ds.transform
    except GeoError:
        raise
    except Exception as exc:  # rasterio raises its own errors for every unreadable file
        raise GeoError(f"{path}: not a raster rasterio can read ({str(exc).splitlines()[0][:120]})") from None
    if file_crs and crs and not same_crs(file_crs, crs, str(path)):
        raise GeoError(f"{path}: the raster's CRS is {file_crs} but the scenario says crs: {crs}; drop one")
    if not (file_crs or crs):
        raise GeoError(f"{path}: the raster has no CRS; give one with `crs:` (e.g. EPSG:4326)")
    raster_crs = parse_crs(file_crs, str(path)) if file_crs else parse_crs(crs, f"{path}: crs")
    to_crs = Transformer.from_crs("EPSG:4326", raster_crs, always_xy=True)
    inverse = ~transform
    h, w = data.shape
    # a raster across ±180° (GEBCO cut at 179.9..180.1, data in 0..360) holds longitudes past 180: PROJ's
    # -179.99 must read its column at 180.01, or the east half was NaN and the seabed the default depth (QA)
    mid_lon = (transform * (w / 2, h / 2))[0] if raster_crs.is_geographic else None

    def enu_to_pixel(x, y):
        geo = frame.level_to_geodetic(x, y)
        px, py = to_crs.transform(geo[:, 1], geo[:, 0])
        if mid_lon is not None:
            px = (np.asarray(px) - mid_lon + 180.0) % 360.0 - 180.0 + mid_lon
        col, row = inverse @ (np.asarray(px), np.asarray(py))
        return np.asarray(col) - 0.5, np.asarray(row) - 0.5  # pixel centres at integers

    cx, cy = transform @ (np.array([0.0, w, 0.0, w]), np.array([0.0, 0.0, h, h]))
    lon, lat = Transformer.from_crs(raster_crs, "EPSG:4326", always_xy=True).transform(cx, cy)
    corners = frame.to_enu(lat, lon)
    lo, hi = corners[:, :2].min(axis=0), corners[:, :2].max(axis=0)
    if not (np.all(np.isfinite(corners)) and np.all(lo < extent_m) and np.all(hi > -extent_m)):
        raise GeoError(f"{path}: the raster does not cover the scene ({extent_m:g} m around the origin); "
                       "wrong CRS, origin or file?")  # fmt: skip
    return Raster(data, enu_to_pixel, str(path))
