"""Metrics of a navigation run against the ground truth (frames: map = world ENU, metres, seconds).

- map IoU: occupied-class intersection over union of the map (p > 0.65) and the true occupancy within
  `range_m` of the true track, over the faces the LiDAR observed (`map_iou`), strict (same cell) and with a
  one-cell (0.25 m) tolerance.
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
from scipy.ndimage import binary_dilation

from usvsim.autonomy.grid import OccupancyGrid, edt


def map_iou(grid: OccupancyGrid, truth: np.ndarray, track_xy: np.ndarray, range_m: float = 30.0,
            tolerance_cells: int = 1) -> float:  # fmt: skip
    """IoU = TP / (TP + FP + FN) of the occupied cells within `range_m` of the track: a mapped cell is a true
    positive when a truly occupied cell lies within `tolerance_cells` (0 = the same cell), a false positive
    otherwise; an observed face (a truly occupied cell next to a free one, within 2 cells of an observed cell) is
    a false negative when no mapped cell lies within the tolerance. The inside of a quay or a shed's far side
    is never observed, so it is not judged."""
    xs, ys = grid.centres()
    gx, gy = np.meshgrid(xs, ys)
    near: np.ndarray = np.zeros(grid.shape, bool)
    for x, y in track_xy[:: max(1, len(track_xy) // 200)]:
        near |= (gx - x) ** 2 + (gy - y) ** 2 < range_m**2

    def dilate(a: np.ndarray, iterations: int) -> np.ndarray:
        return binary_dilation(a, iterations=iterations) if iterations else a

    def grow(a: np.ndarray) -> np.ndarray:
        return dilate(a, tolerance_cells)

    mapped = grid.occupied() & near
    face = truth & dilate(~truth, 1) & dilate(grid.known() & ~truth, 2) & near
    tp = int((mapped & grow(truth)).sum())
    fp, fn = int(mapped.sum()) - tp, int((face & ~grow(mapped)).sum())
    return tp / (tp + fp + fn) if tp + fp + fn else math.nan


def ate(t_est: np.ndarray, est_xy: np.ndarray, truth: np.ndarray) -> dict:
    """`truth` rows (t, x, y, yaw) at every step; estimates at times t_est. Aligned RMSE and drift."""
    true_xy = np.column_stack(
        [np.interp(t_est, truth[:, 0], truth[:, 1]), np.interp(t_est, truth[:, 0], truth[:, 2])]
    )
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


def min_clearance(grid: OccupancyGrid, truth: np.ndarray, poses: np.ndarray, length_m: float, beam_m: float,
                  centre_x_m: float = 0.0, centre_y_m: float = 0.0) -> float:  # fmt: skip
    """Smallest distance (m) from the hull box (centred at (centre_x_m, centre_y_m) in base_link) at each true
    pose (x, y, yaw) to a true occupied cell."""
    dist = edt(~truth) * grid.resolution_m
    u = np.linspace(-0.5, 0.5, 9) * length_m + centre_x_m
    u, v = np.meshgrid(u, np.linspace(-0.5, 0.5, 5) * beam_m + centre_y_m)
    box = np.column_stack([u.ravel(), v.ravel()])
    best = math.inf
    for x, y, yaw in poses[:: max(1, len(poses) // 2000)]:
        c, s = math.cos(yaw), math.sin(yaw)
        pts = box @ np.array([[c, s], [-s, c]]) + (x, y)
        ij = np.clip(grid.cells(pts), 0, np.array(grid.shape) - 1)
        best = min(best, float(dist[ij[:, 0], ij[:, 1]].min()))
    return max(0.0, best - 0.5 * grid.resolution_m)
