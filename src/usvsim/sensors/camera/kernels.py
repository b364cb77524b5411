"""numba kernels for the camera's per-pixel work: one pass over the GL buffers, no temporaries.

GL buffers come bottom row first; every kernel writes top row first (image order). Pixel (u, v) of an
ideal pinhole camera sees the optical-frame ray (x, y, 1) with x = (u - cx) / fx, y = (v - cy) / fy.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def finish_rgb_depth(rgb_gl, z_gl, near_m, far_m, zero_near, up_optical, intrinsics, zenith, horizon, paint_sky,
                     rgb_out, depth_out):  # fmt: skip
    """Flip, linearize depth (metres along optical z, NaN = nothing nearer than `far_m`) and paint the sky.

    `z_gl`: window depth (0 at near if `zero_near`, else reversed Z). `up_optical`: the world up axis
    expressed in the optical frame (sky gradient: horizon colour at 0°, zenith colour straight up).
    `intrinsics` = (fx, fy, cx, cy); `zenith`, `horizon` RGB in 0..255. Without `paint_sky` the drawn colour is
    kept everywhere (the shader renderer draws the sky and water beyond the far plane itself).
    """
    height, width = z_gl.shape
    fx, fy, cx, cy = intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]
    ratio = near_m / far_m
    for row in range(height):
        src = height - 1 - row
        y = (row - cy) / fy
        for col in range(width):
            raw = np.float64(z_gl[src, col])
            if zero_near:
                empty = raw >= 1.0
                d = near_m / (1.0 - raw * (1.0 - ratio))
            else:
                empty = raw <= 0.0
                d = near_m / (raw + (1.0 - raw) * ratio)
            if (empty or d >= 0.999 * far_m) and not paint_sky:
                depth_out[row, col] = np.nan
                for c in range(3):
                    rgb_out[row, col, c] = rgb_gl[src, col, c]
            elif empty or d >= 0.999 * far_m:
                depth_out[row, col] = np.nan
                x = (col - cx) / fx
                t = (x * up_optical[0] + y * up_optical[1] + up_optical[2]) / math.sqrt(x * x + y * y + 1.0)
                t = min(max(t, 0.0), 1.0)
                for c in range(3):
                    rgb_out[row, col, c] = np.uint8(horizon[c] + t * (zenith[c] - horizon[c]))
            else:
                depth_out[row, col] = d
                for c in range(3):
                    rgb_out[row, col, c] = rgb_gl[src, col, c]


@njit(cache=True, nogil=True)
def finish_segmentation(rgb_gl, lut, out):
    """Flip and decode MuJoCo's id colours (scene geom index + 1, 24 bits) into labels via `lut`."""
    height, width = out.shape
    top = lut.shape[0] - 1
    for row in range(height):
        src = height - 1 - row
        for col in range(width):
            idx = np.int64(rgb_gl[src, col, 0]) | (np.int64(rgb_gl[src, col, 1]) << 8) | (np.int64(rgb_gl[src, col, 2]) << 16)
            out[row, col] = lut[min(idx, top)]


@njit(cache=True, nogil=True)
def finish_segmentation_water(rgb_gl, water_gl, lut, water, out):
    """`finish_segmentation` with the label `water` wherever `water_gl` (bottom row first) is non-zero."""
    height, width = out.shape
    top = lut.shape[0] - 1
    for row in range(height):
        src = height - 1 - row
        for col in range(width):
            if water_gl[src, col] != 0:
                out[row, col] = water
                continue
            idx = np.int64(rgb_gl[src, col, 0]) | (np.int64(rgb_gl[src, col, 1]) << 8) | (np.int64(rgb_gl[src, col, 2]) << 16)
            out[row, col] = lut[min(idx, top)]


@njit(cache=True, nogil=True)
def remap_bilinear(src, corners, weights, out):
    """out.flat[i] = Σ_k weights[i, k] · src.flat[corners[i, k]] per channel, rounded (uint8 images)."""
    flat_src = src.reshape(-1, src.shape[-1])
    flat_out = out.reshape(-1, out.shape[-1])
    for i in range(corners.shape[0]):
        for c in range(flat_src.shape[1]):
            acc = np.float32(0.0)
            for k in range(4):
                acc += weights[i, k] * np.float32(flat_src[corners[i, k], c])
            flat_out[i, c] = np.uint8(min(acc + np.float32(0.5), np.float32(255.0)))


@njit(cache=True, nogil=True)
def rgb_gain_noise(rgb, normal, stddev):
    """In place: rgb = clip(round(rgb · (1 + stddev · normal)), 0, 255)."""
    flat, n = rgb.reshape(-1), normal.reshape(-1)
    for i in range(flat.shape[0]):
        value = np.float32(flat[i]) * (np.float32(1.0) + stddev * n[i])
        flat[i] = np.uint8(min(max(np.float32(round(value)), np.float32(0.0)), np.float32(255.0)))


@njit(cache=True, nogil=True)
def vignette_factors(height, width, gain, vignetting, intrinsics):
    """(height, width) int32 factors in 1/256 steps: 256 · gain · (1 - vignetting · r²/r_corner²), r from the
    principal point (`expose_vignette` applies them; a camera computes them once per look)."""
    fx, fy, cx, cy = intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]
    corner = max(cx * cx, (width - cx) ** 2) / (fx * fx) + max(cy * cy, (height - cy) ** 2) / (fy * fy)
    out = np.empty((height, width), np.int32)
    for row in range(height):
        y2 = ((row - cy) / fy) ** 2
        for col in range(width):
            x = (col - cx) / fx
            out[row, col] = np.int32(256.0 * max(gain * (1.0 - vignetting * (x * x + y2) / corner), 0.0) + 0.5)
    return out


@njit(cache=True, nogil=True)
def apply_factors(rgb, factors):
    """In place: rgb · factor / 256, rounded and clipped (integer arithmetic, one pass the compiler vectorizes)."""
    height, width = factors.shape
    for row in range(height):
        for col in range(width):
            f = factors[row, col]
            for c in range(3):
                rgb[row, col, c] = np.uint8(min((np.int32(rgb[row, col, c]) * f + 128) >> 8, 255))


def expose_vignette(rgb, gain, vignetting, intrinsics):
    """In place: rgb · gain · (1 - vignetting · r²/r_corner²), rounded and clipped; r from the principal point.
    The factor is applied in 1/256 steps (integer arithmetic: a quarter of the float loop's time)."""
    apply_factors(rgb, vignette_factors(rgb.shape[0], rgb.shape[1], gain, vignetting, intrinsics))


@njit(cache=True, nogil=True)
def still_water_depth(depth, up_optical, intrinsics, camera_z, plane_z, level_z, far_m):
    """In place, MuJoCo's look: pixels whose surface point lies on the drawn still-water plane (world z within
    2 cm of `plane_z`, which sits below the drawn wave field's lowest trough) get the depth of the still water at
    its mean level `level_z` along the same ray (NaN beyond `far_m`). The drawn field's own points are at or above
    its lowest trough, 5 cm above the plane. `up_optical`: world up in the optical frame; `camera_z`: world z (m)."""
    height, width = depth.shape
    fx, fy, cx, cy = intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]
    for row in range(height):
        y = (row - cy) / fy
        for col in range(width):
            d = depth[row, col]
            if not np.isfinite(d):
                continue
            # world dz per unit of optical z along the pixel's ray
            rz = ((col - cx) / fx) * up_optical[0] + y * up_optical[1] + up_optical[2]
            if abs(camera_z + d * rz - plane_z) > 0.02:
                continue
            mean = (level_z - camera_z) / rz if rz < 0.0 else np.inf
            depth[row, col] = mean if mean < far_m else np.nan
