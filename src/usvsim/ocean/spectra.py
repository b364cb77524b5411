"""Wave spectra, directional spreading and the dispersion relation (physics.md §4.1–§4.3).

Frequency spectra are one-sided, S(ω) in m²·s/rad, ω in rad/s. Directions are the direction the waves
travel toward, radians counter-clockwise from +x (east). g = 9.81 m/s² throughout (VRX's 9.8 in its
dispersion helper is not reproduced, so every component obeys the same dispersion relation).
"""

from __future__ import annotations

import math

import numpy as np

G = 9.81
PM_ALPHA = 8.1e-3
PM_BETA = 0.74


def pierson_moskowitz(omega: np.ndarray, hs: float, tp: float) -> np.ndarray:
    """Pierson–Moskowitz spectrum from significant height `hs` (m) and peak period `tp` (s); m0 = hs²/16."""
    w = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / tp
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = 5.0 / 16.0 * hs**2 * wp**4 * w**-5.0 * np.exp(-1.25 * (wp / w) ** 4)
    return np.where(w > 0, s, 0.0)


def pm_from_wind(wind_speed_mps: float) -> tuple[float, float]:
    """(Hs, Tp) of the fully developed Pierson–Moskowitz sea for the wind speed at 19.5 m above the sea.

    S(ω) = α g² ω⁻⁵ exp(-β (g/(U ω))⁴) has ω_p = (4β/5)^{1/4} g/U and m0 = α U⁴/(4 β g²), so
    Hs = 4 √m0 = 2 √(α/β) U²/g ≈ 0.209 U²/g.
    """
    if wind_speed_mps <= 0:
        return 0.0, math.inf
    wp = (0.8 * PM_BETA) ** 0.25 * G / wind_speed_mps
    hs = 2.0 * math.sqrt(PM_ALPHA / PM_BETA) * wind_speed_mps**2 / G
    return hs, 2.0 * math.pi / wp


def jonswap(omega: np.ndarray, hs: float, tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP spectrum, DNV form: A_γ S_PM γ^r, σ = 0.07 below the peak and 0.09 above, A_γ = 1 - 0.287 ln γ."""
    w = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / tp
    sigma = np.where(w <= wp, 0.07, 0.09)
    r = np.exp(-((w - wp) ** 2) / (2.0 * sigma**2 * wp**2))
    return (1.0 - 0.287 * math.log(gamma)) * pierson_moskowitz(w, hs, tp) * gamma**r


def dnv_gamma(hs: float, tp: float) -> float:
    """DNV-RP-C205 peak enhancement when none is given: 5 for Tp/√Hs ≤ 3.6, 1 for ≥ 5, exp(5.75 - 1.15 r) between."""
    r = tp / math.sqrt(hs)
    if r <= 3.6:
        return 5.0
    if r >= 5.0:
        return 1.0
    return math.exp(5.75 - 1.15 * r)


def vrx_pms(omega: np.ndarray, period: float) -> np.ndarray:
    """VRX's "PMS" spectrum α g²/ω⁵ exp(-5/4 (ω_p/ω)⁴), α = 0.0081, ω_p = 2π/period (amplitude set by period only)."""
    w = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / period
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = PM_ALPHA * G**2 * w**-5.0 * np.exp(-1.25 * (wp / w) ** 4)
    return np.where(w > 0, s, 0.0)


def cos2s_norm(s: float) -> float:
    """C(s) = Γ(s+1) / (2 √π Γ(s+1/2)), so that ∫_{-π}^{π} C(s) cos^{2s}(θ/2) dθ = 1."""
    return math.exp(math.lgamma(s + 1.0) - math.lgamma(s + 0.5)) / (2.0 * math.sqrt(math.pi))


def cos2s(theta: np.ndarray, mean_direction: float, s: float) -> np.ndarray:
    """Longuet-Higgins cos-2s spreading D(θ) = C(s) cos^{2s}((θ - θ_m)/2), per radian, integrates to 1."""
    half = 0.5 * (np.asarray(theta, dtype=float) - mean_direction)
    return cos2s_norm(s) * np.abs(np.cos(half)) ** (2.0 * s)


def cos2s_mean_resultant(s: float) -> float:
    """First circular moment E[cos(θ - θ_m)] of the cos-2s distribution: s / (s + 1)."""
    return s / (s + 1.0)


def sample_cos2s(rng: np.random.Generator, n: int, mean_direction: float, s: float) -> np.ndarray:
    """Draw `n` directions (rad) from the cos-2s distribution by inverting its tabulated CDF."""
    grid = np.linspace(-math.pi, math.pi, 4097)
    pdf = cos2s(grid, 0.0, s)
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (pdf[1:] + pdf[:-1]) * np.diff(grid))])
    cdf /= cdf[-1]
    return mean_direction + np.interp(rng.random(n), cdf, grid)


def phillips(
    kx: np.ndarray, ky: np.ndarray, wind_speed_mps: float, wind_direction: float, chaos: float = 0.0
) -> np.ndarray:
    """HDRP-like Phillips wavenumber spectrum S(kx, ky) in m⁴ (variance per unit area of k-space).

    S = 0.2/(2π)² exp(-1/(k L)²)/k⁴ w², L = V²/g, w = lerp(k̂·ŵ, 0.5, chaos), and × chaos for w < 0 (waves
    against the wind). HDRP's per-bin variance 0.2 (...)/patch² equals S Δk² with Δk = 2π/patch.
    ŵ points where the wind blows toward, so the waves travel toward the wind direction.
    """
    k = np.hypot(kx, ky)
    length = wind_speed_mps**2 / G
    safe = np.where(k > 0, k, 1.0)
    w = (kx * math.cos(wind_direction) + ky * math.sin(wind_direction)) / safe
    w = w + (0.5 - w) * chaos
    s = 0.2 / (2.0 * math.pi) ** 2 * np.exp(-1.0 / (safe * length) ** 2) / safe**4 * w**2
    s = np.where(w < 0, s * chaos, s)
    return np.where((k > 0) & (length > 0), s, 0.0)


def wavenumber(omega: float | np.ndarray, depth: float = math.inf) -> np.ndarray:
    """Wavenumber k (rad/m) from ω² = g k tanh(k h) by Newton's method (deep water: k = ω²/g)."""
    w = np.asarray(omega, dtype=float)
    k = w**2 / G
    if math.isinf(depth):
        return k
    k = np.maximum(k, w / math.sqrt(G * depth))
    for _ in range(50):
        th = np.tanh(k * depth)
        f = G * k * th - w**2
        df = G * th + G * k * depth * (1.0 - th**2)
        step = f / np.where(df > 0, df, 1.0)
        k = k - step
        if np.all(np.abs(step) <= 1e-14 * np.maximum(k, 1e-12)):
            break
    return k


def angular_frequency(k: np.ndarray, depth: float = math.inf) -> np.ndarray:
    """ω(k) from the dispersion relation, rad/s."""
    k = np.asarray(k, dtype=float)
    if math.isinf(depth):
        return np.sqrt(G * k)
    return np.sqrt(G * k * np.tanh(k * depth))
