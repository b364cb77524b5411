"""FFT cascades: same sea as the direct sum of their bins, spectrum statistics, choppy sign, determinism."""

import math

import numpy as np
import pytest

from usvsim.ocean import spectra
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.fft import FFTWaveField, cascade_sizes, directional_spectrum

JONSWAP = directional_spectrum(lambda w: spectra.jonswap(w, 2.0, 8.0, 3.3), 0.4, 10.0)


@pytest.fixture(scope="module")
def single():
    return FFTWaveField(
        JONSWAP, [600.0], np.random.default_rng(5), resolution=64, choppiness=0.8, time_tolerance=0
    )


def test_tile_vertices_equal_the_direct_sum_of_the_bins(single):
    exact = DirectWaveField(single.components(), max_iter=60)
    grid = np.arange(0, 64, 5) * 600.0 / 64
    gx, gy = np.meshgrid(grid, grid)
    np.testing.assert_allclose(
        single.displaced_surface(gx, gy, 4.2), exact.displaced_surface(gx, gy, 4.2), atol=2e-6
    )
    no_chop = FFTWaveField(JONSWAP, [600.0], np.random.default_rng(5), resolution=64, time_tolerance=0)
    exact = DirectWaveField(no_chop.components())
    z = np.full(gx.size, 5.0)  # above the surface: the surface kinematics (deeper, bands decay approximately)
    for got, want in zip(no_chop.kinematics(gx, gy, z, 4.2), exact.kinematics(gx, gy, z, 4.2)):
        np.testing.assert_allclose(got, want, atol=2e-6)


def test_elevation_inverts_the_displacement(single):
    rng = np.random.default_rng(1)
    px, py = rng.uniform(-300, 300, 5000), rng.uniform(-300, 300, 5000)
    x0, y0, z, iters = single.surface_labels(px, py, 3.0, return_iterations=True)
    back = single.displaced_surface(x0, y0, 3.0)
    assert np.abs(back[:, 0] - px).max() < 1e-8 and np.abs(back[:, 1] - py).max() < 1e-8
    np.testing.assert_array_equal(back[:, 2], z)
    assert iters.max() < single.max_iter


def test_drawn_surface_is_the_physics_surface():
    field = FFTWaveField(JONSWAP, cascade_sizes(100.0, 3, 64), np.random.default_rng(2), 64, choppiness=0.9)
    verts = field.render_grid((10.0, 20.0), 40.0, 21, 6.0).reshape(-1, 3)
    np.testing.assert_allclose(field.elevation(verts[:, 0], verts[:, 1], 6.0), verts[:, 2], atol=1e-8)


def test_spatial_variance_matches_the_spectrum():
    """§4.7: 4√m0 = 2.0024 m for γ = 3.3. Bins hold S integrated over their cells (Parseval at the vertices),
    amplified by bilinear interpolation's mean loss, so the variance over all positions is m0."""
    field = FFTWaveField(JONSWAP, cascade_sizes(100.0), np.random.default_rng(3), 256, time_tolerance=0)
    tiles = field.tiles(11.0)
    at_vertices = sum(float(tiles[b, 0].var()) for b in range(3))
    assert 2 * field.components().variance == pytest.approx(2 * at_vertices, rel=1e-4)
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, 2000, 200_000), rng.uniform(0, 2000, 200_000)
    assert 4 * math.sqrt(field.elevation(x, y, 11.0).var()) == pytest.approx(2.0024, rel=0.01)
    h = (field.sizes / field.n)[:, None, None]
    gain = (2 + np.cos(field._kx * h)) / 3 * (2 + np.cos(field._ky * h)) / 3
    assert 4 * math.sqrt(np.sum(0.5 * np.abs(field._amp) ** 2 * gain)) == pytest.approx(2.0024, rel=2e-3)


def test_every_bin_obeys_deep_water_dispersion(single):
    c = single.components()
    np.testing.assert_allclose(c.phase_speed, np.sqrt(spectra.G / c.k), rtol=1e-12)


def test_choppy_fft_sharpens_crests():
    k = 2 * math.pi / 25.0

    def one_bin(kx, ky, band):
        dk = 2 * math.pi / 200.0  # a spectral line: the density 0.5/dk² over one bin's cell
        return np.where((np.abs(kx - k) < dk / 2) & (np.abs(ky) < dk / 2), 0.5 / dk**2, 0.0)

    field = FFTWaveField(one_bin, [200.0], np.random.default_rng(0), 256, choppiness=0.9)
    x = np.linspace(0.0, 200.0, 8001)[:-1]
    above = (field.elevation(x, np.zeros_like(x), 0.0) > 0).mean()
    assert above < 0.45


def test_same_seed_same_sea_and_waves_travel_toward_their_direction():
    a = FFTWaveField(JONSWAP, [600.0], np.random.default_rng(9), 64)
    b = FFTWaveField(JONSWAP, [600.0], np.random.default_rng(9), 64)
    x = np.linspace(0, 100, 50)
    np.testing.assert_array_equal(a.elevation(x, x, 1.0), b.elevation(x, x, 1.0))
    c = a.components()
    mean = math.atan2(
        np.sum(c.amplitude**2 * np.sin(c.direction)), np.sum(c.amplitude**2 * np.cos(c.direction))
    )
    assert mean == pytest.approx(0.4, abs=0.05)


def test_tiles_too_far_apart_are_rejected():
    with pytest.raises(ValueError, match="resolution"):
        FFTWaveField(JONSWAP, [1000.0, 10.0], np.random.default_rng(0), 64)
