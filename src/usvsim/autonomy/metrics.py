"""Metrics of a navigation run against the ground truth (frames: map = world ENU, metres, seconds).

- map IoU: occupied-class intersection over union of the map (p > 0.65) and the true occupancy, over the
  cells a LiDAR could judge: within `range_m` of the true track, restricted to the truth's free cells and
  its surface layer (occupied cells within `surface_cells` of a free cell: the inside of a quay is never seen).
- ATE: RMS of the horizontal position error after the rigid 2D alignment of the estimated to the true
  track (Horn/Umeyama, as in the TUM benchmark), and per 100 m travelled; `drift_m` is the final error
  without alignment.
- cross-track: RMS and max of the true position's distance to the followed path leg.
- clearance: smallest distance (m) from the true hull footprint (a `length_m` × `beam_m` box) to the truth's
  occupied cells.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import binary_dilation, distance_transform_edt

from usvsim.autonomy.grid import OccupancyGrid


def map_iou(grid: OccupancyGrid, truth: np.ndarray, track_xy: np.ndarray, range_m: float = 30.0,
            surface_cells: int = 1) -> float:  # fmt: skip
    xs, ys = grid.centres()
    gx, gy = np.meshgrid(xs, ys)
    near = np.zeros(grid.shape, bool)
    for x, y in track_xy[:: max(1, len(track_xy) // 200)]:
        near |= (gx - x) ** 2 + (gy - y) ** 2 < range_m**2
    surface = truth & binary_dilation(~truth, iterations=surface_cells)
    judged = near & (~truth | surface)
    mapped = grid.occupied() & judged
    true = truth & judged
    union = (mapped | true).sum()
    return float((mapped & true).sum() / union) if union else math.nan


def ate(t_est: np.ndarray, est_xy: np.ndarray, truth: np.ndarray) -> dict:
    """`truth` rows (t, x, y, yaw) at every step; estimates at times t_est. Aligned RMSE and drift."""
    true_xy = np.column_stack([np.interp(t_est, truth[:, 0], truth[:, 1]), np.interp(t_est, truth[:, 0], truth[:, 2])])
    mu_e, mu_t = est_xy.mean(axis=0), true_xy.mean(axis=0)
    u, _, vt = np.linalg.svd((true_xy - mu_t).T @ (est_xy - mu_e))
    d = np.diag([1.0, np.sign(np.linalg.det(u @ vt))])
    rot = u @ d @ vt
    aligned = (est_xy - mu_e) @ rot.T + mu_t
    rmse = float(np.sqrt(np.mean(np.sum((aligned - true_xy) ** 2, axis=1))))
    length = float(np.sum(np.hypot(*np.diff(truth[:, 1:3], axis=0).T)))
    raw = np.hypot(*(est_xy - true_xy).T)
    return {"ate_rmse_m": rmse, "ate_per_100m_m": rmse / max(length, 1e-9) * 100.0, "path_length_m": length,
            "raw_rmse_m": float(np.sqrt(np.mean(raw**2))), "drift_m": float(raw[-1])}  # fmt: skip


def min_clearance(grid: OccupancyGrid, truth: np.ndarray, poses: np.ndarray, length_m: float, beam_m: float) -> float:
    """Smallest distance (m) from the hull box at each true pose (x, y, yaw) to a true occupied cell."""
    dist = distance_transform_edt(~truth) * grid.resolution_m
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, 9) * length_m, np.linspace(-0.5, 0.5, 5) * beam_m)
    box = np.column_stack([u.ravel(), v.ravel()])
    best = math.inf
    for x, y, yaw in poses[:: max(1, len(poses) // 2000)]:
        c, s = math.cos(yaw), math.sin(yaw)
        pts = box @ np.array([[c, s], [-s, c]]) + (x, y)
        ij = np.clip(grid.cells(pts), 0, np.array(grid.shape) - 1)
        best = min(best, float(dist[ij[:, 0], ij[:, 1]].min()))
    return max(0.0, best - 0.5 * grid.resolution_m)
