"""Numba kernels of the look's image effects (datasets/look.py): one pass per image, no temporaries."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def finish_look(rgb, depth, ray_scale, fog_per_m, fog_rgb, sky_m, gain, vignette, out):
    """out = (fogged rgb) · gain · (1 - vignette) as float32 0–1; fog by Koschmieder from the ray length
    (depth · ray_scale; NaN depth: the sky, `sky_m` away); fog_per_m = 0 turns fog off."""
    h, w = depth.shape
    for v in range(h):
        for u in range(w):
            d = depth[v, u]
            keep = 1.0
            if fog_per_m > 0.0:
                dist = sky_m if math.isnan(d) else d * ray_scale[v, u]
                keep = math.exp(-fog_per_m * dist)
            g = gain * (1.0 - vignette[v, u])
            for c in range(3):
                x = rgb[v, u, c] / 255.0
                out[v, u, c] = (x * keep + (1.0 - keep) * fog_rgb[c]) * g


@njit(cache=True, nogil=True)
def blur_axis(src, taps, axis, out):
    """Convolve an (H, W, C) image along `axis` (0: columns, 1: rows) with a symmetric kernel `taps` (centre
    first), edges repeated; the innermost loops run over contiguous memory."""
    h, w, ch = src.shape
    r = len(taps) - 1
    for v in range(h):
        for u in range(w):
            for c in range(ch):
                out[v, u, c] = taps[0] * src[v, u, c]
        for k in range(1, r + 1):
            t = taps[k]
            if axis == 0:
                lo, hi = max(v - k, 0), min(v + k, h - 1)
                for u in range(w):
                    for c in range(ch):
                        out[v, u, c] += t * (src[lo, u, c] + src[hi, u, c])
            else:
                for u in range(w):
                    lo, hi = max(u - k, 0), min(u + k, w - 1)
                    for c in range(ch):
                        out[v, u, c] += t * (src[v, lo, c] + src[v, hi, c])


def gaussian_blur(img: np.ndarray, sigma_px: float) -> np.ndarray:
    """Separable Gaussian blur of an (H, W, 3) float32 image (radius 3σ, edges repeated)."""
    r = max(1, int(math.ceil(3.0 * sigma_px)))
    taps = np.exp(-0.5 * (np.arange(r + 1) / sigma_px) ** 2)
    taps = (taps / (taps[0] + 2.0 * taps[1:].sum())).astype(np.float32)
    tmp, out = np.empty_like(img), np.empty_like(img)
    blur_axis(img, taps, 1, tmp)
    blur_axis(tmp, taps, 0, out)
    return out


@njit(cache=True, nogil=True)
def to_uint8_noisy(img, normal, stddev, out):
    """out = clip(img · (1 + stddev · n)) as 8-bit; `normal` may be empty (no noise)."""
    h, w, ch = img.shape
    noisy = normal.size > 0
    for v in range(h):
        for u in range(w):
            for c in range(ch):
                x = img[v, u, c] * (1.0 + stddev * normal[v, u, c]) if noisy else img[v, u, c]
                out[v, u, c] = np.uint8(min(max(x, 0.0), 1.0) * 255.0 + 0.5)
