"""The draw-independent tables of an FFT sea are kept per process: a second field of the same sea (a reset, another
seed) reuses them and is bit-identical to one built without them."""

from __future__ import annotations

from functools import partial

import numpy as np

from usvsim.ocean import fft, spectra


def field(seed: int, key, gaussian: bool = False) -> fft.FFTWaveField:
    spectrum = fft.directional_spectrum(partial(spectra.jonswap, hs=2.0, tp=8.0, gamma=3.3), 0.3, 10.0)
    return fft.FFTWaveField(spectrum, fft.cascade_sizes(100.0, 3, 64), np.random.default_rng(seed), resolution=64,
                            choppiness=0.8, gaussian_amplitudes=gaussian, spectrum_key=key)  # fmt: skip


def surface(f: fft.FFTWaveField) -> np.ndarray:
    x, y = np.meshgrid(np.linspace(-30.0, 30.0, 23), np.linspace(-25.0, 35.0, 19))
    return np.concatenate([f.elevation(x, y, 3.7).ravel(), f.velocity(x.ravel(), y.ravel(), -0.5 * np.ones(x.size), 3.7).ravel()])


def test_a_field_from_kept_tables_equals_one_built_without_them():
    fft._TABLES.clear()
    cold = field(4, ("test", 1))  # computes the tables and keeps them
    warm = field(4, ("test", 1))  # reuses them
    alone = field(4, None)  # never kept
    assert warm._var is cold._var and alone._var is not cold._var
    for f in (warm, alone):
        assert np.array_equal(f._var, cold._var) and np.array_equal(f._amp, cold._amp)
        assert f.snapshot_intervals_s == cold.snapshot_intervals_s
        assert np.array_equal(surface(f), surface(cold))


def test_another_draw_of_the_same_sea_shares_the_tables_only():
    fft._TABLES.clear()
    first, second = field(4, ("test", 2)), field(5, ("test", 2))
    assert second._var is first._var and not np.array_equal(second._amp, first._amp)
    # random phases keep each bin's variance: |c|²/2 is the table's, whatever the draw
    np.testing.assert_allclose(0.5 * np.abs(second._amp) ** 2, first._var, rtol=1e-12, atol=0.0)
    # the snapshot intervals come from the expected variance: the same for every draw, Gaussian amplitudes too
    g1, g2 = field(4, ("test", 3), gaussian=True), field(9, ("test", 3), gaussian=True)
    assert g1.snapshot_intervals_s == g2.snapshot_intervals_s == field(6, None, gaussian=True).snapshot_intervals_s


def test_the_process_keeps_a_bounded_number_of_seas():
    fft._TABLES.clear()
    for k in range(fft.TABLES_KEPT + 3):
        field(0, ("bounded", k))
    assert len(fft._TABLES) == fft.TABLES_KEPT
    assert ("bounded", 0) not in {key[0] for key in fft._TABLES}  # the oldest went first
