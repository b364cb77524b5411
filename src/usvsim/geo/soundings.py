"""Bathymetry from a vector file: soundings (points) or depth contours (lines), each with its value in a
property, interpolated linearly over their Delaunay triangulation (scipy). A lookup at a sounding returns
its value; between soundings it is the plane through the three around; outside their hull it is NaN (the
scene's default depth applies there). Contour lines contribute their vertices.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from usvsim.geo.frame import GeoError, GeoFrame
from usvsim.geo.vector import read_features


@dataclass(frozen=True)
class Soundings:
    """Values at ENU points (x, y) and their linear interpolant."""

    points: np.ndarray  # (n, 2) ENU m
    values: np.ndarray  # (n,)
    interpolant: Callable[[np.ndarray, np.ndarray], np.ndarray]  # (x, y) ENU m → value

    def sample(self, x_m, y_m) -> np.ndarray:
        x = np.atleast_1d(np.asarray(x_m, float))
        y = np.broadcast_to(np.asarray(y_m, float), x.shape)
        return self.interpolant(x.ravel(), y.ravel()).reshape(x.shape)

    def sample_grid(self, xs_m: np.ndarray, ys_m: np.ndarray) -> np.ndarray:
        gx, gy = np.meshgrid(xs_m, ys_m)
        return self.sample(gx, gy)


def read_soundings(path: Path, layer: str | None, crs: str | None, frame: GeoFrame, extent_m: float,
                   value_property: str) -> Soundings:  # fmt: skip
    """Points or lines with a numeric `value_property`, as a linear interpolant in ENU."""
    from scipy.interpolate import LinearNDInterpolator

    feats = read_features(path, layer, crs, frame, 2.0 * extent_m, ("Point", "LineString"))
    xy, values = [], []
    for geom, props in zip(feats.geometries, feats.properties):
        try:
            value = float(props.get(value_property))  # pyright: ignore[reportArgumentType] (None → TypeError below)
        except (TypeError, ValueError):
            raise GeoError(f"{path}: a feature has no number in property '{value_property}'") from None
        coords = shapely.get_coordinates(geom)
        xy.append(coords)
        values.append(np.full(len(coords), value))
    points, values = np.concatenate(xy), np.concatenate(values)
    if len(points) < 3 or not np.all(np.isfinite(values)):
        raise GeoError(f"{path}: needs at least 3 soundings with finite '{value_property}' values")
    return Soundings(points, values, LinearNDInterpolator(points, values))
