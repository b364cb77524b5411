"""Voxelization of closed triangle meshes (any shape: non-convex, several components), with a disk cache.

Inside test: the winding number along a vertical ray (+z) from each voxel centre, counted column by
column: every non-vertical triangle whose xy-projection covers the column adds +1 (faces up) or -1
(faces down) to every centre below its crossing height. A point is inside where the sum is nonzero
(nonzero rule, so overlapping components count once). Points on a shared edge are assigned to
exactly one of the two triangles by evaluating the edge function in a canonical vertex order with a
tie rule, so rays through edges and vertices (common for boxes on an aligned grid) are exact.

Grid: cell centres at c + k·s (c = centre of the mesh bounds), the seed's alignment, so results
converge as s shrinks (R = 0.5 m icosphere: 486, 4140, 33372 centre-inside cells at s = 0.1, 0.05,
0.025; the seed's Unity sphere gave 512, 4154, 33378). Centre sampling (supersample q = 1, the
seed's method) has a volume error of order s × surface (1-7 % here); q = 4 samples 64 points per
cell and keeps each cell's inside fraction and centroid (volume within 0.6 % at 10+ cells across).
Cache: `$USVSIM_CACHE/voxels/<sha256>.npz` (default `~/.cache/usvsim`), key = sha256 of the
vertex (float64) and face (int64) bytes, the voxel size and the format version.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

FORMAT_VERSION = b"usvsim-voxels-1"


@dataclass(frozen=True)
class VoxelGrid:
    """Voxels of a mesh in its (body) frame: `centers` (n,3) m (centroid of each cell's inside part;
    the cell centre when supersample = 1), `fill` (n,) inside fraction, edge `size` m, the mesh's
    volume m³, the supersampling q and the cache key."""

    centers: np.ndarray
    fill: np.ndarray
    size: float
    mesh_volume: float
    supersample: int
    key: str

    @property
    def volume(self) -> float:
        """Σ fill · size³ (m³)."""
        return float(self.fill.sum() * self.size**3)


@njit(cache=True)
def _edge(ux, uy, vx, vy, px, py):
    """Edge function of p against u→v, evaluated in a canonical order (bitwise antisymmetric) and
    the tie owner: returns (value, owner) with owner = +1 if (u, v) is in canonical order."""
    if ux < vx or (ux == vx and uy < vy):
        return (vx - ux) * (py - uy) - (vy - uy) * (px - ux), 1.0
    return -((ux - vx) * (py - vy) - (uy - vy) * (px - vx)), -1.0


@njit(cache=True)
def _covers(e, owner, sigma):
    """Point counts for this edge: strictly inside, or on it and this triangle owns the tie."""
    v = e * sigma
    return v > 0.0 or (v == 0.0 and owner * sigma > 0.0)


@njit(cache=True)
def _accumulate(tri, x0, y0, z0, s, nx, ny, nz, acc):
    """acc[i, j, k] += ±1 for every crossing of column (i, j) above the first k centres."""
    for f in range(tri.shape[0]):
        ax, ay, az = tri[f, 0, 0], tri[f, 0, 1], tri[f, 0, 2]
        bx, by, bz = tri[f, 1, 0], tri[f, 1, 1], tri[f, 1, 2]
        cx, cy, cz = tri[f, 2, 0], tri[f, 2, 1], tri[f, 2, 2]
        d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if d == 0.0:
            continue  # vertical: parallel to the ray
        sigma = 1.0 if d > 0.0 else -1.0
        # column range of the xy bounds, one wider each side: the exact test below decides
        i0 = max(int(np.ceil((min(ax, bx, cx) - x0) / s)) - 1, 0)
        i1 = min(int(np.floor((max(ax, bx, cx) - x0) / s)) + 1, nx - 1)
        j0 = max(int(np.ceil((min(ay, by, cy) - y0) / s)) - 1, 0)
        j1 = min(int(np.floor((max(ay, by, cy) - y0) / s)) + 1, ny - 1)
        for i in range(i0, i1 + 1):
            px = x0 + i * s
            for j in range(j0, j1 + 1):
                py = y0 + j * s
                e0, o0 = _edge(bx, by, cx, cy, px, py)
                e1, o1 = _edge(cx, cy, ax, ay, px, py)
                e2, o2 = _edge(ax, ay, bx, by, px, py)
                if not (_covers(e0, o0, sigma) and _covers(e1, o1, sigma) and _covers(e2, o2, sigma)):
                    continue
                z = (e0 * az + e1 * bz + e2 * cz) / d  # barycentric weights e_k / d
                k = int(np.ceil((z - z0) / s))
                acc[i, j, min(max(k, 0), nz)] += int(sigma)


def _winding_grid(v: np.ndarray, faces: np.ndarray, origin: np.ndarray, s: float, n) -> np.ndarray:
    """Winding number (nx,ny,nz) int32 at the grid points origin + (i, j, k)·s."""
    nx, ny, nz = (int(a) for a in n)
    acc = np.zeros((nx, ny, nz + 1), dtype=np.int32)
    tri = np.ascontiguousarray(v[np.asarray(faces, dtype=np.int64)])
    _accumulate(tri, origin[0], origin[1], origin[2], float(s), nx, ny, nz, acc)
    return np.cumsum(acc[:, :, ::-1], axis=2)[:, :, ::-1][:, :, 1:]  # sum over crossings above k


MAX_CELLS = 2_000_000  # grid cells over the hull's bounds: ~2.7 GB while voxelizing at supersample 4 (1.6 M: 2.2 GB)


def grid_shape(vertices: np.ndarray, size: float) -> np.ndarray:
    """Cells (nx, ny, nz) of edge `size` covering the bounds of `vertices` (the grid `voxel_grid` builds)."""
    v = np.asarray(vertices, dtype=np.float64)
    return 2 * np.floor(0.5 * (v.max(axis=0) - v.min(axis=0)) / size + 0.5).astype(np.int64) + 1


def check_grid(vertices: np.ndarray, size: float) -> None:
    """A ValueError naming the cell count when `size` is too fine for the hull (more than MAX_CELLS cells)."""
    cells = float(np.prod(grid_shape(vertices, size).astype(float)))
    if cells > MAX_CELLS:
        extent = np.ptp(np.asarray(vertices, dtype=np.float64), axis=0)
        raise ValueError(f"voxel_size_m {size:g} m gives {cells:.3g} cells over the {extent[0]:.3g} x {extent[1]:.3g} x "
                         f"{extent[2]:.3g} m hull, more than {MAX_CELLS:,}; use a larger voxel_size_m")  # fmt: skip


def voxel_grid(vertices: np.ndarray, faces: np.ndarray, size: float, supersample: int = 1):
    """Cells (edge `size`, m) of the grid that hold part of the closed mesh.

    supersample q = 1: a cell counts, full, if its centre is inside (the seed's method). q > 1: the
    inside test runs on q³ points per cell; returns each cell's filled fraction and the centroid of
    its inside points. Returns (centroids (n,3) m, fill (n,) in (0, 1]).
    """
    check_grid(vertices, size)
    v = np.asarray(vertices, dtype=np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    n_half = np.floor(half / size + 0.5).astype(int)  # cells cover the bounds
    n, q = 2 * n_half + 1, int(supersample)
    fine = size / q
    origin = center - n_half * size - 0.5 * (q - 1) * fine
    inside = _winding_grid(v, faces, origin, fine, n * q) != 0
    blocks = inside.reshape(n[0], q, n[1], q, n[2], q)
    count = blocks.sum(axis=(1, 3, 5))
    idx = np.argwhere(count > 0)
    sel = count[idx[:, 0], idx[:, 1], idx[:, 2]].astype(float)
    offs = (np.arange(q) - 0.5 * (q - 1)) * fine
    i, j, k = idx[:, 0], idx[:, 1], idx[:, 2]
    per_x = blocks.sum(axis=(3, 5))[i, :, j, k]  # (n, q) inside points per fine x layer
    per_y = blocks.sum(axis=(1, 5))[i, j, :, k]
    per_z = blocks.sum(axis=(1, 3))[i, j, k, :]
    mean = np.stack([(p * offs).sum(axis=1) for p in (per_x, per_y, per_z)], axis=1) / sel[:, None]
    centers = center - n_half * size + idx * size + mean
    return centers, sel / q**3


def voxel_centers(vertices: np.ndarray, faces: np.ndarray, size: float) -> np.ndarray:
    """Centres (n,3) of the grid cells whose centre lies inside the closed mesh (q = 1)."""
    return voxel_grid(vertices, faces, size, 1)[0]


def mesh_key(vertices: np.ndarray, faces: np.ndarray, size: float, supersample: int = 1) -> str:
    h = hashlib.sha256(FORMAT_VERSION)
    h.update(np.ascontiguousarray(vertices, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(faces, dtype=np.int64).tobytes())
    h.update(f"{float(size)!r}/{int(supersample)}".encode())
    return h.hexdigest()


def cache_dir() -> Path:
    return Path(os.environ.get("USVSIM_CACHE", Path.home() / ".cache" / "usvsim")) / "voxels"


def voxelize(vertices: np.ndarray, faces: np.ndarray, size: float, supersample: int = 4,
             use_cache: bool = True) -> VoxelGrid:
    """Voxel grid of a closed mesh (body frame, m), read from or written to the cache."""
    key = mesh_key(vertices, faces, size, supersample)
    path = cache_dir() / f"{key}.npz"
    if use_cache and path.is_file():
        with np.load(path) as d:
            return VoxelGrid(d["centers"], d["fill"], float(d["size"]), float(d["mesh_volume"]), supersample, key)
    centers, fill = voxel_grid(vertices, faces, size, supersample)
    a, b, c = (np.asarray(vertices, float)[np.asarray(faces)[:, k]] for k in range(3))
    volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    grid = VoxelGrid(centers, fill, float(size), volume, int(supersample), key)
    if use_cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".npz", delete=False) as tmp:
            np.savez(tmp, centers=centers, fill=fill, size=size, mesh_volume=volume)
        os.replace(tmp.name, path)
    return grid
