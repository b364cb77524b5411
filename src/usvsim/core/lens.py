"""Brown–Conrady (OpenCV plumb_bob) lens distortion on normalized image coordinates, and its inverse.

(x, y) = (X/Z, Y/Z) in the optical frame; D = (k1, k2, p1, p2, k3), r² = x² + y²:
  x_d = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2 x²)
  y_d = y (1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2 y²) + 2 p2 x y
The inverse is Newton's method on the 2x2 Jacobian, from the distorted point: it converges for every lens that is
invertible over the image, strong pincushion (k1 > 0) included, where the fixed-point iteration OpenCV's
undistortPoints uses diverges once the distortion's slope passes 2 (k1 = 5 at 80°). Points with no preimage (a
barrel polynomial that turns back inside the image) stay unconverged; `inverse_error` says by how much.
"""

from __future__ import annotations

import numpy as np

ITERATIONS = 20


def distort(xy: np.ndarray, D) -> np.ndarray:
    """Undistorted normalized points (n, 2) → distorted normalized points (plumb_bob D = k1, k2, p1, p2, k3)."""
    k1, k2, p1, p2, k3 = D
    x, y = xy[:, 0], xy[:, 1]
    r2 = x * x + y * y
    radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
    return np.stack([x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                     y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y], axis=1)  # fmt: skip


def undistort(xy_d: np.ndarray, D, iterations: int = ITERATIONS) -> np.ndarray:
    """Inverse of `distort` (Newton's method; see the module text)."""
    k1, k2, p1, p2, k3 = D
    xy = np.array(xy_d, dtype=float)
    with np.errstate(all="ignore"):  # a point without a preimage may run off to inf/NaN: left as it ends
        for _ in range(iterations):
            x, y = xy[:, 0], xy[:, 1]
            r2 = x * x + y * y
            radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
            slope = k1 + r2 * (2 * k2 + 3 * k3 * r2)  # d radial / d r²
            fx = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x) - xy_d[:, 0]
            fy = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y - xy_d[:, 1]
            jxx = radial + 2 * x * x * slope + 2 * p1 * y + 6 * p2 * x
            jyy = radial + 2 * y * y * slope + 6 * p1 * y + 2 * p2 * x
            jxy = 2 * x * y * slope + 2 * p1 * x + 2 * p2 * y  # = jyx
            det = jxx * jyy - jxy * jxy
            xy[:, 0] = x - (jyy * fx - jxy * fy) / det
            xy[:, 1] = y - (jxx * fy - jxy * fx) / det
    return xy


def inverse_error(xy_d: np.ndarray, D) -> np.ndarray:
    """How far (normalized units, per point) `distort(undistort(xy_d))` lands from xy_d: NaN or large where the
    lens has no inverse there."""
    with np.errstate(all="ignore"):
        return np.abs(distort(undistort(xy_d, D), D) - xy_d).max(axis=1)
