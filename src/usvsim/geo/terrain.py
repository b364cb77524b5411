"""The ground under and around the water as MuJoCo height-field tiles: seabed from bathymetry, land raised.

One elevation grid z (m, up) covers the scene with vertices every `cell_m`: water vertices take the seabed
(bathymetry, else the default depth; never shallower than `min_depth_m`), land vertices the land height.
MuJoCo joins the vertices with planar triangles, so the collision coastline lies within one cell of the
drawn one (structures are exact convex pieces instead). The grid is cut into square tiles of `TILE` cells:
each tile is its own geom with a tight bounding box, so the broadphase pairs a floating hull only with the
few tiles around it that reach up to its keel (a 10 km² scene adds a few µs to a step).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TILE = 128  # cells per tile side
BASE_M = 1.0  # thickness of each tile's solid base below its lowest point


@dataclass(frozen=True)
class HeightTile:
    """A height field: `z` (rows along +y, columns along +x) in metres, centred at `center` (ENU)."""

    name: str
    z: np.ndarray
    center: tuple[float, float]
    half_size: tuple[float, float]


@dataclass(frozen=True)
class Terrain:
    """The elevation grid (ny, nx) with vertex coordinates `xs`, `ys` (ENU m) and its tiles."""

    xs: np.ndarray
    ys: np.ndarray
    z: np.ndarray

    def tiles(self, tile: int = TILE) -> list[HeightTile]:
        out = []
        ny, nx = self.z.shape
        for r in range(0, ny - 1, tile):
            for c in range(0, nx - 1, tile):
                block = self.z[r : min(r + tile, ny - 1) + 1, c : min(c + tile, nx - 1) + 1]
                x0, x1 = self.xs[c], self.xs[c + block.shape[1] - 1]
                y0, y1 = self.ys[r], self.ys[r + block.shape[0] - 1]
                out.append(HeightTile(f"terrain_{r // tile}_{c // tile}", np.ascontiguousarray(block),
                                      ((x0 + x1) / 2, (y0 + y1) / 2), ((x1 - x0) / 2, (y1 - y0) / 2)))  # fmt: skip
        return out

    def coarse(self, max_vertices: int) -> HeightTile:
        """One tile of the whole grid, subsampled to at most `max_vertices` per side (for drawing)."""
        step = max(1, int(np.ceil((len(self.xs) - 1) / (max_vertices - 1))))
        z = self.z[::step, ::step]
        xs, ys = self.xs[::step], self.ys[::step]
        return HeightTile("seabed", np.ascontiguousarray(z), ((xs[0] + xs[-1]) / 2, (ys[0] + ys[-1]) / 2),
                          ((xs[-1] - xs[0]) / 2, (ys[-1] - ys[0]) / 2))  # fmt: skip


def vertex_grid(extent_m: float, cell_m: float) -> np.ndarray:
    """Vertex coordinates from -extent to +extent (m) every cell (the last step may be shorter: none is)."""
    n = int(np.ceil(2 * extent_m / cell_m))
    return np.linspace(-extent_m, extent_m, n + 1)


def land_mask(polygons: list, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """True at grid vertices inside any polygon (rows along y)."""
    if not polygons:
        return np.zeros((len(ys), len(xs)), bool)
    from rasterio import features
    from rasterio.transform import Affine

    dx, dy = xs[1] - xs[0], ys[1] - ys[0]
    transform = Affine(dx, 0.0, xs[0] - dx / 2, 0.0, dy, ys[0] - dy / 2)  # pixel (c, r) centred on vertex
    mask = features.rasterize(((p, 1) for p in polygons), out_shape=(len(ys), len(xs)), transform=transform,
                              fill=0, dtype="uint8")  # fmt: skip
    assert mask is not None  # rasterio's stub: None only when writing into a given `out`
    return mask.astype(bool)
