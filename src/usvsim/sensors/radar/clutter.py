"""Radar clutter and noise, in units of the receiver noise power (so 0 dB = the noise floor).

Sea clutter: mean power C(r) = C₁₀₀ · (r / 100 m)^-n; C₁₀₀ = 10^(snr_at_100m_db / 10) or, from the sea state,
SEA_STATE_SNR_DB (+5 dB per state: Nathanson's X-band σ⁰ at low grazing rises ~4-6 dB per Douglas state, and
at low grazing σ⁰A/r⁴ with A ∝ r and σ⁰ ∝ grazing ∝ 1/r gives the r^-3 default). Intensity is K-distributed:
a gamma texture τ (shape ν, mean 1) times exponential speckle, so I = C τ s has mean C and
E[I²] / E[I]² = 2 (1 + 1/ν) (Ward, Tough & Watts, Sea Clutter, ch. 4); with noise (and rain) added:
I = (1 + R + C τ) s ("K + noise"), mean 1 + R + C.

Rain: volume clutter with Rayleigh (exponential) intensity; reflectivity Z ∝ R^1.6 (Marshall-Palmer) fills
every beam cell, whose volume grows as r², so the mean falls as r^-2, times two-way attenuation
exp(-2 α r) with α = 0.01 R^1.21 dB/km at X band (ITU-R P.838 order of magnitude).
Receiver noise: exponential intensity of mean 1 (the unit of every power).
"""

from __future__ import annotations

import math

import numpy as np

SEA_STATE_SNR_DB = (-30.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 33.0, 36.0, 38.0)  # mean sea clutter at 100 m, dB
HS_UPPER_M = (0.0, 0.1, 0.5, 1.25, 2.5, 4.0, 6.0, 9.0, 14.0)  # WMO code table 3700: upper Hs of states 0-8
TEXTURE_CELLS = 4
RAIN_SNR_AT_1KM_DB_PER_MMH = 3.0  # 1 mm/h gives 3 dB at 1 km (10 log10 R^1.6 added)


def sea_state_of(sea) -> int:
    """WMO sea state of an environment `sea` config: its code, or from its Hs; flat/unknown seas are 0."""
    if getattr(sea, "code", None) is not None:
        return int(sea.code)
    hs = getattr(sea, "hs_m", None)
    if hs is None:
        return 0
    return int(np.searchsorted(HS_UPPER_M, hs, side="left"))


def sea_clutter_mean(range_m: np.ndarray, snr_at_100m_db: float, exponent: float) -> np.ndarray:
    """Mean sea clutter power (noise units) per range bin."""
    return 10.0 ** (snr_at_100m_db / 10.0) * (np.maximum(range_m, 1.0) / 100.0) ** (-exponent)


def rain_mean(range_m: np.ndarray, rain_mm_h: float) -> np.ndarray:
    """Mean rain clutter power (noise units) per range bin."""
    if rain_mm_h <= 0:
        return np.zeros_like(range_m)
    at_1km = 10.0 ** ((RAIN_SNR_AT_1KM_DB_PER_MMH + 16.0 * math.log10(rain_mm_h)) / 10.0)
    alpha_db_per_m = 0.01 * rain_mm_h**1.21 / 1000.0
    attenuation = 10.0 ** (-2.0 * alpha_db_per_m * range_m / 10.0)
    return at_1km * (np.maximum(range_m, 1.0) / 1000.0) ** -2.0 * attenuation


def background(rng: np.random.Generator, shape: tuple[int, int], sea_mean: np.ndarray, nu: float,
               rain: np.ndarray) -> np.ndarray:  # fmt: skip
    """Noise + sea clutter + rain power (spokes, bins) for per-bin means `sea_mean` (spokes, bins), `rain` (bins,).

    Noise, rain and sea speckle are complex Gaussian, so their sum is too: the intensity is exponential with mean
    1 + rain + C·τ ("K + noise"). The texture τ (gamma, shape ν, mean 1) is correlated over TEXTURE_CELLS spokes
    and bins (it is the sea's swell and wave groups; the speckle decorrelates from cell to cell)."""
    k = TEXTURE_CELLS
    coarse = rng.gamma(nu, 1.0 / nu, (-(-shape[0] // k), -(-shape[1] // k)))
    texture = np.repeat(np.repeat(coarse, k, axis=0), k, axis=1)[: shape[0], : shape[1]]
    return (1.0 + rain + sea_mean * texture) * rng.standard_exponential(shape)
