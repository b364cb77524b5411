"""Overlay layers the viewer draws on top of the 3D scene: a point cloud and an image inset.

Sensors feed them later (LiDAR points in the world frame, a camera image); today they take any (n, 3)
float array of world ENU points and any (h, w, 3) uint8 image.
"""

from __future__ import annotations

import mujoco
import numpy as np

MAX_POINTS = 2000  # drawn as small cubes; larger clouds are subsampled evenly
POINT_SIZE_M = 0.06
_LOW, _HIGH = np.array([0.1, 0.9, 1.0]), np.array([1.0, 0.25, 0.6])  # colour by height: cyan → magenta


def point_colors(points: np.ndarray, alpha: float = 1.0) -> np.ndarray:
    """RGBA (n, 4) by height: the lowest point cyan, the highest magenta."""
    z = points[:, 2]
    span = max(float(np.ptp(z)), 1e-6) if len(z) else 1.0
    f = ((z - (z.min() if len(z) else 0.0)) / span)[:, None]
    rgb = (1.0 - f) * _LOW + f * _HIGH
    return np.hstack([rgb, np.full((len(points), 1), alpha)]).astype(np.float32)


def add_points(
    scene: mujoco.MjvScene, points, rgba=None, size_m: float = POINT_SIZE_M, max_points: int = MAX_POINTS
) -> int:
    """Append points (n, 3), world ENU m, to a scene as small cubes (NaN rows skipped); returns the count drawn.
    `rgba`: one colour (4,) or per point (n, 4); default colours by height."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    keep = np.isfinite(pts).all(axis=1)
    colors = (
        point_colors(pts[keep])
        if rgba is None
        else np.broadcast_to(np.asarray(rgba, np.float32), (len(pts), 4))[keep]
    )
    pts = pts[keep]
    room = min(max_points, scene.maxgeom - scene.ngeom)
    if len(pts) > room > 0:
        pick = np.linspace(0, len(pts) - 1, room).astype(int)
        pts, colors = pts[pick], colors[pick]
    elif room <= 0:
        return 0
    size, mat = np.full(3, 0.5 * size_m), np.eye(3).ravel()
    geoms, start = scene.geoms, scene.ngeom
    for i in range(len(pts)):
        mujoco.mjv_initGeom(geoms[start + i], mujoco.mjtGeom.mjGEOM_BOX, size, pts[i], mat, colors[i])
    scene.ngeom = start + len(pts)
    return len(pts)


def inset_rect(
    viewport: mujoco.MjrRect, image_shape, width_frac: float = 0.28, margin: int = 10
) -> mujoco.MjrRect:
    """Top-right rectangle for an image inset, keeping its aspect ratio."""
    h, w = image_shape[:2]
    width = max(1, int(viewport.width * width_frac))
    height = max(1, int(round(width * h / w)))
    return mujoco.MjrRect(viewport.left + viewport.width - width - margin,
                          viewport.bottom + viewport.height - height - margin, width, height)  # fmt: skip


def fit_image(image: np.ndarray, width: int, height: int) -> np.ndarray:
    """Nearest-neighbour resize of an (h, w, 3) image to (height, width, 3) uint8."""
    img = np.asarray(image)
    if img.dtype != np.uint8:
        img = np.clip(img * (255.0 if img.dtype.kind == "f" and img.max() <= 1.0 else 1.0), 0, 255).astype(
            np.uint8
        )
    rows = (np.arange(height) * img.shape[0] / height).astype(int)
    cols = (np.arange(width) * img.shape[1] / width).astype(int)
    return img[rows][:, cols, :3]


def draw_inset(
    image, viewport: mujoco.MjrRect, context: mujoco.MjrContext, width_frac: float = 0.28
) -> mujoco.MjrRect:
    """Draw an (h, w, 3) image in the top-right corner of the viewport, with a thin frame."""
    rect = inset_rect(viewport, np.shape(image), width_frac)
    frame = mujoco.MjrRect(rect.left - 2, rect.bottom - 2, rect.width + 4, rect.height + 4)
    mujoco.mjr_rectangle(frame, 0.05, 0.05, 0.05, 1.0)
    pixels = np.ascontiguousarray(fit_image(image, rect.width, rect.height)[::-1])  # GL rows are bottom-up
    mujoco.mjr_drawPixels(pixels.ravel(), None, rect, context)
    return rect
