"""The image box of a 3D box seen by a camera: its faces clipped against the view frustum, then projected.

A box partly outside the image or partly behind the camera must not be projected corner by corner (points
behind the camera project to the wrong side, and clamping x/Z and y/Z separately drags far points into image
corners). Instead each of the 6 faces (a convex quad in the optical frame, z forward) is clipped
(Sutherland–Hodgman) against the near plane z ≥ near and the 4 side planes of the field of view
x_low·z ≤ x ≤ x_high·z, y_low·z ≤ y ≤ y_high·z (undistorted normalized coordinates); what is left lies in
front of the camera, inside the region where the distortion polynomial is valid. The clipped faces are
projected (edges sampled when the lens distorts, as straight edges then bend), clipped in 2D to the image
rectangle [-0.5, W-0.5] x [-0.5, H-0.5] (pixel centres at integers), and the box is the bounds of what is
left. For a pinhole camera this is exact: the bounds of the box's visible silhouette, whether or not other
objects hide it (the amodal box). One compiled call per box (`_box`; it was ~40 small numpy calls per clipped box).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.sensors.camera.intrinsics import Intrinsics

# the 6 faces of a box whose corners are ordered x major, z minor (index = 4 ix + 2 iy + iz), each a loop
FACES = np.array([[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]])
EDGE_SAMPLES = 16  # points per clipped edge of a distorting camera


def frustum_planes(near_m: float, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Half-spaces n · p >= offset of the frustum, rows (nx, ny, nz, offset): the near plane and the 4 side planes
    through the origin; `low`, `high`: normalized (x, y) bounds of the field of view."""
    return np.array([[0.0, 0.0, 1.0, near_m],
                     [1.0, 0.0, -low[0], 0.0], [-1.0, 0.0, high[0], 0.0],
                     [0.0, 1.0, -low[1], 0.0], [0.0, -1.0, high[1], 0.0]])  # fmt: skip


def camera_planes(cam: Intrinsics, near_m: float) -> np.ndarray:
    """The frustum of every output pixel's ray (half a pixel beyond the outer pixel centres)."""
    xy = cam.rays()  # undistorted normalized rays of every output pixel: the field of view
    margin = np.array([1.0 / cam.fx, 1.0 / cam.fy])
    return frustum_planes(near_m, xy.min(axis=(0, 1)) - margin, xy.max(axis=(0, 1)) + margin)


@njit(cache=True)
def _clip(poly, n, normal, offset, out):
    """Sutherland–Hodgman: the part of polygon poly[:n] (rows of d = len(normal) coordinates) where
    point · normal >= offset, into `out` (room for 2n rows); returns its row count."""
    d = len(normal)
    m = 0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        di, dj = -offset, -offset
        for k in range(d):
            di += poly[i, k] * normal[k]
            dj += poly[j, k] * normal[k]
        if di >= 0.0:
            out[m, :d] = poly[i, :d]
            m += 1
        if (di >= 0.0) != (dj >= 0.0):
            f = di / (di - dj)
            for k in range(d):
                out[m, k] = poly[i, k] + f * (poly[j, k] - poly[i, k])
            m += 1
    return m


@njit(cache=True)
def _pixel(x, y, z, fx, fy, cx, cy, dist, distorted):
    """(u, v) of an optical-frame point in front of the camera (plumb_bob distortion as intrinsics.distort)."""
    x, y = x / z, y / z
    if distorted:
        k1, k2, p1, p2, k3 = dist[0], dist[1], dist[2], dist[3], dist[4]
        r2 = x * x + y * y
        radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
        x, y = (x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)  # fmt: skip
    return fx * x + cx, fy * y + cy


@njit(cache=True)
def _box(corners, planes, faces, fx, fy, cx, cy, dist, distorted, width, height, out):
    """`image_box` into out (4,); False when no part of the box is in the image."""
    w, h = width - 0.5, height - 0.5
    inside = True
    for c in range(8):
        for p in range(planes.shape[0]):
            if corners[c, 0] * planes[p, 0] + corners[c, 1] * planes[p, 1] + corners[c, 2] * planes[p, 2] < planes[p, 3]:
                inside = False
    lo_u, lo_v, hi_u, hi_v = np.inf, np.inf, -np.inf, -np.inf
    if inside and not distorted:  # the common case: the corners' bounds, clamped to the image
        for c in range(8):
            u, v = _pixel(corners[c, 0], corners[c, 1], corners[c, 2], fx, fy, cx, cy, dist, False)
            lo_u, lo_v, hi_u, hi_v = min(lo_u, u), min(lo_v, v), max(hi_u, u), max(hi_v, v)
        out[0], out[1], out[2], out[3] = max(lo_u, -0.5), max(lo_v, -0.5), min(hi_u, w), min(hi_v, h)
        return out[2] > out[0] and out[3] > out[1]
    samples = EDGE_SAMPLES if distorted else 1
    a, b = np.empty((4 << 5, 3)), np.empty((4 << 5, 3))  # a cut adds at most a row per row (one in exact arithmetic)
    image = np.array([[1.0, 0.0, -0.5], [-1.0, 0.0, -w], [0.0, 1.0, -0.5], [0.0, -1.0, -h]])
    found = False
    for f in range(6):
        for k in range(4):
            a[k] = corners[faces[f, k]]
        n = 4
        for p in range(planes.shape[0]):
            n = _clip(a, n, planes[p, :3], planes[p, 3], b)
            a, b = b, a
            if n == 0:
                break
        if n < 3:
            continue
        pa, pb = np.empty((n * samples << 4, 2)), np.empty((n * samples << 4, 2))  # each image-edge cut: 2x at most
        m = 0
        for i in range(n):  # the clipped face's outline in pixels (edges sampled: a distorting lens bends them)
            j = i + 1 if i + 1 < n else 0
            for s in range(samples):
                t = s / samples
                x = a[i, 0] + t * (a[j, 0] - a[i, 0])
                y = a[i, 1] + t * (a[j, 1] - a[i, 1])
                z = a[i, 2] + t * (a[j, 2] - a[i, 2])
                pa[m, 0], pa[m, 1] = _pixel(x, y, z, fx, fy, cx, cy, dist, distorted)
                m += 1
        for p in range(4):
            m = _clip(pa, m, image[p, :2], image[p, 2], pb)
            pa, pb = pb, pa
            if m == 0:
                break
        for i in range(m):
            lo_u, lo_v = min(lo_u, pa[i, 0]), min(lo_v, pa[i, 1])
            hi_u, hi_v = max(hi_u, pa[i, 0]), max(hi_v, pa[i, 1])
            found = True
    out[0], out[1], out[2], out[3] = lo_u, lo_v, hi_u, hi_v
    return found and hi_u > lo_u and hi_v > lo_v


def image_box(corners_optical: np.ndarray, cam: Intrinsics, planes: np.ndarray) -> np.ndarray | None:
    """(u_min, v_min, u_max, v_max) of the box with 8 `corners_optical` (optical frame, m) inside the image,
    None when no part of it is; `planes`: `frustum_planes(...)` of the camera."""
    out = np.empty(4)
    corners = np.ascontiguousarray(corners_optical, dtype=np.float64)
    if not _box(corners, planes, FACES, cam.fx, cam.fy, cam.cx, cam.cy, np.asarray(cam.D, dtype=np.float64),
                cam.distorted, cam.width, cam.height, out):  # fmt: skip
        return None
    return out
