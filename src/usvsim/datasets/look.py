"""Applies a look (the `rendering:` section, docs/rendering.md) to a camera frame: the one adapter between
the randomization and the renderer.

`SHADER_DRAWS_LOOK` says whether the camera renderer draws the look itself (the [rendering] shader). Until
it does, this module approximates it with MuJoCo's plain renderer: the sun is the model's directional light
(direction from azimuth/elevation, colour warmer when low, scaled by `intensity`), fog is blended into the
image from the depth image by Koschmieder's law (contrast 2 % at the visibility; the sky counts as 1 km),
and the camera effects (exposure, vignetting, blur, noise) are applied to the 8-bit image. Sky turbidity,
haze and the water look are not approximated. Switching to the shader renderer changes only this module;
the randomization file format stays the same.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from scipy.ndimage import gaussian_filter

from usvsim.config.rendering import Rendering, sun_angles_deg, sun_direction_enu

SHADER_DRAWS_LOOK = False
KOSCHMIEDER = 3.912  # extinction coefficient x visibility at 2 % contrast


def sun_color(elevation_deg: float) -> np.ndarray:
    """White at high sun, orange near the horizon (a simple stand-in for the shader's daylight model)."""
    s = float(
        np.clip(math.sin(math.radians(max(elevation_deg, 0.0))) / math.sin(math.radians(30.0)), 0.0, 1.0)
    )
    return np.array([1.0, 0.72 + 0.28 * s, 0.45 + 0.55 * s])


class LookAdapter:
    """Puts a look on a camera's MuJoCo renderer before a frame and on its image after."""

    def __init__(self, sim, renderer, cam):
        self.sim, self.renderer, self.cam = sim, renderer, cam
        m = sim.model
        self.sun = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_LIGHT, "sun")
        self.base_diffuse = m.light_diffuse[self.sun].copy()
        self.vignette: np.ndarray | None = None
        self.ray_scale: np.ndarray | None = None

    def before(self, look: Rendering) -> None:
        self.sim.look = look
        if SHADER_DRAWS_LOOK:
            return
        origin = self.sim.scenario.world.origin
        az, el = sun_angles_deg(look, origin.latitude_deg, origin.longitude_deg)
        m = self.sim.model
        m.light_dir[self.sun] = -np.asarray(sun_direction_enu(az, el))
        color = np.asarray(look.sun.color) if look.sun.color is not None else sun_color(el)
        daylight = look.sun.intensity * max(0.15, math.sin(math.radians(max(el, 0.0))) ** 0.5)
        m.light_diffuse[self.sun] = np.clip(self.base_diffuse * color * daylight, 0.0, 1.0)

    def after(
        self, look: Rendering, rgb: np.ndarray, depth: np.ndarray | None, rng: np.random.Generator
    ) -> np.ndarray:
        """The camera effects and the fogged sky on an (H, W, 3) uint8 image; returns a new image."""
        if SHADER_DRAWS_LOOK:
            return rgb
        img = rgb.astype(np.float32) / 255.0
        if look.fog.visibility_m is not None and depth is not None:
            img = self._fog(img, depth, look)
        cam = look.camera
        gain = 2.0 ** (cam.exposure_ev / 2.2)  # on gamma-encoded values: 2^ev in linear light
        if cam.vignetting > 0:
            img *= gain * self._vignette(img.shape[:2], cam.vignetting)[..., None]
        elif gain != 1.0:
            img *= gain
        if cam.blur_sigma_px > 0:
            img = gaussian_filter(img, sigma=(cam.blur_sigma_px, cam.blur_sigma_px, 0), mode="nearest")
        if cam.noise_stddev > 0:
            img *= 1.0 + cam.noise_stddev * rng.standard_normal(img.shape, dtype=np.float32)
        return (np.clip(img, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)

    def _fog(self, img: np.ndarray, depth: np.ndarray, look: Rendering) -> np.ndarray:
        """Koschmieder: what is seen at distance d keeps exp(-3.912 d / V) of its contrast, the rest is fog
        colour; the sky (no depth) is a kilometre of fog away."""
        if self.ray_scale is None or self.ray_scale.shape != depth.shape:
            xy = self.cam.rays()  # the published (distorted) pixels' rays
            self.ray_scale = np.sqrt(1.0 + (xy**2).sum(axis=2)).astype(np.float32)  # distance / optical z
        d = np.where(np.isnan(depth), 1000.0, depth * self.ray_scale)
        keep = np.exp(-KOSCHMIEDER / look.fog.visibility_m * d).astype(np.float32)[..., None]
        return img * keep + (1.0 - keep) * np.asarray(look.fog.color, np.float32)

    def _vignette(self, shape, strength: float) -> np.ndarray:
        """Brightness factor, 1 at the centre and 1 - strength at the corners (cos⁴-like falloff)."""
        if self.vignette is None or self.vignette.shape != shape:
            v, u = np.mgrid[0 : shape[0], 0 : shape[1]].astype(np.float32)
            r2 = ((u - (shape[1] - 1) / 2) ** 2 + (v - (shape[0] - 1) / 2) ** 2) / (
                (shape[1] / 2) ** 2 + (shape[0] / 2) ** 2
            )
            self.vignette = r2
        return 1.0 - strength * self.vignette
