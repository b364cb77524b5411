"""Applies a look (the `rendering:` section, docs/rendering.md) to a camera frame: the one adapter between
the randomization and the renderer.

With `renderer: shader` the camera draws the look itself (sun, sky, haze, fog, water, exposure,
vignetting, blur: usvsim.rendering) and only the look's noise is added here. With `renderer: mujoco` this
module approximates it with MuJoCo's plain renderer: the sun is the model's directional light
(direction from azimuth/elevation, colour warmer when low, scaled by `intensity`), fog is blended into the
image in linear light from the depth image by Koschmieder's law (contrast 2 % at the visibility; the sky counts as
1 km; the fog colour is linear RGB, as for the shader look),
and the camera effects (exposure, vignetting, blur, noise) are applied to the 8-bit image. Sky turbidity,
haze and the water look are not approximated. Switching to the shader renderer changes only this module;
the randomization file format stays the same.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from usvsim.config.rendering import Rendering, sun_angles_deg, sun_direction_enu
from usvsim.datasets.look_kernels import finish_look, to_uint8_noisy

KOSCHMIEDER = 3.912  # extinction coefficient x visibility at 2 % contrast
SKY_FOG_M = 1000.0  # the sky counts as this far away in fog
NOISE_BANK_FRAMES = 4  # image noise: a window of a fixed bank of normals, 4 frames long, at a drawn offset


def gaussian_blur(img: np.ndarray, sigma_px: float) -> np.ndarray:
    """Separable Gaussian blur of an (H, W, 3) float32 image (radius 3σ, edges repeated; OpenCV)."""
    import cv2

    r = max(1, int(math.ceil(3.0 * sigma_px)))
    return cv2.GaussianBlur(img, (2 * r + 1, 2 * r + 1), sigma_px, borderType=cv2.BORDER_REPLICATE)


def noise_window(bank: np.ndarray, shape, rng: np.random.Generator) -> np.ndarray:
    """Standard-normal noise of `shape` (float32): a contiguous window of `bank` at an offset drawn from
    `rng` (a draw of 900 k fresh normals per frame cost more than the rest of the look)."""
    n = int(np.prod(shape))
    start = int(rng.integers(0, bank.size - n + 1))
    return bank[start : start + n].reshape(shape)


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
        self.bank = np.random.default_rng(0x5EED).standard_normal(
            NOISE_BANK_FRAMES * cam.height * cam.width * 3, dtype=np.float32
        )
        h, w = cam.height, cam.width  # per-pixel ray length scale and vignetting radius
        xy = cam.rays()  # the published (distorted) pixels' rays: distance = depth · ray_scale
        self.ray_scale = np.sqrt(1.0 + (xy**2).sum(axis=2)).astype(np.float32)
        v, u = np.mgrid[0:h, 0:w].astype(np.float32)
        self.radius2 = ((u - (w - 1) / 2) ** 2 + (v - (h - 1) / 2) ** 2) / ((w / 2) ** 2 + (h / 2) ** 2)

    def before(self, look: Rendering) -> None:
        self.sim.look = look
        if look.renderer == "shader":
            return
        origin = self.sim.scenario.world.origin
        az, el = sun_angles_deg(look, origin.latitude_deg, origin.longitude_deg)
        m = self.sim.model
        m.light_dir[self.sun] = -np.asarray(sun_direction_enu(az, el))
        color = np.asarray(look.sun.color) if look.sun.color is not None else sun_color(el)
        daylight = look.sun.intensity * max(0.15, math.sin(math.radians(max(el, 0.0))) ** 0.5)
        m.light_diffuse[self.sun] = np.clip(self.base_diffuse * color * daylight, 0.0, 1.0)

    def after(
        self, look: Rendering, rgb: np.ndarray, depth: np.ndarray, rng: np.random.Generator
    ) -> np.ndarray:
        """Fog, exposure, vignetting, blur and noise on an (H, W, 3) uint8 image; returns a new image. Under the
        shader look the camera drew all but the noise. Thread-safe (worker threads call it)."""
        h, w = depth.shape
        cam = look.camera
        noise = (
            noise_window(self.bank, (h, w, 3), rng) if cam.noise_stddev > 0 else np.empty((0, 0, 3), np.float32)
        )
        if look.renderer == "shader":
            out = np.empty((h, w, 3), np.uint8)
            to_uint8_noisy(rgb.astype(np.float32) / np.float32(255.0), noise, np.float32(cam.noise_stddev), out)
            return out
        fog = look.fog.visibility_m
        img = np.empty((h, w, 3), np.float32)  # exposure on gamma-encoded values: 2^ev in linear light
        finish_look(rgb, depth, self.ray_scale, KOSCHMIEDER / fog if fog else 0.0, np.asarray(look.fog.color, np.float32),
                    SKY_FOG_M, 2.0 ** (cam.exposure_ev / 2.2), (cam.vignetting * self.radius2).astype(np.float32), img)  # fmt: skip
        if cam.blur_sigma_px > 0:
            img = gaussian_blur(img, cam.blur_sigma_px)
        out = np.empty((h, w, 3), np.uint8)
        to_uint8_noisy(img, noise, np.float32(cam.noise_stddev), out)
        return out
