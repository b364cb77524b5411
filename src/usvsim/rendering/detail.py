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


def resolved_statistics(waves) -> tuple[float, tuple[float, float]]:
    """(Hs in m, principal slope variances (major, minor) of the shortest band) of the physics' resolved sea
    (without the ramp); the slope as the shader sees it: the slope tiles' central differences (a wave's slope k
    becomes sin(k h)/h), read bilinearly between texels at points spread over the sea (linear interpolation at a
    fraction f of a texel keeps 1 - 2f(1-f)(1 - cos kh) of a wave's variance; over f uniform: 1 - (1 - cos kh)/3
    per axis, a third at the Nyquist wavenumber; 0.84 of the texels' mean square in the FFT seas). A wind sea's
    slopes are anisotropic (about 4:1 up- and cross-wind): the whitecaps' tail depends on both."""
    var = 0.5 * np.abs(waves._amp) ** 2
    h = float(waves.sizes[-1]) / waves.n
    kx, ky = waves._kx[-1] * h, waves._ky[-1] * h
    weight = var[-1] * (1.0 - (1.0 - np.cos(kx)) / 3.0) * (1.0 - (1.0 - np.cos(ky)) / 3.0) / h**2
    sx, sy = np.sin(kx), np.sin(ky)
    cov = np.array([[np.sum(weight * sx * sx), np.sum(weight * sx * sy)], [np.sum(weight * sx * sy), np.sum(weight * sy * sy)]])
    return 4.0 * math.sqrt(float(var.sum())), principal(cov)


def principal(cov: np.ndarray) -> tuple[float, float]:
    """(major, minor) variances of a 2 x 2 covariance of the slopes (∂h/∂x, ∂h/∂y)."""
    low, high = np.linalg.eigvalsh(np.asarray(cov, dtype=np.float64))
    return float(max(high, 0.0)), float(max(low, 0.0))


def whitecap_fraction(hs_m: float) -> float:
    """Monahan's whitecap fraction for the wind of a fully developed sea of significant height `hs_m`."""
    wind = math.sqrt(max(hs_m, 0.0) * G / 0.21)
    return min(3.84e-6 * wind**3.41, 0.2)


GUST = (0.7, 0.6)  # the shader's breaking noise: the slope is weighed by 0.7 + 0.6·n (n: the noise texture)
FOAM_RAMP = (0.8, 1.0)  # the shader's foam ramp on g·|∇h| / τ: smoothstep(0.8, 1.0, ·)
STREAKS = (0.35, 0.8, 0.6)  # breakup into streaks: smoothstep(0.35, 0.8, 0.6·n₁ + 0.4·grain)
GRAIN = (0.55, 0.45)  # the foam's density: 0.55 + 0.45·grain
NOISE_TEXELS = 64
MASK_SAMPLES = 32768


def foam_noise() -> np.ndarray:
    """The water's noise texture (64, 64) float32 [row y, column x], values U(0, 1) from a fixed seed: the same
    bytes every run (marine.py uploads it; the shader reads it bilinearly, repeating)."""
    return np.random.default_rng(17).random((NOISE_TEXELS, NOISE_TEXELS), dtype=np.float32)


def _bilinear(tex: np.ndarray, p: np.ndarray) -> np.ndarray:
    """GL's LINEAR, REPEAT lookup of `tex` at `p` (n, 2) in texels (x, y): texel centres at i + 0.5."""
    n = tex.shape[0]
    q = p - 0.5
    i = np.floor(q).astype(np.int64)
    f = q - i
    x0, y0, x1, y1 = i[:, 0] % n, i[:, 1] % n, (i[:, 0] + 1) % n, (i[:, 1] + 1) % n
    fx, fy = f[:, 0], f[:, 1]
    t = tex.astype(np.float64)
    return (t[y0, x0] * (1 - fx) + t[y0, x1] * fx) * (1 - fy) + (t[y1, x0] * (1 - fx) + t[y1, x1] * fx) * fy


def breaking_mask() -> tuple[np.ndarray, np.ndarray]:
    """The shader's foam mask apart from the slope, sampled over the sea: (gust g, weight w) per sample, where a
    point's foam is w·smoothstep(0.8, 1.0, g·|∇h| / τ); w = the streak breakup × the foam's density. The three
    noise lookups (gust, streaks, grain) are at scales 0.23, 3.1 and 1.7 per metre, incommensurate: over the sea
    they are independent samples of the texture (grain enters both the streaks and the density, as in the shader)."""
    tex = foam_noise()
    rng = np.random.default_rng(0)
    gust, streak, grain = (_bilinear(tex, rng.random((MASK_SAMPLES, 2)) * NOISE_TEXELS) for _ in range(3))
    g = GUST[0] + GUST[1] * gust
    s = np.clip((STREAKS[2] * streak + (1.0 - STREAKS[2]) * grain - STREAKS[0]) / (STREAKS[1] - STREAKS[0]), 0, 1)
    return g, s * s * (3.0 - 2.0 * s) * (GRAIN[0] + GRAIN[1] * grain)


def exceedance(x: np.ndarray, variances: tuple[float, float]) -> np.ndarray:
    """P(|∇h| > x) for Gaussian slopes with principal variances (a², b²): in polar coordinates,
    (1 / 2π a b) ∫ exp(-q x² / 2) / q dθ with q = cos²θ / a² + sin²θ / b² (isotropic: exp(-x² / (a² + b²)))."""
    a2, b2 = (max(v, 1e-12) for v in variances)
    theta = (np.arange(64) + 0.5) * math.pi / 64  # the integrand has period π
    q = np.cos(theta) ** 2 / a2 + np.sin(theta) ** 2 / b2
    x2 = np.asarray(x, dtype=np.float64)[..., None] ** 2
    return np.mean(np.exp(-0.5 * q * x2) / q, axis=-1) / math.sqrt(a2 * b2)


def foam_cover(tau: float, variances: tuple[float, float], mask=None) -> float:
    """Mean foam (the area fraction that is white, a pixel with foam 0.3 counting 0.3) of the shader's steep-face
    whitecaps at threshold τ, for Gaussian slopes of principal variances `variances`:
    E[w·smoothstep(a, b, g|∇h|/τ)] = E_w,g[w ∫ smoothstep'(u) P(|∇h| > uτ/g) du] (`breaking_mask`, `exceedance`)."""
    g, w = breaking_mask() if mask is None else mask
    a, b = FOAM_RAMP
    u = a + (b - a) * (np.arange(16) + 0.5) / 16  # midpoint rule over the ramp
    t = (u - a) / (b - a)
    du = 6.0 * t * (1.0 - t) / 16  # smoothstep'(u) du
    edges = np.linspace(g.min(), g.max(), 129)  # the gust in 128 bins: the exceedance once per bin
    which = np.clip(np.searchsorted(edges, g, side="right") - 1, 0, 127)
    weight = np.bincount(which, weights=w, minlength=128) / len(g)
    centre = 0.5 * (edges[1:] + edges[:-1])
    exceed = exceedance(u[None, :] * tau / centre[:, None], variances)  # (bins, ramp points)
    return float(weight @ (exceed @ du))


def whitecap_threshold(hs_m: float, variances: tuple[float, float]) -> float:
    """The slope threshold τ (the shader's u_sea.y) at which the rendered foam covers Monahan's whitecap fraction
    W (`foam_cover` = W, the mean of the shader's foam mask: its breaking noise, ramp, streaks and density, over
    the sea's slopes of principal variances `variances`), solved by bisection (inf: no whitecaps). The streaks
    keep about a third of the surface and the density averages ~0.8, so τ sits lower than for a plain slope
    threshold."""
    w = whitecap_fraction(hs_m)
    if w <= 1e-6 or sum(variances) <= 0.0:
        return math.inf
    mask = breaking_mask()
    lo, hi = 0.0, 10.0 * math.sqrt(sum(variances))
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if foam_cover(mid, variances, mask) > w else (lo, mid)
    return 0.5 * (lo + hi)


MIP_LEVELS = 8


def mip_slope_ratio(waves) -> np.ndarray:
    """(MIP_LEVELS,) float32: rms slope of the shortest band's slope tile at each mipmap level over level 0's, as
    the shader reads them (bilinearly, at points spread over the sea). A mip level L of a periodic 2^n texture is
    the mean over 2^L x 2^L blocks, which scales a wave's slope by the box response
    sin(k h 2^L / 2) / (2^L sin(k h / 2)) per axis, and bilinear reads between its texels (2^L h apart) keep
    1 - (1 - cos(k h 2^L)) / 3 of its variance per axis (see `resolved_statistics`); the shader scales the
    whitecap threshold by this ratio at the level it samples, so distant (filtered) water keeps the same
    whitecap share."""
    var = 0.5 * np.abs(waves._amp[-1]) ** 2
    h = float(waves.sizes[-1]) / waves.n
    kx, ky = waves._kx[-1] * h, waves._ky[-1] * h
    slope2 = (np.sin(kx) ** 2 + np.sin(ky) ** 2) / h**2 * var

    def box(k, m):
        den = m * np.sin(0.5 * k)
        return np.where(np.abs(den) > 1e-12, np.sin(0.5 * k * m) / np.where(np.abs(den) > 1e-12, den, 1.0), 1.0)

    def lerp(k, m):
        return 1.0 - (1.0 - np.cos(k * m)) / 3.0

    level = [slope2 * (box(kx, 2**lv) * box(ky, 2**lv)) ** 2 * lerp(kx, 2**lv) * lerp(ky, 2**lv)
             for lv in range(MIP_LEVELS)]  # fmt: skip
    base = float(level[0].sum())
    out = [math.sqrt(float(np.sum(v)) / base) if base > 0 else 1.0 for v in level]
    return np.maximum(np.array(out, np.float32), 1e-3)
