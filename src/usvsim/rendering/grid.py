"""The water grid: a projected grid, regular in screen space, laid onto the sea plane by the vertex shader.

Each vertex is a normalized device coordinate (x, y) of the view, on a grid of about `CELL_PX` pixels that
reaches `MARGIN` beyond the image on every side (displaced waves near the edges stay covered). The vertex
shader casts the pixel's ray onto the still-water plane; rays that miss it (above the horizon) land at
`FAR_M` along their compass direction, so the surface reaches the horizon from any height, with no edge and
no seam in view, and detail follows the pixels: fine at the bow, coarse at the horizon. Triangles are
ordered top of the image first (far to near): depth-clamped fragments beyond the far plane tie, and the
nearer, drawn later, wins.
"""

from __future__ import annotations

import math

import numpy as np

CELL_PX, MARGIN, FAR_M = 8.0, 0.25, 60_000.0


def screen_grid(width: int, height: int, cell_px: float = CELL_PX, margin: float = MARGIN):
    """(vertices (n, 2) float32 NDC, indices (m,) uint32, radians of view per cell along x per unit tan)."""
    cols = int(math.ceil(width * (1 + 2 * margin) / cell_px)) + 1
    rows = int(math.ceil(height * (1 + 2 * margin) / cell_px)) + 1
    x = np.linspace(-1 - 2 * margin, 1 + 2 * margin, cols)
    y = np.linspace(1 + 2 * margin, -1 - 2 * margin, rows)  # top row first
    gx, gy = np.meshgrid(x, y)
    vertices = np.stack([gx, gy], axis=-1).reshape(-1, 2).astype(np.float32)
    r = np.arange(rows - 1)[:, None] * cols
    c = np.arange(cols - 1)[None, :]
    a0, a1, b0, b1 = r + c, r + c + 1, r + cols + c, r + cols + c + 1
    quads = np.stack([a0, b0, a1, a1, b0, b1], axis=-1)
    return vertices, quads.reshape(-1).astype(np.uint32), 2.0 / (cols - 1) * (1 + 2 * margin)
