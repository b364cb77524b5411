"""Speed paths that must not change a single bit: heights without displacement (no Newton inversion), the fused
Froude–Krylov heads, a still ocean's constant wind and current; serial/parallel kernel builds (own cache entries)."""

import math

import numpy as np
import pytest

from usvsim.ocean import direct, fft_kernels, pressure, spectra
from usvsim.ocean.components import from_arrays, vrx_pms_components
from usvsim.ocean.current import Current
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.fft import FFTWaveField, cascade_sizes, directional_spectrum
from usvsim.ocean.ocean import Ocean
from usvsim.ocean.wind import Wind

JONSWAP = directional_spectrum(lambda w: spectra.jonswap(w, 1.5, 7.0, 3.3), 0.4, 10.0)
RNG = np.random.default_rng(11)
PX, PY = RNG.uniform(-400.0, 400.0, 300), RNG.uniform(-400.0, 400.0, 300)


def _newton(kernel, *args):
    out = np.empty(len(PX)), np.empty(len(PX)), np.empty(len(PX)), np.empty(len(PX), np.int64)
    kernel(PX, PY, *args, *out)
    return out


def test_fft_heights_without_choppiness_equal_the_inversion_bit_for_bit():
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(2), 64, ramp_time_s=2.0)
    for t in (0.3, 4.71):
        x0, y0, z, iters = field.surface_labels(PX, PY, t, return_iterations=True)
        wts = field.update(t)
        ref = _newton(fft_kernels.INVERT[0], field.geometry.tiles, wts, field.inv_cells, 0.0, field.tol, 20)
        assert np.array_equal(z, ref[2]) and np.array_equal(x0, ref[0]) and np.array_equal(y0, ref[1])
        assert np.array_equal(iters, ref[3]) and not iters.any()


def test_direct_heights_without_steepness_equal_the_inversion_bit_for_bit():
    field = DirectWaveField(vrx_pms_components(1.0, 5.0, direction=0.3), ramp_time_s=3.0)
    for t in (0.5, 7.1):
        x0, y0, z, iters = field.surface_labels(PX, PY, t, return_iterations=True)
        ref = _newton(direct.INVERT[0], float(t), *field._args, field.ramp(t), field.tol, field.max_iter)
        assert np.array_equal(z, ref[2]) and np.array_equal(x0, ref[0]) and np.array_equal(iters, ref[3])


def test_constant_wind_and_current_are_the_processes_values():
    ocean = Ocean(wind=Wind(7.0, 0.4), current=Current(0.6, -1.1))
    z = np.array([-0.5, 0.0, -2.0])
    for t in (0.0, 0.01, 3.0):
        assert np.array_equal(ocean.wind_velocity(t), Wind(7.0, 0.4).velocity())
        assert np.array_equal(ocean.velocity(z, z, z, t), Current(0.6, -1.1).velocity(z))
    ocean.wind_velocity(0.0)[0] = 99.0  # callers get copies
    assert ocean.wind_velocity(0.0)[0] != 99.0
    gusty = Ocean(wind=Wind(7.0, 0.4, np.random.default_rng(0), gust_gain=2.0))
    first = gusty.wind_velocity(0.0)
    assert not gusty.wind.constant and gusty.wind_velocity(1.0)[0] != first[0]


def test_serial_and_parallel_builds_have_their_own_cache_entries():
    for serial, parallel in (fft_kernels.INVERT, fft_kernels.HEIGHTS, direct.INVERT, direct.KINEMATICS):
        assert serial.py_func.__qualname__ != parallel.py_func.__qualname__
        assert parallel.targetoptions.get("parallel") and not serial.targetoptions.get("parallel")


def test_fused_froude_krylov_heads_equal_the_two_pass_sums_bit_for_bit():
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(4), 64)
    pz = RNG.uniform(-3.0, 1.0, len(PX))
    eta, zeta = pressure.surface_and_dynamic_head(field, PX, PY, pz, 2.2)
    ref_x0, ref_y0, ref_eta, _ = _newton(fft_kernels.INVERT[0], field.geometry.tiles, field.update(2.2),
                                         field.inv_cells, 0.0, field.tol, 20)  # fmt: skip
    ref = np.empty(len(PX))
    pressure.FFT_HEAD[0](ref_x0, ref_y0, pz, ref_eta, field.geometry.tiles, field.update(2.2), field.inv_cells,
                         pressure.height_decay_wavenumbers(field), ref)  # fmt: skip
    assert (
        np.array_equal(eta, ref_eta) and np.array_equal(zeta, ref) and (pz < eta).any() and (pz > eta).any()
    )


def test_velocity_spectra_made_beside_the_geometry_equal_their_own_transforms():
    import scipy.fft

    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(6), 64)
    shared = [b for b in range(3) if field.velocity_ring.intervals[b] == field.geometry.intervals[b]]
    assert shared  # the usual case: the same snapshot times for some bands
    for t in (0.0, 1.37, 1.41, 6.0):
        field.update(t)
        field.update_kinematics(t)
    ring, spec = field.velocity_ring, np.empty((1, 64, 64), np.complex64)
    for b in range(3):
        for r in range(4):
            fft_kernels.kinematic_spectra(field._amp[b], field._omega[b], field._khx[b], field._khy[b],
                                          ring._held[b, r], False, spec)  # fmt: skip
            assert np.array_equal(ring.tiles[b, r], scipy.fft.ifft2(spec, norm="forward", workers=1))


@pytest.mark.parametrize("depth", [math.inf, 6.0])
def test_fused_direct_froude_krylov_heads_equal_the_two_pass_sums_bit_for_bit(depth):
    k = np.array([0.05, 0.3, 1.2, 4.0])
    comps = from_arrays([0.4, 0.2, 0.05, 0.01], k, [0.1, 1.0, -0.7, 2.0], [0.3, 1.1, 2.0, -1.0], 0.0, depth)
    field = DirectWaveField(comps, depth=depth, ramp_time_s=1.0)
    pz = RNG.uniform(-5.0, 0.5, len(PX))
    eta, zeta = pressure.surface_and_dynamic_head(field, PX, PY, pz, 3.3)
    ref = _newton(direct.INVERT[0], 3.3, *field._args, field.ramp(3.3), field.tol, field.max_iter)
    head = np.empty(len(PX))
    pressure.DIRECT_HEAD[0](ref[0], ref[1], pz, ref[2], 3.3, *field._args[:5], field.ramp(3.3), depth, head)
    assert (
        np.array_equal(eta, ref[2]) and np.array_equal(zeta, head) and (pz < eta).any() and (pz > eta).any()
    )


def test_cached_tile_nodes_give_the_uncached_heights_and_heads_bit_for_bit():
    """The node cache (fft_kernels.band_heights_cached) over a sequence of queries that changes the blend
    weights, brings in new snapshots, goes back in time and interleaves other users of the tiles: every height
    and Froude-Krylov head equals the per-point kernels' (HEIGHTS, FFT_SURFACE_AND_HEAD serial) exactly."""
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(5), 64, ramp_time_s=1.0)
    px, py = RNG.uniform(-30.0, 30.0, 500), RNG.uniform(-30.0, 30.0, 500)  # a fleet's worth of shared nodes
    pz = RNG.uniform(-1.5, 0.5, 500)
    for t in (0.0, 0.01, 0.02, 0.02, 0.37, 3.9, 0.01, 12.345, 12.355):
        z = field.surface_labels(px, py, t)[2]
        ref = np.empty(len(px))
        fft_kernels.HEIGHTS[0](px, py, field.geometry.tiles, field.update(t), field.inv_cells, ref)
        assert np.array_equal(z, ref)
        eta, zeta = pressure.surface_and_dynamic_head(field, px, py, pz, t)
        ref_eta, ref_zeta, band_h = np.empty(len(px)), np.empty(len(px)), np.empty((len(px), 3))
        pressure.FFT_SURFACE_AND_HEAD[0](px, py, pz, field.geometry.tiles, field.update(t), field.inv_cells,
                                         pressure.height_decay_wavenumbers(field), band_h, ref_eta, ref_zeta)  # fmt: skip
        assert np.array_equal(eta, ref_eta) and np.array_equal(zeta, ref_zeta)
        field.tiles(t + 0.5)  # another blend of the same tiles in between (weights with scale 1, new snapshots)


def test_one_call_hull_water_and_velocity_equal_the_array_code_bit_for_bit():
    """pressure.hull_water (what World._water does for an FFT sea in one call) and the one-call FFT velocity equal
    surface_and_dynamic_head + the array arithmetic, and `kinematics`, exactly."""
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(8), 64, ramp_time_s=1.0)
    verts = np.column_stack([RNG.uniform(-20, 20, 400), RNG.uniform(-20, 20, 400), RNG.uniform(-1.0, 1.0, 400)])
    level = 0.25
    for t in (0.0, 0.7, 0.71, 5.2):
        eta, head = np.empty(400), np.empty(400)
        assert pressure.hull_water(field, verts, level, t, eta, head)
        ref_eta, zeta = pressure.surface_and_dynamic_head(field, verts[:, 0], verts[:, 1], verts[:, 2] - level, t)
        assert np.array_equal(eta, ref_eta + level) and np.array_equal(head, (zeta + level) - verts[:, 2])
        vel = field.velocity(verts[:, 0], verts[:, 1], verts[:, 2], t)
        assert np.array_equal(vel, field.kinematics(verts[:, 0], verts[:, 1], verts[:, 2], t, acceleration=False)[0])


def test_velocity_into_equals_velocity_bit_for_bit():
    """Ocean.velocity_into (one compiled call for an FFT sea under a constant uniform current) writes what
    Ocean.velocity returns, at points above and below the surface, at several times."""
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(9), 64, ramp_time_s=1.0)
    ocean = Ocean(waves=field, current=Current(0.6, -1.1), level_m=0.3)
    points = np.column_stack([RNG.uniform(-30, 30, 50), RNG.uniform(-30, 30, 50), RNG.uniform(-2.0, 1.5, 50)])
    out = np.empty((50, 3))
    for t in (0.0, 0.33, 0.34, 7.0):
        ocean.velocity_into(points, t, out)
        assert np.array_equal(out, ocean.velocity(points[:, 0], points[:, 1], points[:, 2], t))
    assert not np.allclose(out[:, :2], Current(0.6, -1.1).velocity(points[:, 2] - 0.3)[:, :2])  # waves move it
