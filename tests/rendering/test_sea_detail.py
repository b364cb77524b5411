"""The short-wave render band continues the physics' spectrum; whitecap coverage follows Monahan's law."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.rendering.detail import DetailBand, resolved_statistics, whitecap_fraction, whitecap_threshold
from usvsim.rendering.gallery import load, scenario_dict


@pytest.fixture(scope="module")
def sea4():
    raw = scenario_dict(4, {}, 64, 48)
    raw["objects"] = []
    sim = load(raw, seed=3)
    yield sim.ocean.waves
    sim.close()


def test_short_waves_carry_the_spectrum_tail_slope_variance(sea4):
    band = DetailBand(sea4)
    # Phillips' saturation range: the same slope variance per e-fold as the physics' top octave, over ln 4
    assert band.slope_var == pytest.approx(band.beta * math.log(4.0), rel=1e-9)
    assert 0.002 < band.beta < 0.006  # α/2 with Phillips' α ≈ 0.0081 is 0.004
    tiles = band.slopes(12.5)
    assert tiles.shape == (sea4.n, sea4.n, 2) and tiles.dtype == np.float32
    measured = float(np.mean(tiles[..., 0] ** 2 + tiles[..., 1] ** 2))
    assert measured == pytest.approx(band.slope_var, rel=0.02)  # Parseval: the tiles hold the band's variance
    assert abs(float(tiles.mean())) < 1e-6  # a band without a mean slope


def test_short_waves_are_reproducible_and_move(sea4):
    a, b = DetailBand(sea4), DetailBand(sea4)
    assert np.array_equal(a.slopes(4.0), b.slopes(4.0))
    assert not np.array_equal(a.slopes(4.0), a.slopes(4.5))


def test_whitecap_threshold_gives_monahans_coverage(sea4):
    from usvsim.rendering.detail import _bilinear, breaking_mask, foam_cover
    from usvsim.rendering.surface import surface_data

    hs, (major, minor) = resolved_statistics(sea4)
    assert hs == pytest.approx(1.875, rel=0.1)
    assert major > 3.0 * minor  # a wind sea: steeper up- and downwind than across
    wind = math.sqrt(hs * 9.81 / 0.21)  # fully developed: Hs = 0.21 U²/g
    w = whitecap_fraction(hs)
    assert w == pytest.approx(3.84e-6 * wind**3.41)
    tau = whitecap_threshold(hs, (major, minor))
    assert foam_cover(tau, (major, minor)) == pytest.approx(w, rel=1e-3)
    # Monte Carlo of the shader's foam mask: the noise texture's breaking gust, streaks and density at random
    # points, times smoothstep(0.8, 1.0, g |slope| / tau), over anisotropic Gaussian slopes...
    g, density = breaking_mask()
    rng = np.random.default_rng(1)
    angle = rng.random()  # principal axes anywhere
    a, b = np.sqrt(major) * rng.standard_normal(g.size), np.sqrt(minor) * rng.standard_normal(g.size)
    slope = np.hypot(a * np.cos(angle) - b * np.sin(angle), a * np.sin(angle) + b * np.cos(angle))
    x = np.clip((g * slope / tau - 0.8) / 0.2, 0.0, 1.0)
    assert np.mean(density * x * x * (3 - 2 * x)) == pytest.approx(w, rel=0.1)
    # ...and over the physics' own slope tile (the shortest band), read bilinearly as the shader reads it
    class Ocean:
        waves, level_m = sea4, 0.0

    cover = []
    for t in (20.0, 40.0, 60.0):
        tile = surface_data(Ocean, t, (0.0, 0.0)).slope[-1, ..., :2].astype(np.float64)
        p = rng.random((g.size, 2)) * tile.shape[0]
        s = np.hypot(_bilinear(tile[..., 0], p), _bilinear(tile[..., 1], p))
        x = np.clip((g * s / tau - 0.8) / 0.2, 0.0, 1.0)
        cover.append(np.mean(density * x * x * (3 - 2 * x)))
    assert np.mean(cover) == pytest.approx(w, rel=0.15)
    assert whitecap_threshold(0.0, (major, minor)) == math.inf


def test_mip_slope_ratio_matches_bilinear_reads_of_the_block_means(sea4):
    from usvsim.rendering.detail import _bilinear, mip_slope_ratio
    from usvsim.rendering.surface import surface_data

    class Ocean:  # the FFT field alone, at full height
        waves, level_m = sea4, 0.0

    tile = surface_data(Ocean, 30.0, (0.0, 0.0)).slope[-1, ..., :2].astype(np.float64)  # the shortest band
    n = tile.shape[0]
    points = np.random.default_rng(2).random((100_000, 2))

    def rms(level: np.ndarray) -> float:  # bilinear reads at points spread over the tile (the shader's LINEAR)
        p = points * level.shape[0]
        return float(np.sqrt(np.mean(_bilinear(level[..., 0], p) ** 2 + _bilinear(level[..., 1], p) ** 2)))

    rms0 = rms(tile)
    ratio = mip_slope_ratio(sea4)
    for level in (1, 2, 3, 4):
        m = 2**level
        blocks = tile.reshape(n // m, m, n // m, m, 2).mean(axis=(1, 3))  # a mip level: 2^L x 2^L block means
        assert rms(blocks) / rms0 == pytest.approx(ratio[level], rel=0.08)
    assert ratio[0] == pytest.approx(1.0) and np.all(np.diff(ratio) <= 0)


def _near_water_texture(sea_state: int, short_waves: float) -> float:
    """Mean |high-pass| of the luminance over the near water of the onboard camera (the gallery's SS4 look)."""
    pytest.importorskip("moderngl")
    from usvsim.rendering.frame import water_label
    from usvsim.rendering.gallery import LOOKS

    raw = scenario_dict(sea_state, {**LOOKS["onboard_sea_state_4"][1], "water": {"short_waves": short_waves}}, 320, 240)
    raw["objects"] = []
    sim = load(raw, seed=0)
    sim.run(4.0)
    images = sim.sensors["wamv/camera"].render(sim)
    label = water_label(sim.model)
    sim.close()
    y = images["rgb"].astype(float) @ np.array([0.3, 0.6, 0.1])
    high = y - 0.25 * (np.roll(y, 1, 0) + np.roll(y, -1, 0) + np.roll(y, 1, 1) + np.roll(y, -1, 1))
    near = images["segmentation"] == label
    near[:150] = False  # the lower part of the image: water within ~10 m
    return float(np.mean(np.abs(high[near])))


def test_onboard_camera_in_sea_state_4_does_not_read_calm():
    flat, resolved_only, with_short = (_near_water_texture(0, 1.0), _near_water_texture(4, 0.0),
                                       _near_water_texture(4, 1.0))  # fmt: skip
    assert resolved_only < 2.0 * flat  # the physics' resolved sea alone: about as smooth as a flat sea
    assert with_short > 3.0 * max(flat, resolved_only)  # with the short waves: individual waves, shading, glint
