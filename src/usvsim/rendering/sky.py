"""Daylight from the sun's position: Preetham et al. (1999) sky, sun colour through the air mass, twilight.

Everything here is per frame on the CPU (a few dozen numbers); the shaders evaluate the sky per pixel with
`sky_radiance` in shaders.py from these coefficients. Radiance is in display units: the clear noon zenith
is about 0.5 before exposure, a white surface under the noon sun about 0.9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.config.rendering import Rendering, sun_angles_deg, sun_direction_enu

SKY_SCALE = 1.0 / 24.0  # kcd/m² → display units
_PREETHAM = {  # distribution coefficients (A..E) = a·T + b for luminance Y and chromaticities x, y
    "Y": ((0.1787, -1.4630), (-0.3554, 0.4275), (-0.0227, 5.3251), (0.1206, -2.5771), (-0.0670, 0.3703)),
    "x": ((-0.0193, -0.2592), (-0.0665, 0.0008), (-0.0004, 0.2125), (-0.0641, -0.8989), (-0.0033, 0.0452)),
    "y": ((-0.0167, -0.2608), (-0.0950, 0.0092), (-0.0079, 0.2102), (-0.0441, -1.6537), (-0.0109, 0.0529)),
}
_ZENITH_X = (
    (0.00166, -0.00375, 0.00209, 0.0),
    (-0.02903, 0.06377, -0.03202, 0.00394),
    (0.11693, -0.21196, 0.06052, 0.25886),
)
_ZENITH_Y = (
    (0.00275, -0.00610, 0.00317, 0.0),
    (-0.04214, 0.08970, -0.04153, 0.00516),
    (0.15346, -0.26756, 0.06670, 0.26688),
)
_XYZ_TO_RGB = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])
_EXTINCTION = np.array([0.045, 0.075, 0.14])  # optical depth of a clear vertical atmosphere, R, G, B (T = 2)
NIGHT_SKY = np.array([0.004, 0.006, 0.012])  # moonless clear night, display units


@dataclass(frozen=True)
class Daylight:
    """What the shaders and MuJoCo's lights need for one frame (directions ENU, colours linear RGB)."""

    sun_dir: np.ndarray  # unit vector toward the sun
    sun_color: np.ndarray  # irradiance of the sun on a surface facing it, display units
    ambient: np.ndarray  # sky irradiance on an upward surface / π, display units
    coeffs: np.ndarray  # (3, 5) Preetham A..E for Y, x, y
    zenith: np.ndarray  # (3,) zenith Y (display units), x, y
    theta_sun: float  # sun zenith angle used by the distribution (rad, ≤ 89°)
    day: float  # 0 at night, 1 in daylight (twilight ramp from -8° to +4° elevation)
    horizon: np.ndarray  # sky radiance at the horizon away from the sun (haze colour)


def daylight(look: Rendering, latitude_deg: float = 0.0, longitude_deg: float = 0.0) -> Daylight:
    azimuth, elevation = sun_angles_deg(look, latitude_deg, longitude_deg)
    sun_dir = np.array(sun_direction_enu(azimuth, elevation))
    turbidity = look.sky.turbidity
    theta = math.radians(min(90.0 - elevation, 89.0))
    day = _smoothstep(-8.0, 4.0, elevation)
    coeffs = np.array([[a * turbidity + b for a, b in _PREETHAM[c]] for c in "Yxy"])
    chi = (4.0 / 9.0 - turbidity / 120.0) * (math.pi - 2.0 * theta)
    zenith_y = max((4.0453 * turbidity - 4.9710) * math.tan(chi) - 0.2155 * turbidity + 2.4192, 0.05)
    t_vec = np.array([turbidity**2, turbidity, 1.0])
    th = np.array([theta**3, theta**2, theta, 1.0])
    zenith = np.array([zenith_y * SKY_SCALE * day * look.sun.intensity,
                       t_vec @ np.array(_ZENITH_X) @ th, t_vec @ np.array(_ZENITH_Y) @ th])  # fmt: skip
    sun_color = _sun_color(look, elevation, turbidity) * day
    ambient = _rgb_of(zenith[0] * 0.9, zenith[1], zenith[2]) + NIGHT_SKY
    horizon = _sky_rgb(coeffs, zenith, theta, math.radians(88.0), math.radians(120.0)) + NIGHT_SKY
    grey = float(horizon @ (0.3, 0.6, 0.1))
    horizon = 0.4 * horizon + 0.6 * grey * np.array([0.88, 0.95, 1.05])  # Preetham's horizon leans purple
    return Daylight(sun_dir, sun_color, ambient, coeffs, zenith, theta, day, horizon)


def _sun_color(look: Rendering, elevation_deg: float, turbidity: float) -> np.ndarray:
    """Sun irradiance colour through the air mass (Kasten–Young), or the look's colour if it gives one."""
    if look.sun.color is not None:
        return np.array(look.sun.color) * look.sun.intensity
    z = 90.0 - max(elevation_deg, -1.0)
    air_mass = 1.0 / (math.cos(math.radians(min(z, 90.0))) + 0.50572 * (96.07995 - z) ** -1.6364)
    return 1.05 * np.exp(-_EXTINCTION * (turbidity / 2.0) ** 0.7 * air_mass) * look.sun.intensity


def _perez(c: np.ndarray, theta, gamma):
    return (1 + c[0] * np.exp(c[1] / np.maximum(np.cos(theta), 0.01))) * (
        1 + c[2] * np.exp(c[3] * gamma) + c[4] * np.cos(gamma) ** 2
    )


def _sky_rgb(coeffs, zenith, theta_sun, theta, gamma) -> np.ndarray:
    """Preetham sky radiance (..., 3) for view zenith angles `theta` and angles `gamma` from the sun (rad)."""
    values = [
        zenith[i] * _perez(coeffs[i], theta, gamma) / _perez(coeffs[i], 0.0, theta_sun) for i in range(3)
    ]
    return _rgb_of(*values)


def _rgb_of(luminance, x, y) -> np.ndarray:
    luminance, x, y = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (luminance, x, y)))
    xyz = np.stack([x * luminance / y, luminance, (1 - x - y) * luminance / y], axis=-1)
    return np.maximum(xyz @ _XYZ_TO_RGB.T, 0.0)


def sky_table(light: Daylight, size: int = 64) -> np.ndarray:
    """Sky radiance (size, size, 3) float32 over the upper hemisphere for the shaders' `u_sky`: texel (u, v)
    holds direction d with (d.x, d.y) / (1 + d.z) = 2 (u, v) - 1 (a stereographic map; outside: the horizon)."""
    s = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    px, py = np.meshgrid(s, s)  # rows: v (y), columns: u (x)
    rho2 = np.minimum(px**2 + py**2, 1.0)
    z = (1.0 - rho2) / (1.0 + rho2)
    dirs = np.stack([px * (1.0 + z), py * (1.0 + z), z], axis=-1)
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    gamma = np.arccos(np.clip(dirs @ light.sun_dir, -1.0, 1.0))
    theta = np.arccos(np.clip(dirs[..., 2], math.sin(math.radians(0.1)), 1.0))
    rgb = _sky_rgb(light.coeffs, light.zenith, light.theta_sun, theta, gamma)
    grey = (rgb @ np.array([0.3, 0.6, 0.1]))[..., None] * np.array([0.88, 0.95, 1.05])
    low = (1.0 - dirs[..., 2:3]) ** 8  # Preetham's horizon leans purple: toward blue-grey there
    return (rgb + 0.6 * low * (grey - rgb) + NIGHT_SKY).astype(np.float32)


def hazy_sky_table(light: Daylight, haze_depth: float, size: int = 256) -> np.ndarray:
    """`sky_table` with the sun's aureole, seen through the clear-air haze (optical depth `haze_depth` toward the
    zenith, / sin(elevation) toward the horizon), for the sky shader and the water's reflections alike."""
    s = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    px, py = np.meshgrid(s, s)
    rho2 = px**2 + py**2
    z = (1.0 - rho2) / (1.0 + rho2)  # outside the disc (below the horizon): the horizon's haze
    dirs = np.stack([px * (1.0 + z), py * (1.0 + z), z], axis=-1)
    cos_sun = dirs @ light.sun_dir / np.linalg.norm(dirs, axis=-1)
    sky = sky_table(light, size) + 0.12 * np.maximum(cos_sun, 0.0)[..., None] ** 200 * light.sun_color
    clear = np.exp(-haze_depth / np.maximum(z, 1e-3))[..., None]
    return (light.horizon * (1.0 - clear) + sky * clear).astype(np.float32)


def _smoothstep(lo: float, hi: float, v: float) -> float:
    t = min(max((v - lo) / (hi - lo), 0.0), 1.0)
    return t * t * (3 - 2 * t)
