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
- **Motion blur** (`camera.motion_blur_ms`): each pixel smeared along the image motion that the camera's own
  motion gives it during the exposure (`motion_field`): the camera frame's linear and angular velocity (from its
  vessel's rigid-body state, in the optical frame) and the pixel's depth, through the instantaneous motion field
  of a pinhole camera over a static scene (Longuet-Higgins & Prazdny 1980). Translation blurs near things more
  than far ones (the sky, depth NaN, not at all), yaw and pitch shift the whole image, roll turns it about the
  principal point. Things that move (vessels, buoys: each pixel's rigid body, from the segmentation labels) add
  their own velocity at the pixel's surface point, so the camera's own vessel, moving with it, stays sharp. A
  camera at rest over a scene at rest is not touched (same bytes).
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


def blur_along(rgb: np.ndarray, flow_u: np.ndarray, flow_v: np.ndarray) -> None:
    """In place: each pixel of an RGB image the mean of ceil(|flow|) samples (at most 32) of the image on the
    segment of its flow (pixels during the exposure, u right, v down), centred on it, nearest pixel, clamped at the
    border. Pixels whose flow is under one pixel are left as they are."""
    if rgb.size == 0 or float(np.max(np.hypot(flow_u, flow_v))) < 1.0:
        return
    _blur_along(rgb, rgb.copy(), flow_u.astype(np.float32), flow_v.astype(np.float32))


@njit(cache=True, nogil=True)
def _blur_along(out, src, flow_u, flow_v):
    h, w = src.shape[0], src.shape[1]
    for r in range(h):
        for col in range(w):
            fu, fv = flow_u[r, col], flow_v[r, col]
            steps = int(min(math.ceil(math.sqrt(fu * fu + fv * fv)), 32.0))
            if steps < 2:
                continue
            a0 = a1 = a2 = 0
            for k in range(steps):
                s = -0.5 + k / (steps - 1)
                rr = min(max(r + int(math.floor(fv * s + 0.5)), 0), h - 1)
                cc = min(max(col + int(math.floor(fu * s + 0.5)), 0), w - 1)
                a0 += src[rr, cc, 0]
                a1 += src[rr, cc, 1]
                a2 += src[rr, cc, 2]
            half = steps // 2
            out[r, col, 0] = (a0 + half) // steps
            out[r, col, 1] = (a1 + half) // steps
            out[r, col, 2] = (a2 + half) // steps


def motion_field(depth_m: np.ndarray, v_optical, omega_optical, fx: float, fy: float, cx: float, cy: float,
                 exposure_s: float, moving: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Image motion (pixels during the exposure; u right, v down) of each pixel seen by a camera moving at
    `v_optical` (m/s) and turning at `omega_optical` (rad/s), both in its optical frame (x right, y down,
    z forward), `depth_m` (H, W) the depth along z (m; NaN or inf: at infinity). With x = (u - cx)/fx,
    y = (v - cy)/fy and a static point's velocity relative to the camera -v - ω × P:
    ẋ = (-v_x + x v_z)/Z + x y ω_x - (1 + x²) ω_y + y ω_z,  ẏ = (-v_y + y v_z)/Z + (1 + y²) ω_x - x y ω_y - x ω_z.
    `moving`: (rows, cols, velocity (n, 3)) the optical-frame velocity (m/s) of the surface points at those
    pixels, whose own motion adds ((V_x - x V_z)/Z, (V_y - y V_z)/Z)."""
    h, w = depth_m.shape
    x = ((np.arange(w, dtype=np.float64) - cx) / fx)[None, :]
    y = ((np.arange(h, dtype=np.float64) - cy) / fy)[:, None]
    vx, vy, vz = (float(c) for c in v_optical)
    wx, wy, wz = (float(c) for c in omega_optical)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_z = np.where(np.isfinite(depth_m) & (depth_m > 0), 1.0 / depth_m, 0.0)
    dx = (-vx + x * vz) * inv_z + x * y * wx - (1.0 + x * x) * wy + y * wz
    dy = (-vy + y * vz) * inv_z + (1.0 + y * y) * wx - x * y * wy - x * wz
    if moving is not None and len(moving[0]):
        r, c, vel = moving
        xs, ys, iz = x[0, c], y[r, 0], inv_z[r, c]
        dx[r, c] += (vel[:, 0] - xs * vel[:, 2]) * iz
        dy[r, c] += (vel[:, 1] - ys * vel[:, 2]) * iz
    return (dx * fx * exposure_s).astype(np.float32), (dy * fy * exposure_s).astype(np.float32)


def camera_weather(rgb: np.ndarray, look, intrinsics, seed: int, name: str, time_ns: int, depth_m: np.ndarray | None,
                   v_optical, omega_optical, moving: tuple | None = None) -> None:  # fmt: skip
    """In place, in the order a camera suffers them: motion blur of the scene (`motion_field` from the camera's
    velocities `v_optical` m/s and `omega_optical` rad/s in its optical frame, the depth image `depth_m` (None:
    all at infinity) and the pixels of moving things, `moving`), rain in front of it, drops on the lens (the
    look's `camera.motion_blur_ms`, `rain`, `camera.droplets`). `intrinsics`: fx, fy, cx, cy (pixels)."""
    fx, fy, cx, cy = (float(v) for v in intrinsics)
    if look.camera.motion_blur_ms > 0:
        depth = depth_m if depth_m is not None else np.full(rgb.shape[:2], np.inf, np.float32)
        exposure = look.camera.motion_blur_ms * 1e-3
        blur_along(rgb, *motion_field(depth, v_optical, omega_optical, fx, fy, cx, cy, exposure, moving))
    rain_streaks(rgb, look.rain.rate_mm_h, look.rain.slant_deg, fx, seed, name, time_ns)
    lens_droplets(rgb, look.camera.droplets, seed, name, time_ns * 1e-9)
