"""Which object pixels the fog leaves visible: labels only for what the image can show.

Meteorological visibility V (`rendering.fog.visibility_m`) is the distance at which the contrast of a dark
object against the horizon falls to Koschmieder's threshold, CONTRAST_THRESHOLD = 2 % (so the extinction is
-ln 0.02 / V = 3.912 / V). A pixel of an object counts as visible for labelling when the fog's transmittance
along its ray, keep = exp(-∫ σ ds), is at least that threshold; beyond it the pixel is fog colour to within
2 % of the object's contrast, and no observer (nor a detector) could tell it from fog.

keep is computed as the active renderer computes the fog it draws, from the frame's depth image (metric depth
along the optical axis; ray length r = depth · sqrt(1 + x² + y²) for the pixel's normalized ray (x, y)):
- `renderer: mujoco` (datasets/look.py, look_kernels.finish_look): σ = 3.912 / V, uniform; keep = exp(-σ r).
- `renderer: shader` (rendering/shaders.py `layer_depth`, marine.set_light): σ = 3.912 / V plus the rain's
  extinction (rendering/weather.fog_extinction_per_m), falling by e every `fog.height_falloff_m` = H above the
  sea's mean level: σ(z) = σ exp(-(z - level) / H). Along a ray from the eye at height z₀ that rises
  Δz = u·r (u: the world-up component of its unit direction), ∫ σ(z) ds = σ e^{-(z₀ - level)/H} r (1 - e^{-Δz/H}) / (Δz/H).
The clear-air haze (`rendering.haze`, 25 km by default) is no fog and is not counted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from usvsim.datasets.look import KOSCHMIEDER
from usvsim.rendering.weather import fog_extinction_per_m

CONTRAST_THRESHOLD = 0.02  # Koschmieder: the contrast at the meteorological visibility (exp(-3.912) = 0.02)


def fog_extinction(look) -> tuple[float, float]:
    """(extinction at sea level in 1/m, height falloff in m; inf: uniform) of the fog `look`'s renderer draws."""
    if look.renderer == "shader":
        return fog_extinction_per_m(look), look.fog.height_falloff_m
    fog = look.fog.visibility_m
    return (KOSCHMIEDER / fog if fog else 0.0), math.inf


@dataclass
class FogFrame:
    """One frame's fog along the camera's rays; `hidden` (H, W) marks object pixels the fog hides (filled by
    objects_in)."""

    depth: np.ndarray  # (H, W) float32, m along the optical axis
    xy: np.ndarray  # (H, W, 2) normalized rays of the published pixels
    sigma_per_m: float
    height_m: float
    at_eye: float  # the fog's density at the eye relative to sea level
    up: np.ndarray  # world-up component of the optical axes x, y, z (rises in m per m of depth)
    hidden: np.ndarray

    def stats(self, seg, owner, n_objects):
        """(fog-visible pixel counts, their bounds, sums of their transmittance) per object, as label_stats."""
        return fog_label_stats(seg, owner, n_objects, self.depth, self.xy, self.sigma_per_m, self.height_m,
                               self.at_eye, self.up, CONTRAST_THRESHOLD, self.hidden)  # fmt: skip


class FogSight:
    """A camera's rays, to make each frame's FogFrame."""

    def __init__(self, cam):
        self.xy = cam.rays()  # the published (distorted) pixels' rays, as datasets/look.py uses them

    def frame(self, look, depth, pos_world, rot_optical, level_m: float) -> FogFrame | None:
        """The frame's fog (None: no fog drawn); `rot_optical`: optical frame → world (ENU), eye at `pos_world`."""
        sigma, height = fog_extinction(look)
        if sigma <= 0.0:
            return None
        at_eye = math.exp(-(float(pos_world[2]) - level_m) / height)
        up = np.ascontiguousarray(np.asarray(rot_optical, np.float64)[2])
        return FogFrame(depth, self.xy, sigma, height, at_eye, up, np.zeros(depth.shape, np.bool_))


@njit(cache=True, nogil=True)
def transmittance(r, rise, sigma, height, at_eye):
    """exp(-optical depth) over a ray of length r (m) rising `rise` m through fog σ·at_eye·exp(-Δz/H)."""
    dz = rise / height
    path = -math.expm1(-dz) / dz if abs(dz) > 1e-6 else 1.0 - 0.5 * dz
    return math.exp(-at_eye * sigma * r * path)


@njit(cache=True, nogil=True)
def fog_label_stats(seg, owner, n_objects, depth, xy, sigma, height, at_eye, up, threshold, hidden):
    """label_stats over the object pixels whose transmittance reaches `threshold`, plus the sum of it per
    object; the others are set in `hidden`. Only object pixels are computed."""
    counts = np.zeros(n_objects + 1, np.int64)
    keep_sum = np.zeros(n_objects + 1, np.float64)
    bounds = np.empty((n_objects + 1, 4), np.int64)
    bounds[:, 0] = bounds[:, 1] = 1 << 30
    bounds[:, 2] = bounds[:, 3] = -1
    for v in range(seg.shape[0]):
        for u in range(seg.shape[1]):
            k = owner[min(np.int64(seg[v, u]), owner.shape[0] - 1)]
            if k == 0:
                continue
            x, y, d = xy[v, u, 0], xy[v, u, 1], np.float64(depth[v, u])
            keep = transmittance(d * math.sqrt(1.0 + x * x + y * y), d * (up[0] * x + up[1] * y + up[2]), sigma,
                                 height, at_eye)  # fmt: skip
            if not keep >= threshold:  # NaN depth too
                hidden[v, u] = True
                continue
            counts[k] += 1
            keep_sum[k] += keep
            bounds[k, 0], bounds[k, 1] = min(bounds[k, 0], u), min(bounds[k, 1], v)
            bounds[k, 2], bounds[k, 3] = max(bounds[k, 2], u), max(bounds[k, 3], v)
    return counts, bounds, keep_sum
