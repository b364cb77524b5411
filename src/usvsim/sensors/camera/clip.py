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
objects hide it (the amodal box).
"""

from __future__ import annotations

import numpy as np

from usvsim.sensors.camera.intrinsics import Intrinsics, distort

# the 6 faces of a box whose corners are ordered x major, z minor (index = 4 ix + 2 iy + iz), each a loop
FACES = np.array([[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]])
EDGE_SAMPLES = 16  # points per clipped edge of a distorting camera


def clip_polygon(points: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The part of a convex polygon (n, d) where points · normal ≥ offset (Sutherland–Hodgman)."""
    dist = points @ normal - offset
    out = []
    for i in range(len(points)):
        j = (i + 1) % len(points)
        if dist[i] >= 0.0:
            out.append(points[i])
        if (dist[i] >= 0.0) != (dist[j] >= 0.0):
            out.append(points[i] + dist[i] / (dist[i] - dist[j]) * (points[j] - points[i]))
    return np.array(out).reshape(-1, points.shape[1])


def frustum_planes(near_m: float, low: np.ndarray, high: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """(normal, offset) half-spaces of the frustum: near plane and the 4 side planes through the origin;
    `low`, `high`: normalized (x, y) bounds of the field of view."""
    return [(np.array([0.0, 0.0, 1.0]), near_m),
            (np.array([1.0, 0.0, -low[0]]), 0.0), (np.array([-1.0, 0.0, high[0]]), 0.0),
            (np.array([0.0, 1.0, -low[1]]), 0.0), (np.array([0.0, -1.0, high[1]]), 0.0)]  # fmt: skip


def camera_planes(cam: Intrinsics, near_m: float) -> list[tuple[np.ndarray, float]]:
    """The frustum of every output pixel's ray (half a pixel beyond the outer pixel centres)."""
    xy = cam.rays()  # undistorted normalized rays of every output pixel: the field of view
    margin = np.array([1.0 / cam.fx, 1.0 / cam.fy])
    return frustum_planes(near_m, xy.min(axis=(0, 1)) - margin, xy.max(axis=(0, 1)) + margin)


def _image_planes(cam: Intrinsics) -> list[tuple[np.ndarray, float]]:
    w, h = cam.width - 0.5, cam.height - 0.5
    return [(np.array([1.0, 0.0]), -0.5), (np.array([-1.0, 0.0]), -w),
            (np.array([0.0, 1.0]), -0.5), (np.array([0.0, -1.0]), -h)]  # fmt: skip


def _project(poly: np.ndarray, cam: Intrinsics) -> np.ndarray:
    """Pixel outline (n, 2) of a clipped face (points in front of the camera, inside the field of view)."""
    if cam.distorted:
        t = np.linspace(0.0, 1.0, EDGE_SAMPLES, endpoint=False)
        poly = (poly[:, None, :] + t[None, :, None] * (np.roll(poly, -1, axis=0) - poly)[:, None, :]).reshape(
            -1, 3
        )
    xy = poly[:, :2] / poly[:, 2:3]
    if cam.distorted:
        xy = distort(xy, cam.D)
    return np.stack([cam.fx * xy[:, 0] + cam.cx, cam.fy * xy[:, 1] + cam.cy], axis=1)


def image_box(corners_optical: np.ndarray, cam: Intrinsics, planes: list) -> np.ndarray | None:
    """(u_min, v_min, u_max, v_max) of the box with 8 `corners_optical` (optical frame, m) inside the image,
    None when no part of it is; `planes`: `frustum_planes(...)` of the camera."""
    inside = all((corners_optical @ normal >= offset).all() for normal, offset in planes)
    if inside and not cam.distorted:  # the common case: the corners' bounds, clamped to the image
        uv = _project(corners_optical, cam)
        w, h = cam.width - 0.5, cam.height - 0.5
        box = np.array(
            [
                max(uv[:, 0].min(), -0.5),
                max(uv[:, 1].min(), -0.5),
                min(uv[:, 0].max(), w),
                min(uv[:, 1].max(), h),
            ]
        )
        return box if box[2] > box[0] and box[3] > box[1] else None
    outline = []
    for face in FACES:
        poly = corners_optical[face]
        for normal, offset in planes:
            poly = clip_polygon(poly, normal, offset)
            if len(poly) == 0:
                break
        if len(poly) < 3:
            continue
        pixels = _project(poly, cam)
        for normal, offset in _image_planes(cam):
            pixels = clip_polygon(pixels, normal, offset)
            if len(pixels) == 0:
                break
        if len(pixels):
            outline.append(pixels)
    if not outline:
        return None
    pts = np.concatenate(outline)
    box = np.array([pts[:, 0].min(), pts[:, 1].min(), pts[:, 0].max(), pts[:, 1].max()])
    return box if box[2] > box[0] and box[3] > box[1] else None
