"""2D occupancy grid in log-odds with numba ray tracing, saved in the ROS `map_server` format.

The grid covers a fixed rectangle of the `map` frame (ENU, metres): cell (i, j) = row i (y), column j (x),
centre at origin + ((j + 0.5)·res, (i + 0.5)·res). Each beam from the sensor to a hit lowers the log-odds
of the cells it crosses (free) and raises the hit cell's (occupied); values are clamped so the map can
change its mind (moving boats). Probability p = 1 / (1 + exp(-l)); unknown = 0.5.

`save_map` writes `<name>.png` (8-bit grey: 0 occupied, 254 free, 205 unknown, image row 0 = top = +y)
and `<name>.yaml` (image, resolution, origin [x, y, yaw], negate 0, occupied_thresh 0.65,
free_thresh 0.196, mode trinary), which `nav2_map_server` and slam_toolbox load as is.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numba
import numpy as np
from PIL import Image
from scipy.ndimage import distance_transform_edt

L_FREE, L_OCC, L_MIN, L_MAX = -0.4, 0.85, -2.0, 3.5  # log-odds per observation and clamps
OCC_THRESH, FREE_THRESH = 0.65, 0.196  # map_server's defaults
L_STOP = 0.0  # a beam stops clearing behind a cell with net occupied evidence (p > 0.5)


@numba.njit(cache=True, nogil=True)
def trace_rays(
    logodds, sensor_ij, hits_ij, free_only, l_free, l_occ, l_min, l_max, l_stop
):  # pragma: no cover - numba
    """Bresenham from the sensor cell to each end cell: free along the way, occupied at the end
    (unless free_only[k], a beam with no return cut at the mapping range). Cells off the grid are skipped.
    A beam that crosses a cell with net occupied evidence (log-odds > l_stop) lowers it once and clears nothing behind it:
    it passed above a low obstacle (a quay 1 m high, a pier deck), which hides what lies behind at its height."""
    rows, cols = logodds.shape
    i0, j0 = sensor_ij
    for k in range(hits_ij.shape[0]):
        i1, j1 = hits_ij[k, 0], hits_ij[k, 1]
        di, dj = abs(i1 - i0), abs(j1 - j0)
        si, sj = (1 if i1 > i0 else -1), (1 if j1 > j0 else -1)
        err, i, j, clear = dj - di, i0, j0, True
        while clear and (i != i1 or j != j1):
            if 0 <= i < rows and 0 <= j < cols:
                clear = logodds[i, j] <= l_stop
                logodds[i, j] = max(l_min, logodds[i, j] + l_free)
            e2 = 2 * err
            if e2 > -di:
                err -= di
                j += sj
            if e2 < dj:
                err += dj
                i += si
        if 0 <= i1 < rows and 0 <= j1 < cols:
            logodds[i1, j1] = min(l_max, logodds[i1, j1] + (l_free if free_only[k] else l_occ))


@dataclass
class OccupancyGrid:
    """Log-odds grid over [x0, x0 + cols·res) × [y0, y0 + rows·res) of the map frame (ENU, m)."""

    origin_xy: tuple[float, float]
    shape: tuple[int, int]
    resolution_m: float = 0.25

    def __post_init__(self):
        self.logodds = np.zeros(self.shape, np.float32)

    @classmethod
    def around(cls, xmin: float, ymin: float, xmax: float, ymax: float, resolution_m: float = 0.25):
        rows, cols = int(np.ceil((ymax - ymin) / resolution_m)), int(np.ceil((xmax - xmin) / resolution_m))
        return cls((xmin, ymin), (rows, cols), resolution_m)

    def cells(self, xy: np.ndarray) -> np.ndarray:
        """(row, col) int32 cells of map points (n, 2) (may lie off the grid)."""
        ij = np.floor((np.asarray(xy)[:, ::-1] - np.array(self.origin_xy)[::-1]) / self.resolution_m)
        return ij.astype(np.int32)

    def centres(self) -> tuple[np.ndarray, np.ndarray]:
        """x (cols,) and y (rows,) of the cell centres, m."""
        r, (x0, y0) = self.resolution_m, self.origin_xy
        return x0 + (np.arange(self.shape[1]) + 0.5) * r, y0 + (np.arange(self.shape[0]) + 0.5) * r

    def integrate(self, sensor_xy, hits_xy: np.ndarray, free_only: np.ndarray | None = None) -> None:
        """One scan: beams from `sensor_xy` to `hits_xy` (n, 2), map frame."""
        ends = self.cells(hits_xy)
        flags = np.zeros(len(ends), np.bool_) if free_only is None else free_only
        start = self.cells(np.asarray(sensor_xy, float)[None, :2])[0]
        trace_rays(
            self.logodds, (int(start[0]), int(start[1])), ends, flags, L_FREE, L_OCC, L_MIN, L_MAX, L_STOP
        )

    def probability(self) -> np.ndarray:
        return 1.0 / (1.0 + np.exp(-self.logodds))

    def occupied(self) -> np.ndarray:
        return self.probability() > OCC_THRESH

    def known(self) -> np.ndarray:
        return self.logodds != 0.0

    def save_map(self, path: str | Path) -> tuple[Path, Path]:
        """`path`.png + `path`.yaml in the map_server format (trinary)."""
        path = Path(path)
        p = self.probability()
        img = np.full(self.shape, 205, np.uint8)
        img[p > OCC_THRESH] = 0
        img[p < FREE_THRESH] = 254
        png, yaml_path = path.with_suffix(".png"), path.with_suffix(".yaml")
        Image.fromarray(img[::-1]).save(png)
        x0, y0 = self.origin_xy
        yaml_path.write_text(
            f"image: {png.name}\nmode: trinary\nresolution: {self.resolution_m}\norigin: [{x0}, {y0}, 0.0]\n"
            f"negate: 0\noccupied_thresh: {OCC_THRESH}\nfree_thresh: {FREE_THRESH}\n"
        )
        return png, yaml_path


def edt(free: np.ndarray) -> np.ndarray:
    """Euclidean distance (in cells) of each True cell to the nearest False one. scipy's stub types the return
    as a union over `return_distances` / `return_indices`; with the defaults it is the distance array."""
    return cast(np.ndarray, distance_transform_edt(free))
