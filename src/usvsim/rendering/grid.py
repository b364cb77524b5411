"""The water grid: a projected grid, regular in screen space, laid onto the sea plane by the vertex shader.

Each vertex is a normalized device coordinate (x, y) of the view, on a grid of about `CELL_PX` pixels (the viewer: `view_cell_px`) that
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
VIEW_CELL_PX, VIEW_CELL_ROWS = 20.0, 480  # the viewer's cells: 20 px at 480 rows, in proportion to the height


def view_cell_px(height: int) -> float:
    """Grid cell size (pixels) for the viewer's pictures, `height` pixels tall: the angle of a 20-pixel cell at 480
    rows (30 px at 720), at least `CELL_PX`. llvmpipe shades 4 x 4 pixel blocks, so a triangle costs its area
    plus the blocks along its edges: 8-pixel cells shade about twice the water's pixels, 12-pixel cells 1.6 times
    (-22 % water time at 640 x 480, pictures within ~1 grey level on average). At 1280 x 720, 30-pixel cells
    instead of 18 cost 11 % less CPU per viewer frame (the window: 18.4 -> 20.4 fps); the pictures differ by
    about 3 grey levels on average, in the far glitter and the near crests' outlines (docs/rendering.md).
    Cameras keep `CELL_PX`: the coarser mesh sits farther from the physical surface (median vertical error of
    water depth points 10-50 m away in sea state 4: 3.2 cm with 8 px, 5.0 cm with 12 px)."""
    return max(CELL_PX, VIEW_CELL_PX * height / VIEW_CELL_ROWS)


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
