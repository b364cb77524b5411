"""Shadows of geoms on the water: each visual geom's box (its mesh's or primitive's bounds), cast along the sun
onto the still-water plane, drawn as the 12 triangles of its 6 projected faces (their union is the box's
shadow) into the G channel of the top-down texture the wakes use (rendering/wakes.WakePass); the water shader
takes the sun's share (glint, the sunlit part of the body colour and of foam) away there. Parts below the
water cast from the waterline. Boxes, not meshes: a hull's shadow is its bounding box's.
"""

from __future__ import annotations

import mujoco
import numpy as np

REACH_M = 400.0  # casters within this distance of the camera's vessel
_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)
_FACES = np.array([[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]])
_TRIS = np.concatenate([_FACES[:, [0, 1, 2]], _FACES[:, [0, 2, 3]]])  # (12, 3) corner indices


def shadow_triangles(
    model: mujoco.MjModel, data: mujoco.MjData, sun_dir, level_m: float, center_xy
) -> np.ndarray:
    """(n, 2) float32 vertices (ENU m) of the triangles covering the geoms' shadows on the sea plane."""
    sun = np.asarray(sun_dir, dtype=np.float64)
    if sun[2] < 0.05:  # sun at or below the horizon: no direct light to take away
        return np.zeros((0, 2), np.float32)
    geoms = np.flatnonzero(model.geom_group == 1)
    near = np.linalg.norm(data.geom_xpos[geoms, :2] - np.asarray(center_xy[:2]), axis=1) < REACH_M
    geoms = geoms[near]
    if not len(geoms):
        return np.zeros((0, 2), np.float32)
    local = model.geom_aabb[geoms, None, :3] + _SIGNS[None] * model.geom_aabb[geoms, None, 3:]  # (g, 8, 3)
    rot = data.geom_xmat[geoms].reshape(-1, 3, 3)
    corners = np.einsum("gij,gkj->gki", rot, local) + data.geom_xpos[geoms, None, :]
    above = corners[..., 2].max(axis=1) > level_m
    corners = corners[above]
    height = np.maximum(corners[..., 2] - level_m, 0.0)  # below the water: cast from the waterline
    ground = corners[..., :2] - sun[None, None, :2] * (height / sun[2])[..., None]
    return ground[:, _TRIS].reshape(-1, 2).astype(np.float32)
