"""Numba kernels of the look's image effects (datasets/look.py): one pass per image, no temporaries."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def finish_look(rgb, depth, ray_scale, fog_per_m, fog_rgb, sky_m, gain, vignette, out):
    """out = (fogged rgb) · gain · (1 - vignette) as float32 0–1; fog by Koschmieder from the ray length
    (depth · ray_scale; NaN depth: the sky, `sky_m` away); fog_per_m = 0 turns fog off. The fog is blended in
    linear light, as the shader look blends it: the 8-bit value x decodes to x² (display gamma 2, MuJoCo's space and
    the shader's `display`), mixes with the linear `fog_rgb`, and is encoded back by the square root."""
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
                if keep < 1.0:
                    x = math.sqrt(x * x * keep + (1.0 - keep) * fog_rgb[c])
                out[v, u, c] = x * g


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
