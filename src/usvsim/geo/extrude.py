"""Polygons (ENU m) → closed prism meshes with vertical walls exactly on the polygon's rings, and convex
pieces of a footprint for exact collision.

The top is flat at a constant height, or follows a height function (a DEM) on a grid of `cell_m`; the
bottom is flat at `bottom_z`. Triangles wind counter-clockwise seen from outside (outward normals).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely

from usvsim.vessels.parts import Mesh

Heights = Callable[[np.ndarray, np.ndarray], np.ndarray]  # (x, y) → top z (m)


def _triangles(polygon) -> np.ndarray:
    """(n, 3, 2) triangles covering the polygon (constrained Delaunay), counter-clockwise."""
    tris = shapely.constrained_delaunay_triangles(polygon)
    coords = shapely.get_coordinates(shapely.get_exterior_ring(np.asarray(tris.geoms)))
    tri = coords.reshape(-1, 4, 2)[:, :3]
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    tri[cw] = tri[cw][:, ::-1]
    return tri


def _top(polygon, heights: Heights | None, top_z: float, cell_m: float) -> np.ndarray:
    """Top triangles (n, 3, 3); under a height function the polygon is cut into grid cells first."""
    if heights is None:
        tri = _triangles(polygon)
        return np.concatenate([tri, np.full(tri.shape[:2] + (1,), top_z)], axis=2)
    pieces = [p for block in _blocks(polygon, cell_m) for p in _cells(block, cell_m)]
    tri = np.concatenate([_triangles(p) for p in pieces]) if pieces else np.zeros((0, 3, 2))
    z = heights(tri[..., 0].ravel(), tri[..., 1].ravel()).reshape(tri.shape[:2] + (1,))
    return np.concatenate([tri, z], axis=2)


def _blocks(polygon, cell_m: float, cells_per_block: int = 16) -> list:
    """The polygon clipped to square blocks of cells (each piece has few vertices, so cutting it is cheap)."""
    x0, y0, x1, y1 = polygon.bounds
    size = cell_m * cells_per_block
    return [b for bx in np.arange(x0, x1, size) for by in np.arange(y0, y1, size)
            if not (b := shapely.clip_by_rect(polygon, bx, by, bx + size, by + size)).is_empty]  # fmt: skip


def _cells(block, cell_m: float) -> list:
    """The block cut into grid cells (cells wholly inside are kept as squares)."""
    x0, y0, x1, y1 = block.bounds
    gx, gy = np.meshgrid(np.arange(x0, x1, cell_m), np.arange(y0, y1, cell_m))
    cells = shapely.box(gx.ravel(), gy.ravel(), gx.ravel() + cell_m, gy.ravel() + cell_m)
    shapely.prepare(block)
    inside = shapely.contains_properly(block, cells)
    cut = shapely.intersection(block, cells[~inside])
    return list(cells[inside]) + [p for g in cut for p in _polygons(g)]


def _polygons(geom) -> list:
    if geom.is_empty:
        return []
    if hasattr(geom, "geoms"):
        return [p for g in geom.geoms for p in _polygons(g)]
    return [geom] if geom.geom_type == "Polygon" else []


def _walls(polygon, heights: Heights | None, top_z: float, bottom_z: float) -> np.ndarray:
    """Wall quads (as triangles) along every ring; outward normals for an oriented polygon."""
    out = []
    for ring in [polygon.exterior, *polygon.interiors]:
        xy = np.asarray(ring.coords)[:, :2]
        a, b = xy[:-1], xy[1:]
        za = np.full(len(a), top_z) if heights is None else heights(a[:, 0], a[:, 1])
        zb = np.full(len(b), top_z) if heights is None else heights(b[:, 0], b[:, 1])
        ab, bb = np.column_stack([a, np.full(len(a), bottom_z)]), np.column_stack([b, np.full(len(b), bottom_z)])
        at, bt = np.column_stack([a, za]), np.column_stack([b, zb])
        out += [np.stack([ab, bb, bt], axis=1), np.stack([ab, bt, at], axis=1)]
    return np.concatenate(out)


def prism(polygon, bottom_z: float, top_z: float = 0.0, heights: Heights | None = None,
          cell_m: float = 25.0) -> np.ndarray:  # fmt: skip
    """Triangles (n, 3, 3) of a closed prism over `polygon` from `bottom_z` to the top (m)."""
    polygon = shapely.orient_polygons(polygon)
    if heights is not None:
        polygon = shapely.segmentize(polygon, cell_m)
    top = _top(polygon, heights, top_z, cell_m)
    bottom = top[:, ::-1].copy()
    bottom[..., 2] = bottom_z
    return np.concatenate([top, bottom, _walls(polygon, heights, top_z, bottom_z)])


def to_mesh(triangles: np.ndarray) -> Mesh:
    """A Mesh with merged vertices from triangle soup (n, 3, 3)."""
    verts, inverse = np.unique(triangles.reshape(-1, 3).round(6), axis=0, return_inverse=True)
    faces = inverse.reshape(-1, 3)
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return Mesh(verts, faces[keep])


def convex_footprints(polygon) -> list:
    """Convex polygons whose union is `polygon`: triangles merged greedily while the union stays convex
    (Hertel–Mehlhorn style; at most four times the optimal count)."""
    pieces = [shapely.Polygon(t) for t in _triangles(shapely.orient_polygons(polygon))]
    merged = True
    while merged and len(pieces) > 1:
        merged = False
        tree = shapely.STRtree(pieces)
        work: list[shapely.Polygon | None] = list(pieces)  # merged pieces become None
        for i, p in enumerate(work):
            for j in tree.query(p, predicate="touches"):
                other = work[j]
                if j == i or other is None or p is None:
                    continue
                union = shapely.union(p, other)
                if union.geom_type == "Polygon" and abs(union.convex_hull.area - union.area) < 1e-9 * max(union.area, 1):
                    work[i], work[j], p = union, None, union
                    merged = True
        pieces = [p for p in work if p is not None]
    return [shapely.normalize(shapely.simplify(p, 0.0)) for p in pieces]
