"""Camera effects of weather and motion, on the 8-bit RGB image after it is read back: rain streaks, water
droplets on the lens, motion blur. Depth and labels never see them.

Every random choice comes from a generator seeded by the simulation's seed, the camera's name and (for rain)
the frame's time on the simulation clock, so the same seed and parameters give the same bytes.

- **Rain** (`rendering.rain.rate_mm_h`): drops between the lens and ~20 m, drawn as the streaks they leave
  during the exposure: count per frame ∝ R^0.8 (about 1000 drops per m³ at 10 mm/h, Marshall–Palmer; 0.2 % of
  them drawn as visible streaks, a factor set by eye), length = fall speed (~6 m/s) × exposure (`EXPOSURE_S`) × focal / distance, slanted by
  `rain.slant_deg`, faint (a drop refracts the bright sky above it: it brightens what it crosses). Rain also
  thins the air: extinction 0.25·R^0.63 per km (R in mm/h) adds to the fog (marine.py).
- **Droplets on the lens** (`camera.droplets`, 0–1): round drops of 1.5–6 % of the image height, each a small
  lens that shows the scene inverted and blurred, with a darker rim; they come and go slowly (each its own
  lifetime of 20–60 s of simulated time, phase from the seed).
- **Motion blur** (`camera.motion_blur_ms`): the image smeared along the flow that the camera's rotation
  (from its vessel's angular velocity) makes at the image centre during the exposure; translation and roll
  are left out.
"""

from __future__ import annotations

import math
import zlib

import numpy as np
from numba import njit

EXPOSURE_S = 1.0 / 60.0
FALL_MPS = 6.0
DROPS_PER_M3_AT_10 = 1000.0
MAX_STREAKS = 4000


def extinction_per_m(rate_mm_h: float) -> float:
    """Extinction coefficient of rain (1/m): 0.25·R^0.63 per km (R in mm/h)."""
    return 0.0 if rate_mm_h <= 0 else 0.25e-3 * rate_mm_h**0.63


def _rng(seed: int, name: str, *extra: int) -> np.random.Generator:
    return np.random.default_rng([int(seed) & 0xFFFFFFFF, zlib.crc32(name.encode()), *extra])


def rain_streaks(rgb: np.ndarray, rate_mm_h: float, slant_deg: float, focal_px: float, seed: int, name: str,
                 time_ns: int) -> None:  # fmt: skip
    """In place: the streaks of the drops falling through the view during one exposure."""
    if rate_mm_h <= 0:
        return
    h, w = rgb.shape[:2]
    rng = _rng(seed, name, int(time_ns) & 0xFFFFFFFF, int(time_ns) >> 32)
    # drops in the view frustum from 0.3 m to 20 m: volume ≈ (w·h / f²)·(20³ - 0.3³)/3 m³
    volume = w * h / focal_px**2 * (20.0**3 - 0.3**3) / 3.0
    drops = DROPS_PER_M3_AT_10 * (rate_mm_h / 10.0) ** 0.8 * volume * 0.002  # the visible share (by eye)
    count = min(int(drops), MAX_STREAKS)
    if count == 0:
        return
    dense = drops / count  # more than MAX_STREAKS: each drawn streak stands for several
    dist = 0.3 + 19.7 * rng.random(count) ** (1.0 / 3.0)  # uniform in volume
    x, y = rng.random(count) * w, rng.random(count) * h
    length = np.minimum(FALL_MPS * EXPOSURE_S * focal_px / dist, 0.5 * h)
    width_alpha = np.clip(1.5 / dist, 0.05, 0.4) * dense  # near drops are larger and blurrier: more visible
    slant = math.radians(slant_deg)
    bright = np.minimum(0.5 * rgb.reshape(-1, 3).max(axis=0).astype(np.float32) + 110.0, 255.0)
    _streaks(rgb, x, y, length, width_alpha.astype(np.float32), math.sin(slant), math.cos(slant), bright)


@njit(cache=True, nogil=True)
def _streaks(rgb, x, y, length, alpha, dx, dy, bright):
    """Accumulate the streaks' coverage (24 points each, at most 0.6 per pixel) and blend toward `bright`."""
    h, w = rgb.shape[0], rgb.shape[1]
    cover = np.zeros((h, w), np.float32)
    steps = 24
    for i in range(x.shape[0]):
        weight = alpha[i] * min(length[i], steps) / steps
        for k in range(steps):
            s = -0.5 + k / (steps - 1)
            px = min(max(int(x[i] + dx * length[i] * s), 0), w - 1)
            py = min(max(int(y[i] + dy * length[i] * s), 0), h - 1)
            cover[py, px] += weight
    for r in range(h):
        for c in range(w):
            a = min(cover[r, c], 0.6)
            if a > 0.0:
                for ch in range(3):
                    v = rgb[r, c, ch] * (1.0 - a) + bright[ch] * a
                    rgb[r, c, ch] = np.uint8(min(max(v, 0.0), 255.0))


def lens_droplets(rgb: np.ndarray, amount: float, seed: int, name: str, time_s: float) -> None:
    """In place: water drops on the lens, each showing the scene inverted and blurred through it."""
    if amount <= 0:
        return
    h, w = rgb.shape[:2]
    rng = _rng(seed, name, 17)
    n = int(round(60 * amount))
    cx, cy = rng.random(n) * w, rng.random(n) * h
    radius = h * (0.015 + 0.045 * rng.random(n) ** 2)
    life, phase = 20.0 + 40.0 * rng.random(n), rng.random(n)
    shown = ((time_s / life + phase) % 1.0) < 0.75
    small = rgb[::4, ::4].astype(np.float32)  # a blurred copy: what a drop sees is out of focus
    small = 0.25 * (small + np.roll(small, 1, 0) + np.roll(small, 1, 1) + np.roll(small, (1, 1), (0, 1)))
    out = rgb.astype(np.float32)
    for i in np.flatnonzero(shown):
        r = radius[i]
        x0, x1 = int(max(cx[i] - r, 0)), int(min(cx[i] + r + 1, w))
        y0, y1 = int(max(cy[i] - r, 0)), int(min(cy[i] + r + 1, h))
        if x1 <= x0 or y1 <= y0:
            continue
        yy, xx = np.mgrid[y0:y1, x0:x1].astype(np.float32)
        ux, uy = (xx - cx[i]) / r, (yy - cy[i]) / r
        rho2 = ux * ux + uy * uy
        inside = rho2 < 1.0
        if not inside.any():
            continue
        # a ball lens: the scene inverted, seen from a wider field (x 3), centred a little above the drop
        sx = np.clip((cx[i] - 3.0 * r * ux) / 4, 0, small.shape[1] - 1).astype(np.int64)
        sy = np.clip((cy[i] - 2.0 * r - 3.0 * r * uy) / 4, 0, small.shape[0] - 1).astype(np.int64)
        seen = small[sy, sx] * 0.95
        rim = np.clip((rho2 - 0.6) / 0.4, 0.0, 1.0)[..., None]
        seen = seen * (1.0 - 0.3 * rim)  # the rim bends light away: darker
        glint = np.exp(-((ux + 0.35) ** 2 + (uy + 0.4) ** 2) / 0.015)[..., None] * 50.0
        edge = np.clip((1.0 - rho2) / 0.1, 0.0, 1.0)[..., None]
        block = out[y0:y1, x0:x1]
        out[y0:y1, x0:x1] = np.where(inside[..., None], block * (1 - edge) + (seen + glint) * edge, block)
    rgb[:] = np.clip(out, 0, 255).astype(np.uint8)


def motion_blur(rgb: np.ndarray, flow_px: tuple[float, float]) -> None:
    """In place: the average of the image shifted along `flow_px` (pixels during the exposure), centred."""
    fx, fy = flow_px
    steps = int(min(math.ceil(math.hypot(fx, fy)), 32))
    if steps < 2:
        return
    h, w = rgb.shape[:2]
    shifts = [(int(round(fx * s)), int(round(fy * s))) for s in np.linspace(-0.5, 0.5, steps)]
    px, py = max(abs(dx) for dx, _ in shifts), max(abs(dy) for _, dy in shifts)
    padded = np.pad(rgb, ((py, py), (px, px), (0, 0)), mode="edge")
    acc = np.zeros(rgb.shape, np.uint16)  # at most 32 x 255
    for dx, dy in shifts:
        acc += padded[py + dy : py + dy + h, px + dx : px + dx + w]
    rgb[:] = ((acc + steps // 2) // steps).astype(np.uint8)


def rotation_flow(omega_optical: np.ndarray, focal_px: float, exposure_s: float) -> tuple[float, float]:
    """Image flow (pixels) at the image centre during the exposure for the camera turning at `omega_optical`
    (rad/s, optical frame: x right, y down, z forward): a fixed direction moves by (-ω_y, ω_x)·f·t."""
    return -float(omega_optical[1]) * focal_px * exposure_s, float(omega_optical[0]) * focal_px * exposure_s


def camera_weather(rgb: np.ndarray, look, focal_px: float, seed: int, name: str, time_ns: int,
                   omega_optical: np.ndarray) -> None:  # fmt: skip
    """In place, in the order a camera suffers them: motion blur of the scene, rain in front of it, drops on
    the lens (the look's `camera.motion_blur_ms`, `rain`, `camera.droplets`)."""
    if look.camera.motion_blur_ms > 0:
        motion_blur(rgb, rotation_flow(omega_optical, focal_px, look.camera.motion_blur_ms * 1e-3))
    rain_streaks(rgb, look.rain.rate_mm_h, look.rain.slant_deg, focal_px, seed, name, time_ns)
    lens_droplets(rgb, look.camera.droplets, seed, name, time_ns * 1e-9)
