"""What every wave field shares: the start-up ramp, point-array handling and the rendering grids.

A wave field is a parametric surface (x0, y0, t) → (x0 + Δx, y0 + Δy, η) in world ENU metres. Rendering draws
`displaced_surface` at grid labels; physics asks `elevation` at world points, which inverts the horizontal
displacement. Both evaluate the same function, so what is drawn is what the physics feels.
"""

from __future__ import annotations

import math

import numpy as np

Labels = tuple[np.ndarray, np.ndarray, np.ndarray]
"""(x0, y0, z) of `WaveField.surface_labels`."""
LabelsIterations = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""(x0, y0, z, iterations used per point) of `surface_labels(..., return_iterations=True)`."""


def as_points(*arrays) -> tuple[np.ndarray, ...]:
    """Flatten coordinate arrays to contiguous float64 1-D arrays of equal length (arrays that already are
    such are passed through, as `np.ascontiguousarray` would, without its per-call cost)."""
    out = tuple(a if type(a) is np.ndarray and a.ndim == 1 and a.dtype == np.float64 and a.flags.c_contiguous
                else np.ascontiguousarray(np.ravel(a), dtype=np.float64) for a in arrays)  # fmt: skip
    n = len(out[0])
    if any(len(a) != n for a in out):
        raise ValueError(f"coordinate arrays differ in size: {[len(a) for a in out]}")
    return out


class WaveField:
    """Base class: subclasses implement `surface_labels`, `displaced_surface` and the kinematics."""

    def __init__(self, ramp_time_s: float = 0.0):
        if ramp_time_s < 0:
            raise ValueError(f"ramp_time_s must be >= 0, got {ramp_time_s}")
        self.ramp_time_s = float(ramp_time_s)

    def ramp(self, t: float) -> float:
        """Start-up ramp 1 - exp(-t/τ) (VRX form, t0 = 0) applied to every amplitude; 1 when τ = 0."""
        if self.ramp_time_s == 0.0:
            return 1.0
        return 0.0 if t <= 0 else 1.0 - math.exp(-t / self.ramp_time_s)

    def surface_labels(self, x, y, t: float) -> Labels:
        """(x0, y0, z): the labels whose displaced position is the world point (x, y), and the height there."""
        raise NotImplementedError

    def elevation(self, x, y, t: float) -> np.ndarray:
        """Height z (m) of the surface above the still-water level at world points (x, y), time t (s)."""
        shape = np.shape(x)
        return self.surface_labels(x, y, t)[2].reshape(shape)

    def height_grid(self, center_xy, size_m: float, n: int, t: float) -> np.ndarray:
        """Surface heights on an n×n world grid of side `size_m` centred on `center_xy`; [iy, ix] indexing."""
        axis = np.linspace(-0.5 * size_m, 0.5 * size_m, n)
        gx, gy = np.meshgrid(center_xy[0] + axis, center_xy[1] + axis)
        return self.elevation(gx, gy, t)

    def render_grid(self, center_xy, size_m: float, n: int, t: float) -> np.ndarray:
        """Vertices (n, n, 3) of the displaced surface over an n×n label grid, for drawing a mesh."""
        axis = np.linspace(-0.5 * size_m, 0.5 * size_m, n)
        gx, gy = np.meshgrid(center_xy[0] + axis, center_xy[1] + axis)
        return self.displaced_surface(gx.ravel(), gy.ravel(), t).reshape(n, n, 3)

    def displaced_surface(self, x0, y0, t: float) -> np.ndarray:
        raise NotImplementedError

    def normal(self, x, y, t: float) -> np.ndarray:
        """Unit surface normal (n, 3), ENU, at world points (x, y)."""
        raise NotImplementedError

    def kinematics(self, x, y, z, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Orbital velocity and acceleration (n, 3), ENU, at world points (x, y, z) (z relative to still water)."""
        raise NotImplementedError

    def velocity(self, x, y, z, t: float) -> np.ndarray:
        """Orbital velocity (n, 3), ENU, at world points (x, y, z) (z relative to still water)."""
        raise NotImplementedError
