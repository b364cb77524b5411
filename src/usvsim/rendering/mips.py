"""Mipmaps of the ocean's texture layers on the CPU: a 2 x 2 box filter per level, in one numba pass.

llvmpipe builds mipmaps (`glGenerateMipmap`) with one blit draw per level and layer (about 0.7 ms per
128² x 4-layer float texture on this machine); the same box filter here costs a few hundredths of that, and the
levels are uploaded with the base level. Odd sizes repeat their last row or column (GL leaves NPOT filtering open).
"""

from __future__ import annotations

import numpy as np
from numba import njit


def mip_levels(layers: np.ndarray) -> list[np.ndarray]:
    """(bands, N, M, C) float32 → [level 0 (the input), level 1, ... down to 1 x 1], each (bands, n, m, C)."""
    levels = [np.ascontiguousarray(layers, dtype=np.float32)]
    while levels[-1].shape[1] > 1 or levels[-1].shape[2] > 1:
        src = levels[-1]
        out = np.empty((src.shape[0], max(src.shape[1] // 2, 1), max(src.shape[2] // 2, 1), src.shape[3]), np.float32)
        _halve(src, out)
        levels.append(out)
    return levels


@njit(cache=True, nogil=True)
def _halve(src, out):
    n, m = src.shape[1], src.shape[2]
    for b in range(out.shape[0]):
        for i in range(out.shape[1]):
            i0, i1 = min(2 * i, n - 1), min(2 * i + 1, n - 1)
            for j in range(out.shape[2]):
                j0, j1 = min(2 * j, m - 1), min(2 * j + 1, m - 1)
                for c in range(out.shape[3]):
                    out[b, i, j, c] = np.float32(0.25) * (
                        (src[b, i0, j0, c] + src[b, i0, j1, c]) + (src[b, i1, j0, c] + src[b, i1, j1, c])
                    )
