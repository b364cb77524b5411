"""Pinhole intrinsics and Brown–Conrady (OpenCV plumb_bob) distortion, as published in CameraInfo.

Pixel coordinates follow ROS/OpenCV: pixel (u, v) has its centre at integer (u, v), u right, v down, so
the optical axis of a centred camera is at c = ((W-1)/2, (H-1)/2). Normalized coordinates (x, y) = (X/Z,
Y/Z) in the optical frame. Distortion (k1, k2, p1, p2, k3), r² = x² + y²:
  x_d = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2 x²)
  y_d = y (1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2 y²) + 2 p2 x y
and (u, v) = (fx x_d + cx, fy y_d + cy). The published image is the distorted one: it is made by
rendering an ideal pinhole image (wide enough to cover every source ray) and remapping it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.core.lens import distort, undistort
from usvsim.sensors.camera.kernels import remap_bilinear

__all__ = ["Intrinsics", "Remap", "distort", "undistort"]


@dataclass(frozen=True)
class Intrinsics:
    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    D: tuple[float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0)

    @classmethod
    def from_fov(cls, width: int, height: int, horizontal_fov_deg: float, D=(0.0,) * 5) -> Intrinsics:
        """Square pixels, optical axis at the image centre."""
        f = 0.5 * width / math.tan(math.radians(horizontal_fov_deg) / 2)
        k1, k2, p1, p2, k3 = (float(d) for d in D)
        return cls(width, height, f, f, (width - 1) / 2, (height - 1) / 2, (k1, k2, p1, p2, k3))

    @property
    def K(self) -> np.ndarray:
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def distorted(self) -> bool:
        return any(d != 0.0 for d in self.D)

    def project(self, points_optical: np.ndarray) -> np.ndarray:
        """Pixel coordinates (n, 2) of optical-frame points (n, 3) with Z > 0, distortion included."""
        xy = distort(points_optical[:, :2] / points_optical[:, 2:3], self.D)
        return np.stack([self.fx * xy[:, 0] + self.cx, self.fy * xy[:, 1] + self.cy], axis=1)

    def rays(self) -> np.ndarray:
        """Undistorted normalized coordinates (H, W, 2) of every output pixel's ray."""
        v, u = np.mgrid[0 : self.height, 0 : self.width].astype(np.float64)
        xy_d = np.stack([(u.ravel() - self.cx) / self.fx, (v.ravel() - self.cy) / self.fy], axis=1)
        xy = undistort(xy_d, self.D) if self.distorted else xy_d
        return xy.reshape(self.height, self.width, 2)


class Remap:
    """Distorted output image ← ideal pinhole render. `render` is the pinhole camera to draw (same size,
    focal scaled down if needed so that every output ray falls inside it); `apply` samples it."""

    def __init__(self, cam: Intrinsics):
        self.cam = cam
        xy = cam.rays()
        ok = np.isfinite(xy).all(axis=-1)  # a lens the config refuses (no inverse) leaves some rays undefined
        reach_x = max(np.abs(xy[ok, 0]).max(initial=0.0) * cam.fx / max(cam.cx + 0.5, cam.width - cam.cx - 0.5), 1.0)
        reach_y = max(np.abs(xy[ok, 1]).max(initial=0.0) * cam.fy / max(cam.cy + 0.5, cam.height - cam.cy - 0.5), 1.0)
        scale = 1.0 / max(reach_x, reach_y) * 0.999
        self.render = Intrinsics(cam.width, cam.height, cam.fx * scale, cam.fy * scale, cam.cx, cam.cy)
        su = self.render.fx * xy[..., 0] + cam.cx  # source pixel coordinates in the pinhole render
        sv = self.render.fy * xy[..., 1] + cam.cy
        su, sv = np.nan_to_num(su, nan=-1.0), np.nan_to_num(sv, nan=-1.0)  # never an index out of the image
        self.nearest = (np.clip(np.rint(sv), 0, cam.height - 1).astype(np.intp) * cam.width
                        + np.clip(np.rint(su), 0, cam.width - 1).astype(np.intp)).ravel()  # fmt: skip
        u0 = np.clip(np.floor(su), 0, cam.width - 2).astype(np.int64)
        v0 = np.clip(np.floor(sv), 0, cam.height - 2).astype(np.int64)
        fu, fv = (su - u0).clip(0, 1).ravel(), (sv - v0).clip(0, 1).ravel()
        base = (v0 * cam.width + u0).ravel()
        self.corners = np.stack([base, base + 1, base + cam.width, base + cam.width + 1], axis=1)
        self.weights = np.stack([(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv], axis=1).astype(np.float32)

    def linear(self, image: np.ndarray) -> np.ndarray:
        """Bilinear resampling of an (H, W, C) uint8 image (RGB)."""
        out = np.empty_like(image)
        remap_bilinear(np.ascontiguousarray(image), self.corners, self.weights, out)
        return out

    def closest(self, image: np.ndarray) -> np.ndarray:
        """Nearest-pixel resampling (depth, labels): never blends two surfaces."""
        return image.reshape(-1, *image.shape[2:])[self.nearest].reshape(image.shape)
