"""The sea's short waves that the physics does not resolve, as a normals-only render band; whitecap coverage.

The FFT field's shortest band stops at its Nyquist wavenumber k0 = π N / L (about 1.3 m waves in sea state 4),
while a real sea keeps a saturation range of shorter wind waves whose slopes add about as much again to the
mean square slope (Phillips: S(k) ∝ k⁻³, so each e-fold of k adds the same slope variance β). From the onboard
camera those short waves are what shows: without them a sea state 4 reads as a smooth, glassy swell.

`DetailBand` continues the physics' own spectrum past k0: β is measured on the top octave of the shortest band
(slope variance per e-fold), the mean direction too, and the band fills k0 ... 4 k0 on a tile L/8 with
β·D(θ)/k⁴ (D: cos^(2s)(Δθ/2), s = 4, broader than the long waves). Its phases come from a generator seeded by
the physics' own amplitudes (so the seed decides them; same seed, same bytes), its waves move with deep-water
dispersion ω = √(g k), and it is drawn only as slopes (its heights are millimetres to centimetres): it does not
move the surface that depth and labels hold, and the physics never sees it.

`whitecap_threshold`: Monahan & O'Muircheartaigh (1980) give the sea's whitecap fraction W = 3.84e-6 U^3.41 for a
wind U (m/s) at 10 m; U comes from the sea's own Hs through the fully developed Pierson–Moskowitz relation
Hs = 0.21 U²/g, and the threshold is the resolved slope that a fraction W of the surface exceeds (Rayleigh:
P(|∇h| > τ) = exp(-τ²/σ²)), weighed by the shader's breaking noise (crests break here and there).
"""

from __future__ import annotations

import math
import zlib

import numpy as np

G = 9.81
SPREAD_S = 4.0
SPAN = 4.0  # the band covers k0 ... SPAN·k0 (the top at 4 texels per wavelength of its tile)
TILE_RATIO = 8.0  # its tile is the shortest physics tile / this


def fft_waves(ocean):
    """The ocean's FFT wave field, or None (other fields get no detail band)."""
    waves = getattr(ocean, "waves", None)
    return waves if waves is not None and hasattr(waves, "tiles") and hasattr(waves, "_amp") else None


class DetailBand:
    """Slope tiles (N, N) of the unresolved short waves of an FFT field, at any time."""

    def __init__(self, waves):
        amp, kx, ky = waves._amp[-1], waves._kx[-1], waves._ky[-1]  # the shortest band's bins (ocean/fft.py)
        self.n = n = int(waves.n)
        last = float(waves.sizes[-1])
        k0 = math.pi * n / last
        var = 0.5 * np.abs(amp) ** 2
        k = np.hypot(kx, ky)
        top = (k >= 0.5 * k0) & (k < k0)
        slope_var = float(np.sum(var[top] * k[top] ** 2))
        self.beta = slope_var / math.log(2.0)  # slope variance per e-fold of k
        theta = np.arctan2(ky, kx)
        self.direction = float(
            np.arctan2(np.sum(var[top] * np.sin(theta[top])), np.sum(var[top] * np.cos(theta[top])))
        )
        self.size_m = last / TILE_RATIO
        k1 = 2.0 * math.pi * np.fft.fftfreq(n, d=self.size_m / n)
        dx, dy = np.meshgrid(k1, k1)
        dk = np.hypot(dx, dy)
        band = (dk >= k0) & (dk < SPAN * k0)
        spread = np.cos(0.5 * (np.arctan2(dy, dx) - self.direction)) ** (2 * SPREAD_S)
        weight = np.where(band, spread / np.maximum(dk, 1e-9) ** 4, 0.0)
        total = float(np.sum(weight * dk**2))
        target = self.beta * math.log(SPAN)
        dvar = weight * (target / total if total > 0 else 0.0)
        seed = zlib.crc32(np.ascontiguousarray(amp).tobytes())
        phase = np.random.default_rng(seed).random((n, n))
        a = np.sqrt(2.0 * dvar) * np.exp(2j * math.pi * phase)
        self._ax, self._ay = 1j * dx * a, 1j * dy * a  # slope spectra ∂/∂x, ∂/∂y
        self._omega = np.sqrt(G * dk)
        self.slope_var = float(np.sum(dvar * dk**2))

    def slopes(self, t: float) -> np.ndarray:
        """(N, N, 2) float32 ∂h/∂x, ∂h/∂y [iy, ix] at time t (s), unscaled by the start-up ramp (as the tiles)."""
        turn = np.exp(-1j * self._omega * t) * float(self.n * self.n)
        sx = np.fft.ifft2(self._ax * turn).real
        sy = np.fft.ifft2(self._ay * turn).real
        return np.stack([sx, sy], axis=-1).astype(np.float32)


def resolved_statistics(waves) -> tuple[float, float]:
    """(Hs in m, mean square slope of the shortest band) of the physics' resolved sea (without the ramp); the
    slope as the renderer's slope tiles hold it (central differences: a wave's slope k becomes sin(k h)/h)."""
    var = 0.5 * np.abs(waves._amp) ** 2
    h = (np.asarray(waves.sizes, dtype=float) / waves.n)[:, None, None]
    k2 = (np.sin(waves._kx * h) ** 2 + np.sin(waves._ky * h) ** 2) / h**2
    return 4.0 * math.sqrt(float(var.sum())), float(np.sum(var[-1] * k2[-1]))


def whitecap_fraction(hs_m: float) -> float:
    """Monahan's whitecap fraction for the wind of a fully developed sea of significant height `hs_m`."""
    wind = math.sqrt(max(hs_m, 0.0) * G / 0.21)
    return min(3.84e-6 * wind**3.41, 0.2)


GUST = (0.7, 0.6)  # the shader's breaking noise: the slope is weighed by 0.7 + 0.6·n, n ~ U(0, 1)
FOAM_EDGE = 0.9  # the middle of the shader's foam ramp, in units of the threshold


def whitecap_threshold(hs_m: float, mean_square_slope: float) -> float:
    """The slope threshold τ (the shader's u_sea.y) at which the foam covers the whitecap fraction: a point
    foams where g·|∇h| > FOAM_EDGE·τ with g the breaking noise, so E_g[exp(-(FOAM_EDGE τ / g)² / σ²)] = W
    (Rayleigh slopes of mean square σ²), solved by bisection (inf: no whitecaps)."""
    w = whitecap_fraction(hs_m)
    if w <= 1e-6 or mean_square_slope <= 0.0:
        return math.inf
    g = GUST[0] + GUST[1] * (np.arange(64) + 0.5) / 64

    def cover(tau: float) -> float:
        return float(np.mean(np.exp(-((FOAM_EDGE * tau / g) ** 2) / mean_square_slope)))

    lo, hi = 0.0, 10.0 * math.sqrt(mean_square_slope)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cover(mid) > w else (lo, mid)
    return 0.5 * (lo + hi)


MIP_LEVELS = 8


def mip_slope_ratio(waves) -> np.ndarray:
    """(MIP_LEVELS,) float32: rms slope of the shortest band's slope tile at each mipmap level over level 0's.
    A mip level L of a periodic 2^n texture is the mean over 2^L x 2^L blocks, which scales a wave's slope by
    the box response sin(k h 2^L / 2) / (2^L sin(k h / 2)) per axis; the shader scales the whitecap threshold by
    this ratio at the level it samples, so distant (filtered) water keeps the same whitecap share."""
    var = 0.5 * np.abs(waves._amp[-1]) ** 2
    h = float(waves.sizes[-1]) / waves.n
    kx, ky = waves._kx[-1] * h, waves._ky[-1] * h
    slope2 = (np.sin(kx) ** 2 + np.sin(ky) ** 2) / h**2 * var

    def box(k, m):
        den = m * np.sin(0.5 * k)
        return np.where(np.abs(den) > 1e-12, np.sin(0.5 * k * m) / np.where(np.abs(den) > 1e-12, den, 1.0), 1.0)

    base = float(slope2.sum())
    out = [math.sqrt(float(np.sum(slope2 * (box(kx, 2**lv) * box(ky, 2**lv)) ** 2)) / base) if base > 0 else 1.0
           for lv in range(MIP_LEVELS)]  # fmt: skip
    return np.maximum(np.array(out, np.float32), 1e-3)
