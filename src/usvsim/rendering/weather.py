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


def fog_extinction_per_m(look) -> float:
    """The shader look's fog extinction at sea level (1/m): Koschmieder's 3.912 / `fog.visibility_m` (contrast 2 %
    at the visibility; 0 without fog) plus the rain's. Shared by the fog pass (marine.py) and the labels
    (datasets/fog_sight.py)."""
    fog = 0.0 if look.fog.visibility_m is None else 3.912 / look.fog.visibility_m
    return fog + extinction_per_m(look.rain.rate_mm_h)  # rain thins the air like fog


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


def blur_along(rgb: np.ndarray, flow_u: np.ndarray, flow_v: np.ndarray, depth_m: np.ndarray | None = None,
               labels: np.ndarray | None = None) -> None:  # fmt: skip
    """In place: motion blur from each pixel's image motion during the exposure (`flow_u`, `flow_v`: pixels, u right,
    v down, the segment centred on the pixel's place in the frame). Without `depth_m` (m; NaN or inf: far) and
    `labels` (the segmentation image: one id per object part, 0 the water and sky): each pixel the mean of
    ceil(|flow|) samples (at most 32) of the image on its flow's segment, nearest pixel, clamped at the border.
    With them, two layers per pixel, where another labelled thing lies nearer (2 % of the depth):
    - its own: that mean, leaving out the samples of such nearer things (they hid the scene passing through the
      pixel, whose colour the frame does not hold);
    - the nearer things that sweep over it: a nearer pixel Y whose own segment passes through this pixel covers it
      for 1/|flow_Y| of the exposure (one pixel of its path); those shares, searched along the largest flow of a
      labelled thing (label > 0) in the neighbourhood (tiles of the image's largest half flow, 4-32 px, and their
      3 x 3 neighbours; after McGuire et al. 2012's reconstruction filter), add up to the part of
      the exposure the near layer hides this one (at most all of it), and its colours come in by them.
    So a vessel crossing a still scene smears over the background beside it (a moving box's edges become the ramps
    of its exposure: tests/rendering/test_weather.py), while a still thing in front of a moving background (the
    camera's own pontoons) keeps its bytes and does not bleed into the water. Pixels whose neighbourhood moves less
    than a pixel are left as they are."""
    if rgb.size == 0:
        return
    fu, fv = np.ascontiguousarray(flow_u, np.float32), np.ascontiguousarray(flow_v, np.float32)
    top = math.sqrt(_max_speed2(fu, fv))
    if top < 1.0:
        return
    layered = depth_m is not None and labels is not None
    depth = np.ascontiguousarray(depth_m, np.float32) if layered else np.ones((1, 1), np.float32)
    ids = np.ascontiguousarray(labels) if layered else np.zeros((1, 1), np.int32)
    tile = int(min(max(math.ceil(top / 2.0), 4), 32))
    _blur_layers(rgb, rgb.copy(), fu, fv, depth, ids, tile, layered)


@njit(cache=True, nogil=True)
def _max_speed2(flow_u, flow_v):
    top = 0.0
    for i in range(flow_u.shape[0]):
        for j in range(flow_u.shape[1]):
            top = max(top, flow_u[i, j] * flow_u[i, j] + flow_v[i, j] * flow_v[i, j])
    return top


@njit(cache=True, nogil=True)
def _depth(depth, r, c):
    """The depth (m) at a pixel, far (inf) where none (NaN, inf, <= 0)."""
    z = depth[r, c]
    return z if z > 0.0 and z < math.inf else math.inf


NEAR = 0.98  # a pixel is in front of another when its depth is under this share of the other's
ACROSS_PX = 0.75  # how far (px) a pixel may lie beside a segment and be on it: the search's rounding (up to 1/√2)


@njit(cache=True, nogil=True)
def _neighbourhood(flow_u, flow_v, labels, tile, layered):
    """Per tile of `tile` px, over it and its 3 x 3 neighbours: the largest flow (u, v); the largest flow of a
    labelled thing (label > 0; 0 is the water and sky), along which a pixel looks for things sweeping over it; and
    whether more than one label is seen (never without `layered`)."""
    h, w = flow_u.shape
    th, tw = (h + tile - 1) // tile, (w + tile - 1) // tile
    most = np.zeros((th, tw, 6))  # largest flow u, v, |.|²; largest of labelled things u, v, |.|²
    first = np.full((th, tw), -1, np.int64)
    mixed = np.zeros((th, tw), np.bool_)
    for r in range(h):
        t = r // tile
        for c in range(w):
            s = c // tile
            u, v = flow_u[r, c], flow_v[r, c]
            f2 = u * u + v * v
            if f2 > most[t, s, 2]:
                most[t, s, 0], most[t, s, 1], most[t, s, 2] = u, v, f2
            if not layered:
                continue
            if labels[r, c] > 0 and f2 > most[t, s, 5]:
                most[t, s, 3], most[t, s, 4], most[t, s, 5] = u, v, f2
            if first[t, s] < 0:
                first[t, s] = labels[r, c]
            elif labels[r, c] != first[t, s]:
                mixed[t, s] = True
    near = np.zeros((th, tw, 4))  # the same over the 3 x 3 tiles: u, v of the largest; u, v of things' largest
    nmixed = np.zeros((th, tw), np.bool_)
    for t in range(th):
        for s in range(tw):
            best = best_thing = -1.0
            for a in range(max(t - 1, 0), min(t + 2, th)):
                for b in range(max(s - 1, 0), min(s + 2, tw)):
                    if most[a, b, 2] > best:
                        best, near[t, s, 0], near[t, s, 1] = most[a, b, 2], most[a, b, 0], most[a, b, 1]
                    if most[a, b, 5] > best_thing:
                        best_thing, near[t, s, 2], near[t, s, 3] = most[a, b, 5], most[a, b, 3], most[a, b, 4]
                    if mixed[a, b] or first[a, b] != first[t, s]:
                        nmixed[t, s] = True
    return near, nmixed


@njit(cache=True, nogil=True)
def _blur_layers(out, src, flow_u, flow_v, depth, labels, tile, layered):
    h, w = src.shape[0], src.shape[1]
    near, nmixed = _neighbourhood(flow_u, flow_v, labels, tile, layered)
    for r in range(h):
        t = r // tile
        for col in range(w):
            s = col // tile
            if near[t, s, 0] * near[t, s, 0] + near[t, s, 1] * near[t, s, 1] < 1.0:
                continue
            if nmixed[t, s]:  # another thing in the neighbourhood
                _layered_pixel(out, src, flow_u, flow_v, depth, labels, r, col, near[t, s, 2], near[t, s, 3], tile)
                continue
            fu, fv = flow_u[r, col], flow_v[r, col]
            steps = int(min(math.ceil(math.sqrt(fu * fu + fv * fv)), 32.0))
            if steps < 2:
                continue
            a0 = a1 = a2 = 0
            for k in range(steps):
                q = -0.5 + k / (steps - 1)
                rr = min(max(r + int(math.floor(fv * q + 0.5)), 0), h - 1)
                cc = min(max(col + int(math.floor(fu * q + 0.5)), 0), w - 1)
                a0 += src[rr, cc, 0]
                a1 += src[rr, cc, 1]
                a2 += src[rr, cc, 2]
            half = steps // 2
            out[r, col, 0] = (a0 + half) // steps
            out[r, col, 1] = (a1 + half) // steps
            out[r, col, 2] = (a2 + half) // steps


@njit(cache=True, nogil=True)
def _layered_pixel(out, src, flow_u, flow_v, depth, labels, r, col, search_u, search_v, tile):
    """One pixel of `_blur_layers` where more than one label is near: its own layer without the nearer things'
    samples, and the share of the exposure nearer things sweeping over it hide it (see `blur_along`)."""
    h, w = src.shape[0], src.shape[1]
    zx, lx = _depth(depth, r, col), labels[r, col]
    fu, fv = flow_u[r, col], flow_v[r, col]
    steps = int(min(math.ceil(math.sqrt(fu * fu + fv * fv)), 32.0))
    a0 = a1 = a2 = n = 0
    if steps >= 2:
        for k in range(steps):
            q = -0.5 + k / (steps - 1)
            rr = min(max(r + int(math.floor(fv * q + 0.5)), 0), h - 1)
            cc = min(max(col + int(math.floor(fu * q + 0.5)), 0), w - 1)
            if labels[rr, cc] != lx and _depth(depth, rr, cc) < NEAR * zx:
                continue
            a0 += src[rr, cc, 0]
            a1 += src[rr, cc, 1]
            a2 += src[rr, cc, 2]
            n += 1
    if n == 0:
        a0, a1, a2, n = src[r, col, 0], src[r, col, 1], src[r, col, 2], 1
    cover = f0 = f1 = f2 = 0.0
    norm = math.sqrt(search_u * search_u + search_v * search_v)
    du, dv = search_u / max(norm, 1e-9), search_v / max(norm, 1e-9)
    reach = int(math.ceil(min(0.5 * norm, tile))) if norm >= 1.0 else 0
    for j in range(-reach, reach + 1):
        yr = r + int(math.floor(dv * j + 0.5))
        yc = col + int(math.floor(du * j + 0.5))
        if j == 0 or yr < 0 or yr >= h or yc < 0 or yc >= w:
            continue
        if labels[yr, yc] == lx or not _depth(depth, yr, yc) < NEAR * zx:
            continue
        vu, vv = flow_u[yr, yc], flow_v[yr, yc]
        len2 = vu * vu + vv * vv
        if len2 < 1.0:
            continue
        dx, dy = col - yc, r - yr
        if abs(dx * vu + dy * vv) > 0.5 * len2 or abs(dx * vv - dy * vu) > ACROSS_PX * math.sqrt(len2):
            continue  # this pixel is not on Y's segment (along it, or across it)
        share = 1.0 / math.sqrt(len2)
        cover += share
        f0 += share * src[yr, yc, 0]
        f1 += share * src[yr, yc, 1]
        f2 += share * src[yr, yc, 2]
    if cover == 0.0:
        if steps >= 2:
            half = n // 2
            out[r, col, 0] = (a0 + half) // n
            out[r, col, 1] = (a1 + half) // n
            out[r, col, 2] = (a2 + half) // n
        return
    if cover > 1.0:
        f0, f1, f2, cover = f0 / cover, f1 / cover, f2 / cover, 1.0
    rest = (1.0 - cover) / n
    out[r, col, 0] = int(f0 + rest * a0 + 0.5)
    out[r, col, 1] = int(f1 + rest * a1 + 0.5)
    out[r, col, 2] = int(f2 + rest * a2 + 0.5)


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
                   v_optical, omega_optical, moving: tuple | None = None, labels: np.ndarray | None = None) -> None:  # fmt: skip
    """In place, in the order a camera suffers them: motion blur of the scene (`motion_field` from the camera's
    velocities `v_optical` m/s and `omega_optical` rad/s in its optical frame, the depth image `depth_m` (None:
    all at infinity), the pixels of moving things, `moving`, and the segmentation `labels`, which let
    near things sweep over what lies behind them), rain in front of it, drops on the lens (the
    look's `camera.motion_blur_ms`, `rain`, `camera.droplets`). `intrinsics`: fx, fy, cx, cy (pixels)."""
    fx, fy, cx, cy = (float(v) for v in intrinsics)
    if look.camera.motion_blur_ms > 0:
        depth = depth_m if depth_m is not None else np.full(rgb.shape[:2], np.inf, np.float32)
        exposure = look.camera.motion_blur_ms * 1e-3
        blur_along(rgb, *motion_field(depth, v_optical, omega_optical, fx, fy, cx, cy, exposure, moving), depth, labels)
    rain_streaks(rgb, look.rain.rate_mm_h, look.rain.slant_deg, fx, seed, name, time_ns)
    lens_droplets(rgb, look.camera.droplets, seed, name, time_ns * 1e-9)
